"""Shadows bpy for `make test-fast` (PYTHONPATH=tests/blender_free): that tier must need no Blender, in
the test process or in any child it starts, so importing bpy there fails at once."""

raise ModuleNotFoundError("bpy is refused in the Blender-free tier (make test-fast); mark the test 'subprocess' or "
                  "move it to tests/bpy")

"""bpy tier: every test starts from an empty factory scene with Radiometer registered."""

import pytest

bpy = pytest.importorskip("bpy")

from radiometer.compat import ensure_node_tree  # noqa: E402

# Blender 4.5's bpy module can hang at interpreter exit: its delayed-file-close thread and a global
# destructor wait on each other (gdb: GlobalState::~GlobalState in pthread_cond_destroy while
# delayed_close_thread_run waits); 5.0 exits normally. On 4.x the session ends with os._exit once
# pytest has reported, with pytest's exit status.
_session = {"status": 0}


def pytest_sessionfinish(session, exitstatus):
    _session["status"] = int(exitstatus)


def pytest_unconfigure(config):
    if bpy.app.version < (5, 0, 0):
        import os
        import sys

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_session["status"])


@pytest.fixture
def clean_blender():
    import radiometer

    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    try:
        yield bpy
    finally:
        radiometer.unregister()


def make_black_world(scene):
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return world


def add_light(scene, kind, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), **props):
    data = bpy.data.lights.new(f"{kind.lower()}", kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    obj.location, obj.rotation_euler = location, rotation
    scene.collection.objects.link(obj)
    return obj


def add_plane(scene, size=1.0, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), albedo=0.8, name="plane"):
    h = size / 2
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.location, obj.rotation_euler = location, rotation
    scene.collection.objects.link(obj)
    return obj


@pytest.fixture
def build():
    """Scene builders for tests: build.black_world(scene), build.light(...), build.plane(...)."""
    import types

    return types.SimpleNamespace(black_world=make_black_world, light=add_light, plane=add_plane)

"""False colour in the viewport (issue 13): toggle, legend layout, clean removal."""

import bpy
import numpy as np
import pytest

from radiometer.errors import RadiometerError


def _grid_scene(tmp_path, lux=None):
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("Work Plane")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("Work Plane", mesh)
    plane.location = (0.0, 0.0, 0.75)
    plane.hide_render = True
    scene.collection.objects.link(plane)
    lux = np.arange(12.0).reshape(3, 4) * 10.0 + 50.0 if lux is None else lux
    path = tmp_path / "grid.csv"
    with open(path, "w", encoding="utf-8") as f:
        f.write("row,col,x,y,z,illuminance_lx,irradiance_W_m2,rel_std_error\n")
        for j in range(lux.shape[0]):
            for i in range(lux.shape[1]):
                f.write(f"{j},{i},0,0,0.75,{lux[j, i]},{lux[j, i] / 683},0.01\n")
    s = scene.radiometer_analysis
    s.grid_target, s.grid_csv = plane.name, str(path)
    s.grid_nx, s.grid_ny = lux.shape[1], lux.shape[0]
    return scene, plane, lux


def test_toggle_creates_and_removes_overlay_and_handler(clean_blender, tmp_path):
    from radiometer.measure.analyses.grid import lux_from_csv
    from radiometer.operators import false_colour as fc

    scene, plane, lux = _grid_scene(tmp_path)
    assert np.allclose(lux_from_csv(scene.radiometer_analysis.grid_csv), lux)
    assert not fc.is_shown()
    assert bpy.ops.radiometer.toggle_false_colour() == {"FINISHED"}
    assert fc.is_shown() and fc._state["handler"] is not None
    (name,) = fc._state["objects"]
    obj = bpy.data.objects[name]
    assert obj.hide_render and obj.get(fc.OBJECT_MARK)
    assert "lux_colour" in obj.data.color_attributes
    assert len(obj.data.polygons) == lux.size
    assert obj.matrix_world.translation.z == pytest.approx(0.75, abs=1e-3)
    assert obj.data.materials[0].name == fc.MATERIAL_NAME
    assert (fc._state["lo"], fc._state["hi"]) == (pytest.approx(lux.min()), pytest.approx(lux.max()))
    fc.draw_legend()  # headless: returns without drawing
    mesh_name = obj.data.name
    assert bpy.ops.radiometer.toggle_false_colour() == {"FINISHED"}
    assert not fc.is_shown() and fc._state["handler"] is None
    assert name not in bpy.data.objects and mesh_name not in bpy.data.meshes
    assert fc.MATERIAL_NAME not in bpy.data.materials
    assert plane.name in bpy.data.objects


def test_toggle_needs_a_grid(clean_blender, tmp_path):
    from radiometer.operators import false_colour as fc

    assert not bpy.ops.radiometer.toggle_false_colour.poll()
    scene, plane, _ = _grid_scene(tmp_path)
    scene.radiometer_analysis.grid_csv = str(tmp_path / "missing.csv")
    with pytest.raises(RuntimeError):
        bpy.ops.radiometer.toggle_false_colour()
    with pytest.raises(RadiometerError):
        fc.last_grid(scene)
    assert not fc.is_shown()


def test_unregister_and_file_load_remove_everything(clean_blender, tmp_path):
    import radiometer
    from radiometer.operators import false_colour as fc

    scene, _, _ = _grid_scene(tmp_path)
    bpy.ops.radiometer.toggle_false_colour()
    path = str(tmp_path / "with_overlay.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)  # load_pre: handler gone; load_post: saved copy removed
    assert not fc.is_shown()
    assert not [ob for ob in bpy.data.objects if ob.get(fc.OBJECT_MARK)]
    assert "Work Plane" in bpy.data.objects
    _grid_scene(tmp_path)
    bpy.ops.radiometer.toggle_false_colour()
    name = fc._state["objects"][0]
    radiometer.unregister()
    try:
        assert not fc.is_shown() and name not in bpy.data.objects
        assert fc._on_load_pre not in bpy.app.handlers.load_pre
        assert fc._on_load_post not in bpy.app.handlers.load_post
    finally:
        radiometer.register()


def test_legend_layout_ticks_colours_and_scale():
    from radiometer.measure.analyses.grid import false_colour
    from radiometer.operators.false_colour import legend_layout

    lay = legend_layout(100.0, 500.0, 800, 600, ticks=5, steps=16)
    x0, y0, x1, y1 = lay["bar"]
    assert 0 < x0 < x1 < 800 and 0 < y0 < y1 < 600
    assert [v for _, v, _ in lay["ticks"]] == pytest.approx([100, 200, 300, 400, 500])
    assert [lbl for *_, lbl in lay["ticks"]] == ["100 lx", "200 lx", "300 lx", "400 lx", "500 lx"]
    assert lay["ticks"][0][0] == pytest.approx(y0) and lay["ticks"][-1][0] == pytest.approx(y1)
    segs = lay["segments"]
    assert len(segs) == 16 and segs[0][0] == pytest.approx(y0) and segs[-1][1] == pytest.approx(y1)
    lum = [0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2] for *_, c in segs]
    assert lum == sorted(lum)  # inferno: dark (low lux) at the bottom, bright at the top
    assert false_colour(0.0)[:3] == pytest.approx((0.001462, 0.000466, 0.013866), abs=1e-4)
    big = legend_layout(100.0, 500.0, 800, 600, ui_scale=2.0)
    assert big["bar"][2] - big["bar"][0] == pytest.approx(2 * (x1 - x0))
    flat = legend_layout(42.0, 42.0, 300, 200)  # uniform grid, tiny region: still a valid bar
    assert all(v == 42.0 for _, v, _ in flat["ticks"]) and flat["bar"][3] > flat["bar"][1]
    assert legend_layout(float("nan"), float("nan"), 300, 200)["ticks"][0][2] == "n/a"


def test_toggle_is_one_undo_step_and_the_legend_follows(clean_blender, tmp_path):
    """Toggling adds/removes an object, so it is undoable; after undo/redo the legend's draw handler
    exists exactly when the coloured copy does (as the UI calls it: EXEC_DEFAULT with undo)."""
    from radiometer.operators import false_colour as fc

    assert "UNDO" in bpy.types.RADIOMETER_OT_toggle_false_colour.bl_options
    _grid_scene(tmp_path)
    bpy.ops.ed.undo_push(message="grid")
    assert bpy.ops.radiometer.toggle_false_colour("EXEC_DEFAULT", True) == {"FINISHED"}
    marked = lambda: [ob.name for ob in bpy.data.objects if ob.get(fc.OBJECT_MARK)]  # noqa: E731
    assert len(marked()) == 1 and fc._state["handler"] is not None
    assert bpy.ops.ed.undo() == {"FINISHED"}
    assert marked() == [] and not fc.is_shown() and fc._state["handler"] is None
    assert bpy.ops.ed.redo() == {"FINISHED"}
    assert len(marked()) == 1 and fc.is_shown() and fc._state["handler"] is not None
    assert bpy.ops.radiometer.toggle_false_colour("EXEC_DEFAULT", True) == {"FINISHED"}  # hide
    assert marked() == [] and not fc.is_shown()
    assert bpy.ops.ed.undo() == {"FINISHED"}  # the hide undone: shown again
    assert len(marked()) == 1 and fc._state["handler"] is not None
    fc.hide()

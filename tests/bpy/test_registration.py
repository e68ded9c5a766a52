"""Registration is an exact mirror image and settings survive save/reload (issue 2)."""

import os

import bpy
import pytest


def _snapshot():
    return {
        "types": set(dir(bpy.types)),
        "object_props": set(bpy.types.Object.bl_rna.properties.keys()),
        "scene_props": set(bpy.types.Scene.bl_rna.properties.keys()),
        "material_props": set(bpy.types.Material.bl_rna.properties.keys()),
        "add_menu": len(bpy.types.VIEW3D_MT_add._dyn_ui_initialize()) if hasattr(bpy.types.VIEW3D_MT_add, "_dyn_ui_initialize") else None,
        "handlers": {name: len(getattr(bpy.app.handlers, name)) for name in dir(bpy.app.handlers)
                     if not name.startswith("_") and isinstance(getattr(bpy.app.handlers, name), list)},
        "keymaps": sum(len(km.keymap_items) for km in bpy.context.window_manager.keyconfigs.addon.keymaps)
        if bpy.context.window_manager.keyconfigs.addon else 0,
        "ops": set(dir(bpy.ops.radiometer)),
    }


def test_register_unregister_five_times_leaves_nothing_behind(tmp_path):
    import radiometer
    from radiometer.operators import live
    from radiometer.props import live_state
    from radiometer.operators import false_colour

    bpy.ops.wm.read_factory_settings(use_empty=True)
    before = _snapshot()
    assert not bpy.app.timers.is_registered(live.tick)
    for _ in range(5):
        radiometer.register()
        assert hasattr(bpy.types.Scene, "radiometer")
        assert "radiometer_meter" in bpy.types.Object.bl_rna.properties.keys()
        assert hasattr(bpy.ops.radiometer, "measure") and hasattr(bpy.ops.radiometer, "add_meter")
        # The live mode: one depsgraph handler and one timer, exactly once.
        assert bpy.app.handlers.depsgraph_update_post.count(live.on_depsgraph_update) == 1
        assert bpy.app.timers.is_registered(live.tick)
        bpy.context.scene.radiometer.live = True  # leaves live state behind, which unregister forgets
        assert live_state._states
        # The false-colour overlay: a coloured copy and a draw handler, both gone after unregister.
        lux = tmp_path / "grid.csv"
        lux.write_text("row,col,x,y,z,illuminance_lx,irradiance_W_m2,rel_std_error\n0,0,0,0,0,10,0,0\n"
                       "0,1,0,0,0,20,0,0\n", encoding="utf-8")
        bpy.ops.mesh.primitive_plane_add()
        analysis = bpy.context.scene.radiometer_analysis
        analysis.grid_target, analysis.grid_csv = bpy.context.active_object.name, str(lux)
        assert bpy.ops.radiometer.toggle_false_colour() == {"FINISHED"}
        assert false_colour._state["handler"] is not None
        coloured = false_colour._state["objects"][0]
        radiometer.unregister()
        assert _snapshot() == before
        assert false_colour._state["handler"] is None and coloured not in bpy.data.objects
        assert false_colour._on_load_pre not in bpy.app.handlers.load_pre
        assert live.on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post
        assert not bpy.app.timers.is_registered(live.tick)
        assert not live_state._states
    assert not hasattr(bpy.types.Scene, "radiometer")


def test_expected_operators_are_registered(clean_blender):
    ops = set(dir(bpy.ops.radiometer))
    for name in ("add_meter", "measure"):
        assert name in ops


def test_meter_settings_and_readings_survive_save_and_reload(clean_blender, tmp_path):
    scene = bpy.context.scene
    bpy.ops.radiometer.add_meter(kind="LUMINANCE", acceptance_deg=2.5)
    meter = bpy.context.active_object
    name = meter.name
    # readings are read-only properties, stored as ID properties by measure.meter.meter_objects.write_reading
    meter.radiometer_meter["photometric"] = 123.25
    meter.radiometer_meter["has_reading"] = True
    meter.radiometer_meter["notes"] = "note a | note b"
    scene.radiometer.efficacy_convention = "RADIANCE_179"
    path = str(tmp_path / "saved.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects[name]
    m = obj.radiometer_meter
    assert m.is_meter and m.kind == "LUMINANCE"
    assert m.acceptance_deg == pytest.approx(2.5)
    assert m.photometric == pytest.approx(123.25)
    assert m.notes == "note a | note b"
    assert bpy.context.scene.radiometer.efficacy == pytest.approx(179.0)
    assert os.path.exists(path)


def test_api_assign_brdf_returns_fidelity(clean_blender):
    from radiometer import api

    mat = bpy.data.materials.new("m")
    fidelity = api.assign_brdf(mat, "lambert", method="nodes", albedo=0.5)
    assert fidelity.kind == "exact"
    assert mat.radiometer_brdf.model == "lambert"


def test_all_ui_operators_registered(clean_blender):
    ops = set(dir(bpy.ops.radiometer))
    for name in ("add_meter", "measure", "assign_brdf", "brdf_plot", "check_inverse_square", "check_cosine_law",
                 "illuminance_grid", "convergence_study", "export_report", "set_light_power"):
        assert name in ops, name


def test_register_twice_is_harmless():
    import radiometer

    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    try:
        radiometer.register()  # idempotent: no "already registered" error
        assert hasattr(bpy.types.Scene, "radiometer")
    finally:
        radiometer.unregister()
    assert not hasattr(bpy.types.Scene, "radiometer")

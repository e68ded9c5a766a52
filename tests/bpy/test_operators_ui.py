"""Findable and native: a Radiometer menu with every operator, tooltips, Add Meter options, readings."""

import math

import bpy
import pytest

OWN_OPERATORS = ("add_meter", "measure", "set_light_power", "check_inverse_square", "check_cosine_law",
                 "illuminance_grid", "convergence_study", "export_report")


def _undescribed(rna):
    return [p.identifier for p in rna.properties if p.identifier not in ("rna_type", "name") and not p.description]


def test_meter_and_scene_settings_have_tooltips(clean_blender):
    from radiometer.props import meter

    for cls in meter.classes:
        assert _undescribed(cls.bl_rna) == [], cls.__name__


def test_every_radiometer_property_group_has_tooltips(clean_blender):
    """Every property of every registered Radiometer property group (meter, BRDF, analysis ...)."""
    import radiometer.props as props

    groups = []
    for module in ("meter", "brdf", "analysis"):
        groups += list(getattr(props, module).classes)
    # and any other registered group of the add-on (operators' or panels' own)
    pending = list(bpy.types.PropertyGroup.__subclasses__())
    while pending:
        cls = pending.pop()
        pending += cls.__subclasses__()
        if cls.__module__.startswith("radiometer") and cls not in groups and getattr(cls, "is_registered", False):
            groups.append(cls)
    assert len(groups) >= 6
    for cls in groups:
        assert _undescribed(cls.bl_rna) == [], cls.__name__


def test_every_radiometer_operator_and_its_properties_have_tooltips(clean_blender):
    names = [n for n in dir(bpy.ops.radiometer) if not n.startswith("_")]
    assert set(OWN_OPERATORS) <= set(names)
    assert {"assign_brdf", "brdf_plot", "brdf_preset", "enable_osl", "calibrate_world",
            "import_luminaire"} <= set(names)
    missing = {}
    for name in names:
        rna = getattr(bpy.ops.radiometer, name).get_rna_type()
        bad = _undescribed(rna) + ([] if rna.description else ["<operator>"])
        if bad:
            missing[name] = bad
    assert missing == {}


@pytest.mark.parametrize("name", OWN_OPERATORS)
def test_operator_properties_have_tooltips(clean_blender, name):
    rna = getattr(bpy.ops.radiometer, name).get_rna_type()
    assert rna.description, name
    assert _undescribed(rna) == [], name


def test_radiometer_menu_lists_every_operator_and_sits_in_the_object_menu(clean_blender):
    from radiometer.panels import meter

    assert hasattr(bpy.types, "RADIOMETER_MT_main")
    listed = set(meter.MENU_OPERATORS)
    registered = set(dir(bpy.ops.radiometer))
    assert listed <= registered  # the fixed part names real operators; the rest is listed dynamically
    entries = bpy.types.VIEW3D_MT_object._dyn_ui_initialize()
    assert meter._draw_menu_entry in entries


def test_add_meter_at_a_location_aligned_to_the_cursor(clean_blender):
    scene = bpy.context.scene
    scene.cursor.location = (1.0, 2.0, 3.0)
    scene.cursor.rotation_euler = (0.3, -0.2, 1.1)
    assert bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", align="CURSOR") == {"FINISHED"}
    ob = bpy.context.active_object
    assert tuple(ob.location) == pytest.approx((1.0, 2.0, 3.0))
    assert tuple(ob.rotation_euler) == pytest.approx((0.3, -0.2, 1.1), abs=1e-6)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(0.5, 0.0, 0.0), rotation=(0.0, 0.2, 0.0))
    ob = bpy.context.active_object
    assert tuple(ob.location) == pytest.approx((0.5, 0.0, 0.0)) and ob.rotation_euler[1] == pytest.approx(0.2)


def test_add_meter_defaults_and_view_align_without_a_view(clean_blender):
    bpy.ops.radiometer.add_meter(kind="LUMINANCE")
    assert bpy.context.active_object.rotation_euler[0] == pytest.approx(math.pi / 2)  # looks along +Y
    assert bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", align="VIEW") == {"FINISHED"}  # no view: world
    assert tuple(bpy.context.active_object.rotation_euler) == pytest.approx((0.0, 0.0, 0.0))


def test_set_photometric_power_runs_with_its_properties(clean_blender, build):
    light = build.light(bpy.context.scene, "POINT", (0, 0, 1), energy=1.0)
    bpy.context.view_layer.objects.active = light
    assert bpy.ops.radiometer.set_light_power(unit="LUMEN", value=683.0) == {"FINISHED"}
    from radiometer.measure.authoring import light_power

    assert light_power.photometric_power(light, "LUMEN", bpy.context.scene) == pytest.approx(683.0, rel=1e-6)


@pytest.mark.parametrize("value, rel, exact, text", [
    (402.283, 0.0112, False, "402"),
    (402.283, 0.0012, False, "402.3"),
    (39.7335, 0.0012, False, "39.73"),
    (8885.87, 0.0057, False, "8890"),
    (0.04567, 0.02, False, "0.0457"),
    (123456.7, 0.01, False, "123000"),
    (2.5e7, 0.01, False, "2.50e+07"),
    (431.0958, 0.0, True, "431.10"),
    (float("nan"), 0.01, False, "n/a"),
    (0.0, 0.0, True, "0"),
])
def test_readings_keep_the_digits_their_error_supports(clean_blender, value, rel, exact, text):
    from radiometer.panels.meter import format_value

    assert format_value(value, rel, exact) == text

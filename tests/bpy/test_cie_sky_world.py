"""CIE sky worlds (api.set_cie_sky, measure/authoring/sky.py): the meter reads them exactly where nothing is
above its horizon, against an independent integration written here; a Cycles render of a white patch
(tests/bpy/reference.py) agrees; an edited sky is no longer called exact."""

import importlib.util
import math
import pathlib

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.errors import RadiometerError


def _load(name):
    spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")  # imports nothing from Radiometer

SUN = np.array([math.cos(math.radians(30)) * math.sin(math.radians(200)),
                math.cos(math.radians(30)) * math.cos(math.radians(200)), math.sin(math.radians(30))])


def independent(normal, sky, sun, e_h, rho, n_zen=300):
    """E (lux) on an unobstructed plane: ISO 15469 Table 1 / CIE overcast formulas written out here,
    midpoint rule in (Z, azimuth), normalised by the same rule's horizontal integral; ground
    rho E_h / pi over the lower hemisphere by the same rule (mirror cells)."""
    table = {12: (-1, -0.32, 10, -3, 0.45), 7: (0, -1, 5, -2.5, 0.3)}
    dz = (math.pi / 2) / n_zen
    z = (np.arange(n_zen) + 0.5) * dz
    da = 2 * math.pi / (4 * n_zen)
    az = (np.arange(4 * n_zen) + 0.5) * da
    Z, A = np.meshgrid(z, az, indexing="ij")
    if sky == "overcast":
        rel = 1 + 2 * np.cos(Z)
    else:
        a, b, c, d, e = table[sky]
        zs, a_s = math.acos(sun[2]), math.atan2(sun[0], sun[1])
        cos_chi = np.cos(zs) * np.cos(Z) + np.sin(zs) * np.sin(Z) * np.cos(A - a_s)
        chi = np.arccos(np.clip(cos_chi, -1, 1))
        rel = (1 + c * (np.exp(d * chi) - math.exp(d * math.pi / 2)) + e * cos_chi ** 2) * (1 + a * np.exp(b / np.cos(Z)))
    x, y, up = np.sin(Z) * np.sin(A), np.sin(Z) * np.cos(A), np.cos(Z)
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    w = np.sin(Z) * dz * da
    lz_scale = e_h / np.sum(rel * up * w)
    sky_part = lz_scale * np.sum(rel * np.maximum(n[0] * x + n[1] * y + n[2] * up, 0) * w)
    ground = rho * e_h / math.pi * np.sum(np.maximum(n[0] * x + n[1] * y - n[2] * up, 0) * w)
    return sky_part + ground


NORMALS = [(0, 0, 1), (0, 1, 0), (0, -1, 0), (1, 0, 0), (0.4, -0.6, 0.5), (-0.2, 0.5, -0.8)]


@pytest.mark.parametrize("sky", ["overcast", 12, 7])
def test_meter_reads_cie_sky_exactly(clean_blender, sky):
    scene = bpy.context.scene
    info = api.set_cie_sky(scene, sky, horizontal_illuminance_lux=12_000.0, sun_direction=SUN, ground_reflectance=0.25)
    assert scene.world.name == info["world"]
    readings = api.measure_illuminance(np.zeros((len(NORMALS), 3)), np.array(NORMALS, float))
    assert readings[0].illuminance == pytest.approx(12_000.0, rel=1e-9)
    for r, n in zip(readings, NORMALS):
        assert r.exact and r.method == "analytic", r.notes
        assert r.illuminance == pytest.approx(independent(n, sky, SUN, 12_000.0, 0.25), rel=1e-4), n
        assert r.rel_std_error < 1e-6


def test_render_of_cie_sky_agrees_with_exact_reading(clean_blender):
    scene = bpy.context.scene
    api.set_cie_sky(scene, 12, horizontal_illuminance_lux=10_000.0, sun_direction=SUN)
    scene.render.engine = "CYCLES"
    for n in ((0.0, 0.0, 1.0), tuple(-SUN * [1, 1, 0] / np.linalg.norm(SUN[:2]))):  # up; vertical, facing away
        exact = api.measure_illuminance((0, 0, 0), n).illuminance
        e_rgb, rel, _info = reference.reference_irradiance(scene, (0, 0, 0), n, target_rel_error=1e-2, max_seconds=8)
        _y, e_ref = reference.luminance(e_rgb)
        print("render vs exact", n, e_ref, exact, rel)
        assert abs(e_ref - exact) <= 3 * rel * e_ref, (n, e_ref, exact, rel)


def test_edited_sky_is_not_exact_and_bad_input(clean_blender):
    scene = bpy.context.scene
    api.set_cie_sky(scene, "overcast", horizontal_illuminance_lux=10_000.0)
    assert api.world_model(scene).kind == "cie_sky"
    tree = scene.world.node_tree
    node = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeMath" and n.operation == "MULTIPLY_ADD")
    node.inputs[1].default_value *= 1.5
    w = api.world_model(scene)
    assert not w.modelled and "edited" in w.reason
    with pytest.raises(RadiometerError, match="sky type"):
        api.set_cie_sky(scene, 16)
    with pytest.raises(RadiometerError, match="sun"):
        api.set_cie_sky(scene, 12)
    with pytest.raises(RadiometerError, match="below the horizon"):
        api.set_cie_sky(scene, 12, sun_direction=(0, 1, -0.2))
    with pytest.raises(RadiometerError, match="> 0"):
        api.set_cie_sky(scene, "overcast", horizontal_illuminance_lux=float("nan"))


def test_set_cie_sky_operator_is_undoable_and_uses_the_scene_sun(clean_blender, build):
    scene = bpy.context.scene
    assert "UNDO" in bpy.types.RADIOMETER_OT_set_cie_sky.bl_options
    assert bpy.ops.radiometer.set_cie_sky(sky_type="overcast", horizontal_illuminance=8000.0) == {"FINISHED"}
    assert api.measure_illuminance((0, 0, 0), (0, 0, 1)).illuminance == pytest.approx(8000.0, rel=1e-9)
    with pytest.raises(RuntimeError, match="depends on the sun"):  # no Sun light yet
        bpy.ops.radiometer.set_cie_sky(sky_type="12")
    sun = build.light(scene, "SUN", rotation=(math.radians(60), 0, math.radians(200)), energy=0.0)  # direction only
    assert bpy.ops.radiometer.set_cie_sky(sky_type="12", horizontal_illuminance=9000.0) == {"FINISHED"}
    w = api.world_model(scene)
    np.testing.assert_allclose(w.sun_direction, np.array(sun.matrix_world.to_3x3().col[2]), atol=1e-6)
    assert api.measure_illuminance((0, 0, 0), (0, 0, 1)).illuminance == pytest.approx(9000.0, rel=1e-9)


def test_the_operator_and_the_sun_study_take_the_mapped_skies(clean_blender, monkeypatch):
    """``api.SKY_MODELS`` drives the *Set CIE Sky* list and the sun study's check (tests/test_sky_models.py
    the CLI's): an entry added to the mapping is offered and accepted, a name outside it is refused."""
    import dataclasses
    import datetime as dt

    from radiometer.operators import sky as sky_operator
    from radiometer.radiometry.skies import sky_models

    items = sky_operator._sky_items(None, None)
    assert [api.sky_model(ident) for ident, _label, _d in items] == list(api.SKY_MODELS.values())
    assert [label for _i, label, _d in items] == [m.label for m in api.SKY_MODELS.values()]
    uniform = dataclasses.replace(api.SKY_MODELS["cie:5"], name="test:uniform", label="test uniform sky")
    monkeypatch.setitem(sky_models.SKY_MODELS, "test:uniform", uniform)
    assert ("test:uniform", "test uniform sky") in [(i, label) for i, label, _d in sky_operator._sky_items(None, None)]
    when = [dt.datetime(2026, 6, 21, 12, tzinfo=dt.timezone.utc)]
    with pytest.raises(RadiometerError, match="sky model.*test:uniform"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), when, latitude_deg=51.5, longitude_deg=0.0, sky="cie:16")

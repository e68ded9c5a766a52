"""Photometric light power: setting lumens/candela/lux/nits gives back the same reading (issue 3)."""

import math

import bpy
import pytest

from radiometer import api
from radiometer.errors import RadiometerError
from radiometer.measure.authoring import light_power


def test_candela_sets_the_illuminance_at_one_metre(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", (0, 0, 1), energy=1.0, shadow_soft_size=0.0)
    bpy.context.view_layer.objects.active = lamp
    assert bpy.ops.radiometer.set_light_power(unit="CANDELA", value=100.0) == {"FINISHED"}
    # E_v = I_v / d^2 (lecture: inverse-square law) -> 100 lx at 1 m.
    assert api.measure_illuminance((0, 0, 0), method="analytic").illuminance == pytest.approx(100.0, rel=1e-6)  # energy is stored as float32
    assert lamp.data.energy == pytest.approx(4 * math.pi * 100 / 683, rel=1e-6)


def test_lumens_honour_temperature_and_exposure(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", (0, 0, 1), energy=1.0, shadow_soft_size=0.0,
                       use_temperature=True, temperature=2700.0, exposure=1.0)
    light_power.set_photometric_power(lamp, "LUMEN", 800.0, scene)
    assert light_power.photometric_power(lamp, "LUMEN", scene) == pytest.approx(800.0, rel=1e-6)  # float32 energy
    # Isotropic point: E_v = Phi / (4 pi d^2).
    lux = api.measure_illuminance((0, 0, 0), method="analytic").illuminance
    assert lux == pytest.approx(800.0 / (4 * math.pi), rel=1e-6)


def test_sun_lux_and_area_nits(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    sun = build.light(scene, "SUN", energy=1.0, angle=0.0)
    light_power.set_photometric_power(sun, "LUX", 1e5, scene)
    assert api.measure_illuminance((0, 0, 0), method="analytic").illuminance == pytest.approx(1e5, rel=1e-6)  # energy is stored as float32
    sun.data.energy = 0.0
    panel = build.light(scene, "AREA", (0, 0, 1), energy=1.0, shape="RECTANGLE", size=0.5, size_y=0.2)
    light_power.set_photometric_power(panel, "NIT", 3000.0, scene)
    lum = api.measure_luminance((0, 0, 0.5), (0, 0, 1), acceptance_deg=1.0)
    assert lum.luminance == pytest.approx(3000.0, rel=1e-3 + 3 * lum.rel_std_error)


def test_wrong_unit_for_light_type_is_refused(clean_blender, build):
    sun = build.light(bpy.context.scene, "SUN", energy=1.0)
    with pytest.raises(RadiometerError, match="does not apply"):
        light_power.set_photometric_power(sun, "CANDELA", 10.0)
    with pytest.raises(RadiometerError, match="finite"):
        light_power.set_photometric_power(sun, "LUX", float("nan"))


def test_photometric_light_flux_comes_from_its_table(clean_blender, tmp_path):
    """An imported isotropic IES file of 100 cd emits 4 pi x 100 lm (closed form), not K x watts."""
    from radiometer import api
    from radiometer.measure.authoring import light_power
    from radiometer.errors import RadiometerError

    path = tmp_path / "iso.ies"
    path.write_text("IESNA:LM-63-2002\n[TEST] isotropic\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n"
                    "0 90 180\n0\n100 100 100\n")
    obj = api.import_luminaire(str(path))
    assert light_power.photometric_power(obj, "LUMEN") == pytest.approx(400 * math.pi, rel=1e-4)
    with pytest.raises(RadiometerError, match="come from its file"):
        light_power.photometric_power(obj, "CANDELA")

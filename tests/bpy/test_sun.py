"""The sun as a Blender light (issue 19 item 2): direction, strength read back by the meter, horizon,
north offset, the Daylight operator and its undo step."""

import datetime as dt
import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.errors import RadiometerError
from radiometer.radiometry.sun import solar_position as sp

UTC = dt.timezone.utc
NOON = dt.datetime(2026, 6, 21, 12, 0, tzinfo=UTC)


def _to_sun(obj):
    # A Blender sun shines along its local -Z: its local +Z points at the sun (no parent here).
    return np.array(obj.rotation_euler.to_matrix().col[2])


def test_set_sun_points_at_the_sun_and_the_meter_reads_the_given_illuminance(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    out = api.set_sun(scene, 51.5, -0.12, NOON, direct_normal_illuminance_lux=90_000.0)
    obj = scene.objects[out["object"]]
    pos = api.sun_position(51.5, -0.12, NOON)
    assert obj.data.type == "SUN" and math.degrees(obj.data.angle) == pytest.approx(0.53)
    assert np.allclose(_to_sun(obj), pos.direction, atol=1e-6)
    assert out["above_horizon"] and out["model"] == "given"
    # K = 683 lm/W, white: strength = E / K
    assert obj.data.energy == pytest.approx(90_000.0 / 683.0, rel=1e-6)
    facing = api.measure_illuminance((0, 0, 0), pos.direction)
    assert facing.exact and facing.illuminance == pytest.approx(90_000.0, rel=1e-6)
    up = api.measure_illuminance((0, 0, 0), (0, 0, 1))
    assert up.illuminance == pytest.approx(90_000.0 * math.sin(math.radians(pos.elevation_deg)), rel=1e-5)


def test_the_sun_has_a_stated_spectrum_for_melanopic_readings(clean_blender, build):
    """A new Radiometer sun gets CIE D55 (stated in its notes), so its direct light reads in mel-EDI exactly;
    a spectrum the user set is kept when the sun is moved."""
    from radiometer.radiometry.photometry import action_spectra, spectral

    scene = bpy.context.scene
    build.black_world(scene)
    out = api.set_sun(scene, 51.5, -0.12, NOON, direct_normal_illuminance_lux=90_000.0)
    obj = scene.objects[out["object"]]
    assert obj.data["radiometer_spectrum"] == "D55" and any("D55" in n for n in out["notes"])
    pos = api.sun_position(51.5, -0.12, NOON)
    r = api.spectral_reading((0, 0, 0), pos.direction)
    der = float(action_spectra.alpha_opic_der(spectral.cie_illuminant("D55"))[4])
    assert r["exact"] and r["mel_edi_lx"] == pytest.approx(90_000.0 * der, rel=1e-6)
    obj.data["radiometer_spectrum"] = "D5000"
    out = api.set_sun(scene, 51.5, -0.12, NOON.replace(hour=15))
    assert obj.data["radiometer_spectrum"] == "D5000" and not any("D55" in n for n in out["notes"])


def test_scene_efficacy_and_unit_scale_are_honoured(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    scene.radiometer.efficacy = 179.0
    scene.unit_settings.scale_length = 0.01  # centimetres
    out = api.set_sun(scene, 40.0, -74.0, NOON.replace(hour=16), direct_normal_illuminance_lux=50_000.0)
    r = api.measure_illuminance((0, 0, 0), out["direction"])
    assert r.illuminance == pytest.approx(50_000.0, rel=1e-6)


def test_update_keeps_one_sun_and_default_model_is_ies_clear_day(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    first = api.set_sun(scene, -33.87, 151.21, NOON.replace(hour=2))  # Sydney midday in winter
    second = api.set_sun(scene, -33.87, 151.21, NOON.replace(hour=4))
    suns = [ob for ob in scene.objects if ob.type == "LIGHT"]
    assert first["created"] and not second["created"] and len(suns) == 1
    pos = api.sun_position(-33.87, 151.21, NOON.replace(hour=4))
    expected = float(sp.clear_day_direct_normal_illuminance(pos.zenith_deg, pos.earth_sun_distance_au))
    assert second["direct_normal_illuminance_lux"] == pytest.approx(expected, rel=1e-12)
    assert 40_000 < expected < 110_000  # a clear winter day's sun (well below the 127.5 klx above the air)
    assert np.allclose(_to_sun(suns[0]), pos.direction, atol=1e-6)
    r = api.measure_illuminance((0, 0, 0), pos.direction)
    assert r.illuminance == pytest.approx(expected, rel=1e-6)


def test_below_the_horizon_the_sun_is_off(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    out = api.set_sun(scene, 51.5, -0.12, NOON.replace(hour=0), direct_normal_illuminance_lux=90_000.0)
    assert not out["above_horizon"] and out["elevation_deg"] < 0
    assert scene.objects[out["object"]].data.energy == 0.0 and out["direct_normal_illuminance_lux"] == 0.0


def test_north_offset_turns_the_sun_about_z(clean_blender):
    scene = bpy.context.scene
    a = api.set_sun(scene, 48.0, 11.0, NOON.replace(hour=8), direct_normal_illuminance_lux=1.0)
    b = api.set_sun(scene, 48.0, 11.0, NOON.replace(hour=8), direct_normal_illuminance_lux=1.0, north_offset_deg=90.0)
    da, db = np.array(a["direction"]), np.array(b["direction"])
    # north turned 90 deg counter-clockwise: a vector (x, y) becomes (-y, x)
    assert np.allclose(db, [-da[1], da[0], da[2]], atol=1e-12)
    assert np.allclose(_to_sun(scene.objects[b["object"]]), db, atol=1e-6)


def test_bad_input_is_one_line_and_changes_nothing(clean_blender):
    scene = bpy.context.scene
    with pytest.raises(RadiometerError, match="time zone"):
        api.set_sun(scene, 51.5, 0.0, dt.datetime(2026, 6, 21, 12))
    with pytest.raises(RadiometerError):
        api.set_sun(scene, 95.0, 0.0, NOON)
    with pytest.raises(RadiometerError):
        api.set_sun(scene, 51.5, 0.0, NOON, direct_normal_illuminance_lux=-5.0)
    assert len(bpy.data.lights) == 0 and len(bpy.data.objects) == 0


def test_daylight_operator_city_preset_and_undo(clean_blender):
    scene = bpy.context.scene
    s = scene.radiometer_daylight
    s.city = "TOKYO"
    assert (s.latitude, s.longitude, s.time_zone) == (pytest.approx(35.6762), pytest.approx(139.6503), "Asia/Tokyo")
    s.year, s.month, s.day, s.hour, s.minute = 2026, 3, 20, 9, 30
    s.direct_normal_illuminance = 80_000.0
    bpy.ops.ed.undo_push(message="before sun")
    assert bpy.ops.radiometer.set_sun("EXEC_DEFAULT", True) == {"FINISHED"}
    sun = next(ob for ob in bpy.context.scene.objects if ob.type == "LIGHT")
    when = dt.datetime(2026, 3, 20, 0, 30, tzinfo=UTC)  # 09:30 JST = 00:30 UTC
    pos = api.sun_position(35.6762, 139.6503, when)
    assert np.allclose(_to_sun(sun), pos.direction, atol=1e-5)
    assert sun.data.energy == pytest.approx(80_000.0 / 683.0, rel=1e-6)
    assert bpy.ops.ed.undo() == {"FINISHED"}
    assert not [ob for ob in bpy.context.scene.objects if ob.type == "LIGHT"]
    # a wall time that does not exist is refused with one line, nothing created
    s = bpy.context.scene.radiometer_daylight
    s.time_zone, s.month, s.day, s.hour, s.minute = "Europe/London", 3, 29, 1, 30
    with pytest.raises(RuntimeError, match="does not exist"):
        bpy.ops.radiometer.set_sun()
    s.time_zone = "Nowhere/Atlantis"
    with pytest.raises(RuntimeError, match="unknown time zone"):
        bpy.ops.radiometer.set_sun()
    assert not [ob for ob in bpy.context.scene.objects if ob.type == "LIGHT"]

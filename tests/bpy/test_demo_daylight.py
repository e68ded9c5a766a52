"""The daylit demo room (issue 19 item 7): it builds, sets the sun and reads what the closed forms say
where they hold; the sun patch behind the 6 mm pane reads at least the sun's light through it (Fresnel
transmittance of a clear slab, closed form below) plus the room's reflections."""

import math
import os

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.demo import daylight
from radiometer.measure.blender import request as request_of  # noqa: E402


def test_daylit_demo_room(clean_blender, tmp_path):
    out = daylight.run(str(tmp_path), quality="preview", stream=open(os.devnull, "w"))
    sun = out["sun"]
    pos = api.sun_position(daylight.SITE["latitude_deg"], daylight.SITE["longitude_deg"], daylight.local_time())
    assert sun["azimuth_deg"] == pytest.approx(float(pos.azimuth_deg), abs=1e-9)
    assert 30 < sun["elevation_deg"] < 45  # London, March equinox, noon: 90 - 51.5 + refraction
    m = out["meters"]
    e_dn = sun["direct_normal_illuminance_lux"]
    # Proven unoccluded with nothing above their horizon: the closed form, zero error. (In a batch that
    # renders other meters the meter labels every reading "hybrid", exact=False, even these.)
    roof = m["Roof (open sky)"]
    assert roof["rel_std_error"] == 0.0
    assert roof["illuminance_lx"] == pytest.approx(e_dn * math.sin(math.radians(sun["elevation_deg"])), rel=1e-5)
    facade = m["South facade"]
    assert facade["rel_std_error"] == 0.0
    assert facade["illuminance_lx"] == pytest.approx(facade["unobstructed_direct_lx"], rel=1e-5)
    patch = m["Floor in the sun patch"]
    assert patch["sunlit"] and not patch["exact"]
    # Through the pane: unpolarised Fresnel transmittance of a non-absorbing slab, T = (1 - R) / (1 + R) per
    # polarisation (incoherent multiple reflections; Born & Wolf), at the sun's incidence on the pane.
    cos_i = abs(float(np.dot(sun["direction"], (0.0, -1.0, 0.0))))
    n = 1.5
    cos_t = math.sqrt(1 - (1 - cos_i ** 2) / n ** 2)
    r_s = ((cos_i - n * cos_t) / (cos_i + n * cos_t)) ** 2
    r_p = ((n * cos_i - cos_t) / (n * cos_i + cos_t)) ** 2
    t_slab = 0.5 * ((1 - r_s) / (1 + r_s) + (1 - r_p) / (1 + r_p))
    assert 0.85 < t_slab < 0.95
    # the sun's light through the glass plus what the room reflects onto the patch, within 3 stated errors;
    # the room (albedo 0.3 floor, 0.6 walls, one window) adds well under 20 %
    low = t_slab * patch["unobstructed_direct_lx"] * (1 - 3 * patch["rel_std_error"])
    assert low <= patch["illuminance_lx"] <= 1.2 * t_slab * patch["unobstructed_direct_lx"]
    corner = m["Floor, back corner"]
    assert not corner["sunlit"] and 0 < corner["illuminance_lx"] < 0.05 * patch["illuminance_lx"]
    assert os.path.exists(out["blend"])
    bpy.ops.wm.open_mainfile(filepath=out["blend"])
    assert not bpy.data.objects["Window Pane"].hide_render
    assert [ob.name for ob in bpy.data.objects if ob.type == "LIGHT"] == ["Radiometer Sun"]


def test_daylit_demo_from_the_command_line(clean_blender, tmp_path, capsys):
    """`radiometer demo --daylight` runs the same room (the demo module imports no CLI code; the
    subcommand owns the options); an open window and another time change what the meters read."""
    import json

    from radiometer import cli

    out = tmp_path / "out"
    assert cli.main(["demo", "--daylight", "--open", "--time", "2026-06-21T15:00", "--out", str(out),
                     "--json", str(tmp_path / "d.json")]) == 0
    result = json.loads((tmp_path / "d.json").read_text())
    assert result["time"] == "2026-06-21T15:00:00+01:00"  # London summer time
    assert result["blend"] == str(out / "daylight_room.blend") and os.path.exists(result["blend"])
    # no temp file, no .blend1; the synthetic weather year beside the room
    assert sorted(p.name for p in out.iterdir()) == ["daylight_room.blend", "daylight_room_synthetic.epw"]
    bpy.ops.wm.open_mainfile(filepath=result["blend"])
    assert bpy.data.objects["Window Pane"].hide_render  # --open: the pane is hidden in renders
    capsys.readouterr()
    assert cli.main(["demo", "--open", "--out", str(out)]) == 2
    assert "--open and --time go with --daylight" in capsys.readouterr().err


def test_saved_daylit_room_is_ready_for_the_daylight_commands(clean_blender, tmp_path, capsys):
    """Issue 34, getting started: the saved room has a work plane, a camera and meter objects, the
    synthetic EPW beside it reads as a whole SYNTHETIC year, and `annual` runs on the saved room with
    neither --points nor --plane (the work plane found by its name) and that weather file."""
    import json

    from radiometer import cli
    from radiometer.radiometry.sun import epw

    out = daylight.run(str(tmp_path / "demo"), quality="preview", stream=open(os.devnull, "w"))
    weather = epw.read_epw(out["weather"])
    assert weather.is_full_year and weather.notes == [] and "SYNTHETIC" in weather.city
    bpy.ops.wm.open_mainfile(filepath=out["blend"])
    scene = bpy.context.scene
    assert [p.name for p in api.work_planes(scene)] == ["Work Plane"]
    plane = bpy.data.objects["Work Plane"]
    assert plane.hide_render and plane.location.z == pytest.approx(daylight.WORK_PLANE["height"])
    assert scene.camera is not None and scene.camera.name == "Camera"
    # the camera looks at the window: its view axis (local -Z) is the room's -Y (south)
    view = scene.camera.matrix_world.to_3x3() @ __import__("mathutils").Vector((0.0, 0.0, -1.0))
    assert tuple(view) == pytest.approx((0.0, -1.0, 0.0), abs=1e-6)
    meters = {ob.name: ob for ob in api.meter_objects(scene=scene)}
    assert sorted(meters) == sorted(daylight.METERS)
    for name, (location, normal) in daylight.METERS.items():
        ob = meters[name]
        assert tuple(ob.location) == pytest.approx(location)
        axis = ob.matrix_world.to_3x3() @ __import__("mathutils").Vector((0.0, 0.0, 1.0))
        assert tuple(axis) == pytest.approx(normal, abs=1e-6)
    capsys.readouterr()
    if bpy.app.version < (5, 0, 0):  # annual's one-render sky dome needs 5.0: the sun study runs on 4.5
        result_path = tmp_path / "sun.json"
        assert cli.main(["sun-study", out["blend"], "--start", "2026-03-20T10:00", "--end", "2026-03-20T14:00",
                         "--step", "120", "--lat", "51.5074", "--lon", "-0.1278", "--tz", "Europe/London",
                         "--resolution", "2", "2", "--quality", "preview", "--json", str(result_path)]) == 0, \
            capsys.readouterr().err
        result = json.loads(result_path.read_text())
        assert len(result["locations"]) == 4 and all(p[2] == pytest.approx(0.85) for p in result["locations"])
        assert len(result["sunlight_hours"]) == 4 and max(result["sunlight_hours"]) > 0  # the sun patch
        return
    result_path = tmp_path / "annual.json"
    assert cli.main(["annual", out["blend"], "--epw", out["weather"], "--resolution", "2", "2", "--quality", "preview",
                     "--json", str(result_path)]) == 0, capsys.readouterr().err
    result = json.loads(result_path.read_text())
    assert len(result["locations"]) == 4 and all(p[2] == pytest.approx(0.85) for p in result["locations"])
    assert result["whole_year"] and 0.0 <= result["sda_300_50"] <= 1.0
    assert "London (SYNTHETIC)" in capsys.readouterr().out


def test_saved_daylit_room_window_shows_the_clear_sky(clean_blender, tmp_path):
    """The saved sunny room's window shows the sky (before: a black world, so the camera saw 10-100 cd/m² of
    the room reflected in the pane). The world is the CIE clear sky (type 12) of the IES clear day, and a
    1 deg luminance reading from the camera through the pane, above the horizon, is the sky model's
    luminance in that direction times the thin pane's Fresnel transmittance (n = 1.5, two faces, multiple
    reflections; closed form here). What the estimate leaves out: the room reflected in the pane (r ~ 0.08
    of a ~400 cd/m² room, ~0.3 %)."""
    import json

    from radiometer.measure.authoring import sky
    from radiometer.measure.meter import camera
    from radiometer.radiometry.skies import cie_sky

    out = daylight.run(str(tmp_path / "demo"), quality="preview", stream=open(os.devnull, "w"))
    bpy.ops.wm.open_mainfile(filepath=out["blend"])
    scene = bpy.context.scene
    info = json.loads(scene.world[sky.CIE_SKY_TAG])
    elevation = out["sun"]["elevation_deg"]
    e_h = 800.0 + 15500.0 * math.sin(math.radians(elevation)) ** 0.5  # IES clear day, lx
    assert info["sky_type"] == 12 and info["horizontal_illuminance_lux"] == pytest.approx(e_h, rel=1e-12)
    eye = np.array(daylight.CAMERA["location"])
    through = np.array([0.0, -daylight.ROOM[1] / 2 - daylight.WALL, 1.6])  # the window's middle, 0.1 m above
    d = (through - eye) / np.linalg.norm(through - eye)
    reading = camera.measure_luminance(tuple(eye), tuple(d), acceptance_deg=1.0,
                                       request=request_of.build(scene, quality="preview"))
    sun = np.asarray(out["sun"]["direction"], float)
    lz = float(cie_sky.zenith_luminance(e_h, 12, sun))
    l_sky = lz * float(cie_sky.relative_luminance(d, 12, sun))
    ci = abs(d[1])
    ct = math.sqrt(1.0 - (1.0 - ci * ci) / 1.5 ** 2)
    rs, rp = ((ci - 1.5 * ct) / (ci + 1.5 * ct)) ** 2, ((1.5 * ci - ct) / (1.5 * ci + ct)) ** 2
    t_pane = 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp))
    expected = t_pane * l_sky
    assert expected > 5000.0  # a sunny day's sky through the window: kilo-candelas (black world: tens)
    assert reading.luminance == pytest.approx(expected, rel=0.01 + 3 * reading.rel_std_error)

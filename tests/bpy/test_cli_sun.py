"""CLI `sun` and `sun-study` (issue 19 item 7): position, --set into a copy of the .blend, a study from
a CSV of points or a plane grid, --json and --csv, one-line errors."""

import datetime as dt
import json
import math

import bpy
import numpy as np
import pytest

from radiometer import api, cli

LONDON = ["--lat", "51.5", "--lon", "-0.12"]


def _err_line(capsys):
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("radiometer: error")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def test_sun_position_json_matches_the_api(clean_blender, tmp_path, capsys):
    out = tmp_path / "sun.json"
    assert cli._blender_cli(["sun", "--time", "2026-06-21T12:00", "2026-12-21T12:00", "--tz", "Europe/London",
                             *LONDON, "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    summer = dt.datetime(2026, 6, 21, 11, tzinfo=dt.timezone.utc)  # 12:00 BST
    winter = dt.datetime(2026, 12, 21, 12, tzinfo=dt.timezone.utc)  # 12:00 GMT
    pos = api.sun_position(51.5, -0.12, [summer, winter])
    assert [p["time"] for p in data["positions"]] == ["2026-06-21T12:00:00+01:00", "2026-12-21T12:00:00+00:00"]
    assert np.allclose([p["azimuth_deg"] for p in data["positions"]], pos.azimuth_deg, atol=1e-12)
    assert np.allclose([p["elevation_deg"] for p in data["positions"]], pos.elevation_deg, atol=1e-12)
    assert "azimuth" in capsys.readouterr().out


@pytest.mark.parametrize("args, fragment", [
    (["--time", "2026-06-21T12:00"], "no UTC offset"),
    (["--time", "noon", "--tz", "UTC"], "not an ISO 8601"),
    (["--time", "2026-06-21T12:00", "--tz", "Mars/Olympus"], "unknown time zone"),
    (["--time", "2026-03-29T01:30", "--tz", "Europe/London"], "does not exist"),
    (["--time", "2026-06-21T12:00+00:00", "--set"], "--out"),
])
def test_sun_bad_input_is_one_line(clean_blender, capsys, args, fragment):
    assert cli._blender_cli(["sun", *args, *LONDON]) == 2
    assert fragment in _err_line(capsys)


def test_sun_set_writes_a_copy_with_the_sun(clean_blender, tmp_path, capsys):
    src = tmp_path / "site.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(src))
    out = tmp_path / "site_sun.blend"
    assert cli._blender_cli(["sun", str(src), "--time", "2026-06-21T09:00+01:00", *LONDON, "--lux", "90000",
                             "--set", "--out", str(out)]) == 0
    assert out.exists() and not list(tmp_path.glob("*.blend1")) and not list(tmp_path.glob(".*tmp*"))
    bpy.ops.wm.open_mainfile(filepath=str(src))
    assert not [ob for ob in bpy.data.objects if ob.type == "LIGHT"]  # the input is untouched
    bpy.ops.wm.open_mainfile(filepath=str(out))
    sun = next(ob for ob in bpy.data.objects if ob.type == "LIGHT")
    assert sun.data.type == "SUN" and sun.data.energy == pytest.approx(90_000.0 / 683.0, rel=1e-6)


def test_sun_study_from_points_csv_and_plane(clean_blender, build, tmp_path, capsys):
    scene = bpy.context.scene
    plane = build.plane(scene, size=2.0, location=(0, 0, -0.001), name="Ground")
    plane.hide_render = True  # an imaginary grid plane: nothing to render, the study stays exact
    points = tmp_path / "points.csv"
    points.write_text("x,y,z,nx,ny,nz\n0,0,0,0,0,1\n1,2,3,1,0,0\n5,5,5\n", encoding="utf-8")
    js, table = tmp_path / "study.json", tmp_path / "study.csv"
    args = ["sun-study", "--start", "2026-03-20T06:00", "--end", "2026-03-20T18:00", "--step", "180", "--tz",
            "Europe/London", *LONDON, "--lux", "100000", "--quality", "preview"]
    assert cli._blender_cli([*args, "--points", str(points), "--json", str(js), "--csv", str(table)]) == 0
    data = json.loads(js.read_text())
    e = np.array(data["illuminance_lx"])
    assert e.shape == (5, 3) and len(data["sun"]) == 5
    times = [dt.datetime(2026, 3, 20, h, tzinfo=dt.timezone.utc) for h in (6, 9, 12, 15, 18)]
    pos = api.sun_position(51.5, -0.12, times)
    normals = np.array([[0, 0, 1], [1, 0, 0], [0, 0, 1]], float)
    expected = 100_000.0 * np.maximum(0, pos.direction @ normals.T) * (pos.elevation_deg > 0)[:, None]
    assert np.allclose(e, expected, rtol=1e-4, atol=1e-2)
    assert table.read_text().count("\n") == 1 + 5 * 3
    capsys.readouterr()
    js2 = tmp_path / "grid.json"
    assert cli._blender_cli([*args, "--plane", "Ground", "--resolution", "2", "2", "--json", str(js2)]) == 0
    grid = json.loads(js2.read_text())
    assert np.array(grid["illuminance_lx"]).shape == (5, 4) and len(grid["locations"]) == 4
    assert "sunlight hours" in capsys.readouterr().out
    # one-line errors
    assert cli._blender_cli([*args, "--plane", "Nope"]) == 2
    assert "no object named" in _err_line(capsys)
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0,0\n1,2\n", encoding="utf-8")
    assert cli._blender_cli([*args, "--points", str(bad)]) == 2
    assert "line 2" in _err_line(capsys)
    assert cli._blender_cli([*args[:4], "2026-03-19T06:00", *args[5:], "--points", str(points)]) == 2
    assert "before --start" in _err_line(capsys)

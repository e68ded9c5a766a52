"""Daylight maps through Blender (issue 34): the side-lit room's plan from the captured scene (its 4 x 3 m
outline and the 2 m window, the room's own dimensions), and `daylight-factor --plane --png` / api.daylight_map
writing the map; the --png target is checked before any work, and --png with --points is refused."""

import pathlib
import runpy
import types

import bpy
import numpy as np
import pytest

from radiometer import api, cli
from radiometer.errors import RadiometerError


def _room():
    """tests/bpy/daylight_room.py as a namespace (its names run as a script)."""
    return types.SimpleNamespace(**runpy.run_path(str(pathlib.Path(__file__).with_name("daylight_room.py"))))


room = _room()


def _side_lit_room(build):
    scene = bpy.context.scene
    room.build_blender(scene)
    plane = build.plane(scene, size=1.0, location=(room.W / 2, room.D / 2, 0.85), name="Work plane")
    plane.scale = (room.W - 0.4, room.D - 0.4, 1.0)  # render-visible: its own triangles lie in the cut
    return scene, plane


def test_room_plan_from_the_scene(clean_blender, build):
    from radiometer.measure.reports import daylight_maps

    scene, _plane = _side_lit_room(build)
    walls, openings = daylight_maps.room_plan(scene, 0.85)
    assert np.linalg.norm(walls[:, 1] - walls[:, 0], axis=1).sum() == pytest.approx(2 * (room.W + room.D), rel=1e-6)
    assert len(openings) == 1
    assert sorted(map(tuple, np.round(openings[0], 6))) == [(1.0, 0.0), (3.0, 0.0)]


def test_daylight_factor_map_cli_and_api(clean_blender, build, tmp_path, capsys):
    scene, plane = _side_lit_room(build)
    png = tmp_path / "df.png"
    # the target is checked before the work: a missing folder fails at once, one line, nothing written
    assert cli._blender_cli(["daylight-factor", "--plane", "Work plane", "--png", str(tmp_path / "no" / "x.png")]) == 2
    assert "--png file" in capsys.readouterr().err
    assert cli._blender_cli(["daylight-factor", "--points", str(tmp_path / "p.csv"), "--png", str(png)]) == 2
    assert "--png goes with --plane" in capsys.readouterr().err
    assert cli._blender_cli(["daylight-factor", "--plane", "Work plane", "--resolution", "5", "4", "--quality",
                             "preview", "--png", str(png)]) == 0
    assert f"wrote {png}" in capsys.readouterr().out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["df.png"]
    # the API: the same map from a result; other results and bad metrics are one-line errors
    g = api.daylight_factor_grid(plane, resolution=(3, 2), quality="preview")
    assert np.all(np.diff(g.daylight_factor[:, 1]) < 0)  # darker away from the window (y = 0)
    out = tmp_path / "api.png"
    assert api.daylight_map(g, str(out)) == str(out) and out.stat().st_size > 0
    with pytest.raises(RadiometerError, match="maps only its daylight factor"):
        api.daylight_map(g, str(tmp_path / "y.png"), metric="sda")
    with pytest.raises(RadiometerError, match="no daylight map for a dict"):
        api.daylight_map({}, str(tmp_path / "z.png"))
    assert not (tmp_path / "y.png").exists() and not (tmp_path / "z.png").exists()


def test_map_of_points_off_one_plane_refused_before_the_work(clean_blender, build, tmp_path, capsys):
    _side_lit_room(build)
    points = tmp_path / "p.csv"
    points.write_text("2,0.75,0.85\n2,1.5,1.2\n", encoding="utf-8")
    png = tmp_path / "sun.png"
    assert cli._blender_cli(["sun-study", "--start", "2026-03-21T12:00+00:00", "--end", "2026-03-21T12:00+00:00",
                             "--lat", "51.5", "--lon", "0", "--points", str(points), "--png", str(png)]) == 2
    err = capsys.readouterr()
    assert "not on one horizontal plane" in err.err and "sun study:" not in err.out  # nothing measured
    assert not png.exists()

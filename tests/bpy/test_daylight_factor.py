"""Daylight factor (api.daylight_factor / daylight_factor_grid, measure/analyses/daylight_factor.py): exact
outdoors, a side-lit room against Radiance's rtrace run as a path tracer under the same sharp-horizon
overcast sky, the user's world, lights and data-blocks unchanged afterwards.

Radiance's results come from tests/data/radiance_cache/ when an earlier rtrace run had the same scene.rad,
sky.cal, rays, command and Radiance build (tests/bpy/daylight_room.py radiance_daylight_factor; a new key
runs rtrace and writes the entry, to be committed). RADIOMETER_RADIANCE_RERUN=1 runs rtrace every time."""

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


room = _load("daylight_room")


def _state(scene):
    ids = {name: sorted(b.name for b in getattr(bpy.data, name)) for name in ("objects", "worlds", "lights", "materials")}
    lights = {ob.name: (ob.hide_render, ob.data.energy) for ob in scene.objects if ob.type == "LIGHT"}
    return ids, lights, scene.world


def test_unobstructed_daylight_factor_is_exact(clean_blender, build):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("user world")
    scene.world = world
    build.light(scene, "POINT", (0, 0, 3), energy=1000.0)
    before = _state(scene)
    rs = api.daylight_factor([(0, 0, 0), (0, 0, 0), (5, 5, 1)], [(0, 0, 1), (0, 1, 0), (0, 0, -1)], ground_reflectance=0.3)
    vertical = 100 * ((math.pi / 6 + 4 / 9) / (7 * math.pi / 9) + 0.3 / 2)  # sky + ground, closed forms
    for r, want in zip(rs, (100.0, vertical, 30.0)):
        assert r.exact and r.method == "analytic"
        assert r.daylight_factor == pytest.approx(want, rel=1e-9)
    assert _state(scene) == before  # world, light (hidden during the run), data-blocks as they were
    with pytest.raises(RadiometerError, match="ground_reflectance"):
        api.daylight_factor((0, 0, 0), ground_reflectance=1.5)


def test_grid_statistics_and_en17037(clean_blender, build):
    scene = bpy.context.scene
    plane = build.plane(scene, size=2.0, location=(0, 0, 0.5), name="work plane")
    plane.hide_render = True  # an imaginary work plane
    g = api.daylight_factor_grid(plane, resolution=(3, 2), target_percent=2.0, median_external_illuminance_lux=15_000.0)
    np.testing.assert_allclose(g.daylight_factor, 100.0, rtol=1e-9)
    assert g.stats["average"] == pytest.approx(100.0) and g.stats["uniformity"] == pytest.approx(1.0)
    assert g.stats["share_above_target"] == 1.0
    lv = g.stats["en17037"]["levels"]
    assert lv["minimum"]["D_T"] == pytest.approx(2.0) and lv["minimum"]["D_TM"] == pytest.approx(100 / 150)
    assert lv["high"]["D_T"] == pytest.approx(5.0) and all(v["met"] for v in lv.values())
    from radiometer.measure.analyses.daylight_factor import plane_statistics

    s = plane_statistics([1.0, 2.0, 3.0, 6.0], target_percent=2.5, median_external_illuminance_lux=15_000.0)
    assert s["average"] == 3.0 and s["minimum"] == 1.0 and s["uniformity"] == pytest.approx(1 / 3)
    assert s["share_above_target"] == 0.5
    # minimum level: D_T = 2 % reached by 3/4 (>= 50 %), D_TM = 0.667 % by 4/4 (>= 95 %): met
    assert s["en17037"]["levels"]["minimum"]["met"] and not s["en17037"]["levels"]["high"]["met"]
    with pytest.raises(RadiometerError):
        plane_statistics([1.0, float("nan")])


@pytest.mark.slow
def test_side_lit_room_against_radiance(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    room.build_blender(scene)
    world = bpy.data.worlds.new("user world")
    scene.world = world
    build.light(scene, "AREA", (2, 1.5, 2.6), rotation=(math.pi, 0, 0), energy=200.0)
    before = _state(scene)
    rs = api.daylight_factor(room.POINTS, quality="standard", seed=3)
    assert _state(scene) == before
    cam = api.daylight_factor(room.POINTS, quality="preview", seed=3, method="camera")  # the meter camera
    assert _state(scene) == before
    ref, ref_rel = room.radiance_daylight_factor(str(tmp_path), room.POINTS, cache=True)
    for r, df_ref, rel_ref in zip(cam, ref, ref_rel):
        assert not r.exact and r.method == "camera" and 0 < r.rel_std_error < 0.02
        se = math.hypot(r.rel_std_error * r.daylight_factor, rel_ref * df_ref)
        print(f"DF meter camera {r.daylight_factor:.4f} % +- {100 * r.rel_std_error:.2f} %, Radiance {df_ref:.4f} %")
        assert abs(r.daylight_factor - df_ref) <= max(3 * se, 0.01 * df_ref)
    for r, df_ref, rel_ref in zip(rs, ref, ref_rel):
        assert not r.exact and r.method in ("render", "hybrid")
        se = math.hypot(r.rel_std_error * r.daylight_factor, rel_ref * df_ref)
        print(f"DF Radiometer {r.daylight_factor:.4f} % +- {100 * r.rel_std_error:.2f} %, "
              f"Radiance {df_ref:.4f} % +- {100 * rel_ref:.2f} %")
        assert abs(r.daylight_factor - df_ref) <= max(3 * se, 0.01 * df_ref)


def test_cli_daylight_factor(clean_blender, build, tmp_path, capsys):
    import json

    from radiometer import cli

    scene = bpy.context.scene
    plane = build.plane(scene, size=2.0, location=(0, 0, 0.5), name="Work plane")
    plane.hide_render = True
    points = tmp_path / "points.csv"
    points.write_text("x,y,z,nx,ny,nz\n0,0,0,0,0,1\n1,2,3,0,0,-1\n", encoding="utf-8")
    js, table = tmp_path / "df.json", tmp_path / "df.csv"
    assert cli._blender_cli(["daylight-factor", "--points", str(points), "--ground-reflectance", "0.1",
                             "--json", str(js), "--csv", str(table)]) == 0
    rows = json.loads(js.read_text())["daylight_factor"]
    assert [r["daylight_factor"] for r in rows] == pytest.approx([100.0, 10.0], rel=1e-9)
    assert table.read_text().count("\n") == 3
    # issue 34: the table states errors in DF points (absolute) and the digits a proof supports
    out = capsys.readouterr().out
    assert "1 s.e. (DF points)" in out and "+- %" not in out
    rows_out = [t.split() for t in out.splitlines() if t.strip().startswith("0.000") or t.strip().startswith("1.000")]
    assert [r[3] for r in rows_out] == ["100.00", "10.000"] and all(r[4] == "exact" for r in rows_out)
    js2 = tmp_path / "grid.json"
    assert cli._blender_cli(["daylight-factor", "--plane", "Work plane", "--resolution", "2", "2", "--target", "2",
                             "--median-external-lux", "15000", "--json", str(js2)]) == 0
    grid = json.loads(js2.read_text())
    assert np.array(grid["daylight_factor"]).shape == (2, 2) and grid["stats"]["average"] == pytest.approx(100.0)
    out = capsys.readouterr().out
    assert "EN 17037 minimum" in out and ("DF points, 1 s.e." in out or "every point exact" in out)
    assert cli._blender_cli(["daylight-factor", "--plane", "Nope"]) == 2
    assert "no object named" in capsys.readouterr().err
    assert cli._blender_cli(["daylight-factor", "--points", str(points), "--target", "2"]) == 2


@pytest.mark.slow
def test_side_lit_room_with_6mm_glass_pane_against_radiance(clean_blender, tmp_path):
    # The pane is a solid of Glass BSDF (IOR 1.52); Radiance gets the same solid as a dielectric box.
    scene = bpy.context.scene
    room.build_blender(scene)
    room.add_pane_blender(scene)
    points = room.POINTS[:2]
    rs = api.daylight_factor(points, quality="standard", seed=5)
    rs += api.daylight_factor(points, quality="preview", seed=5, method="camera")  # through the meter camera
    ref, ref_rel = room.radiance_daylight_factor(str(tmp_path), points, samples=80_000, glass=True, cache=True)
    for r, df_ref, rel_ref in zip(rs, list(ref) * 2, list(ref_rel) * 2):
        se = math.hypot(r.rel_std_error * r.daylight_factor, rel_ref * df_ref)
        print(f"DF behind glass: Radiometer {r.daylight_factor:.4f} % +- {100 * r.rel_std_error:.2f} %, "
              f"Radiance {df_ref:.4f} % +- {100 * rel_ref:.2f} %")
        assert abs(r.daylight_factor - df_ref) <= max(3 * se, 0.01 * df_ref)

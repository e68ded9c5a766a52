"""The `blender -c radiometer` entry point runs the same implementation as `python -m radiometer`."""

import json
import math

import bpy
import pytest

from radiometer import cli


def test_blender_cli_measures_meters_of_the_open_file(clean_blender, build, tmp_path, capsys):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    out = tmp_path / "r.json"
    assert cli._blender_cli(["measure", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["meters"][0]["illuminance"] == pytest.approx(683 * 100 / (16 * math.pi), rel=1e-6)
    assert "lx" in capsys.readouterr().out


def test_blender_cli_bad_option_is_one_line(clean_blender, capsys):
    assert cli._blender_cli(["measure", "--nope"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("radiometer: error")


def test_measure_without_meters_is_a_clear_error(clean_blender, capsys):
    assert cli._blender_cli(["measure"]) == 2
    assert "no light meters" in capsys.readouterr().err

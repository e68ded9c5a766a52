"""The circadian check (api.circadian_check, issue 35): vertical meters at the occupants' eyes read in
melanopic EDI and rated against WELL v2 L03's indicative thresholds.

Reference (independent of the pipeline): a D65 point light (mel-DER = 1 by CIE S 026's definition) in a
black room, so mel-EDI = E_v = efficacy x Y(white) x P / (4 pi r^2) x cos(theta) at each eye, the eye
1.2 m (seated) or 1.7 m (standing) above the floor position."""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402

POWER_W, LIGHT = 25.0, (0.0, 2.0, 1.2)


def _scene(build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=12.0, location=(0.0, 0.0, 0.0), albedo=0.0, name="floor")
    light = build.light(scene, "POINT", LIGHT, energy=POWER_W, shadow_soft_size=0.0, use_soft_falloff=False)
    light.data["radiometer_spectrum"] = "D65"
    return scene


def _ev(scene, eye, facing):
    d = np.asarray(LIGHT) - np.asarray(eye)
    r = float(np.linalg.norm(d))
    return scene.radiometer.efficacy * POWER_W / (4.0 * math.pi * r * r) * float(d @ facing) / r


def test_eyes_read_mel_edi_and_rate_it(clean_blender, build):
    scene = _scene(build)
    forward = np.array([0.0, 1.0, 0.0])
    positions = [(0.0, 0.0, 0.0), (0.0, -2.0, 0.0)]
    out = api.circadian_check(positions, forward, scene=scene)
    assert out["eye_height_m"] == 1.2 and out["indicative"] and out["units"]["mel_edi_lx"] == "lx"
    near, far = out["eyes"]
    for row, pos in zip(out["eyes"], positions):
        eye = np.asarray(pos) + [0.0, 0.0, 1.2]
        assert row["eye"] == pytest.approx(tuple(eye), abs=1e-12)
        assert row["mel_edi_lx"] == pytest.approx(_ev(scene, eye, forward), rel=1e-6)   # D65: mel-DER 1
        assert row["mel_der"] == pytest.approx(1.0, rel=1e-6)
        assert row["lower_bound"] and any("reflected" in s for s in row["left_out"])
    assert near["mel_edi_lx"] > 250.0 and near["verdict"] == {"1": "met", "3": "met"}
    # 4 m away: about 75 lx, below both thresholds, but the reflections were left out: unknown, not "not met"
    assert far["mel_edi_lx"] < 136.0 and far["verdict"] == {"1": "unknown", "3": "unknown"}
    assert out["points"] == 0 and out["points_may_be_higher"]
    assert out["share"]["1"]["met"] == 0.5
    standing = api.circadian_check(positions[0], forward, scene=scene, posture="standing")
    eye = np.array([0.0, 0.0, 1.7])
    assert standing["eyes"][0]["mel_edi_lx"] == pytest.approx(_ev(scene, eye, forward), rel=1e-6)
    assert standing["points"] == 3


def test_bad_arguments_get_one_line(clean_blender, build):
    scene = _scene(build)
    with pytest.raises(RadiometerError, match="posture"):
        api.circadian_check((0, 0, 0), scene=scene, posture="lying")
    with pytest.raises(RadiometerError, match="view_directions"):
        api.circadian_check((0, 0, 0), (0, 0, 0), scene=scene)
    with pytest.raises(RadiometerError, match="one per position"):
        api.circadian_check([(0, 0, 0), (1, 0, 0)], [(0, 1, 0), (1, 0, 0), (0, 1, 0)], scene=scene)


def test_a_whole_reading_can_say_not_met(clean_blender, build):
    """With the reflected part read too (band renders: here the black floor reflects nothing), nothing is
    left out, so the far eye's 75 lx is a 'not met' with its 95 % interval below 136 lx."""
    scene = _scene(build)
    out = api.circadian_check((0.0, -2.0, 0.0), (0.0, 1.0, 0.0), scene=scene, reflected=True)
    (row,) = out["eyes"]
    assert row["left_out"] == [] and not row["lower_bound"], row
    assert row["high_95_lx"] < 136.0 and row["verdict"] == {"1": "not met", "3": "not met"}
    assert row["mel_edi_lx"] == pytest.approx(_ev(scene, (0.0, -2.0, 1.2), np.array([0.0, 1.0, 0.0])), rel=1e-3)
    assert out["points"] == 0 and not out["points_may_be_higher"]


def test_cli_prints_the_table_and_writes_json(clean_blender, build, tmp_path, capsys):
    import json

    from radiometer import cli

    _scene(build)
    blend = str(tmp_path / "room.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    out = tmp_path / "c.json"
    assert cli.main(["circadian", blend, "--position", "0", "0", "0", "0", "1", "0", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "WELL v2 L03" in text and "mel-EDI lx" in text and "met" in text
    data = json.loads(out.read_text())
    assert data["eyes"][0]["verdict"] == {"1": "met", "3": "met"} and data["units"]["mel_edi_lx"] == "lx"
    assert cli.main(["circadian", blend, "--position", "0", "0", "0", "0", "0", "0"]) == 2   # one line
    assert "view_directions" in capsys.readouterr().err


def test_a_partly_hidden_light_is_no_met(clean_blender, build):
    """A D65 area light 2 m ahead with a black board hiding most of it from the eye: its direct part is not a
    proven closed form (the unhidden value, bound 100 %), so the reading's low end is 0 and no threshold is
    'met' on the strength of light the board stops (found by review: it read 301 lx 'met' where 54 lx arrive)."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=12.0, location=(0.0, 0.0, 0.0), albedo=0.0, name="floor")
    light = build.light(scene, "AREA", (0.0, 2.0, 1.2), (math.radians(-90), 0, 0), energy=6.0, size=1.0)
    light.data["radiometer_spectrum"] = "D65"
    free = api.circadian_check((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), scene=scene)["eyes"][0]
    assert free["verdict"]["1"] == "met"
    build.plane(scene, size=0.45, location=(0.0, 1.0, 1.2), rotation=(math.radians(90), 0, 0), albedo=0.0, name="board")
    out = api.circadian_check((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), scene=scene)
    (row,) = out["eyes"]
    assert row["low_95_lx"] == 0.0 and row["direct_bound_lx"] > 0
    assert row["verdict"] == {"1": "unknown", "3": "unknown"} and out["points"] == 0
    # the meter is vertical: a view downwards reads what the level view reads, straight down is refused
    tilted = api.circadian_check((0.0, 0.0, 0.0), (0.0, 1.0, -1.0), scene=scene)["eyes"][0]
    assert tilted["view_direction"] == pytest.approx((0.0, 1.0, 0.0))
    with pytest.raises(RadiometerError, match="vertical"):
        api.circadian_check((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), scene=scene)

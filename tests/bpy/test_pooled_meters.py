"""Many meters on one plane read through the pooled field (radiometry/sampling/pooled_field.py, issue 17).

The interreflecting room of test_allocation_coverage (truth there from bench/room_reference.py, an
independent numpy path tracer), 200 meters at 0.75 m including its 5 reference points; the group
size that switches pooling on is lowered to 200 so the test stays small (the product's is 300)."""

import re

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402
from radiometer.radiometry.sampling import pooled_field  # noqa: E402
from tests.bpy.test_allocation_coverage import REFERENCE, _room  # noqa: E402


def test_pooled_readings_state_their_method_and_cover_the_truth(clean_blender, build, monkeypatch):
    monkeypatch.setattr(pooled_field, "POOL_MIN_METERS", 200)
    scene = _room()
    build.black_world(scene)
    build.light(scene, "AREA", (0.0, 0.0, 2.99), energy=400.0, shape="SQUARE", size=1.0)
    rng = np.random.default_rng(4)
    pts = np.r_[[p for p, _e, _s in REFERENCE], np.c_[rng.uniform(-1.8, 1.8, (195, 2)), np.full(195, 0.75)]]
    readings = api.measure_illuminance(pts, (0.0, 0.0, 1.0), target_rel_error=0.01, seed=3)
    pooled = np.array([r.method == "hybrid+pooled" for r in readings])
    assert pooled.sum() >= 100, [r.method for r in readings][:10]
    assert {r.method for r in readings} <= {"hybrid", "hybrid+pooled"}
    for r in readings:
        assert not r.exact and r.rel_std_error <= 0.01
    held = [r for r in readings if any(n.startswith("held out") for n in r.notes)]
    assert len(held) == pooled_field.MIN_HOLDOUT and all(r.method == "hybrid" for r in held)
    for r in np.array(readings, dtype=object)[pooled]:
        per_block = pooled_field.FIT_SPP * 16  # its fitted samples: blocks of 4 x 4 texels (fit_blocks)
        assert r.samples in {per_block * b for b in range(pooled_field.FIT_MIN_BLOCKS, pooled_field.FIT_MAX_BLOCKS + 1)}
        assert any(n.startswith("pooled (issue 17)") and "held-out" in n for n in r.notes), r.notes
        # The note states the samples the fitted meters took, this one's among them.
        [note] = [n for n in r.notes if n.startswith("pooled (issue 17)")]
        lo, hi = (int(x.replace(",", "")) for x in re.search(r"([\d,]+)-([\d,]+) samples each", note).groups())
        assert lo <= r.samples <= hi
        assert r.parts["analytic"]  # the panel's direct light stays a per-meter closed form
    # Against the independent tracer at the reference points (pooled or not): within 3.5 combined sigma.
    for (p, e, s), r in zip(REFERENCE, readings[:5]):
        z = (r.irradiance - e) / np.hypot(r.rel_std_error * r.irradiance, s)
        assert abs(z) < 3.5, (p, r.method, r.irradiance, e, r.rel_std_error)


def test_pooling_is_a_boolean():
    with pytest.raises(RadiometerError, match="pooling must be True or False"):
        api.measure_illuminance((0.0, 0.0, 1.0), pooling="yes")

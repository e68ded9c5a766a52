"""Issue 32: the samples that decide when to stop must not bias the reading. Pure numpy: a rare-hit
meter (each sample finds the light with probability p and then carries 1 / p, so the mean is exactly
1, the independent reference) read over 1000 seeds by ``allocation.allocate`` with ``staged=True``
(planning rounds, then one measurement sized from them alone). Its mean z = (reading - 1) / stated
s.e. must lie within +-0.3 and its 95 % intervals must cover at least 90 %."""

import numpy as np
import pytest

from radiometer.radiometry.sampling import allocation


def _rare_bake(p, rng):
    def bake(spp, blocks):
        idx = np.repeat(np.arange(len(blocks)), np.asarray(blocks) * allocation.BLOCK_TEXELS ** 2)
        x = rng.binomial(spp, p, size=len(idx)) / p / spp
        return idx, x, np.repeat(x[:, None], 3, axis=1)
    return bake


def _z(p, target, staged, seeds, meters=4):
    zs, spent = [], []
    for seed in range(seeds):
        r = allocation.allocate(_rare_bake(p, np.random.default_rng(seed)), meters, target=target, staged=staged)
        t = r.tally
        lit = t.std_error > 0  # a pilot with no hit is a dark meter (a one-sided bound), not a z
        zs.append((t.mean[lit] - 1.0) / t.std_error[lit])
        spent.append(r.samples)
    return np.concatenate(zs), np.concatenate(spent)


@pytest.mark.parametrize("p", [0.05, 0.01])
def test_staged_rule_is_unbiased_on_rare_hits(p):
    z, _spent = _z(p, 0.05, True, 250)  # 250 seeds x 4 meters = 1000 readings
    assert len(z) >= 900
    assert abs(np.mean(z)) <= 0.3, np.mean(z)
    assert np.mean(np.abs(z) < 1.96) >= 0.90


def test_measurement_is_sized_from_the_planning_alone():
    """The measurement's size is fixed before it is drawn: the same planning tally gives the same plan
    whatever the measurement later reads (no decision looks at the measurement's texels)."""
    rng = np.random.default_rng(0)
    tally = allocation.MeterTally(2)
    x = rng.binomial(8, 0.05, 64) / 0.05 / 8
    tally.add(np.repeat([0, 1], 32), 8, x, np.repeat(x[:, None], 3, axis=1))
    a = allocation.measurement_round(tally, np.array([0.05, 0.05]))
    b = allocation.measurement_round(tally, np.array([0.05, 0.05]))
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert np.all(a[1] >= allocation.MIN_BLOCKS)


def test_absolute_floor_stops_a_faint_meter():
    """``target_abs``: a meter whose error is below the absolute floor stops there, not at 1 % of little."""
    p = np.array([0.05, 0.05])
    rng = np.random.default_rng(1)

    def bake(spp, blocks):
        idx = np.repeat(np.arange(2), np.asarray(blocks) * allocation.BLOCK_TEXELS ** 2)
        x = rng.binomial(spp, p[idx]) / p[idx] / spp * np.where(idx == 0, 1.0, 1e-3)  # meter 1: 1000x fainter
        return idx, x, np.repeat(x[:, None], 3, axis=1)

    plain = allocation.allocate(bake, 2, target=0.02)
    floored = allocation.allocate(bake, 2, target=0.02, target_abs=np.array([0.0, 1e-3 * 0.05]))
    assert floored.reached and floored.tally.std_error[1] <= 1e-3 * 0.05
    assert floored.samples[1] < 0.5 * plain.samples[1]
    assert floored.samples[0] > 0.5 * plain.samples[0]  # the bright meter still meets 2 %


def test_every_preset_states_an_absolute_floor():
    """Issue 31: each preset names its absolute floor in lux; the relative target rules above floor / target."""
    from radiometer import quality

    for name in quality.PRESETS:
        p = quality.preset(name)
        assert p["target_abs_lux"] > 0
        assert p["target_abs_lux"] / p["target"] <= 50.0  # the relative target rules at any task illuminance >= 50 lx


def test_daylight_factor_floor_is_stated_in_df_points():
    """A DF floor in DF points is the meter's floor in lux at the 10 000 lx overcast sky (issue 31)."""
    pytest.importorskip("bpy")
    from radiometer import quality
    from radiometer.measure.analyses import daylight_factor

    assert daylight_factor.floor_lux("standard", None) == pytest.approx(
        quality.preset("standard")["target_abs_df"] / 100 * daylight_factor.SKY_HORIZONTAL_LUX)
    assert daylight_factor.floor_lux("standard", 0.01) == pytest.approx(1.0)  # 0.01 DF points = 1 lx
    assert daylight_factor.floor_lux("preview", 0) == 0.0  # 0: no floor

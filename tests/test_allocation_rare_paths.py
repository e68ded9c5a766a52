"""Rare paths (issue 18): a meter whose light arrives by a path the pilot usually misses (a small bright
region seen past an obstruction) must not stop at "0 +- 0"."""

import numpy as np

from radiometer.radiometry import allocation


def _rare_bake(value, p, rng):
    """Each sample finds the light with probability p[k] and then carries value[k] / p[k]: the mean
    is value[k], and a texel of spp samples is Binomial(spp, p) hits."""
    def bake(spp, blocks):
        idx = np.repeat(np.arange(len(value)), blocks * allocation.BLOCK_TEXELS ** 2)
        hits = rng.binomial(spp, p[idx])
        x = np.where(p[idx] > 0, hits * value[idx] / np.where(p[idx] > 0, p[idx], 1.0) / spp, 0.0)
        return idx, x, np.repeat(x[:, None], 3, axis=1)
    return bake


def test_dark_pilot_with_possible_light_keeps_sampling():
    pilot = allocation.pilot_blocks(2) * allocation.PILOT_SPP * allocation.BLOCK_TEXELS ** 2
    value, p = np.array([1.0, 0.0]), np.array([2e-4, 0.0])
    found, missed_before = 0, 0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        # Without the rule, a pilot that found nothing stops at 0 +- 0 (the 0 lx case).
        plain = allocation.allocate(_rare_bake(value, p, rng), 2, target=0.05)
        if plain.tally.mean[0] == 0.0:
            missed_before += 1
            assert plain.tally.rel_std_error()[0] == 0.0 and plain.samples[0] == pilot
        result = allocation.allocate(_rare_bake(value, p, rng), 2, target=0.05, may_be_lit=np.array([True, True]))
        assert result.samples[0] >= min(allocation.DARK_FLOOR, allocation.MAX_SAMPLES_PER_METER)
        found += result.tally.mean[0] > 0.0
        # The truly dark meter took the floor and is reported dark (the meter states an unknown error).
        assert result.samples[1] >= allocation.DARK_FLOOR
        assert allocation.dark_meters(result.tally, [True, True])[1]
    assert missed_before >= 15      # P(no hit in the 512-sample pilot of two meters) = 0.90 (seeded)
    assert found == 20              # P(no hit in 65536 samples) = 2e-6

"""A sample floor for heavy-tailed meters (issue 18): light from a small bright region of a rendered
world arrives by rare high-value paths. Reference: a synthetic bake with a known mean (each sample is
0.5, or 0.5 + 100 with probability 1e-4: mean 0.51), no bpy."""

import numpy as np

from radiometer.radiometry.sampling import allocation

RARE, SPIKE, BASE = 1e-4, 100.0, 0.5
MEAN = BASE + RARE * SPIKE


def heavy_tailed_bake(rng):
    def bake(spp, blocks):
        texels = int(np.sum(blocks)) * allocation.BLOCK_TEXELS ** 2
        idx = np.repeat(np.arange(len(blocks)), np.asarray(blocks) * allocation.BLOCK_TEXELS ** 2)
        value = BASE + SPIKE * rng.binomial(spp, RARE, size=texels) / spp
        return idx, value, np.repeat(value[:, None], 3, axis=1)
    return bake


def test_floor_round_reaches_the_floor_with_independent_texels():
    tally = allocation.MeterTally(3)
    tally.add(np.repeat([0, 1, 2], 32), 8, np.ones(96), np.ones((96, 3)))
    spp, blocks = allocation.floor_round(tally, np.array([allocation.DARK_FLOOR, 0, 100]))
    per_block = spp * allocation.BLOCK_TEXELS ** 2
    assert tally.n[0] + blocks[0] * per_block >= allocation.DARK_FLOOR
    assert blocks[0] >= allocation.MIN_BLOCKS and blocks[1] == 0 and blocks[2] == 0  # 256 >= 100 already
    assert allocation.PILOT_SPP <= spp <= allocation.MAX_SPP


def test_a_floor_makes_a_heavy_tailed_meter_honest():
    hits, seeds = {None: 0, allocation.DARK_FLOOR: 0}, 20
    for floor in hits:
        for seed in range(seeds):
            rng = np.random.default_rng(seed)
            result = allocation.allocate(heavy_tailed_bake(rng), 1, target=0.05,
                                         min_samples=None if floor is None else [floor])
            t = result.tally
            if floor is not None:
                assert t.n[0] >= floor
            hits[floor] += abs(t.mean[0] - MEAN) <= 1.96 * max(t.std_error[0], 1e-300)
    # Without the floor the 256-sample pilot usually sees no spike: 0.5 +- 0 (the 2 % missing is
    # "converged"); with it, the stated 95 % intervals cover about 95 % of the runs.
    assert hits[None] <= seeds // 2
    assert hits[allocation.DARK_FLOOR] >= 0.8 * seeds

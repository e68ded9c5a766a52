"""The pooled estimator of many meters' rendered light (radiometry/sampling/pooled_field.py, issue 17): pure numpy.

Synthetic fields with a known truth, sampled by a fake bake whose texels are the truth plus Gaussian
noise of a known spread (the batch-means statistics of ``allocation`` on top, as in a measurement)."""

import numpy as np

from radiometer.radiometry.sampling import allocation, pooled_field as pf


def smooth(p):
    x, y = p[:, 0], p[:, 1]
    return 10.0 + 2.0 * np.cos(0.8 * x) + 1.5 * np.sin(0.6 * y) + 0.125 * x * y


def bump(p):
    """A peak 0.15 m wide: no polynomial of degree <= 6 over 3.6 m follows it."""
    return smooth(p) + 4.0 * np.exp(-((p[:, 0] - 0.7) ** 2 + (p[:, 1] + 0.4) ** 2) / (2 * 0.15 ** 2))


def room_meters(n, rng, z=0.75):
    pts = np.c_[rng.uniform(-1.8, 1.8, (n, 2)), np.full(n, z)]
    return pts, np.tile([0.0, 0.0, 1.0], (n, 1))


def fake_bake(truth, rel_spread, rng):
    """Texels of ``spp`` samples: truth + noise of relative spread ``rel_spread`` per sample."""
    def bake(spp, blocks):
        idx = np.repeat(np.arange(len(blocks)), np.asarray(blocks) * allocation.BLOCK_TEXELS ** 2)
        values = truth[idx] * (1.0 + rel_spread / np.sqrt(spp) * rng.standard_normal(len(idx)))
        return idx, values, np.stack([values, 0.5 * values, 0.25 * values], axis=1)
    return bake


def measure(field, seed, n=1000, target=0.01, offset=10.0):
    rng = np.random.default_rng(seed)
    pts, nrm = room_meters(n, rng)
    truth = field(pts)
    res = pf.allocate_pooled(fake_bake(truth, 0.3, rng), n, points_m=pts, normals=nrm, target=target,
                             offset=np.full(n, offset), seed=seed)
    return pts, truth, res


def test_fit_recovers_a_polynomial_exactly():
    rng = np.random.default_rng(0)
    uv = rng.uniform(-1, 1, (200, 2))
    truth = 3.0 + uv[:, 0] - 2.0 * uv[:, 1] ** 2 + 0.5 * uv[:, 0] * uv[:, 1]
    fit = pf.fit_field(uv, truth[:, None], np.full((200, 1), 1e-6))
    mean, se = fit.predict(uv)
    assert fit.degree >= 2
    np.testing.assert_allclose(mean[:, 0], truth, atol=1e-9)
    assert np.all(se > 0)


def test_fit_error_covers_noise_when_the_model_is_right():
    """A field the basis holds exactly, values with known noise: (fit - truth) / fit s.e. has s.d. ~1."""
    z = []
    for seed in range(30):
        rng = np.random.default_rng(seed)
        uv = rng.uniform(-1, 1, (400, 2))
        truth = 5.0 + uv[:, 0] ** 2 - uv[:, 1]
        sd = 0.05 * (1.0 + 0.5 * uv[:, 0] ** 2)  # unequal noise: the sandwich covariance's case
        fit = pf.fit_field(uv, (truth + sd * rng.standard_normal(400))[:, None], (sd ** 2)[:, None], max_degree=2)
        probe = np.array([[0.3, -0.2], [-0.7, 0.6]])
        mean, se = fit.predict(probe)
        z += list((mean[:, 0] - (5.0 + probe[:, 0] ** 2 - probe[:, 1])) / se[:, 0])
    assert 0.75 < np.std(z) < 1.3


def test_misfit_upper_bound_covers_the_true_misfit():
    """Held-out residuals with extra variance tau^2 = 0.09 beyond their known ones: the 95 % upper
    bound is above 0.09 in about 95 % of draws, the estimate is near it on average."""
    rng = np.random.default_rng(1)
    above, estimates = 0, []
    for _ in range(400):
        v = rng.uniform(0.02, 0.1, 100)
        r = rng.standard_normal(100) * np.sqrt(v + 0.09)
        est, ub = pf.misfit_upper_bound(r, v)
        above += ub >= 0.09
        estimates.append(est)
    assert 0.91 <= above / 400 <= 0.99
    assert abs(np.mean(estimates) - 0.09) < 0.015
    est, ub = pf.misfit_upper_bound(np.zeros(50), np.ones(50))
    assert est == 0.0 and ub == 0.0


def test_held_out_check_refuses_an_outlier_and_too_few_meters():
    rng = np.random.default_rng(2)
    r, v = rng.standard_normal(100), np.ones(100)
    assert pf.check_held_out(r, v).passed
    r[7] = 12.0  # one held-out meter far off the field: a feature the field cannot follow
    bad = pf.check_held_out(r, v)
    assert not bad.passed and "cannot follow" in bad.reason
    few = pf.check_held_out(rng.standard_normal(10), np.ones(10))
    assert not few.passed and "fewer than" in few.reason


def test_plane_groups_split_by_normal_plane_and_key():
    rng = np.random.default_rng(3)
    a, na = room_meters(400, rng, z=0.75)
    b, nb = room_meters(400, rng, z=0.85)                    # another plane
    uv = rng.uniform(-1.0, 1.0, (400, 2))                    # a tilted plane: another normal
    c = np.array([0.0, 0.0, 1.5]) + uv[:, :1] * [1.0, 0.0, 0.0] + uv[:, 1:] * [0.0, 0.8, -0.6]
    nc = np.tile([0.0, 0.6, 0.8], (400, 1))
    pts, nrm = np.vstack([a, b, c]), np.vstack([na, nb, nc])
    keys = [frozenset()] * 1200
    groups = pf.plane_groups(pts, nrm, keys)
    assert sorted(len(g) for g in groups) == [400, 400, 400]
    scattered = c + nc * rng.uniform(-0.5, 0.5, (400, 1))    # off the plane along its normal: no group
    assert pf.plane_groups(scattered, nc) == []
    keys = [frozenset({("lamp",)}) if k % 2 else frozenset() for k in range(1200)]  # two renders per plane
    assert pf.plane_groups(pts, nrm, keys) == []            # 200 each: below POOL_MIN_METERS
    eligible = np.arange(1200) >= 100
    assert sorted(len(g) for g in pf.plane_groups(pts, nrm, None, eligible)) == [300, 400, 400]


def test_smooth_field_is_pooled_with_errors_that_cover_the_truth():
    covered, count, spent = 0, 0, []
    for seed in range(4):
        pts, truth, res = measure(smooth, seed)
        t = res.tally
        assert res.reached and res.pooled.mean() > 0.8       # the held-out 10 % read on their own
        total = t.mean + 10.0
        assert np.all(t.std_error / total <= 0.01 + 1e-12)
        z = (t.mean - truth) / t.std_error
        covered += int(np.sum(np.abs(z[res.pooled]) < 1.96))
        count += int(res.pooled.sum())
        spent.append(res.samples[res.pooled])
        g = res.groups[0]
        assert g.check.passed and g.check.held_out == 100 and 1 <= g.fit.degree <= pf.MAX_DEGREE
        np.testing.assert_allclose(t.mean_rgb[res.pooled, 1], 0.5 * t.mean[res.pooled], rtol=0.05)
    assert covered / count >= 0.95
    # A pooled reading's own samples are its fitted ones: 1-4 blocks at the pilot's spp (fit_blocks).
    per_block = pf.FIT_SPP * allocation.BLOCK_TEXELS ** 2
    spent = np.concatenate(spent)
    assert set(np.unique(spent)) <= {per_block * b for b in range(pf.FIT_MIN_BLOCKS, pf.FIT_MAX_BLOCKS + 1)}


def test_sharp_feature_falls_back_to_per_meter_sampling():
    """The bump is caught (the local check on the fitted meters, or the held-out check) and its meters
    are read on their own, to the target, covering the truth; none is pooled near it."""
    for seed in range(4):
        pts, truth, res = measure(bump, seed)
        t = res.tally
        near = np.hypot(pts[:, 0] - 0.7, pts[:, 1] + 0.4) < 0.35
        assert not np.any(res.pooled & near)
        assert res.groups[0].check.flagged > 0 or not res.groups[0].check.passed
        rel = t.std_error / (t.mean + 10.0)
        assert np.all(rel[near] <= 0.01 + 1e-12)  # read on their own samples (a pilot of their own, then more)
        z = (t.mean - truth) / t.std_error
        assert np.mean(np.abs(z) < 1.96) > 0.9


def test_few_meters_are_not_pooled():
    rng = np.random.default_rng(5)
    pts, nrm = room_meters(100, rng)
    truth = smooth(pts)
    res = pf.allocate_pooled(fake_bake(truth, 0.3, rng), 100, points_m=pts, normals=nrm, target=0.01)
    assert not res.pooled.any() and res.groups == [] and res.reached
    assert np.all(res.tally.std_error / res.tally.mean <= 0.01)


def test_rounds_are_logged_over_all_meters():
    pts, truth, res = measure(smooth, 9, n=400)
    assert all(len(r["texels"]) == 400 for r in res.tally.rounds)
    assert sum((r["spp"] * r["texels"]).sum() for r in res.tally.rounds) >= res.samples.sum()


def test_local_check_is_the_same_in_chunks(monkeypatch):
    """The neighbour search runs a chunk of rows at a time (a 10,000-point grid would need 800 MB at once)."""
    rng = np.random.default_rng(11)
    uv = rng.uniform(-1, 1, (700, 2))
    z2 = rng.chisquare(1, 700)
    z2[:30] += 40.0 * (uv[:30, 0] > 0)  # some large residuals: flagged discs
    whole = pf.local_misfit(uv, z2)
    monkeypatch.setattr(pf, "_CHUNK", 64)
    chunked = pf.local_misfit(uv, z2)
    np.testing.assert_array_equal(whole[0], chunked[0])
    np.testing.assert_allclose(whole[1], chunked[1])
    assert whole[0].any()


def test_meters_lit_by_rare_paths_are_not_pooled():
    """Meters whose pilot samples find their light in ~1 of 20 samples (Bernoulli, per-sample relative
    variance 19) are read on their own, however smooth their mean is (3 seeds: from 128 samples, the
    fitted meters' fewest, a meter's spread is a noisy judge)."""
    for seed in (12, 16, 17):
        rng = np.random.default_rng(seed)
        n = 1000
        pts, nrm = room_meters(n, rng)
        truth = smooth(pts)
        rare = pts[:, 0] > 1.2
        base = fake_bake(truth, 0.3, rng)

        def bake(spp, blocks):
            idx, values, rgb = base(spp, blocks)
            hit = rng.random((len(idx), spp)) < 0.05  # each of a texel's spp samples finds the light or not
            lucky = np.where(rare[idx], truth[idx] * hit.mean(axis=1) / 0.05, values)
            return idx, lucky, np.stack([lucky, 0.5 * lucky, 0.25 * lucky], axis=1)

        res = pf.allocate_pooled(bake, n, points_m=pts, normals=nrm, target=0.01, offset=np.full(n, 10.0))
        assert res.pooled.any() and not np.any(res.pooled & rare), seed
        assert np.all(res.tally.std_error / (res.tally.mean + 10.0) <= 0.01 + 1e-12)


def test_the_held_out_pilot_rides_in_the_fitted_meters_bake(monkeypatch):
    """One bake fewer when the fitted meters' spp is the pilot's: the held-out meters' pilot is baked with
    the fitted meters' samples, and what the bake returns for them is their own texels (the readings are
    the same as baking them apart)."""
    monkeypatch.setattr(pf, "FIT_SPP", allocation.PILOT_SPP)
    rng = np.random.default_rng(13)
    pts, nrm = room_meters(600, rng)
    truth = smooth(pts)
    calls = []
    base = fake_bake(truth, 0.3, rng)

    def bake(spp, blocks):
        calls.append((spp, np.flatnonzero(blocks)))
        return base(spp, blocks)

    res = pf.allocate_pooled(bake, 600, points_m=pts, normals=nrm, target=0.01, offset=np.full(600, 10.0))
    g = res.groups[0]
    first_spp, first_meters = calls[0]
    assert set(first_meters) == set(g.fitted) | set(g.held_out)       # one bake for both pilots
    assert all(set(m) <= set(g.held_out) | set(np.flatnonzero(~res.pooled)) for _s, m in calls[1:])
    held = res.tally.std_error[g.held_out] / (res.tally.mean[g.held_out] + 10.0)
    pilot = allocation.PILOT_SPP * allocation.BLOCK_TEXELS ** 2 * allocation.pilot_blocks(len(g.held_out))
    assert np.all(held <= 0.01 + 1e-12) and np.all(res.samples[g.held_out] >= pilot)


def test_a_group_lit_only_by_rare_paths_falls_back_whole():
    """Every meter's light found in ~1 of 20 samples: no field is fitted, every meter is read on its own
    (a 10 % target keeps the per-meter samples small)."""
    rng = np.random.default_rng(14)
    n = 300
    pts, nrm = room_meters(n, rng)
    truth = smooth(pts)

    def bake(spp, blocks):
        idx = np.repeat(np.arange(n), np.asarray(blocks) * allocation.BLOCK_TEXELS ** 2)
        values = truth[idx] * (rng.random((len(idx), spp)) < 0.05).mean(axis=1) / 0.05
        return idx, values, np.stack([values] * 3, axis=1)

    res = pf.allocate_pooled(bake, n, points_m=pts, normals=nrm, target=0.1)
    g = res.groups[0]
    assert not res.pooled.any() and not g.check.passed and "smooth light" in g.check.reason
    assert np.all(res.tally.std_error / res.tally.mean <= 0.1 + 1e-12)


def test_pooled_error_includes_the_sampler_tables_floor():
    """With Cycles' table (``table_patterns``), a pooled error is never below the table's floor for its
    pilot, sqrt(per-sample variance / (table size x patterns)) (allocation.MeterTally.table_floor)."""
    def run(patterns):
        rng = np.random.default_rng(15)
        pts, nrm = room_meters(1000, rng)
        return pf.allocate_pooled(fake_bake(smooth(pts), 0.3, rng), 1000, points_m=pts, normals=nrm, target=0.01,
                                  offset=np.full(1000, 10.0), table_patterns=patterns)

    plain, table = run(0), run(allocation.TABLE_PATTERNS)
    both = plain.pooled & table.pooled
    assert both.sum() > 800
    floor = 0.3 * table.tally.mean[both] / np.sqrt(allocation.table_size(8) * allocation.TABLE_PATTERNS)
    added = table.tally.std_error[both] ** 2 - plain.tally.std_error[both] ** 2
    assert np.all(added > 0)
    # Each meter's floor comes from its own pilot's spread estimate (31 degrees of freedom): right on average.
    assert 0.9 < np.median(added / floor ** 2) < 1.1


def test_fitted_samples_follow_the_fields_leverage():
    """``fit_blocks``: more samples where a polynomial leans on few meters (edges, corners), fewer in the
    middle; with fewer samples in all than 256 each, the field's largest standard error over the fitted
    meters is smaller than with 256 each (the same noise per sample; the fit's sandwich covariance)."""
    rng = np.random.default_rng(21)
    n = 900
    pts, nrm = room_meters(n, rng)
    group = pf.PooledGroup(fitted=np.arange(n), held_out=np.zeros(0, int))
    blocks = pf.fit_blocks(pts, nrm, [group], n)
    per_block = pf.FIT_SPP * allocation.BLOCK_TEXELS ** 2
    assert blocks.min() == pf.FIT_MIN_BLOCKS and blocks.max() > 2 * np.median(blocks)
    edge = np.max(np.abs(pts[:, :2]), axis=1) > 1.6
    assert np.mean(blocks[edge]) > 1.5 * np.mean(blocks[~edge])
    assert blocks.sum() * per_block < 256 * n
    uv, _frame = pf.plane_coordinates(pts, nrm[0])
    values = 10.0 + uv[:, 0] ** 4 - uv[:, 0] * uv[:, 1] ** 2  # degree 4: the fit is exact, only its noise left

    def worst_se(samples, weights=None):
        fit = pf.fit_field(uv, values, 0.3 ** 2 * 100.0 / samples, max_degree=4, weights=weights)
        return fit.predict(uv)[1][:, 0].max()

    design = blocks * per_block  # weighted by its samples, as allocate_pooled fits
    assert worst_se(design, design) < 0.75 * worst_se(np.full(n, 256.0))  # 0.66 here, at 0.76 of the samples


def narrow_bump(p):
    """A peak 0.1 m wide in the middle, where fitted meters take the fewest samples (128 each)."""
    return smooth(p) + 3.0 * np.exp(-((p[:, 0] + 0.3) ** 2 + (p[:, 1] - 0.2) ** 2) / (2 * 0.1 ** 2))


def test_a_sharp_feature_among_meters_of_few_samples_is_refused_or_read_on_its_own():
    """The fewest-sample design (128 samples at the middle's fitted meters) still sees a feature a
    few meters wide there: the local check (or the held-out check) catches it, and no meter near it
    is pooled; those meters are read on their own, to the target."""
    for seed in range(3):
        pts, truth, res = measure(narrow_bump, seed)
        near = np.hypot(pts[:, 0] + 0.3, pts[:, 1] - 0.2) < 0.25
        g = res.groups[0]
        assert g.check.flagged > 0 or not g.check.passed
        assert not np.any(res.pooled & near)
        assert np.all(res.tally.std_error[near] / (res.tally.mean[near] + 10.0) <= 0.01 + 1e-12)

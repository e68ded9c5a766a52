"""Student-t quantile of radiometer.radiometry.sampling.stats (numpy/math only) against scipy.stats.t.ppf.

Reference values: scipy.stats.t.ppf (Boost's inverse incomplete beta), the closed forms for 1, 2, 4
degrees of freedom (Shaw 2006, sec. 3) and the normal limit Phi^{-1}(0.975) = 1.959963984540054
(Abramowitz & Stegun table 26.5).
"""

import math

import numpy as np
import pytest

from radiometer.radiometry.sampling import stats

scipy_stats = pytest.importorskip("scipy.stats")

DFS = list(range(1, 201)) + [250, 500, 999, 1000, 1999, 2000, 2001, 10 ** 4, 10 ** 6, 10 ** 9]


@pytest.mark.parametrize("df", DFS)
def test_t_quantile_matches_scipy(df):
    ref = scipy_stats.t.ppf(0.975, df)
    assert stats.t_quantile_975(df) == pytest.approx(ref, rel=1e-12, abs=0)  # brief: 1e-9; measured 1.6e-14


def test_t_quantile_closed_forms_and_limits():
    assert stats.t_quantile_975(1) == pytest.approx(math.tan(0.475 * math.pi), rel=1e-15)  # Cauchy
    assert stats.t_quantile_975(2) == pytest.approx(0.95 / math.sqrt(2 * 0.975 * 0.025), rel=1e-15)
    a = 4 * 0.975 * 0.025
    q4 = 2 * math.sqrt(math.cos(math.acos(math.sqrt(a)) / 3) / math.sqrt(a) - 1)
    assert stats.t_quantile_975(4) == pytest.approx(q4, rel=1e-15)
    assert [round(stats.t_quantile_975(d), 3) for d in (3, 5, 10, 30)] == [3.182, 2.571, 2.228, 2.042]  # printed tables
    # normal limit: t = z + (z^3 + z) / (4 df) + O(df^-2) (A&S 26.7.5)
    assert stats.t_quantile_975(10 ** 15) == pytest.approx(1.959963984540054, rel=1e-14)
    q = [stats.t_quantile_975(d) for d in range(1, 300)]
    assert all(a > b for a, b in zip(q, q[1:]))  # heavier tails for fewer degrees of freedom


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, float("nan"), float("inf")])
def test_t_quantile_rejects_bad_degrees_of_freedom(bad):
    with pytest.raises((ValueError, OverflowError)):
        stats.t_quantile_975(bad)


def test_t_half_width_matches_scipy_on_batches_along_any_axis():
    rng = np.random.default_rng(5)
    values = rng.normal(10.0, 2.0, size=(7, 3, 4))  # K = 7 batches along axis 0, 12 meters
    _, se = stats.batch_mean(values)
    np.testing.assert_allclose(stats.t_half_width_95(values), scipy_stats.t.ppf(0.975, 6) * se, rtol=1e-13)
    _, se2 = stats.batch_mean(values, axis=2)
    np.testing.assert_allclose(stats.t_half_width_95(values, axis=2), scipy_stats.t.ppf(0.975, 3) * se2,
                               rtol=1e-13)

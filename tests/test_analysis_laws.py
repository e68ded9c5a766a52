"""Pure tier: law-check math (radiometry.metrics.laws, grid, convergence) against closed forms."""

import math

import numpy as np
import pytest

from radiometer.radiometry.sampling import convergence
from radiometer.radiometry.metrics import grid, laws


def square_on_axis(h, a=1.0):
    """Projected solid angle of a square of side a seen on its axis at distance h (sr).

    Closed form: four corner rectangles (Howell's catalogue of view factors, C-11), each
    (b / s) atan(b / s) with b = a/2, s = sqrt(b^2 + h^2).
    """
    b = a / 2
    s = np.sqrt(b * b + h * h)
    return 4 * (b / s) * np.arctan(b / s)


def test_power_law_fit_recovers_exponent_and_prefactor():
    d = np.geomspace(0.1, 10, 9)
    fit = laws.fit_power_law(d, 3.0 / d**2)
    assert fit.exponent == pytest.approx(-2.0, abs=1e-12)
    assert fit.prefactor == pytest.approx(3.0, rel=1e-12)
    assert fit.exponent_se < 1e-12 and fit.count == 9


def test_power_law_fit_standard_error_matches_scatter():
    rng = np.random.default_rng(1)
    d = np.geomspace(1, 100, 40)
    slopes, ses = [], []
    for _ in range(300):
        y = d**-2 * np.exp(rng.normal(0, 0.02, d.size))
        f = laws.fit_power_law(d, y)
        slopes.append(f.exponent)
        ses.append(f.exponent_se)
    # The stated s.e. agrees with the actual scatter of the slope (to sampling error ~5 %).
    assert np.std(slopes) == pytest.approx(np.mean(ses), rel=0.15)


def test_power_law_fit_propagates_point_errors():
    d = np.array([1.0, 2.0])
    f = laws.fit_power_law(d, d**-2, rel_std_error=[0.01, 0.01])
    # b = (ln y2 - ln y1) / ln 2: s.e. = sqrt(2) * 0.01 / ln 2 (error propagation)
    assert f.exponent_se == pytest.approx(math.sqrt(2) * 0.01 / math.log(2), rel=1e-12)


@pytest.mark.parametrize("bad", [([1, 2], [1, 0]), ([1], [1]), ([2, 2], [1, 3]), ([1, np.nan], [1, 2])])
def test_power_law_fit_rejects_bad_input(bad):
    with pytest.raises(ValueError):
        laws.fit_power_law(*bad)


def test_near_field_limit_of_a_square_is_5_74_sides():
    # Reference: the on-axis closed form above; deviation = Omega_perp / (A / h^2) - 1. The
    # 1 % crossing solved by root finding on the closed form is 5.7431 side lengths.
    from scipy.optimize import brentq

    exact = brentq(lambda h: square_on_axis(h) * h**2 - 1 + 0.01, 1, 20)
    assert exact == pytest.approx(5.7431, abs=1e-4)
    d = np.geomspace(0.3, 60, 25)
    dev = square_on_axis(d) * d**2 - 1
    limit = laws.near_field_limit(d, dev)
    assert limit == pytest.approx(exact, rel=2e-3)  # log-log interpolation between grid points
    rule = laws.five_times_rule(1.0, limit)
    assert not rule["rule_holds"] and rule["limit_in_sizes"] == pytest.approx(limit)


def test_near_field_limit_edge_cases():
    d = np.array([1.0, 2.0, 4.0])
    assert laws.near_field_limit(d, [0.0, 0.0, 0.0]) == 0.0
    assert laws.near_field_limit(d, [0.5, 0.2, 0.05]) == math.inf
    # Noise allowance: a 2 % deviation with 1 % s.e. is within 1 % + 3 s.e.
    assert laws.near_field_limit(d, [0.02, 0.0, 0.0], rel_std_error=[0.01, 0, 0]) == 0.0
    # A deviation falling exactly as 1/d^2 crosses 1 % exactly where it should: 0.04/d^2 = 0.01 -> d = 2.
    d = np.array([1.0, 3.0, 9.0])
    assert laws.near_field_limit(d, 0.04 / d**2) == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(ValueError):
        laws.near_field_limit([0.0, 1.0], [0, 0])


def test_cosine_analysis_point_and_clipped_source():
    a = np.array([0, 30, 60, 85, 89.0])
    res = laws.cosine_law_analysis(a, 5 * np.cos(np.radians(a)))
    assert res["passed"] and res["max_rel_deviation"] < 1e-12 and math.isnan(res["onset_deg"])
    # A uniform disk of angular radius alpha tilted past 90 - alpha: E falls off slower than cos
    # near the horizon; model it with a 10 % excess from 85 deg on.
    measured = 5 * np.cos(np.radians(a)) * np.where(a >= 85, 1.1, 1.0)
    res = laws.cosine_law_analysis(a, measured)
    assert not res["passed"] and res["onset_deg"] == 85.0
    assert res["max_rel_deviation"] == pytest.approx(0.1)
    assert laws.horizon_onset_deg(math.radians(10)) == pytest.approx(80.0)
    with pytest.raises(ValueError):
        laws.cosine_law_analysis([10, 20], [1, 1])  # no E(0)
    with pytest.raises(ValueError):
        laws.cosine_law_analysis([0, 20], [0, 1])  # dark at 0


def test_en12464_spacing_closed_form():
    # p = 0.2 * 5^log10(d): d = 1 -> 0.2; d = 10 -> 1.0; d = 100 -> 5.0; capped at 10 m.
    assert grid.en12464_spacing([1.0, 10.0, 100.0, 1e4]).tolist() == pytest.approx([0.2, 1.0, 5.0, 10.0])
    assert grid.grid_counts(3.6, 3.6) == (math.ceil(3.6 / (0.2 * 5 ** math.log10(3.6))),) * 2
    assert grid.grid_counts(1.0, 0.4, 0.2) == (5, 2)
    with pytest.raises(ValueError):
        grid.en12464_spacing(0.0)
    with pytest.raises(ValueError):
        grid.grid_counts(0.0, 1.0)


def test_cell_centres_and_stats():
    c = grid.cell_centres((-1, 1), (0, 1), 4, 2)
    assert c.shape == (2, 4, 2)
    assert c[0, :, 0].tolist() == pytest.approx([-0.75, -0.25, 0.25, 0.75])
    assert c[:, 0, 1].tolist() == pytest.approx([0.25, 0.75])
    s = grid.grid_stats([[100.0, 200.0], [300.0, 400.0]])
    assert s == {"avg": 250.0, "min": 100.0, "max": 400.0, "u0": 0.4, "count": 4}
    with pytest.raises(ValueError):
        grid.cell_centres((0, 1), (0, 1), 0, 3)
    with pytest.raises(ValueError):
        grid.grid_stats([1.0, np.nan])


def test_one_plane_statistics_for_illuminance_and_daylight_factor():
    """Issue 30: one function; the illuminance grid's EN 12464-1 names and the daylight factor's are views
    of it, and a dark plane has an undefined uniformity in both (NaN), never 0."""
    from radiometer.measure.analyses.daylight_factor import plane_statistics as df_statistics

    values = [[1.0, 2.0], [3.0, 6.0]]
    s = grid.plane_statistics(values, target=2.5)
    assert s == {"average": 3.0, "minimum": 1.0, "maximum": 6.0, "median": 2.5, "uniformity": pytest.approx(1 / 3),
                 "points": 4, "target": 2.5, "share_at_or_above_target": 0.5}
    e = grid.grid_stats(values)
    assert (e["avg"], e["min"], e["max"], e["u0"], e["count"]) == (3.0, 1.0, 6.0, s["uniformity"], 4)
    d = df_statistics(values, target_percent=2.5)
    assert d["average"] == 3.0 and d["uniformity"] == s["uniformity"] and d["share_above_target"] == 0.5
    dark = [0.0, 0.0, 0.0]
    assert np.isnan(grid.plane_statistics(dark)["uniformity"]) and np.isnan(grid.grid_stats(dark)["u0"])
    assert np.isnan(df_statistics(dark)["uniformity"])


def test_convergence_fit_inverts_for_targets():
    n = np.array([16, 64, 256, 1024.0])
    err = 0.08 * n**-0.5
    t = 0.05 + 1e-4 * n
    fit = convergence.fit_convergence(n, t, err)
    assert fit.slope == pytest.approx(-0.5, abs=1e-12)
    assert fit.samples_for(0.001) == pytest.approx(6400.0, rel=1e-9)  # (0.08/0.001)^2
    assert fit.seconds_for(0.001) == pytest.approx(0.05 + 0.64, rel=1e-9)
    assert convergence.rms_relative_error([[1.1, 0.9]], [1.0]) == pytest.approx([0.1])


def test_convergence_time_fit_inverts_for_targets():
    n = np.array([16, 64, 256, 1024.0])
    err = 0.08 * n**-0.5
    t = 1e-4 * n  # no fixed cost: error ~ t^-1/2 exactly
    fit = convergence.fit_convergence(n, t, err)
    assert fit.time_slope == pytest.approx(-0.5, abs=1e-12)
    assert fit.seconds_for_by_time(0.001) == pytest.approx(0.64, rel=1e-9)  # 1e-4 s x (0.08/0.001)^2
    flat = convergence.fit_convergence(n, t, np.full(4, 0.01))
    assert flat.seconds_for_by_time(0.001) == float("inf")


@pytest.mark.parametrize("seconds", [3.0, 0.5])
def test_convergence_time_fit_over_times_that_barely_vary_is_not_extrapolated(seconds, tmp_path):
    """Two levels whose renders cost the same to 0.1 % (a fixed cost dominating, a busy machine): the time
    fit's line is too steep for its value at 1 s to be a float. No overflow warning (a CI run failed on one),
    no extrapolation from it (nan: not measured), the samples fit and its time model unaffected, and the
    plot drawn."""
    from radiometer.plots.convergence import convergence_plot

    n, err = np.array([16.0, 256.0]), np.array([0.1, 0.025])
    t = seconds * np.array([1.0, 1.001])
    fit = convergence.fit_convergence(n, t, err)          # pytest.ini turns RuntimeWarnings into errors
    assert fit.time_prefactor in (0.0, float("inf"))
    assert math.isnan(fit.seconds_for_by_time(0.01))
    assert fit.samples_for(0.01) == pytest.approx(1600.0, rel=1e-9)   # 16 x (0.1 / 0.01)^2
    assert fit.seconds_for(0.01) == pytest.approx(t[0] + (t[1] - t[0]) / 240.0 * (1600.0 - 16.0), rel=1e-9)
    convergence_plot(tmp_path / "c.png", n, t, err, fit=fit.to_dict(), target=0.01)
    assert (tmp_path / "c.png").stat().st_size > 0

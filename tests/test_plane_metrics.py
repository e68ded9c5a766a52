"""The plane metrics' extension point (issue 30): one mapping, ``PLANE_METRICS`` (radiometry/metrics/grid.py,
re-exported as ``api.PLANE_METRICS``), that the one plane-statistics function computes and the illuminance
grid (EN 12464-1 names; compliance reads them), the daylight factor's grid and bench/ read. A new entry
appears in all of them. Blender-free."""

import numpy as np
import pytest

from radiometer import api
from radiometer.measure.analyses.daylight_factor import plane_statistics as df_statistics
from radiometer.radiometry.metrics import grid

PLANE = np.array([[1.0, 2.0], [3.0, 6.0]])  # by hand: mean 3, min 1, max 6, median 2.5, U0 1/3


def test_every_metric_reaches_every_view_with_its_hand_worked_value():
    assert api.PLANE_METRICS is grid.PLANE_METRICS
    by_hand = {"average": 3.0, "minimum": 1.0, "maximum": 6.0, "median": 2.5, "uniformity": 1.0 / 3.0, "points": 4}
    assert tuple(grid.PLANE_METRICS) == tuple(by_hand)
    s = grid.plane_statistics(PLANE)
    d = df_statistics(PLANE)
    e = grid.grid_stats(PLANE)
    for name, metric in grid.PLANE_METRICS.items():
        assert s[name] == pytest.approx(by_hand[name], rel=1e-15) and d[name] == s[name]
        if metric.grid_name is not None:
            assert e[metric.grid_name] == s[name]
    assert set(e) == {"avg", "min", "max", "u0", "count"}  # the grid's JSON/CSV/report names stay


def test_a_new_metric_appears_in_the_grid_the_daylight_factor_and_the_statistics(monkeypatch):
    p90 = grid.PlaneMetric(lambda v: float(np.percentile(v, 90)), "p90", "90th percentile")
    monkeypatch.setitem(grid.PLANE_METRICS, "percentile_90", p90)
    expected = float(np.percentile(PLANE, 90))  # 1, 2, 3, 6: 3 + 0.7 x 3 = 5.1
    assert expected == pytest.approx(5.1)
    assert grid.plane_statistics(PLANE)["percentile_90"] == expected
    assert grid.grid_stats(PLANE)["p90"] == expected
    assert df_statistics(PLANE, target_percent=2.0)["percentile_90"] == expected
    assert api.PLANE_METRICS["percentile_90"] is p90


def test_dark_plane_and_bad_values():
    dark = np.zeros(5)
    assert np.isnan(grid.plane_statistics(dark)["uniformity"]) and grid.plane_statistics(dark)["average"] == 0.0
    with pytest.raises(ValueError):
        grid.plane_statistics([])
    with pytest.raises(ValueError):
        grid.plane_statistics([1.0, np.inf])

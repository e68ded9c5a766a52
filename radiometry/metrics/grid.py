"""Illuminance grids on a work plane: EN 12464-1 spacing, point layout and statistics (pure numpy).

References
----------
- EN 12464-1:2011 "Light and lighting - Lighting of work places - Part 1: Indoor work places",
  annex / sec. 4.4 (grid): maximum grid cell size p = 0.2 x 5^log10(d) m, d the longer dimension of
  the area in m (p <= 10 m); number of points in a dimension = d / p rounded up; points at the
  centres of the cells; uniformity U0 = E_min / E_avg (EN 12464-1 sec. 3.2, also CIE S 008/E:2001).

Plane metrics
-------------
``PLANE_METRICS`` holds every statistic of a quantity over a plane's equal-area cells, by name: one
:class:`PlaneMetric` each (its function of the values, and its key in the grid's EN 12464-1 names).
:func:`plane_statistics` computes every entry; the illuminance grid (``grid_stats``: ``api.grid``,
``grid`` command, reports, compliance), the daylight factor's grid (``api.daylight_factor_grid``) and
``bench/`` read their numbers from it.

How to add a plane metric
-------------------------
1. A pure function of the values ``v`` (N,), finite and not empty, returning one number; cited where
   a standard defines it (as ``_uniformity``: EN 12464-1 sec. 3.2), with its behaviour on a dark
   plane stated (a ratio over an average of 0 is NaN, not 0);
2. one entry in ``PLANE_METRICS`` below: ``PlaneMetric(function, grid_name, description)``; a
   ``grid_name`` puts it in the illuminance grid's stats (JSON, CSV header, report tables that list
   them) under that key, None keeps it in ``plane_statistics`` only;
3. a test against a hand-worked plane in ``tests/test_plane_metrics.py`` (every entry is also checked
   to reach ``plane_statistics``, ``grid_stats`` and the daylight factor's statistics).
A metric that needs more than the values (a target, a threshold) is an argument of
``plane_statistics`` (as ``target``), not an entry.
"""

import dataclasses
import math

import numpy as np

from ..units import as_finite_array

__all__ = ["en12464_spacing", "grid_counts", "cell_centres", "PlaneMetric", "PLANE_METRICS", "plane_statistics",
           "grid_stats", "MAX_SPACING_M"]

#: EN 12464-1 caps the grid cell size at 10 m.
MAX_SPACING_M = 10.0


def en12464_spacing(longer_dimension_m):
    """Maximum grid cell size p = 0.2 * 5**log10(d) (m), capped at 10 m.

    ``d`` in m, > 0. Examples (closed form): d = 1 m -> 0.2 m; d = 10 m -> 1 m; d = 100 m -> 5 m.
    """
    d = as_finite_array(longer_dimension_m, "longer dimension")
    if np.any(d <= 0):
        raise ValueError("the area's longer dimension must be > 0 m")
    return np.minimum(0.2 * 5.0 ** np.log10(d), MAX_SPACING_M)


def grid_counts(size_x_m, size_y_m, spacing_m=None):
    """(nx, ny): points along x and y, each ceil(size / spacing) and at least 1.

    ``spacing_m`` defaults to :func:`en12464_spacing` of the longer side.
    """
    sx, sy = float(size_x_m), float(size_y_m)
    if not (math.isfinite(sx) and math.isfinite(sy)) or sx <= 0 or sy <= 0:
        raise ValueError(f"the area must have a positive size, got {sx} x {sy} m")
    p = float(en12464_spacing(max(sx, sy))) if spacing_m is None else float(spacing_m)
    if not math.isfinite(p) or p <= 0:
        raise ValueError(f"spacing must be > 0 m, got {spacing_m}")
    # 1e-9: a size that is an exact multiple of p must not gain a point from rounding noise.
    return max(1, math.ceil(sx / p - 1e-9)), max(1, math.ceil(sy / p - 1e-9))


def cell_centres(x_range, y_range, nx, ny):
    """Centres of an nx x ny grid of equal cells covering [x0, x1] x [y0, y1]: (ny, nx, 2)."""
    nx, ny = int(nx), int(ny)
    if nx < 1 or ny < 1:
        raise ValueError(f"resolution must be at least 1 x 1, got {nx} x {ny}")
    (x0, x1), (y0, y1) = x_range, y_range
    xs = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
    ys = y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny
    gx, gy = np.meshgrid(xs, ys)
    return np.stack([gx, gy], axis=-1)


@dataclasses.dataclass(frozen=True)
class PlaneMetric:
    """One statistic over a plane's cells: ``of(v)`` -> a number for the values ``v`` (N,) (finite, not
    empty); ``grid_name``: its key in the illuminance grid's stats (None: not there); ``description``."""

    of: object
    grid_name: str = None
    description: str = ""


def _uniformity(v):
    """U0 = minimum / average (EN 12464-1 sec. 3.2); NaN on a dark plane (average 0), where it is undefined."""
    avg = float(v.mean())
    return float(v.min()) / avg if avg > 0 else float("nan")


#: Every plane metric by name, in the order the statistics list them (module docstring: how to add one).
PLANE_METRICS = {
    "average": PlaneMetric(lambda v: float(v.mean()), "avg",
                           "mean over equal-area cells (E_avg; BS 8206-2's average daylight factor)"),
    "minimum": PlaneMetric(lambda v: float(v.min()), "min", "smallest cell value (E_min)"),
    "maximum": PlaneMetric(lambda v: float(v.max()), "max", "largest cell value (E_max)"),
    "median": PlaneMetric(lambda v: float(np.median(v)), None,
                          "median cell value (EN 17037's 50 % of the plane for the daylight factor)"),
    "uniformity": PlaneMetric(_uniformity, "u0", "minimum / average (U0, EN 12464-1); NaN on a dark plane"),
    "points": PlaneMetric(lambda v: int(v.size), "count", "number of cells"),
}


def plane_statistics(values, *, target=None):
    """The one set of statistics of a quantity over the equal-area cells of a plane (illuminance in lx,
    a daylight factor in %, ...): a dict with every ``PLANE_METRICS`` entry (``average``, ``minimum``,
    ``maximum``, ``median``, ``uniformity`` (minimum / average; NaN on a dark plane, where it is
    undefined), ``points``); with ``target``, also ``target`` and ``share_at_or_above_target``
    (fraction of cells >= target). Non-finite or no values raise ValueError."""
    v = as_finite_array(values, "plane values").ravel()
    if v.size == 0:
        raise ValueError("the plane has no points")
    out = {name: metric.of(v) for name, metric in PLANE_METRICS.items()}
    if target is not None:
        out["target"] = float(target)
        out["share_at_or_above_target"] = float(np.mean(v >= float(target)))
    return out


def grid_stats(values):
    """An illuminance grid's statistics under EN 12464-1's names (avg, min, max, u0 = min/avg, count: each
    ``PLANE_METRICS`` entry's ``grid_name``), from :func:`plane_statistics` (the names the grid's JSON,
    CSV and reports have always used)."""
    s = plane_statistics(values)
    return {m.grid_name: s[name] for name, m in PLANE_METRICS.items() if m.grid_name is not None}

"""Illuminance grids on a work plane: EN 12464-1 spacing, point layout and statistics (pure numpy).

References
----------
- EN 12464-1:2011 "Light and lighting - Lighting of work places - Part 1: Indoor work places",
  annex / sec. 4.4 (grid): maximum grid cell size p = 0.2 x 5^log10(d) m, d the longer dimension of
  the area in m (p <= 10 m); number of points in a dimension = d / p rounded up; points at the
  centres of the cells; uniformity U0 = E_min / E_avg (EN 12464-1 sec. 3.2, also CIE S 008/E:2001).
"""

import math

import numpy as np

from ..units import as_finite_array

__all__ = ["en12464_spacing", "grid_counts", "cell_centres", "plane_statistics", "grid_stats", "MAX_SPACING_M"]

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


def plane_statistics(values, *, target=None):
    """The one set of statistics of a quantity over the equal-area cells of a plane (illuminance in lx,
    a daylight factor in %, ...): a dict with ``average``, ``minimum``, ``maximum``, ``median``,
    ``uniformity`` (minimum / average; NaN on a dark plane, where it is undefined) and ``points``;
    with ``target``, also ``target`` and ``share_at_or_above_target`` (fraction of cells >= target).
    Non-finite or no values raise ValueError."""
    v = as_finite_array(values, "plane values").ravel()
    if v.size == 0:
        raise ValueError("the plane has no points")
    avg = float(v.mean())
    out = {"average": avg, "minimum": float(v.min()), "maximum": float(v.max()), "median": float(np.median(v)),
           "uniformity": float(v.min()) / avg if avg > 0 else float("nan"), "points": int(v.size)}
    if target is not None:
        out["target"] = float(target)
        out["share_at_or_above_target"] = float(np.mean(v >= float(target)))
    return out


def grid_stats(values):
    """An illuminance grid's statistics under EN 12464-1's names (avg, min, max, u0 = min/avg, count),
    from :func:`plane_statistics` (the names the grid's JSON, CSV and reports have always used)."""
    s = plane_statistics(values)
    return {"avg": s["average"], "min": s["minimum"], "max": s["maximum"], "u0": s["uniformity"], "count": s["points"]}

"""Daylight maps: a plan view of any per-point daylight quantity (daylight factor, sDA / ASE / UDI per
point, sunlight hours, melanopic EDI) in false colour, in the isolux map's style (``plots.isolux``).

Each point is drawn as what was measured there, nothing interpolated: on a grid, the cell around its
centre in one flat colour; scattered points as filled markers. The colour scale is labelled with the
quantity and its unit. The title states the error (:func:`error_share_text`). A point that could not
be measured (its value is not finite) is drawn hatched grey with a cross, never as a colour of the
scale, and the legend counts them. Points can also be flagged (an sDA point whose pass or fail is
uncertain at 2 standard errors) with a ring. The room comes as plain 2D geometry in metres: ``walls``,
segments (S, 2, 2) (a plan section at the work plane's height) and ``openings``, polylines (K, 2).
"""

import math

import numpy as np

from . import pyplot, save_png
from .isolux import format_lux

#: Points labelled with their values at most (more would overlap).
MAX_LABELLED = 60


def error_share_text(rel_std_error, target=None, *, what="1 s.e."):
    """The stated error as a title line from per-point relative standard errors (fractions; non-finite
    entries are the unmeasured points and are left out): 'DF 1 s.e. <= 1.2 % at every measured point',
    or with a ``target`` (fraction) the share of measured points that meet it and the worst."""
    e = np.asarray(rel_std_error, float).ravel()
    e = e[np.isfinite(e)]
    if not e.size:
        return "no point measured"
    worst = float(np.max(e))
    if target is None:
        return f"{what} <= {_pct(worst)} % at every measured point"
    share = float(np.mean(e <= float(target)))
    return (f"{what} <= {_pct(float(target))} % at {100 * share:.0f} % of the {e.size} measured points"
            + ("" if share == 1.0 else f" (worst {_pct(worst)} %)"))


def _pct(fraction):
    v = 100.0 * fraction
    return f"{v:.2g}" if v < 10 else f"{v:.0f}"


#: Characters per title line at the map's width (longer lines are wrapped, never run into the scale).
TITLE_WIDTH = 66


def wrapped_title(*lines, width=TITLE_WIDTH):
    """The non-empty ``lines`` joined, each wrapped at ``width`` characters on word boundaries."""
    import textwrap

    return "\n".join("\n".join(textwrap.wrap(t, width, break_on_hyphens=False)) for t in lines if t)


#: Points further from one height than this (m) are not one horizontal plane.
LEVEL_TOLERANCE_M = 1e-4


def plan_height(z_m):
    """The one height (m) of points on a horizontal plane (a map is a plan view), or a one-line
    RadiometerError naming their span."""
    from ..errors import RadiometerError

    z = np.asarray(z_m, float).ravel()
    if not z.size or not np.all(np.isfinite(z)):
        raise RadiometerError("a daylight map needs points with finite locations")
    h = float(np.median(z))
    if np.max(np.abs(z - h)) > LEVEL_TOLERANCE_M:
        raise RadiometerError(f"a daylight map is a plan view: the points lie between z = {z.min():.3f} m and "
                              f"{z.max():.3f} m, not on one horizontal plane")
    return h


def _points(n):
    return f"{n} point" + ("" if n == 1 else "s")


def lattice_shape(points, rel_tol=1e-6):
    """(ny, nx) when the (N, 3) or (N, 2) points, row by row, form a regular lattice
    p[j, i] = p[0, 0] + i du + j dv with nx, ny >= 2 (a grid laid out as every grid is), else None."""
    p = np.asarray(points, float).reshape(len(points), -1)
    n = len(p)
    scale = max(float(np.ptp(p, axis=0).max()) if n else 0.0, 1e-12)
    for nx in range(2, n // 2 + 1):
        if n % nx:
            continue
        g = p.reshape(n // nx, nx, -1)
        du, dv = g[0, 1] - g[0, 0], g[1, 0] - g[0, 0]
        j, i = np.mgrid[0:n // nx, 0:nx]
        model = g[0, 0] + i[..., None] * du + j[..., None] * dv
        area = np.linalg.norm(du) ** 2 * np.linalg.norm(dv) ** 2 - float(du @ dv) ** 2  # |du x dv|^2, any dimension
        if area > (1e-6 * scale) ** 4 and np.max(np.abs(model - g)) <= rel_tol * scale:
            return n // nx, nx
    return None


def cell_corners(centres):
    """Corners (ny + 1, nx + 1, 2) of the cells around grid centres (ny, nx, 2), ny, nx >= 2: midpoints
    between neighbours, extended by half a step at the edges (exact for a regular grid, any rotation)."""
    c = np.asarray(centres, float)
    # pad one row / column on each side by linear extrapolation
    c = np.concatenate([2 * c[:1] - c[1:2], c, 2 * c[-1:] - c[-2:-1]], axis=0)
    c = np.concatenate([2 * c[:, :1] - c[:, 1:2], c, 2 * c[:, -1:] - c[:, -2:-1]], axis=1)
    return 0.25 * (c[:-1, :-1] + c[1:, :-1] + c[:-1, 1:] + c[1:, 1:])


def daylight_map_figure(values, points, *, quantity, unit, title="", error_text="", walls=None, openings=(),
                        vmin=None, vmax=None, flagged=None, flagged_label="flagged",
                        axis_labels=("scene x (m)", "scene y (m)"), section_height=None, label_points=True):
    """The map (matplotlib Figure) of ``values`` at ``points``.

    ``values`` (ny, nx) with ``points`` (ny, nx, 2) (a grid: cells), or (N,) with (N, 2) (scattered:
    markers), in metres in plot coordinates. ``quantity`` and ``unit`` label the colour scale
    ('daylight factor', '%'). ``error_text`` is the title's second line. ``walls`` (S, 2, 2) and
    ``openings`` [(K, 2)] draw the room (``section_height``, m, names the cut in the legend). ``vmin``,
    ``vmax``: the scale's ends (default 0, or the lowest value when negative, to the highest).
    ``flagged``: bool like ``values``, points ringed and named ``flagged_label`` in the legend.
    """
    plt = pyplot()
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Polygon

    z = np.asarray(values, float)
    xy = np.asarray(points, float)[..., :2]
    if xy.shape[:-1] != z.shape or xy.shape[-1] != 2:
        raise ValueError(f"values {z.shape} and points {np.asarray(points).shape} do not match")
    flag = np.zeros(z.shape, bool) if flagged is None else np.asarray(flagged, bool).reshape(z.shape)
    good = np.isfinite(z)
    lo = float(np.min(z[good])) if good.any() else 0.0
    hi = float(np.max(z[good])) if good.any() else 1.0
    v0 = float(vmin) if vmin is not None else min(0.0, lo)
    v1 = float(vmax) if vmax is not None else hi
    if not v1 > v0:
        v1 = v0 + (abs(v0) if v0 else 1.0)
    norm = Normalize(vmin=v0, vmax=v1)
    cmap = plt.get_cmap("inferno")

    grid = z.ndim == 2 and z.shape[0] >= 2 and z.shape[1] >= 2
    pts = xy.reshape(-1, 2)
    extent_pts = [pts]
    corners = cell_corners(xy) if grid else None
    if grid:
        extent_pts.append(corners.reshape(-1, 2))
    wall_segs = np.zeros((0, 2, 2)) if walls is None else np.asarray(walls, float).reshape(-1, 2, 2)
    if len(wall_segs):
        extent_pts.append(wall_segs.reshape(-1, 2))
    openings = [np.asarray(o, float)[:, :2] for o in openings]
    extent_pts += openings
    allp = np.vstack(extent_pts)
    lo_xy, hi_xy = allp.min(axis=0), allp.max(axis=0)
    pad = 0.04 * max(float(np.max(hi_xy - lo_xy)), 1e-3)
    x0, x1, y0, y1 = lo_xy[0] - pad, hi_xy[0] + pad, lo_xy[1] - pad, hi_xy[1] + pad
    aspect = (y1 - y0) / max(x1 - x0, 1e-12)
    fig, ax = plt.subplots(figsize=(6.8, min(max(3.6, 5.0 * aspect + 2.0), 9.5)))

    zf = z.ravel()
    bad = ~np.isfinite(zf)
    if grid:
        mesh = ax.pcolormesh(corners[..., 0], corners[..., 1], np.ma.masked_invalid(z), cmap=cmap, norm=norm,
                             shading="flat", edgecolors="face", linewidth=0.0)
        ny, nx = z.shape
        for j, i in zip(*np.nonzero(~np.isfinite(z))):
            quad = [corners[j, i], corners[j, i + 1], corners[j + 1, i + 1], corners[j + 1, i]]
            ax.add_patch(Polygon(quad, closed=True, facecolor="0.82", edgecolor="0.35", hatch="xx", lw=0.0))
        size = 7
    else:
        mesh = ax.scatter(pts[~bad, 0], pts[~bad, 1], c=zf[~bad], cmap=cmap, norm=norm, s=90, marker="o",
                          edgecolors="0.3", linewidths=0.5, zorder=3)
        size = 9
    if bad.any():
        ax.plot(pts[bad, 0], pts[bad, 1], "x", color="black", ms=size, mew=1.4, zorder=4)
    if flag.any():
        fl = flag.ravel() & ~bad
        ax.plot(pts[fl, 0], pts[fl, 1], "o", mfc="none", mec="#2ad0ff", ms=size + 4, mew=1.3, zorder=5)
    bar = fig.colorbar(mesh, ax=ax, shrink=0.85, pad=0.02)
    bar.set_label(f"{quantity} ({unit})")
    if label_points and zf.size <= MAX_LABELLED:
        for (px, py), val in zip(pts, zf):
            if not math.isfinite(val):
                continue
            r, g, b, _ = cmap(norm(val))
            ink = "black" if 0.299 * r + 0.587 * g + 0.114 * b > 0.5 else "white"
            ax.annotate(format_lux(float(f"{val:.3g}")), (px, py), xytext=(0, -3 if grid else 7),
                        textcoords="offset points", ha="center", va="top" if grid else "bottom", fontsize=6,
                        color=ink if grid else "black", zorder=6)

    handles = []
    if len(wall_segs):
        ax.add_collection(LineCollection(wall_segs, colors="black", linewidths=2.0, zorder=7))
        cut = f" (section at z = {section_height:.2f} m)" if section_height is not None else ""
        handles.append(Line2D([], [], color="black", lw=2.0, label="walls" + cut))
    for o in openings:
        ax.plot(o[:, 0], o[:, 1], "-", color="#2ad0ff", lw=4.0, solid_capstyle="butt", zorder=8)
    if openings:
        handles.append(Line2D([], [], color="#2ad0ff", lw=4.0, label="openings"))
    if bad.any():
        label = f"not measured ({int(bad.sum())} of {_points(zf.size)})"
        handles.append(Patch(facecolor="0.82", edgecolor="0.35", hatch="xx", label=label) if grid else
                       Line2D([], [], ls="none", marker="x", color="black", ms=8, mew=1.4, label=label))
    if flag.any():
        handles.append(Line2D([], [], ls="none", marker="o", mfc="none", mec="#2ad0ff", ms=9, mew=1.3,
                              label=f"{flagged_label} ({_points(int((flag.ravel() & ~bad).sum()))})"))
    if handles:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=min(2, len(handles)),
                  fontsize=7, frameon=False)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel(axis_labels[0])
    ax.set_ylabel(axis_labels[1])
    ax.set_title(wrapped_title(title, error_text), fontsize=9)
    fig.tight_layout()
    return fig


def daylight_map_png(path, values, points, **kwargs):
    """Write :func:`daylight_map_figure` as a PNG at ``path`` (whole or not at all); returns ``path``."""
    fig = daylight_map_figure(values, points, **kwargs)
    return save_png(fig, path, dpi=110, bbox_inches="tight")

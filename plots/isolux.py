"""Isolux map of a work-plane grid: a smooth false-colour field in metres, isolines at the standard
illuminance steps labelled as plain numbers in lx, the plane's (or room's) outline, optionally the
measured points with their values.

Geometry: the grid's cell centres lie on a parallelogram P(s, t) = origin + s * axis_u + t * axis_v,
s, t in [0, 1], given in the plot's own metric coordinates (scene XY in metres for a horizontal plane,
the plane's own metric axes otherwise): so a scaled, rotated or non-square plane is drawn at its true
size and orientation. The field between the centres is a separable cubic (Keys, a = -0.5, exact for
quadratics) interpolation of the measured values, held constant beyond the outer centres (no
extrapolation past what was measured).
"""

import math

import numpy as np

from . import pyplot, save_png

#: Standard illuminance steps within one decade (EN 12464-1 / CIE scale of maintained illuminances:
#: ..., 20, 30, 50, 75, 100, 150, 200, 300, 500, 750, 1000, ...), as multiples of 10^k.
STANDARD_STEPS = (1.0, 1.5, 2.0, 3.0, 5.0, 7.5)


def standard_levels(lo, hi, max_levels=8):
    """Isolux levels (lx) strictly inside (lo, hi) from the standard series 1, 1.5, 2, 3, 5, 7.5 x 10^k.

    When more than ``max_levels`` fall inside, every other one is kept (then every third, ...). When
    fewer than two fall inside (a narrow range such as 210-270 lx), round 1-2-5 steps are used
    instead so the field still has isolines. Returns an increasing numpy array (may be empty when
    hi <= lo or the data are not positive and finite).
    """
    lo, hi = float(lo), float(hi)
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo or hi <= 0:
        return np.array([])
    low = max(lo, hi * 1e-6)
    k0, k1 = math.floor(math.log10(low)) - 1, math.ceil(math.log10(hi)) + 1
    series = np.array([m * 10.0 ** k for k in range(k0, k1 + 1) for m in STANDARD_STEPS])
    inside = series[(series > lo) & (series < hi)]
    if inside.size >= 2:
        step = max(1, math.ceil(inside.size / max_levels))
        return inside[::step]
    # narrow range: the roundest 1-2-5 step that gives at least two levels inside
    for k in range(k1, k0 - 3, -1):
        for m in (5.0, 2.0, 1.0):
            d = m * 10.0 ** k
            levels = np.arange(math.floor(lo / d) + 1, math.ceil(hi / d)) * d
            levels = levels[(levels > lo) & (levels < hi)]
            if 2 <= levels.size <= max_levels:
                return levels
    return inside


def format_lux(value):
    """A level as a plain number: '1500', '75', '7.5', '0.75' (no scientific notation)."""
    v = float(value)
    if v == 0:
        return "0"
    if abs(v) >= 100:
        return f"{v:.0f}"
    digits = max(0, 1 - math.floor(math.log10(abs(v))))
    text = f"{v:.{digits}f}"
    return text.rstrip("0").rstrip(".") if "." in text else text


def _cubic_weights(n_in, positions):
    """(len(positions), n_in) weights of Keys' cubic convolution (a = -0.5) at fractional indices,
    with the end samples repeated (no extrapolation beyond the first and last sample)."""
    x = np.clip(np.asarray(positions, float), 0.0, n_in - 1.0)
    w = np.zeros((x.size, n_in))
    if n_in == 1:
        w[:] = 1.0
        return w
    base = np.floor(x).astype(int)
    for offset in (-1, 0, 1, 2):
        idx = base + offset
        d = np.abs(x - idx)
        k = np.where(d <= 1, 1.5 * d**3 - 2.5 * d**2 + 1,
                     np.where(d < 2, -0.5 * d**3 + 2.5 * d**2 - 4 * d + 2, 0.0))
        np.add.at(w, (np.arange(x.size), np.clip(idx, 0, n_in - 1)), k)
    return w


def smooth_field(values, samples=(120, 120)):
    """Cubic interpolation of cell-centre values (ny, nx) onto a fine grid over the whole plane.

    Returns (s, t, field): s (mu,) and t (mv,) in [0, 1] across the plane, field (mv, mu). Cell
    centres sit at s = (i + 0.5) / nx; at those points the field equals the measured values.
    """
    z = np.asarray(values, float)
    ny, nx = z.shape
    mu, mv = samples
    s = np.linspace(0.0, 1.0, mu)
    t = np.linspace(0.0, 1.0, mv)
    wx = _cubic_weights(nx, s * nx - 0.5)
    wy = _cubic_weights(ny, t * ny - 0.5)
    return s, t, wy @ z @ wx.T


def plane_outline(origin, axis_u, axis_v):
    """The parallelogram's corners (5, 2), closed, in plot coordinates (m)."""
    o, u, v = (np.asarray(a, float) for a in (origin, axis_u, axis_v))
    return np.array([o, o + u, o + u + v, o + v, o])


def plot_extent(origin, axis_u, axis_v, outline=None, margin=0.03):
    """(x0, x1, y0, y1) in m: the plane's parallelogram (and the outline, when given) plus a margin
    of ``margin`` times the larger side."""
    pts = plane_outline(origin, axis_u, axis_v)
    if outline is not None and len(outline):
        pts = np.vstack([pts, np.asarray(outline, float)[:, :2]])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = margin * float(np.max(hi - lo))
    return (float(lo[0] - pad), float(hi[0] + pad), float(lo[1] - pad), float(hi[1] + pad))


def isolux_figure(lux, origin, axis_u, axis_v, *, title="", stats=None, unit="lx", axis_labels=("x (m)", "y (m)"),
                  outline=None, outline_label="room", mark_points=False, max_levels=8):
    """The isolux figure (matplotlib Figure) of ``lux`` (ny, nx) measured at the cell centres of the
    parallelogram origin + s axis_u + t axis_v (plot coordinates in m); see the module docstring.

    ``outline``: an (N, 2) polygon in the same coordinates (the room), drawn as a dark line.
    ``mark_points``: mark the measured points (with their values when there are at most 60).
    """
    plt = pyplot()
    from matplotlib.colors import LogNorm, Normalize

    z = np.asarray(lux, float)
    ny, nx = z.shape
    o, u, v = (np.asarray(a, float) for a in (origin, axis_u, axis_v))
    s, t, field = smooth_field(z, samples=(max(60, 12 * nx), max(60, 12 * ny)))
    lo, hi = float(np.min(z)), float(np.max(z))
    field = np.clip(field, lo, hi)  # the cubic's overshoot must not invent values outside the measured range
    gs, gt = np.meshgrid(s, t)
    X = o[0] + gs * u[0] + gt * v[0]
    Y = o[1] + gs * u[1] + gt * v[1]

    x0, x1, y0, y1 = plot_extent(o, u, v, outline)
    aspect = (y1 - y0) / max(x1 - x0, 1e-12)
    width = 6.8
    fig, ax = plt.subplots(figsize=(width, min(max(3.2, 5.2 * aspect + 1.4), 9.0)))
    # A sun patch next to shade spans decades: a log colour scale keeps both readable.
    use_log = lo > 0 and hi / lo > 20
    norm = LogNorm(vmin=lo, vmax=hi) if use_log else Normalize(vmin=lo, vmax=hi if hi > lo else lo + 1)
    mesh = ax.pcolormesh(X, Y, field, cmap="inferno", norm=norm, shading="gouraud", rasterized=True)
    bar = fig.colorbar(mesh, ax=ax, shrink=0.85, pad=0.02)
    bar.set_label(f"illuminance ({unit})" + (", log scale" if use_log else ""))
    bar.ax.yaxis.set_major_formatter(_plain_formatter())
    bar.ax.yaxis.set_minor_formatter(_plain_formatter(minor=True))
    levels = standard_levels(lo, hi, max_levels)
    if levels.size:
        lines = ax.contour(X, Y, field, levels=levels, colors="white", linewidths=0.8)
        ax.clabel(lines, fmt={lv: format_lux(lv) for lv in lines.levels}, fontsize=7, colors="white",
                  inline=True, inline_spacing=3)
        bar.add_lines(lines)
    ring = plane_outline(o, u, v)
    ax.plot(ring[:, 0], ring[:, 1], "-", color="0.35", lw=0.8, label="work plane")
    if outline is not None and len(outline):
        poly = np.asarray(outline, float)[:, :2]
        poly = np.vstack([poly, poly[:1]])
        ax.plot(poly[:, 0], poly[:, 1], "-", color="black", lw=1.6, label=outline_label)
    if mark_points:
        cs = (np.arange(nx) + 0.5) / nx
        ct = (np.arange(ny) + 0.5) / ny
        ps, pt = np.meshgrid(cs, ct)
        px = o[0] + ps * u[0] + pt * v[0]
        py = o[1] + ps * u[1] + pt * v[1]
        ax.plot(px.ravel(), py.ravel(), "+", color="0.8", ms=4, mew=0.7)
        if z.size <= 60:
            for xx, yy, val in zip(px.ravel(), py.ravel(), z.ravel()):
                ax.annotate(format_lux(float(f"{val:.3g}")), (xx, yy), xytext=(0, 3), textcoords="offset points",
                            ha="center", va="bottom", fontsize=6, color="0.85")
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel(axis_labels[0])
    ax.set_ylabel(axis_labels[1])
    heading = title
    if stats:
        heading += ("\n" if heading else "") + (
            f"E_avg {format_lux(_sig(stats['avg']))} {unit}, E_min {format_lux(_sig(stats['min']))} {unit}, "
            f"E_max {format_lux(_sig(stats['max']))} {unit}, U0 {stats['u0']:.2f}")
    ax.set_title(heading, fontsize=9)
    fig.tight_layout()
    return fig


def _sig(value, digits=3):
    """``value`` rounded to ``digits`` significant digits (for plain-number printing)."""
    return float(f"{float(value):.{digits}g}") if math.isfinite(float(value)) else float(value)


def _plain_formatter(minor=False):
    from matplotlib.ticker import FuncFormatter

    def fmt(value, _pos):
        if minor:
            return ""
        return format_lux(value) if value > 0 else "0"

    return FuncFormatter(fmt)


def isolux_png(path, lux, origin, axis_u, axis_v, **kwargs):
    """Write :func:`isolux_figure` as a PNG at ``path`` (whole or not at all); returns ``path``."""
    fig = isolux_figure(lux, origin, axis_u, axis_v, **kwargs)
    return save_png(fig, path, dpi=110)

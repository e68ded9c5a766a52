"""Goniometric (polar intensity) diagram of a luminaire: the C0-C180 and C90-C270 planes, with the
beam (50 %) and field (10 %) angles of each plane marked."""

import numpy as np

from . import pyplot, save_png


def spread_angle(vertical_deg, right, left, fraction):
    """Full angle (deg) of the cone within which one C-plane pair keeps ``fraction`` of its peak.

    On each side (``right`` = I(v, C), ``left`` = I(v, C + 180), v from the nadir) the edge is the first
    vertical angle, going out from the peak's side of the nadir, where I falls below ``fraction`` x the
    pair's maximum (linear interpolation between samples); the angle is the sum of both sides. Beam angle:
    fraction 0.5; field angle: 0.1 (IES LM-63 / CIE 121 conventions). None when the peak is not at the
    nadir side (I(0) < fraction x max: a batwing or an uplight, where a cone angle is meaningless).
    """
    v = np.asarray(vertical_deg, float)
    r, l = np.asarray(right, float), np.asarray(left, float)
    peak = max(float(np.max(r)), float(np.max(l)))
    if not peak > 0 or r[0] < fraction * peak:
        return None
    total = 0.0
    for side in (r, l):
        below = np.flatnonzero(side < fraction * peak)
        if below.size == 0:
            return None
        k = int(below[0])
        if k == 0:
            return None
        a, b = side[k - 1], side[k]
        t = (a - fraction * peak) / (a - b) if a != b else 0.0
        total += v[k - 1] + t * (v[k] - v[k - 1])
    return total


def goniometric_png(path, vertical_deg, planes, *, unit="cd", title=""):
    """Write a polar plot with the nadir at the bottom, as lighting catalogues draw it.

    ``planes``: dict label -> (right, left) intensity arrays over ``vertical_deg`` (0..180), e.g.
    {"C0-C180": (I(v, 0), I(v, 180)), "C90-C270": (I(v, 90), I(v, 270))}; ``right`` is drawn to
    the right of the vertical axis, ``left`` mirrored to the left. The beam (50 %) and field (10 %)
    angles of each plane (:func:`spread_angle`) are drawn as radial lines and named in the legend.
    Returns ``path``.
    """
    plt = pyplot()
    from matplotlib.ticker import MaxNLocator

    v = np.radians(np.asarray(vertical_deg, float))
    fig = plt.figure(figsize=(6.4, 6.8))
    ax = fig.add_subplot(111, projection="polar")
    ax.set_theta_zero_location("S")
    ax.set_theta_direction(1)
    styles = ("-", "--", ":", "-.")
    colours = ("C3", "C0", "C2", "C1")
    rmax = 0.0
    for k, (label, (right, left)) in enumerate(planes.items()):
        theta = np.concatenate([-v[::-1], v])
        r = np.concatenate([np.asarray(left, float)[::-1], np.asarray(right, float)])
        rmax = max(rmax, float(np.max(r)))
        beam = spread_angle(vertical_deg, right, left, 0.5)
        field = spread_angle(vertical_deg, right, left, 0.1)
        extra = []
        if beam is not None:
            extra.append(f"beam {beam:.0f}°")
        if field is not None:
            extra.append(f"field {field:.0f}°")
        text = label + (f" ({', '.join(extra)})" if extra else "")
        ax.plot(theta, r, styles[k % len(styles)], color=colours[k % 4], lw=1.6, label=text)
        for angle, ls in ((beam, (0, (4, 2))), (field, (0, (1, 2)))):
            if angle is not None:
                for sign in (-1, 1):
                    ax.plot([0, sign * np.radians(angle / 2)], [0, 1e9], color=colours[k % 4], lw=0.8, ls=ls,
                            alpha=0.8)
    ax.set_ylim(0, rmax * 1.05 if rmax > 0 else 1)
    ax.yaxis.set_major_locator(MaxNLocator(4))
    ax.yaxis.set_major_formatter(lambda value, _pos: f"{value:.0f}")
    ax.set_thetagrids(range(0, 360, 30), labels=[f"{a if a <= 180 else 360 - a}°" for a in range(0, 360, 30)])
    # radial labels in the upper half (empty for a downlight), away from the curves and the legend
    ax.set_rlabel_position(157.5)
    ax.tick_params(axis="y", labelsize=8)
    ax.set_title(title or "Luminous intensity", pad=18)
    ax.text(0.5, -0.08, f"intensity in {unit}; 0° = nadir; dashed: beam angle (50 %), dotted: field angle (10 %)",
            transform=ax.transAxes, ha="center", fontsize=8)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), fontsize=9, frameon=False, ncol=1)
    return save_png(fig, path, dpi=110, bbox_inches="tight")

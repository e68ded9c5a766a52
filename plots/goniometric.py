"""Goniometric (polar intensity) diagram of a luminaire: the C0-C180 and C90-C270 planes."""

import numpy as np

from . import pyplot


def goniometric_png(path, vertical_deg, planes, *, unit="cd", title=""):
    """Write a polar plot with the nadir at the bottom, as lighting catalogues draw it.

    ``planes``: dict label -> (right, left) intensity arrays over ``vertical_deg`` (0..180), e.g.
    {"C0-C180": (I(v, 0), I(v, 180)), "C90-C270": (I(v, 90), I(v, 270))}; ``right`` is drawn to
    the right of the vertical axis, ``left`` mirrored to the left. Returns ``path``.
    """
    plt = pyplot()
    v = np.radians(np.asarray(vertical_deg, float))
    fig = plt.figure(figsize=(6.0, 6.2))
    ax = fig.add_subplot(111, projection="polar")
    ax.set_theta_zero_location("S")
    ax.set_theta_direction(1)
    styles = ("-", "--", ":", "-.")
    for k, (label, (right, left)) in enumerate(planes.items()):
        theta = np.concatenate([-v[::-1], v])
        r = np.concatenate([np.asarray(left, float)[::-1], np.asarray(right, float)])
        ax.plot(theta, r, styles[k % len(styles)], color=("C3", "C0", "C2", "C1")[k % 4], lw=1.6, label=label)
    ax.set_thetagrids(range(0, 360, 30), labels=[f"{a if a <= 180 else 360 - a}°" for a in range(0, 360, 30)])
    ax.set_rlabel_position(100)
    ax.set_title(title or "Luminous intensity", pad=18)
    ax.text(0.5, -0.08, f"intensity in {unit}; 0° = nadir", transform=ax.transAxes, ha="center", fontsize=9)
    ax.legend(loc="lower left", bbox_to_anchor=(-0.1, -0.12), fontsize=9, frameon=False)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path

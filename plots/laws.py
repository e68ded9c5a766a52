"""Plots of the inverse-square and cosine-law checks."""

import textwrap

import numpy as np

from ..outputs import atomic_output
from . import pyplot


def _wrapped(title, width=78):
    """A long title broken into lines that fit the figure (never cut at its edges)."""
    return "\n".join(textwrap.fill(part, width) for part in str(title).split("\n"))


def _save(fig, path):
    try:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png", dpi=110)
    finally:
        fig.clf()


def inverse_square_plot(path, distances, measured, predicted, rel_std_error, *, title="",
                        near_field_limit=0.0, rule_distance=None, unit="W/m²", tolerance=0.01):
    """Two panels: E vs d on log-log axes (measured with 3 s.e. bars, I/d² line) and the deviation."""
    plt = pyplot()
    d = np.asarray(distances, float)
    m = np.asarray(measured, float)
    p = np.asarray(predicted, float)
    s = np.asarray(rel_std_error, float)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    ax1.loglog(d, p, "-", color="0.4", label="I/d² (far-field intensity)")
    ax1.errorbar(d, m, yerr=3 * s * np.abs(m), fmt="o", ms=3, color="C0", label="measured (±3 s.e.)")
    ax1.set_ylabel(f"irradiance E ({unit})")
    if not (near_field_limit is not None and np.isfinite(near_field_limit)):
        # "limit inf m" means the far field was not reached: say so in words, never "inf m"
        title = str(title).replace("near-field limit inf m", "far field not reached in the free space checked")
    ax1.set_title(_wrapped(title), fontsize=9)
    dev = 100 * (m - p) / p
    ax2.semilogx(d, dev, "o-", ms=3, color="C0")
    ax2.fill_between(d, -100 * (tolerance + 3 * s), 100 * (tolerance + 3 * s), color="C2", alpha=0.2,
                     label=f"±{100 * tolerance:g} % + 3 s.e.")
    ax2.axhline(0, color="0.4", lw=0.8)
    for x, style, colour, label in ((near_field_limit, "--", "C3", "near-field limit"),
                                    (rule_distance, ":", "C4", "5 x source size")):
        if x and np.isfinite(x):
            ax1.axvline(x, ls=style, color=colour, label=f"{label} {x:.3g} m")
            ax2.axvline(x, ls=style, color=colour)
    ax1.legend(loc="lower left", fontsize=8)
    ax2.set_xlabel("distance d (m)")
    ax2.set_ylabel("deviation from I/d² (%)")
    ax2.legend(loc="upper right", fontsize=8)
    from matplotlib.ticker import FuncFormatter, NullFormatter

    ax2.xaxis.set_major_formatter(FuncFormatter(lambda v, _p: f"{v:g}"))
    ax2.xaxis.set_minor_formatter(FuncFormatter(lambda v, _p: f"{v:g}" if f"{v:.0e}"[0] in "25" else ""))
    ax1.yaxis.set_minor_formatter(NullFormatter())
    ax1.yaxis.set_major_formatter(FuncFormatter(lambda v, _p: f"{v:g}"))
    fig.tight_layout()
    try:
        _save(fig, path)
    finally:
        plt.close(fig)
    return path


def cosine_plot(path, angles_deg, ratio, ratio_rel_se, *, title="", tolerance=0.01):
    """E(theta)/E(0) against cos(theta), and the relative deviation in %."""
    plt = pyplot()
    a = np.asarray(angles_deg, float)
    r = np.asarray(ratio, float)
    s = np.asarray(ratio_rel_se, float)
    fine = np.linspace(0, 90, 181)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    ax1.plot(fine, np.cos(np.radians(fine)), "-", color="0.4", label="cos θ")
    ax1.errorbar(a, r, yerr=3 * s * np.abs(r), fmt="o", ms=3, color="C0", label="E(θ)/E(0) (±3 s.e.)")
    ax1.set_ylabel("E(θ) / E(0)")
    ax1.legend(fontsize=8)
    ax1.set_title(_wrapped(title), fontsize=9)
    cos = np.cos(np.radians(a))
    ax2.plot(a, 100 * (r / cos - 1), "o-", ms=3, color="C0")
    ax2.axhspan(-100 * tolerance, 100 * tolerance, color="C2", alpha=0.2, label=f"±{100 * tolerance:g} %")
    # linear: the deviations of interest are a few per cent either side of 0
    dev_pct = 100 * (r / cos - 1)
    finite = dev_pct[np.isfinite(dev_pct)]
    span = max(2 * 100 * tolerance, float(np.max(np.abs(finite))) * 1.15 if finite.size else 0.0)
    ax2.set_ylim(-span, span)
    ax2.set_xlabel("tilt θ from facing the light (deg)")
    ax2.set_ylabel("E(θ)/(E(0) cos θ) - 1 (%)")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    try:
        _save(fig, path)
    finally:
        plt.close(fig)
    return path

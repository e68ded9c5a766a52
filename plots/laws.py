"""Plots of the inverse-square and cosine-law checks.

Each plot shows three things a lighting designer can tell apart: the law of a point source (I/d², cos θ),
the closed form of THIS light's shape alone (an extended source's near field, a soft-falloff sphere,
a source sinking below the meter's horizon: the departure physics expects), and the measurement.
Illuminance is drawn in lux when the scene gives a luminous efficacy (``unit="lx"``: the caller passes
lux), else in W/m².
"""

import textwrap

import numpy as np

from . import pyplot, save_png


def _wrapped(title, width=84):
    """A long title broken into lines that fit the figure (never cut at its edges)."""
    return "\n".join(textwrap.fill(part, width) for part in str(title).split("\n"))


def _plain_number(v):
    """0.05, 0.5, 2, 500, 10 000, 1 000 000: never 1e+06 or 10^0."""
    return f"{v:,.0f}".replace(",", "\u2009") if abs(v) >= 1000 else f"{v:g}"


def _plain_ticks(ax, axis="x"):
    """Plain numbers on a log axis; the 2, 3, 5 between decades labelled only on a short axis (they
    would crowd one spanning several decades)."""
    from matplotlib.ticker import FuncFormatter

    ax_ = ax.xaxis if axis == "x" else ax.yaxis
    lo, hi = ax.get_xlim() if axis == "x" else ax.get_ylim()
    decades = np.log10(max(hi, 1e-300) / max(lo, 1e-300))
    ax_.set_major_formatter(FuncFormatter(lambda v, _p: _plain_number(v)))
    ax_.set_minor_formatter(FuncFormatter(lambda v, _p: _plain_number(v) if decades < 2.2 and f"{v:.0e}"[0] in "235"
                                          else ""))


def _clipped_ylim(ax, values, floor, keep=None):
    """Limit the deviation axis to what matters: the points where ``keep`` is True and at least
    ±``floor`` % around 0. Returns (low, high); the caller marks points outside at the edge."""
    v = np.asarray(values, float)
    keep = np.isfinite(v) if keep is None else (np.asarray(keep, bool) & np.isfinite(v))
    low, high = -floor, floor
    if keep.any():
        low, high = min(low, float(v[keep].min())), max(high, float(v[keep].max()))
    pad = 0.12 * (high - low)
    ax.set_ylim(low - pad, high + pad)
    return low - pad, high + pad


def inverse_square_plot(path, distances, measured, predicted, rel_std_error, *, title="",
                        near_field_limit=0.0, rule_distance=None, unit="W/m²", tolerance=0.01, model=None,
                        model_label="closed form of this light's shape"):
    """Two panels: E vs d on log-log axes and the deviation from I/d² in %.

    ``distances`` in m; ``measured`` (with 3 s.e. bars from ``rel_std_error``), ``predicted`` (I/d²)
    and ``model`` (the light's own closed form, no room) in ``unit``. ``near_field_limit`` (m): the
    distance beyond which the light follows I/d² within ``tolerance``; 0 when it does everywhere,
    inf when not within the distances checked (then the whole sweep is shaded as near field).
    """
    plt = pyplot()
    d = np.asarray(distances, float)
    m = np.asarray(measured, float)
    p = np.asarray(predicted, float)
    s = np.asarray(rel_std_error, float)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.6), sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    ax1.loglog(d, p, "-", color="0.45", label="I/d² (a point source of the same intensity)")
    if model is not None:
        ax1.loglog(d, np.asarray(model, float), "--", color="C1", label=model_label)
    ax1.errorbar(d, m, yerr=3 * s * np.abs(m), fmt="o", ms=3.5, color="C0", label="measured, direct light (±3 s.e.)")
    ax1.set_ylabel(f"illuminance E ({unit})" if unit == "lx" else f"irradiance E ({unit})")
    ax1.set_title(_wrapped(title), fontsize=9)
    dev = 100 * (m - p) / p
    ax2.semilogx(d, dev, "o", ms=3.5, color="C0", label="measured")
    if model is not None:
        ax2.semilogx(d, 100 * (np.asarray(model, float) - p) / p, "--", color="C1", label="expected for this shape")
    ax2.fill_between(d, -100 * (tolerance + 3 * s), 100 * (tolerance + 3 * s), color="C2", alpha=0.2,
                     label=f"±{100 * tolerance:g} % (+3 s.e.)")
    ax2.axhline(0, color="0.45", lw=0.8)
    limit = near_field_limit if near_field_limit is not None else 0.0
    if limit > 0:
        right = min(limit, d[-1] * 1.05) if np.isfinite(limit) else d[-1] * 1.05
        label = (f"near field (to {limit:.2g} m): not a point here" if np.isfinite(limit)
                 else "near field at every distance checked")
        for ax in (ax1, ax2):
            ax.axvspan(d[0] / 1.05, right, color="C1", alpha=0.07, lw=0, label=label if ax is ax1 else None)
    if rule_distance and np.isfinite(rule_distance) and rule_distance <= d[-1] * 1.05:
        for ax in (ax1, ax2):
            ax.axvline(rule_distance, ls=":", color="C4", label=f"5 × source size ({rule_distance:.2g} m)"
                       if ax is ax1 else None)
    ax1.set_xlim(d[0] / 1.05, d[-1] * 1.05)
    ax1.legend(loc="lower left", fontsize=7.5)
    ax2.set_xlabel("distance d from the light (m)")
    ax2.set_ylabel("departure from I/d² (%)")
    _clipped_ylim(ax2, dev, 3 * 100 * tolerance)
    _plain_ticks(ax1, "y")
    ax2.legend(loc="lower right", fontsize=7.5)
    _plain_ticks(ax2, "x")
    fig.tight_layout()
    return save_png(fig, path, dpi=110)


def cosine_plot(path, angles_deg, ratio, ratio_rel_se, *, title="", tolerance=0.01, model_ratio=None,
                horizon_deg=None, model_label="closed form of this light's shape"):
    """E(θ)/E(0) against cos θ, and the relative deviation in %.

    ``model_ratio``: the light's own closed form E(θ)/E(0) (no room); ``horizon_deg``: the tilt from
    which part of the source is below the meter's horizon (an extended source: E falls slower than
    cos θ beyond it). Deviations beyond the horizon tilt can be hundreds of % of a tiny E: the axis
    shows the tilts before it, and points off the axis are written at its edge with their value.
    """
    plt = pyplot()
    a = np.asarray(angles_deg, float)
    r = np.asarray(ratio, float)
    s = np.asarray(ratio_rel_se, float)
    fine = np.linspace(0, 90, 181)
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.2), sharex=True)
    ax1.plot(fine, np.cos(np.radians(fine)), "-", color="0.45", label="cos θ (a point source)")
    if model_ratio is not None:
        ax1.plot(a, np.asarray(model_ratio, float), "--", color="C1", label=model_label)
    ax1.errorbar(a, r, yerr=3 * s * np.abs(r), fmt="o", ms=3.5, color="C0", label="measured, direct light (±3 s.e.)")
    ax1.set_ylabel("E(θ) / E(0)")
    ax1.set_title(_wrapped(title), fontsize=9)
    cos = np.cos(np.radians(a))
    dev = 100 * (r / cos - 1)
    ax2.plot(a, dev, "o", ms=3.5, color="C0", label="measured")
    if model_ratio is not None:
        ax2.plot(a, 100 * (np.asarray(model_ratio, float) / cos - 1), "--", color="C1", label="expected for this shape")
    ax2.axhspan(-100 * tolerance, 100 * tolerance, color="C2", alpha=0.2, label=f"±{100 * tolerance:g} %")
    ax2.axhline(0, color="0.45", lw=0.8)
    below = np.zeros(a.size, bool)
    if horizon_deg is not None and np.isfinite(horizon_deg) and horizon_deg < 90:
        below = a > horizon_deg + 1e-9
        for ax in (ax1, ax2):
            ax.axvspan(horizon_deg, 90, color="C1", alpha=0.08, lw=0,
                       label=f"from {horizon_deg:.3g}°: part of the source below the horizon" if ax is ax1 else None)
    low, high = _clipped_ylim(ax2, dev, 3 * 100 * tolerance, keep=~below if (~below).sum() >= 2 else None)
    off = [(x, y) for x, y in zip(a, dev) if np.isfinite(y) and not low <= y <= high]
    for x, y in off:
        edge = high - 0.04 * (high - low) if y > 0 else low + 0.04 * (high - low)
        ax2.plot([x], [edge], marker="^" if y > 0 else "v", color="C0", ms=5, clip_on=False)
    if off:
        # one block of text (labels beside neighbouring points would overlap)
        listed = off if len(off) <= 5 else off[:2] + [None] + off[-2:]
        text = "off the axis:\n" + "\n".join("…" if p is None else f"{p[0]:g}°: {p[1]:+.3g} %" for p in listed)
        ax2.text(0.985, 0.5, text, transform=ax2.transAxes, ha="right", va="center", fontsize=7, color="C0",
                 bbox={"facecolor": "white", "edgecolor": "0.8", "alpha": 0.9})
    ax1.set_xlim(0, 90)
    ax1.legend(loc="lower left", fontsize=7.5)
    ax2.set_xlabel("tilt θ of the meter from facing the light (°)")
    ax2.set_ylabel("E(θ) / (E(0) cos θ) − 1 (%)")
    ax2.legend(loc="upper left", fontsize=7.5)
    fig.tight_layout()
    return save_png(fig, path, dpi=110)

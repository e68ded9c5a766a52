"""Error against samples and seconds on log-log axes, with the fitted power laws."""

import math
import textwrap

import numpy as np

from . import pyplot, save_png


def fit_in_words(slope, what="samples"):
    """A power law error ∝ x^slope said as a user reads it: "error halves with every 4x more samples".

    Returns "" for a slope >= 0 or not finite (no convergence to describe).
    """
    slope = float(slope)
    if not math.isfinite(slope) or slope >= 0:
        return ""
    factor = 2.0 ** (-1.0 / slope)
    return f"error halves with every {factor:.2g}x more {what}"


def _percent_axis(ax):
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _p: f"{v:g} %"))
    lo, hi = ax.get_ylim()
    # under a decade on the axis: label the 2x and 5x minor ticks too, plainly
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _p: f"{v:g} %" if hi / lo < 30 and
                                               f"{v:.0e}"[0] in "25" else ""))
    ax.xaxis.set_major_locator(LogLocator(base=10, numticks=6))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _p: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())


def _power(prefactor, x, slope):
    """prefactor * x**slope in logs: a steep fit over a narrow x has factors beyond a float, not its values."""
    return np.exp(np.log(prefactor) + slope * np.log(x))


def convergence_plot(path, samples, seconds, errors, std_errors=None, *, fit=None, target=None, title=""):
    """Two panels: relative error vs samples per estimate and vs seconds, log-log, with fits."""
    plt = pyplot()
    n = np.asarray(samples, float)
    t = np.asarray(seconds, float)
    e = np.asarray(errors, float)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.0, 5.0))
    for ax, x, label in ((ax1, n, "samples per estimate"), (ax2, t, "seconds per measurement")):
        ax.loglog(x, 100 * e, "o", color="C0", label="RMS error vs reference")
        if std_errors is not None:
            ax.loglog(x, 100 * np.asarray(std_errors, float), "s", mfc="none", color="C1",
                      label="stated standard error")
        ax.set_xlabel(label)
        ax.set_ylabel("relative error (%)")
        ax.grid(True, which="both", alpha=0.3)
    if fit is not None:
        xn = np.geomspace(n.min(), n.max(), 50)
        if not 0.0 < fit["prefactor"] < np.inf:  # the sample counts barely varied: no line to draw
            ax1.plot([], [], " ", label="no fit: the sample counts barely varied")
        else:
            ax1.loglog(xn, 100 * _power(fit["prefactor"], xn, fit["slope"]), "-", color="0.4",
                       label=f"fit: {fit_in_words(fit['slope'], 'samples') or 'no convergence'} "
                             f"(error ∝ N^{fit['slope']:.2f}±{fit['slope_se']:.2f})")
        xt = np.geomspace(t.min(), t.max(), 50)
        if not 0.0 < fit["time_prefactor"] < np.inf:  # the times barely varied: no line to draw
            ax2.plot([], [], " ", label="no fit of error against time: the times barely varied")
        else:
            ax2.loglog(xt, 100 * _power(fit["time_prefactor"], xt, fit["time_slope"]), "-", color="0.4",
                       label=f"fit: {fit_in_words(fit['time_slope'], 'time') or 'no convergence'} "
                             f"(error ∝ t^{fit['time_slope']:.2f}±{fit['time_slope_se']:.2f})")
    if target:
        for ax in (ax1, ax2):
            ax.axhline(100 * target, ls="--", color="C3", label=f"target {100 * target:g} %")
    for ax, x in ((ax1, n), (ax2, t)):
        _percent_axis(ax)  # after every loglog call: setting the scale resets the formatters
        if not np.any((10.0 ** np.arange(-12, 13) >= x.min()) & (10.0 ** np.arange(-12, 13) <= x.max())):
            ax.set_xticks([x.min(), x.max()], [f"{x.min():.4g}", f"{x.max():.4g}"])  # no decade inside: the ends
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), frameon=False)
    fig.suptitle("\n".join(textwrap.fill(p, 110) for p in str(title).split("\n")), fontsize=9)
    fig.tight_layout()
    return save_png(fig, path, dpi=110)

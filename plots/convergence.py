"""Error against samples and seconds on log-log axes, with the fitted power laws."""

import numpy as np

from . import pyplot


def convergence_plot(path, samples, seconds, errors, std_errors=None, *, fit=None, target=None, title=""):
    """Two panels: relative error vs samples per estimate and vs seconds, log-log, with fits."""
    plt = pyplot()
    n = np.asarray(samples, float)
    t = np.asarray(seconds, float)
    e = np.asarray(errors, float)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9.0, 4.0))
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
        ax1.loglog(xn, 100 * fit["prefactor"] * xn ** fit["slope"], "-", color="0.4",
                   label=f"fit: N^{fit['slope']:.2f}±{fit['slope_se']:.2f}")
        xt = np.geomspace(t.min(), t.max(), 50)
        ax2.loglog(xt, 100 * fit["time_prefactor"] * xt ** fit["time_slope"], "-", color="0.4",
                   label=f"fit: t^{fit['time_slope']:.2f}±{fit['time_slope_se']:.2f}")
    if target:
        for ax in (ax1, ax2):
            ax.axhline(100 * target, ls="--", color="C3", label=f"target {100 * target:g} %")
    ax1.legend(fontsize=7)
    ax2.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

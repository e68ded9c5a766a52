"""PNG plots of a BRDF: the library's summary (``radiometer.brdf.plots.plot_summary``) and the model's
in-plane lobes against the Cycles closure that renders it. Plain numbers in, a file out, no bpy: the
callers (``commands/brdf.py``, ``operators/brdf.py``) check the parameters and gather the lobes."""

import os

from ..errors import RadiometerError
from . import pyplot, require_matplotlib, save_png


def write_summary(model, path, **params):
    """Write the library's summary plot of ``model`` with ``params`` (already checked, e.g. by
    ``shading.realise.check_params``) to ``path`` (PNG); returns ``path``.

    Raises
    ------
    RadiometerError
        The folder is missing, the library has no plotting module, or matplotlib is not installed
        (Blender's own Python).
    """
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise RadiometerError(f"cannot write {path}: directory {directory} does not exist")
    try:
        from ..brdf import plots
    except ImportError:
        raise RadiometerError("radiometer.brdf.plots is not available in this version") from None
    require_matplotlib()
    plots.plot_summary(model, path, **params)
    return path


def write_lobes(path, model, closure, summary, lobes, weights):
    """PNG of in-plane lobes, the model (solid) against the Cycles closure (dashed), one colour per
    incidence angle, luminance-weighted.

    Parameters
    ----------
    path : str
        The PNG to write (whole or not at all).
    model, closure, summary : str
        The model's name, the closure's name and the fidelity summary, for the title.
    lobes : list of (theta_i_deg, theta_o_deg (n,), f_model (n, 3), f_closure (n, 3))
        BRDF values in 1/sr; theta_o in the plane of incidence, + on the mirror side.
    weights : (3,) array
        Luminance weights of the RGB channels (the working colour space's CIE Y row).

    Returns
    -------
    str
        ``path``.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=100)
    for (ti, to, fm, fc), colour in zip(lobes, ("C0", "C1", "C2")):
        ax.plot(to, fm @ weights, color=colour, label=f"model, θi = {ti:.0f}°")
        ax.plot(to, fc @ weights, color=colour, ls="--", label=f"Cycles, θi = {ti:.0f}°")
    ax.set_yscale("symlog", linthresh=1e-3)
    ax.set_xlabel("θo in the plane of incidence (deg, + = mirror side)")
    ax.set_ylabel("f (1/sr, luminance)")
    ax.set_title(f"{model}: model vs {closure} ({summary})", fontsize=8)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_png(fig, path)

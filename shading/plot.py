"""Write the library's BRDF summary plot (no bpy)."""

import os

from ..errors import RadiometerError


def write_plot(model, path, **params):
    """Write ``radiometer.brdf.plots.plot_summary(model, path, **params)`` to ``path`` (PNG).

    Raises
    ------
    RadiometerError
        Unknown model/parameter, the library has no plotting module, or the directory is missing.
    """
    from .realise import check_params

    p = check_params(model, params)
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise RadiometerError(f"cannot write {path}: directory {directory} does not exist")
    try:
        from ..brdf import plots
    except ImportError:
        raise RadiometerError("radiometer.brdf.plots is not available in this version") from None
    plots.plot_summary(model, path, **p)
    return path

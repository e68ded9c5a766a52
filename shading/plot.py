"""Write the library's BRDF summary plot (no bpy)."""

import os

from ..errors import RadiometerError


def write_plot(model, path, **params):
    """Write ``radiometer.brdf.plots.plot_summary(model, path, **params)`` to ``path`` (PNG).

    Raises
    ------
    RadiometerError
        Unknown model/parameter, the library has no plotting module, the directory is missing, or
        matplotlib is not installed (Blender's own Python).
    """
    from ..plots import require_matplotlib
    from .realise import check_params

    p = check_params(model, params)
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise RadiometerError(f"cannot write {path}: directory {directory} does not exist")
    try:
        from ..brdf import plots
    except ImportError:
        raise RadiometerError("radiometer.brdf.plots is not available in this version") from None
    require_matplotlib()
    plots.plot_summary(model, path, **p)
    return path

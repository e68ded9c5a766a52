"""PNG plots of analysis results. Each function takes plain numbers and a path and returns the path.

matplotlib is imported inside the functions (Agg backend), so importing this package is cheap and
works where matplotlib is missing until a plot is asked for. Blender's bundled Python has no
matplotlib: :func:`require_matplotlib` then raises a RadiometerError that says how to get it, and the
analyses (``measure.analyses.analysis``) skip their images with a note while every number, CSV and JSON stays.
"""

import importlib
import sys

from ..errors import RadiometerError


def missing_message():
    """The one-line user message for a Python without matplotlib (names this interpreter)."""
    return ("plots need matplotlib, which this Blender's Python lacks: install it with "
            f"'\"{sys.executable}\" -m pip install matplotlib' (or run Radiometer from a Python that has "
            "it); numbers, CSV and JSON files work without it")


def matplotlib_available():
    """True when ``import matplotlib`` works here."""
    try:
        importlib.import_module("matplotlib")
    except ImportError:
        return False
    return True


def require_matplotlib():
    """The matplotlib module, or RadiometerError(:func:`missing_message`) where it is not installed."""
    try:
        return importlib.import_module("matplotlib")
    except ImportError:
        raise RadiometerError(missing_message()) from None


def pyplot():
    """matplotlib.pyplot with the non-interactive Agg backend (no window, safe in Blender)."""
    matplotlib = require_matplotlib()

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_png(fig, path, **savefig_kwargs):
    """Write ``fig`` as a PNG at ``path``, whole or not at all and never through a planted link
    (``outputs.atomic_output``), then close it; returns ``path``. ``savefig_kwargs``: dpi, bbox_inches."""
    from ..outputs import atomic_output

    try:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png", **savefig_kwargs)
    finally:
        pyplot().close(fig)
    return path

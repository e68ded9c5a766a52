"""False-colour picture of a luminance (cd/m²) or illuminance (lx) image with a legend, as Radiance's
``falsecolor`` draws it: a log (decades) or linear scale, the colour bar labelled in the unit."""

import math

import numpy as np

from . import pyplot, save_png


def scale_range(values, scale="log", value_range=None):
    """(lo, hi) of the colour scale: ``value_range`` when given; else for 'log' the whole decades from the
    0.5th to the 99.5th percentile (2 to 4 decades), for 'linear' 0 .. the 99.5th percentile.
    Non-positive or non-finite pixels do not count."""
    v = np.asarray(values, float)
    if value_range is not None:
        lo, hi = (float(x) for x in value_range)
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo and (scale == "linear" or lo > 0)):
            raise ValueError(f"range must be two finite numbers lo < hi (lo > 0 on a log scale), got {value_range}")
        return lo, hi
    good = v[np.isfinite(v) & (v > 0)]
    if good.size == 0:
        return (1e-3, 1.0) if scale == "log" else (0.0, 1.0)
    top = float(np.percentile(good, 99.5))
    if scale == "log":
        # whole decades from the 0.5th to the 99.5th percentile: at least 2, at most 4 (a lamp's
        # few pixels must not squeeze the room into one colour, nor a dark corner spread it thin)
        hi = 10.0 ** math.ceil(math.log10(top))
        lo = 10.0 ** math.floor(math.log10(float(np.percentile(good, 0.5))))
        lo = min(max(lo, hi * 1e-4), hi * 1e-2)
        return lo, hi
    return 0.0, top


def false_colour_png(path, values, *, unit="cd/m²", quantity="luminance", scale="log", value_range=None, title=""):
    """Write ``values`` (H, W) as a false-colour PNG with a colour bar in ``unit``; returns ``path``."""
    plt = pyplot()
    from matplotlib.colors import LogNorm, Normalize
    from matplotlib.ticker import FuncFormatter

    if scale not in ("log", "linear"):
        raise ValueError(f"scale must be 'log' or 'linear', got {scale!r}")
    v = np.asarray(values, float)
    lo, hi = scale_range(v, scale, value_range)
    shown = np.where(np.isfinite(v), v, np.nan)
    if scale == "log":
        shown = np.clip(shown, lo, hi)
        norm = LogNorm(vmin=lo, vmax=hi)
    else:
        shown = np.clip(shown, lo, hi)
        norm = Normalize(vmin=lo, vmax=hi)
    h, w = v.shape
    width = 7.0
    fig, ax = plt.subplots(figsize=(width, max(2.5, width * h / w * 0.85 + 0.6)))
    image = ax.imshow(shown, cmap="turbo", norm=norm, interpolation="nearest")
    ax.set_axis_off()
    bar = fig.colorbar(image, ax=ax, shrink=0.9, pad=0.02)
    bar.set_label(f"{quantity} ({unit})" + (", log scale" if scale == "log" else ""))
    bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda x, _p: f"{x:g}"))
    if title:
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return save_png(fig, path, dpi=100)

"""Diagnostic plots of the BRDF models (matplotlib imported lazily, Agg canvas, no pyplot state).

Every function writes an image file and returns its path as str. Colour channels are combined to
luminance with the Rec. 709 / sRGB weights Y = 0.2126 R + 0.7152 G + 0.0722 B where one curve is
drawn (IEC 61966-2-1).
"""

import math
import os

import numpy as np

from . import registry
from .frame import normalize, to_local

__all__ = ["plot_lobes", "plot_albedo", "plot_sphere", "plot_summary", "sphere_image"]

_Y = np.array([0.2126, 0.7152, 0.0722])


def _figure(width, height):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=100)
    FigureCanvasAgg(fig)
    return fig


def _save(fig, path):
    from ..outputs import atomic_output

    path = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with atomic_output(path) as tmp:  # whole or not at all, never through a planted link (issue 21)
        fig.savefig(tmp, format=os.path.splitext(path)[1].lstrip(".").lower() or "png")
    return path


def _title(model, params):
    extra = ", ".join(f"{k}={np.round(v, 3).tolist() if not isinstance(v, str) else v}" for k, v in params.items())
    return f"{model}" + (f" ({extra})" if extra else "")


def _draw_lobes(ax, model, theta_i_deg, params):
    theta_o = np.radians(np.linspace(-89.5, 89.5, 721))  # signed: < 0 is the mirror side
    wo = np.stack([np.sin(theta_o), np.zeros_like(theta_o), np.cos(theta_o)], -1)
    for t in theta_i_deg:
        ti = math.radians(t)
        wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
        y = registry.evaluate(model, wi, wo, **params) @ _Y * np.cos(theta_o)
        line, = ax.plot(theta_o, y, label=f"θi = {t:g}°")
        ax.plot([ti, ti], [0, max(float(np.max(y)), 1e-12) * 1.05], ls=":", color=line.get_color())
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(-90)
    ax.set_thetamax(90)
    ax.set_xlabel("θo [deg] in the plane of incidence (light on the + side)")
    ax.set_title("f·cos θo [1/sr] (luminance)", fontsize=9)
    from matplotlib.ticker import MaxNLocator

    # few radial ticks, labelled along the left edge; the legend sits outside on the right so neither
    # runs into the other
    ax.yaxis.set_major_locator(MaxNLocator(3))
    ax.tick_params(axis="y", labelsize=7)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0), frameon=False)


def plot_lobes(model, path, theta_i_deg=(0, 30, 60, 80), **params):
    """Polar plot of f·cos θo [1/sr] (luminance) in the plane of incidence for several θi.

    The radius at angle θo is the reflected radiance per unit normal irradiance times cos θo,
    i.e. the distribution of reflected flux per solid angle (as in Rusinkiewicz' BRDF viewer plots
    of the CS348B lecture); dotted radial lines mark the incident directions.
    """
    fig = _figure(6, 4)
    ax = fig.add_subplot(111, projection="polar")
    _draw_lobes(ax, model, theta_i_deg, params)
    fig.suptitle(_title(model, params), fontsize=9)
    return _save(fig, path)


def _draw_albedo(ax, model, params):
    t = np.linspace(0.0, 89.0, 46)
    a = registry.albedo(model, np.radians(t), **params)
    for c, name in enumerate(("R", "G", "B")):
        ax.plot(t, a[:, c], color=name.lower() if name != "G" else "g", lw=1, alpha=0.6, label=name)
    ax.plot(t, a @ _Y, color="k", lw=2, label="luminance")
    ax.set_xlabel("incidence angle θi [deg]")
    ax.set_ylabel("directional albedo ∫ f cos θo dωo [1]")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, max(1.05, float(np.nanmax(a)) * 1.05))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def plot_albedo(model, path, **params):
    """Directional albedo vs incidence angle θi [deg], RGB channels and luminance."""
    fig = _figure(5, 4)
    _draw_albedo(fig.add_subplot(111), model, params)
    fig.suptitle(_title(model, params), fontsize=9)
    return _save(fig, path)


def sphere_image(model, light_dir=(1.0, 1.0, 1.0), resolution=160, irradiance=1.0, **params):
    """Radiance image [W/(m² sr)] of an orthographic sphere view, shape (res, res, 3), NaN outside.

    View direction +z (towards the camera); a distant light from ``light_dir`` gives normal
    irradiance ``irradiance`` [W/m²]; pixel = f(wi, wo) cos θi E. The tangent at every point is the
    projection of the image "up" axis (0, 1, 0): alpha_x / n_u act along screen-vertical, alpha_y / n_v along
    screen-horizontal.
    """
    r = (np.arange(resolution) + 0.5) / resolution * 2 - 1
    x, y = np.meshgrid(r, -r)
    inside = x * x + y * y < 1
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, 1))
    n = np.stack([x, y, z], -1)
    light = normalize(np.asarray(light_dir, dtype=float))
    up = np.array([0.0, 1.0, 0.0])
    t = up - (n @ up)[..., None] * n
    t = np.where((np.linalg.norm(t, axis=-1) > 1e-9)[..., None], t, np.array([1.0, 0.0, 0.0]))
    wi = to_local(light, n, t)
    wo = to_local(np.array([0.0, 0.0, 1.0]), n, t)
    f = registry.evaluate(model, wi, wo, **params)
    img = f * np.maximum(0.0, wi[..., 2:3]) * irradiance
    return np.where(inside[..., None], img, np.nan)


def _tonemap(img):
    # Exposure: a white Lambertian facing the light (L = E/π) maps to display value 1; then clip and
    # sRGB-encode (IEC 61966-2-1). Highlights brighter than that clip to white.
    v = np.clip(np.nan_to_num(img, nan=0.0) * math.pi, 0, 1)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)


def _draw_sphere(ax, model, light_dir, params):
    img = sphere_image(model, light_dir, **params)
    ax.imshow(_tonemap(img), extent=(-1, 1, -1, 1))
    ax.set_xlabel("x (view: orthographic along -z)")
    ax.set_ylabel("y")
    peak = float(np.nanmax(img)) if np.any(np.isfinite(img)) else 0.0
    ax.set_title(f"lit sphere, E = 1 W/m² from {tuple(np.round(light_dir, 2))}\n"
                 f"display = sRGB(clip(π·L)), peak L = {peak:.3g} W/(m²·sr)", fontsize=8)


def plot_sphere(model, path, light_dir=(1.0, 1.0, 1.0), **params):
    """Lit-sphere preview: pixel = f·cos θi·E with E = 1 W/m², tone map sRGB(clip(π L, 0, 1))."""
    fig = _figure(4.5, 4.8)
    _draw_sphere(fig.add_subplot(111), model, light_dir, params)
    fig.suptitle(_title(model, params), fontsize=9)
    return _save(fig, path)


def plot_summary(model, path, light_dir=(1.0, 1.0, 1.0), theta_i_deg=(0, 30, 60, 80), **params):
    """Lobes, albedo and lit sphere side by side in one image."""
    fig = _figure(15, 4.8)
    _draw_lobes(fig.add_subplot(131, projection="polar"), model, theta_i_deg, params)
    _draw_albedo(fig.add_subplot(132), model, params)
    _draw_sphere(fig.add_subplot(133), model, light_dir, params)
    fig.suptitle(_title(model, params), fontsize=10)
    fig.tight_layout()
    return _save(fig, path)

"""Radiance scene description text (``.rad``, ``.cal``, ``.pts``, ``.vf``) from plain numbers: the pure
half of the Radiance export (``measure.reports.radiance_export`` reads the scene and calls these).

Units and conventions (Radiance reference manual, "Materials" and "Surfaces"; rtrace(1), gensky(1)):

* lengths in metres; every primitive is ``modifier type identifier`` then three argument lines
  (strings, integers, reals), each line starting with its count;
* radiance in Radiance's "watts" of 179 lm/W (the luminous efficacy of white light Radiance assumes:
  ``rtrace -I`` times 179 is lux). Radiometer's scene radiance (W/(m^2 sr) at the scene's efficacy K,
  683 lm/W by default) is written as L x K / 179 per channel: the same luminance;
* ``plastic`` r g b spec rough: diffuse colour and specular reflectance at normal incidence, rough =
  RMS facet slope; ``metal`` the same with the specular part tinted by the colour;
* ``glass`` tr tg tb [n]: a thin pane as one surface whose arguments are the *transmissivity*
  tn (the fraction one pass through the glass keeps), not the normal transmittance Tn. With
  R = ((n - 1)/(n + 1))^2 at normal incidence and incoherent multiple reflections,
  Tn = tn (1 - R)^2 / (1 - R^2 tn^2) (the glass material's own model), solved for tn in
  :func:`glass_transmissivity`; for n = 1.52 this is the manual's
  tn = (sqrt(.8402528435 + .0072522239 Tn^2) - .9166530661) / .0036261119 / Tn;
* ``light`` r g b: radiance of an emitting surface (front side for polygons, which the vertices'
  counter-clockwise order fixes: normal = (v1 - v0) x (v2 - v0));
* a ``.pts`` line is ``x y z dx dy dz`` (a sensor and the direction it faces), read by ``rtrace -I``;
* a ``.vf`` file is ``rview -vtv -vp .. -vd .. -vu .. -vh .. -vv ..`` (angles in degrees).

This module never imports bpy.
"""

import math
import re

import numpy as np

from ..constants import K_RADIANCE_WHITE_LM_PER_W

#: Radiance's luminous efficacy of its "watts" (lm/W): rtrace's irradiance x 179 = illuminance (lux).
RADIANCE_EFFICACY = K_RADIANCE_WHITE_LM_PER_W

_ID = re.compile(r"[^A-Za-z0-9_.\-]")


def identifier(name, taken=None):
    """A Radiance identifier for ``name``: no blanks or shell characters (they end an identifier in a
    .rad file), never empty; made unique against the set ``taken`` (added to it) with a suffix."""
    base = _ID.sub("_", str(name)) or "unnamed"
    if base[0].isdigit() or base[0] in ".-":
        base = "m_" + base
    if taken is None:
        return base
    out, k = base, 1
    while out in taken:
        k += 1
        out = f"{base}_{k}"
    taken.add(out)
    return out


def _reals(values):
    values = [float(v) for v in values]
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"a Radiance argument must be finite, got {values}")
    return " ".join([str(len(values))] + [f"{v + 0.0:.8g}" for v in values])  # + 0.0: no "-0"


def primitive(modifier, kind, name, reals=(), strings=()):
    """One primitive as text: ``modifier kind name`` and its three argument lines."""
    s = f"{len(strings)} " + " ".join(strings) if strings else "0"
    return f"{modifier} {kind} {name}\n{s}\n0\n{_reals(reals)}\n"


def _rgb(value):
    rgb = np.broadcast_to(np.asarray(value, float), (3,))
    if not np.all(np.isfinite(rgb)) or np.any(rgb < 0):
        raise ValueError(f"an RGB value must be finite and >= 0, got {tuple(rgb)}")
    return tuple(float(v) for v in rgb)


def plastic(name, rgb, specular=0.0, roughness=0.0):
    """``plastic``: diffuse reflectance ``rgb`` (0..1), specular reflectance and RMS slope roughness."""
    return primitive("void", "plastic", name, _rgb(rgb) + (float(specular), float(roughness)))


def metal(name, rgb, specular=1.0, roughness=0.0):
    """``metal``: reflectance ``rgb``, the specular fraction (tinted by the colour) and RMS slope."""
    return primitive("void", "metal", name, _rgb(rgb) + (float(specular), float(roughness)))


def glass_transmissivity(normal_transmittance, ior=1.52):
    """Transmissivity tn (fraction one pass keeps) of Radiance's ``glass`` whose normal-incidence
    transmittance is ``normal_transmittance`` Tn (array-like, 0..1): the root in [0, inf) of
    Tn R^2 tn^2 + (1 - R)^2 tn - Tn = 0, R = ((n - 1)/(n + 1))^2 (module docstring). A Tn above
    the clear pane's (1 - R)/(1 + R) gives tn > 1: no glass of index ``ior`` transmits that much."""
    t = np.asarray(normal_transmittance, float)
    r = ((float(ior) - 1.0) / (float(ior) + 1.0)) ** 2
    a = (1.0 - r) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        tn = np.where(t > 0, (np.sqrt(a * a + 4.0 * (t * r) ** 2) - a) / (2.0 * t * r * r), 0.0) if r > 0 else t / a
    return tn


def glass_normal_transmittance(transmissivity, ior=1.52):
    """The inverse of :func:`glass_transmissivity`: Tn = tn (1 - R)^2 / (1 - R^2 tn^2)."""
    tn = np.asarray(transmissivity, float)
    r = ((float(ior) - 1.0) / (float(ior) + 1.0)) ** 2
    return tn * (1.0 - r) ** 2 / (1.0 - (r * tn) ** 2)


def glass(name, normal_transmittance_rgb, ior=1.52):
    """``glass`` of normal transmittance ``normal_transmittance_rgb`` (converted to transmissivity);
    the index is written only where it differs from Radiance's default 1.52."""
    tn = glass_transmissivity(_rgb(normal_transmittance_rgb), ior)
    reals = tuple(float(v) for v in tn) + (() if abs(float(ior) - 1.52) < 1e-6 else (float(ior),))
    return primitive("void", "glass", name, reals)


def light(name, radiance_rgb, modifier="void"):
    """``light`` of radiance ``radiance_rgb`` (Radiance watts/(m^2 sr), see :func:`to_radiance_units`)."""
    return primitive(modifier, "light", name, _rgb(radiance_rgb))


def spotlight(name, radiance_rgb, cone_deg, direction, focus=1e-4):
    """``spotlight``: a ``light`` that emits only within a cone of full angle ``cone_deg`` about
    ``direction`` (a hard edge: Radiance has no blend). The orientation vector's length is the distance
    (m) of the cone's focus behind the source's centre, and Radiance's inverse square counts from that
    focus (measured: a unit vector at 3 m reads (3/4)^2 of the intensity); ``focus`` m, small for a spot
    whose cone starts at its centre as Cycles' does."""
    return primitive("void", "spotlight", name,
                     _rgb(radiance_rgb) + (float(cone_deg),) + tuple(_unit(direction) * float(focus)))


def glow(name, radiance_rgb, max_radius=0.0, modifier="void"):
    """``glow``: radiance that lights the scene only through the ambient calculation (a sky)."""
    return primitive(modifier, "glow", name, _rgb(radiance_rgb) + (float(max_radius),))


def to_radiance_units(radiance_w, efficacy):
    """Scene radiance (W/(m^2 sr) at the scene's ``efficacy`` lm/W, per channel) in Radiance's 179 lm/W
    watts: the same luminance."""
    return np.asarray(radiance_w, float) * (float(efficacy) / RADIANCE_EFFICACY)


def _unit(v):
    v = np.asarray(v, float)
    n = float(np.linalg.norm(v))
    if not (n > 0 and math.isfinite(n)):
        raise ValueError(f"a direction must be non-zero and finite, got {tuple(v)}")
    return v / n


def polygon(modifier, name, vertices):
    """``polygon`` through ``vertices`` (K >= 3, 3) m; its front side is where the counter-clockwise
    order faces."""
    v = np.asarray(vertices, float).reshape(-1, 3)
    if len(v) < 3:
        raise ValueError(f"a polygon needs at least 3 vertices, got {len(v)}")
    return primitive(modifier, "polygon", name, v.ravel())


def triangles(modifier, prefix, tris):
    """Many ``polygon`` triangles (T, 3, 3) m named ``prefix.0``, ``prefix.1``, ... in one string
    (formatted with numpy: a capture may hold millions). Degenerate triangles (zero area) are skipped:
    oconv warns about them."""
    t = np.asarray(tris, float).reshape(-1, 3, 3)
    if not np.all(np.isfinite(t)):
        raise ValueError("triangle coordinates must be finite")
    area2 = np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
    keep = np.flatnonzero(area2 > 0)
    if not len(keep):
        return ""
    body = np.char.mod("%.8g", t[keep].reshape(len(keep), 9))
    lines = [f"{modifier} polygon {prefix}.{k}\n0\n0\n9 " + " ".join(row) + "\n" for k, row in zip(keep, body)]
    return "".join(lines)


def sphere(modifier, name, centre, radius):
    """``sphere`` of ``radius`` m about ``centre``."""
    return primitive(modifier, "sphere", name, tuple(np.asarray(centre, float)) + (float(radius),))


def ring(modifier, name, centre, normal, outer_radius, inner_radius=0.0):
    """``ring``: a disc (annulus) of ``outer_radius`` m about ``centre`` facing ``normal`` (its front);
    Radiance samples a ring source exactly where a many-sided polygon source loses its rim ("aiming
    failure", measured 6 % low for a 64-gon at -ds 0.002)."""
    return primitive(modifier, "ring", name, tuple(np.asarray(centre, float)) + tuple(_unit(normal))
                     + (float(inner_radius), float(outer_radius)))


def source(modifier, name, direction, angle_deg):
    """``source``: a distant disc towards ``direction`` (from the scene to the source) of full angle
    ``angle_deg`` (360: the whole sphere, a sky)."""
    return primitive(modifier, "source", name, tuple(_unit(direction)) + (float(angle_deg),))


def distant_radiance(normal_irradiance, angle_rad):
    """Radiance of a uniform distant disc of full angle ``angle_rad`` giving ``normal_irradiance`` on a
    surface facing it: E / Omega with Omega = 2 pi (1 - cos(angle / 2))."""
    omega = 2.0 * math.pi * (1.0 - math.cos(0.5 * float(angle_rad)))
    return np.asarray(normal_irradiance, float) / omega


def sphere_light_radiance(intensity, radius):
    """Radiance of a Lambertian-looking sphere of ``radius`` m with radiant ``intensity`` (W/sr) in
    every direction: I = L pi r^2 (its projected area)."""
    return np.asarray(intensity, float) / (math.pi * float(radius) ** 2)


def points(locations, directions):
    """``.pts`` text: one ``x y z dx dy dz`` line per sensor (``rtrace -I`` input)."""
    p = np.asarray(locations, float).reshape(-1, 3)
    d = np.broadcast_to(np.asarray(directions, float), p.shape)
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(d))):
        raise ValueError("sensor positions and directions must be finite")
    n = np.linalg.norm(d, axis=1, keepdims=True)
    if np.any(n == 0):
        raise ValueError("a sensor direction must be non-zero")
    rows = np.char.mod("%.8g", np.concatenate([p, d / n], axis=1))
    return "".join(" ".join(r) + "\n" for r in rows)


def view(position, direction, up, horizontal_deg, vertical_deg, projection="v", shift=(0.0, 0.0)):
    """``.vf`` text: ``rview -vt<projection> -vp x y z -vd .. -vu .. -vh .. -vv ..`` (degrees);
    ``projection`` 'v' perspective, 'l' parallel (then the sizes are metres), 'a' angular fisheye."""
    vp, vd, vu = (np.asarray(v, float) for v in (position, direction, up))
    _unit(vd), _unit(vu)
    parts = [f"rview -vt{projection}", "-vp " + " ".join(f"{v:.8g}" for v in vp),
             "-vd " + " ".join(f"{v:.8g}" for v in _unit(vd)), "-vu " + " ".join(f"{v:.8g}" for v in _unit(vu)),
             f"-vh {float(horizontal_deg):.8g}", f"-vv {float(vertical_deg):.8g}"]
    if any(shift):
        parts.append(f"-vs {float(shift[0]):.8g} -vl {float(shift[1]):.8g}")
    return " ".join(parts) + "\n"

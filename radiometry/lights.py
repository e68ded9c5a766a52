"""Analytic direct irradiance from Blender/Cycles lights, in SI, vectorised over receivers.

Every model follows what Cycles (Blender 5.0) renders, read from its source
(``intern/cycles/scene/light.cpp`` device_update_lights and ``Light::area``;
``kernel/light/{point,spot,area,distant}.h``) and checked by renders in
``tests/bpy/test_cycles_lights_*.py``:

* point/spot, radius 0: radiant intensity I = P/(4 pi) (``eval_fac = 1/(pi * 4)``), E = I cos/r^2;
  a spot multiplies by ``smoothstep((z - cos(size/2)) / ((1 - cos(size/2)) * blend))`` where z is the
  cosine to -Z of the direction *in the object's scaled local frame* (non-uniform scale stretches
  the cone); blend 0 is a hard edge.
* point/spot, radius R, soft falloff OFF: Lambertian sphere of radiance P/(4 pi^2 R^2).
* point/spot, radius R, soft falloff ON: a disk of radius R always facing the receiver, same
  radiance, so E = P cos / (4 pi (R^2 + r^2)) above the horizon.
* spot with R > 0: the cone attenuation is applied per incoming direction (quadrature).
* sun: uniform cone of half-angle angle/2 whose normal irradiance is ``energy``.
* area: Lambertian emitter L = P/(pi A) on the -Z side; ``spread`` < 180 deg multiplies the
  radiance by max((tan(s/2) - tan a) / (tan(s/2) - s/2), 0) (soft-box slats, flux preserving).

Units: positions in metres, rgb_power in W per channel (sun: W/m^2 per channel), results in
W/m^2 per channel. A delta light (point/spot of radius 0) at zero distance raises ValueError.

References
----------
See :mod:`.geometry` for the projected-solid-angle formulas (Lambert 1760, Arvo 1995, Baum 1989,
Snyder 1996, Lagarde & de Rousiers 2014); spread: Blender differential D10594 (soft-box spread).
"""

from dataclasses import dataclass, field

import numpy as np

from .geometry import cap_projected_solid_angle, norm, polygon_projected_solid_angle, unit
from .units import as_finite_array, check_nonnegative, scene_to_metres

__all__ = ["LightSpec", "light_spec_from_values", "irradiance", "exactness", "radiant_intensity",
           "spot_attenuation", "DISK_POLYGON_SIDES"]

KINDS = ("POINT", "SPOT", "SUN", "AREA")
SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")

#: Sides of the equal-area polygon standing in for a disk/ellipse: relative irradiance error
#: below 1e-7 (measured against the closed-form disk in tests/test_radiometry_lights.py).
DISK_POLYGON_SIDES = 2048

#: Gauss-Legendre orders of the quadratures (spot with radius, spread < 180 deg).
QUADRATURE_RADIAL = 48
QUADRATURE_ANGULAR = 96


def _frozen(a):
    a = np.array(a, dtype=np.float64)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class LightSpec:
    """A Blender light in SI units (see module docstring for the meaning Cycles gives each field).

    Attributes
    ----------
    name : str
    kind : {'POINT', 'SPOT', 'SUN', 'AREA'}
    position : (3,) m
    axes : (3, 3) orthonormal rotation, columns = local x, y, z (emission along local -Z)
    scale : (3,) object scale (spot cone shape, area light extents)
    rgb_power : (3,) W per channel = energy * 2**exposure * colour (* Cycles' area when normalize
        is off); SUN: irradiance W/m^2 per channel on a surface facing it
    radius : m (shadow_soft_size); soft_falloff : bool
    spot_size : rad (full cone angle); spot_blend : 0..1
    angle : rad (sun's full angular diameter)
    shape, size, size_y : area-light shape and unscaled extents, m
    spread : rad (area light, pi = Lambertian)
    normalize : bool, informational (already folded into rgb_power)
    """

    name: str = "light"
    kind: str = "POINT"
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))
    axes: np.ndarray = field(default_factory=lambda: np.eye(3))
    scale: np.ndarray = field(default_factory=lambda: np.ones(3))
    rgb_power: np.ndarray = field(default_factory=lambda: np.ones(3))
    radius: float = 0.0
    soft_falloff: bool = True
    spot_size: float = np.pi / 4
    spot_blend: float = 0.15
    angle: float = 0.0
    shape: str = "SQUARE"
    size: float = 1.0
    size_y: float = 1.0
    spread: float = np.pi
    normalize: bool = True

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {SHAPES}, got {self.shape!r}")
        object.__setattr__(self, "position", _frozen(as_finite_array(self.position, "position", (3,))))
        axes = as_finite_array(self.axes, "axes", (3, 3))
        if not np.allclose(axes.T @ axes, np.eye(3), atol=1e-5):
            raise ValueError("axes must be an orthonormal rotation (columns = local x, y, z)")
        object.__setattr__(self, "axes", _frozen(axes))
        scale = as_finite_array(self.scale, "scale", (3,))
        if np.any(scale <= 0.0):
            raise ValueError("scale must be > 0 on every axis (put mirroring into axes)")
        object.__setattr__(self, "scale", _frozen(scale))
        object.__setattr__(self, "rgb_power", _frozen(as_finite_array(self.rgb_power, "rgb_power", (3,))))
        for name in ("radius", "spot_size", "spot_blend", "angle", "size", "size_y", "spread"):
            value = float(check_nonnegative(getattr(self, name), name))
            if name in ("spot_size", "angle", "spread"):
                # Blender stores angles in float32: float32(pi) is 8.7e-8 above float64 pi.
                if value > np.pi + 1e-6:
                    raise ValueError(f"{name} must be <= pi rad, got {value!r}")
                value = min(value, np.pi)
            object.__setattr__(self, name, value)

    # Derived quantities -------------------------------------------------------------------
    @property
    def emission_direction(self):
        """Unit world vector the light points along (local -Z)."""
        return -self.axes[:, 2]

    @property
    def extents(self):
        """Area light full extents (u, v) in metres, object scale included."""
        v = self.size_y if self.shape in ("RECTANGLE", "ELLIPSE") else self.size
        return self.size * self.scale[0], v * self.scale[1]

    @property
    def area_m2(self):
        """Emitting area: area light (ellipse pi/4 u v), sphere 4 pi R^2; sun/delta: nan."""
        if self.kind == "AREA":
            u, v = self.extents
            return u * v * (np.pi / 4 if self.shape in ("DISK", "ELLIPSE") else 1.0)
        if self.radius > 0.0 and self.kind in ("POINT", "SPOT"):
            return 4.0 * np.pi * self.radius**2
        return float("nan")


# --- construction from Blender values ------------------------------------------------------

def _cycles_area_scene_units(kind, values, scale3):
    """Cycles' ``Light::area`` in scene units (used as the power factor when normalize is off)."""
    if kind in ("POINT", "SPOT"):
        r = float(values.get("shadow_soft_size", 0.0))
        return 4.0 * np.pi * r * r if r > 0.0 else 4.0
    if kind == "SUN":
        half = 0.5 * float(values.get("angle", 0.0))
        return np.pi * np.sin(half) ** 2 if half > 0.0 else 1.0
    shape = values.get("shape", "SQUARE")
    u = float(values.get("size", 1.0))
    v = float(values.get("size_y", 1.0)) if shape in ("RECTANGLE", "ELLIPSE") else u
    area = u * scale3[0] * v * scale3[1]
    return area * (np.pi / 4 if shape in ("DISK", "ELLIPSE") else 1.0)


def light_spec_from_values(values, scale_length=1.0):
    """Build a :class:`LightSpec` in SI from plain values read from a ``bpy.types.Light`` and object.

    Parameters
    ----------
    values : dict
        Keys named as Blender 5 Light RNA: ``type``, ``energy``, ``color``, ``use_temperature``,
        ``temperature``, ``temperature_color`` (optional: Blender's own value; computed with
        :func:`.photometry.blackbody_rgb` otherwise), ``exposure``, ``normalize``,
        ``use_soft_falloff``, ``shadow_soft_size``, ``spot_size``, ``spot_blend``, ``shape``,
        ``size``, ``size_y``, ``spread``, ``angle``; plus ``matrix_world`` (4x4 nested list, rows)
        and optionally ``name``.
    scale_length : float
        Metres per scene unit.

    Notes
    -----
    Colour: with ``use_temperature`` Cycles uses ``color * temperature_color`` (measured, see the
    bpy tests). Power per channel = energy * 2**exposure * colour, times Cycles' ``Light::area``
    (scene units) when normalize is off. Cycles renders in scene units; to keep every quantity
    consistent with the render (E_SI = E_render / scale_length^2), the sun's irradiance is divided
    by scale_length^2 too.
    """
    from .photometry import blackbody_rgb  # local: keeps import order simple

    kind = str(values.get("type", "POINT"))
    if kind not in KINDS:
        raise ValueError(f"unsupported light type {kind!r}; expected one of {KINDS}")
    matrix = as_finite_array(values.get("matrix_world", np.eye(4)), "matrix_world", (4, 4))
    columns = matrix[:3, :3]
    scale3 = norm(columns.T)
    if np.any(scale3 <= 0.0):
        raise ValueError("matrix_world has a zero scale axis")
    axes = columns / scale3[np.newaxis, :]
    if np.linalg.det(axes) < 0.0:  # mirrored object: fold the mirror into the local x axis sign
        axes[:, 0] = -axes[:, 0]
    if not np.allclose(axes.T @ axes, np.eye(3), atol=1e-5):
        raise ValueError("matrix_world has shear; only rotation, translation and scale are supported")
    scale = float(scale_length)
    colour = as_finite_array(values.get("color", (1.0, 1.0, 1.0)), "color", (3,))
    if values.get("use_temperature", False):
        tc = values.get("temperature_color")
        tc = blackbody_rgb(float(values.get("temperature", 6500.0))) if tc is None else tc
        colour = colour * as_finite_array(tc, "temperature_color", (3,))
    energy = float(values.get("energy", 10.0)) * 2.0 ** float(values.get("exposure", 0.0))
    rgb = energy * colour
    normalize = bool(values.get("normalize", True))
    if not normalize:
        rgb = rgb * _cycles_area_scene_units(kind, values, scale3)
    if kind == "SUN":
        rgb = rgb / scale**2
    return LightSpec(
        name=str(values.get("name", "light")), kind=kind,
        position=scene_to_metres(matrix[:3, 3], scale), axes=axes, scale=scale3, rgb_power=rgb,
        radius=float(scene_to_metres(values.get("shadow_soft_size", 0.0), scale)),
        soft_falloff=bool(values.get("use_soft_falloff", True)),
        spot_size=float(values.get("spot_size", np.pi / 4)), spot_blend=float(values.get("spot_blend", 0.15)),
        angle=float(values.get("angle", 0.0)), shape=str(values.get("shape", "SQUARE")),
        size=float(scene_to_metres(values.get("size", 1.0), scale)),
        size_y=float(scene_to_metres(values.get("size_y", 1.0), scale)),
        spread=float(values.get("spread", np.pi)), normalize=normalize,
    )


# --- shared pieces -------------------------------------------------------------------------

def _smoothstep(x):
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def spot_attenuation(spec, directions):
    """Cycles' spot cone factor for world directions leaving the light, (..., 3) -> (...).

    z = cosine to the local -Z axis of the direction mapped into the scaled local frame
    (``itfm``), factor = smoothstep((z - cos(spot_size/2)) / ((1 - cos(spot_size/2)) * blend)).
    """
    d = np.asarray(directions, dtype=np.float64)
    local = unit((d @ spec.axes) / spec.scale)
    z = -local[..., 2]
    cos_half = np.cos(0.5 * spec.spot_size)
    width = (1.0 - cos_half) * spec.spot_blend
    if width <= 0.0:
        return (z > cos_half).astype(np.float64)
    return _smoothstep((z - cos_half) / width)


def _prepare(points, normals):
    p = as_finite_array(points, "points")
    n = as_finite_array(normals, "normals")
    if p.shape[-1:] != (3,) or n.shape[-1:] != (3,):
        raise ValueError("points and normals need a last axis of 3")
    p, n = np.broadcast_arrays(p, n)
    lead = p.shape[:-1]
    n_len = norm(n)
    if np.any(n_len == 0.0):
        raise ValueError("normals contain a zero vector")
    return p.reshape(-1, 3), (n / n_len[..., np.newaxis]).reshape(-1, 3), lead


def _cone_quadrature(axis_dirs, sin_sq_sigma, normals, weight_fn, chunk=256):
    """int over the cone {angle to axis < sigma} of weight_fn(omega) * max(n.omega, 0) d omega.

    Gauss-Legendre in t = 1 - cos(gamma) on [0, 1 - cos sigma] and in azimuth; returns (N,).
    """
    tg, tw = np.polynomial.legendre.leggauss(QUADRATURE_RADIAL)
    pg, pw = np.polynomial.legendre.leggauss(QUADRATURE_ANGULAR)
    out = np.empty(axis_dirs.shape[0])
    for start in range(0, axis_dirs.shape[0], chunk):
        sl = slice(start, start + chunk)
        w = axis_dirs[sl]
        s2 = sin_sq_sigma[sl]
        one_minus_cos = s2 / (1.0 + np.sqrt(np.maximum(1.0 - s2, 0.0)))
        helper = np.where(np.abs(w[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        e1 = unit(np.cross(w, helper))
        e2 = np.cross(w, e1)
        t = 0.5 * (tg[np.newaxis, :] + 1.0) * one_minus_cos[:, np.newaxis]            # (M, R)
        wt = 0.5 * tw[np.newaxis, :] * one_minus_cos[:, np.newaxis]
        phi = np.pi * (pg + 1.0)
        wphi = np.pi * pw
        sin_g = np.sqrt(np.maximum(t * (2.0 - t), 0.0))
        cos_g = 1.0 - t
        dirs = (cos_g[..., None, None] * w[:, None, None, :]
                + sin_g[..., None, None] * (np.cos(phi)[None, None, :, None] * e1[:, None, None, :]
                                            + np.sin(phi)[None, None, :, None] * e2[:, None, None, :]))
        cosr = np.maximum(np.einsum("mrak,mk->mra", dirs, normals[sl]), 0.0)
        f = weight_fn(dirs, sl) * cosr
        out[sl] = np.einsum("mra,mr,a->m", f, wt, wphi)
    return out


def _ellipse_polygon(spec):
    u, v = spec.extents
    k = np.sqrt((2 * np.pi / DISK_POLYGON_SIDES) / np.sin(2 * np.pi / DISK_POLYGON_SIDES))  # equal area
    phi = np.arange(DISK_POLYGON_SIDES) * (2 * np.pi / DISK_POLYGON_SIDES)
    return np.stack([0.5 * u * k * np.cos(phi), 0.5 * v * k * np.sin(phi)], axis=1)


def _area_outline_local(spec):
    u, v = spec.extents
    if spec.shape in ("DISK", "ELLIPSE"):
        return _ellipse_polygon(spec)
    return np.array([[-u / 2, -v / 2], [u / 2, -v / 2], [u / 2, v / 2], [-u / 2, v / 2]])


def _spread_normalisation(half_spread):
    # Cycles scene/light.cpp: 1 / (tan h - h), third-order Taylor 3 / h^3 below h = 0.05 rad.
    if half_spread > 0.05:
        return 1.0 / (np.tan(half_spread) - half_spread)
    return 3.0 / half_spread**3


# --- per-kind geometric factors (irradiance per unit rgb_power), shape (N,) ------------------

def _delta_factor(spec, p, n):
    to_light = spec.position - p
    r = norm(to_light)
    if np.any(r == 0.0):
        raise ValueError("zero distance to light: a point/spot of radius 0 has infinite irradiance at its position")
    w = to_light / r[:, None]
    cos_r = np.maximum(np.sum(w * n, axis=1), 0.0)
    g = cos_r / (4.0 * np.pi * r) / r
    if spec.kind == "SPOT":
        g = g * spot_attenuation(spec, -w)
    return g


def _sphere_or_disk_factor(spec, p, n):
    to_light = spec.position - p
    d = norm(to_light)
    if np.any(d == 0.0) and spec.soft_falloff:
        raise ValueError("zero distance to light: receiver at the centre of a soft-falloff light")
    w = unit(to_light)
    big_r = spec.radius
    radiance = 1.0 / (4.0 * np.pi**2 * big_r**2)
    if spec.soft_falloff:
        sin_sq = big_r**2 / (big_r**2 + d**2)
        inside = np.zeros(d.shape, dtype=bool)
    else:
        inside = d <= big_r
        sin_sq = np.where(inside, 1.0, (big_r / np.maximum(d, big_r)) ** 2)
    cos_t = np.sum(w * n, axis=1)
    if spec.kind == "POINT":
        g = radiance * cap_projected_solid_angle(cos_t, sin_sq)
    else:
        g = radiance * _cone_quadrature(w, sin_sq, n, lambda dirs, sl: spot_attenuation(spec, -dirs))
    # Inside a sphere Cycles sees radiance L over the whole hemisphere, without spot attenuation.
    return np.where(inside, radiance * np.pi, g)


def _sun_factor(spec, p, n):
    to_sun = spec.axes[:, 2]
    cos_t = n @ to_sun
    half = 0.5 * spec.angle
    if half == 0.0:
        return np.maximum(cos_t, 0.0)
    sin_sq = np.sin(half) ** 2
    return cap_projected_solid_angle(cos_t, np.full_like(cos_t, sin_sq)) / (np.pi * sin_sq)


def _area_factor(spec, p, n):
    area = spec.area_m2
    if area <= 0.0:
        return np.zeros(p.shape[0])
    normal = spec.emission_direction
    in_front = (p - spec.position) @ normal > 0.0
    radiance = 1.0 / (np.pi * area)
    out = np.zeros(p.shape[0])
    if not np.any(in_front):
        return out
    pf, nf = p[in_front], n[in_front]
    if spec.spread >= np.pi:
        outline = _area_outline_local(spec)
        verts = spec.position + outline[:, :1] * spec.axes[:, 0] + outline[:, 1:] * spec.axes[:, 1]
        out[in_front] = radiance * polygon_projected_solid_angle(verts, pf, nf)
    elif spec.spread == 0.0:
        out[in_front] = _collimated_area_factor(spec, pf, nf)
    else:
        out[in_front] = radiance * _spread_quadrature(spec, pf, nf)
    return out


def _inside_shape(spec, uv):
    u, v = spec.extents
    if spec.shape in ("DISK", "ELLIPSE"):
        return (2 * uv[:, 0] / u) ** 2 + (2 * uv[:, 1] / v) ** 2 <= 1.0
    return (np.abs(uv[:, 0]) <= u / 2) & (np.abs(uv[:, 1]) <= v / 2)


def _collimated_area_factor(spec, p, n):
    # Spread 0: Cycles emits only along the normal (attenuation pi for tan a < 1e-5), flux P.
    rel = p - spec.position
    uv = np.stack([rel @ spec.axes[:, 0], rel @ spec.axes[:, 1]], axis=1)
    cos_r = np.maximum(n @ (-spec.emission_direction), 0.0)
    return np.where(_inside_shape(spec, uv), cos_r / spec.area_m2, 0.0)


def _ray_interval(spec, foot, directions):
    """rho interval [lo, hi] where foot + rho * dir (2-D, light plane) lies inside the shape."""
    u, v = spec.extents
    fx, fy = foot[:, None, 0], foot[:, None, 1]
    dx, dy = directions[None, :, 0], directions[None, :, 1]
    if spec.shape in ("DISK", "ELLIPSE"):
        a, b = u / 2, v / 2
        qa = (dx / a) ** 2 + (dy / b) ** 2
        qb = 2 * (fx * dx / a**2 + fy * dy / b**2)
        qc = (fx / a) ** 2 + (fy / b) ** 2 - 1.0
        disc = qb * qb - 4 * qa * qc
        root = np.sqrt(np.maximum(disc, 0.0))
        lo = (-qb - root) / (2 * qa)
        hi = (-qb + root) / (2 * qa)
        hi = np.where(disc > 0.0, hi, lo)
        return lo, hi
    lo = np.full(np.broadcast(fx, dx).shape, -np.inf)
    hi = np.full(lo.shape, np.inf)
    for f, d, half in ((fx, dx, u / 2), (fy, dy, v / 2)):
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (-half - f) / d
            t2 = (half - f) / d
        parallel = np.abs(d) < 1e-300
        outside = parallel & (np.abs(f) > half)
        t_lo = np.where(parallel, -np.inf, np.minimum(t1, t2))
        t_hi = np.where(parallel, np.inf, np.maximum(t1, t2))
        lo = np.maximum(lo, t_lo)
        hi = np.minimum(hi, np.where(outside, -np.inf, t_hi))
    return lo, hi


def _spread_quadrature(spec, p, n):
    """int over the emitter of att(a) cos_r cos_l / r^2 dA, polar around the receiver's foot point.

    att = max((tan h - tan a) * norm, 0) with tan a = rho / t only depends on the distance rho from
    the foot point, so in polar coordinates the integrand is smooth in rho on
    [0, min(t tan h, shape boundary)]: Gauss-Legendre in rho (exact support) and in azimuth.
    """
    half = 0.5 * spec.spread
    tan_h = np.tan(half)
    ns = _spread_normalisation(half)
    normal = spec.emission_direction
    rel = p - spec.position
    t = rel @ normal                                   # > 0: distance to the light plane
    foot = np.stack([rel @ spec.axes[:, 0], rel @ spec.axes[:, 1]], axis=1)
    rho_max = t * tan_h
    rg, rw = np.polynomial.legendre.leggauss(QUADRATURE_RADIAL)
    pg, pw = np.polynomial.legendre.leggauss(QUADRATURE_ANGULAR * 2)
    phi = np.pi * (pg + 1.0)
    wphi = np.pi * pw
    dirs2 = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    lo, hi = _ray_interval(spec, foot, dirs2)          # (N, A)
    lo = np.maximum(lo, 0.0)
    hi = np.minimum(hi, rho_max[:, None])
    span = np.maximum(hi - lo, 0.0)
    rho = lo[..., None] + 0.5 * (rg + 1.0) * span[..., None]     # (N, A, R)
    w_r = 0.5 * rw * span[..., None]
    # Light point minus receiver = rho * (in-plane direction) - t * normal, world frame.
    x = rho * dirs2[None, :, None, 0]
    y = rho * dirs2[None, :, None, 1]
    vec = (x[..., None] * spec.axes[:, 0] + y[..., None] * spec.axes[:, 1]
           - t[:, None, None, None] * normal)            # receiver -> light point
    r2 = rho**2 + t[:, None, None] ** 2
    cos_l = t[:, None, None] / np.sqrt(r2)
    cos_r = np.maximum(np.einsum("nark,nk->nar", vec, n) / np.sqrt(r2), 0.0)
    att = np.maximum((tan_h - rho / t[:, None, None]) * ns, 0.0)
    integrand = att * cos_r * cos_l / r2 * rho          # rho: polar Jacobian
    return np.einsum("nar,nar,a->n", integrand, w_r, wphi)


# --- public API ----------------------------------------------------------------------------

def irradiance(spec, points, normals):
    """Direct irradiance (no occlusion) from one light, W/m^2 per RGB channel.

    Parameters
    ----------
    spec : LightSpec
    points : array_like, shape (..., 3)
        Receiver positions, m.
    normals : array_like, shape (..., 3)
        Receiver normals (normalised here; zero vectors raise ValueError).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Irradiance; 0 behind area/spot lights, outside cones and below the horizon.

    Raises
    ------
    ValueError
        NaN/inf inputs, or a receiver exactly at a delta light's position ("zero distance").
    """
    p, n, lead = _prepare(points, normals)
    if spec.kind == "SUN":
        g = _sun_factor(spec, p, n)
    elif spec.kind == "AREA":
        g = _area_factor(spec, p, n)
    elif spec.radius == 0.0:
        g = _delta_factor(spec, p, n)
    else:
        g = _sphere_or_disk_factor(spec, p, n)
    return (g[:, None] * spec.rgb_power[None, :]).reshape(lead + (3,))


def exactness(spec):
    """(is_exact, model_name, note) describing how :func:`irradiance` computes this light."""
    if spec.kind == "SUN":
        if spec.angle == 0.0:
            return True, "directional", "E = energy cos(theta), exact"
        return True, "uniform cap", "Snyder 1996 cap under the horizon, exact"
    if spec.kind == "AREA":
        if spec.spread >= np.pi:
            if spec.shape in ("DISK", "ELLIPSE"):
                return True, "Lambert polygon", f"equal-area {DISK_POLYGON_SIDES}-gon, rel. error < 1e-7"
            return True, "Lambert polygon", "closed form with horizon clipping, exact"
        if spec.spread == 0.0:
            return True, "collimated", "spread 0: emission only along the normal"
        return False, "quadrature", (f"Gauss-Legendre {QUADRATURE_RADIAL}x{2 * QUADRATURE_ANGULAR} in polar "
                                     "coordinates about the foot point; rel. error ~1e-4 or better")
    if spec.radius == 0.0:
        return True, "point" if spec.kind == "POINT" else "spot", "inverse square law, exact"
    model = "disk facing receiver" if spec.soft_falloff else "Lambertian sphere"
    if spec.kind == "POINT":
        return True, model, "closed-form cap projected solid angle, exact"
    return False, "quadrature", (f"{model} with per-direction spot attenuation, Gauss-Legendre "
                                 f"{QUADRATURE_RADIAL}x{QUADRATURE_ANGULAR} over the cone; ~1e-3 at hard edges")


def radiant_intensity(spec, direction):
    """Far-field radiant intensity, W/sr per channel, for world directions leaving the light.

    Point/sphere/disk: P/(4 pi); spot: times the cone factor; area: L A cos(theta) times the
    spread factor (0 behind); sun: ValueError (no position, inverse square does not apply).
    """
    d = unit(as_finite_array(direction, "direction"))
    if spec.kind == "SUN":
        raise ValueError("a sun has no position: inverse-square does not apply")
    if spec.kind in ("POINT", "SPOT"):
        f = np.full(d.shape[:-1], 1.0 / (4.0 * np.pi))
        if spec.kind == "SPOT":
            f = f * spot_attenuation(spec, d)
    else:
        cos_l = np.maximum(d @ spec.emission_direction, 0.0)
        f = cos_l / np.pi
        if spec.spread < np.pi:
            half = 0.5 * spec.spread
            tan_a = np.sqrt(np.maximum(1.0 - cos_l**2, 0.0)) / np.maximum(cos_l, 1e-300)
            f = f * np.maximum((np.tan(half) - tan_a) * _spread_normalisation(half), 0.0) if half > 0 else f * 0.0
    return f[..., None] * spec.rgb_power

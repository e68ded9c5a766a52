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
* photometric point light (radius 0, node tree Emission <- IES Texture; ``intensity_table``):
  I(dir) = rgb_power * table(dir) W/sr with Cycles' IES lookup (see :class:`IntensityTable`),
  E = I cos / r^2.

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
from .units import as_finite_array, check_nonnegative, frozen_array, scene_to_metres

__all__ = ["LightSpec", "IntensityTable", "light_spec_from_values", "irradiance", "irradiance_with_bound", "exactness",
           "radiant_intensity",
           "spot_attenuation", "DISK_POLYGON_SIDES"]

KINDS = ("POINT", "SPOT", "SUN", "AREA")
SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")

#: Sides of the equal-area polygon standing in for a disk/ellipse: relative irradiance error
#: below 1e-8 unless the receiver is within ~1 % of the radius of the rim (measured against a
#: 262144-gon: 2e-5 at 0.1 mm from a 0.5 m rim, 1 mm below it); irradiance_with_bound's per-point
#: bound (2048- vs 1024-gon) covers it conservatively (3e-4 there).
DISK_POLYGON_SIDES = 2048

#: Gauss-Legendre orders of the quadratures (spread < 180 deg; sheared area lights).
QUADRATURE_RADIAL = 48
QUADRATURE_ANGULAR = 96
#: Spot with radius: azimuth nodes, and nodes per smooth polar piece (between cone edge,
#: blend edge and horizon crossings).
QUADRATURE_SPOT_PHI = 256
QUADRATURE_SPOT_T = 8


_frozen = frozen_array  # short local name


@dataclass(frozen=True)
class IntensityTable:
    """A photometric (IES) light's intensity per unit ``rgb_power``, as Cycles looks it up.

    I(d) = rgb_power * interp(h(d), v(d)) W/sr for a world direction d leaving the light, with
    u = vector_map @ matrix.T @ d (Cycles: Geometry Incoming, world-to-object NORMAL transform =
    the transposed object matrix, then the node tree's Mapping), v = acos(-u_z / |u|) and
    h = atan2(u_x, u_y) + 180 deg, and ``interp`` Cycles' IES kernel
    (:func:`.photometric_files.catmull_rom_table`: Catmull-Rom on indices, 0 outside the table).

    Attributes
    ----------
    h_deg : (n_h,) ascending C angles of Cycles' table, deg (0..360 for a wrapping table)
    v_deg : (n_v,) ascending vertical angles, deg (0 = along the IES vector's -Z)
    values : (n_h, n_v) W/sr per W of rgb_power (Cycles' IES texture value / (4 pi))
    vector_map : (3, 3) the Mapping node's linear map (identity without one)
    rgb_scale : (3,) Emission colour x Emission strength x IES strength, folded into rgb_power
        by :func:`light_spec_from_values`
    label : str, where the table came from (shown in notes)
    """

    h_deg: np.ndarray
    v_deg: np.ndarray
    values: np.ndarray
    vector_map: np.ndarray = field(default_factory=lambda: np.eye(3))
    rgb_scale: np.ndarray = field(default_factory=lambda: np.ones(3))
    label: str = "IES"

    def __post_init__(self):
        h = _frozen(as_finite_array(self.h_deg, "h_deg"))
        v = _frozen(as_finite_array(self.v_deg, "v_deg"))
        values = _frozen(as_finite_array(self.values, "values"))
        if h.ndim != 1 or v.ndim != 1 or h.size < 2 or v.size < 2 or values.shape != (h.size, v.size):
            raise ValueError("IntensityTable needs h_deg (n_h >= 2), v_deg (n_v >= 2) and values (n_h, n_v)")
        if np.any(np.diff(h) <= 0.0) or np.any(np.diff(v) <= 0.0):
            raise ValueError("IntensityTable angles must increase")
        if np.any(values < 0.0):
            raise ValueError("IntensityTable values must be >= 0")
        vmap = as_finite_array(self.vector_map, "vector_map", (3, 3))
        if abs(np.linalg.det(vmap)) < 1e-12:
            raise ValueError("IntensityTable vector_map is singular")
        for name, value in (("h_deg", h), ("v_deg", v), ("values", values), ("vector_map", _frozen(vmap)),
                            ("rgb_scale", _frozen(as_finite_array(self.rgb_scale, "rgb_scale", (3,))))):
            object.__setattr__(self, name, value)

    def lookup(self, local):
        """Table value for directions ``local`` = matrix.T @ d (..., 3), before the Mapping."""
        from .photometric_files import catmull_rom_table

        u = unit(np.asarray(local, dtype=np.float64) @ self.vector_map.T)
        v = np.degrees(np.arccos(np.clip(-u[..., 2], -1.0, 1.0)))
        h = np.degrees(np.arctan2(u[..., 0], u[..., 1]) + np.pi)
        if self.h_deg[0] == 0.0 and abs(self.h_deg[-1] - 360.0) < 1e-4:
            # Cycles returns 0 at exactly h = 360 deg (h >= last angle), a single direction where
            # its rendered patch still sees the neighbouring values: read it as 0 deg instead.
            h = np.where(h >= self.h_deg[-1], 0.0, h)
        return catmull_rom_table(self.h_deg, self.v_deg, self.values, h, v)


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
    intensity_table : IntensityTable or None
        A photometric point light (POINT, radius 0): its intensity table replaces P/(4 pi).
    matrix : (3, 3) or None
        The object's full linear map (``matrix_world[:3, :3]``, dimensionless, may be sheared or
        mirrored). None means ``axes @ diag(scale)``. Cycles takes every light direction from it:
        emission/sun direction -normalize(column 2), spot cone via its inverse, area edges
        column 0 * size and column 1 * size_y.
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
    matrix: np.ndarray = None
    intensity_table: IntensityTable = None

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
        if self.matrix is None:
            matrix = axes * scale[np.newaxis, :]
        else:
            matrix = as_finite_array(self.matrix, "matrix", (3, 3))
            if abs(np.linalg.det(matrix)) <= 1e-12 * np.prod(norm(matrix.T)):
                raise ValueError("matrix is singular (a zero scale axis)")
        object.__setattr__(self, "matrix", _frozen(matrix))
        object.__setattr__(self, "rgb_power", _frozen(as_finite_array(self.rgb_power, "rgb_power", (3,))))
        for name in ("radius", "spot_size", "spot_blend", "angle", "size", "size_y", "spread"):
            value = float(check_nonnegative(getattr(self, name), name))
            if name in ("spot_size", "angle", "spread"):
                # Blender stores angles in float32: float32(pi) is 8.7e-8 above float64 pi.
                if value > np.pi + 1e-6:
                    raise ValueError(f"{name} must be <= pi rad, got {value!r}")
                value = min(value, np.pi)
            object.__setattr__(self, name, value)
        if self.intensity_table is not None:
            _check_table_light(self)

    # Derived quantities -------------------------------------------------------------------
    @property
    def emission_direction(self):
        """Unit world vector the light points along: -normalize(matrix column 2), Cycles' ``dir``."""
        return -unit(self.matrix[:, 2])

    @property
    def is_sheared(self):
        """True when the matrix columns are not mutually orthogonal (a rotated child of a
        non-uniformly scaled parent): Cycles' area-light sampling then departs from geometry."""
        c = unit(self.matrix.T)
        gram = c @ c.T
        return bool(np.max(np.abs(gram - np.diag(np.diag(gram)))) > 1e-6)

    @property
    def edges(self):
        """Area light's two world edge vectors (full extents, m): matrix columns 0 and 1 times
        size and size_y (SQUARE/DISK: size), exactly as Cycles' ``extentu``/``extentv``."""
        v = self.size_y if self.shape in ("RECTANGLE", "ELLIPSE") else self.size
        return self.matrix[:, 0] * self.size, self.matrix[:, 1] * v

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
    try:
        matrix = as_finite_array(values.get("matrix_world", np.eye(4)), "matrix_world", (4, 4))
    except ValueError as exc:
        raise ValueError(f"light {values.get('name', 'light')!r}: {exc}") from None
    columns = matrix[:3, :3]
    scale3 = norm(columns.T)
    if np.any(scale3 <= 0.0):
        raise ValueError(f"light {values.get('name', 'light')!r}: matrix_world has a zero scale axis")
    axes = columns / scale3[np.newaxis, :]
    mirrored = np.linalg.det(columns) < 0.0
    if mirrored:  # mirrored object: fold the mirror into the local x axis sign
        axes[:, 0] = -axes[:, 0]
    if not np.allclose(axes.T @ axes, np.eye(3), atol=1e-5):
        # Sheared (rotated child of a non-uniformly scaled parent): ``axes`` becomes an
        # orthonormal frame with z = column 2 (Cycles' light direction) and x in the plane of
        # columns 0 and 2; the exact map is kept in ``matrix`` and used by every model.
        z = axes[:, 2]
        x = unit(columns[:, 0] - (columns[:, 0] @ z) * z) * (-1.0 if mirrored else 1.0)
        axes = np.stack([x, np.cross(z, x), z], axis=1)
    scale = float(scale_length)
    label = f"light {values.get('name', 'light')!r}"
    for key in ("energy", "exposure", "color", "temperature_color", "temperature", "shadow_soft_size",
                "size", "size_y", "spot_size", "spot_blend", "spread", "angle"):
        if values.get(key) is not None and not np.all(np.isfinite(np.asarray(values[key], dtype=np.float64))):
            raise ValueError(f"{label}: {key} is not finite ({values[key]!r})")
    colour = as_finite_array(values.get("color", (1.0, 1.0, 1.0)), "color", (3,))
    if values.get("use_temperature", False):
        tc = values.get("temperature_color")
        tc = blackbody_rgb(float(values.get("temperature", 6500.0))) if tc is None else tc
        colour = colour * as_finite_array(tc, "temperature_color", (3,))
    energy = float(values.get("energy", 10.0)) * 2.0 ** float(values.get("exposure", 0.0))
    if not np.isfinite(energy) or not np.all(np.isfinite(energy * colour)):
        raise ValueError(f"{label}: energy * 2**exposure * color overflows ({energy!r})")
    rgb = energy * colour
    table = values.get("intensity_table")
    if table is not None:
        rgb = rgb * table.rgb_scale
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
        spread=float(values.get("spread", np.pi)), normalize=normalize, matrix=columns, intensity_table=table,
    )


# --- shared pieces -------------------------------------------------------------------------

def _smoothstep(x):
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def spot_attenuation(spec, directions):
    """Cycles' spot cone factor for world directions leaving the light, (..., 3) -> (...).

    z = cosine to the local -Z axis of the direction mapped by the inverse object matrix
    (``itfm``: scale, shear and mirror included), factor = smoothstep((z - cos(spot_size/2)) / ((1 - cos(spot_size/2)) * blend)).
    """
    d = np.asarray(directions, dtype=np.float64)
    local = unit(d @ np.linalg.inv(spec.matrix).T)       # Cycles: itfm, any affine map
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


def _cap_frame(w):
    helper = np.where(np.abs(w[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = unit(np.cross(w, helper))
    return e1, np.cross(w, e1)


def _cap_dirs(w, e1, e2, t, cphi, sphi):
    """Directions at t = 1 - cos(gamma) and azimuth (cos, sin) about w; t (M, A, ...)."""
    sin_g = np.sqrt(np.maximum(t * (2.0 - t), 0.0))[..., None]
    shape = (w.shape[0],) + (1,) * (t.ndim - 1) + (3,)
    ca = cphi.reshape((1, -1) + (1,) * (t.ndim - 2) + (1,))
    sa = sphi.reshape((1, -1) + (1,) * (t.ndim - 2) + (1,))
    return ((1.0 - t)[..., None] * w.reshape(shape)
            + sin_g * (ca * e1.reshape(shape) + sa * e2.reshape(shape)))


def _spot_cap_quadrature(spec, w, s2, normals, order_phi, order_t, grid=24):
    """int over the cap {angle to w < sigma} of spot_att(-omega) max(n.omega, 0) d omega, (M,).

    Piecewise Gauss-Legendre that follows the discontinuities: per azimuth, the polar variable
    t = 1 - cos(gamma) in [0, 1 - cos sigma] is cut where the direction crosses the cone edge
    (z = cos(size/2)), the blend's inner edge (z = cos(size/2) + width) and the receiver's
    horizon (n . omega = 0); each smooth piece gets ``order_t`` nodes. The crossings are found
    numerically (a ``grid``-point scan, then bisection), so an elliptical (non-uniformly scaled or
    sheared) cone needs no closed form. Azimuth: ``order_phi`` Gauss-Legendre nodes on [0, 2 pi].
    """
    inv_t = np.linalg.inv(spec.matrix).T
    cos_half = np.cos(0.5 * spec.spot_size)
    width = (1.0 - cos_half) * spec.spot_blend
    levels = [cos_half] + ([cos_half + width] if 0.0 < width and cos_half + width < 1.0 else [])
    e1, e2 = _cap_frame(w)
    tmax = s2 / (1.0 + np.sqrt(np.maximum(1.0 - s2, 0.0)))                     # 1 - cos sigma
    pg, pw = np.polynomial.legendre.leggauss(order_phi)
    phi = np.pi * (pg + 1.0)
    cphi, sphi = np.cos(phi), np.sin(phi)
    tg, tw = np.polynomial.legendre.leggauss(order_t)

    def funcs(t):  # (M, A, ...) -> (M, A, ..., F): zero at each discontinuity
        d = _cap_dirs(w, e1, e2, t, cphi, sphi)
        z = -unit(-d @ inv_t)[..., 2]
        nn = normals.reshape((normals.shape[0],) + (1,) * (t.ndim - 1) + (3,))
        return np.stack([z - c for c in levels] + [np.sum(d * nn, axis=-1)], axis=-1)

    m, a = w.shape[0], order_phi
    tt = tmax[:, None, None] * np.linspace(0.0, 1.0, grid)[None, None, :] * np.ones((1, a, 1))
    f = funcs(tt)                                                           # (M, A, G, F)
    change = np.signbit(f[:, :, :-1]) != np.signbit(f[:, :, 1:])            # (M, A, G-1, F)
    idx = np.arange(grid - 1)[None, None, :, None]
    first = np.where(change, idx, grid).min(axis=2)                         # (M, A, F)
    last = np.where(change, idx, -1).max(axis=2)
    cuts = []
    for k_idx, valid in ((first, first < grid), (last, last >= 0)):
        k = np.clip(k_idx, 0, grid - 2)
        lo = np.take_along_axis(tt, k, axis=2)                              # (M, A, F)
        hi = np.take_along_axis(tt, k + 1, axis=2)
        f_lo = np.take_along_axis(f, k[:, :, :, None], axis=2)              # (M, A, F, F)
        f_lo = np.diagonal(f_lo, axis1=2, axis2=3)                          # (M, A, F)
        for _ in range(48):
            mid = 0.5 * (lo + hi)
            fm = np.diagonal(funcs(mid), axis1=2, axis2=3)
            same = np.signbit(fm) == np.signbit(f_lo)
            lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
            f_lo = np.where(same, fm, f_lo)
        cuts.append(np.where(valid, 0.5 * (lo + hi), tmax[:, None, None]))
    bounds = np.sort(np.concatenate([np.zeros((m, a, 1)), *cuts, tmax[:, None, None] * np.ones((1, a, 1))],
                                    axis=2), axis=2)                         # (M, A, P+1)
    lo, span = bounds[:, :, :-1], np.diff(bounds, axis=2)                    # (M, A, P)
    t = lo[..., None] + 0.5 * (tg + 1.0) * span[..., None]                   # (M, A, P, K)
    d = _cap_dirs(w, e1, e2, t, cphi, sphi)
    att = spot_attenuation(spec, -d)
    cosr = np.maximum(np.einsum("mapkx,mx->mapk", d, normals), 0.0)
    return np.einsum("mapk,mapk,k,a->m", att * cosr, 0.5 * span[..., None] * np.ones_like(t), tw, np.pi * pw)


def _spot_cap_with_bound(spec, w, s2, normals, chunk=64):
    """(value, relative bound): 256 azimuths against 128 (8 nodes per smooth piece in both)."""
    out = np.empty(w.shape[0])
    rel = np.empty(w.shape[0])
    for start in range(0, w.shape[0], chunk):
        sl = slice(start, start + chunk)
        fine = _spot_cap_quadrature(spec, w[sl], s2[sl], normals[sl], QUADRATURE_SPOT_PHI, QUADRATURE_SPOT_T)
        coarse = _spot_cap_quadrature(spec, w[sl], s2[sl], normals[sl], QUADRATURE_SPOT_PHI // 2,
                                      QUADRATURE_SPOT_T)
        out[sl] = fine
        rel[sl] = np.abs(fine - coarse) / np.where(fine != 0.0, np.abs(fine), 1.0) * (fine != 0.0)
    return out, rel


def _ellipse_polygon(spec, sides=DISK_POLYGON_SIDES):
    u, v = spec.extents
    k = np.sqrt((2 * np.pi / sides) / np.sin(2 * np.pi / sides))  # equal area
    phi = np.arange(sides) * (2 * np.pi / sides)
    return np.stack([0.5 * u * k * np.cos(phi), 0.5 * v * k * np.sin(phi)], axis=1)


def _area_outline_local(spec):
    u, v = spec.extents
    if spec.shape in ("DISK", "ELLIPSE"):
        return _ellipse_polygon(spec)
    return np.array([[-u / 2, -v / 2], [u / 2, -v / 2], [u / 2, v / 2], [-u / 2, v / 2]])


def _outline_world(spec, sides):
    """World vertices of the emitter: position + a edge_u + b edge_v (a, b in [-1/2, 1/2])."""
    eu, ev = spec.edges
    if spec.shape in ("DISK", "ELLIPSE"):
        k = np.sqrt((2 * np.pi / sides) / np.sin(2 * np.pi / sides))  # equal-area polygon
        phi = np.arange(sides) * (2 * np.pi / sides)
        ab = 0.5 * k * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    else:
        ab = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    return spec.position + ab[:, :1] * eu + ab[:, 1:] * ev


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
    return g, np.zeros_like(g)


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
    bound = np.zeros(d.shape)
    if spec.kind == "POINT":
        g = radiance * cap_projected_solid_angle(cos_t, sin_sq)
    else:
        g = np.zeros(d.shape)
        todo = ~inside
        if np.any(todo):
            q, b = _spot_cap_with_bound(spec, w[todo], sin_sq[todo], n[todo])
            g[todo], bound[todo] = radiance * q, b
    # Inside a sphere (soft falloff off) Cycles samples the receiver's hemisphere and applies no
    # spot attenuation (kernel/light/spot.h: attenuation only when d^2 > r^2): E = pi L.
    return np.where(inside, radiance * np.pi, g), bound


def _sun_factor(spec, p, n):
    to_sun = -spec.emission_direction
    cos_t = n @ to_sun
    half = 0.5 * spec.angle
    if half == 0.0:
        g = np.maximum(cos_t, 0.0)
    else:
        sin_sq = np.sin(half) ** 2
        g = cap_projected_solid_angle(cos_t, np.full_like(cos_t, sin_sq)) / (np.pi * sin_sq)
    return g, np.zeros_like(g)


def _area_factor(spec, p, n):
    area = spec.area_m2
    out = np.zeros(p.shape[0])
    bound = np.zeros(p.shape[0])
    if area <= 0.0:
        return out, bound
    normal = spec.emission_direction
    in_front = (p - spec.position) @ normal > 0.0
    radiance = 1.0 / (np.pi * area)
    if not np.any(in_front):
        return out, bound
    pf, nf = p[in_front], n[in_front]
    if spec.is_sheared:
        if spec.spread < np.pi:
            out[in_front] = radiance * _spread_quadrature(spec, pf, nf)
            bound[in_front] = np.nan  # not modelled: see exactness()
        else:
            out[in_front], bound[in_front] = _sheared_area_factor(spec, pf, nf)
    elif spec.spread >= np.pi:
        if spec.shape in ("DISK", "ELLIPSE"):
            # Equal-area 2048-gon; bound: its difference from the 1024-gon, which is larger than
            # the 2048-gon's own error (see DISK_POLYGON_SIDES).
            fine = polygon_projected_solid_angle(_outline_world(spec, DISK_POLYGON_SIDES), pf, nf)
            coarse = polygon_projected_solid_angle(_outline_world(spec, DISK_POLYGON_SIDES // 2), pf, nf)
            out[in_front] = radiance * fine
            bound[in_front] = np.abs(fine - coarse) / np.where(fine > 0.0, fine, 1.0) * (fine > 0.0)
        else:
            out[in_front] = radiance * polygon_projected_solid_angle(_outline_world(spec, 4), pf, nf)
    elif spec.spread == 0.0:
        out[in_front] = _collimated_area_factor(spec, pf, nf)
    else:
        fine = _spread_quadrature(spec, pf, nf)
        coarse = _spread_quadrature(spec, pf, nf, QUADRATURE_RADIAL // 2, QUADRATURE_ANGULAR // 2)
        out[in_front] = radiance * fine
        bound[in_front] = np.abs(fine - coarse) / np.where(fine > 0.0, fine, 1.0) * (fine > 0.0)
    return out, bound


def _sheared_area_nee(spec, p, n, order):
    """Cycles' light-sampling estimate for a sheared area light, per unit rgb_power, (N,).

    Rectangle (``area_light_rect_sample``): Urena's spherical-rectangle sampler is run in the
    frame x = unit(edge_u), y = unit(edge_v), z = x cross y as if it were orthonormal; the sample
    (xu, yv) of the rectangle [xc +- len_u/2] x [yc +- len_v/2] at height z0 (xc = (c - P).x,
    ...) is placed at P + xu x + yv y + z0 z, and the estimate is L cos_r S with S that
    rectangle's solid angle. Its mean is L int_R0 max(n . unit(A w), 0) d omega(w), A = [x y z].
    Ellipse (``ellipse_sample``): uniform points on the true (sheared) ellipse with pdf
    1/(pi/4 len_u len_v) and area-to-solid-angle factor from Cycles' ``dir`` (not the plane's
    normal): mean = L (A_cycles/A_true) int max(cos_r, 0) |cos(dir, -D)| / t^2 dA.
    L = 1/(pi A_cycles), A_cycles = |edge_u| |edge_v| (pi/4).
    """
    eu, ev = spec.edges
    lu, lv = norm(eu), norm(ev)
    x, y = eu / lu, ev / lv
    g, wts = np.polynomial.legendre.leggauss(order)
    radiance = 1.0 / (np.pi * spec.area_m2)
    if spec.shape in ("DISK", "ELLIPSE"):
        # Polar coordinates on the unit disk: r in [0, 1], phi in [0, 2 pi].
        r = 0.5 * (g + 1.0)
        wr = 0.5 * wts * r
        pg, pw = np.polynomial.legendre.leggauss(2 * order)
        phi = np.pi * (pg + 1.0)
        wphi = np.pi * pw
        ab = 0.5 * r[:, None, None] * np.stack([np.cos(phi), np.sin(phi)], -1)[None]      # (R, A, 2)
        q = spec.position + ab[..., :1] * eu + ab[..., 1:] * ev                             # (R, A, 3)
        true_area = norm(np.cross(eu, ev)) * np.pi / 4
        dvec = q[None] - p[:, None, None, :]                                                # (N, R, A, 3)
        t2 = np.sum(dvec * dvec, axis=-1)
        dn = dvec / np.sqrt(t2)[..., None]
        f = (np.maximum(np.einsum("nrak,nk->nra", dn, n), 0.0)
             * np.abs(dn @ spec.emission_direction) / t2)
        # dA = |eu x ev| / 4 r dr dphi: the Jacobian of (r, phi) -> a eu + b ev.
        integral = np.einsum("nra,r,a->n", f, wr, wphi) * norm(np.cross(eu, ev)) / 4.0
        return radiance * (spec.area_m2 / true_area) * integral
    z = np.cross(x, y)
    rel = spec.position - p
    z0 = rel @ z
    zs = np.where(z0 > 0.0, -1.0, 1.0)
    z0 = z0 * zs
    xc, yc = rel @ x, rel @ y
    xs = xc[:, None] + 0.5 * lu * g[None, :]                                                 # (N, K)
    ys = yc[:, None] + 0.5 * lv * g[None, :]
    wv = np.stack([np.broadcast_to(xs[:, :, None], xs.shape + (order,)),
                   np.broadcast_to(ys[:, None, :], xs.shape + (order,)),
                   np.broadcast_to(z0[:, None, None], xs.shape + (order,))], -1)             # (N, K, K, 3)
    r2 = np.sum(wv * wv, axis=-1)
    domega = np.abs(z0)[:, None, None] / r2**1.5 * (0.25 * lu * lv) * wts[None, :, None] * wts[None, None, :]
    world = (wv[..., :1] * x + wv[..., 1:2] * y + wv[..., 2:] * (zs[:, None, None, None] * z))
    cos_r = np.maximum(np.einsum("nabk,nk->nab", unit(world), n), 0.0)
    return radiance * np.sum(cos_r * domega, axis=(1, 2))


#: Sheared area lights: Cycles' MIS mixes its light-sampling estimate (modelled exactly) with BSDF
#: hits on a differently shaped region; measured gap MIS - light sampling: +0.04 % to +0.21 %
#: (tests/bpy/test_cycles_lights_render.py, rectangles and disks, mirrored too). Empirical bound.
SHEARED_MIS_BOUND = 5e-3


def _sheared_area_factor(spec, p, n, chunk=128):
    """(value, relative bound) for a sheared area light: Cycles' light-sampling estimate; the
    bound is its quadrature error (48 vs 24 nodes) plus :data:`SHEARED_MIS_BOUND`."""
    out = np.empty(p.shape[0])
    bound = np.empty(p.shape[0])
    for start in range(0, p.shape[0], chunk):
        sl = slice(start, start + chunk)
        fine = _sheared_area_nee(spec, p[sl], n[sl], 48)
        coarse = _sheared_area_nee(spec, p[sl], n[sl], 24)
        denom = np.where(fine > 0.0, fine, 1.0)
        out[sl] = fine
        bound[sl] = (np.abs(fine - coarse) / denom + SHEARED_MIS_BOUND) * (fine > 0.0)
    return out, bound


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


def _spread_quadrature(spec, p, n, order_r=QUADRATURE_RADIAL, order_phi=QUADRATURE_ANGULAR):
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
    rg, rw = np.polynomial.legendre.leggauss(order_r)
    pg, pw = np.polynomial.legendre.leggauss(order_phi * 2)
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

def _factor_with_bound(spec, p, n):
    if spec.intensity_table is not None:
        return _table_factor(spec, p, n)
    if spec.kind == "SUN":
        return _sun_factor(spec, p, n)
    if spec.kind == "AREA":
        return _area_factor(spec, p, n)
    if spec.radius == 0.0:
        return _delta_factor(spec, p, n)
    return _sphere_or_disk_factor(spec, p, n)


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
        Irradiance; 0 behind area/spot lights, outside cones and below the horizon. A light of
        negative energy gives negative irradiance (Cycles subtracts it).

    Raises
    ------
    ValueError
        NaN/inf inputs, or a receiver exactly at a delta light's position ("zero distance").
    """
    return irradiance_with_bound(spec, points, normals)[0]


def irradiance_with_bound(spec, points, normals):
    """Direct irradiance and a per-receiver relative error bound of the model against Cycles.

    Parameters are those of :func:`irradiance`.

    Returns
    -------
    (E, rel_bound)
        E : numpy.ndarray (..., 3), W/m^2 per channel, identical to :func:`irradiance`.
        rel_bound : numpy.ndarray (...), dimensionless, >= 0: |E - E_cycles| / |E| is expected
        below it (0 where E = 0 exactly). 0 for closed forms (float64 round-off aside).
        Quadratures: |Q_fine - Q_coarse| / |Q_fine| computed per receiver (spot with radius:
        256 against 128 azimuths, 8 nodes per smooth polar piece; spread < 180 deg: 48 x 192 against
        24 x 96; disk/ellipse: the 2048-gon against the 1024-gon). Sheared area lights: quadrature error plus
        :data:`SHEARED_MIS_BOUND` (measured gap between Cycles' light-sampling estimate, which is
        modelled, and its MIS result, which mixes in BSDF hits on a differently shaped region).
        NaN: not modelled (sheared area light with spread < 180 deg).
    """
    p, n, lead = _prepare(points, normals)
    g, bound = _factor_with_bound(spec, p, n)
    return ((g[:, None] * spec.rgb_power[None, :]).reshape(lead + (3,)),
            np.asarray(bound, dtype=np.float64).reshape(lead))


def exactness(spec):
    """(is_exact, model_name, note) describing how :func:`irradiance` computes this light.

    ``is_exact`` is True for closed forms (and the disk's 2048-gon, rel. error below 1e-8); the
    per-receiver error of every model is :func:`irradiance_with_bound`'s.
    """
    sign = ("; negative energy: Cycles subtracts this light, E < 0"
            if np.any(spec.rgb_power < 0.0) else "")
    if spec.intensity_table is not None:
        return True, "photometric point", (f"{spec.intensity_table.label}: I(theta, C) cos / r^2 with Cycles' IES "
                                           "interpolation, exact" + sign)
    if spec.kind == "SUN":
        if spec.angle == 0.0:
            return True, "directional", "E = energy cos(theta), exact" + sign
        return True, "uniform cap", "Snyder 1996 cap under the horizon, exact" + sign
    if spec.kind == "AREA":
        if spec.is_sheared:
            if spec.spread < np.pi:
                return False, "unmodelled", ("sheared area light with spread < 180 deg: Cycles' sampling "
                                             "is not modelled (bound NaN); render it" + sign)
            return False, "sheared quadrature", (
                "sheared transform: Cycles' light sampling (modelled, Gauss-Legendre 48^2) and its BSDF-hit "
                "geometry disagree, and MIS mixes them; see irradiance_with_bound for the per-point bound" + sign)
        if spec.spread >= np.pi:
            if spec.shape in ("DISK", "ELLIPSE"):
                return True, "Lambert polygon", (f"equal-area {DISK_POLYGON_SIDES}-gon, rel. error < 1e-8 except within "
                                                 "~1 % of the radius from the rim (2e-5 there); per-point bound (vs the 1024-gon) from irradiance_with_bound"
                                                 + sign)
            return True, "Lambert polygon", "closed form with horizon clipping, exact" + sign
        if spec.spread == 0.0:
            return True, "collimated", "spread 0: emission only along the normal" + sign
        return False, "quadrature", (f"Gauss-Legendre {QUADRATURE_RADIAL}x{2 * QUADRATURE_ANGULAR} in polar "
                                     "coordinates about the foot point; per-point bound from irradiance_with_bound"
                                     + sign)
    if spec.radius == 0.0:
        return True, "point" if spec.kind == "POINT" else "spot", "inverse square law, exact" + sign
    model = "disk facing receiver" if spec.soft_falloff else "Lambertian sphere"
    if spec.kind == "POINT":
        return True, model, "closed-form cap projected solid angle, exact" + sign
    return False, "quadrature", (f"{model} with per-direction spot attenuation, piecewise Gauss-Legendre "
                                 f"{QUADRATURE_SPOT_PHI} azimuths x {QUADRATURE_SPOT_T} per smooth piece (cut at the "
                                 "cone edge, blend edge and horizon); per-point bound from irradiance_with_bound"
                                 + sign)


def radiant_intensity(spec, direction):
    """Far-field radiant intensity, W/sr per channel, for world directions leaving the light.

    Point/sphere/disk: P/(4 pi); spot: times the cone factor; area: L A cos(theta) times the
    spread factor (0 behind); sun: ValueError (no position, inverse square does not apply).
    """
    d = unit(as_finite_array(direction, "direction"))
    if spec.intensity_table is not None:
        return _table_intensity(spec, d)[..., None] * spec.rgb_power
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


# --- photometric (IES) point lights ----------------------------------------------------------

def _check_table_light(spec):
    if spec.kind != "POINT" or spec.radius != 0.0:
        raise ValueError("an intensity table is modelled for a point light of radius 0 only "
                         f"(got {spec.kind.lower()} of radius {spec.radius:g} m)")
    if not isinstance(spec.intensity_table, IntensityTable):
        raise ValueError("intensity_table must be an IntensityTable")


def _table_intensity(spec, directions):
    """Table value (W/sr per W) for unit world directions leaving the light, (..., 3) -> (...)."""
    return spec.intensity_table.lookup(np.asarray(directions, dtype=np.float64) @ spec.matrix)


def _table_factor(spec, p, n):
    # Delta source: E = I(-w) cos / r^2, w = unit vector from the receiver to the light.
    to_light = spec.position - p
    r = norm(to_light)
    if np.any(r == 0.0):
        raise ValueError("zero distance to light: a photometric point light has infinite irradiance at its position")
    w = to_light / r[:, None]
    cos_r = np.maximum(np.sum(w * n, axis=1), 0.0)
    g = _table_intensity(spec, -w) * cos_r / r / r
    return g, np.zeros_like(g)

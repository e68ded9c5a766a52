"""The parameters every Blender light shares, in SI, and their construction from Blender's values.

:class:`CyclesLight` is the common base of the analytic kinds (:mod:`.point`, :mod:`.spot`,
:mod:`.sun`, :mod:`.area`, :mod:`.photometric`): one frozen record of what Cycles reads from a
``bpy.types.Light`` and its object, plus the :class:`~.base.Emitter` interface. Constructing
``CyclesLight(kind=...)`` returns the emitter of that kind, so ``dataclasses.replace`` and every
caller that builds one from values get the right class.

Units: positions in metres; ``rgb_power`` W per channel (sun: W/m^2 per channel on a surface facing
it); angles in radians. What each field means to Cycles is in the module of the kind that uses it;
the sources read are ``intern/cycles/scene/light.cpp`` and ``kernel/light/*.h`` (Blender 5.0).
"""

from dataclasses import dataclass, field

import numpy as np

from ..scene.geometry import norm, unit
from ..units import as_finite_array, check_nonnegative, frozen_array, scene_to_metres
from ..photometry.efficacy import blackbody_rgb
from .base import Emitter, RayVisibility, SourceId, prepare_receivers

__all__ = ["CyclesLight", "KINDS", "SHAPES", "from_blender_values", "light_class"]

KINDS = ("POINT", "SPOT", "SUN", "AREA")
SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")

_frozen = frozen_array  # short local name

#: (kind, has an intensity table) -> the emitter class; filled by each kind's module.
_KIND_CLASSES = {}


def _class_for(kind, table):
    if table is not None:
        return _KIND_CLASSES[("POINT", True)]
    return _KIND_CLASSES.get((kind, False), _KIND_CLASSES[("POINT", False)])  # a bad kind fails in __post_init__


def light_class(light):
    """The emitter class that answers for ``light``: its own class, or for a plain record of a light's
    values (``kind``, ``radius``, ... as the fields below) the class of its kind, whose answers read only
    those values (``light_class(r).describe(r)``)."""
    if isinstance(light, CyclesLight):
        return type(light)
    return _class_for(light.kind, getattr(light, "intensity_table", None))


@dataclass(frozen=True)
class CyclesLight(Emitter):
    """A Blender light in SI units (see each kind's module for the meaning Cycles gives each field).

    Attributes
    ----------
    name : str, for messages only (identity is ``source_id``)
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
    matrix : (3, 3) or None
        The object's full linear map (``matrix_world[:3, :3]``, dimensionless, may be sheared or
        mirrored). None means ``axes @ diag(scale)``. Cycles takes every light direction from it:
        emission/sun direction -normalize(column 2), spot cone via its inverse, area edges
        column 0 * size and column 1 * size_y.
    intensity_table : a light's :class:`.photometric.Photometry` (``Photometry.light_table``) or None
        A photometric point light (POINT, radius 0): its intensity table replaces P/(4 pi).
    source_id : :class:`.base.SourceId` or None (built outside a capture)
    visibility : :class:`.base.RayVisibility`
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
    intensity_table: object = None
    source_id: SourceId = None
    visibility: RayVisibility = RayVisibility.ALL

    def __new__(cls, *args, **kwargs):
        # The kind decides the class; no arguments (unpickling) keeps the class being restored.
        if args or kwargs or cls is CyclesLight:
            kind = kwargs.get("kind", args[1] if len(args) > 1 else "POINT")
            table = kwargs.get("intensity_table", args[17] if len(args) > 17 else None)
            cls = _class_for(kind, table)
        return object.__new__(cls)

    def __init_subclass__(cls, kind_key=None, **kwargs):
        super().__init_subclass__(**kwargs)
        if kind_key is not None:
            _KIND_CLASSES[kind_key] = cls

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
        if self.source_id is not None and not isinstance(self.source_id, SourceId):
            object.__setattr__(self, "source_id", SourceId(*self.source_id))
        object.__setattr__(self, "visibility", RayVisibility(self.visibility))
        self._check_kind()

    def _check_kind(self):
        """Kind-specific checks (ValueError); the photometric kind checks its table."""
        if self.intensity_table is not None:
            raise ValueError("intensity_table needs a photometric point light")

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
        """Emitting area, m^2: area light (ellipse pi/4 u v), sphere 4 pi R^2; sun/delta: nan.
        The one home of a light's area (photometric power, glare, reports read it here)."""
        if self.kind == "AREA":
            u, v = self.extents
            return u * v * (np.pi / 4 if self.shape in ("DISK", "ELLIPSE") else 1.0)
        if self.radius > 0.0 and self.kind in ("POINT", "SPOT"):
            return 4.0 * np.pi * self.radius**2
        return float("nan")

    # What callers ask a light (issue 30: each kind answers in its own class, no caller asks its kind) ----
    @property
    def size_m(self):
        """Largest dimension of the luminous area, m: an area light's longer side or diameter, a sphere's
        2R; 0 for a delta light and a sun."""
        return 0.0

    def describe(self):
        """The light in a designer's words: 'area light 0.6 x 0.6 m', 'point light, radius 0.1 m, soft falloff'."""
        return f"{self.kind.lower()} light"

    def luminous_shape(self):
        """What emits, as a shape a file format can write (issue 30: an exporter asks this, never the kind):
        "distant" (a sun: a disc of ``angle`` rad seen along ``emission_direction``), "sphere" (point and spot:
        ``radius`` m at ``position``; a spot also has a cone of ``spot_size`` rad about
        ``emission_direction``), "round" (a disk or ellipse area light) or "polygon" (a square or rectangle
        area light: ``edges`` about ``position``)."""
        if self.kind == "SUN":
            return "distant"
        if self.kind in ("POINT", "SPOT"):
            return "sphere"
        if self.kind == "AREA":
            return "round" if self.shape in ("DISK", "ELLIPSE") else "polygon"
        return self.kind.lower()

    @property
    def has_cone(self):
        """True for a spot light (its emission is cut to a cone of ``spot_size`` rad)."""
        return self.kind == "SPOT"

    @property
    def interior_radius_m(self):
        """Radius, m, of the region around the centre where a receiver is inside the emitter (a sphere
        light without soft falloff); 0 where there is none."""
        return 0.0

    @property
    def may_render_small(self):
        """True for a source so small in the render (point, spot, sun, of any radius or angle) that its
        images in sharp mirrors and through glass are caustics a path tracer may miss; False for an area
        light."""
        return True

    @property
    def render_reason(self):
        """Why Cycles' answer for this light is its own, so it must be rendered although a closed form
        exists ('' when the closed form stands)."""
        return ""

    def towards_centre(self, p):
        """Vector from ``p`` (3,) m to the light's centre, m (a sun: the unit vector towards it)."""
        return np.asarray(self.position, float) - p

    def angular_radius(self, point_m, facing):
        """Largest angle (rad) between ``facing`` and a direction from ``point_m`` to a point of the
        source (0 for a delta light)."""
        return 0.0

    def occlusion_bases(self, points, scene_reach, sides):
        """Per receiver (N, 3) m: ('segment', ends (N, 3)) or ('polytope', bases (N, K, 3), ``sides``-gons
        for round parts) such that the pyramid from the receiver over its base (or the segment to its end)
        holds every segment from the receiver to the light; ``inside`` (N,) marks receivers with no such
        region (inside a spherical light). ``scene_reach``: m, beyond every surface (a sun's far end)."""
        n = len(points)
        return "segment", np.broadcast_to(np.asarray(self.position, float), (n, 3)), np.zeros(n, bool)

    def beyond_plane(self, normal, height, side, tol):
        """True when the light lies wholly on the side of the plane ``normal . x = height`` opposite to
        ``side`` (+1 / -1), by more than ``tol`` m."""
        return all(side * (normal @ x - height) + self._reach < -tol for x in self._extreme_points())

    def _extreme_points(self):
        return [self.position]

    def extent(self):
        if not self.has_position:
            return None
        return np.asarray(self._extreme_points(), float).reshape(-1, 3), float(self._reach)

    _reach = 0.0  # m, how far the emitter extends around its extreme points (a sphere's radius)

    def mirror_cone(self, p, normal, plane_point, tol):
        """The cone of directions in which the light's mirror image in the plane through ``plane_point``
        with unit ``normal`` (towards ``p``) is seen from ``p``: (unit axis r, half-angle rad, c = the
        cosine of r to the plane's normal, sign towards the plane), 'far' when the light lights only the
        plane's far side, None when nothing is proven (the light straddles the plane, an area light)."""
        return None

    def mirror_image_solid_angle(self, at, path_length):
        """Solid angle (sr) of the light's mirror image seen over a path of ``path_length`` m that meets
        the light from the mirror point ``at`` (m); 0 for a delta light (its highlight is the lobe alone)."""
        return 0.0

    def luminous_area_seen(self, eye, efficacy, weights, sides):
        """What an eye at ``eye`` (3,) m sees of the light's luminous area, for glare (CIE 117):
        ((luminance cd/m², solid angle sr, centre (3,) m, convex outline (K, 3) m holding it, round parts as
        ``sides``-gons), None), or (None, reason). ``efficacy`` lm/W and RGB -> Y ``weights`` make the
        photometric values."""
        to_eye = np.asarray(eye, float) - np.asarray(self.position, float)
        dist = float(np.linalg.norm(to_eye))
        if dist == 0:
            return None, "the observer is inside the light"
        return self._seen_from(to_eye / dist, dist, np.asarray(eye, float), efficacy, weights, sides)

    def _seen_from(self, d, dist, eye, efficacy, weights, sides):
        return None, f"a {self.kind.lower()} light without a luminous area: its luminance is not defined"

    def near_field_words(self):
        """Why this light departs from I/d² close to it, in words."""
        return f"the source ({light_class(self).describe(self)}) is not a point at these distances"

    def inverse_square_causes(self, d):
        """Causes ('light: ...') in the light itself of a departure from I/d² over distances ``d`` (m,
        ascending) where its closed form departs."""
        return []

    def cosine_causes(self):
        """Causes ('light: ...') in the light itself of a departure from cos θ beyond its extent."""
        return []

    # The interface, in terms of each kind's per-unit-power models ----------------------------
    def _unit_irradiance(self, p, n):
        """(g (N,), relative bound (N,)): irradiance per unit ``rgb_power`` at receivers p (N, 3) m
        with unit normals n (N, 3); bound NaN where not modelled. Each kind implements it."""
        raise NotImplementedError

    def _unit_intensity(self, d):
        """Far-field intensity per unit ``rgb_power`` (...,) W/sr per W towards unit directions d."""
        raise ValueError(f"a {self.kind.lower()} light has no position: intensity does not apply")

    def exactness(self):
        """(is_exact, model_name, note): how :meth:`irradiance_at` computes this light."""
        raise NotImplementedError

    def _sign_note(self):
        return "; negative energy: Cycles subtracts this light, E < 0" if np.any(self.rgb_power < 0.0) else ""

    def relative_irradiance(self, points, normals):
        """(E (..., 3) W/m^2 per channel, relative bound (...)): the model and a per-receiver bound
        on |E - E_cycles| / |E| (0 for closed forms; NaN where not modelled)."""
        p, n, lead = prepare_receivers(points, normals)
        g, bound = self._unit_irradiance(p, n)
        return ((g[:, None] * self.rgb_power[None, :]).reshape(lead + (3,)),
                np.asarray(bound, dtype=np.float64).reshape(lead))

    def irradiance_at(self, points, normals):
        e, rel = self.relative_irradiance(points, normals)
        if np.any(np.isnan(rel)):
            return e, None
        return e, rel[..., None] * np.abs(e)

    def intensity_towards(self, directions):
        d = unit(as_finite_array(directions, "direction"))
        return self._unit_intensity(d)[..., None] * self.rgb_power


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


def from_blender_values(values, scale_length=1.0, *, source_id=None, visibility=RayVisibility.ALL):
    """Build the emitter (:class:`CyclesLight` of its kind) in SI from plain values read from a ``bpy.types.Light`` and object.

    Parameters
    ----------
    values : dict
        Keys named as Blender 5 Light RNA: ``type``, ``energy``, ``color``, ``use_temperature``,
        ``temperature``, ``temperature_color`` (optional: Blender's own value; computed with
        :func:`..photometry.blackbody_rgb` otherwise), ``exposure``, ``normalize``,
        ``use_soft_falloff``, ``shadow_soft_size``, ``spot_size``, ``spot_blend``, ``shape``,
        ``size``, ``size_y``, ``spread``, ``angle``; plus ``matrix_world`` (4x4 nested list, rows)
        and optionally ``name``.
    scale_length : float
        Metres per scene unit.
    source_id : SourceId or None; visibility : RayVisibility
        Identity and ray visibility, given by the capture layer.

    Notes
    -----
    Colour: with ``use_temperature`` Cycles uses ``color * temperature_color`` (measured, see the
    bpy tests). Power per channel = energy * 2**exposure * colour, times Cycles' ``Light::area``
    (scene units) when normalize is off. Cycles renders in scene units; to keep every quantity
    consistent with the render (E_SI = E_render / scale_length^2), the sun's irradiance is divided
    by scale_length^2 too.
    """
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
    return CyclesLight(
        name=str(values.get("name", "light")), kind=kind,
        position=scene_to_metres(matrix[:3, 3], scale), axes=axes, scale=scale3, rgb_power=rgb,
        radius=float(scene_to_metres(values.get("shadow_soft_size", 0.0), scale)),
        soft_falloff=bool(values.get("use_soft_falloff", True)),
        spot_size=float(values.get("spot_size", np.pi / 4)), spot_blend=float(values.get("spot_blend", 0.15)),
        angle=float(values.get("angle", 0.0)), shape=str(values.get("shape", "SQUARE")),
        size=float(scene_to_metres(values.get("size", 1.0), scale)),
        size_y=float(scene_to_metres(values.get("size_y", 1.0), scale)),
        spread=float(values.get("spread", np.pi)), normalize=normalize, matrix=columns, intensity_table=table,
        source_id=source_id, visibility=visibility,
    )



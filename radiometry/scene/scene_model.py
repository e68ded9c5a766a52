"""What the meter sees, as plain data, and which part of each reading a closed form gives exactly.

A ``SceneModel`` is the scene exactly as Cycles renders it (filled by ``measure.capture.scene_capture`` from
the render depsgraph: render visibility, instances, modifiers, ray-visibility and shadow flags,
transforms): its lights (an emitter where a closed form covers them) and its geometry as a
triangle soup in metres. ``plan_direct`` decides, for every light and every receiver, how its
direct light is obtained, with the reason, so that tests can inspect the decisions:

``EXACT``      closed form, and nothing can block it (proved: see :mod:`.visibility`);
``ZERO``       exactly nothing: the light is a portal, invisible to diffuse rays, below the
               receiver's horizon / behind / outside its cone, or blocked by an opaque triangle;
``BOUNDED``    closed-form quadrature with a stated error bound, nothing can block it;
``RENDER``     no closed form, or an occluder may cut part of the light: Cycles must render it.

Light that reaches the receiver by reflection (``indirect``) is never a closed form here; it is
possible only when some render-visible surface lies above the receiver's horizon, the world emits,
or a surface emits.

This module never imports bpy.
"""

from dataclasses import dataclass, field

import numpy as np

from . import sealed
from . import source_visibility
from . import visibility

EXACT, ZERO, BOUNDED, RENDER = "exact", "zero", "bounded", "render"

#: Sides of the polygon circumscribing a round source's silhouette in the clearance proof.
ROUND_SIDES = 16


@dataclass
class ModelLight:
    """The scene's slot for one light instance: its emitter (``spec``, a :mod:`.emitters` kind built once
    by the capture layer; None when no closed form covers it, ``uncovered`` says why: only a render
    measures it) and what the planner needs beside it (portal, shadow and diffuse visibility, notes).
    ``source_id`` is the instance's stable identity (:class:`.emitters.SourceId`), ``name`` its label."""

    name: str
    spec: object = None
    uncovered: str = None
    casts_shadow: bool = True      # Light.use_shadow: False lets its light through every surface
    reaches_diffuse: bool = True   # Object.visible_diffuse: False removes it from diffuse surfaces
    portal: bool = False           # light.cycles.is_portal: guides world sampling, emits nothing
    notes: tuple = ()
    source: str = ""               # the light OBJECT (shared by all its instances)
    source_id: tuple = None        # emitters.SourceId: object session uid, library, instance id, part

    @property
    def emitter(self):
        """The light's emitter (:class:`.emitters.Emitter`), or None when only a render measures it."""
        return self.spec


@dataclass
class SceneGeometry:
    """Render-visible surfaces as triangles (T, 3, 3) in metres, scene coordinates times scale."""

    triangles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3, 3)))
    object_index: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    object_names: list = field(default_factory=list)
    #: per object: (session uid, library) of the Blender object behind it (the object part of a
    #: ``emitters.SourceId``; the host finds objects by it, never by name); empty for hand-built geometry
    object_ids: list = field(default_factory=list)
    casts_shadow: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))  # per object
    opaque: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))        # per triangle
    reflects: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))      # per object
    emissive: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))      # per triangle
    #: per object: every kind of ray stops at it (diffuse, glossy, transmission, shadow and volume visibility
    #: on, not a holdout, not volume-only): with opaque triangles it may close a sealed shell (``sealed``);
    #: empty (hand-built geometry): nothing is known to seal
    seals: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    #: (T,) per triangle: its material has only shader nodes through which no light passes (no alpha,
    #: transmission, subsurface, portal, ...: ``measure.capture.shader_kinds.seals``); None: not known
    sealing_material: np.ndarray = None
    unmodelled: list = field(default_factory=list)  # render-visible geometry not triangulated
    #: (T,) per triangle: the object index of the thin pane it belongs to, or -1 (issue 18).
    pane_of: np.ndarray = None
    #: (T,) per triangle: its material slot index in its object (``Object.material_slots``), or None when
    #: the geometry was built by hand (the Radiance export maps each slot's material).
    material_slot: np.ndarray = None
    #: (O,) per object: its transform mirrors (a negative determinant): Cycles' front side of its faces is then the
    #: reverse of the captured triangles' winding (it flips them back); None: not known (hand-built geometry)
    mirrored: np.ndarray = None
    #: optional (tri_min, tri_max) already computed with :func:`triangle_bounds` (a capture keeps them per
    #: object, so a partial capture does not compute them again); not kept after construction
    tri_bounds: tuple = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        self.triangles = np.asarray(self.triangles, float).reshape(-1, 3, 3)
        self.object_index = np.asarray(self.object_index, int)
        if self.pane_of is None or len(self.pane_of) != len(self.triangles):
            self.pane_of = np.full(len(self.triangles), -1, int)
        if self.material_slot is not None and len(self.material_slot) != len(self.triangles):
            self.material_slot = None
        given = self.tri_bounds
        if given is not None and all(np.shape(x) == (len(self.triangles), 3) for x in given):
            self.tri_min, self.tri_max = (np.asarray(x, float) for x in given)
        else:
            self.tri_min, self.tri_max = triangle_bounds(self.triangles)
        self.tri_bounds = None
        self._grid = None
        self._objects = None

    @property
    def grid(self):
        """Index of the triangles' boxes (``visibility.LazyTriangleGrid``: a scan for the first few
        queries, then a uniform grid built once per geometry; the sensor placement and the proofs share
        it, and a capture that keeps the geometry keeps it too)."""
        if self._grid is None:
            self._grid = visibility.LazyTriangleGrid(self.tri_min, self.tri_max)
        return self._grid

    def object_ranges(self):
        """Per object k: (first, end) of its triangles when each object's triangles are contiguous and in
        object order (as every capture stores them), else None."""
        index = self.object_index
        if len(index) > 1 and np.any(index[1:] < index[:-1]):
            return None
        ks = np.arange(len(self.object_names))
        return np.c_[np.searchsorted(index, ks, "left"), np.searchsorted(index, ks, "right")]

    def object_vertices(self):
        """Per object: (vertices (V, 3), bounding-box corners (8, 3)), largest object first (built once per
        geometry; a capture's contiguous objects are views, not copies)."""
        if self._objects is None:
            ranges = self.object_ranges()
            out = []
            for k in range(len(self.object_names)):
                if ranges is not None:
                    part = slice(*ranges[k])
                else:
                    part = np.flatnonzero(self.object_index == k)
                tris = self.triangles[part]
                if not len(tris):
                    continue
                verts = tris.reshape(-1, 3)
                lo, hi = visibility.column_min(self.tri_min[part]), visibility.column_max(self.tri_max[part])
                corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
                emitting = tris[self.emissive[part]] if len(self.emissive) else np.zeros((0, 3, 3))
                out.append((k, verts, corners, emitting))
            self._objects = sorted(out, key=lambda item: -len(item[1]))
        return self._objects

    @property
    def count(self):
        return len(self.triangles)

    def shadow_triangles(self):
        mask = np.asarray(self.casts_shadow, bool)[self.object_index] if self.count else np.zeros(0, bool)
        return mask

    def sealing_triangles(self):
        """(T,) bool: opaque triangles of objects that stop every kind of ray (``seals``), of a material that lets
        no light through (``sealing_material``)."""
        if not self.count or len(self.seals) != len(self.object_names) or self.sealing_material is None \
                or len(self.sealing_material) != self.count:
            return np.zeros(self.count, bool)
        return (np.asarray(self.seals, bool)[self.object_index] & np.asarray(self.opaque, bool)
                & np.asarray(self.sealing_material, bool))

    def reflecting_triangles(self):
        return np.asarray(self.reflects, bool)[self.object_index] if self.count else np.zeros(0, bool)

    def bounds(self):
        if not self.count:
            return np.zeros(3), np.zeros(3)
        return visibility.column_min(self.tri_min), visibility.column_max(self.tri_max)


def triangle_bounds(triangles):
    """(T, 3) per-triangle minimum and maximum corners of ``triangles`` (T, 3, 3), elementwise over the
    three vertices (coordinate by coordinate: 2x faster than over whole vertex rows at 130k triangles)."""
    flat = triangles.reshape(len(triangles), 9)
    lo, hi = np.empty((len(triangles), 3)), np.empty((len(triangles), 3))
    for k in range(3):
        np.minimum(np.minimum(flat[:, k], flat[:, 3 + k]), flat[:, 6 + k], out=lo[:, k])
        np.maximum(np.maximum(flat[:, k], flat[:, 3 + k]), flat[:, 6 + k], out=hi[:, k])
    return lo, hi


@dataclass
class SceneModel:
    lights: list
    geometry: SceneGeometry
    world_emits: bool = False
    needs: dict = field(default_factory=dict)
    scale_length: float = 1.0
    notes: list = field(default_factory=list)
    world: object = None  # radiometry.skies.environment.WorldLight when the world emits (modelled or not)
    #: Participating media (issue 18): (name, box min (3,), box max (3,)) in metres per volume object
    #: (a mesh with a Volume shader, an OpenVDB volume); ``world_volume`` when the world has one.
    volumes: list = field(default_factory=list)
    world_volume: bool = False
    #: Recognised thin glass panes (``radiometry.scene.thin_glass.Pane``) by object index (issue 18).
    panes: dict = field(default_factory=dict)
    #: Transmissive objects that are not thin panes (name, reason): rendered as they are (issue 18).
    refractors: list = field(default_factory=list)
    #: Surfaces with an Emission shader as emitters (:class:`.emitters.EmissiveMesh`, rendered only).
    emissive_meshes: list = field(default_factory=list)
    #: What analyses derive from the captured model alone (e.g. its closed shell and openings), kept by key:
    #: a captured model is not changed afterwards, so one daylight request finds them once, not per step.
    derived: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def emissive_surfaces(self):
        return bool(self.needs.get("emissive_surfaces", False)) or bool(self.emissive_meshes)

    @property
    def emitters(self):
        """Every emitter of the scene: the lights' (those a closed form covers), the emissive meshes',
        and the world when it emits."""
        out = [light.spec for light in self.lights if light.spec is not None]
        out += list(self.emissive_meshes)
        if self.world_emits and self.world is not None:
            out.append(self.world)
        return out


@dataclass
class DirectPlan:
    """Per light (L) and receiver (N): ``status`` (L, N) of EXACT/ZERO/BOUNDED/RENDER and ``reason``;
    per receiver: ``indirect`` (N,) bool and ``indirect_reason`` (N,) str."""

    status: np.ndarray
    reason: np.ndarray
    indirect: np.ndarray
    indirect_reason: np.ndarray
    world_status: np.ndarray = None  # (N,) EXACT/ZERO/BOUNDED/RENDER of the world's light (world_statuses)
    world_reason: np.ndarray = None
    #: (L, N, 3) factor of the thin panes crossed on the way to each light (1 without glass), and
    #: (L, N) its relative bound over the light's extent (issue 18).
    transmittance: np.ndarray = None
    glass_bound: np.ndarray = None
    interpane: np.ndarray = None  # (L, N) share of T from light bouncing between panes (not rendered)

    def exact_points(self):
        """(N,) bool: every contribution is a closed form with verified conditions, no indirect light."""
        exact = np.all(np.isin(self.status, (EXACT, ZERO)), axis=0) & ~self.indirect
        if self.world_status is not None:
            exact &= np.isin(self.world_status, (EXACT, ZERO))
        return exact

    def rendered_lights(self, k):
        return np.flatnonzero(self.status[:, k] == RENDER)


def _emitter_exactness(emitter):
    return emitter.exactness()


def length_tolerance(points):
    """Absolute tolerance (m) for the proofs: a few float32 steps of the coordinates, >= 1 nm."""
    return 4e-7 * max(1.0, float(np.max(np.abs(points)))) if len(points) else 1e-9


def receiver_offset(points, unit_length=1.0):
    """Scale-aware offset (same units as ``points``) along the normal at which a sensor sits.

    2e-6 of the larger of the coordinates' magnitude and one metre (``unit_length`` = scene units
    per metre): about 17 float32 steps of the coordinates, so a sensor placed on a surface never
    meets that surface in Cycles' float32 geometry, yet 2 um at the origin changes E by ~2e-6 of
    (offset / distance to the light).
    """
    p = np.asarray(points, float)
    return 2e-6 * np.maximum(np.max(np.abs(p), axis=-1), unit_length)


def occlusion_statuses(spec, points, normals, geometry, tol, scene_reach, panes=None):
    """(status (N,), blocker object name or None (N,)) of the light as seen from every receiver;
    with ``panes`` (thin panes by object index) also the panes crossed whole on the way, per
    receiver a list of (object index, cos at the light's centre, cos_min, cos_max).

    Triangles entirely below a receiver's horizon are ignored (they cannot cut light arriving
    from above it), as are objects that cast no shadow. Candidates come from the triangle grid;
    the exact tests run on all (receiver, triangle) pairs at once.
    """
    points = np.asarray(points, float)
    normals = np.asarray(normals, float)
    n = len(points)
    status = np.full(n, visibility.CLEAR, dtype=object)
    blocker = np.full(n, None, dtype=object)
    crossings = [[] for _ in range(n)]
    if not geometry.count or not n:
        return (status, blocker, crossings) if panes is not None else (status, blocker)
    kind, ends, inside = spec.occlusion_bases(points, scene_reach, ROUND_SIDES)
    status[inside] = visibility.PARTIAL
    shadow = geometry.shadow_triangles()
    pane_tri = (geometry.pane_of >= 0) & np.isin(geometry.pane_of, list(panes or ()))
    pair_point, pair_tri = [], []
    for k in np.flatnonzero(~inside):
        p = points[k]
        if kind == "segment":
            box_min, box_max = np.minimum(p, ends[k]), np.maximum(p, ends[k])
        else:
            box_min = np.minimum(p, ends[k].min(axis=0))
            box_max = np.maximum(p, ends[k].max(axis=0))
        idx = geometry.grid.query(box_min, box_max, tol)
        if idx.size:
            idx = idx[shadow[idx]]
        if idx.size:
            idx = idx[~visibility.below_plane(geometry.triangles[idx], p, normals[k], tol)]
        if idx.size and pane_tri[idx].any():
            # Thin panes the segments provably cross whole are a factor T, not an occluder (issue 18).
            keep = np.ones(idx.size, bool)
            for obj in np.unique(geometry.pane_of[idx[pane_tri[idx]]]):
                crossed = _pane_crossing(panes[obj].geometry, spec, kind, p, ends[k], tol)
                if crossed is not None:
                    crossings[k].append((int(obj),) + crossed)
                    keep &= geometry.pane_of[idx] != obj
            idx = idx[keep]
        if idx.size:
            pair_point.append(np.full(idx.size, k))
            pair_tri.append(idx)
    if not pair_point:
        return (status, blocker, crossings) if panes is not None else (status, blocker)
    pk, pt = np.concatenate(pair_point), np.concatenate(pair_tri)
    tris = geometry.triangles[pt]
    names = geometry.object_names
    if kind == "polytope":
        verts, face_normals, edges = visibility.pyramids(points[pk], ends[pk])
        meets = visibility.triangles_meet_polytopes(tris, verts, face_normals, edges, tol)
        for k in np.unique(pk[meets]):
            status[k] = visibility.PARTIAL
            hit = pt[meets & (pk == k)]
            blocker[k] = names[geometry.object_index[hit[0]]]
            # An opaque coplanar patch (a baffle, a wall) across the whole pyramid hides the light.
            opaque = hit[np.asarray(geometry.opaque, bool)[hit]]
            hiding = source_visibility.hidden_behind(points[k], ends[k], geometry.triangles[opaque], tol) \
                if opaque.size else None
            if hiding is not None:
                status[k] = visibility.BLOCKED
                blocker[k] = names[geometry.object_index[opaque[hiding[0]]]]
        return (status, blocker, crossings) if panes is not None else (status, blocker)
    for k in np.unique(pk):
        sel = pk == k
        state, j = visibility.segment_status(points[k], ends[k], tris[sel], geometry.opaque[pt[sel]], tol)
        status[k] = state
        blocker[k] = names[geometry.object_index[pt[sel][j]]] if j >= 0 else None
    return (status, blocker, crossings) if panes is not None else (status, blocker)


def _pane_crossing(geom, spec, kind, p, end, tol):
    """(cos at the light's centre, cos_min, cos_max) when every segment from ``p`` to the light
    crosses the pane whole (``thin_glass`` proofs), else None."""
    from . import thin_glass

    if kind == "segment":
        ok, c = thin_glass.segment_crossing(geom, p, end, tol)
        return (c, c, c) if ok else None
    ok, cmin, cmax = thin_glass.pyramid_crossing(geom, p, end, tol)
    if not ok:
        return None
    centre = spec.towards_centre(p)
    c = float(abs(centre @ geom.normal) / np.linalg.norm(centre))
    return c, min(cmin, c), max(cmax, c)


def glass_factor(model, crossings):
    """(T (3,), relative bound, words) of the panes crossed on the way to a light: the adding
    formula over the panes at the light's centre direction; the bound is the largest relative change
    of T over the directions to the light (T is monotone in the angle)."""
    from . import thin_glass

    if not crossings:
        return np.ones(3), 0.0, ""
    layers, lo_layers, hi_layers, words = [], [], [], []
    for obj, c, cmin, cmax in crossings:
        pane = model.panes[obj]
        for cos, out in ((c, layers), (cmin, lo_layers), (cmax, hi_layers)):
            T, R, _A = pane.optics(cos)
            out.append((T, R))
        words.append(f"{pane.name!r} ({pane.model}) at {np.degrees(np.arccos(min(c, 1.0))):.1f} deg")
    T, _R = thin_glass.stack(layers)
    spread = max(np.max(np.abs(thin_glass.stack(x)[0] - T)) for x in (lo_layers, hi_layers))
    bound = float(spread / max(float(np.max(T)), 1e-300))
    return T, bound, "; ".join(words)


def interpane_fraction(model, crossings):
    """Relative share of T that light bouncing between two or more panes carries (1 - prod T_i / T):
    a render of thin panes cannot find it (a specular chain to a small light)."""
    from . import thin_glass

    if len(crossings) < 2:
        return 0.0
    layers = [model.panes[obj].optics(c)[:2] for obj, c, _lo, _hi in crossings]
    T = thin_glass.stack(layers)[0]
    single = np.prod([t for t, _r in layers], axis=0)
    return float(np.max(1.0 - single / np.maximum(T, 1e-300)))


def lone_panes(model):
    """The thin panes (key, Pane) that may be quiet at some point (``quiet_panes``), with the scene's
    emitting lights: none unless no object other than panes reflects or emits and every light has a
    closed-form emitter; a pane with a frame in the same object, or that emits, is never one. It does
    not depend on the point: ``plan_direct`` computes it once for all of them."""
    g = model.geometry
    if not model.panes or g.pane_of is None:
        return [], []
    emits = np.zeros(len(g.object_names), bool)
    if len(g.emissive):
        emits[np.unique(g.object_index[np.asarray(g.emissive, bool)])] = True
    others = (np.asarray(g.reflects, bool) | emits) & ~np.isin(np.arange(len(g.object_names)), list(model.panes))
    lights = [lt for lt in model.lights if not lt.portal]
    if others.any() or any(lt.spec is None or not hasattr(lt.spec, "beyond_plane") for lt in lights):
        return [], []
    panes = [(k, pane) for k, pane in model.panes.items() if pane.geometry is not None and not emits[k]
             and np.all(g.pane_of[g.object_index == k] == k)]
    return panes, lights


def quiet_panes(model, p, tol, lone=None):
    """Object indices of thin panes that can send ``p`` no light beyond what crosses them straight (the
    closed forms' T, inter-pane reflections included). A pane reflects only light from ``p``'s side of
    it, so it is quiet when nothing on that side shines or reflects: no object other than panes
    reflects or emits, and every light lies wholly beyond every pane (an emitting world was handled
    before). A light on ``p``'s side keeps it quiet when its mirror image in every triangle of the pane
    provably misses ``p`` (``mirror_misses``, issue 32) and every other pane lies on or beyond its
    plane (nothing else on ``p``'s side can send it light to mirror). ``lone``: ``lone_panes(model)``
    when the caller has it."""
    panes, lights = lone_panes(model) if lone is None else lone
    quiet = set()
    g = model.geometry
    for k, pane in panes:
        normal = np.asarray(pane.geometry.normal, float)
        offsets = normal @ p - np.asarray(pane.geometry.heights, float)
        if not (np.all(offsets > tol) or np.all(offsets < -tol)):
            continue  # p inside the slab or on a face
        side = 1.0 if offsets[0] > 0 else -1.0
        height = min(pane.geometry.heights) if side > 0 else max(pane.geometry.heights)
        near = [lt for lt in lights if not lt.spec.beyond_plane(normal, height, side, tol)]
        if near:
            others = np.asarray(g.triangles[(g.pane_of >= 0) & (g.pane_of != k)], float).reshape(-1, 3)
            if np.any(side * (others @ normal - height) > tol):
                continue  # another pane on p's side may send it light to mirror
            mine = np.asarray(g.triangles[g.pane_of == k], float)
            if not all(mirror_misses(mine, p, lt.spec, max(tol, pane.geometry.tol)) for lt in near):
                continue
        quiet.add(k)
    return quiet


def mirror_misses(triangles, p, spec, tol):
    """True when no triangle of ``triangles`` (T, 3, 3) m, each a sharp mirror on both sides, shows the
    light ``spec`` to a receiver at ``p``: proven the way visibility is (issue 32).

    Per triangle: a light wholly behind its plane (seen from ``p``) lights only its far side. Otherwise
    the light reaches ``p`` from the triangle only along directions w in the cone around r, the mirror
    image of the direction to the light (a sun: its disc's half-angle a; a point or spot light of radius
    r_l: the cone from ``p`` over its mirrored sphere). That cone meets the plane within a disc around
    the central hit x0: with h the height of ``p`` over the plane, theta the angle of r to the plane's
    normal, c_min = cos(theta + a) and c_max = cos(max(theta - a, 0)), a direction w of the cone meets the
    plane at distance s_w in [h / c_max, h / c_min] and x - x0 = s_w (w - r) + (s_w - t) r, so
    |x - x0| <= h / c_min 2 sin(a / 2) + h / c_min - h / c_max. The triangle is missed when x0
    lies outside it by more than that radius (+ ``tol``), or when the light arrives so near grazing that
    its mirror image leaves the plane less steeply (the light's elevation over the plane + a) than any
    point of the triangle is seen from ``p`` (asin(h / farthest vertex distance)). Area lights prove
    nothing (False)."""
    p = np.asarray(p, float)
    for tri in np.asarray(triangles, float).reshape(-1, 3, 3):
        normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        length = float(np.linalg.norm(normal))
        if length == 0.0:
            continue  # a degenerate triangle has no area to mirror with
        normal = normal / length
        hp = float(normal @ (p - tri[0]))
        if abs(hp) <= tol:
            return False
        normal = normal * np.sign(hp)  # towards p
        cone = spec.mirror_cone(p, normal, tri[0], tol)
        if cone is None:
            return False  # nothing proven (the light straddles the plane, an area light)
        if isinstance(cone, str):
            continue  # the light lights only the plane's far side
        r, half, c = cone
        height = abs(hp)
        # Every point of the triangle is seen from p at least this steeply against its plane; the mirrored
        # light leaves the plane no steeper than the light arrives (+ its half-angle): a grazing light misses.
        steep = float(np.arcsin(min(1.0, height / float(np.max(np.linalg.norm(tri - p, axis=1))))))
        if steep > float(np.arcsin(min(1.0, abs(c)))) + half + 1e-12:
            continue
        theta = float(np.arccos(np.clip(c, -1.0, 1.0)))
        if theta + half >= 0.5 * np.pi - 1e-9:
            return False
        c_min, c_max = float(np.cos(theta + half)), float(np.cos(max(theta - half, 0.0)))
        reach = height / c_min * (1.0 + 2.0 * np.sin(0.5 * half)) - height / c_max
        x0 = p + height / c * r
        # Signed distances of x0 beyond each edge's line, in the triangle's plane (outward positive).
        outside = -np.inf
        for i in range(3):
            a, b, other = tri[i], tri[(i + 1) % 3], tri[(i + 2) % 3]
            out = np.cross(b - a, normal)
            out = out / np.linalg.norm(out)
            if out @ (other - a) > 0:
                out = -out
            outside = max(outside, float(out @ (x0 - a)))
        if outside <= reach + tol:
            return False
    return True


#: Largest (planar objects x scene vertices) ``dark_planes`` examines (about a second of numpy).
DARK_PLANE_WORK = 20_000_000


def dark_planes(model):
    """{object index: (normal (3,), height, sides, tolerance m)} of the opaque planar objects that send no light to
    one side of their plane (``sides``: the signs s with nothing on that side; issue 32).

    Light reaches a surface's side s only along rays from the open half-space on side s; an opaque
    surface (no transmission) sends light only back into the half-space it came from. So a planar
    object, opaque, emitting nothing, is dark on side s when every light lies wholly on the other side
    (``beyond_plane`` of each emitter) and every other object that reflects or emits lies on or beyond its plane: then
    nothing on side s emits or scatters (none with a participating medium in the scene; the world's own
    light is rendered wherever a surface rises above the horizon: ``world_statuses``). A
    lamp with shadows off shining through a wall at a meter before it lights the meter (a closed
    form) and the wall's far side only. Empty when a light has no closed-form emitter, or the work would
    exceed ``DARK_PLANE_WORK``."""
    from . import thin_glass

    g = model.geometry
    lights = [lt for lt in model.lights if not lt.portal]
    if (not g.count or model.volumes or model.world_volume
            or any(lt.spec is None or not hasattr(lt.spec, "beyond_plane") for lt in lights)):
        return {}  # a medium anywhere may scatter light onto either side
    opaque = np.asarray(g.opaque, bool)
    emissive = np.asarray(g.emissive, bool) if len(g.emissive) else np.zeros(g.count, bool)
    reflects = np.asarray(g.reflects, bool)
    relevant = (reflects[g.object_index] | emissive)
    candidates = []
    for k, verts, _corners, _emitting in g.object_vertices():
        mine = g.object_index == k
        if not reflects[k] or k in model.panes or not np.all(opaque[mine]) or np.any(emissive[mine]):
            continue
        centred = verts - verts.mean(axis=0)
        _u, sv, vt = np.linalg.svd(centred, full_matrices=False)
        normal = vt[-1]
        tol = thin_glass.coordinate_tolerance(float(np.abs(verts).max()))
        offsets = centred @ normal
        if len(sv) < 3 or sv[-2] <= 0.0 or np.any(np.abs(offsets) > tol):
            continue  # not one plane
        candidates.append((k, normal, float(verts.mean(axis=0) @ normal), tol))
    if not candidates or len(candidates) * 3 * g.count > DARK_PLANE_WORK:
        return {}
    out = {}
    for k, normal, height, tol in candidates:
        others = g.triangles[relevant & (g.object_index != k)].reshape(-1, 3) @ normal - height
        sides = tuple(side for side in (1.0, -1.0)
                      if not np.any(side * others > tol)
                      and all(lt.spec.beyond_plane(normal, height, side, tol) for lt in lights))
        if sides:
            out[k] = (normal, height, sides, tol)
    return out


def indirect_possible(model, p, n, tol, lone=None, dark=None):
    """(bool, reason): can light reach p (normal n) other than straight from a light?

    Exactly when some render-visible surface that reflects or emits lies (partly) above the
    receiver's horizon plane (a thin pane that can mirror nothing there does not count:
    ``quiet_panes``), the world emits, or geometry could not be triangulated. Objects are
    tested largest first, by their bounding boxes and then their vertices, and the first one
    above ends the search.
    ``lone``: ``lone_panes(model)``, computed once by a caller that asks for many points; ``dark``:
    ``dark_planes(model)`` likewise (an opaque planar object whose side towards ``p`` nothing can light
    does not count).
    """
    if model.world_emits and not world_modelled(model):
        return True, "the world emits light"
    volume = volume_above(model, p, n, tol)
    if volume:
        return True, f"{volume} scatters light toward the meter (in-scattering is rendered)"
    g = model.geometry
    if g.unmodelled:
        return True, f"geometry without triangles ({', '.join(g.unmodelled[:3])})"
    if not g.count:
        return False, ""
    reflects = np.asarray(g.reflects, bool)
    quiet = quiet_panes(model, p, tol, lone)
    dark = dark_planes(model) if dark is None else dark
    for k, verts, corners, emitting in g.object_vertices():
        if not reflects[k] or k in quiet or np.all((corners - p) @ n <= tol):
            continue
        if k in dark:
            normal, height, sides, plane_tol = dark[k]
            offset = float(normal @ p) - height
            if abs(offset) > max(tol, plane_tol) and np.sign(offset) in sides:
                continue
        if np.any(verts @ n > p @ n + tol):
            if len(emitting) and np.any(~visibility.below_plane(emitting, p, n, tol)):
                return True, "an emitting surface is above the meter's horizon"
            return True, f"surfaces above the meter's horizon reflect light (e.g. {g.object_names[k]!r})"
    return False, ""


def plan_direct(model, points, normals, exact_model=None):
    """Decide every contribution. ``points``/``normals`` (N, 3) in metres; ``exact_model(emitter)`` ->
    (is_exact, model name, note); default: the emitter's own ``exactness()``. Returns a :class:`DirectPlan`."""
    if exact_model is None:
        exact_model = _emitter_exactness
    points = np.asarray(points, float)
    normals = np.asarray(normals, float)
    n_lights, n_pts = len(model.lights), len(points)
    status = np.full((n_lights, n_pts), RENDER, dtype=object)
    reason = np.full((n_lights, n_pts), "", dtype=object)
    tol = length_tolerance(points)
    reach = scene_reach(model.geometry, points)
    indirect = np.zeros(n_pts, bool)
    indirect_reason = np.full(n_pts, "", dtype=object)
    transmittance = np.ones((n_lights, n_pts, 3))   # thin glass on the way (issue 18)
    glass_bound = np.zeros((n_lights, n_pts))
    interpane = np.zeros((n_lights, n_pts))
    lone, dark = lone_panes(model), dark_planes(model)  # the same for every point
    for k in range(n_pts):
        indirect[k], indirect_reason[k] = indirect_possible(model, points[k], normals[k], tol, lone, dark)
    for i, light in enumerate(model.lights):
        if light.portal:
            status[i], reason[i] = ZERO, "portal light: guides world sampling, emits nothing"
            continue
        if not light.reaches_diffuse:
            status[i], reason[i] = ZERO, "invisible to diffuse rays (visible_diffuse off): no direct light on a diffuse sensor"
            continue
        if light.spec is None:
            status[i], reason[i] = RENDER, f"no closed form: {light.uncovered}"
            continue
        exact, model_name, _note = exact_model(light.spec)
        if model_name == "unmodelled":
            status[i], reason[i] = RENDER, f"no closed form: {_note}"
            continue
        if light.spec.render_reason:
            status[i], reason[i] = RENDER, light.spec.render_reason
            continue
        closed = EXACT if exact else BOUNDED
        if not light.casts_shadow:
            status[i], reason[i] = closed, f"{model_name}; casts no shadow (use_shadow off)"
            continue
        states, blockers, crossed = occlusion_statuses(light.spec, points, normals, model.geometry, tol, reach,
                                                       panes=model.panes)
        for k in range(n_pts):
            state, blocker = states[k], blockers[k]
            if state == visibility.CLEAR and crossed[k]:
                T, bound, words = glass_factor(model, crossed[k])
                transmittance[i, k], glass_bound[i, k] = T, bound
                interpane[i, k] = interpane_fraction(model, crossed[k])
                status[i, k] = closed if bound == 0.0 else BOUNDED
                reason[i, k] = (f"{model_name}; proved unoccluded but for thin glass: {words}; T = "
                                f"{', '.join(f'{t:.4f}' for t in T)} (RGB)"
                                + (f", +-{100 * bound:.2g} % over the light's extent" if bound else ""))
            elif state == visibility.CLEAR:
                status[i, k], reason[i, k] = closed, f"{model_name}; proved unoccluded"
            elif state == visibility.BLOCKED:
                status[i, k], reason[i, k] = ZERO, f"blocked by opaque {blocker!r}"
            else:
                where = f" by {blocker!r}" if blocker else " (meter inside the light)"
                status[i, k], reason[i, k] = RENDER, f"may be partly occluded{where}"
    if model.world_volume or model.volumes:
        for i, light in enumerate(model.lights):
            if light.spec is None or light.portal or not light.reaches_diffuse:
                continue
            media = volume_on_paths(model, light.spec, points, tol, reach)
            for k in np.flatnonzero(media != None):  # noqa: E711 - object array
                if status[i, k] in (EXACT, BOUNDED):
                    status[i, k], reason[i, k] = RENDER, (f"{media[k]} may lie between the meter and the light: it "
                                                          "attenuates and scatters it (no closed form); rendered")
    world_status, world_reason = world_statuses(model, points, normals, tol)
    # Meters that no source can reach through closed opaque shells: exactly 0 (issue 31, dark meters)
    # (asked only where something would otherwise be rendered: a meter read in closed form needs no proof)
    need = indirect | np.any(status == RENDER, axis=0)
    if world_status is not None:
        need |= world_status == RENDER
    dark, why = sealed.sealed_off(model, points[need]) if need.any() else (np.zeros(0, bool), "")
    for k in np.flatnonzero(need)[dark]:
        status[:, k], reason[:, k] = ZERO, why
        indirect[k], indirect_reason[k] = False, why
        transmittance[:, k], glass_bound[:, k], interpane[:, k] = 1.0, 0.0, 0.0
        if world_status is not None:
            world_status[k], world_reason[k] = ZERO, why
    return DirectPlan(status, reason, indirect, indirect_reason, world_status, world_reason,
                      transmittance=transmittance, glass_bound=glass_bound, interpane=interpane)


# --- participating media (issue 18) ------------------------------------------------------------------

def volume_on_paths(model, spec, points, tol, scene_reach):
    """(N,) object array: the name of a volume that may meet a segment from each receiver to the
    light (the world's volume, or a volume object whose box meets the region holding those segments:
    ``boxes_on_paths``), else None. Conservative: a box overlap is not a crossing."""
    points = np.asarray(points, float)
    out = np.full(len(points), None, dtype=object)
    if model.world_volume:
        out[:] = "the world's volume"
        return out
    boxes = [(f"volume {name!r}", vlo, vhi) for name, vlo, vhi in model.volumes]
    return boxes_on_paths(spec, points, boxes, tol, scene_reach)


def boxes_on_paths(spec, points, boxes, tol, scene_reach):
    """(N,) object array: the label of the first of ``boxes`` ((label, min (3,), max (3,)) in m) that may
    meet a segment from each receiver to the light, else None. A box is passed over only when it misses
    the segment from the receiver to the centre of the region's far base widened by that base's radius
    (the region holding every segment to the light lies within that distance of it: a cone narrows
    towards its apex). Conservative: meeting a box is not meeting what it bounds."""
    points = np.asarray(points, float)
    n = len(points)
    out = np.full(n, None, dtype=object)
    if not boxes or not n:
        return out
    kind, ends, inside = spec.occlusion_bases(points, scene_reach, ROUND_SIDES)
    for k in range(n):
        if inside[k]:
            out[k] = boxes[0][0]
            continue
        base = np.reshape(ends[k], (-1, 3))
        centre = base.mean(axis=0)
        widen = float(np.max(np.linalg.norm(base - centre, axis=1))) + tol
        region = np.vstack([points[k][None, :], base])
        lo, hi = region.min(axis=0) - tol, region.max(axis=0) + tol
        for name, vlo, vhi in boxes:
            vlo, vhi = np.asarray(vlo, float), np.asarray(vhi, float)
            if not (np.all(vhi >= lo) and np.all(vlo <= hi)):
                continue
            if not _segment_meets_box(points[k], centre, vlo - widen, vhi + widen):
                continue
            out[k] = name
            break
    return out


def scene_reach(geometry, points):
    """A length (m) past every surface and receiver: how far the proofs follow a ray to the sun."""
    lo, hi = geometry.bounds()
    return 4.0 * (np.linalg.norm(hi - lo) + np.max(np.abs(points)) + 1.0) if len(points) else 1.0


def _segment_meets_box(a, b, lo, hi):
    """True when the segment a -> b meets the closed box [lo, hi] (slab test)."""
    d = np.asarray(b, float) - a
    t0, t1 = 0.0, 1.0
    for axis in range(3):
        if abs(d[axis]) < 1e-300:
            if a[axis] < lo[axis] or a[axis] > hi[axis]:
                return False
            continue
        u, v = (lo[axis] - a[axis]) / d[axis], (hi[axis] - a[axis]) / d[axis]
        t0, t1 = max(t0, min(u, v)), min(t1, max(u, v))
        if t0 > t1:
            return False
    return True


def volume_above(model, p, n, tol):
    """Name of a medium that may scatter light to a receiver at ``p`` facing ``n`` (the world's
    volume, or a volume object with a bounding-box corner above the horizon plane), else ''."""
    if model.world_volume:
        return "the world's volume"
    for name, lo, hi in model.volumes:
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        if np.any((corners - p) @ n > tol):
            return f"volume {name!r}"
    return ""


# --- the world as its own contribution (issue 14) -------------------------------------------------------

def world_modelled(model):
    """True when the world's light is a closed form (``model.world`` is a modelled WorldLight)."""
    world = getattr(model, "world", None)
    return world is not None and bool(getattr(world, "modelled", False))


def world_statuses(model, points, normals, tol):
    """(status (N,), reason (N,)) of the world's light at every receiver.

    ZERO when the world is black; RENDER when it is not modelled, or when any render-visible surface
    that casts shadows or reflects lies above the receiver's horizon (it may block or reflect the
    world's light: there is no world light linking in bakes, so such scenes are rendered whole);
    else EXACT (pixel-exact) or BOUNDED (the bilinear interpolant by quadrature).
    """
    n = len(points)
    status = np.full(n, ZERO, dtype=object)
    reason = np.full(n, "the world emits nothing", dtype=object)
    world = getattr(model, "world", None)
    if not model.world_emits or (world is not None and getattr(world, "kind", None) == "black"):
        return status, reason
    if not world_modelled(model):
        why = getattr(world, "reason", "") if world is not None else ""
        status[:], reason[:] = RENDER, f"world not modelled{': ' + why if why else ''}"
        return status, reason
    closed = EXACT if world.exact else BOUNDED
    g = model.geometry
    relevant = np.asarray(g.reflects, bool) | np.asarray(g.casts_shadow, bool) if len(g.object_names) else []
    for k in range(n):
        p, nk = points[k], normals[k]
        medium = volume_above(model, p, nk, tol)
        if medium:  # issue 18: a medium above the horizon attenuates and scatters the world's light
            status[k], reason[k] = RENDER, f"{medium} attenuates and scatters the world's light"
            continue
        status[k], reason[k] = closed, f"world {world.kind}: closed form over its pixels; nothing above the horizon"
        if g.unmodelled:
            status[k], reason[k] = RENDER, "geometry without triangles may block the world"
            continue
        for j, verts, corners, _emitting in g.object_vertices():
            if not relevant[j] or np.all((corners - p) @ nk <= tol):
                continue
            if np.any(verts @ nk > p @ nk + tol):
                status[k], reason[k] = RENDER, (f"{g.object_names[j]!r} lies above the meter's horizon and may block or "
                                                "reflect the world's light (no world light linking in bakes)")
                break
    return status, reason


# --- where a receiver sits -------------------------------------------------------------------------

_ENCLOSURE_DIRECTIONS = np.array(
    [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1],
     [1, 1, 1], [-1, -1, 1], [1, -1, -1], [-1, 1, -1], [0.3, 0.8, -0.5], [-0.7, 0.2, 0.68]], float)


def surface_under(geometry, p, n, within):
    """(object name, distance m) of the surface straight below ``p`` against ``n``, if within ``within`` m."""
    if not geometry.count:
        return None, None
    near = geometry.grid.query(p, p, within)
    if not near.size:
        return None, None
    dist, index, _facing = visibility.first_hits(p + n * within, -np.asarray(n, float)[None, :],
                                                 geometry.triangles[near])
    if index[0] < 0 or dist[0] > 2 * within:
        return None, None
    return geometry.object_names[geometry.object_index[near[index[0]]]], float(dist[0] - within)


def enclosing_object(geometry, p):
    """Name of the mesh whose inside holds ``p`` (every test ray leaves through its back side), or None."""
    if not geometry.count:
        return None
    dirs = _ENCLOSURE_DIRECTIONS / np.linalg.norm(_ENCLOSURE_DIRECTIONS, axis=1, keepdims=True)
    dist, index, facing = visibility.first_hits(p, dirs, geometry.triangles)
    if np.any(index < 0) or np.any(facing <= 0):
        return None
    owners = set(geometry.object_index[index].tolist())
    return geometry.object_names[owners.pop()] if len(owners) == 1 else None

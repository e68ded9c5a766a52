"""Thin glass: what a planar pane passes and reflects, and when a ray provably crosses one (pure numpy).

A lighting designer's window is a *thin pane*: light crosses it undeflected (the lateral shift of a
tilted pane, d sin(theta - theta_t) / cos(theta_t), about 2 mm for a 6 mm pane at 45 degrees, is
stated, not modelled) and loses what the two interfaces reflect and the glass absorbs. Cycles, by
contrast, renders a Glass BSDF as refraction, which turns a small light seen through the pane into
a caustic that a path tracer essentially never finds (docs/FACTS.md: the sun through a window read
0.1 % of its value after 4.2 M samples). Radiance's ``glass`` material makes the same thin-pane
choice for the same reason.

Model (unpolarised light, each polarisation treated separately and averaged at the end):

* Fresnel reflectance r_s, r_p of one air/glass interface at incidence cos(theta), exact (IOR n;
  the inner interface has the same r by Snell's law);
* inside the pane the ray travels d / cos(theta_t) and keeps a = exp(-sigma_a d / cos(theta_t)) of
  its power (sigma_a per RGB channel, 1/m);
* a tint acts at every crossing and internal reflection the way Cycles' closure weights do: every
  transmission through an interface is multiplied by ``tint_t`` and every reflection by
  ``tint_r`` (Glass BSDF: both its Color; Principled BSDF: Base Color on transmission, white on
  reflection);
* multiple internal reflections are summed in closed form (incoherent):

      T = t^2 (1 - r)^2 a / (1 - (c_r r a)^2),     R = c_r r + t^2 c_r r (1 - r)^2 a^2 / (1 - (c_r r a)^2)

  with t = tint_t and c_r = tint_r; A = 1 - T - R is absorbed. At normal incidence, without
  absorption or tint, T = (1 - r0) / (1 + r0) = 2n / (n^2 + 1) (0.9174 for n = 1.52, 0.9200 for
  n = 1.5).

Several panes in a row (double glazing) combine by the adding formula of parallel layers,
T12 = T1 T2 / (1 - R1 R2), which sums the light bouncing between the panes.

A single face (a plane with a glass shader, the common archviz window) is read as a pane of zero
thickness: both interfaces, no absorption path.
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = ["fresnel_dielectric", "slab", "Pane", "PaneGeometry", "pane_geometry", "stack",
           "segment_crossing", "pyramid_crossing", "convex_hull_2d"]


def fresnel_dielectric(cos_i, ior):
    """(r_s, r_p): Fresnel power reflectances of light arriving from outside (index 1) on a medium
    of index ``ior`` at incidence cosine ``cos_i`` (clipped to [0, 1]). Total internal reflection
    (ior < 1 past the critical angle) gives 1."""
    c = np.clip(np.asarray(cos_i, float), 0.0, 1.0)
    n = float(ior)
    sin_t2 = (1.0 - c * c) / (n * n)
    tir = sin_t2 >= 1.0
    ct = np.sqrt(np.clip(1.0 - sin_t2, 0.0, 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        rs = ((c - n * ct) / (c + n * ct)) ** 2
        rp = ((n * c - ct) / (n * c + ct)) ** 2
    rs = np.where(tir | ~np.isfinite(rs), 1.0, rs)
    rp = np.where(tir | ~np.isfinite(rp), 1.0, rp)
    return rs, rp


def cos_refracted(cos_i, ior):
    """cos(theta_t) inside a medium of index ``ior`` for incidence cosine ``cos_i`` (0 past TIR)."""
    c = np.clip(np.asarray(cos_i, float), 0.0, 1.0)
    return np.sqrt(np.clip(1.0 - (1.0 - c * c) / (float(ior) ** 2), 0.0, 1.0))


def slab(cos_i, ior, thickness=0.0, absorption=(0.0, 0.0, 0.0), tint_t=(1.0, 1.0, 1.0), tint_r=(1.0, 1.0, 1.0)):
    """(T, R, A), each (..., 3) RGB: transmittance, reflectance and absorptance of a plane-parallel
    pane (module docstring) at incidence cosine ``cos_i`` (...,). ``thickness`` in m, ``absorption``
    sigma_a in 1/m per channel, ``tint_t``/``tint_r`` per channel in [0, 1]."""
    c = np.asarray(cos_i, float)[..., None]
    rs, rp = fresnel_dielectric(c, ior)
    ct = cos_refracted(c, ior)
    sigma = np.asarray(absorption, float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        path = np.where(ct > 0.0, float(thickness) / ct, np.inf)
        a = np.where(sigma * path > 0.0, np.exp(-sigma * path), 1.0)
    t = np.asarray(tint_t, float)
    cr = np.asarray(tint_r, float)
    T = np.zeros(np.broadcast_shapes(c.shape, (3,)))
    R = np.zeros_like(T)
    for r in (rs, rp):
        denom = 1.0 - (cr * r * a) ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            tp = np.where(denom > 0.0, t * t * (1.0 - r) ** 2 * a / denom, 0.0)
            rp_ = np.where(denom > 0.0, cr * r + t * t * cr * r * (1.0 - r) ** 2 * a * a / denom, cr * r)
        T = T + 0.5 * tp
        R = R + 0.5 * rp_
    T = np.clip(T, 0.0, 1.0)
    R = np.clip(R, 0.0, 1.0)
    return T, R, np.clip(1.0 - T - R, 0.0, 1.0)


def stack(layers):
    """(T, R) of parallel panes crossed in order, each given as (T, R) RGB arrays (same both ways:
    a homogeneous pane is symmetric), by the adding formula T12 = T1 T2 / (1 - R1 R2),
    R12 = R1 + T1^2 R2 / (1 - R1 R2)."""
    T, R = None, None
    for t, r in layers:
        t, r = np.asarray(t, float), np.asarray(r, float)
        if T is None:
            T, R = t, r
            continue
        denom = 1.0 - R * r
        T, R = T * t / denom, R + T * T * r / denom
    return T, R


@dataclass
class Pane:
    """One recognised pane: its optics and its shape (``PaneGeometry``); ``model`` says in words
    what it was read as (for the notes)."""

    name: str
    ior: float = 1.5
    thickness: float = 0.0          # m (0: a single face)
    absorption: tuple = (0.0, 0.0, 0.0)   # sigma_a, 1/m
    tint_t: tuple = (1.0, 1.0, 1.0)
    tint_r: tuple = (1.0, 1.0, 1.0)
    geometry: object = None
    model: str = ""
    trick: bool = False             # the archviz "Is Shadow Ray -> Transparent" glass
    source: str = ""                # the object's name at capture time (for the notes)
    source_id: object = None        # its identity (``emitters.SourceId``): how its material is found to swap
    slots: tuple = ()               # its material slots that are the pane (others: a frame, ...)

    def optics(self, cos_i):
        """(T, R, A) RGB at incidence cosine ``cos_i``."""
        return slab(cos_i, self.ior, self.thickness, self.absorption, self.tint_t, self.tint_r)


# --- shape: planar panes and the proofs that a ray crosses one --------------------------------------

@dataclass
class PaneGeometry:
    """A planar pane: unit ``normal``, plane offsets ``heights`` (1 for a face, 2 for a slab:
    normal . x = h), an in-plane frame (``origin``, ``u``, ``v``) and the pane's outline as a convex
    polygon ``hull`` (K, 2) in that frame, counter-clockwise. Every face triangle lies in one of the
    planes and the face triangles of each plane cover the hull exactly (checked by area), so a ray
    crossing a plane strictly inside the hull crosses the pane there."""

    normal: np.ndarray
    heights: tuple
    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray
    hull: np.ndarray
    extra: list = field(default_factory=list)

    @property
    def thickness(self):
        return float(max(self.heights) - min(self.heights))


def convex_hull_2d(points):
    """Counter-clockwise convex hull (K, 2) of 2D points (Andrew's monotone chain)."""
    pts = sorted(set(map(tuple, np.round(np.asarray(points, float), 15))))
    if len(pts) < 3:
        return np.asarray(pts, float)

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(reversed(pts))
    return np.asarray(lower[:-1] + upper[:-1], float)


def _polygon_area(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def pane_geometry(triangles, tol):
    """(PaneGeometry, "") when ``triangles`` (T, 3, 3) in metres form a planar pane: one plane, or
    two parallel planes (a solidified slab, a flat box) whose face triangles cover the same convex
    outline; else (None, reason)."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if not len(tris):
        return None, "no triangles"
    cross = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    areas = 0.5 * np.linalg.norm(cross, axis=1)
    k = int(np.argmax(areas))
    if areas[k] <= 0.0:
        return None, "degenerate triangles"
    n = cross[k] / np.linalg.norm(cross[k])
    verts = tris.reshape(-1, 3)
    h = verts @ n
    lo, hi = float(h.min()), float(h.max())
    on_lo, on_hi = np.abs(h - lo) <= tol, np.abs(h - hi) <= tol
    if not np.all(on_lo | on_hi):
        return None, "not planar: vertices between its two faces (curved, bevelled or thick glass)"
    heights = (lo,) if hi - lo <= tol else (lo, hi)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(n, helper)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    origin = verts.mean(axis=0)
    flat = np.stack([(verts - origin) @ u, (verts - origin) @ v], axis=1)
    hull = convex_hull_2d(flat)
    if len(hull) < 3:
        return None, "degenerate outline"
    hull_area = _polygon_area(hull)
    th = tris @ n
    for height in heights:
        face = np.all(np.abs(th - height) <= tol, axis=1)
        face_area = float(areas[face].sum())
        if abs(face_area - hull_area) > 1e-6 * hull_area + 4 * tol * np.sqrt(hull_area):
            return None, ("its face does not fill its convex outline (holes, an L shape, or overlapping "
                          "triangles)")
    if len(heights) == 2:
        side = ~np.all(np.abs(th - heights[0]) <= tol, axis=1) & ~np.all(np.abs(th - heights[1]) <= tol, axis=1)
        side_normals = cross[side] / np.maximum(np.linalg.norm(cross[side], axis=1, keepdims=True), 1e-300)
        if np.any(np.abs(side_normals @ n) > 1e-6):
            return None, "its edges are not square to its faces (a bevel or taper)"
        # Both faces must have the same outline: the pane is a right prism over ``hull``.
        for height in heights:
            sel = np.abs(h - height) <= tol
            if abs(_polygon_area(convex_hull_2d(flat[sel])) - hull_area) > 1e-6 * hull_area:
                return None, "its two faces have different outlines"
    return PaneGeometry(normal=n, heights=heights, origin=origin, u=u, v=v, hull=hull), ""


def _inside_hull(geom, x, margin):
    """(M,) bool: points x (M, 3) (on the pane's plane) inside the hull by at least ``margin`` m."""
    q = np.stack([(x - geom.origin) @ geom.u, (x - geom.origin) @ geom.v], axis=-1)
    a = geom.hull
    b = np.roll(a, -1, axis=0)
    edge = b - a
    length = np.linalg.norm(edge, axis=1)
    # Signed distance to each edge's line, positive inside (counter-clockwise hull).
    dist = (edge[None, :, 0] * (q[:, None, 1] - a[None, :, 1]) - edge[None, :, 1] * (q[:, None, 0] - a[None, :, 0])) \
        / length[None, :]
    return np.all(dist > margin, axis=1)


def segment_crossing(geom, a, b, tol):
    """(crosses, cos_i): True when the segment a -> b (metres) crosses every plane of the pane
    strictly inside its outline and both ends lie outside the pane (beyond ``tol``): then it meets
    exactly the pane's two faces (or its one face) and nothing else of it; ``cos_i`` = |cos| of the
    segment's angle to the normal. (False, nan) when it does not provably do so."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    ha, hb = float(a @ geom.normal), float(b @ geom.normal)
    lo, hi = min(geom.heights), max(geom.heights)
    below = lambda h: h < lo - tol  # noqa: E731
    above = lambda h: h > hi + tol  # noqa: E731
    if not ((below(ha) and above(hb)) or (above(ha) and below(hb))):
        return False, float("nan")
    x = np.array([a + d * (height - ha) / (hb - ha) for height in geom.heights])
    if not np.all(_inside_hull(geom, x, tol)):
        return False, float("nan")
    return True, float(abs(d @ geom.normal) / np.linalg.norm(d))


def pyramid_crossing(geom, apex, base, tol):
    """(crosses, cos_min, cos_max): True when every segment from ``apex`` to a point of the convex
    polygon ``base`` (K, 3) crosses the pane as in :func:`segment_crossing` (checked on the lateral
    edges: the pyramid's section by a plane is the convex hull of the edges' crossings, and the
    outline is convex). cos_min/cos_max bound |cos| to the normal over the pyramid's directions
    (from its edges, and 1 when the normal direction lies inside it)."""
    apex = np.asarray(apex, float)
    base = np.asarray(base, float)
    cosines = []
    for q in base:
        ok, c = segment_crossing(geom, apex, q, tol)
        if not ok:
            return False, float("nan"), float("nan")
        cosines.append(c)
    cos_max = max(cosines)
    # The normal (towards the pane) inside the cone over the base: then directions at cos 1 exist.
    side = np.sign((base.mean(axis=0) - apex) @ geom.normal)
    nrm = geom.normal * side
    ring = base - apex
    edges_ok = True
    for i in range(len(ring)):
        face_normal = np.cross(ring[i], ring[(i + 1) % len(ring)])
        inner = np.sign(face_normal @ ring.mean(axis=0))
        if inner * (face_normal @ nrm) < 0:
            edges_ok = False
            break
    if edges_ok:
        cos_max = 1.0
    return True, min(cosines), cos_max


# --- multiple glazing (issue 18, F5) ------------------------------------------------------------------

def parallel_stacks(panes, tol=1e-6):
    """Groups (lists of keys, two or more) of ``panes`` ({key: Pane}) that are parallel and whose
    outlines overlap seen along their normal (bounding boxes of the hulls in the first pane's frame:
    conservative): multiple glazing, where light bounces between the panes."""
    keys = [k for k, p in panes.items() if getattr(p, "geometry", None) is not None]
    groups, placed = [], set()
    for i, a in enumerate(keys):
        if a in placed:
            continue
        ga = panes[a].geometry
        lo_a, hi_a = ga.hull.min(axis=0), ga.hull.max(axis=0)
        group = [a]
        for b in keys[i + 1:]:
            gb = panes[b].geometry
            if b in placed or abs(float(np.dot(ga.normal, gb.normal))) < 1.0 - tol:
                continue
            corners = gb.origin + gb.hull[:, :1] * gb.u + gb.hull[:, 1:] * gb.v
            flat = np.stack([(corners - ga.origin) @ ga.u, (corners - ga.origin) @ ga.v], axis=1)
            if np.all(flat.max(axis=0) > lo_a + tol) and np.all(flat.min(axis=0) < hi_a - tol):
                group.append(b)
        if len(group) > 1:
            placed.update(group)
            groups.append(group)
    return groups


def interpane_share(panes, cos_i):
    """Largest relative share (over RGB) of the light crossing ``panes`` (Pane, in order) at incidence
    cosine ``cos_i`` that bounces between them: 1 - prod T_i / T_stack (the adding formula). A render
    of the panes as separate thin panes misses it (a specular chain)."""
    layers = [p.optics(cos_i)[:2] for p in panes]
    T = stack(layers)[0]
    single = np.prod([t for t, _r in layers], axis=0)
    return float(np.max(1.0 - single / np.maximum(T, 1e-300)))

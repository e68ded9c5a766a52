"""Where the sun lights each surface, as exact polygons: the sun's first bounce as Lambertian emitters
(pure numpy; issue 31, the low sun).

Why. At a low sun the light in a room comes from thin sunlit strips: at 2 deg over the demo room's south
window the sun cannot cross the 0.1 m wall at all, and the room is lit by an 8 cm strip of the west reveal
(sunlit outside the pane and, through the pane at 88 deg, behind it) and by the sun mirrored in the pane's
outer face onto the reveal. A path from a meter finds such a strip by chance (a few in 10^3 diffuse rays),
so a meter's pilot often finds nothing and a sound stop cannot follow (docs/errors.md). Radiance answers
with secondary sources (``mkillum``); here the sunlit part of every Lambertian surface becomes one. On a
Lambertian surface of albedo rho the sun's irradiance E leaves as radiance rho E / pi in every direction of
its front side, so from there on that light IS the light of a one-sided Lambertian emitter of radiance
rho E / pi over the sunlit polygons, and a path tracer samples emitters by next-event estimation.

The polygons. For one direction d towards the sun, a receiver's sunlit part is the receiver minus the
shadows of every opaque triangle in front of it, cast along d onto its plane: the occluder clipped to the
half-space in front of the plane (``> tol``), then moved along d onto it, an affine map, so a convex
occluder casts a convex shadow and the clipped part's shadow is the shadow of the part that can block.
The parts behind a thin pane (``thin_glass.Pane``: its convex outline at its mid-plane, crossed
undeflected as the meter's thin-pane model has it) are kept with the pane's T at that incidence. A pane's
side that faces the sun also mirrors it: the sunlit part of its outline, cast along the mirrored direction
onto the surfaces in front of it, lights them with the pane's R (the sun's first image in each pane). An
image that meets another pane would be mirrored again there (R1 R2 of the light: 1 % at 45 deg, 30 % at
80 deg); that case is refused, not cast.

The sun's disc (angular radius a). The irradiance at a point is the mean over the disc of the point-sun
irradiance, so a reading of the emitters' light is a mean over the disc of readings with a point sun, a
smooth function of the direction (a penumbra 0.0093 rad wide per metre from its edge moves light by
millimetres, which readings metres away see at second order). It is taken with a cubature of the disc:
three points exact to degree 2 (error of order (a l / w)^3 for a strip w wide lit past an edge l away:
about 0.15 % for the demo's 8 cm strip at 2 m), or Stroud's seven exact to degree 5 ((a l / w)^6).
"""

import time
from dataclasses import dataclass, field

import numpy as np

from ..skies import sky_aperture

__all__ = ["SunPieces", "Surfaces", "DISC_RULES", "disc_cubature", "surfaces", "sunlit_pieces", "merge_pairs",
           "pane_outline", "polygon_area_3d"]

#: Cubature rules on the unit disc, (radius, angle, weight) per point: exact for polynomials of degree 2 (three
#: points at radius sqrt(1/2), 120 deg apart, 1/3 each) and of degree 5 (Stroud: the centre 1/4, six points at
#: sqrt(2/3), 1/6 ... 1/8 each).
DISC_RULES = {
    2: [(np.sqrt(0.5), k * 2.0 * np.pi / 3.0, 1.0 / 3.0) for k in range(3)],
    5: [(0.0, 0.0, 0.25)] + [(np.sqrt(2.0 / 3.0), k * np.pi / 3.0, 0.125) for k in range(6)],
}


def disc_cubature(direction, radius_rad, degree=5):
    """((K, 3) unit directions, (K,) weights summing to 1) over the sun's disc of angular radius
    ``radius_rad`` around ``direction``: the rule of ``DISC_RULES`` exact to ``degree`` (2: 3 points, 5: 7
    points); one point when the radius is 0."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    if radius_rad <= 0.0:
        return d[None, :], np.ones(1)
    u, v = sky_aperture.plane_axes(d)
    dirs, weights = [], []
    for r, phi, w in DISC_RULES[degree]:
        t = np.tan(r * radius_rad)  # a point on the tangent plane at angle r a from the centre
        x = d + t * (np.cos(phi) * u + np.sin(phi) * v)
        dirs.append(x / np.linalg.norm(x))
        weights.append(w)
    return np.asarray(dirs), np.asarray(weights)


def polygon_area_3d(poly):
    """Area of a planar polygon (K, 3)."""
    poly = np.asarray(poly, float)
    if len(poly) < 3:
        return 0.0
    return 0.5 * float(np.linalg.norm(np.sum(np.cross(poly, np.roll(poly, -1, axis=0)), axis=0)))


def pane_outline(geometry):
    """A thin pane's convex outline (K, 3) at its mid-plane (``thin_glass.PaneGeometry``)."""
    g = geometry
    n = np.asarray(g.normal, float)
    pts = np.asarray(g.origin, float) + g.hull[:, :1] * np.asarray(g.u, float) + g.hull[:, 1:2] * np.asarray(g.v, float)
    mid = 0.5 * (max(g.heights) + min(g.heights))
    return pts + (mid - pts @ n)[:, None] * n


@dataclass
class SunPieces:
    """The sunlit pieces of the Lambertian receivers for one sun: ``polygons`` (P,) of (K, 3) m, each on
    its receiver's plane; ``triangle`` (P,) the receiver's index; ``normal`` (P, 3) the lit side's unit
    normal; ``irradiance`` (P, 3) the irradiance on the piece per unit normal irradiance of the sun
    (RGB: cos of incidence x the panes' T or R x the cubature weight); ``kind`` (P,) "direct" or
    "mirror"; ``proven`` False with ``reason`` where a condition failed (then nothing else holds);
    ``notes``."""

    polygons: list = field(default_factory=list)
    triangle: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    normal: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    irradiance: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    kind: list = field(default_factory=list)
    proven: bool = True
    reason: str = ""
    notes: list = field(default_factory=list)

    def area(self):
        return np.array([polygon_area_3d(p) for p in self.polygons])

    def flux(self):
        """(P, 3) the pieces' received flux per unit normal irradiance of the sun (m^2)."""
        return self.area()[:, None] * self.irradiance if self.polygons else np.zeros((0, 3))


# --- 2D convex polygons in a receiver's plane (plain lists of (x, y): 3-8 vertices, where numpy's
# per-call overhead would dominate) ----------------------------------------------------------------------

def _area2(q):
    s = 0.0
    k = len(q)
    for i in range(k):
        x0, y0 = q[i]
        x1, y1 = q[(i + 1) % k]
        s += x0 * y1 - x1 * y0
    return 0.5 * s


def _clip_line(q, a, e, keep_left=True):
    """Convex polygon q [(x, y)] clipped to the left (or right) of the line through ``a`` along ``e``."""
    if not q:
        return q
    ax, ay = a
    ex, ey = e
    sgn = 1.0 if keep_left else -1.0
    s = [sgn * (ex * (y - ay) - ey * (x - ax)) for x, y in q]
    if min(s) >= 0.0:
        return q
    if max(s) <= 0.0:
        return []
    out = []
    k = len(q)
    for i in range(k):
        j = (i + 1) % k
        si, sj = s[i], s[j]
        if si >= 0.0:
            out.append(q[i])
        if (si > 0.0 and sj < 0.0) or (si < 0.0 and sj > 0.0):
            t = si / (si - sj)
            (x0, y0), (x1, y1) = q[i], q[j]
            out.append((x0 + t * (x1 - x0), y0 + t * (y1 - y0)))
    return out


def _difference(piece, shadow, min_area):
    """(convex pieces of ``piece`` outside the convex ``shadow`` (CCW), the part inside it or None)."""
    outside, rest = [], piece
    k = len(shadow)
    for i in range(k):
        a = shadow[i]
        b = shadow[(i + 1) % k]
        e = (b[0] - a[0], b[1] - a[1])
        part = _clip_line(rest, a, e, keep_left=False)
        if len(part) >= 3 and abs(_area2(part)) > min_area:
            outside.append(part)
        rest = _clip_line(rest, a, e, keep_left=True)
        if len(rest) < 3 or abs(_area2(rest)) <= min_area:
            return outside, None
    return outside, rest


def _bbox(q):
    xs = [x for x, _y in q]
    ys = [y for _x, y in q]
    return min(xs), min(ys), max(xs), max(ys)


def _clip_plane(poly, normal, offset):
    """Convex polygon (K, 3) clipped to ``poly . normal >= offset`` (unit ``normal``)."""
    shift = offset * np.asarray(normal, float)
    return sky_aperture.clip_polygon(np.asarray(poly, float) - shift, normal) + shift


class _Plane:
    """A receiver's plane: origin, lit-side unit normal n, in-plane axes; casting along d (n . d > 0)."""

    def __init__(self, origin, normal, d):
        self.o, self.n, self.d = origin, normal, d
        self.c = float(normal @ d)
        self.u, self.v = sky_aperture.plane_axes(normal)

    def cast(self, pts):
        """Points (K, 3) moved along d onto the plane, in plane coordinates (K, 2) (affine)."""
        h = (pts - self.o) @ self.n
        q = pts - (h / self.c)[:, None] * self.d - self.o
        return np.stack([q @ self.u, q @ self.v], axis=1)

    def lift(self, q):
        q = np.asarray(q, float).reshape(-1, 2)
        return self.o + q[:, :1] * self.u + q[:, 1:2] * self.v


def _ccw(q):
    """(K, 2) array -> counter-clockwise list of (x, y), repeated vertices dropped."""
    q = _dedupe([(float(x), float(y)) for x, y in q])
    return q[::-1] if _area2(q) < 0.0 else q


def _shadow(plane, poly3, tol, extra=()):
    """The convex shadow (K, 2, CCW) that the part of ``poly3`` in front of ``plane`` (and inside every
    half-space ``(normal, offset)`` of ``extra``) casts along its direction, or None."""
    part = _clip_plane(poly3, plane.n, float(plane.o @ plane.n) + tol)
    for normal, offset in extra:
        if len(part) < 3:
            return None
        part = _clip_plane(part, normal, offset)
    if len(part) < 3:
        return None
    q = plane.cast(part)
    return _ccw(q)


def _dedupe(q, eps=0.0):
    """A polygon [(x, y)] without repeated consecutive vertices (a triangle padded to a quad)."""
    out = []
    for p in q:
        if not out or abs(p[0] - out[-1][0]) > eps or abs(p[1] - out[-1][1]) > eps:
            out.append(p)
    while len(out) > 1 and abs(out[0][0] - out[-1][0]) <= eps and abs(out[0][1] - out[-1][1]) <= eps:
        out.pop()
    return out


def _shadows(plane, polys, tol):
    """``_shadow`` of many convex polygons (M, K, 3) at once: [CCW list or None]. The part in front of the
    plane (> tol) of each is its front vertices and its edges' crossings of the offset plane, in order."""
    m, k = polys.shape[:2]
    h = ((polys.reshape(-1, 3) - plane.o) @ plane.n).reshape(m, k) - tol
    nxt = np.roll(np.arange(k), -1)
    hi, hj = h, h[:, nxt]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where((hi > 0) != (hj > 0), hi / (hi - hj), 0.0)
    cross = polys + t[:, :, None] * (polys[:, nxt] - polys)
    flat_v = plane.cast(polys.reshape(-1, 3)).reshape(m, k, 2).tolist()
    flat_x = plane.cast(cross.reshape(-1, 3)).reshape(m, k, 2).tolist()
    front = (h > 0).tolist()
    out = []
    for i in range(m):
        f = front[i]
        if not any(f):
            out.append(None)
            continue
        q = []
        for j in range(k):
            if f[j]:
                q.append(tuple(flat_v[i][j]))
            if f[j] != f[(j + 1) % k]:
                q.append(tuple(flat_x[i][j]))
        q = _dedupe(q)
        if len(q) < 3:
            out.append(None)
            continue
        out.append(q[::-1] if _area2(q) < 0.0 else q)
    return out


def _lit(plane, start, occluders, filters, tol, min_area, extra=(), budget=None):
    """Pieces [(q (K, 2), factor (3,))] of the convex regions ``start`` [(q, factor)] left by the shadows
    of ``occluders`` (M, 3, 3) and multiplied by each filter's factor inside its shadow. ``filters``:
    [(outline (K, 3), factor (3,))]. ``budget``: a one-item list, the pieces still allowed (None: no limit);
    returns None when it runs out."""
    pieces = list(start)
    if len(occluders):
        boxes = np.array([_bbox(q) for q, _f in pieces])
        lo, hi = boxes[:, :2].min(axis=0) - tol, boxes[:, 2:].max(axis=0) + tol
        k = occluders.shape[1]
        h = ((occluders.reshape(-1, 3) - plane.o) @ plane.n).reshape(-1, k)
        front = h.max(axis=1) > tol
        flat = plane.cast(occluders[front].reshape(-1, 3)).reshape(-1, k, 2)
        near = (flat.min(axis=1) <= hi).all(axis=1) & (flat.max(axis=1) >= lo).all(axis=1)
        cand = occluders[front][near]
        # nearest first: a receiver inside a closed solid (the inner side of a wall's face) is shaded whole
        # by its own solid's faces, found first
        depth = h[front][near].mean(axis=1)
        cand = cand[np.argsort(depth, kind="stable")]
        shadows = _shadows(plane, cand, tol) if not extra else None
        for i, tri in enumerate(cand):
            shadow = shadows[i] if shadows is not None else _shadow(plane, tri, tol, extra)
            if shadow is None or abs(_area2(shadow)) <= min_area:
                continue
            sx0, sy0, sx1, sy1 = _bbox(shadow)
            nxt = []
            for q, f in pieces:
                qx0, qy0, qx1, qy1 = _bbox(q)
                if qx1 < sx0 or qy1 < sy0 or qx0 > sx1 or qy0 > sy1:
                    nxt.append((q, f))
                    continue
                outside, _inside = _difference(q, shadow, min_area)
                nxt.extend((p, f) for p in outside)
            pieces = nxt
            if budget is not None:
                if len(pieces) > budget[0]:
                    return None
            if not pieces:
                return []
    for outline, factor in filters:
        shadow = _shadow(plane, outline, tol, extra)
        if shadow is None or abs(_area2(shadow)) <= min_area:
            continue
        nxt = []
        for q, f in pieces:
            outside, inside = _difference(q, shadow, min_area)
            nxt.extend((p, f) for p in outside)
            if inside is not None:
                nxt.append((inside, f * factor))
        pieces = nxt
    if budget is not None:
        budget[0] -= len(pieces)
        if budget[0] < 0:
            return None
    return pieces


def merge_pairs(triangles, keys, tol):
    """Convex polygons (M, 4, 3) from ``triangles`` (T, 3, 3): two triangles with the same ``keys`` (T,)
    that share an edge, lie in one plane (within ``tol``) and make a convex quad become that quad; the
    others stay triangles, their last vertex repeated. Returns (polygons, owner (M,): the first triangle's
    index). Half the polygons, a quarter of the shadow work (quads come triangulated)."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    n = len(tris)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    unit = normals / np.where(lengths > 0, lengths, 1.0)[:, None]
    scale = max(float(np.abs(tris).max()) if n else 1.0, 1e-300)
    ids = np.round(tris.reshape(-1, 3) / (scale * 1e-12)).astype(np.int64).reshape(n, 3, 3)
    edges = {}
    used = np.zeros(n, bool)
    polys, owner = [], []
    keys = list(keys)
    for i in range(n):
        for a, b in ((0, 1), (1, 2), (2, 0)):
            e = (keys[i],) + tuple(sorted((tuple(ids[i, a]), tuple(ids[i, b]))))
            j = edges.get(e)
            if j is None:
                edges[e] = (i, a, b)
                continue
            j, ja, jb = j
            if used[i] or used[j] or lengths[i] <= 0 or lengths[j] <= 0 or unit[i] @ unit[j] < 0.0:
                continue
            other = 3 - ja - jb  # j's vertex off the shared edge
            c = 3 - a - b        # i's
            if abs((tris[j, other] - tris[i, 0]) @ unit[i]) > tol:
                continue
            quad = np.array([tris[i, c], tris[i, a], tris[j, other], tris[i, b]])
            # i runs c, a, b counter-clockwise about its normal; j's far vertex goes between a and b
            if not _convex_3d(quad, unit[i] if _orient(tris[i], c, a, b, unit[i]) else -unit[i]):
                continue
            used[i] = used[j] = True
            polys.append(quad)
            owner.append(min(i, j))
    rest = np.flatnonzero(~used)
    if len(rest):
        polys.extend(np.concatenate([tris[rest], tris[rest, 2:3]], axis=1))
        owner.extend(rest.tolist())
    if not polys:
        return np.zeros((0, 4, 3)), np.zeros(0, int)
    return np.asarray(polys, float).reshape(-1, 4, 3), np.asarray(owner, int)


def _orient(tri, c, a, b, n):
    return float(np.cross(tri[a] - tri[c], tri[b] - tri[c]) @ n) > 0.0


def _convex_3d(quad, n):
    """True when the planar quad (4, 3) turns the same way (about ``n``) at every vertex."""
    turns = [float(np.cross(quad[(k + 1) % 4] - quad[k], quad[(k + 2) % 4] - quad[(k + 1) % 4]) @ n)
             for k in range(4)]
    return all(t > 0.0 for t in turns)


@dataclass
class Surfaces:
    """What the sunlit polygons are cast on and by: receivers (R, 4, 3) convex polygons (triangles with their
    last vertex repeated), their unit normals (R, 3) and owner triangles (R,); occluders (M, 4, 3)."""

    receivers: np.ndarray
    normals: np.ndarray
    owner: np.ndarray
    occluders: np.ndarray


def surfaces(triangles, receivers, occluders, *, groups=None, tol=1e-6):
    """:class:`Surfaces` of ``triangles`` (T, 3, 3) m: the ``receivers`` (T,) bool merged in pairs within
    their ``groups`` (T,) (one albedo each; None: one group), the ``occluders`` (T,) bool merged freely."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    rec = np.flatnonzero(np.asarray(receivers, bool))
    keys = np.zeros(len(tris), int) if groups is None else np.asarray(groups)
    polys, owner = merge_pairs(tris[rec], keys[rec].tolist(), tol)
    normals = np.cross(polys[:, 1] - polys[:, 0], polys[:, 2] - polys[:, 0]) if len(polys) else np.zeros((0, 3))
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 0.0
    occ, _o = merge_pairs(tris[np.asarray(occluders, bool)], [0] * int(np.sum(occluders)), tol)
    return Surfaces(polys[keep], normals[keep] / lengths[keep, None], rec[owner[keep]], occ)


class _Refused(Exception):
    """The sunlit polygons would cost more than they are allowed (the reason)."""


def _checked(pieces, max_pieces):
    if pieces is None:
        raise _Refused(f"the sunlit polygons exceed {max_pieces} pieces")
    return pieces


def _facing(surf, direction, deadline):
    """(polygon, its unit normal on the side facing ``direction``, owner, |cos|) of every receiver of
    :class:`Surfaces` not edge-on to ``direction``; raises :class:`_Refused` past ``deadline``."""
    for i, (poly, n0, k) in enumerate(zip(surf.receivers, surf.normals, surf.owner)):
        if deadline is not None and i % 64 == 0 and time.perf_counter() > deadline:
            raise _Refused("the sunlit polygons took longer than their time allowance")
        c = float(n0 @ direction)
        if abs(c) >= 1e-12:
            yield poly, (n0 if c > 0 else -n0), k, abs(c)


def sunlit_pieces(triangles, receivers, occluders, direction, *, panes=(), tol=1e-6, weight=1.0, mirrors=True,
                  max_pieces=20000, max_pairs=5e7, groups=None, deadline=None):
    """The sunlit pieces of the ``receivers`` for a point sun in ``direction`` (unit, towards the sun).

    ``triangles`` (T, 3, 3) m (or their :class:`Surfaces`, which several directions share: ``receivers``,
    ``occluders`` and ``groups`` are then not read); ``receivers`` (T,) bool: the Lambertian surfaces whose
    sunlit part is wanted (both sides: the side facing the sun); ``occluders`` (T,) bool: the opaque shadow
    casters (a receiver is one too); ``groups`` (T,): receivers of one group may merge (one albedo);
    ``panes``: [``thin_glass.Pane``] crossed as filters (T at the incidence) and mirroring the sun (R) when
    ``mirrors``; their own triangles must not be occluders. ``weight``: the cubature weight of this
    direction. ``tol`` (m): what lies within it of a receiver's plane does not shade it (its neighbours
    along an edge). Returns :class:`SunPieces` (``proven`` False when the work exceeds ``max_pieces``
    pieces or ``max_pairs`` receiver-occluder pairs, or runs past ``deadline``, a ``time.perf_counter()``)."""
    surf = triangles if isinstance(triangles, Surfaces) else surfaces(triangles, receivers, occluders,
                                                                        groups=groups, tol=tol)
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    occ = surf.occluders
    out = SunPieces()
    if len(surf.receivers) * max(len(occ), 1) > max_pairs:
        out.proven, out.reason = False, (f"{len(surf.receivers)} receivers x {len(occ)} shadow casters exceed "
                                         f"the {max_pairs:.0e} pairs the exact sunlit polygons are computed for")
        return out
    min_area = (tol * tol)
    budget = [int(max_pieces)]
    pane_filters = []
    for pane in panes:
        outline = pane_outline(pane.geometry)
        c = abs(float(np.asarray(pane.geometry.normal, float) @ d))
        T, R, _A = pane.optics(c)
        pane_filters.append((pane, outline, np.asarray(T, float), np.asarray(R, float), c))
    polys, owner, nrm, irr, kind = [], [], [], [], []

    def add(pieces, plane, k, factor_kind, cos_in):
        for q, f in pieces:
            polys.append(plane.lift(q))
            owner.append(k)
            nrm.append(plane.n)
            irr.append(weight * cos_in * f)
            kind.append(factor_kind)

    filters = [(outline, T) for _p, outline, T, _R, _c in pane_filters]
    try:
        for poly, n, k, c in _facing(surf, d, deadline):
            plane = _Plane(poly[0], n, d)
            add(_checked(_lit(plane, [(_ccw(plane.cast(poly)), np.ones(3))], occ, filters, tol, min_area,
                              budget=budget), max_pieces), plane, k, "direct", c)
        for j, (pane, outline, _T, R, c_p) in enumerate(pane_filters if mirrors else ()):
            pn = np.asarray(pane.geometry.normal, float)
            pn = pn if pn @ d > 0 else -pn  # the side that faces the sun
            if c_p < 1e-12 or not np.any(R > 0):
                continue
            # the pane's own sunlit part (other panes as filters)
            pplane = _Plane(outline[0], pn, d)
            others = [(o, T) for i, (_p, o, T, _R, _c) in enumerate(pane_filters) if i != j]
            lit = _checked(_lit(pplane, [(_ccw(pplane.cast(outline)), np.ones(3))], occ, others, tol, min_area,
                                budget=budget), max_pieces)
            if not lit:
                continue
            image = d - 2.0 * (d @ pn) * pn  # from a receiver towards the sun's image in the pane
            offset = float(outline[0] @ pn)
            offset_plane = (pn, offset + tol)

            def image_on(poly, n, filters):
                """The pieces of receiver ``poly`` (facing ``image`` on side ``n``) the sun's image in pane j lights."""
                front = _clip_plane(poly, pn, offset + tol)  # the part on the mirror's sunlit side
                if len(front) < 3:
                    return []
                plane = _Plane(poly[0], n, image)
                tri_q = _ccw(plane.cast(front))
                if len(tri_q) < 3:
                    return []
                start = []
                for q, f in lit:
                    shadow = _shadow(plane, pplane.lift(q), tol)
                    if shadow is None:
                        continue
                    _o, inside = _difference(tri_q, shadow, min_area)
                    if inside is not None:
                        start.append((inside, f * R))
                if not start:
                    return []
                # only what stands between the receiver and the pane shades it
                return plane, _checked(_lit(plane, start, occ, filters, tol, min_area, extra=(offset_plane,),
                                            budget=budget), max_pieces)

            # the image meeting another pane would make an image of the image, which is not cast: refused
            for i, (_p, o_i, _T_i, _R_i, _c_i) in enumerate(pane_filters):
                n_i = np.asarray(_p.geometry.normal, float)
                if i == j or abs(float(n_i @ image)) < 1e-12:
                    continue
                hit = image_on(o_i, n_i if n_i @ image > 0 else -n_i,
                               [(o, T) for m, (_q, o, T, _r, _c) in enumerate(pane_filters) if m not in (i, j)])
                if hit and hit[1]:
                    raise _Refused(f"the sun's image in pane {getattr(pane, 'name', j)!r} lights pane "
                                   f"{getattr(_p, 'name', i)!r}: its image there (two reflections) is not cast")
            for poly, n, k, c in _facing(surf, image, deadline):
                hit = image_on(poly, n, others)
                if hit:
                    add(hit[1], hit[0], k, "mirror", c)
    except _Refused as why:
        out.proven, out.reason = False, str(why)
        return out
    out.polygons = polys
    out.triangle = np.asarray(owner, int)
    out.normal = np.asarray(nrm, float).reshape(-1, 3)
    out.irradiance = np.asarray(irr, float).reshape(-1, 3)
    out.kind = kind
    return out

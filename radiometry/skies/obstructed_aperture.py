"""The sky seen through an opening past obstructions, in closed form (pure numpy; issue 31).

Where opaque triangles stand in the directions from a point through a convex opening (a building across
the street, a cabinet between the point and the window), the directions that still reach the world are the
opening minus the obstructions' silhouettes. Each direction through the opening is one point of the
opening's plane (the ray from the point meets the plane there), so in that plane:

* a triangle's part on the opening's side of the point (farther along the opening's normal than the point
  by at least the tolerance t) projects from the point to a convex polygon of the plane, its silhouette:
  exactly the directions through the opening that this part blocks (seen edge-on it blocks no solid angle
  and is skipped). The rest of the triangle blocks no direction through the opening: such a direction
  gains at least depth / D along the normal per metre (depth the point's distance to the opening's plane,
  D its farthest vertex), so a blocking point nearer than t along the normal lies within t D / depth of
  the point, and the triangle's plane is checked to be farther than that (else: refused);
* the opening minus each silhouette, cut edge by edge, is a union of disjoint convex polygons
  (``unblocked_pieces``; a convex polygon minus a triangle is at most three convex pieces);
* on each piece ``sky_aperture.aperture_illuminance`` is the closed form (Lambert and its first-moment
  extension), and the pieces add up.

The silhouettes are exact; the pieces are exact up to floating-point rounding (slivers with an area below
``SLIVER`` of the opening's are dropped: each is below 1e-12 of the opening's solid angle there). A triangle
whose plane passes within t D / depth of the point is refused with a reason: the caller then renders that
point whole. What the blocking triangles reflect (the externally reflected
component) is not here: it is rendered. Which triangles may block: ``sky_aperture.apertures_blockers``.

Where no closed room holds the openings (walls, floor and roof built of separate boxes that touch or overlap:
no single closed surface), ``open_directions`` finds every direction from a point above its plane that meets
no triangle at all: the six faces of a cube round the point, each clipped to the point's side of its plane, are
openings of their own, and each minus every triangle's silhouette is a set of convex pieces. A direction above
the point's plane cannot meet a triangle whose vertices all lie on or below that plane, so those are left out
exactly; the rest are culled per face by the face's pyramid (a triangle wholly outside one of its four side
planes meets none of its directions).
"""

import numpy as np

from ..metrics.glare import triangle_solid_angles
from . import sky_aperture

__all__ = ["unblocked_pieces", "open_directions", "closed_solids", "quad_pairs", "SLIVER"]

#: Pieces with an area below this share of the opening's are dropped.
SLIVER = 1e-12


def _area(q):
    """Signed area of a 2D polygon (K, 2) or a list of (x, y); positive when counter-clockwise."""
    n = len(q)
    return 0.5 * sum(q[k][0] * q[(k + 1) % n][1] - q[(k + 1) % n][0] * q[k][1] for k in range(n))


def _clip(q, a, b, keep_left):
    """Convex 2D polygon ``q`` (a list of (x, y)) clipped to the left (``keep_left``) or the right of the line a -> b
    (Sutherland-Hodgman; points on the line are kept on both sides). Plain floats: the polygons have a handful of
    vertices, where numpy's per-call cost was most of the proof's time."""
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    side = [dx * (y - ay) - dy * (x - ax) for x, y in q]
    if not keep_left:
        side = [-v for v in side]
    if min(side) >= 0.0:
        return q
    if max(side) <= 0.0:
        return []
    out = []
    n = len(q)
    for k in range(n):
        j = (k + 1) % n
        sk, sj = side[k], side[j]
        if sk >= 0.0:
            out.append(q[k])
        if (sk > 0.0 and sj < 0.0) or (sk < 0.0 and sj > 0.0):
            t = sk / (sk - sj)
            out.append((q[k][0] + t * (q[j][0] - q[k][0]), q[k][1] + t * (q[j][1] - q[k][1])))
    return out


def _box(q):
    xs, ys = [v[0] for v in q], [v[1] for v in q]
    return min(xs), min(ys), max(xs), max(ys)


def unblocked_pieces(point, vertices, blockers, tol):
    """The part of the convex planar opening ``vertices`` (K, 3) through which ``point`` (3,) sees past the
    triangles ``blockers`` (B, 3, 3), or a list of convex planar polygons (K_b, 3): a list of disjoint convex
    polygons (M, 3) in the opening's plane whose
    union is the opening minus the blockers' silhouettes seen from the point; or a str, why not (the point
    lies in the opening's plane, or a blocker's plane passes too near it). Metres throughout."""
    p = np.asarray(point, float)
    poly = np.asarray(vertices, float)
    blockers = [np.asarray(b, float) for b in blockers] if isinstance(blockers, list) else \
        np.asarray(blockers, float).reshape(-1, 3, 3)
    normal, offset = sky_aperture.polygon_plane(poly)
    h = offset - float(normal @ p)
    if abs(h) <= tol:
        return "the point lies in the opening's plane"
    m = normal if h > 0.0 else -normal           # from the point towards the opening
    depth = abs(h)
    e1, e2 = sky_aperture.plane_axes(normal)
    origin = poly[0]

    def flat(x):
        rel = x - origin
        return np.c_[rel @ e1, rel @ e2]

    base = [tuple(v) for v in flat(poly).tolist()]
    if _area(base) < 0.0:
        base = base[::-1]
    smallest = SLIVER * abs(_area(base))
    near = tol * float(np.max(np.linalg.norm(poly - p, axis=1))) / depth  # see the module docstring
    pieces = [base]
    for tri in blockers:
        along = (tri - p) @ m
        if np.all(along < tol):
            front = tri[:0]
        else:
            front = tri if np.all(along >= tol) else \
                p + sky_aperture.clip_polygon(tri - p - tol * m, m) + tol * m  # its part with along >= tol
        if np.any(along < tol):
            tri_normal = np.cross(tri[1] - tri[0], tri[2] - tri[0])
            size = float(np.linalg.norm(tri_normal))
            if size == 0.0 or abs(float((p - tri[0]) @ tri_normal)) / size <= near:
                return ("an obstruction in the view through an opening passes within "
                        f"{near:.3g} m of the point, behind it as seen from the opening")
        if len(front) < 3:
            continue  # wholly behind: it blocks no direction through the opening
        sil = [tuple(v) for v in flat(p + (front - p) * (depth / ((front - p) @ m))[:, None]).tolist()]  # central projection
        area = _area(sil)
        if abs(area) <= smallest:
            continue  # seen edge-on: no solid angle
        if area < 0.0:
            sil = sil[::-1]
        kept = []
        lox, loy, hix, hiy = _box(sil)
        for piece in pieces:
            px0, py0, px1, py1 = _box(piece)
            if px1 < lox or py1 < loy or px0 > hix or py0 > hiy:
                kept.append(piece)  # their boxes are apart: the silhouette cuts nothing of this piece
                continue
            rest = piece
            for k in range(len(sil)):
                a, b = sil[k], sil[(k + 1) % len(sil)]
                outside = _clip(rest, a, b, keep_left=False)
                if len(outside) >= 3 and _area(outside) > smallest:
                    kept.append(outside)
                rest = _clip(rest, a, b, keep_left=True)
                if len(rest) < 3:
                    break
            # what is left of ``rest`` lies inside the silhouette: blocked
        pieces = kept
        if not pieces:
            break
    pieces = [np.asarray(q, float).reshape(-1, 2) for q in pieces]
    return [origin + q[:, :1] * e1 + q[:, 1:] * e2 for q in map(_without_repeats, pieces) if len(q) >= 3]


def _without_repeats(q):
    """A clipped polygon without consecutive repeated vertices (a vertex on a cutting line comes back as an
    intersection too)."""
    step = np.linalg.norm(q - np.roll(q, 1, axis=0), axis=1)
    scale = float(np.max(np.abs(q))) if len(q) else 0.0
    # 1e-10 of the scale: many silhouette edges' lines meet near the point straight ahead, where rounding leaves
    # vertices 1e-15 apart whose edge has no direction (patch_aperture's edge planes need one)
    return q[step > 1e-10 * max(scale, 1.0)]


def _face_squares(point, d):
    """The six faces of the cube of half-side ``d`` round ``point``: (axis (3,), square (4, 3), side axes (2, 3))."""
    p = np.asarray(point, float)
    out = []
    for k in range(3):
        for sign in (1.0, -1.0):
            a = np.zeros(3)
            a[k] = sign
            u, v = np.zeros(3), np.zeros(3)
            u[(k + 1) % 3], v[(k + 2) % 3] = 1.0, 1.0
            c = p + d * a
            sq = np.array([c - d * u - d * v, c + d * u - d * v, c + d * u + d * v, c - d * u + d * v])
            out.append((a, sq, (u, v)))
    return out


def closed_solids(triangles, tol, groups=None):
    """The closed surfaces among ``triangles`` (T, 3, 3) wound consistently (every edge of it met once each way,
    vertices welded within ``tol``), each within one of ``groups`` (T,) (e.g. the objects: boxes that touch share
    vertices, so together they close nothing): a list of (triangle indices, +1 where their winding normals point
    out of the solid, -1 into it). ``open_directions`` leaves out their faces turned away from a point outside
    them: a ray from outside a closed surface meets a face turned towards it first."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    groups = np.zeros(len(tris), int) if groups is None else np.asarray(groups)
    found = []
    for value in np.unique(groups):
        members = np.flatnonzero(groups == value)
        found += [members[idx] for idx in sky_aperture.closed_components(tris[members], tol)]
    out = []
    for idx in found:
        part = tris[idx]
        _pts, inv = sky_aperture._weld(part.reshape(-1, 3), tol)
        ids = inv.reshape(-1, 3)
        directed = np.stack([ids, np.roll(ids, -1, axis=1)], axis=-1).reshape(-1, 2)
        uniq, counts = np.unique(directed, axis=0, return_counts=True)
        if np.any(counts != 1) or len(uniq) != len(np.unique(np.sort(directed, axis=1), axis=0)) * 2:
            continue  # an edge twice the same way (wound inconsistently), or one met only one way
        volume = float(np.sum(np.einsum("tk,tk->t", part[:, 0], np.cross(part[:, 1], part[:, 2]))))
        if volume != 0.0:
            out.append((np.asarray(idx, int), 1 if volume > 0.0 else -1))
    return out


def quad_pairs(triangles, tol):
    """(partner (T,), quads (T, 4, 3)): for each triangle the index of the triangle it makes a convex planar quad
    with (they share an edge, wound the same way, in one plane within ``tol``), or -1, and that quad, wound as both
    (zeros where none): the two triangles of a box's face, whose silhouettes ``open_directions`` subtracts
    as one (half the cuts, and no piece split along the diagonal)."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    partner = np.full(len(tris), -1)
    quads = np.zeros((len(tris), 4, 3))
    if not len(tris):
        return partner, quads
    _pts, inv = sky_aperture._weld(tris.reshape(-1, 3), tol)
    ids = inv.reshape(-1, 3)
    nrm = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    size = np.linalg.norm(nrm, axis=1)
    owner = {}
    for t, (a, b, c) in enumerate(ids.tolist()):
        for x, y in ((a, b), (b, c), (c, a)):
            owner.setdefault((x, y), []).append(t)
    for t, row in enumerate(ids.tolist()):
        if partner[t] >= 0 or size[t] == 0.0:
            continue
        for k in range(3):
            x, y = row[k], row[(k + 1) % 3]
            for u in owner.get((y, x), []):  # the neighbour across this edge, wound the same way
                if u == t or partner[u] >= 0 or size[u] == 0.0:
                    continue
                if float(nrm[t] @ nrm[u]) < (1.0 - 1e-12) * size[t] * size[u]:
                    continue  # not parallel
                opposite = tris[u, next(v for v in range(3) if ids[u, v] not in (x, y))]
                quad = np.insert(tris[t], k + 1, opposite, axis=0)  # its vertex between the shared edge's two
                if abs(float((opposite - tris[t, 0]) @ nrm[t])) > tol * size[t] or not sky_aperture.is_convex(quad, tol):
                    continue
                partner[t], partner[u] = u, t
                quads[t] = quads[u] = quad
                break
            if partner[t] >= 0:
                break
    return partner, quads


def open_directions(point, normal, triangles, tol, solids=None, pairs=None, inside=None):
    """The directions from ``point`` (3,) above its plane (``normal`` (3,), unit) that meet none of
    ``triangles`` (T, 3, 3): a list of disjoint convex polygons (M, 3) on the faces of a cube round the point
    (each direction is one point of them), or a str, why not (``unblocked_pieces`` refused: a triangle's
    plane passes too near the point). ``solids``: ``closed_solids(triangles, tol)``, to leave out their faces
    turned away from the point (no direction at all where the point is inside one); ``pairs``:
    ``quad_pairs(triangles, tol)``, to subtract each pair's quad at once; ``inside``: per solid whether the point is
    inside it (True / False / None: ``sky_aperture.inside_enclosures``), when the caller found it for many points at
    once. Metres throughout; see the module docstring."""
    p = np.asarray(point, float)
    n = np.asarray(normal, float)
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    keep = np.ones(len(tris), bool)
    for j, (idx, sign) in enumerate(solids or ()):
        within = sky_aperture.inside_enclosures([p], tris[idx], [], tol)[0] if inside is None else inside[j]
        if within is True:
            return []  # inside a closed surface of triangles that stop every ray: every direction meets it
        if within is False:
            t = tris[idx]
            facing = sign * np.einsum("tk,tk->t", np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), p - t[:, 0])
            keep[idx[facing < 0.0]] = False
    rel = tris - p
    keep &= np.max(rel @ n, axis=1) > 0.0
    d = max(1.0, 1e3 * tol)  # the cube's size changes nothing but the pieces' scale
    pieces = []
    for axis, square, (u, v) in _face_squares(p, d):
        face = p + sky_aperture.clip_polygon(square - p, n)
        if len(face) < 3:
            continue
        along = rel @ axis                                      # (T, 3)
        inside = keep & (np.max(along, axis=1) > 0.0)           # some part in front of the face's plane
        for side in (u, -u, v, -v):  # wholly beyond a side plane of the face's pyramid: meets none of its directions
            inside &= ~np.all(rel @ side > along, axis=1)
        found = unblocked_pieces(p, face, _blockers(tris, rel, np.flatnonzero(inside), pairs), tol)
        if isinstance(found, str):
            return found
        pieces += found
    return pieces


def _blockers(tris, rel, idx, pairs):
    """The triangles ``idx`` as polygons to subtract, the largest solid angles first (the pieces are used up sooner;
    the order changes nothing else); a pair of ``pairs`` (``quad_pairs``) both among them as its quad."""
    omega = triangle_solid_angles(np.zeros(3), rel[idx])
    if pairs is None:
        return [tris[k] for k in idx[np.argsort(-omega)]]
    partner, quads = pairs
    where = dict(zip(idx.tolist(), omega))
    polys, weights = [], []
    for k, w in where.items():
        mate = int(partner[k])
        if mate in where:  # both halves in view: the quad once, from the lower index
            if k < mate:
                polys.append(quads[k])
                weights.append(w + where[mate])
            continue
        polys.append(tris[k])
        weights.append(w)
    return [polys[j] for j in np.argsort(-np.asarray(weights))]

"""The direct sky component through an opening, in closed form (pure numpy; issue 31).

The illuminance at a point ``p`` (unit normal ``n``) from the world seen through a planar convex
aperture ``A`` (an open hole in a room, or a pane's outline) is

    E = integral over the directions u through A of L(u) max(0, n . u) T(u) du,

with L the sky's luminance above the horizon (u_z > 0) and the ground's below it (a sharp horizon,
as ``measure.authoring.sky`` builds the world), and T the pane's transmittance (1 for an opening).

Closed forms
------------
The directions through A form a convex spherical polygon; clipped by the receiver's horizon
(n . u >= 0) and by the sky's horizon (u_z >= 0 for the sky, <= 0 for the ground) it stays convex
(clipping the planar polygon by planes through p). On a convex spherical polygon P with edges
(great-circle arcs a_i -> b_i of angle Theta_i) and outward conormals m_i, the surface divergence
theorem on the unit sphere gives, for constant vectors v, w:

* zeroth moment: the solid angle Omega (fan of Van Oosterom-Strackee triangles);
* first moment (Lambert): int_P (w . u) du = -1/2 sum_i Theta_i (w . m_i)
  (from div_S(w - (w . u) u) = -2 w . u);
* second moment: int_P (v . u)(w . u) du = 1/3 [(v . w) Omega - sum_i (w . m_i) int_arc (v . u) ds],
  int_arc (v . u) ds = (v . a_i) sin Theta_i + (v . t_i)(1 - cos Theta_i), t_i the unit tangent at a_i
  (from div_S[(v . u)(w - (w . u) u)] = v . w - 3 (v . u)(w . u); J. Arvo, "Applications of
  Irradiance Tensors to the Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995, derives the
  same moments).

The uniform sky (L = Lz) needs the first moment with w = n. The traditional CIE overcast sky,
L = Lz (1 + 2 u_z) / 3, is linear in u_z, so E = Lz/3 [int (n . u) du + 2 int (n . u)(z . u) du]:
a first and a second moment. The ground (uniform Lg) is a first moment over the part below the
horizon. Unobstructed, a horizontal receiver gets Lz (pi/3 + 4 pi/9) = 7 pi Lz / 9 (the overcast
sky's E_h): a test.

Panes: bounds by subdivision
----------------------------
A pane's transmittance T(cos_i) (cos_i = |m . u|, m the pane's normal) is not polynomial. The
aperture's spherical polygon is cut into triangles; on each, cos_i lies in an exactly computed range
[c_lo, c_hi] (the extremes of a linear function over a convex spherical triangle lie at a vertex, on
an edge's interior critical point, or at m itself when m is inside), so with T non-decreasing in
cos_i (checked on a dense grid when the bound is asked for) and the rest of the integrand >= 0,
T(c_lo) I_k <= E_k <= T(c_hi) I_k, I_k the closed form of the piece. Pieces are halved along their
longest edge, widest bound first, until the half-width is at most ``rel_tol`` of the estimate (the
bounds' midpoint) or ``max_pieces`` is reached; the half-width returned is a hard bound, not a
standard error.

What is proven and what is not
------------------------------
These formulas are exact for the directions through the aperture. That they are the direct sky
component of a scene needs a visibility proof (nothing between p and the aperture and nothing
beyond it in those directions): :func:`aperture_clear` gives it for triangle meshes with
``radiometry.scene.visibility``'s separating-axis tests (every doubt reads as "not proven").

Lengths in metres, luminance in cd/m^2, illuminance in lux (any consistent radiometric units work
the same way).
"""

import numpy as np

from ..scene import visibility

__all__ = ["clip_polygon", "fan_triangles", "spherical_moments", "aperture_illuminance", "pane_bounded_illuminance",
           "pane_bounded_illuminances", "polygon_plane", "aperture_clear", "apertures_clear", "apertures_blockers",
           "coplanar_outside", "find_apertures", "inside_prism", "is_convex", "enclosure_closed", "closed_components",
           "shell_holes", "edge_pieces",
           "enclosure_closed_part", "inside_enclosure", "inside_enclosures", "plane_axes", "triangle_parts", "SKIES"]

#: Sky models with a closed form over a polygon: name -> (constant, z-coefficient) of L / Lz = c0 + c1 u_z.
SKIES = {"uniform": (1.0, 0.0), "overcast": (1.0 / 3.0, 2.0 / 3.0)}


def _unit(v):
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0.0)


def clip_polygon(poly, axis, sign=1.0):
    """Convex polygon (K, 3) clipped to the half-space ``sign * axis . x >= 0`` (Sutherland-Hodgman);
    points exactly on the plane are kept. Returns (K', 3), K' = 0 when nothing is left."""
    poly = np.asarray(poly, float)
    if len(poly) == 0:
        return poly.reshape(0, 3)
    axis = sign * np.asarray(axis, float)
    h = poly @ axis
    if np.all(h >= 0.0):  # wholly inside (the usual case for a grid's points): the polygon as it is
        return poly.copy()
    if np.all(h < 0.0):
        return poly[:0]
    out = []
    for k in range(len(poly)):
        a, b, ha, hb = poly[k], poly[(k + 1) % len(poly)], h[k], h[(k + 1) % len(poly)]
        if ha >= 0.0:
            out.append(a)
        if (ha >= 0.0) != (hb >= 0.0):
            x = a + (ha / (ha - hb)) * (b - a)
            out.append(x - (x @ axis) / (axis @ axis) * axis)  # exactly on the plane
    return np.asarray(out, float).reshape(-1, 3)


def fan_triangles(poly):
    """Convex polygon (K, 3) as K - 2 triangles (K-2, 3, 3) fanned from its first vertex."""
    poly = np.asarray(poly, float)
    if len(poly) < 3:
        return np.zeros((0, 3, 3))
    return np.stack([np.broadcast_to(poly[0], (len(poly) - 2, 3)), poly[1:-1], poly[2:]], axis=1)


def _arcs(tris):
    """What the moments and the cosine ranges of spherical triangles (M, 3, 3) share: their unit vertices,
    edges (start, end, end x start's cross, sin and cos of the arc, its angle, unit tangent at its start),
    the triple product ``det`` and solid angle ``omega``."""
    u = _unit(np.asarray(tris, float))                                   # (M, 3, 3)
    start, end = u, u[:, [1, 2, 0]]                                      # edges a->b, b->c, c->a
    cross = np.cross(start, end)
    det = np.einsum("mk,mk->m", u[:, 0], cross[:, 1])                   # a . (b x c)
    cos_t = np.einsum("mek,mek->me", start, end)
    denom = 1.0 + cos_t.sum(axis=1)
    sin_t = np.sqrt(np.einsum("mek,mek->me", cross, cross))
    return {"u": u, "start": start, "end": end, "cross": cross, "det": det, "cos_t": cos_t, "sin_t": sin_t,
            "theta": np.arctan2(sin_t, cos_t), "omega": 2.0 * np.arctan2(np.abs(det), denom),
            "tangent": _unit(end - cos_t[..., None] * start)}


def spherical_moments(tris, v, w, arcs=None):
    """Moments over spherical triangles (M, 3, 3) (directions from the origin, any lengths):
    (Omega (M,) sr, first (M,) = int (w . u) du, second (M,) = int (v . u)(w . u) du).

    ``v``, ``w``: (3,) vectors, or (M, 3) one per triangle (not necessarily unit). Degenerate triangles
    give zeros. ``arcs``: the triangles' :func:`_arcs`, when the caller has them already.
    """
    g = arcs if arcs is not None else _arcs(tris)
    omega, theta, sin_t, cos_t, start = g["omega"], g["theta"], g["sin_t"], g["cos_t"], g["start"]
    orient = np.sign(g["det"])                                           # + : counter-clockwise from outside
    m = -orient[:, None, None] * _unit(g["cross"])                       # outward conormals
    v = np.broadcast_to(np.asarray(v, float), (len(omega), 3))
    w = np.broadcast_to(np.asarray(w, float), (len(omega), 3))
    w_m = np.einsum("mek,mk->me", m, w)
    first = -0.5 * np.sum(theta * w_m, axis=1)
    arc_v = np.einsum("mek,mk->me", start, v) * sin_t + np.einsum("mek,mk->me", g["tangent"], v) * (1.0 - cos_t)
    second = (np.einsum("mk,mk->m", v, w) * omega - np.sum(w_m * arc_v, axis=1)) / 3.0
    ok = (orient != 0.0)
    return np.where(ok, omega, 0.0), np.where(ok, first, 0.0), np.where(ok, second, 0.0)


def _pieces(poly_rel, normal, up=(0.0, 0.0, 1.0)):
    """Triangles of the aperture (relative to the receiver) above the receiver's horizon, split into
    (sky part u_z >= 0, ground part u_z <= 0)."""
    above = clip_polygon(poly_rel, normal)
    return fan_triangles(clip_polygon(above, up, 1.0)), fan_triangles(clip_polygon(above, up, -1.0))


def _sky_weight(tris, normal, sky, arcs=None):
    c0, c1 = SKIES[sky]
    _omega, first, second = spherical_moments(tris, np.array([0.0, 0.0, 1.0]), normal, arcs)
    return c0 * first + c1 * second


def _check_polygon(vertices):
    poly = np.asarray(vertices, float)
    if poly.ndim != 2 or poly.shape[1] != 3 or len(poly) < 3 or not np.all(np.isfinite(poly)):
        raise ValueError("aperture vertices must be a finite (K >= 3, 3) array")
    return poly


def _check(polys, points, normals, sky):
    """(polygons, points (N, 3), unit normals (N, 3)): one polygon for every point (``polys`` one (K, 3)
    array for all, or a list of N)."""
    if sky not in SKIES:
        raise ValueError(f"sky must be one of {sorted(SKIES)}, got {sky!r}")
    p = np.atleast_2d(np.asarray(points, float))
    n = _unit(np.array(np.broadcast_to(np.asarray(normals, float), p.shape)))
    if isinstance(polys, (list, tuple)) and len(polys) and np.ndim(polys[0]) == 2:
        if len(polys) != len(p):
            raise ValueError(f"one aperture per point: {len(polys)} apertures for {len(p)} points")
        return [_check_polygon(q) for q in polys], p, n
    poly = _check_polygon(polys)
    return [poly] * len(p), p, n


def _pieces_of(polys, p, n):
    """The pieces of every point's aperture: (triangles (M, 3, 3) relative to their point, owner (M,) point
    index, is_sky (M,) bool); points with a non-finite coordinate or normal have none."""
    tris, owner, is_sky = [], [], []
    for k, (poly, pk, nk) in enumerate(zip(polys, p, n)):
        if not (np.all(np.isfinite(pk)) and np.all(np.isfinite(nk))):
            continue
        for part, sky in zip(_pieces(poly - pk, nk), (True, False)):
            tris.append(part)
            owner.append(np.full(len(part), k))
            is_sky.append(np.full(len(part), sky))
    if not tris:
        return np.zeros((0, 3, 3)), np.zeros(0, int), np.zeros(0, bool)
    return np.concatenate(tris), np.concatenate(owner), np.concatenate(is_sky)


def _weights(tris, owner, is_sky, n, zenith_luminance, ground_luminance, sky, arcs=None):
    """(M,) lux of each piece: the sky's (``sky`` model, zenith luminance) on sky pieces, the uniform
    ground's on ground pieces, seen by a receiver facing ``n[owner]``. ``arcs``: the pieces' :func:`_arcs`."""
    w = np.zeros(len(tris))
    normals = n[owner]
    for luminance, these in ((zenith_luminance, is_sky), (ground_luminance, ~is_sky)):
        if luminance == 0.0 or not np.any(these):
            continue
        every = bool(np.all(these))
        part = arcs if every and arcs is not None else (
            None if arcs is None else {k: a[these] for k, a in arcs.items()})
        t, nn = (tris, normals) if every else (tris[these], normals[these])
        if these is is_sky:
            w[these] = luminance * _sky_weight(t, nn, sky, part)
        else:
            w[these] = luminance * spherical_moments(t, nn, nn, part)[1]
    return w


def aperture_illuminance(vertices, points, normals, *, zenith_luminance=1.0, ground_luminance=0.0, sky="overcast"):
    """Illuminance (N,) at ``points`` (N, 3) facing ``normals`` from the world seen through the convex
    planar aperture ``vertices`` (K, 3) (or a list of N such apertures, one per point): the sky (``sky``:
    "uniform" L = Lz, "overcast" L = Lz (1 + 2 u_z) / 3) above the horizon, a uniform ground of
    ``ground_luminance`` below it; closed form, all points at once.

    Returns (sky part (N,), ground part (N,)) in lux for luminances in cd/m^2. Nothing is assumed
    about visibility: see :func:`aperture_clear`. Points with a non-finite coordinate give NaN.
    """
    polys, p, n = _check(vertices, points, normals, sky)
    tris, owner, is_sky = _pieces_of(polys, p, n)
    w_sky = _weights(tris, owner, is_sky, n, zenith_luminance, 0.0, sky)
    w_ground = _weights(tris, owner, is_sky, n, 0.0, ground_luminance, sky)
    # float even where no point sees its aperture (numpy's bincount of no weights is an int array)
    e_sky = np.bincount(owner, w_sky, minlength=len(p)).astype(float)
    e_ground = np.bincount(owner, w_ground, minlength=len(p)).astype(float)
    bad = ~(np.all(np.isfinite(p), axis=1) & np.all(np.isfinite(n), axis=1))
    e_sky[bad] = e_ground[bad] = np.nan
    with np.errstate(invalid="ignore"):
        return np.maximum(e_sky, 0.0), np.maximum(e_ground, 0.0)


# --- panes: T(cos_i) by bounding subdivision ----------------------------------------------------------

def _cos_range(tris, m, arcs=None):
    """(lo, hi) (M,) of m . u over spherical triangles (M, 3, 3), m a unit vector: exact extremes.
    ``arcs``: the triangles' :func:`_arcs`, when the caller has them already."""
    g = arcs if arcs is not None else _arcs(tris)
    u, start, theta = g["u"], g["start"], g["theta"]
    vals = [u @ m]                                                      # vertices (M, 3)
    # m . u(s) = (m . a) cos s + (m . t) sin s: critical points s* = atan2(m . t, m . a) (+ pi).
    ma, mt = start @ m, g["tangent"] @ m
    s0 = np.arctan2(mt, ma)
    for s in (s0, s0 + np.pi, s0 - np.pi):
        inside = (s > 0.0) & (s < theta)
        vals.append(np.where(inside, ma * np.cos(s) + mt * np.sin(s), np.nan))
    vals = np.concatenate([v.reshape(len(u), -1) for v in vals], axis=1)
    lo, hi = np.nanmin(vals, axis=1), np.nanmax(vals, axis=1)
    # m itself inside the triangle: the maximum is 1.
    det = g["det"]
    side = (g["cross"] @ m) * np.sign(det)[:, None]
    hi = np.where(np.all(side >= 0.0, axis=1) & (det != 0.0), 1.0, hi)
    return lo, hi


#: Cosines at which a pane's T is tabulated for its bound (``pane_bounded_illuminances``): 1/65536 apart,
#: where a 6 mm pane's T rises at most 2.9 per unit cosine (at grazing), so the table widens a piece's
#: range by at most 4.4e-5 of T.
T_TABLE_SIZE = 65537


def _transmittance_table(transmittance):
    """T at ``T_TABLE_SIZE`` cosines 0..1, checked: finite, >= 0, one per cosine, non-decreasing."""
    c = np.linspace(0.0, 1.0, T_TABLE_SIZE)
    t = np.asarray(transmittance(c), float)
    if t.shape != c.shape or not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("transmittance(cos) must return finite values >= 0, one per cosine")
    if np.any(np.diff(t) < 0.0):
        raise ValueError(f"the bound needs a transmittance non-decreasing in cos(incidence) (checked on "
                         f"{T_TABLE_SIZE} cosines); this one is not")
    return t


def _split(tris):
    """Halve triangles (M, 3, 3) at the midpoint of their longest edge: (2M, 3, 3)."""
    u = _unit(tris)
    length = np.linalg.norm(np.roll(u, -1, axis=1) - u, axis=-1)        # edge k: vertex k -> k+1
    k = np.argmax(length, axis=1)
    idx = np.arange(len(tris))
    a, b, c = tris[idx, k], tris[idx, (k + 1) % 3], tris[idx, (k + 2) % 3]
    mid = 0.5 * (_unit(a) + _unit(b))                                   # a direction between a and b
    return np.concatenate([np.stack([a, mid, c], axis=1), np.stack([mid, b, c], axis=1)])


def pane_bounded_illuminance(vertices, point, normal, transmittance, pane_normal, *, zenith_luminance=1.0,
                             ground_luminance=0.0, sky="overcast", rel_tol=1e-3, max_pieces=20000):
    """Illuminance at one point through a glazed convex aperture, weighted by the pane's
    ``transmittance(cos_i)`` (a vectorised callable, non-decreasing in cos_i; cos_i = |pane_normal . u|).

    Returns (estimate, half_width, pieces) in lux: the true value lies in estimate +- half_width
    (a hard bound, see the module's Notes); half_width <= rel_tol * estimate unless ``max_pieces``
    was reached first.
    """
    est, half, pieces = pane_bounded_illuminances(vertices, point, normal, transmittance, pane_normal,
                                                  zenith_luminance=zenith_luminance, ground_luminance=ground_luminance,
                                                  sky=sky, rel_tol=rel_tol, max_pieces=max_pieces)
    return float(est[0]), float(half[0]), int(pieces[0])


def pane_bounded_illuminances(vertices, points, normals, transmittance, pane_normal, *, zenith_luminance=1.0,
                              ground_luminance=0.0, sky="overcast", rel_tol=1e-3, max_pieces=20000):
    """:func:`pane_bounded_illuminance` at N points at once, each through its own aperture (``vertices`` one
    (K, 3) polygon for all, or a list of N): arrays (estimate (N,), half_width (N,), pieces (N,)).

    Every point's subdivision is its own (its pieces, its widest half refined, its stopping rule), as it
    would be alone; the points only share numpy's calls, which is what makes a grid fast.
    """
    polys, p, n = _check(vertices, points, normals, sky)
    # T tabulated once on a fine grid of cosines: a monotone T lies between its values at the grid's points
    # either side of any cosine, so the table's neighbours bound it (hard, as the exact values would) for
    # one lookup a piece instead of a call of the pane's optics.
    table = _transmittance_table(transmittance)
    m = _unit(np.asarray(pane_normal, float))
    count = len(p)
    tris, owner, is_sky = _pieces_of(polys, p, n)

    def bounds(t, own, s):
        arcs = _arcs(t)
        w = np.maximum(_weights(t, own, s, n, zenith_luminance, ground_luminance, sky, arcs), 0.0)
        lo, hi = _cos_range(t, m, arcs)
        if np.any(lo * hi < 0.0) or np.any(np.abs(lo) > 1.0 + 1e-12):
            raise ValueError("the aperture straddles the pane's plane as seen from the point")
        c_lo = np.clip(np.minimum(np.abs(lo), np.abs(hi)), 0, 1)
        c_hi = np.clip(np.maximum(np.abs(lo), np.abs(hi)), 0, 1)
        last = T_TABLE_SIZE - 1
        return w * table[np.floor(c_lo * last).astype(int)], w * table[np.ceil(c_hi * last).astype(int)]

    lo, hi = bounds(tris, owner, is_sky) if len(tris) else (np.zeros(0), np.zeros(0))
    while True:
        s_lo, s_hi = np.bincount(owner, lo, count), np.bincount(owner, hi, count)
        pieces = np.bincount(owner, minlength=count)
        est, half = 0.5 * (s_lo + s_hi), 0.5 * (s_hi - s_lo)
        done = (half <= rel_tol * est) | (pieces >= max_pieces) | (half == 0.0)
        if np.all(done):
            bad = ~(np.all(np.isfinite(p), axis=1) & np.all(np.isfinite(n), axis=1))
            est[bad] = half[bad] = np.nan
            return est, half, pieces
        # each open point refines its widest pieces that together hold half its total width (at least one)
        width = hi - lo
        open_ = np.flatnonzero(~done[owner])
        order = open_[np.lexsort((-width[open_], owner[open_]))]
        own, wid = owner[order], width[order]
        starts = np.r_[0, np.flatnonzero(np.diff(own)) + 1]
        sizes = np.diff(np.r_[starts, len(own)])
        cum_before = np.cumsum(wid) - wid
        cum_before -= np.repeat(cum_before[starts], sizes)               # within each point's pieces
        rank = np.arange(len(own)) - np.repeat(starts, sizes)
        total = np.bincount(owner, width, count)
        budget = np.maximum(1, np.minimum(pieces, max_pieces - pieces))
        pick = ((cum_before < 0.5 * total[own]) | (rank == 0)) & (rank < budget[own])
        take = order[pick]
        keep = np.ones(len(tris), bool)
        keep[take] = False
        new = _split(tris[take])
        new_own, new_sky = np.r_[owner[take], owner[take]], np.r_[is_sky[take], is_sky[take]]
        nlo, nhi = bounds(new, new_own, new_sky)
        tris, owner, is_sky = np.concatenate([tris[keep], new]), np.r_[owner[keep], new_own], np.r_[is_sky[keep], new_sky]
        lo, hi = np.r_[lo[keep], nlo], np.r_[hi[keep], nhi]


# --- finding apertures and proving them clear -----------------------------------------------------------

def polygon_plane(vertices):
    """(unit normal (3,), offset) of a planar polygon (Newell's method): normal . x = offset."""
    v = np.asarray(vertices, float)
    nxt = np.roll(v, -1, axis=0)
    normal = np.array([np.sum((v[:, 1] - nxt[:, 1]) * (v[:, 2] + nxt[:, 2])),
                       np.sum((v[:, 2] - nxt[:, 2]) * (v[:, 0] + nxt[:, 0])),
                       np.sum((v[:, 0] - nxt[:, 0]) * (v[:, 1] + nxt[:, 1]))])
    normal = normal / np.linalg.norm(normal)
    return normal, float(v.mean(axis=0) @ normal)


def plane_axes(normal):
    """Two unit vectors (e1, e2) spanning the plane of unit ``normal``, (e1, e2, normal) right-handed."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = _unit(np.cross(normal, helper))
    return e1, np.cross(normal, e1)


def coplanar_outside(triangles, poly, tol):
    """(T,) bool: triangles lying in the aperture's plane (within ``tol`` m) whose interiors do not
    overlap the convex polygon's interior (2D separating axes; touching along an edge is allowed)."""
    normal, offset = polygon_plane(poly)
    h = np.einsum("tvk,k->tv", triangles, normal) - offset
    flat = np.all(np.abs(h) <= tol, axis=1)
    out = np.zeros(len(triangles), bool)
    idx = np.flatnonzero(flat)
    if not idx.size:
        return out
    e1, e2 = plane_axes(normal)
    q = np.c_[poly @ e1, poly @ e2]                                      # (K, 2)
    t2 = np.stack([triangles[idx] @ e1, triangles[idx] @ e2], axis=-1)   # (I, 3, 2)
    axes = []
    for shape in (q,):
        d = np.roll(shape, -1, axis=0) - shape
        axes.append(np.c_[-d[:, 1], d[:, 0]])
    poly_axes = axes[0]
    tri_d = np.roll(t2, -1, axis=1) - t2
    tri_axes = np.stack([-tri_d[..., 1], tri_d[..., 0]], axis=-1)       # (I, 3, 2)
    all_axes = np.concatenate([np.broadcast_to(poly_axes, (len(idx),) + poly_axes.shape), tri_axes], axis=1)
    all_axes = _unit(all_axes)
    pq = np.einsum("iak,vk->iav", all_axes, q)
    pt = np.einsum("iak,ivk->iav", all_axes, t2)
    gap = np.maximum(pt.min(axis=2) - pq.max(axis=2), pq.min(axis=2) - pt.max(axis=2))
    out[idx] = np.any(gap >= -tol, axis=1)                               # separated (or touching) on some axis
    return out


def aperture_clear(point, vertices, triangles, tol, reach, *, sky_only=True, ignore=None, coplanar_checked=False):
    """Proof that nothing stands in the directions from ``point`` through the convex aperture
    ``vertices`` (K, 3), from the point out to ``reach`` metres beyond it (past every triangle of the
    scene): True is a proof, False means "not proven".

    The region is the pyramid with apex ``point`` over the aperture scaled about the point to reach
    past the scene; with ``sky_only`` only its part above the point's horizontal plane (the part
    that sees the sky; below it the world's ground or the scene's ground meshes are seen). Triangles
    in the aperture's plane that only touch it along its edges (the wall around a hole) cannot block
    a direction through its interior and are set aside; ``ignore`` (T,) bool sets others aside (the
    caller's own proof, e.g. a pane's faces that are weighted by T(theta)). ``coplanar_checked``: ``ignore``
    already holds ``coplanar_outside`` (a caller testing many points through one aperture finds it once).
    """
    return bool(apertures_clear([point], vertices, triangles, tol, reach, sky_only=sky_only, ignore=ignore,
                                coplanar_checked=coplanar_checked)[0])


def apertures_clear(points, vertices, triangles, tol, reach, *, sky_only=True, ignore=None, coplanar_checked=False):
    """:func:`aperture_clear` for many points (P, 3) through one aperture: (P,) bool, True a proof for that
    point. The points' pyramids meet the scene's triangles in one batched separating-axis test."""
    blockers = apertures_blockers(points, vertices, triangles, tol, reach, sky_only=sky_only, ignore=ignore,
                                  coplanar_checked=coplanar_checked)
    return np.array([b is not None and b.size == 0 for b in blockers], bool)


def apertures_blockers(points, vertices, triangles, tol, reach, *, sky_only=True, ignore=None,
                       coplanar_checked=False):
    """What may stand in each point's pyramid through one aperture (the region of :func:`aperture_clear`): a
    list over the points (P, 3) of the indices into ``triangles`` of those that meet it (conservative: one
    within ``tol`` of it counts), or None where the point lies on the aperture (within ``tol``: no pyramid).
    An empty array is :func:`aperture_clear`'s proof."""
    pts = np.atleast_2d(np.asarray(points, float))
    poly = np.asarray(vertices, float)
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    skip = np.zeros(len(tris), bool) if coplanar_checked else coplanar_outside(tris, poly, tol)
    if ignore is not None:
        skip |= np.asarray(ignore, bool)
    kept = np.flatnonzero(~skip)
    rest = tris[kept]
    out = [np.zeros(0, int) for _ in range(len(pts))]
    rmin, rmax = rest.min(axis=1), rest.max(axis=1)
    apexes, bases, pairs_point, pairs_tri = [], [], [], []
    for i, p in enumerate(pts):
        rel = poly - p
        if sky_only:
            rel = clip_polygon(rel, np.array([0.0, 0.0, 1.0]))
            if len(rel) < 3:
                continue
        dist = np.linalg.norm(rel, axis=1)
        if np.any(dist <= tol):
            out[i] = None
            continue
        if not len(rest):
            continue
        far = p + rel * ((dist + reach) / dist)[:, None]
        near = np.flatnonzero(visibility.aabb_overlap(rmin, rmax, np.minimum(far.min(axis=0), p),
                                                      np.maximum(far.max(axis=0), p), tol))
        if near.size:
            pairs_point.append(np.full(near.size, len(apexes)))
            pairs_tri.append(near)
            apexes.append((i, p))
            bases.append(far)
    if not apexes:
        return out
    # pyramids of different base sizes (a clipped aperture gains a vertex) padded by repeating the last
    # vertex: the polytope is the same, the repeated vertex's zero edges and normals are skipped as axes
    k = max(len(f) for f in bases)
    bases = np.stack([np.concatenate([f, np.repeat(f[-1:], k - len(f), axis=0)]) for f in bases])
    verts, normals, edges = visibility.pyramids(np.array([p for _i, p in apexes]), bases)
    which, tri = np.concatenate(pairs_point), np.concatenate(pairs_tri)
    meets = visibility.triangles_meet_polytopes(rest[tri], verts[which], normals[which], edges[which], tol)
    hit_point, hit_tri = which[meets], tri[meets]  # grouped by pyramid (the pairs were appended in its order)
    ends = np.searchsorted(hit_point, np.arange(len(apexes) + 1))
    for a, (i, _p) in enumerate(apexes):
        out[i] = kept[hit_tri[ends[a]:ends[a + 1]]]
    return out


def inside_prism(vertices, poly, centre, normal, tol):
    """(V,) bool: ``vertices`` whose projection on the convex loop's plane lies inside it (within ``tol``)."""
    rel = vertices - centre
    flat = rel - np.outer(rel @ normal, normal)
    ok = np.ones(len(vertices), bool)
    for j in range(len(poly)):
        edge = poly[(j + 1) % len(poly)] - poly[j]
        inward = np.cross(normal, edge)
        if inward @ (centre - poly[j]) < 0.0:
            inward = -inward
        inward = inward / np.linalg.norm(inward)
        ok &= (flat + centre - poly[j]) @ inward >= -tol
    return ok


def find_apertures(triangles, tol=1e-6):
    """Holes in planar groups of triangles: a list of (vertices (K, 3), plane normal (3,)), each a
    closed boundary loop of its plane's triangles that winds against them (a hole, not an outline).

    Triangles are grouped by plane (normals and offsets within ``tol``), oriented along the group's
    normal, and their edges split at every vertex of the group lying on them (T-junctions: a wall
    built of separate quads around a window); edges used once (after welding within ``tol``) form
    loops. Collinear vertices are dropped from a loop. Holes that are not convex are returned too;
    the closed forms of this module need convex ones (``is_convex`` in the caller).
    """
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if not len(tris):
        return []
    nrm = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    area2 = np.linalg.norm(nrm, axis=1)
    good = area2 > tol * tol
    tris, nrm = tris[good], nrm[good] / area2[good, None]
    # canonical plane key: normal with its first non-zero component positive
    sign = np.where(np.abs(nrm[:, 0]) > tol, np.sign(nrm[:, 0]),
                    np.where(np.abs(nrm[:, 1]) > tol, np.sign(nrm[:, 1]), np.sign(nrm[:, 2])))
    cn = nrm * sign[:, None]
    off = np.einsum("tk,tk->t", cn, tris[:, 0])
    keys = np.round(np.c_[cn, off] / max(tol, 1e-9) / 1e3).astype(np.int64)
    out = []
    _, group = np.unique(keys, axis=0, return_inverse=True)
    for g in np.unique(group):
        sel = np.flatnonzero(group.ravel() == g)
        gt, gn = tris[sel].copy(), cn[sel[0]]
        flip = np.einsum("tk,k->t", nrm[sel], gn) < 0
        gt[flip] = gt[flip][:, ::-1]
        out += [(loop, gn) for loop in _holes(gt, gn, tol)]
    return out


def _holes(tris, normal, tol):
    e1, e2 = plane_axes(normal)
    verts = tris.reshape(-1, 3)
    q = np.round(np.c_[verts @ e1, verts @ e2] / tol).astype(np.int64)
    uniq, inv = np.unique(q, axis=0, return_inverse=True)
    inv = inv.ravel()
    pts = np.zeros((len(uniq), 3))
    pts[inv] = verts
    xy = np.c_[pts @ e1, pts @ e2]
    edges = []
    for t in inv.reshape(-1, 3):
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            # split at every welded vertex strictly inside the edge (T-junctions)
            d = xy[b] - xy[a]
            length2 = d @ d
            s = ((xy - xy[a]) @ d) / length2
            off = np.abs((xy[:, 0] - xy[a, 0]) * d[1] - (xy[:, 1] - xy[a, 1]) * d[0]) / np.sqrt(length2)
            on = np.flatnonzero((off <= tol) & (s > 1e-12) & (s < 1 - 1e-12))
            chain = [a] + list(on[np.argsort(s[on])]) + [b]
            edges += list(zip(chain[:-1], chain[1:]))
    boundary = _union_boundary(edges, xy, tris @ e1, tris @ e2, tol)
    loops, seen = [], set()
    for start in list(boundary):
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen and v in boundary:
            seen.add(v)
            loop.append(v)
            v = boundary[v]
        if v != start or len(loop) < 3:
            continue
        ring = xy[loop]
        # drop collinear vertices
        keep = []
        for k in range(len(loop)):
            a, b, c = ring[k - 1], ring[k], ring[(k + 1) % len(loop)]
            if abs((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])) > tol * np.linalg.norm(c - a):
                keep.append(loop[k])
        ring = xy[keep]
        signed = 0.5 * np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
        if len(keep) >= 3 and signed < 0 and not _filled(ring[::-1], tris, e1, e2, tol):
            loops.append(pts[keep])  # winds against the faces and nothing of the plane fills it: a hole
    return loops


def _union_boundary(edges, xy, tu, tv, tol):
    """{a: b}: the pieces of the plane's edges (``edges``: (a, b) welded vertex indices, each with its triangle on
    its left, the group's triangles counter-clockwise) that bound the UNION of its triangles (``tu``, ``tv``: (T, 3)
    their 2-D coordinates), each once, directed with the union on its left. A piece with a triangle of its own on
    each side is inside; otherwise it bounds the union where nothing of the plane covers the point just beside its
    middle on its open side. Where every edge is used once or twice (a plane of one sheet) these are the pieces
    used once; a face lying on another (a sill's back face on the wall under a window, up to the window's edge)
    no longer hides the edge it shares with that hole (the edge is used twice, both times from below)."""
    sides = {}
    for a, b in edges:
        key = (min(a, b), max(a, b))
        sides.setdefault(key, set()).add(a == key[0])  # True: the triangle lies left of key[0] -> key[1]
    open_pieces = [(k, s.pop()) for k, s in sides.items() if len(s) == 1]
    if not open_pieces:
        return {}
    a = np.array([xy[k[0]] for k, _ in open_pieces])
    b = np.array([xy[k[1]] for k, _ in open_pieces])
    left = np.array([s for _, s in open_pieces])
    d = b - a
    normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.linalg.norm(d, axis=1, keepdims=True)  # left of a -> b
    probe = 0.5 * (a + b) - np.where(left[:, None], 1.0, -1.0) * normal * (4.0 * tol)  # the open side
    covered = _covered(probe, tu, tv, tol)
    return {(k[0] if s else k[1]): (k[1] if s else k[0]) for (k, s), c in zip(open_pieces, covered) if not c}


def _covered(points, tu, tv, tol):
    """(M,) bool: each 2-D point lies inside some triangle (T, 3) of the plane, more than ``tol`` from its edges."""
    orient = np.sign((tu[:, 1] - tu[:, 0]) * (tv[:, 2] - tv[:, 0]) - (tv[:, 1] - tv[:, 0]) * (tu[:, 2] - tu[:, 0]))
    edges = [(i, tu[:, j] - tu[:, i], tv[:, j] - tv[:, i], np.hypot(tu[:, j] - tu[:, i], tv[:, j] - tv[:, i]))
             for i, j in ((0, 1), (1, 2), (2, 0))]
    out = np.zeros(len(points), bool)
    for s in range(0, len(points), 256):
        p = points[s:s + 256]
        inside = np.ones((len(p), len(tu)), bool)
        for i, eu, ev, length in edges:
            with np.errstate(divide="ignore", invalid="ignore"):
                dist = orient * (eu * (p[:, 1:2] - tv[:, i]) - ev * (p[:, 0:1] - tu[:, i])) / length
            inside &= dist > tol
        out[s:s + 256] = inside.any(axis=1)
    return out


def _ear_triangles(ring):
    """Triangles (M, 3, 2) of the simple counter-clockwise polygon ``ring`` (K, 2), by ear clipping."""
    idx, out = list(range(len(ring))), []
    while len(idx) > 3:
        for k in range(len(idx)):
            a, b, c = ring[idx[k - 1]], ring[idx[k]], ring[idx[(k + 1) % len(idx)]]
            if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0:
                continue  # a reflex (or straight) corner is no ear
            others = ring[[i for i in idx if i not in (idx[k - 1], idx[k], idx[(k + 1) % len(idx)])]]
            d = [(q[0] - p[0]) * (others[:, 1] - p[1]) - (q[1] - p[1]) * (others[:, 0] - p[0])
                 for p, q in ((a, b), (b, c), (c, a))]
            if np.any((d[0] >= 0) & (d[1] >= 0) & (d[2] >= 0)):
                continue  # another corner lies in it
            out.append((a, b, c))
            del idx[k]
            break
        else:
            break  # degenerate ring: keep what was clipped
    out.append(tuple(ring[i] for i in idx[:3]))
    return np.array(out, float)


def _filled(ring, tris, e1, e2, tol):
    """True when a triangle of the plane's group (either facing) overlaps the inside of the
    counter-clockwise loop ``ring`` (K, 2) by more than ``tol``: the loop is then no opening but the
    edge of a face lying on another one. Boxes standing on a floor make this: the walls' bottom faces
    form a ring around the floor's top face, coplanar with it (2D separating axes, per ear of the loop)."""
    t2 = np.stack([tris @ e1, tris @ e2], axis=-1)                          # (T, 3, 2)
    for ear in _ear_triangles(ring):
        d = np.concatenate([np.broadcast_to(np.roll(ear, -1, axis=0) - ear, t2.shape), np.roll(t2, -1, axis=1) - t2],
                           axis=1)                                         # (T, 6, 2): the ear's edges, the triangle's
        axes = _unit(np.stack([-d[..., 1], d[..., 0]], axis=-1))          # (T, 6, 2)
        pe = np.einsum("tak,vk->tav", axes, ear)
        pt = np.einsum("tak,tvk->tav", axes, t2)
        gap = np.maximum(pt.min(axis=2) - pe.max(axis=2), pe.min(axis=2) - pt.max(axis=2))
        if np.any(np.all(gap < -tol, axis=1)):
            return True
    return False


def is_convex(vertices, tol=1e-9):
    """True when the planar polygon (K, 3) is convex (every turn the same way)."""
    v = np.asarray(vertices, float)
    normal, _ = polygon_plane(v)
    turns = np.einsum("kj,j->k", np.cross(np.roll(v, -1, axis=0) - v, np.roll(v, -2, axis=0) - np.roll(v, -1, axis=0)),
                      normal)
    return bool(np.all(turns >= -tol) or np.all(turns <= tol))


# --- closure: every direction from the point leaves through an aperture or meets the enclosure ---------

#: Above this many triangles in the enclosure's search, :func:`enclosure_closed` declines (its edge
#: splitting is O(edges x vertices)): "not proven", never a wrong answer.
CLOSURE_MAX_TRIANGLES = 20000


def _weld(points, tol):
    q = np.round(np.asarray(points, float) / tol).astype(np.int64)
    uniq, inv = np.unique(q, axis=0, return_inverse=True)
    inv = inv.ravel()
    pts = np.zeros((len(uniq), 3))
    pts[inv] = points
    return pts, inv


def _split_edges(pts, edges, tol):
    """Edges (E, 2) split at every welded vertex lying strictly inside them: list of (a, b)."""
    out = []
    for a, b in edges:
        d = pts[b] - pts[a]
        length2 = d @ d
        if length2 <= tol * tol:
            continue
        s = ((pts - pts[a]) @ d) / length2
        off = np.linalg.norm(np.cross(pts - pts[a], d), axis=1) / np.sqrt(length2)
        on = np.flatnonzero((off <= tol) & (s * np.sqrt(length2) > tol) & ((1 - s) * np.sqrt(length2) > tol))
        chain = [a] + list(on[np.argsort(s[on])]) + [b]
        out += list(zip(chain[:-1], chain[1:]))
    return out


def _on_polygon_edge(x, y, loops, tol):
    for poly in loops:
        for k in range(len(poly)):
            a, b = poly[k], poly[(k + 1) % len(poly)]
            d = b - a
            length = np.linalg.norm(d)
            ok = True
            for p in (x, y):
                s = (p - a) @ d / (length * length)
                if not (-tol / length <= s <= 1 + tol / length and np.linalg.norm(np.cross(p - a, d)) / length <= tol):
                    ok = False
            if ok:
                return True
    return False


def _vertex_parts(count, edges):
    """(count,) the connected part (a root vertex) of every vertex, vertices joined by ``edges`` (E, 2):
    union-find."""
    parent = np.arange(count)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in edges:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
    return np.array([find(i) for i in range(count)])


def triangle_parts(triangles, tol):
    """(welded vertices (V, 3), vertex ids (T, 3), part root per vertex (V,)): the connected parts of
    ``triangles`` (T, 3, 3), vertices welded within ``tol`` m and joined by the triangles' edges."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    pts, inv = _weld(tris.reshape(-1, 3), tol)
    ids = inv.reshape(-1, 3)
    return pts, ids, _vertex_parts(len(pts), np.r_[ids[:, [0, 1]], ids[:, [1, 2]]])


#: Largest count of triangles whose T-junctions ``closed_components`` splits (each edge against every vertex:
#: 0.6 s for 2300 triangles); larger sets count welded edges only (a T-junction then reads as open).
SPLIT_MAX_TRIANGLES = 500


def closed_components(triangles, tol):
    """The connected parts of ``triangles`` (T, 3, 3) that are closed surfaces: a list of index arrays, one
    per part whose every edge is used by an even number of its triangles (``enclosure_closed``: two boxes that
    share an edge are one such part; vertices welded within ``tol`` m;
    degenerate triangles left out). A closed surface parts space in two: a path from a point of odd
    crossing parity to one of even parity crosses it (``inside_enclosures``). Edges are counted as welded;
    a part that is not closed that way is tried again with its edges split at T-junctions (as
    :func:`enclosure_closed`) when it has at most ``SPLIT_MAX_TRIANGLES`` triangles."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if not len(tris) or len(tris) > CLOSURE_MAX_TRIANGLES:
        return []
    pts, inv = _weld(tris.reshape(-1, 3), tol)
    ids = inv.reshape(-1, 3)
    keep = np.flatnonzero((ids[:, 0] != ids[:, 1]) & (ids[:, 1] != ids[:, 2]) & (ids[:, 2] != ids[:, 0]))
    ids = ids[keep]
    edges = np.sort(np.stack([ids, np.roll(ids, -1, axis=1)], axis=-1).reshape(-1, 2), axis=1)
    uniq, which, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    roots = _vertex_parts(len(pts), uniq)
    tri_roots = roots[ids[:, 0]]  # a triangle in its first vertex's part
    edge_ok = (counts % 2 == 0)[which.ravel()].reshape(-1, 3).all(axis=1)  # per triangle: 3 edges used evenly
    out = []
    for r in np.unique(tri_roots):
        part = np.flatnonzero(tri_roots == r)
        if edge_ok[part].all():
            out.append(keep[part])
        elif len(part) <= SPLIT_MAX_TRIANGLES and enclosure_closed_part(tris[keep[part]], tol):
            out.append(keep[part])
    return out


def edge_pieces(triangles, tol):
    """(welded vertices (V, 3), vertex ids (T, 3), {(a, b) with a < b: uses}) of ``triangles`` (T, 3, 3): vertices
    welded within ``tol`` m, every edge split at the welded vertices lying inside it (T-junctions), and how many
    triangles use each piece (in the order the pieces first come). O(edges x vertices): the callers bound the count
    (``CLOSURE_MAX_TRIANGLES``); one search may hand the result to both :func:`shell_holes` and
    :func:`enclosure_closed`."""
    pts, inv = _weld(np.asarray(triangles, float).reshape(-1, 3), tol)
    ids = inv.reshape(-1, 3)
    uses = {}
    for a, b in _split_edges(pts, [(t[i], t[(i + 1) % 3]) for t in ids for i in range(3)], tol):
        key = (min(a, b), max(a, b))
        uses[key] = uses.get(key, 0) + 1
    return pts, ids, uses


def enclosure_closed_part(triangles, tol):
    """True when the connected ``triangles`` (T, 3, 3) form a closed surface with their edges split at
    T-junctions (every piece of edge used an even number of times: two closed surfaces may share an edge,
    ``enclosure_closed``)."""
    uses = edge_pieces(triangles, tol)[2]
    return bool(uses) and all(c % 2 == 0 for c in uses.values())


def _on_outline(points, poly, tol):
    """(P,) bool: ``points`` (P, 3) lying on the outline of the polygon ``poly`` (K, 3) within ``tol`` m."""
    pts = np.asarray(points, float).reshape(-1, 3)
    a, b = poly, np.roll(poly, -1, axis=0)
    d = b - a
    length = np.maximum(np.linalg.norm(d, axis=1), 1e-300)
    s = np.einsum("pkj,kj->pk", pts[:, None, :] - a[None], d) / length ** 2
    off = np.linalg.norm(np.cross(pts[:, None, :] - a[None], d[None]), axis=2) / length
    return np.any((off <= tol) & (s >= -tol / length) & (s <= 1 + tol / length), axis=1)


def shell_holes(triangles, loops, tol, pieces=None):
    """The ``loops`` (from :func:`find_apertures`) that are holes of the surface ``triangles`` (T, 3, 3) makes: each
    piece of its outline is used by an odd number of triangles (vertices welded within ``tol`` m, edges split at
    T-junctions; ``pieces``: :func:`edge_pieces` of them, when the caller has it). A hole in a plane whose outline
    other faces close is none: the ring of a window frame's front faces (its inner faces use the same edges), the
    mouth of a tunnel through a solid wall (its reveal does)."""
    if not loops:
        return []
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if len(tris) > CLOSURE_MAX_TRIANGLES:
        return list(loops)  # not checked here: enclosure_closed declines such a scene anyway
    pts, _ids, uses = edge_pieces(tris, tol) if pieces is None else pieces
    if not uses:
        return []
    ends = np.array(list(uses), int)                                      # (E, 2) the pieces
    odd = np.array(list(uses.values())) % 2 == 1
    kept = []
    for poly in loops:
        on = _on_outline(pts, poly, tol)
        outline = np.flatnonzero(on[ends[:, 0]] & on[ends[:, 1]])
        outline = outline[_on_outline(0.5 * (pts[ends[outline, 0]] + pts[ends[outline, 1]]), poly, tol)]
        if outline.size and np.all(odd[outline]):
            kept.append(poly)
    return kept


def enclosure_closed(triangles, loops, tol, pieces=None):
    """(closed, component mask (T,), reason): whether the triangles connected to the aperture ``loops``
    (a list of (K, 3) polygons) form a closed surface apart from exactly those holes (vertices welded
    within ``tol`` m, edges split at T-junctions, every edge used an even number of times except those
    on an aperture's outline, used an odd number of times: once, or three times where a sill's back and top faces
    meet the wall at the window's edge). ``component`` marks those triangles.

    Even, not exactly twice: a cabinet or a column standing against a wall is a closed box whose edges lie
    on the room's (an edge piece used four times). Closed in this sense (a cycle modulo 2: every piece of
    edge bounds an even number of triangles) is what the proofs use: a path from a point of odd crossing
    parity to one of even parity crosses the surface (``inside_enclosures``), and the inside of the box
    against the wall counts as outside the room, as it is. ``pieces``: :func:`edge_pieces` of the triangles, when
    the caller has it."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    none = np.zeros(len(tris), bool)
    if len(tris) > CLOSURE_MAX_TRIANGLES:
        return False, none, f"more than {CLOSURE_MAX_TRIANGLES} triangles: closure not checked"
    pts, ids, uses = edge_pieces(tris, tol) if pieces is None else pieces
    roots = _vertex_parts(len(pts), list(uses))
    loop_pts = np.concatenate(loops)
    near = np.flatnonzero(np.min(np.linalg.norm(pts[:, None, :] - loop_pts[None], axis=2), axis=1) <= tol)
    if not near.size:
        return False, none, "the apertures' outlines are not edges of the scene's surfaces"
    chosen = set(roots[near].tolist())
    comp = np.isin(roots[ids[:, 0]], list(chosen))
    for (a, b), c in uses.items():
        if c % 2 == 0 or roots[a] not in chosen:
            continue
        if _on_polygon_edge(pts[a], pts[b], loops, tol):
            continue  # odd on an opening's outline: its cap makes it even (3: a sill's faces meet the wall there)
        where = np.round(0.5 * (pts[a] + pts[b]), 3).tolist()
        return False, comp, (f"the surface around the openings is not closed (an edge near {where} m is used {c} "
                             "time(s)): sky may enter elsewhere")
    return True, comp, ""


def inside_enclosure(point, triangles, loops, tol):
    """True / False / None (undecided): whether ``point`` lies inside the closed surface made of
    ``triangles`` and the apertures' ``loops`` as caps: the parity of a ray's crossings, for the first
    of a few fixed directions whose every crossing is clear of edges by ``tol`` m."""
    return inside_enclosures([point], triangles, loops, tol)[0]


def inside_enclosures(points, triangles, loops, tol):
    """:func:`inside_enclosure` for many points (P, 3) at once: a list of True / False / None."""
    caps = [fan_triangles(poly) for poly in loops]
    tris = np.concatenate([np.asarray(triangles, float).reshape(-1, 3, 3)] + caps)
    pts = np.atleast_2d(np.asarray(points, float))
    out = [None] * len(pts)
    todo = np.arange(len(pts))
    dirs = _unit(np.array([[0.5358, 0.2672, 0.8010], [-0.3111, 0.8409, 0.4427], [0.7071, -0.6124, -0.3536],
                           [-0.6, -0.48, 0.64], [0.1, -0.2, -0.97468]]))
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    scale = np.maximum(np.linalg.norm(e1, axis=1), np.linalg.norm(e2, axis=1))
    m = tol / np.maximum(scale, 1e-300)
    for d in dirs:
        if not todo.size:
            break
        h = np.cross(d, e2)
        det = np.einsum("tk,tk->t", e1, h)
        s = pts[todo, None, :] - v0[None]                                      # (P, T, 3)
        with np.errstate(divide="ignore", invalid="ignore"):
            f = 1.0 / det
            u = f * np.einsum("ptk,tk->pt", s, h)
            q = np.cross(s, e1[None])
            v = f * (q @ d)
            t = f * np.einsum("ptk,tk->pt", q, e2)
        ok = np.isfinite(f) & (np.abs(det) > 1e-12 * scale ** 2)              # (T,)
        w = 1.0 - u - v
        hit = ok & (u > m) & (v > m) & (w > m) & (t > tol)
        miss = ~ok | (u < -m) | (v < -m) | (w < -m) | (t < -tol)
        # a parallel triangle is missed only if the ray's line stays off its plane
        if np.any(~ok):
            nrm = _unit(np.cross(e1[~ok], e2[~ok]))
            miss[:, ~ok] = np.abs(np.einsum("ptk,tk->pt", s[:, ~ok], nrm)) > tol
        decided = np.all(hit | miss, axis=1)
        for j in np.flatnonzero(decided):
            out[todo[j]] = bool(np.count_nonzero(hit[j]) % 2)
        todo = todo[~decided]
    return out

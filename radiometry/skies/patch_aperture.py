"""The direct light of each sky patch through convex openings, in closed form (pure numpy).

For daylight coefficients (issue 31): a point that sees the world through open, convex openings, with
nothing between it and them and nothing outside in front of them (``measure.analyses.sky_component``
proves that), receives from sky patch i of unit luminance exactly

    D[i] = integral over (patch i) n (opening) n (the receiver's upper hemisphere) of (n . u) du   (sr)

A patch is the radial projection of its triangles on the dome that the renders use
(``sky_patches.dome_mesh``: great-circle edges, altitude circles as 1-degree chords), so the closed form
and the dome split the sphere the same way. The opening seen from the point is a convex cone; each dome
triangle is one too; their intersection, clipped to the receiver's horizon, is a convex spherical
polygon whose first moment is Lambert's contour formula (``sky_aperture.spherical_moments``, Arvo 1995).
Patch 0 (the ground) is the lower hemisphere, as in ``sky_patches``.
"""

import numpy as np

from . import sky_aperture, sky_patches

__all__ = ["dome_triangles", "patch_coefficients", "pane_patch_coefficients"]


def dome_triangles(patches, step_deg=1.0):
    """(T, 3, 3) unit triangles of ``sky_patches.dome_mesh``, counter-clockwise seen from outside, and
    (T,) the patch each belongs to."""
    tris, owner = [], []
    for i, (verts, faces) in enumerate(sky_patches.dome_mesh(patches, step_deg)):
        t = verts[faces]
        flip = np.einsum("tk,tk->t", t[:, 0], np.cross(t[:, 1], t[:, 2])) < 0.0
        t[flip] = t[flip][:, [0, 2, 1]]
        tris.append(t)
        owner.append(np.full(len(t), i))
    return np.concatenate(tris), np.concatenate(owner)


def _clip(poly, count, normal):
    """Convex polygons (B, K, 3) with ``count`` (B,) vertices clipped to ``normal . x >= 0`` (B, 3) at once
    (Sutherland-Hodgman, points on the plane kept): (B, K + 1, 3) and the new counts."""
    b, k, _ = poly.shape
    idx = np.arange(k)
    valid = idx[None, :] < count[:, None]
    h = np.einsum("bkc,bc->bk", poly, normal)
    nxt = (idx[None, :] + 1) % np.maximum(count[:, None], 1)
    following = np.take_along_axis(poly, nxt[..., None], axis=1)
    h_next = np.take_along_axis(h, nxt, axis=1)
    keep = valid & (h >= 0.0)
    cross = valid & ((h >= 0.0) != (h_next >= 0.0))
    t = h / np.where(cross, h - h_next, 1.0)
    x = poly + t[..., None] * (following - poly)
    out = np.stack([poly, x], axis=2).reshape(b, 2 * k, 3)
    mask = np.stack([keep, cross], axis=2).reshape(b, 2 * k)
    order = np.argsort(~mask, axis=1, kind="stable")
    out = np.take_along_axis(out, order[..., None], axis=1)[:, :k + 1]
    return out, np.minimum(mask.sum(axis=1), k + 1)


def _edge_planes(poly, count):
    """Inward unit normals (B, K, 3) of the great circles through the edges of convex polygons (B, K, 3) with
    ``count`` vertices (rows past the count: 0, which every point satisfies)."""
    k = np.arange(poly.shape[1])
    nxt = (k[None, :] + 1) % np.maximum(count[:, None], 1)
    following = np.take_along_axis(poly, nxt[..., None], axis=1)
    raw = np.cross(poly, following)
    # an edge between two (nearly) coincident vertices has no plane of its own (its cross product is rounding):
    # left out, which every point satisfies (the polygon's other edges bound it)
    size = np.linalg.norm(raw, axis=-1)
    real = size > 1e-12 * np.linalg.norm(poly, axis=-1) * np.linalg.norm(following, axis=-1)
    edge = sky_aperture._unit(raw)
    edge = np.where(((k[None, :] < count[:, None]) & real)[..., None], edge, 0.0)
    # a convex polygon lies on one side of each edge: the side of its vertex centroid
    valid = (k[None, :] < count[:, None])[..., None]
    inward = np.sign(np.einsum("bek,bk->be", edge, np.where(valid, poly, 0.0).sum(axis=1)))
    return edge * inward[..., None]


def _caps(directions, valid=None):
    """Enclosing caps of direction sets (..., V, 3) (``valid`` (..., V) marks the members): unit centre (..., 3)
    and angular radius (...,)."""
    u = sky_aperture._unit(directions)
    if valid is not None:
        u = np.where(valid[..., None], u, 0.0)
    c = sky_aperture._unit(u.sum(axis=-2))
    cos = np.einsum("...vk,...k->...v", u, c)
    if valid is not None:
        cos = np.where(valid, cos, 1.0)
    radius = np.arccos(np.clip(cos.min(axis=-1), -1.0, 1.0))
    # a cap wider than a hemisphere is not convex: it holds the vertices but not the arcs between them (a point
    # next to its opening sees it over more than 180 degrees), so such a set's cap is the whole sphere
    return c, np.where(radius >= 0.5 * np.pi, np.pi, radius)


def _pieces(above, count, tris, owner, planes, caps):
    """The convex cones ``above`` (n, K, 3) (``count`` vertices each) cut by the dome's triangles, as spherical
    triangles: (point index (M,), patch (M,), triangles (M, 3, 3)). A dome triangle wholly inside a cone is a
    piece whole, one wholly outside none, the rest are clipped and fanned."""
    valid = (np.arange(above.shape[1])[None, :] < count[:, None])
    # first the triangles whose enclosing caps meet some cone's cap (a cheap superset of those that matter)
    c, radius = _caps(above, valid)
    t_centre, t_radius = caps
    near = np.any(np.arccos(np.clip(c @ t_centre.T, -1.0, 1.0)) <= radius[:, None] + t_radius[None, :] + 1e-9,
                  axis=0)
    keep = np.flatnonzero(near)
    tris, owner, planes = tris[keep], owner[keep], planes[keep]
    edge = _edge_planes(above, count)                                                # (n, K, 3)
    n, t_count = len(above), len(tris)
    if not t_count or not n:  # no cone here (a slot that no point of this chunk fills), or none near the dome's
        return np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3, 3))
    # corners against the cone's edges (n, E, T, 3), as one matrix product
    d = np.matmul(edge, tris.reshape(-1, 3).T).reshape(n, edge.shape[1], t_count, 3)
    inside = np.all(d >= 0.0, axis=(1, 3)) & (count >= 3)[:, None]
    outside = np.any(np.all(d < 0.0, axis=3), axis=1) | (count < 3)[:, None]
    # or the cone's corners all beyond one edge of the triangle
    beyond = (np.matmul(planes.reshape(-1, 3), above.transpose(0, 2, 1)) < 0.0).reshape(n, t_count, 3, -1)
    outside |= np.any(np.all(beyond | ~valid[:, None, None, :], axis=3), axis=2)
    p_in, t_in = np.nonzero(inside)
    points_at, patches_of, pieces = [p_in], [owner[t_in]], [tris[t_in]]
    p, t = np.nonzero(~inside & ~outside)
    if len(p):
        cur, cnt = above[p], count[p]
        for e in range(3):
            cur, cnt = _clip(cur, cnt, planes[t, e])
            cur = cur[:, :max(int(cnt.max()), 1)]
        k = cur.shape[1]
        if k >= 3:
            fan = np.stack([np.broadcast_to(cur[:, :1], (len(cur), k - 2, 3)), cur[:, 1:-1], cur[:, 2:]], axis=2)
            which = np.nonzero((np.arange(k - 2)[None, :] + 2) < cnt[:, None])
            points_at.append(p[which[0]])
            patches_of.append(owner[t[which[0]]])
            pieces.append(fan[which])
    return np.concatenate(points_at), np.concatenate(patches_of), np.concatenate(pieces)


def _cones(polys, points, normals):
    """Each point's opening (one (K, 3) polygon for all, or (N, K, 3) with ``counts``) relative to it, clipped to
    its horizon: (N, K + 1, 3) and the vertex counts."""
    polys, counts = polys
    rel = (polys[None, :, :] if polys.ndim == 2 else polys) - points[:, None, :]
    return _clip(rel, np.broadcast_to(counts, (len(points),)).copy(), normals)


def _dome(patches, step_deg, dome):
    tris, owner = dome if dome is not None else dome_triangles(patches, step_deg)
    # each triangle's cone as three planes through the origin (counter-clockwise: interior on their + side)
    return tris, owner, np.cross(tris, tris[:, [1, 2, 0]]), _caps(tris)


def patch_coefficients(openings, points, normals, patches, *, step_deg=1.0, dome=None, chunk=32):
    """(N, P) sr: the closed form above for N points (metres), unit ``normals``, and the convex ``openings`` (a
    list of (K, 3) vertex arrays in the points' frame, any orientation, or of ((N, K, 3), counts (N,)): one
    polygon per point), summed over the openings (they must not overlap as seen from a point: openings in one
    closed shell do not). ``patches``: a :class:`sky_patches.SkyPatches`; ``dome``: its :func:`dome_triangles`
    if the caller has them."""
    points = np.atleast_2d(np.asarray(points, float))
    normals = np.broadcast_to(np.asarray(normals, float), points.shape)
    tris, owner, planes, caps = _dome(patches, step_deg, dome)
    out = np.zeros((len(points), patches.count))
    for poly in openings:
        poly = (np.asarray(poly, float), len(poly)) if not isinstance(poly, tuple) else \
            (np.asarray(poly[0], float), np.asarray(poly[1], int))
        above, above_count = _cones(poly, points, normals)
        for lo in range(0, len(points), chunk):
            sl = slice(lo, lo + chunk)
            p, patch, pieces = _pieces(above[sl], above_count[sl], tris, owner, planes, caps)
            if len(p):
                _o, first, _s = sky_aperture.spherical_moments(pieces, np.zeros(3), normals[sl][p])
                np.add.at(out[sl], (p, patch), first)
    return out


def pane_patch_coefficients(opening, cores, points, normals, patches, transmittance, pane_normal, *, step_deg=1.0,
                            dome=None, chunk=32, rel_tol=1e-3, max_splits=6):
    """(estimate (N, P), half-width (N, P)) sr: each patch's direct light through a convex ``opening`` glazed with
    a thin pane of ``transmittance(cos_i)`` (vectorised, non-decreasing in cos_i = |pane_normal . u|): the truth
    lies within estimate +- half-width (a hard bound). ``cores``: ((N, K, 3), counts (N,)), per point the part of
    the opening whose directions enter the pane's near face inside its outline (``sky_component._pane_core``);
    on each piece T lies between its values at the piece's exact cosine extremes (``sky_aperture._cos_range``),
    pieces halved up to ``max_splits`` times until their bound is within ``rel_tol`` of their light. The rim
    (the opening outside the core: rays that may pass beside the pane) lies between 0 and its open closed form.
    Past obstructions beyond the pane (``measure.analyses.sky_component``): ``cores`` a list of such per-point
    slots (each point's pieces of its core, counts 0 where it has fewer) and ``opening`` the list of slots of
    each point's pieces of the opening (``patch_coefficients``' per-point form)."""
    points = np.atleast_2d(np.asarray(points, float))
    normals = np.broadcast_to(np.asarray(normals, float), points.shape)
    dome = _dome(patches, step_deg, dome)
    table = sky_aperture._transmittance_table(transmittance)
    m = np.asarray(pane_normal, float) / np.linalg.norm(pane_normal)
    est, half, core = (np.zeros((len(points), patches.count)) for _ in range(3))
    for core_polys, core_counts in (cores if isinstance(cores, list) else [cores]):
        _bounded_core(np.asarray(core_polys, float), np.asarray(core_counts, int), points, normals, dome, table, m,
                      chunk, rel_tol, max_splits, est, half, core)
    whole = patch_coefficients(opening if isinstance(opening, list) else [opening], points, normals, patches,
                               dome=dome[:2], chunk=chunk)
    rim = np.maximum(whole - core, 0.0)
    return est + 0.5 * rim, half + 0.5 * rim


def _bounded_core(core_polys, core_counts, points, normals, dome, table, m, chunk, rel_tol, max_splits, est, half,
                  core):
    """One slot of cores (``pane_patch_coefficients``): adds its T-weighted estimate, half-width and unweighted
    light to ``est``, ``half`` and ``core`` (N, P) in place."""
    last = len(table) - 1
    above, above_count = _cones((core_polys, core_counts), points, normals)
    for lo in range(0, len(points), chunk):
        sl = slice(lo, lo + chunk)
        p, patch, pieces = _pieces(above[sl], above_count[sl], *dome)
        for level in range(max_splits + 1):
            if not len(p):
                break
            arcs = sky_aperture._arcs(pieces)
            _o, first, _s = sky_aperture.spherical_moments(pieces, np.zeros(3), normals[sl][p], arcs)
            # cos_i = |m . u|: every direction through one opening crosses the pane the same way
            c_lo, c_hi = sky_aperture._cos_range(pieces, m, arcs)
            flip = c_hi <= 0.0
            c_lo, c_hi = np.where(flip, -c_hi, c_lo), np.where(flip, -c_lo, c_hi)
            t_lo = table[np.clip(np.floor(np.clip(c_lo, 0.0, 1.0) * last).astype(int), 0, last)]
            t_hi = table[np.clip(np.ceil(np.clip(c_hi, 0.0, 1.0) * last).astype(int), 0, last)]
            if level == 0:  # the core's light unweighted (its pieces, before any split), for the rim below
                np.add.at(core[sl], (p, patch), first)
            e, h = 0.5 * (t_lo + t_hi) * first, 0.5 * (t_hi - t_lo) * np.abs(first)
            wide = (h > rel_tol * np.abs(e)) & (level < max_splits)
            np.add.at(est[sl], (p[~wide], patch[~wide]), e[~wide])
            np.add.at(half[sl], (p[~wide], patch[~wide]), h[~wide])
            p, patch = np.repeat(p[wide], 2), np.repeat(patch[wide], 2)
            halves = sky_aperture._split(pieces[wide])                            # [first halves, second halves]
            count = int(wide.sum())
            pieces = np.stack([halves[:count], halves[count:]], axis=1).reshape(-1, 3, 3)

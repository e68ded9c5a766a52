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

__all__ = ["dome_triangles", "patch_coefficients"]


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


def _first_moments(poly, count, normal):
    """int (normal . u) du over each convex spherical polygon (B,): fanned into triangles."""
    b, k, _ = poly.shape
    if k < 3:
        return np.zeros(b)
    j = np.arange(k - 2)
    tris = np.stack([np.broadcast_to(poly[:, :1], (b, k - 2, 3)), poly[:, 1:-1], poly[:, 2:]], axis=2)
    ok = (j[None, :] + 2) < count[:, None]
    which = np.nonzero(ok)
    if not len(which[0]):
        return np.zeros(b)
    _omega, first, _second = sky_aperture.spherical_moments(tris[which], np.zeros(3), normal[which[0]])
    out = np.zeros(b)
    np.add.at(out, which[0], first)
    return out


def _edge_planes(poly, count):
    """Inward unit normals (B, K, 3) of the great circles through the edges of convex polygons (B, K, 3) with
    ``count`` vertices (rows past the count: 0, which every point satisfies)."""
    k = np.arange(poly.shape[1])
    nxt = (k[None, :] + 1) % np.maximum(count[:, None], 1)
    edge = sky_aperture._unit(np.cross(poly, np.take_along_axis(poly, nxt[..., None], axis=1)))
    edge = np.where((k[None, :] < count[:, None])[..., None], edge, 0.0)
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
    return c, np.arccos(np.clip(cos.min(axis=-1), -1.0, 1.0))


def _add_opening(out, above, count, normals, tris, owner, planes, caps):
    """Add to ``out`` (n, P) the moments of the convex cones ``above`` (n, K, 3) (``count`` vertices each) cut by
    the dome's triangles: a triangle wholly inside a cone counts whole, one wholly outside not at all, the rest are
    clipped."""
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
    # corners against the cone's edges (n, E, T, 3), as one matrix product
    d = np.matmul(edge, tris.reshape(-1, 3).T).reshape(n, edge.shape[1], t_count, 3)
    inside = np.all(d >= 0.0, axis=(1, 3)) & (count >= 3)[:, None]
    outside = np.any(np.all(d < 0.0, axis=3), axis=1) | (count < 3)[:, None]
    # or the cone's corners all beyond one edge of the triangle
    beyond = (np.matmul(planes.reshape(-1, 3), above.transpose(0, 2, 1)) < 0.0).reshape(n, t_count, 3, -1)
    outside |= np.any(np.all(beyond | ~valid[:, None, None, :], axis=3), axis=2)
    p, t = np.nonzero(inside)
    if len(p):
        _o, first, _s = sky_aperture.spherical_moments(tris[t], np.zeros(3), normals[p])
        np.add.at(out, (p, owner[t]), first)
    p, t = np.nonzero(~inside & ~outside)
    if len(p):
        cur, cnt = above[p], count[p]
        for e in range(3):
            cur, cnt = _clip(cur, cnt, planes[t, e])
            cur = cur[:, :max(int(cnt.max()), 1)]
        np.add.at(out, (p, owner[t]), _first_moments(cur, cnt, normals[p]))


def patch_coefficients(openings, points, normals, patches, *, step_deg=1.0, dome=None, chunk=32):
    """(N, P) sr: the closed form above for N points (metres), unit ``normals``, and the convex ``openings`` (a
    list of (K, 3) vertex arrays in the points' frame, any orientation), summed over the openings (they must
    not overlap as seen from a point: openings in one closed shell do not). ``patches``: a
    :class:`sky_patches.SkyPatches`; ``dome``: its :func:`dome_triangles` if the caller has them."""
    points = np.atleast_2d(np.asarray(points, float))
    normals = np.broadcast_to(np.asarray(normals, float), points.shape)
    tris, owner = dome if dome is not None else dome_triangles(patches, step_deg)
    # each triangle's cone as three planes through the origin (counter-clockwise: interior on their + side)
    planes = np.cross(tris, tris[:, [1, 2, 0]])
    caps = _caps(tris)
    out = np.zeros((len(points), patches.count))
    for poly in openings:
        poly = np.asarray(poly, float)
        rel = poly[None, :, :] - points[:, None, :]                                   # (N, K, 3)
        # the part above each receiver's horizon, once per point
        above, above_count = _clip(rel, np.full(len(points), len(poly)), normals)
        for lo in range(0, len(points), chunk):
            sl = slice(lo, lo + chunk)
            _add_opening(out[sl], above[sl], above_count[sl], normals[sl], tris, owner, planes, caps)
    return out

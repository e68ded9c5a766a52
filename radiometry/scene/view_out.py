"""What an eye sees out of a room's openings, for EN 17037's "view out" (pure numpy, never imports bpy).

From each eye, rays are cast through its windows (``skies.sky_aperture.find_apertures``: the holes of
the opaque surfaces whose plane leans at most ``MAX_TILT_FROM_VERTICAL_DEG`` from the vertical: roof lights
show the sky above, not a view out; a pane in an opening is looked through) on a grid of directions
``STEP_DEG`` apart in azimuth and ``ROWS`` rows in elevation across each opening as the eye sees it. The
eye's room is the connected surfaces first met round it; its windows are the openings on them. A ray
counts when it crosses the opening's polygon, nothing opaque stands between the eye and the opening (an
inner wall, a baffle), and what it meets beyond is not the eye's own building (the room, the windows'
frames and reveals, and parts built within ``OWN_GAP_M`` of the room: an overhang, fins, a parapet).
Beyond the opening, its first opaque surface says what it sees:

- **sky**: nothing, above the horizon;
- **ground**: nothing, below the horizon (the ground of the sky model: an endless plane below the
  horizon), or a surface facing up (normal within ``GROUND_TILT_DEG`` of the zenith) below the eye: a
  modelled ground, street or lawn; a lower roof counts as ground too, as a street would;
- **landscape**: any other surface: buildings, terrain, trees, a neighbour's wall.

Per eye: the **horizontal sight angle** is the largest run of adjoining azimuth steps in which some ray
went out (an opening hidden behind a column gives two runs; the larger counts), to within one step; the
**outside distance** is the median distance from the opening to the first surface beyond it, over the
rays that went out within ``LEVEL_BAND_DEG`` of the horizontal (all rays that went out when none did:
a high window); inf when those rays meet nothing (no surroundings in front are modelled).

A scene that models nothing outside its openings but a flat ground (no building, terrain or tree,
separate from the room or seen through an opening) cannot tell a landscape layer or an outside distance:
:func:`surroundings_modelled` says so, and the caller reports "not assessed" rather than "not met".

Coordinates in metres, Z up.
"""

import dataclasses
import math

import numpy as np

from ..skies import sky_aperture

__all__ = ["SceneParts", "scene_parts", "LAYERS", "STEP_DEG", "ROWS", "GROUND_TILT_DEG", "LEVEL_BAND_DEG",
           "MAX_TILT_FROM_VERTICAL_DEG", "OWN_GAP_M", "EyeView", "eye_views", "first_hits_many",
           "surroundings_modelled"]

LAYERS = ("sky", "landscape", "ground")
#: azimuth step of the rays (deg): the sight angle is known to within one step
STEP_DEG = 0.5
#: rows of rays in elevation across each opening as an eye sees it
ROWS = 8
#: a surface whose normal is within this angle of the zenith, below the eye, is ground (deg)
GROUND_TILT_DEG = 30.0
#: an opening whose plane leans further than this from the vertical (a roof light) gives no view out (deg)
MAX_TILT_FROM_VERTICAL_DEG = 30.0
#: a part whose box comes this close to the eye's room's box is built onto it (an overhang, fins, a balcony
#: modelled as separate boxes): the building, not the view (m)
OWN_GAP_M = 0.5
#: rays within this elevation of the horizontal measure the outside distance (deg)
LEVEL_BAND_DEG = 10.0
#: pairs of (ray, triangle) tested in one numpy step (memory: about 200 bytes each)
_CHUNK_PAIRS = 200_000


@dataclasses.dataclass
class EyeView:
    """The view out of one eye. ``layers``: the layers seen (a subset of :data:`LAYERS`, in that order);
    ``rays_out``: rays that went out through an opening (0: no opening is seen from this eye)."""

    eye: tuple
    horizontal_sight_angle_deg: float
    outside_distance_m: float
    layers: tuple
    rays_out: int

    def layer_score(self):
        """EN 17037's count of layers: 0 unless the landscape layer is among them."""
        return len(self.layers) if "landscape" in self.layers else 0


def first_hits_many(origins, directions, triangles):
    """Nearest hit of R rays (``origins``, unit ``directions``: (R, 3)) against triangles (T, 3, 3):
    (distance m or inf (R,), triangle index or -1 (R,)). Moller-Trumbore, every pair, in chunks."""
    o = np.atleast_2d(np.asarray(origins, float))
    d = np.atleast_2d(np.asarray(directions, float))
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    dist = np.full(len(d), np.inf)
    index = np.full(len(d), -1)
    if not len(tris) or not len(d):
        return dist, index
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    step = max(1, _CHUNK_PAIRS // len(tris))
    for s in range(0, len(d), step):
        dd, oo = d[s:s + step, None, :], o[s:s + step, None, :]
        pvec = np.cross(dd, e2[None])
        det = np.einsum("rtk,tk->rt", pvec, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = oo - v0[None]
            u = np.einsum("rtk,rtk->rt", tvec, pvec) * inv
            qvec = np.cross(tvec, e1[None])
            v = np.einsum("rtk,rtk->rt", qvec, dd) * inv
            t = np.einsum("rtk,tk->rt", qvec, e2) * inv
            ok = np.isfinite(inv) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        t = np.where(ok, t, np.inf)
        k = np.argmin(t, axis=1)
        best = t[np.arange(len(k)), k]
        dist[s:s + step] = best
        index[s:s + step] = np.where(np.isfinite(best), k, -1)
    return dist, index


def _inside_polygon(xy, poly_xy):
    """Even-odd test of points (N, 2) against a polygon (K, 2)."""
    x, y = xy[:, 0:1], xy[:, 1:2]
    a, b = poly_xy, np.roll(poly_xy, -1, axis=0)
    crosses = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.sum(crosses & (x < xc), axis=1) % 2 == 1


def _directions(az, el):
    az, el = np.radians(az), np.radians(el)
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)


def _through_opening(eye, poly, step_deg, rows):
    """Directions from ``eye`` that cross the polygon's interior: (dirs (R, 3), azimuth bins (R,) int,
    elevations deg (R,), distance to the opening m (R,)). Empty when the eye is in the opening's plane."""
    normal, offset = sky_aperture.polygon_plane(poly)
    h = float(eye @ normal - offset)
    if abs(h) < 1e-9:
        return np.zeros((0, 3)), np.zeros(0, int), np.zeros(0), np.zeros(0)
    rel = poly - eye
    az_c = math.degrees(math.atan2(rel.mean(axis=0)[1], rel.mean(axis=0)[0]))
    az = (np.degrees(np.arctan2(rel[:, 1], rel[:, 0])) - az_c + 180.0) % 360.0 - 180.0 + az_c
    el = np.degrees(np.arctan2(rel[:, 2], np.hypot(rel[:, 0], rel[:, 1])))
    # the polygon's edges can bulge past their ends' elevations: pad the box by a row, and test each ray
    lo_el, hi_el = el.min(), el.max()
    pad = (hi_el - lo_el) / rows + 1e-6
    lo_el, hi_el = max(-90.0, lo_el - pad), min(90.0, hi_el + pad)
    bins = np.arange(math.floor(az.min() / step_deg), math.ceil(az.max() / step_deg))
    if not bins.size:
        return np.zeros((0, 3)), np.zeros(0, int), np.zeros(0), np.zeros(0)
    a_grid = (bins + 0.5) * step_deg
    e_grid = lo_el + (np.arange(rows) + 0.5) * (hi_el - lo_el) / rows
    aa, ee = np.meshgrid(a_grid, e_grid, indexing="ij")
    bb = np.broadcast_to(bins[:, None], aa.shape)
    dirs = _directions(aa.ravel(), ee.ravel())
    t, ok = _crossing(eye, dirs, poly)
    return dirs[ok], bb.ravel()[ok].astype(int), ee.ravel()[ok], t[ok]


def _crossing(origin, dirs, poly):
    """(t (R,), crosses (R,) bool): where rays from ``origin`` along ``dirs`` meet the polygon's plane, and
    whether ahead of the origin inside the polygon."""
    normal, offset = sky_aperture.polygon_plane(poly)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (offset - origin @ normal) / (dirs @ normal)
    ok = np.isfinite(t) & (t > 0)
    hit = origin + dirs * np.where(ok, t, 0.0)[:, None]
    e1, e2 = sky_aperture.plane_axes(normal)
    return t, ok & _inside_polygon(np.c_[hit @ e1, hit @ e2], np.c_[poly @ e1, poly @ e2])


def _in_wedge(tris, eye, a_lo, a_hi, tol):
    """(T,) bool: the triangles that may meet a ray from ``eye`` whose azimuth lies in [a_lo, a_hi] deg: all
    of them when the wedge spans 180 deg or more, else those not wholly outside one of its two vertical
    bounding half-planes (a cull that loses no hit)."""
    if a_hi - a_lo >= 180.0 or not len(tris):
        return np.ones(len(tris), bool)
    lo, hi = math.radians(a_lo), math.radians(a_hi)
    rel = tris[:, :, :2] - eye[:2]
    d1 = rel @ np.array([-math.sin(lo), math.cos(lo)])       # > 0: counter-clockwise of the wedge's first side
    d2 = rel @ np.array([math.sin(hi), -math.cos(hi)])       # > 0: clockwise of its second side
    return (d1.max(axis=1) >= -tol) & (d2.max(axis=1) >= -tol)


def _largest_run(bins, total):
    """Largest run of adjoining integers in ``bins`` (wrapping at ``total``), in bins."""
    b = np.unique(np.mod(bins, total))
    if not b.size:
        return 0
    if b.size == total:
        return total
    gaps = np.flatnonzero(np.diff(np.r_[b, b[0] + total]) > 1)   # a run ends at each gap (one at least)
    ends = b[gaps]
    starts = b[(np.roll(gaps, 1) + 1) % b.size]                  # and began after the gap before it
    return int(np.max((ends - starts) % total + 1))


def _components(tris, tol):
    """(T,) the connected part of every triangle (vertices welded within ``tol`` m), and the welded vertices
    with their parts: (part per triangle, vertices (V, 3), part per vertex)."""
    if not len(tris):
        return np.zeros(0, int), np.zeros((0, 3)), np.zeros(0, int)
    pts, ids, roots = sky_aperture.triangle_parts(tris, tol)
    return roots[ids[:, 0]], pts, roots


@dataclasses.dataclass
class SceneParts:
    """The connected parts of the opaque triangles, computed once for :func:`eye_views` and
    :func:`surroundings_modelled`: ``part`` per triangle, ``loop_parts`` (the parts on each opening's
    outline, in the openings' order), and each part's box (``ids``, ``box_lo``, ``box_hi``, ``inverse``: each
    triangle's index into ``ids``)."""

    part: np.ndarray
    loop_parts: list
    ids: np.ndarray
    box_lo: np.ndarray
    box_hi: np.ndarray
    inverse: np.ndarray


def scene_parts(triangles, openings, tol=1e-6):
    """:class:`SceneParts` of the opaque ``triangles`` (T, 3, 3) and the ``openings`` (a list of (K, 3))."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    part, pts, roots = _components(tris, tol)
    return SceneParts(part, [_loop_parts(p, pts, roots, tol) for p in openings], *_part_boxes(tris, part))


def _part_boxes(tris, part):
    """(part ids (P,), box lows (P, 3), box highs (P, 3), each triangle's index into ids (T,))."""
    if not len(tris):
        return np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, int)
    ids, inverse = np.unique(part, return_inverse=True)
    inverse = inverse.ravel()
    order = np.argsort(inverse, kind="stable")
    starts = np.r_[0, np.flatnonzero(np.diff(inverse[order])) + 1]
    return (ids, np.minimum.reduceat(tris.min(axis=1)[order], starts),
            np.maximum.reduceat(tris.max(axis=1)[order], starts), inverse)


def _loop_parts(loop, pts, roots, tol):
    """The parts that have a vertex on the opening's outline's corners."""
    found = set()
    for q in np.asarray(loop, float):
        d = np.linalg.norm(pts - q, axis=1)
        found |= set(roots[d <= 10.0 * tol].tolist())
    return found


#: directions from the eye whose first surfaces are the eye's room (the 26 of a 3 x 3 x 3 cube's cells)
_AROUND = np.array([(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if (x, y, z) != (0, 0, 0)],
                   float)
_AROUND /= np.linalg.norm(_AROUND, axis=1, keepdims=True)


def _room_parts(eye, tris, part, openings):
    """The parts of the surfaces round the eye (the first met along 26 directions that do not pass through
    an opening on the way): its room."""
    d, k = first_hits_many(np.broadcast_to(eye, _AROUND.shape), _AROUND, tris)
    through = np.zeros(len(d), bool)
    for poly in openings:
        t, crosses = _crossing(eye, _AROUND, poly)
        through |= crosses & (t < d)
    keep = (k >= 0) & ~through
    return set(part[k[keep]].tolist())


def eye_views(eyes, openings, triangles, *, step_deg=STEP_DEG, rows=ROWS, tol=1e-6, parts=None):
    """One :class:`EyeView` per eye (``eyes`` (N, 3) m) through the ``openings`` (a list of (K, 3)
    polygons) among the opaque ``triangles`` (T, 3, 3).

    The eye's room is the connected parts of the surfaces first met round it (26 directions); its windows
    are the openings whose outlines lie on them (all openings when none does: a room of separate boxes), and
    a ray that meets the room's or a window's own parts again beyond the window (a thick wall's reveal, an
    overhang, fins or a parapet joined to the wall) does not go out. ``parts``: :func:`scene_parts` of the
    same triangles and openings, when the caller has them."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    up_cos = math.cos(math.radians(GROUND_TILT_DEG))
    total = int(round(360.0 / step_deg))
    # roof lights and windows in pitched roofs show the sky above, not a view out: only openings whose
    # plane leans at most MAX_TILT_FROM_VERTICAL_DEG from the vertical are looked through
    parts = parts or scene_parts(tris, openings, tol)
    walls = [j for j, p in enumerate(openings) if abs(float(sky_aperture.polygon_plane(np.asarray(p, float))[0][2]))
             <= math.sin(math.radians(MAX_TILT_FROM_VERTICAL_DEG))]
    openings = [np.asarray(openings[j], float) for j in walls]
    loop_parts = [parts.loop_parts[j] for j in walls]
    part, ids, box_lo, box_hi = parts.part, parts.ids, parts.box_lo, parts.box_hi
    out = []
    for eye in np.atleast_2d(np.asarray(eyes, float)):
        room = _room_parts(eye, tris, part, openings) if len(tris) else set()
        mine = [j for j, lp in enumerate(loop_parts) if lp & room] or list(range(len(openings)))
        own = room.union(*[loop_parts[j] for j in mine]) if mine else room   # walls, reveals, the frame's parts
        if own and len(ids):   # and what is built onto them: parts within OWN_GAP_M of their box (an overhang box)
            sel = np.isin(ids, list(own))
            lo, hi = box_lo[sel].min(axis=0) - OWN_GAP_M, box_hi[sel].max(axis=0) + OWN_GAP_M
            # the ground the building stands on is not built onto it: a part must rise above the room's base
            touching = np.all((box_lo <= hi) & (box_hi >= lo), axis=1) & (box_hi[:, 2] > lo[2] + 2 * OWN_GAP_M)
            own = own | set(ids[touching].tolist())
        mine = [openings[j] for j in mine]
        rays = [_through_opening(eye, p, step_deg, rows) for p in mine]
        if not rays or not sum(len(p[0]) for p in rays):
            out.append(EyeView(tuple(eye), 0.0, 0.0, (), 0))
            continue
        dirs = np.concatenate([p[0] for p in rays])
        bins = np.concatenate([p[1] for p in rays])
        el = np.concatenate([p[2] for p in rays])
        to_opening = np.concatenate([p[3] for p in rays])
        dist, k = np.full(len(dirs), np.inf), np.full(len(dirs), -1)
        start = 0
        for p in rays:
            n = len(p[0])
            if n:
                keep = _in_wedge(tris, eye, p[1].min() * step_deg, (p[1].max() + 1) * step_deg, tol)
                d_j, k_j = first_hits_many(np.broadcast_to(eye, p[0].shape), p[0], tris[keep])
                dist[start:start + n] = d_j
                k[start:start + n] = np.where(k_j >= 0, np.flatnonzero(keep)[np.maximum(k_j, 0)], -1)
            start += n
        # nothing opaque before the window, and beyond it not the room's own building
        on_own = (k >= 0) & np.isin(part[np.maximum(k, 0)], list(own)) if len(part) else np.zeros(len(k), bool)
        out_mask = (dist >= to_opening - tol) & ~on_own
        if not out_mask.any():
            out.append(EyeView(tuple(eye), 0.0, 0.0, (), 0))
            continue
        dirs, bins, el, to_opening, dist, k = (a[out_mask] for a in (dirs, bins, el, to_opening, dist, k))
        met = np.isfinite(dist)
        n = normals[np.maximum(k, 0)]
        hit_z = eye[2] + dirs[:, 2] * np.where(met, dist, 0.0)
        facing = -np.einsum("rk,rk->r", n, dirs)     # > 0: the ray meets the side the normal points to
        up = np.abs(n[:, 2]) >= up_cos
        ground_hit = met & up & (hit_z < eye[2]) & (np.sign(facing) * n[:, 2] > 0)
        seen = {"sky": bool(np.any(~met & (dirs[:, 2] > 0))),
                "ground": bool(np.any(~met & (dirs[:, 2] < 0)) or np.any(ground_hit)),
                "landscape": bool(np.any(met & ~ground_hit))}
        level = np.abs(el) <= LEVEL_BAND_DEG
        pick = level if level.any() else np.ones_like(level)
        beyond = np.where(met, dist - to_opening, np.inf)[pick]
        distance = float(np.median(beyond))
        out.append(EyeView(tuple(float(v) for v in eye), _largest_run(bins, total) * step_deg, distance,
                           tuple(name for name in LAYERS if seen[name]), int(out_mask.sum())))
    return out


def surroundings_modelled(triangles, openings, views_landscape, tol=1e-6, parts=None):
    """True when the scene models something outside the room to see: a landscape surface seen through a
    window (``views_landscape``), or a part of the opaque ``triangles`` not joined to the openings'
    outlines, not flat (a building, terrain, a tree; a ground plane alone does not count) and not within
    the box of the parts that hold the openings (furniture inside the room is no surroundings)."""
    if views_landscape:
        return True
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if not len(tris) or not len(openings):
        return False
    parts = parts or scene_parts(tris, openings, tol)
    part = parts.part
    room = np.isin(part, list(set().union(*parts.loop_parts)))
    if not room.any():
        return False
    lo, hi = tris[room].reshape(-1, 3).min(axis=0), tris[room].reshape(-1, 3).max(axis=0)
    inside = np.all((tris >= lo - tol) & (tris <= hi + tol), axis=(1, 2))
    # parts built onto the room (within OWN_GAP_M of its box: an overhang, fins) are the building too
    near = np.all((parts.box_lo <= hi + OWN_GAP_M) & (parts.box_hi >= lo - OWN_GAP_M), axis=1)
    inside |= near[parts.inverse]
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        nz = np.abs(n[:, 2]) / np.linalg.norm(n, axis=1)
    steep = nz < math.cos(math.radians(GROUND_TILT_DEG))
    return bool(np.any(~room & steep & ~inside))

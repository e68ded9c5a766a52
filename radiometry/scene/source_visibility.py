"""Which part of a luminous surface an eye sees: proofs and bounds over triangle occluders (pure numpy).

Glare (CIE 117 UGR) rates the luminous parts of a source *the observer sees*. A source here is a convex
polygon (an area light's rectangle or ellipse, an IES file's luminous opening) or a set of triangles (an
emitting mesh). Each piece is a *cell*; a cell is

``CLEAR``   proven whole in view: no shadow-casting opaque triangle meets the pyramid from the eye over
            the cell (``visibility.triangles_meet_polytopes``: the separating-axis proof the meter uses for
            a light's visibility; every doubt reads "may meet");
``HIDDEN``  proven hidden: the pyramid's section by the plane of a set of coplanar opaque triangles lies
            inside their union. The proof: the plane lies strictly between the eye and every point of
            the cell, one point of the section is inside a triangle of the set, and no boundary edge of
            the set (an edge that is not shared by two triangles lying on its two sides) enters the
            section's interior; the section is convex, so it lies wholly inside the union;
``MIXED``   neither: it is cut into four (midpoints) and each part classified again, down to
            ``max_depth`` levels or ``max_cells`` cells; a mixed cell left at the end is counted seen
            or hidden by the ray to its centre (the estimate), and whole in the bounds.

So the visible share of the source's solid angle has proven bounds: ``lower`` = the clear cells' share,
``upper`` = 1 - the hidden cells' share; ``fraction`` is the estimate between them. Triangles lying at or
beyond a cell's plane (the source's own surface, a ceiling flush with a panel, the far side of a convex
lamp) cannot block a segment that ends on the cell and are not occluders. Non-opaque triangles (glass)
do not hide: the source is seen through them, without their transmittance (named in ``see_through``).

Weights are exact solid angles (Van Oosterom & Strackee) of the cells. Metres, float64.
"""

from dataclasses import dataclass, field

import numpy as np

from . import visibility
from ..metrics.glare import triangle_solid_angles

__all__ = ["CLEAR", "HIDDEN", "MIXED", "SeenPart", "seen_part", "polygon_cells", "hidden_behind"]

CLEAR, HIDDEN, MIXED = "clear", "hidden", "mixed"

#: Most triangles (whose plane separates the eye from the cell) a hiding proof walks; more: not tried.
MAX_PROOF_TRIANGLES = 512


@dataclass
class SeenPart:
    """What the eye sees of one source. Per input cell (polygon or triangle) i: ``omega`` (sr, the whole
    cell), ``omega_seen`` (sr, estimate), ``centre_seen`` (m, the seen part's area-weighted centre, the
    cell's centre where nothing is seen) and ``area_seen`` (m²). Over the source: ``fraction``, ``lower``,
    ``upper`` (shares of the solid angle), the names of the opaque objects that hide part of it, and of
    the non-opaque ones it is seen through."""

    omega: np.ndarray
    omega_seen: np.ndarray
    omega_clear: np.ndarray     #: per input cell: the part proven in view (sr), a lower bound
    omega_hidden: np.ndarray    #: per input cell: the part proven hidden (sr); omega - it is an upper bound
    area_seen: np.ndarray
    centre_seen: np.ndarray
    fraction: float
    lower: float
    upper: float
    blockers: list = field(default_factory=list)
    see_through: list = field(default_factory=list)
    cells: int = 0              #: cells classified, all levels
    unresolved: int = 0         #: mixed cells left at the end (counted by their centre ray)

    @property
    def status(self):
        """CLEAR (proven whole), HIDDEN (proven hidden) or MIXED (partly seen, or not decided)."""
        if self.lower >= 1.0:
            return CLEAR
        if self.upper <= 0.0:
            return HIDDEN
        return MIXED


def polygon_cells(polygon):
    """A convex polygon (K, 3) as one cell (1, K, 3): the whole source is classified first."""
    p = np.asarray(polygon, float)
    return p[None]


def _split(cell):
    """A cell as triangles: a triangle into four by its midpoints, a quad into two triangles, a larger
    convex polygon into a fan from its centre."""
    k = len(cell)
    if k == 3:
        a, b, c = cell
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        return [np.array(t) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))]
    if k == 4:
        return [cell[[0, 1, 2]], cell[[0, 2, 3]]]
    centre = cell.mean(axis=0)
    return [np.array([centre, cell[j], cell[(j + 1) % k]]) for j in range(k)]


def _area(cell):
    c = np.asarray(cell, float)
    return 0.5 * float(sum(np.linalg.norm(np.cross(c[j] - c[0], c[j + 1] - c[0])) for j in range(1, len(c) - 1)))


def _solid_angle(eye, cell):
    c = np.asarray(cell, float)
    fan = np.stack([np.broadcast_to(c[0], (len(c) - 2, 3)), c[1:-1], c[2:]], axis=1)
    return float(triangle_solid_angles(eye, fan).sum())


def _plane_towards(eye, cell):
    """(unit normal pointing to the eye's side, height of the eye above the cell's plane m)."""
    c = np.asarray(cell, float)
    n = np.zeros(3)
    for j in range(1, len(c) - 1):
        n += np.cross(c[j] - c[0], c[j + 1] - c[0])
    norm = np.linalg.norm(n)
    if norm == 0:
        return n, 0.0
    n /= norm
    h = float((eye - c[0]) @ n)
    return (n, h) if h >= 0 else (-n, -h)


def _candidates(eye, cell, geometry, tol, shadow):
    """Indices of shadow-casting triangles that may cut segments from ``eye`` to ``cell``: their boxes meet
    the pyramid's box and they have a vertex on the eye's side of the cell's plane."""
    lo = np.minimum(eye, cell.min(axis=0))
    hi = np.maximum(eye, cell.max(axis=0))
    idx = geometry.grid.query(lo, hi, tol)
    if not idx.size:
        return idx
    idx = idx[shadow[idx]]
    if not idx.size:
        return idx
    n, _h = _plane_towards(eye, cell)
    return idx[~visibility.below_plane(geometry.triangles[idx], cell[0], n, tol)]


def _inside_triangle_2d(p, tri, tol):
    """True when 2-D point ``p`` lies inside triangle ``tri`` (3, 2) by more than ``tol`` (m) from its edges."""
    for j in range(3):
        a, b, c = tri[j], tri[(j + 1) % 3], tri[(j + 2) % 3]
        e = b - a
        length = np.hypot(*e)
        if length == 0:
            return False
        cross_p = e[0] * (p[1] - a[1]) - e[1] * (p[0] - a[0])
        cross_c = e[0] * (c[1] - a[1]) - e[1] * (c[0] - a[0])
        if cross_c == 0 or cross_p * np.sign(cross_c) / length <= tol:
            return False
    return True


def _segment_enters(seg, poly, tol):
    """True unless the 2-D segment ``seg`` (2, 2) provably stays out of the convex polygon ``poly``'s
    interior (a separating axis with an overlap of at most ``tol`` m: touching its outline is allowed)."""
    axes = [np.array([-(seg[1] - seg[0])[1], (seg[1] - seg[0])[0]])]
    k = len(poly)
    axes += [np.array([-(poly[(j + 1) % k] - poly[j])[1], (poly[(j + 1) % k] - poly[j])[0]]) for j in range(k)]
    for axis in axes:
        norm = np.hypot(*axis)
        if norm == 0:
            continue
        a = axis / norm
        ps, pp = seg @ a, poly @ a
        if ps.min() >= pp.max() - tol or pp.min() >= ps.max() - tol:
            return False
    return True


def _boundary_edges(tris2d, tris3d):
    """The 2-D edges (E, 2, 2) of a set of coplanar triangles that bound their union: every edge except
    those shared by exactly two triangles (same vertex coordinates) whose third vertices lie on its two
    sides. Extra edges only make the proof fail, never wrongly succeed."""
    uses = {}
    for t in range(len(tris3d)):
        for j in range(3):
            a, b = j, (j + 1) % 3
            key = tuple(sorted((tuple(map(float, tris3d[t, a])), tuple(map(float, tris3d[t, b])))))
            uses.setdefault(key, []).append((t, a, b, 3 - a - b))
    out = []
    for users in uses.values():
        t, a, b, _o = users[0]
        if len(users) == 2:
            sides = []
            for u, ua, ub, uo in users:
                p, q, r = tris2d[u, ua], tris2d[u, ub], tris2d[u, uo]
                sides.append(np.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])))
            # the same edge, walked from the same end: the third vertices on opposite sides
            (u0, a0, _b0, _o0), (u1, a1, _b1, _o1) = users
            same_start = np.array_equal(tris3d[u0, a0], tris3d[u1, a1])
            if sides[0] != 0 and sides[1] != 0 and (sides[0] != sides[1]) == same_start:
                continue
        out.append(np.array([tris2d[t, a], tris2d[t, b]]))
    return out


def hidden_behind(eye, cell, tris, tol, max_triangles=MAX_PROOF_TRIANGLES):
    """Indices (into ``tris``, opaque triangles) of a coplanar set proven to hide every point of the convex
    polygon ``cell`` (K, 3) from ``eye``, or None (see the module docstring for the proof). Only triangles
    whose plane lies strictly between the eye and the whole cell can take part (a vectorised first cut);
    more than ``max_triangles`` of them: None (not tried: the proof's edge walk is plain Python)."""
    eye, cell, tris = (np.asarray(a, float) for a in (eye, cell, tris))
    if not len(tris):
        return None
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    norm = np.linalg.norm(n, axis=1)
    good = norm > 0
    n = np.where(good[:, None], n / np.where(norm > 0, norm, 1.0)[:, None], 0.0)
    h_eye = np.einsum("tk,tk->t", eye - tris[:, 0], n)
    n = np.where((h_eye < 0)[:, None], -n, n)          # every normal towards the eye
    h_eye = np.abs(h_eye)
    h_cell = np.einsum("tkv,tv->tk", cell[None, :, :] - tris[:, None, 0, :], n)
    between = good & (h_eye > tol) & np.all(h_cell < -tol, axis=1)  # the plane strictly between
    if not between.any() or between.sum() > max_triangles:
        return None
    offset = np.einsum("tk,tk->t", tris[:, 0], n)
    # Planes by a quantised key (a plane split across two bins only makes the proof fail); a plane whose
    # triangles have less area than the section cannot cover it (a cheap first cut over dense clutter).
    idx = np.flatnonzero(between)
    keys = np.c_[np.round(n[idx] * 1e7), np.round(offset[idx] / max(8.0 * tol, 1e-12))].astype(np.int64)
    _keys, group_of = np.unique(keys, axis=0, return_inverse=True)
    group_of = group_of.ravel()
    ratio = (h_eye[idx][:, None] / (h_eye[idx][:, None] - h_cell[idx]))[..., None]
    sections = eye + ratio * (cell[None] - eye)                                        # (B, K, 3)
    fan = np.cross(sections[:, 1:-1] - sections[:, :1], sections[:, 2:] - sections[:, :1]).sum(axis=1)
    need = 0.5 * np.linalg.norm(fan, axis=1)
    have = np.bincount(group_of, weights=0.5 * norm[idx])
    for g in np.flatnonzero(have >= need[np.unique(group_of, return_index=True)[1]] * (1.0 - 1e-9)):
        members = idx[group_of == g]
        i = int(members[0])
        he = float(h_eye[i])
        hc = h_cell[i]
        section = eye + (he / (he - hc))[:, None] * (cell - eye)
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[i][0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(n[i], helper)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n[i], e1)
        frame = np.stack([e1, e2], axis=1)
        q = section @ frame
        t2 = tris[members] @ frame
        centre = q.mean(axis=0)
        probes = [centre] + [(centre + v) / 2 for v in q]  # interior points of the section (one is enough)
        if not any(_inside_triangle_2d(p, t, tol) for p in probes for t in t2):
            continue
        if any(_segment_enters(edge, q, tol) for edge in _boundary_edges(t2, tris[members])):
            continue
        return members
    return None


def _classify(eye, cells, cands, geometry, tol, shadow, max_pairs):
    """(per cell: (state, names of hiding objects, names of non-opaque objects in the way, indices of the
    triangles that may meet its pyramid), pairs tested); None for the first when the (cell, triangle)
    pairs exceed ``max_pairs`` (a dense occluder: the caller stops cutting). ``cands``: per cell the
    triangles that met its parent's pyramid (a part's pyramid lies inside its parent's), or None."""
    names = geometry.object_names
    per_cell = [_candidates(eye, c, geometry, tol, shadow) if k is None else k for c, k in zip(cells, cands)]
    tested = sum(len(i) for i in per_cell)
    if tested > max_pairs:
        return None, 0
    pk = np.concatenate([np.full(len(i), k) for k, i in enumerate(per_cell)]) if cells else np.zeros(0, int)
    pt = np.concatenate(per_cell) if cells else np.zeros(0, int)
    meets = np.zeros(len(pt), bool)
    if len(pt):
        if len({len(c) for c in cells}) == 1:
            stacked = np.asarray(cells, float)
            step = max(1, 200_000 // stacked.shape[1])  # pairs per batch: bounded memory for 64-gon outlines
            for a in range(0, len(pt), step):
                sl = slice(a, a + step)
                verts, normals, edges = visibility.pyramids(np.broadcast_to(eye, (len(pk[sl]), 3)), stacked[pk[sl]])
                meets[sl] = visibility.triangles_meet_polytopes(geometry.triangles[pt[sl]], verts, normals, edges, tol)
        else:
            start = 0
            for k, idx in enumerate(per_cell):
                if len(idx):
                    meets[start:start + len(idx)] = visibility.triangles_meet_polytope(
                        geometry.triangles[idx], visibility.pyramid(eye, cells[k]), tol)
                start += len(idx)
    out = []
    opaque = np.asarray(geometry.opaque, bool)
    ends = np.cumsum([len(i) for i in per_cell])  # pairs are in cell order: cell k's are [ends[k-1], ends[k])
    for k, cell in enumerate(cells):
        part = slice(ends[k - 1] if k else 0, ends[k])
        met = pt[part][meets[part]]
        through = sorted({names[geometry.object_index[j]] for j in met[~opaque[met]]})
        hit = met[opaque[met]]
        if not hit.size:
            out.append((CLEAR, [], through, met))
            continue
        members = hidden_behind(eye, cell, geometry.triangles[hit], tol)
        if members is not None:
            out.append((HIDDEN, sorted({names[geometry.object_index[j]] for j in hit[members]}), through, met))
        else:
            out.append((MIXED, sorted({names[geometry.object_index[j]] for j in hit}), through, met))
    return out, tested


def _centre_seen(eye, cell, geometry, tol, met):
    """The estimate for a mixed cell left at the end: is the segment to its centre blocked? ``met``: the
    triangles that may meet its pyramid (the only ones that can)."""
    centre = cell.mean(axis=0)
    idx = np.asarray(met, int)
    idx = idx[np.asarray(geometry.opaque, bool)[idx]]
    if not idx.size:
        return True
    to = centre - eye
    dist = float(np.linalg.norm(to))
    # A ray along a seam between two opaque triangles hits one of them (edges count as hits here).
    hit, _index, _facing = visibility.first_hits(eye, (to / dist)[None], geometry.triangles[idx])
    return not hit[0] < dist - tol


def seen_part(eye, cells, geometry, tol, *, max_depth=6, max_cells=4096, max_pairs=2_000_000):
    """:class:`SeenPart` of a source made of ``cells`` (a list or array of convex polygons (K, 3), m: one
    polygon for a light's outline, the triangles of an emitting mesh) seen from ``eye`` (3,) m among
    ``geometry`` (``scene_model.SceneGeometry``: its shadow-casting triangles occlude). ``tol``: the
    proofs' length tolerance (m, ``scene_model.length_tolerance``). ``max_depth``, ``max_cells`` and
    ``max_pairs`` (cell-triangle separating-axis tests) bound the work: cells still undecided then count
    by their centre ray, and whole in the bounds."""
    eye = np.asarray(eye, float)
    cells = [np.asarray(c, float) for c in cells]
    shadow = geometry.shadow_triangles()  # occluders: the surfaces that cast shadows, as for the meter
    m = len(cells)
    omega = np.array([_solid_angle(eye, c) for c in cells])
    seen_w, seen_a, clear_i, hidden_i = np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m)
    seen_c = np.array([c.mean(axis=0) for c in cells]) if m else np.zeros((0, 3))
    moment = np.zeros((m, 3))
    clear_w = hidden_w = 0.0
    blockers, through = set(), set()
    level = [(c, i, 0, None) for i, c in enumerate(cells)]
    count = unresolved = pairs = 0
    exhausted = False
    while level:
        count += len(level)
        states = []
        for size in sorted({len(c) for c, _i, _d, _k in level}):
            group = [item for item in level if len(item[0]) == size]
            found, tested = _classify(eye, [c for c, _i, _d, _k in group], [k for _c, _i, _d, k in group], geometry,
                                      tol, shadow, max_pairs - pairs)
            pairs += tested
            if found is None:  # over the budget of pair tests: these cells are left undecided, no more cuts
                exhausted = True
                found = [(MIXED, [], [], k if k is not None else _candidates(eye, c, geometry, tol, shadow))
                         for c, _i, _d, k in group]
            states += list(zip(group, found))
        nxt = []
        for (cell, i, depth, _k), (state, names, see, met) in states:
            through.update(see)
            w = _solid_angle(eye, cell) if depth else omega[i]
            if state == HIDDEN:
                blockers.update(names)
                hidden_w += w
                hidden_i[i] += w
                continue
            if state == MIXED and not exhausted and depth < max_depth and count + len(nxt) + 4 <= max_cells:
                blockers.update(names)
                nxt += [(part, i, depth + 1, met) for part in _split(cell)]
                continue
            if state == CLEAR:
                clear_w += w
                clear_i[i] += w
            else:
                blockers.update(names)
                unresolved += 1
                if not _centre_seen(eye, cell, geometry, tol, met):
                    continue
            a = _area(cell)
            seen_w[i] += w
            seen_a[i] += a
            moment[i] += a * cell.mean(axis=0)
        level = nxt
    has = seen_a > 0
    seen_c[has] = moment[has] / seen_a[has, None]
    total = float(omega.sum())
    if total > 0:
        fraction, lower, upper = float(seen_w.sum() / total), clear_w / total, 1.0 - hidden_w / total
    else:
        fraction, lower, upper = 1.0, 1.0, 1.0
    # Sub-cells' solid angles add up to their parent's only to rounding: a source whose cells are all
    # clear (hidden), at whatever level, has lower = 1 (upper = 0) exactly; the bounds stay within 0..1.
    lower = 1.0 if not (hidden_w or unresolved) else min(max(lower, 0.0), 1.0)
    upper = 0.0 if not (clear_w or unresolved) else min(max(upper, lower), 1.0)
    fraction = min(max(fraction, lower), upper)
    if lower == 1.0:  # proven whole: the exact solid angles, not a sum of parts
        clear_i, seen_w = omega.copy(), omega.copy()
    if upper == 0.0:
        hidden_i = omega.copy()
    return SeenPart(omega=omega, omega_seen=seen_w, omega_clear=clear_i, omega_hidden=hidden_i, area_seen=seen_a,
                    centre_seen=seen_c, fraction=fraction,
                    lower=lower, upper=upper, blockers=sorted(blockers), see_through=sorted(through),
                    cells=count, unresolved=unresolved)

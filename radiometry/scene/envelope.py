"""Gaps in the faces of the scene's bounding box: where a ray from inside may leave (pure numpy, no bpy; issue 31).

A room built of separate boxes (walls, floor and roof that touch) has no single closed surface, so its openings
cannot be proven as holes of one (``measure.analyses.sky_component``). Its windows still show where the boxes'
outer faces leave the bounding box's faces uncovered. :func:`bounding_face_gaps` finds those parts: on each face
of the box around every render-visible triangle, the cells of a grid (its lines through every coplanar opaque
triangle's vertices, so axis-aligned boxes are met exactly) whose centre no coplanar opaque triangle covers,
merged into rectangles.

What the caller may rely on, whatever the gaps found: each rectangle lies a little outside the bounding box, so
the half-space in front of it holds no surface, and a ray that crosses it would have met nothing but the world
(Radiance's ``mkillum`` secondary sources rest on the same: light leaving through a window is the sky's). A gap
missed, or a rectangle over a covered part, changes only how well a renderer samples the light, never what it
adds up to (``measure.analyses.sky_component.add_envelope_emitters``).
"""

import numpy as np

#: Most grid lines per axis on one face; past it the lines are evenly spaced (a rectangle may then straddle a
#: covered part: allowed, see the module's docstring).
MAX_LINES = 256
#: Most cell-triangle pairs tested at once by ``_covered``.
PAIRS = 2_000_000
#: Emitters of ``stood_off`` facing the same way whose planes lie within this (m) of each other compete for the same
#: rays: they are kept apart like coplanar ones. Two gaps of one face with shorter sides equal but for float32 noise
#: (a window split by a mullion) were moved out by 1e-8 m more or less, counted as two planes, and grown over each
#: other: a shadow ray to one stopped on the other, and the rest of the daylight factor read 18 % low.
COPLANAR_M = 1e-3


def _unique(values, tol):
    values = np.sort(np.asarray(values, float))
    if not len(values):
        return values
    keep = np.r_[True, np.diff(values) > tol]
    return values[keep]


def _covered(cu, cv, tris2d, tol):
    """(len(cu), len(cv)) bool: the cell centres (cu[i], cv[j]) (both sorted) inside any of the triangles (T, 3, 2)
    (edges widened by ``tol``). Each triangle tests only the cells in its bounding box: a face of many small
    triangles costs what its cells do."""
    out = np.zeros((len(cu), len(cv)), bool)
    a, b, c = tris2d[:, 0], tris2d[:, 1], tris2d[:, 2]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    keep = np.abs(area) > tol * tol
    lo, hi = tris2d.min(axis=1) - tol, tris2d.max(axis=1) + tol
    i0, i1 = np.searchsorted(cu, lo[:, 0], "left"), np.searchsorted(cu, hi[:, 0], "right")
    j0, j1 = np.searchsorted(cv, lo[:, 1], "left"), np.searchsorted(cv, hi[:, 1], "right")
    tris = np.flatnonzero(keep & (i1 > i0) & (j1 > j0))
    counts = (i1[tris] - i0[tris]) * (j1[tris] - j0[tris])
    ends = np.cumsum(counts)
    start = 0
    while start < len(tris):  # triangles in chunks of at most PAIRS cell-triangle pairs (one triangle at least)
        stop = max(start + 1, int(np.searchsorted(ends, (ends[start - 1] if start else 0) + PAIRS, "right")))
        t, n = tris[start:stop], counts[start:stop]
        owner = np.repeat(np.arange(len(t)), n)
        k = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        width = (j1[t] - j0[t])[owner]
        ci, cj = i0[t][owner] + k // width, j0[t][owner] + k % width
        x, y = cu[ci], cv[cj]
        inside = np.ones(len(k), bool)
        sign = np.sign(area[t])[owner]
        for p, q in ((a, b), (b, c), (c, a)):
            p, q = p[t][owner], q[t][owner]
            edge = q - p
            length = np.maximum(np.hypot(edge[:, 0], edge[:, 1]), 1e-300)
            inside &= (edge[:, 0] * (y - p[:, 1]) - edge[:, 1] * (x - p[:, 0])) * sign / length >= -tol
        out[ci[inside], cj[inside]] = True
        start = stop
    return out


def _rectangles(free, us, vs):
    """Merge free cells (nu, nv) into rectangles [(u0, u1, v0, v1)]: runs along u per row, equal runs of
    consecutive rows joined."""
    runs = {}
    out = []
    for j in range(free.shape[1]):
        row, i, now = free[:, j], 0, {}
        while i < len(row):
            if row[i]:
                k = i
                while k + 1 < len(row) and row[k + 1]:
                    k += 1
                now[(i, k)] = runs.pop((i, k), j)  # the row where this run started
                i = k + 1
            else:
                i += 1
        out += [(us[i], us[k + 1], vs[start], vs[j]) for (i, k), start in runs.items()]  # runs that ended
        runs = now
    out += [(us[i], us[k + 1], vs[start], vs[free.shape[1]]) for (i, k), start in runs.items()]
    return out


def bounding_face_gaps(triangles, opaque, tol, offset):
    """[(quad (4, 3) m, outward unit normal (3,))]: the parts of the faces of the bounding box of ``triangles``
    (T, 3, 3) m that no coplanar ``opaque`` (T,) triangle covers (within ``tol`` m), each moved ``offset`` m out
    of the box; a quad's vertices run counter-clockwise seen from outside."""
    triangles = np.asarray(triangles, float).reshape(-1, 3, 3)
    opaque = np.asarray(opaque, bool)
    if not len(triangles):
        return []
    lo, hi = triangles.reshape(-1, 3).min(axis=0), triangles.reshape(-1, 3).max(axis=0)
    out = []
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        if hi[u_axis] - lo[u_axis] <= tol or hi[v_axis] - lo[v_axis] <= tol:
            continue  # a flat scene: no face to leave by
        for side, plane in ((-1.0, lo[axis]), (1.0, hi[axis])):
            on = opaque & np.all(np.abs(triangles[:, :, axis] - plane) <= tol, axis=1)
            flat = triangles[on][:, :, [u_axis, v_axis]]
            us = _unique(np.r_[lo[u_axis], hi[u_axis], np.clip(flat[:, :, 0].ravel(), lo[u_axis], hi[u_axis])], tol)
            vs = _unique(np.r_[lo[v_axis], hi[v_axis], np.clip(flat[:, :, 1].ravel(), lo[v_axis], hi[v_axis])], tol)
            if len(us) > MAX_LINES + 1:
                us = np.linspace(lo[u_axis], hi[u_axis], MAX_LINES + 1)
            if len(vs) > MAX_LINES + 1:
                vs = np.linspace(lo[v_axis], hi[v_axis], MAX_LINES + 1)
            cu, cv = 0.5 * (us[1:] + us[:-1]), 0.5 * (vs[1:] + vs[:-1])
            free = ~_covered(cu, cv, flat, tol) if len(flat) else np.ones((len(cu), len(cv)), bool)
            normal = np.zeros(3)
            normal[axis] = side
            for u0, u1, v0, v1 in _rectangles(free, us, vs):
                if (u1 - u0) <= tol or (v1 - v0) <= tol:
                    continue
                quad = np.zeros((4, 3))
                quad[:, axis] = plane + side * offset
                quad[:, u_axis] = (u0, u1, u1, u0)
                quad[:, v_axis] = (v0, v0, v1, v1)
                # (u, v, n) is right-handed, so this order runs counter-clockwise seen from +axis
                out.append((quad if side > 0 else quad[::-1].copy(), normal))
    return out


def stood_off(gaps, standoff, grow):
    """``bounding_face_gaps`` moved further out, each by ``standoff`` x its shorter side, and grown on every side by
    ``grow`` x that distance (a ray leaving through the gap at an angle still meets it), but never into another gap of
    the same plane: gaps whose planes coincide (within ``COPLANAR_M``) must stay apart (where two coplanar emitters
    overlap, a renderer's shadow ray to one may stop on the other). Still outside the bounding box, so still with
    nothing in front."""
    moved = []
    for quad, normal in gaps:
        side = min(np.linalg.norm(quad[1] - quad[0]), np.linalg.norm(quad[3] - quad[0]))
        moved.append((quad + standoff * side * normal, normal, standoff * side))
    out = []
    for k, (quad, normal, d) in enumerate(moved):
        axis = int(np.argmax(np.abs(normal)))
        lo, hi = quad.min(axis=0), quad.max(axis=0)
        g = grow * d
        for j, (other, n2, _d2) in enumerate(moved):
            if j == k or not np.array_equal(n2, normal) or abs(other[0, axis] - quad[0, axis]) > COPLANAR_M:
                continue
            olo, ohi = other.min(axis=0), other.max(axis=0)
            gap = max(max(olo[a] - hi[a], lo[a] - ohi[a]) for a in range(3) if a != axis)
            g = min(g, 0.5 * max(gap, 0.0))
        grown = quad.copy()
        centre = quad.mean(axis=0)
        for a in range(3):
            if a != axis:
                grown[:, a] = np.where(quad[:, a] > centre[a], quad[:, a] + g, quad[:, a] - g)
        out.append((grown, normal))
    return out

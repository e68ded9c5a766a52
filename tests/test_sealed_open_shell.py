"""The dark-meter proof's pane rule (radiometry/scene/sealed.py ``_keeps_going``, issue 31): a thin pane standing
in front of an opening's plane keeps the proof only while every face of it in front lies in the opening's prism
and is perpendicular to the plane, or belongs to a slab whose front side (its winding, reversed for a mirrored
object) does not face the room, so that the thin-pane stand-in (a ray passed on, or mirrored: a slab's face where
the ray meets its front, a single face from either side) never turns a ray leaving the room back towards the
plane."""

import numpy as np

from radiometer.radiometry.scene import sealed

OPENING = np.array([(1.0, 0.0, 0.9), (3.0, 0.0, 0.9), (3.0, 0.0, 2.1), (1.0, 0.0, 2.1)])
OUT = np.array([0.0, -1.0, 0.0])  # the room is at y > 0
TOL = 1e-6


def _slab(depth=0.006, x0=1.0, x1=3.0, z0=0.9, z1=2.1):
    """The pane's faces in front of the plane (outer face and four sides), outward winding, as triangles."""
    y0, y1 = -depth, 0.0
    quads = [[(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],   # outer face: normal -y, along OUT
             [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],   # -x side
             [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],   # +x side
             [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],   # -z side
             [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]]   # +z side
    return np.array([[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads], float)


def _keeps(tris, front_sign=1.0, slab=True):
    n = len(tris)
    return sealed._keeps_going(tris, np.full(n, float(front_sign)), np.full(n, slab), OPENING, OPENING.mean(axis=0),
                               OUT, TOL)


def test_a_pane_in_front_that_sends_nothing_back():
    slab = _slab()
    normals = np.cross(slab[:, 1] - slab[:, 0], slab[:, 2] - slab[:, 0])
    assert np.allclose(normals[0] / np.linalg.norm(normals[0]), OUT)  # the outer face as built faces away
    assert _keeps(slab)
    assert not _keeps(slab, front_sign=-1.0)  # the same slab in a mirrored object: Cycles' front faces the room
    assert not _keeps(slab, front_sign=0.0)   # front side not known
    assert not _keeps(slab, slab=False)       # single faces mirror from both sides: the outer face may send back
    sides = np.concatenate([slab[1:5], slab[6:10]])  # the four side faces alone: perpendicular, safe either way
    assert _keeps(sides, front_sign=0.0, slab=False)


def test_a_face_turned_towards_the_room_or_one_outside_the_prism_breaks_it():
    slab = _slab()
    turned = slab.copy()
    turned[[0, 5]] = turned[[0, 5]][:, ::-1]  # the outer face's two triangles, winding reversed: facing the room
    assert not _keeps(turned)
    leaning = slab.copy()
    leaning[1, 2, 0] += 1e-3  # the -x side's far corner 1 mm out: that face now leans towards the room
    m = np.cross(leaning[1, 1] - leaning[1, 0], leaning[1, 2] - leaning[1, 0])
    assert m @ OUT < -1e-5
    assert not _keeps(leaning)
    away = slab.copy()
    away[1, 1, 0] += 1e-3  # its outer corner 1 mm in instead: leaning away from the room, a mirrored ray moves away
    m = np.cross(away[1, 1] - away[1, 0], away[1, 2] - away[1, 0])
    assert m @ OUT > 1e-5
    assert _keeps(away)
    assert not _keeps(_slab(x1=3.2))  # wider than the opening: it reaches past the rim


def test_a_mirror_facing_away_never_turns_a_leaving_ray_back():
    """The slab rule's reason, sampled: rays moving away from the plane (d . n > 0) mirrored by faces that do not
    face the room (m . n >= 0), where they meet the face's front (d . m < 0), keep d . n > 0; a mirror about a
    perpendicular face keeps d . n from either side."""
    rng = np.random.default_rng(7)
    d = rng.normal(size=(20000, 3))
    m = rng.normal(size=(20000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    d[d @ OUT < 0] *= -1.0
    m[m @ OUT < 0] *= -1.0
    front = np.einsum("ij,ij->i", d, m) < 0
    mirrored = d - 2.0 * np.einsum("ij,ij->i", d, m)[:, None] * m
    assert front.sum() > 1000 and np.all(mirrored[front] @ OUT >= d[front] @ OUT - 1e-12)
    m[:, 1] = 0.0  # faces perpendicular to the plane (OUT is -y)
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    mirrored = d - 2.0 * np.einsum("ij,ij->i", d, m)[:, None] * m
    assert np.allclose(mirrored @ OUT, d @ OUT)


def _quad_triangles(u0, u1, v0, v1, diagonal=0):
    a, b, c, d = (u0, v0), (u1, v0), (u1, v1), (u0, v1)
    return [(a, b, c), (a, c, d)] if diagonal == 0 else [(a, b, d), (b, c, d)]


def test_the_box_faces_cover_proof_counts_whole_rectangles_only():
    """``_behind_covered_faces``' coverage: a face tiled by quads (each split along either diagonal) is covered;
    one quad short, or a quad's one triangle alone (half of it), leaves it uncovered."""
    quads = [(0, 4, 0, 1), (0, 1, 1, 2.2), (3, 4, 1, 2.2), (0, 4, 2.2, 3)]  # a wall round a 2 x 1.2 window
    window = (1, 3, 1, 2.2)
    tris = np.array([t for k, q in enumerate(quads) for t in _quad_triangles(*q, diagonal=k % 2)], float)
    rects = sealed._half_rectangles(tris, 1e-9)
    assert sorted(map(tuple, rects)) == sorted(map(tuple, np.array(quads, float)))
    assert not sealed._face_covered(rects, (0, 4), (0, 3), 1e-9)  # the window is a gap
    closed = np.concatenate([tris, np.array(_quad_triangles(*window), float)])
    assert sealed._face_covered(sealed._half_rectangles(closed, 1e-9), (0, 4), (0, 3), 1e-9)
    half = np.concatenate([tris, np.array(_quad_triangles(*window)[:1], float)])  # the window half glazed over
    assert not sealed._face_covered(sealed._half_rectangles(half, 1e-9), (0, 4), (0, 3), 1e-9)

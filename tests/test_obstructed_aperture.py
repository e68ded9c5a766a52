"""The sky through an opening past obstructions (radiometry.skies.obstructed_aperture): the closed form over
the unblocked pieces against an independent brute-force integration over the opening's area, each cell's ray
tested against every blocking triangle (Moller-Trumbore, written out here)."""

import numpy as np
import pytest

from radiometer.radiometry.skies import obstructed_aperture as oa
from radiometer.radiometry.skies import sky_aperture as sa

WINDOW = np.array([[1.0, 0.0, 0.9], [3.0, 0.0, 0.9], [3.0, 0.0, 2.1], [1.0, 0.0, 2.1]])  # wall y = 0, room y > 0
TOL = 1e-9


def _overcast(u):
    return (1.0 + 2.0 * u[..., 2]) / 3.0


def _blocked(p, targets, tris):
    """(M,) bool: the segment from p towards each target, and on past it, hits one of ``tris`` (a ray)."""
    d = targets - p
    hit = np.zeros(len(d), bool)
    for v0, v1, v2 in tris:
        e1, e2 = v1 - v0, v2 - v0
        pv = np.cross(d, e2)
        det = pv @ e1
        ok = np.abs(det) > 1e-14
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        tv = p - v0
        u = (pv @ tv) * inv
        qv = np.cross(tv, e1)
        v = (d @ qv) * inv
        t = (qv @ e2) * inv
        hit |= ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    return hit


def _brute(p, n, tris, cells=1200):
    """(E, bound): E (sky above the horizon, L / Lz overcast) = int_A L cos_r cos_a / r^2 over the unblocked
    cells of the window (midpoint rule on cells x cells, each cell's centre ray tested), and a bound on its
    error at the silhouettes' edges: the weight of every cell whose corners' and centre's rays disagree (a cell
    cut by an edge), plus twice the largest cell's per blocking triangle (a corner poking into a cell); the
    smooth integrand's own midpoint error is below 1e-6 here (tests/test_sky_aperture.py)."""
    dx, dz = 2.0 / cells, 1.2 / cells
    xs, zs = 1.0 + dx * (np.arange(cells) + 0.5), 0.9 + dz * (np.arange(cells) + 0.5)
    x, z = np.meshgrid(xs, zs)
    q = np.stack([x, np.zeros_like(x), z], axis=-1).reshape(-1, 3)
    r = q - p
    d = np.linalg.norm(r, axis=-1)
    u = r / d[:, None]
    w = np.maximum(u @ n, 0.0) * np.abs(u[:, 1]) / d ** 2 * np.where(u[:, 2] > 0, _overcast(u), 0.0) * dx * dz
    centre = _blocked(p, q, tris)
    xc, zc = np.meshgrid(1.0 + dx * np.arange(cells + 1), 0.9 + dz * np.arange(cells + 1))
    corners = _blocked(p, np.stack([xc, np.zeros_like(xc), zc], axis=-1).reshape(-1, 3), tris)
    corners = corners.reshape(cells + 1, cells + 1)
    stack = np.stack([corners[:-1, :-1], corners[1:, :-1], corners[:-1, 1:], corners[1:, 1:]]).reshape(4, -1)
    mixed = np.any(stack != centre[None], axis=0)
    return float(np.sum(w[~centre])), float(np.sum(w[mixed]) + 2.0 * w.max() * len(tris))


def _closed(p, n, tris):
    pieces = oa.unblocked_pieces(p, WINDOW, tris, TOL)
    assert not isinstance(pieces, str), pieces
    if not pieces:
        return 0.0, pieces
    e = sa.aperture_illuminance(pieces, [p] * len(pieces), [n] * len(pieces), zenith_luminance=1.0)[0]
    return float(np.sum(e)), pieces


def _quad(a, b, c, d):
    a, b, c, d = (np.asarray(v, float) for v in (a, b, c, d))
    return np.array([[a, b, c], [a, c, d]])


def _box(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return np.concatenate([_quad(*[v[i] for i in f]) for f in faces])


CASES = {
    # a building across the street: its face covers the window's lower part from the point
    "face outside": (np.array([2.0, 1.5, 0.85]), np.array([0.0, 0.0, 1.0]), _quad((-5, -4, 0), (9, -4, 0), (9, -4, 5),
                                                                                     (-5, -4, 5))),
    # a block (12 triangles, overlapping silhouettes) off to one side
    "box outside": (np.array([2.0, 1.0, 0.85]), np.array([0.0, 0.0, 1.0]), _box((-2.0, -6.0, 0.0), (1.8, -3.0, 4.0))),
    # a cabinet inside, between the point and the window
    "inside": (np.array([2.0, 3.0, 0.85]), np.array([0.0, -1.0, 0.0]), _box((1.6, 1.0, 0.0), (2.4, 1.5, 1.8))),
    # an awning from outside through the window back over the point: its part in front of the point clipped
    "awning": (np.array([2.0, 1.5, 0.85]), np.array([0.0, 0.0, 1.0]), _quad((1.5, -3.0, 1.0), (2.5, -3.0, 1.0),
                                                                            (2.5, 2.5, 1.9), (1.5, 2.5, 1.9))),
    # a ground plane under everything, behind the point too, seen below the horizon (the sky part: all)
    "ground": (np.array([2.0, 2.5, 1.6]), np.array([0.0, -1.0, 0.0]), np.r_[_quad((-50, -50, 0), (50, -50, 0),
                                                                                  (50, 50, 0), (-50, 50, 0)),
                                                                            _box((-2.0, -6.0, 0.0), (1.8, -3.0, 4.0))]),
    # a tilted receiver and a tilted triangle
    "tilted": (np.array([1.2, 1.0, 1.2]), np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]),
               np.array([[[0.0, -2.0, 1.0], [4.0, -3.0, 2.5], [1.5, -1.5, 4.0]]])),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_closed_form_past_obstructions_matches_area_integration(name):
    p, n, tris = CASES[name]
    closed, pieces = _closed(p, n, tris)
    brute, bound = _brute(p, n, tris)
    open_sky = float(sa.aperture_illuminance(WINDOW, [p], n, zenith_luminance=1.0)[0][0])
    print(f"{name}: closed {closed:.6f}, area rule {brute:.6f} +- {bound:.2g}, open {open_sky:.6f}, "
          f"{len(pieces)} pieces")
    assert 0.05 * open_sky < closed < 0.98 * open_sky  # the obstruction blocks part of the sky here, not all
    assert bound < 0.01 * closed  # the check is sharp enough to mean something
    assert abs(closed - brute) <= bound + 1e-6 * open_sky


def test_random_triangles_outside():
    """Property: random triangles beyond the window (some overlapping) against the area rule."""
    rng = np.random.default_rng(7)
    p, n = np.array([2.0, 1.2, 0.85]), np.array([0.0, 0.0, 1.0])
    for _ in range(6):
        tris = np.stack([rng.uniform([-1.0, -6.0, 0.0], [5.0, -0.5, 5.0], size=(3, 3)) for _ in range(4)])
        closed, _pieces = _closed(p, n, tris)
        brute, bound = _brute(p, n, tris, 900)
        assert abs(closed - brute) <= bound + 1e-6, (closed, brute, bound)


def test_pieces_are_disjoint_convex_and_inside_the_window():
    p, n, tris = CASES["box outside"]
    pieces = oa.unblocked_pieces(p, WINDOW, tris, TOL)
    assert pieces and all(sa.is_convex(q) for q in pieces)
    for q in pieces:
        assert np.allclose(q[:, 1], 0.0) and np.all((q[:, 0] >= 1 - 1e-12) & (q[:, 0] <= 3 + 1e-12))
    # disjoint: random points of the window fall in at most one piece
    rng = np.random.default_rng(3)
    x = np.c_[rng.uniform(1, 3, 20000), rng.uniform(0.9, 2.1, 20000)]

    def inside(q):
        a, b = q[:, [0, 2]], np.roll(q[:, [0, 2]], -1, axis=0)
        s = (b[:, 0] - a[:, 0])[None] * (x[:, None, 1] - a[None, :, 1]) - \
            (b[:, 1] - a[:, 1])[None] * (x[:, None, 0] - a[None, :, 0])
        return np.all(s > 0, axis=1) | np.all(s < 0, axis=1)

    counts = sum(inside(q).astype(int) for q in pieces)
    assert counts.max() == 1
    # and the pieces are what the rays say: unblocked cells inside a piece, blocked ones in none
    targets = np.c_[x[:, 0], np.zeros(len(x)), x[:, 1]]
    blocked = _blocked(p, targets, tris)
    assert np.mean(blocked == (counts == 0)) > 0.999  # (points within float rounding of an edge may differ)


def test_whole_window_blocked_and_refusals():
    p = np.array([2.0, 1.5, 0.85])
    wall = _quad((-50, -2, -1), (50, -2, -1), (50, -2, 50), (-50, -2, 50))
    assert oa.unblocked_pieces(p, WINDOW, wall, TOL) == []
    # a triangle through the point itself: refused, not clipped
    through = np.array([[[0.0, -3.0, 0.85], [4.0, -3.0, 0.85], [2.0, 4.0, 0.85]]])
    assert "passes within" in oa.unblocked_pieces(p, WINDOW, through, TOL)
    assert "plane" in oa.unblocked_pieces(np.array([2.0, 0.0, 1.5]), WINDOW, through, TOL)
    # wholly behind the point: blocks nothing through the window
    behind = np.array([[[0.0, 3.0, 0.0], [4.0, 3.0, 0.0], [2.0, 3.0, 4.0]]])
    assert len(oa.unblocked_pieces(p, WINDOW, behind, TOL)) == 1
    # seen edge-on: blocks nothing
    edge = np.array([[[2.0, -1.0, 0.0], [2.0, -3.0, 0.0], [2.0, -2.0, 6.0]]])  # in the plane x = 2, through p
    flat = oa.unblocked_pieces(p, WINDOW, edge, TOL)
    assert len(flat) == 1 and np.allclose(sorted(map(tuple, flat[0])), sorted(map(tuple, WINDOW)))


def test_blockers_are_what_the_pyramid_meets():
    p, n, tris = CASES["box outside"]
    wall = _quad((-5, 0, 0), (0.5, 0, 0), (0.5, 0, 3), (-5, 0, 3))  # coplanar with the window, beside it
    far = _box((20.0, -9.0, 0.0), (22.0, -8.0, 1.0))                  # outside the pyramid
    everything = np.concatenate([tris, wall, far])
    blockers = sa.apertures_blockers([p, WINDOW[0]], WINDOW, everything, 1e-9, reach=100.0,
                                     sky_only=False)
    assert blockers[1] is None  # at the opening's corner: no pyramid
    found = set(blockers[0].tolist())
    assert found <= set(range(len(tris)))  # never the coplanar wall nor the far box
    assert found  # the box is in the way
    assert sa.apertures_clear([p], WINDOW, far, 1e-9, reach=100.0, sky_only=False)[0]


# --- every direction past every surface: a room of separate boxes (open_directions) ----------------------------

T_WALL = 0.2


def _box_room(mullion=False):
    """A 4 x 5 x 2.8 m room of nine boxes that touch (no single closed surface), walls T_WALL thick, a
    window x 1..3, z 0.9..2.2 through the wall y in [-T_WALL, 0]; a mullion splits it in two."""
    t = T_WALL
    boxes = [((-t, -t, -t), (4 + t, 5 + t, 0)), ((-t, -t, 2.8), (4 + t, 5 + t, 2.8 + t)), ((-t, 0, 0), (0, 5, 2.8)),
             ((4, 0, 0), (4 + t, 5, 2.8)), ((-t, 5, 0), (4 + t, 5 + t, 2.8)), ((-t, -t, 0), (1, 0, 2.8)),
             ((3, -t, 0), (4 + t, 0, 2.8)), ((1, -t, 0), (3, 0, 0.9)), ((1, -t, 2.2), (3, 0, 2.8))]
    if mullion:
        boxes.append(((1.95, -t, 0.9), (2.05, 0, 2.2)))
    return np.concatenate([_box(lo, hi) for lo, hi in boxes])


def _through_tunnel(p, x0, x1):
    """The directions from p (inside the room) through the opening x0..x1, z 0.9..2.2 of the thick wall: its
    outer rectangle clipped by the planes through p and each edge of its inner rectangle (an independent
    construction: both faces' rectangles, nothing else)."""
    outer = np.array([[x0, -T_WALL, 0.9], [x1, -T_WALL, 0.9], [x1, -T_WALL, 2.2], [x0, -T_WALL, 2.2]])
    inner = outer + np.array([0.0, T_WALL, 0.0])
    poly = outer - p
    centre = inner.mean(axis=0) - p
    for j in range(4):
        nrm = np.cross(inner[j] - p, inner[(j + 1) % 4] - p)
        poly = sa.clip_polygon(poly, nrm, 1.0 if nrm @ centre >= 0.0 else -1.0)
    return poly + p


def _sky(p, n, pieces):
    if not pieces:
        return 0.0
    return float(np.sum(sa.aperture_illuminance(pieces, [p] * len(pieces), [n] * len(pieces), zenith_luminance=1.0)[0]))


@pytest.mark.parametrize("mullion", [False, True])
def test_open_directions_in_a_room_of_boxes_are_the_tunnels_through_its_thick_wall(mullion):
    """Nine boxes that touch (floor, roof, walls): from points inside, the directions meeting no triangle are
    exactly those through the window's tunnel in the thick wall (inner and outer rectangles), whatever the
    point's height and tilt; with a mullion, the two tunnels beside it."""
    tris = _box_room(mullion)
    rng = np.random.default_rng(5)
    for _ in range(12):
        p = np.array([rng.uniform(0.1, 3.9), rng.uniform(0.1, 4.9), rng.uniform(0.1, 2.7)])
        n = rng.normal(size=3)
        n = n / np.linalg.norm(n) if rng.random() < 0.5 else np.array([0.0, 0.0, 1.0])
        pieces = oa.open_directions(p, n, tris, 1e-7)
        assert not isinstance(pieces, str), pieces
        tunnels = [(1.0, 1.95), (2.05, 3.0)] if mullion else [(1.0, 3.0)]
        want = sum(_sky(p, n, [q]) for q in (_through_tunnel(p, a, b) for a, b in tunnels) if len(q) >= 3)
        got = _sky(p, n, pieces)
        assert abs(got - want) <= 1e-9 * max(want, 1e-3), (p, n, got, want)


def test_open_directions_past_boxes_outside_match_sampled_directions():
    """The room of boxes with a block outside across the window and a slab over it: the closed form over the
    open directions against cosine-weighted sampled directions (each tested against every triangle)."""
    tris = np.concatenate([_box_room(), _box((-3.0, -6.0, 0.0), (2.2, -4.0, 3.5)), _box((0.5, -1.2, 2.3), (3.5, -0.2, 2.4))])
    rng = np.random.default_rng(9)
    m = 200_000
    for p in (np.array([2.0, 0.8, 0.85]), np.array([1.2, 2.5, 1.6])):
        n = np.array([0.0, 0.0, 1.0])
        pieces = oa.open_directions(p, n, tris, 1e-7)
        assert not isinstance(pieces, str), pieces
        u1, u2 = rng.random(m), rng.random(m)
        r, phi = np.sqrt(u1), 2.0 * np.pi * u2
        d = np.c_[r * np.cos(phi), r * np.sin(phi), np.sqrt(1.0 - u1)]
        value = np.where(_blocked(p, p + d, tris), 0.0, np.pi * _overcast(d))
        mean, se = value.mean(), value.std() / np.sqrt(m)
        got = _sky(p, n, pieces)
        assert 0.0 < got and abs(got - mean) <= 5.0 * se, (p, got, mean, se)


def test_open_directions_inside_a_closed_box_and_refusal():
    """A point inside a closed box sees no direction; a triangle whose plane passes next to the point (behind
    it, as seen along a face) is refused, not guessed."""
    tris = _box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    assert oa.open_directions(np.array([0.5, 0.5, 0.5]), np.array([0.0, 0.0, 1.0]), tris, 1e-7) == []
    board = _quad((0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (0.0, 1.0, 2.0), (0.0, -1.0, 2.0))  # the plane x = 0
    why = oa.open_directions(np.array([1e-9, 0.0, 0.5]), np.array([0.0, 0.0, 1.0]), board, 1e-7)
    assert isinstance(why, str) and "passes within" in why


def _outward_box(lo, hi):
    """A box's 12 triangles wound outward (``_box`` winds its faces as they come)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return np.concatenate([_quad(*[v[i] for i in f]) for f in faces])


def test_closed_solids_leave_out_far_faces_and_change_nothing():
    """Each box of the room is a closed surface wound outward: leaving out its faces turned away from a point, and
    subtracting each face's two triangles as one quad (``quad_pairs``), change no open direction's closed form; a point inside a box sees nothing; a box wound inconsistently (its
    own ``_box``: faces as they come) is no solid."""
    t = T_WALL
    boxes = [((-t, -t, -t), (4 + t, 5 + t, 0)), ((-t, -t, 2.8), (4 + t, 5 + t, 2.8 + t)), ((-t, 0, 0), (0, 5, 2.8)),
             ((4, 0, 0), (4 + t, 5, 2.8)), ((-t, 5, 0), (4 + t, 5 + t, 2.8)), ((-t, -t, 0), (1, 0, 2.8)),
             ((3, -t, 0), (4 + t, 0, 2.8)), ((1, -t, 0), (3, 0, 0.9)), ((1, -t, 2.2), (3, 0, 2.8)),
             ((1.95, -t, 0.9), (2.05, 0, 2.2))]
    tris = np.concatenate([_outward_box(lo, hi) for lo, hi in boxes])
    assert oa.closed_solids(_box_room(mullion=True), 1e-7, np.repeat(np.arange(10), 12)) == []
    groups = np.repeat(np.arange(len(tris) // 12), 12)
    solids = oa.closed_solids(tris, 1e-7, groups)
    assert len(solids) == len(tris) // 12 and all(sign == 1 for _idx, sign in solids)
    pairs = oa.quad_pairs(tris, 1e-7)
    partners = pairs[0]
    assert np.sum(partners >= 0) >= len(tris) - 12  # nearly every face's two triangles pair up as its quad
    paired = np.flatnonzero(partners >= 0)
    assert np.all(partners[partners[paired]] == paired)  # pairs, each the other's
    rng = np.random.default_rng(11)
    for _ in range(8):
        p = np.array([rng.uniform(0.1, 3.9), rng.uniform(0.1, 4.9), rng.uniform(0.1, 2.7)])
        n = np.array([0.0, 0.0, 1.0])
        without = _sky(p, n, oa.open_directions(p, n, tris, 1e-7))
        # equal up to the pieces' rounding (vertices within 1e-10 of the cube's size are merged): 1e-8 of a face's sky
        sides = [sa.inside_enclosures([p], tris[idx], [], 1e-7)[0] for idx, _sign in solids]  # as a grid's caller
        for pieces in (oa.open_directions(p, n, tris, 1e-7, solids), oa.open_directions(p, n, tris, 1e-7, solids, pairs),
                       oa.open_directions(p, n, tris, 1e-7, solids, pairs, sides)):
            assert _sky(p, n, pieces) == pytest.approx(without, rel=1e-9, abs=1e-8)
    assert oa.open_directions(np.array([2.0, -0.1, 0.5]), np.array([0.0, 0.0, 1.0]), tris, 1e-7, solids) == []
    within = [sa.inside_enclosures([(2.0, -0.1, 0.5)], tris[idx], [], 1e-7)[0] for idx, _sign in solids]
    assert oa.open_directions(np.array([2.0, -0.1, 0.5]), np.array([0.0, 0.0, 1.0]), tris, 1e-7, solids, None, within) == []
    flipped = _outward_box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    assert len(oa.closed_solids(flipped, 1e-7)) == 1
    flipped[:2] = flipped[:2, ::-1]  # one face turned inward
    assert oa.closed_solids(flipped, 1e-7) == []

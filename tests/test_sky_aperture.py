"""The direct sky component through openings (radiometry.skies.sky_aperture): closed forms against an
independent brute-force integration over the aperture's area, the unobstructed sky's known values,
the pane's hard bounds, the aperture finder and the visibility proof."""

import math
import pathlib
import importlib.util

import numpy as np
import pytest

from radiometer.radiometry.skies import sky_aperture as sa
from radiometer.radiometry.scene import thin_glass

WINDOW = np.array([[1.0, 0.0, 0.9], [3.0, 0.0, 0.9], [3.0, 0.0, 2.1], [1.0, 0.0, 2.1]])  # wall y = 0
OVERCAST = lambda u: (1.0 + 2.0 * u[..., 2]) / 3.0  # noqa: E731 - L / Lz of the CIE overcast sky


def _room():
    path = pathlib.Path(__file__).parent / "bpy" / "daylight_room.py"
    spec = importlib.util.spec_from_file_location("daylight_room", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _brute(p, n, L=OVERCAST, ground=0.0, T=None, cells=1200):
    """Independent reference: the area form E = int_A L cos(theta_r) cos(theta_a) / r^2 dA over the window
    (midpoint rule on cells x cells; its error is below 1e-6 relative for these points)."""
    xs = 1.0 + 2.0 * (np.arange(cells) + 0.5) / cells
    zs = 0.9 + 1.2 * (np.arange(cells) + 0.5) / cells
    x, z = np.meshgrid(xs, zs)
    r = np.stack([x, np.zeros_like(x), z], axis=-1) - p
    d = np.linalg.norm(r, axis=-1)
    u = r / d[..., None]
    cos_r, cos_a = np.maximum(u @ n, 0.0), np.abs(u[..., 1])
    lum = np.where(u[..., 2] > 0.0, L(u), ground)
    if T is not None:
        lum = lum * T(cos_a)
    return float(np.sum(lum * cos_r * cos_a / d ** 2) * (2.0 / cells) * (1.2 / cells))


CASES = [((2.0, 0.75, 0.85), (0.0, 0.0, 1.0)), ((2.0, 2.5, 0.85), (0.0, 0.0, 1.0)), ((2.0, 1.5, 1.5), (0.0, 0.0, 1.0)),
         ((0.5, 1.0, 1.2), (0.3, -0.5, 0.8)), ((2.0, 2.5, 0.85), (0.0, -1.0, 0.0)), ((3.5, 0.2, 2.0), (-1.0, 0.0, 0.0))]


@pytest.mark.parametrize("p, n", CASES)
@pytest.mark.parametrize("sky", ["overcast", "uniform"])
def test_closed_form_matches_area_integration(p, n, sky):
    p, n = np.asarray(p), np.asarray(n) / np.linalg.norm(n)
    L = OVERCAST if sky == "overcast" else (lambda u: np.ones(u.shape[:-1]))
    e_sky, e_ground = sa.aperture_illuminance(WINDOW, [p], n, zenith_luminance=1.0, ground_luminance=0.35, sky=sky)
    assert e_sky[0] == pytest.approx(_brute(p, n, L=L), rel=2e-6, abs=1e-9)
    assert e_ground[0] == pytest.approx(_brute(p, n, L=lambda u: 0.0 * u[..., 2], ground=0.35), rel=2e-6, abs=1e-9)


def test_unobstructed_sky_values():
    """A huge aperture over (or beside) the point: the overcast sky's known closed forms (cie_sky's
    docstring): E_h = 7 pi Lz / 9; a vertical plane gets Lz (pi/6 + 4/9); the uniform sky pi Lz."""
    big = 1e7
    roof = np.array([[-big, -big, 1.0], [big, -big, 1.0], [big, big, 1.0], [-big, big, 1.0]])
    assert sa.aperture_illuminance(roof, [[0, 0, 0]], [0, 0, 1])[0][0] == pytest.approx(7 * math.pi / 9, rel=1e-6)
    assert sa.aperture_illuminance(roof, [[0, 0, 0]], [0, 0, 1], sky="uniform")[0][0] == pytest.approx(math.pi, rel=1e-6)
    wall = np.array([[-big, 1.0, -big], [big, 1.0, -big], [big, 1.0, big], [-big, 1.0, big]])
    e_sky, e_ground = sa.aperture_illuminance(wall, [[0, 0, 0]], [0, 1, 0], ground_luminance=0.2 * 7 / 9)
    assert e_sky[0] == pytest.approx(math.pi / 6 + 4 / 9, rel=1e-6)
    assert e_ground[0] == pytest.approx(0.2 * 7 / 9 * math.pi / 2, rel=1e-6)  # half the hemisphere's pi Lg


def test_second_moment_is_symmetric_and_matches_sampling():
    """int (v.u)(w.u) du by the edge formula equals int (w.u)(v.u) du (the formula is not symmetric in
    form) and a Monte Carlo estimate over the spherical triangle (seeded; 6 sigma)."""
    rng = np.random.default_rng(7)
    tri = np.array([[[0.2, 0.1, 1.0], [1.0, 0.3, 0.8], [0.1, 1.1, 0.6]]])
    v, w = np.array([0.3, -0.2, 0.9]), np.array([-0.5, 0.7, 0.4])
    omega, _f, vw = sa.spherical_moments(tri, v, w)
    _o, _f, wv = sa.spherical_moments(tri, w, v)
    assert vw[0] == pytest.approx(wv[0], rel=1e-12)
    u = rng.normal(size=(2_000_000, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    a, b, c = tri[0]
    inside = ((np.cross(a, b) @ c) * (u @ np.cross(a, b)) > 0) & ((np.cross(b, c) @ a) * (u @ np.cross(b, c)) > 0) & \
             ((np.cross(c, a) @ b) * (u @ np.cross(c, a)) > 0)
    f = inside * (u @ v) * (u @ w) * 4 * math.pi
    assert abs(vw[0] - f.mean()) < 6 * f.std() / math.sqrt(len(f))
    g = inside * 4 * math.pi
    assert abs(omega[0] - g.mean()) < 6 * g.std() / math.sqrt(len(g))


def test_shapes_and_non_finite_points():
    pts = np.array([[2.0, 1.0, 0.85], [np.nan, 1.0, 0.85], [2.0, -1.0, 0.85], [2.0, 1.0, 3.0]])
    e_sky, e_ground = sa.aperture_illuminance(WINDOW, pts, [0, 0, 1])
    assert e_sky.shape == (4,) and np.isnan(e_sky[1]) and np.isnan(e_ground[1])
    assert e_sky[0] > 0 and e_sky[3] == 0.0  # the point above the window's top sees it below its horizon
    one = sa.aperture_illuminance(WINDOW, pts[0], [0, 0, 1])[0]
    assert one.shape == (1,) and one[0] == e_sky[0]
    with pytest.raises(ValueError, match="sky"):
        sa.aperture_illuminance(WINDOW, pts[:1], [0, 0, 1], sky="perez")
    with pytest.raises(ValueError, match="vertices"):
        sa.aperture_illuminance(WINDOW[:2], pts[:1], [0, 0, 1])


def _fresnel_t(c):
    """Y-weighted transmittance of a clear 6 mm pane of n = 1.52 (thin_glass.slab, equal RGB)."""
    return thin_glass.slab(c, 1.52, 0.006)[0][..., 1]


@pytest.mark.parametrize("p, n", CASES[:4])
def test_pane_bounds_hold_against_area_integration(p, n):
    p, n = np.asarray(p), np.asarray(n) / np.linalg.norm(n)
    est, half, pieces = sa.pane_bounded_illuminance(WINDOW, p, n, _fresnel_t, [0, 1, 0], ground_luminance=0.35,
                                                    rel_tol=1e-3)
    ref = _brute(p, n, ground=0.35, T=_fresnel_t)
    assert half <= 1e-3 * est and pieces > 1
    assert abs(est - ref) <= half + 1e-6 * ref  # the bound holds (plus the reference's own error)
    # Bound and closed form agree where T is constant
    flat = sa.pane_bounded_illuminance(WINDOW, p, n, lambda c: np.full(np.shape(c), 0.8), [0, 1, 0],
                                       ground_luminance=0.35)
    s, g = sa.aperture_illuminance(WINDOW, [p], n, ground_luminance=0.35)
    assert flat[0] == pytest.approx(0.8 * (s[0] + g[0]), rel=1e-12) and flat[1] == 0.0


def test_pane_bounds_of_many_points_are_each_points_own():
    """A grid's points refine together (one numpy call per round) but each by its own rule: the batch
    gives every point exactly the subdivision it gets alone (different apertures, normals and sizes)."""
    pts = [np.asarray(p, float) for p, _n in CASES[:4]]
    nrm = [np.asarray(n, float) / np.linalg.norm(n) for _p, n in CASES[:4]]
    polys = [WINDOW, WINDOW[[0, 1, 2]], WINDOW, WINDOW[[0, 2, 3]]]
    est, half, pieces = sa.pane_bounded_illuminances(polys, pts, nrm, _fresnel_t, [0, 1, 0], ground_luminance=0.35,
                                                     rel_tol=2e-3)
    for k in range(4):
        one = sa.pane_bounded_illuminance(polys[k], pts[k], nrm[k], _fresnel_t, [0, 1, 0], ground_luminance=0.35,
                                          rel_tol=2e-3)
        assert pieces[k] == one[2]
        assert est[k] == pytest.approx(one[0], rel=1e-12) and half[k] == pytest.approx(one[1], rel=1e-9)
    assert len(set(pieces.tolist())) > 2 and max(pieces) > 1000  # the points did stop at different rounds
    # and the closed form batched over apertures equals it point by point
    s, g = sa.aperture_illuminance(polys, pts, nrm, ground_luminance=0.35)
    for k in range(4):
        s1, g1 = sa.aperture_illuminance(polys[k], [pts[k]], nrm[k], ground_luminance=0.35)
        assert (s[k], g[k]) == (pytest.approx(s1[0], rel=1e-12), pytest.approx(g1[0], rel=1e-12, abs=1e-15))


def test_pane_bound_refuses_a_non_monotone_transmittance():
    with pytest.raises(ValueError, match="non-decreasing"):
        sa.pane_bounded_illuminance(WINDOW, (2, 1, 0.85), (0, 0, 1), lambda c: np.sin(6 * np.asarray(c)) ** 2, (0, 1, 0))


def _room_triangles(room):
    tris = []
    for _name, q in room.quads():
        q = np.asarray(q, float)
        tris += [q[[0, 1, 2]], q[[0, 2, 3]]]
    return np.asarray(tris)


def test_find_the_side_lit_rooms_window():
    """The room of the daylight tests is built of separate quads with T-junctions around the window."""
    room = _room()
    found = sa.find_apertures(_room_triangles(room), tol=1e-6)
    assert len(found) == 1
    poly, normal = found[0]
    x0, x1, z0, z1 = room.WINDOW
    assert sorted(map(tuple, np.round(poly, 9))) == sorted([(x0, 0, z0), (x1, 0, z0), (x1, 0, z1), (x0, 0, z1)])
    assert abs(normal[1]) == pytest.approx(1.0) and sa.is_convex(poly)
    assert sa.find_apertures(np.zeros((0, 3, 3))) == []
    # the window closed by a quad: no hole left
    x0, x1, z0, z1 = room.WINDOW
    cap = np.array([[[x0, 0, z0], [x1, 0, z0], [x1, 0, z1]], [[x0, 0, z0], [x1, 0, z1], [x0, 0, z1]]], float)
    assert sa.find_apertures(np.r_[_room_triangles(room), cap], tol=1e-6) == []


def test_aperture_clear_proves_and_refuses():
    room = _room()
    tris = _room_triangles(room)
    poly = sa.find_apertures(tris, tol=1e-6)[0][0]
    for p in room.POINTS:
        assert sa.aperture_clear(p, poly, tris, 1e-6, reach=100.0)
    # an obstruction outside, above the point's horizon through the window: not proven
    block = np.array([[[1.5, -5.0, 1.5], [2.5, -5.0, 1.5], [2.0, -5.0, 4.0]]])
    assert not sa.aperture_clear(room.POINTS[0], poly, np.r_[tris, block], 1e-6, reach=100.0)
    # one below the point's horizon does not block the sky part
    high = (2.0, 1.5, 1.5)  # sees the window's lower part below its horizon
    low = np.array([[[1.5, -1.0, 0.1], [2.5, -1.0, 0.1], [2.0, -1.0, 0.8]]])
    assert sa.aperture_clear(high, poly, np.r_[tris, low], 1e-6, reach=100.0)
    assert not sa.aperture_clear(high, poly, np.r_[tris, low], 1e-6, reach=100.0, sky_only=False)
    # a pane filling the window is in the way unless the caller accounts for it
    pane = np.array([[[1.0, -0.006, 0.9], [3.0, -0.006, 0.9], [3.0, -0.006, 2.1]]])
    assert not sa.aperture_clear(room.POINTS[0], poly, np.r_[tris, pane], 1e-6, reach=100.0)
    ignore = np.r_[np.zeros(len(tris), bool), True]
    assert sa.aperture_clear(room.POINTS[0], poly, np.r_[tris, pane], 1e-6, reach=100.0, ignore=ignore)


def test_aperture_clear_is_sound_against_sampled_rays():
    """Random triangles outside the window: whenever the proof says clear, no sampled ray through the
    window's sky part hits one (brute-force ray casting; the proof may refuse more than needed)."""
    rng = np.random.default_rng(11)
    p = np.array([2.0, 0.75, 0.85])
    room = _room()
    tris = _room_triangles(room)
    poly = sa.find_apertures(tris, tol=1e-6)[0][0]
    s = rng.uniform(size=(4000, 2))
    targets = np.c_[1 + 2 * s[:, 0], np.zeros(len(s)), 0.9 + 1.2 * s[:, 1]]
    dirs = targets - p
    dirs = dirs[dirs[:, 2] > 0]
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    proved = 0
    for _ in range(60):
        c = np.array([rng.uniform(-2, 6), rng.uniform(-8, -0.5), rng.uniform(-1, 8)])
        tri = c + rng.normal(scale=0.8, size=(3, 3))
        clear = sa.aperture_clear(p, poly, np.r_[tris, tri[None]], 1e-9, reach=50.0)
        # Möller-Trumbore of the sampled rays against the triangle
        e1, e2 = tri[1] - tri[0], tri[2] - tri[0]
        h = np.cross(dirs, e2)
        det = h @ e1
        f = 1.0 / det
        sv = p - tri[0]
        u = f * (h @ sv)
        q = np.cross(sv, e1)
        v = f * (dirs @ q)
        t = f * (q @ e2)
        hit = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        if clear:
            proved += 1
            assert not np.any(hit)
    assert proved >= 10  # the test exercised the proof


def test_enclosure_closed_and_inside():
    """The side-lit room is closed apart from its window; a hole elsewhere, or a missing wall, breaks
    the proof; points in the room are inside, points outside are not."""
    room = _room()
    tris = _room_triangles(room)
    loops = [poly for poly, _n in sa.find_apertures(tris, tol=1e-6)]
    closed, comp, reason = sa.enclosure_closed(tris, loops, 1e-6)
    assert closed and comp.all() and reason == ""
    for p in room.POINTS:
        assert sa.inside_enclosure(p, tris, loops, 1e-6) is True
    assert sa.inside_enclosure((2.0, -1.0, 1.0), tris, loops, 1e-6) is False
    assert sa.inside_enclosure((2.0, 1.0, 5.0), tris, loops, 1e-6) is False
    # the back wall removed: open, and the proof says so
    no_back = np.r_[tris[:4], tris[6:]]
    closed, _comp, reason = sa.enclosure_closed(no_back, loops, 1e-6)
    assert not closed and "not closed" in reason
    # a second hole that the caller did not list as an aperture
    x0, x1, z0, z1 = room.WINDOW
    cut = [(n, q) for n, q in room.quads() if not (n == "walls" and q[0] == (x0, 0, z1))]  # drop the strip above
    cut_tris = _room_triangles(type("R", (), {"quads": staticmethod(lambda: cut)}))
    closed, _comp, _reason = sa.enclosure_closed(cut_tris, loops, 1e-6)
    assert not closed


def test_a_furniture_piece_does_not_break_closure():
    """A single-sided table top inside the room is not connected to the room's shell: the shell stays
    closed (the table may still block an aperture: aperture_clear decides that)."""
    room = _room()
    tris = _room_triangles(room)
    table = np.array([[[1.0, 1.0, 0.7], [2.0, 1.0, 0.7], [2.0, 2.0, 0.7]], [[1.0, 1.0, 0.7], [2.0, 2.0, 0.7], [1.0, 2.0, 0.7]]])
    loops = [poly for poly, _n in sa.find_apertures(np.r_[tris, table], tol=1e-6)]
    assert len(loops) == 1
    closed, comp, _ = sa.enclosure_closed(np.r_[tris, table], loops, 1e-6)
    assert closed and comp[:len(tris)].all() and not comp[len(tris):].any()


def test_a_cabinet_against_a_wall_keeps_the_room_closed():
    """A closed box standing in the corner of floor and wall shares their seam (an edge piece used four times):
    the room stays closed (every piece of edge used an even number of times), points in the room are inside and a
    point in the box is not. A single board standing on the same seam leaves edges used once: not closed."""
    room = _room()
    tris = _room_triangles(room)
    cabinet = room.box_triangles((3.5, 1.5, 0.0), (4.0, 2.5, 2.0))  # against the wall x = 4 (the room is 4 m wide)
    both = np.r_[tris, cabinet]
    loops = [poly for poly, _n in sa.find_apertures(both, tol=1e-6)]
    assert len(loops) == 1
    closed, comp, reason = sa.enclosure_closed(both, loops, 1e-6)
    assert closed and comp.all() and reason == "", reason
    inside = sa.inside_enclosures([(2.0, 1.5, 0.85), (3.0, 2.0, 0.85), (3.75, 2.0, 0.85)], both[comp], loops, 1e-6)
    assert inside == [True, True, False]
    assert [len(part) for part in sa.closed_components(cabinet, 1e-6)] == [12]
    board = np.array([[[4.0, 1.0, 0.0], [3.5, 1.0, 0.0], [3.5, 1.0, 1.0]], [[4.0, 1.0, 0.0], [3.5, 1.0, 1.0], [4.0, 1.0, 1.0]]])
    closed, _comp, reason = sa.enclosure_closed(np.r_[tris, board], loops, 1e-6)
    assert not closed and "used 1 time" in reason


def test_a_window_frame_is_no_opening():
    """A window frame in the opening (bars half in front of the wall's plane, touching the opening's corners): the
    rings of its front and back faces are holes in their planes, but its inner faces close them: the room has one
    opening, not five (the sky through the frame's rings was counted again for each), and stays closed."""
    room = _room()
    tris = _room_triangles(room)
    frame = np.concatenate([room.box_triangles(lo, hi) for lo, hi in room.window_frame_boxes()])
    both = np.r_[tris, frame]
    loops = [poly for poly, _n in sa.find_apertures(both, tol=1e-6)]
    assert len(loops) == 5  # the window and, either side of the mullion, the rings of the frame's front and back faces
    holes = sa.shell_holes(both, loops, 1e-6)
    assert len(holes) == 1 and np.allclose(np.ptp(holes[0], axis=0), [2.0, 0.0, 1.2])
    closed, comp, reason = sa.enclosure_closed(both, holes, 1e-6)
    assert closed and reason == ""
    assert sa.shell_holes(tris, [poly for poly, _n in sa.find_apertures(tris, tol=1e-6)], 1e-6)  # the bare room's


def test_a_sill_on_the_wall_under_the_window_keeps_the_opening():
    """An interior sill whose back face lies on the wall, its top at the window's bottom edge: the back face shares
    that edge with the wall, both from below, so the edge was used twice and the window's outline was lost ("no
    opening found"). The edge bounds the UNION of the wall's faces (nothing of the plane covers the window's side of
    it): the opening is found, it is the shell's hole (the edge is used three times: wall, back face, top face) and
    the room stays closed. A sill raised into the window (its back face covering the opening's bottom strip) crosses
    the opening's side edges where neither has a vertex: the plane's edges are not cut there, so no loop closes and no
    opening is claimed (the room then takes the proof that needs none; a loop over the covered strip would be
    refused by ``_filled`` anyway)."""
    room = _room()
    tris = _room_triangles(room)
    x0, x1, z0, z1 = room.WINDOW
    sill = room.box_triangles((x0 - 0.1, 0.0, z0 - 0.05), (x1 + 0.1, 0.25, z0))
    both = np.r_[tris, sill]
    loops = [poly for poly, _n in sa.find_apertures(both, tol=1e-6)]
    assert len(loops) == 1
    assert sorted(map(tuple, np.round(loops[0], 9))) == sorted([(x0, 0, z0), (x1, 0, z0), (x1, 0, z1), (x0, 0, z1)])
    assert sa.shell_holes(both, loops, 1e-6)
    closed, comp, reason = sa.enclosure_closed(both, loops, 1e-6)
    assert closed and comp.all() and reason == "", reason
    assert sa.inside_enclosures([(2.0, 1.0, 0.85), (2.0, 0.1, z0 - 0.02)], both[comp], loops, 1e-6) == [True, False]
    raised = room.box_triangles((x0 - 0.1, 0.0, z0), (x1 + 0.1, 0.25, z0 + 0.05))
    assert sa.find_apertures(np.r_[tris, raised], tol=1e-6) == []


def test_an_aperture_wholly_behind_every_point_gives_zero():
    """Points that face away from the aperture (a vertical meter with its back to the window, one facing up above
    the window's head) read 0 from it, alone or together (it raised a numpy error when no point saw it)."""
    window = np.array([[1.0, 0.0, 0.9], [3.0, 0.0, 0.9], [3.0, 0.0, 2.1], [1.0, 0.0, 2.1]])
    for points, normals in ((np.array([[2.0, 1.5, 0.85]]), np.array([[0.0, 1.0, 0.0]])),
                            (np.array([[2.0, 1.5, 0.85], [2.0, 1.5, 2.5]]), np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]))):
        sky, ground = sa.aperture_illuminance(window, points, normals, zenith_luminance=1.0,
                                                        ground_luminance=0.3)
        assert sky.dtype == float and np.all(sky == 0.0) and np.all(ground == 0.0)

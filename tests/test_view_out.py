"""EN 17037 view out from the geometry (radiometry/scene/view_out.py, pure): the side-lit room of the
daylight tests (tests/bpy/daylight_room.py) with surroundings built as boxes. References: the sight angle
of a window in closed form (the azimuths of its jambs from the eye), the layers and distances from where
rays must go in those boxes, the ray casts against visibility.first_hits (an independent loop)."""

import math
import pathlib
import runpy
import types

import numpy as np
import pytest

from radiometer.radiometry.metrics import en17037
from radiometer.radiometry.scene import view_out, visibility
from radiometer.radiometry.skies import sky_aperture


def _room():
    return types.SimpleNamespace(**runpy.run_path(str(pathlib.Path(__file__).parent / "bpy" / "daylight_room.py")))


ROOM = _room()


def _tris(quads):
    out = []
    for _name, q in quads:
        q = np.asarray(q, float)
        out += [q[[0, 1, 2]], q[[0, 2, 3]]]
    return np.array(out)


def _openings(tris):
    return [p for p, _n in sky_aperture.find_apertures(tris, 1e-6)]


def _sight_angle(eye):
    """The window's jambs x0, x1 in the wall y = 0, seen from the eye in plan (deg)."""
    x0, x1 = ROOM.WINDOW[:2]
    return math.degrees(math.atan2(x1 - eye[0], eye[1]) - math.atan2(x0 - eye[0], eye[1]))


@pytest.mark.parametrize("eye", [(2.0, 1.5, 1.2), (0.5, 2.9, 1.2), (3.7, 0.4, 1.7), (2.0, 0.2, 1.0)])
def test_sight_angle_is_the_windows_in_plan(eye):
    tris = _tris(ROOM.quads())
    v = view_out.eye_views([eye], _openings(tris), tris)[0]
    want = _sight_angle(eye)
    # counted in azimuth steps whose centres a ray went out at: within one step of the true angle
    assert abs(v.horizontal_sight_angle_deg - want) <= view_out.STEP_DEG
    assert v.rays_out > 0


def test_layers_and_distance_with_a_building_opposite():
    """A 40 m wide, 6 m high block 15 m in front of the window wall: from an eye at 1.2 m in the room's
    middle the window shows the block (landscape), the sky over it (the window head at 31 deg, the block's
    top at 15 deg) and the ground under it (the sill at -11 deg, its foot at -4 deg)."""
    tris = _tris(ROOM.quads() + ROOM.obstruction_quads(gap=15.0, width=40.0, height=6.0))
    ops = _openings(_tris(ROOM.quads()))
    v = view_out.eye_views([(2.0, 1.5, 1.2)], ops, tris)[0]
    assert v.layers == ("sky", "landscape", "ground")
    # level rays meet the block's face 15 m out, oblique ones further: at most 15 / cos(azimuth) / cos(10 deg)
    half = math.radians(_sight_angle((2.0, 1.5, 1.2)) / 2)
    assert 15.0 <= v.outside_distance_m <= 15.0 / math.cos(half) / math.cos(math.radians(10.0))
    assert v.layer_score() == 3
    assert view_out.surroundings_modelled(tris, ops, False)


def test_a_tall_block_close_by_hides_the_sky():
    """A 30 m high block 3 m out: the window head (31 deg from the eye) is below the block's top
    (atan(28.8 / 4.5) = 81 deg), so no sky; its foot hides below the sill, so no ground either."""
    tris = _tris(ROOM.quads() + ROOM.obstruction_quads(gap=3.0, width=60.0, height=30.0))
    v = view_out.eye_views([(2.0, 1.5, 1.2)], _openings(_tris(ROOM.quads())), tris)[0]
    assert v.layers == ("landscape",)
    assert 3.0 <= v.outside_distance_m <= 3.0 / math.cos(math.radians(34)) / math.cos(math.radians(10))
    row = en17037.view_out(v.horizontal_sight_angle_deg, v.outside_distance_m, v.layer_score())
    assert row.level == "not met"          # 3.x m < 6 m


def test_open_room_sees_sky_and_ground_but_models_no_surroundings():
    tris = _tris(ROOM.quads())
    ops = _openings(tris)
    v = view_out.eye_views([(2.0, 1.5, 1.2)], ops, tris)[0]
    assert v.layers == ("sky", "ground") and v.outside_distance_m == math.inf and v.layer_score() == 0
    assert not view_out.surroundings_modelled(tris, ops, False)
    ground = np.array([[[-50, -50, 0], [50, -50, 0], [50, 50, 0]], [[-50, -50, 0], [50, 50, 0], [-50, 50, 0]]], float)
    with_ground = np.concatenate([tris, ground - [0, 0, 0.01]])
    assert not view_out.surroundings_modelled(with_ground, ops, False)   # a ground plane alone is no landscape
    v = view_out.eye_views([(2.0, 1.5, 1.2)], ops, with_ground)[0]
    assert v.layers == ("sky", "ground")                              # the plane is seen as ground


def test_a_baffle_hides_the_window_and_a_column_splits_it():
    tris = _tris(ROOM.quads())
    ops = _openings(tris)
    eye = (2.0, 1.5, 1.2)
    baffle = _tris([("b", [(0.5, 1.0, 0.0), (3.5, 1.0, 0.0), (3.5, 1.0, 2.7), (0.5, 1.0, 2.7)])])
    v = view_out.eye_views([eye], ops, np.concatenate([tris, baffle]))[0]
    assert v.rays_out == 0 and v.horizontal_sight_angle_deg == 0.0 and v.layers == ()
    # a 0.2 m column at x 1.9-2.1 just inside the window: two runs, the larger counts
    column = _tris([("c", [(1.9, 0.3, 0.0), (2.1, 0.3, 0.0), (2.1, 0.3, 2.7), (1.9, 0.3, 2.7)])])
    v = view_out.eye_views([eye], ops, np.concatenate([tris, column]))[0]
    side = math.degrees(math.atan2(1.0, 1.5) - math.atan2(0.1, 1.2))     # jamb to the column's edge
    assert abs(v.horizontal_sight_angle_deg - side) <= view_out.STEP_DEG


def test_largest_run_wraps_round_north():
    total = 720
    assert view_out._largest_run(np.array([718, 719, 0, 1, 2, 10, 11]), total) == 5
    assert view_out._largest_run(np.array([5, 6, 7, 100]), total) == 3
    assert view_out._largest_run(np.arange(total), total) == total
    assert view_out._largest_run(np.array([], int), total) == 0


def test_batched_hits_equal_the_one_ray_loop():
    rng = np.random.default_rng(3)
    tris = _tris(ROOM.quads() + ROOM.obstruction_quads())
    origin = np.array([2.0, 1.5, 1.2])
    dirs = rng.normal(size=(300, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    d1, k1 = view_out.first_hits_many(np.broadcast_to(origin, dirs.shape), dirs, tris)
    d2, k2, _ = visibility.first_hits(origin, dirs, tris)
    assert np.array_equal(k1, k2)
    assert np.allclose(d1, d2, rtol=1e-12, atol=0) or np.array_equal(np.isinf(d1), np.isinf(d2))


def test_view_out_over_points_takes_what_three_quarters_reach():
    row = en17037.view_out_over_points([60, 60, 60, 10], [60, 60, 60, 60], [3, 3, 3, 3])
    assert row.level == "high"                 # 3 of 4 points (75 %) reach 54 deg
    row = en17037.view_out_over_points([60, 60, 10, 10], [60] * 4, [3] * 4)
    assert row.level == "not met"              # half the points see 10 deg
    row = en17037.view_out_over_points([60] * 4, [math.inf] * 4, [2] * 4)
    assert row.level == "medium" and row.values["points"] == 4
    with pytest.raises(ValueError):
        en17037.view_out_over_points([60], [1, 2], [3])
    with pytest.raises(ValueError):
        en17037.view_out(30, math.nan, 2)


def test_a_thick_walls_reveal_is_no_landscape():
    """The demo's daylit room of 0.1 m thick boxes (tests/test_daylight_map.py): its window has an inner and an
    outer outline. Rays through the inner one that meet the reveal do not go out, and the reveal is no
    landscape: with nothing outside the room, the view shows sky and ground only; the sight angle is bounded by
    the jambs' outer corners (the reveal hides the rest), within one step."""
    hx, hy, h, t, w, sill, head = 2.0, 2.0, 3.0, 0.3, 1.0, 0.9, 2.1
    boxes = ROOM.box_room_boxes(t, hx, hy, h, w, sill, head)
    tris = np.concatenate([ROOM.box_triangles(lo, hi) for lo, hi in boxes])
    ops = _openings(tris)
    assert len(ops) == 2
    eye = np.array([0.5, 0.0, 1.2])
    v = view_out.eye_views([eye], ops, tris)[0]
    assert v.layers == ("sky", "ground") and not view_out.surroundings_modelled(tris, ops, "landscape" in v.layers)
    # an eye between the jambs (|x| < w) sees past each jamb up to its outer corner (y = -hy - t)
    d_out = hy + t - eye[1]
    want = math.degrees(math.atan2(w - eye[0], d_out) + math.atan2(w + eye[0], d_out))
    assert abs(v.horizontal_sight_angle_deg - want) <= view_out.STEP_DEG, (v.horizontal_sight_angle_deg, want)


def test_a_roof_light_is_no_view_out():
    """The skylight room (tests/bpy/daylight_room.py skylight_quads): the eye under the roof light sees only
    sky straight up; a roof light is not a window (its plane is horizontal), so no ray counts."""
    tris = _tris(ROOM.skylight_quads())
    ops = _openings(tris)
    assert len(ops) == 1
    v = view_out.eye_views([(2.0, 2.0, 1.2)], ops, tris)[0]
    assert v.rays_out == 0 and v.horizontal_sight_angle_deg == 0.0 and v.layers == ()


def test_the_wedge_cull_loses_no_hit(monkeypatch):
    """Triangles scattered all round the room: the views with the azimuth-wedge cull equal those without."""
    rng = np.random.default_rng(7)
    centres = rng.uniform([-20, -20, -1], [24, 23, 8], (3000, 1, 3))
    junk = centres + rng.normal(scale=0.6, size=(3000, 3, 3))
    outside = (junk[:, :, 1] < -0.05).all(axis=1) | (junk[:, :, 1] > 3.05).all(axis=1) | \
        (junk[:, :, 0] < -0.05).all(axis=1) | (junk[:, :, 0] > 4.05).all(axis=1)         # none inside the room
    tris = np.concatenate([_tris(ROOM.quads()), junk[outside]])
    ops = _openings(_tris(ROOM.quads()))
    eyes = [(2.0, 1.5, 1.2), (0.3, 0.4, 1.0), (3.8, 2.8, 1.7)]
    culled = view_out.eye_views(eyes, ops, tris)
    monkeypatch.setattr(view_out, "_in_wedge", lambda t, *a: np.ones(len(t), bool))
    assert culled == view_out.eye_views(eyes, ops, tris)


def test_the_buildings_own_parts_and_furniture_are_no_surroundings():
    """An overhang joined to the window head (it shares the head's corners) is the building, not the
    landscape; a desk inside the room is furniture: with nothing else outside, view out is not assessable."""
    x0, x1, _z0, z1 = ROOM.WINDOW
    overhang = [("walls", [(x0, 0.0, z1), (x0, -1.0, z1), (x1, -1.0, z1), (x1, 0.0, z1)])]
    desk = [("walls", [(1.0, 2.0, 0.0), (3.0, 2.0, 0.0), (3.0, 2.0, 0.75), (1.0, 2.0, 0.75)])]
    tris = _tris(ROOM.quads() + overhang + desk)
    ops = _openings(_tris(ROOM.quads()))
    v = view_out.eye_views([(2.0, 1.5, 1.2)], ops, tris)[0]
    assert "landscape" not in v.layers and v.rays_out > 0
    assert not view_out.surroundings_modelled(tris, ops, "landscape" in v.layers)


def test_an_overhang_box_apart_from_the_wall_is_the_building():
    """A 1 m deep overhang modelled as its own box 0.1 m over the window head (no shared vertex): within
    OWN_GAP_M of the room, so it is built onto it, not a landscape; a ground plane under the room is not."""
    x0, x1, _z0, z1 = ROOM.WINDOW
    tris = np.concatenate([_tris(ROOM.quads()), ROOM.box_triangles((x0, -1.0, z1 + 0.1), (x1, 0.0, z1 + 0.2)),
                           ROOM.box_triangles((-30.0, -30.0, -0.2), (30.0, 30.0, -0.01))])
    ops = _openings(_tris(ROOM.quads()))
    v = view_out.eye_views([(2.0, 1.5, 1.2)], ops, tris)[0]
    assert v.layers == ("sky", "ground"), v
    assert not view_out.surroundings_modelled(tris, ops, False)

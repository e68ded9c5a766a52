"""Exact visibility proofs (radiometry.scene.visibility, radiometry.scene.scene_model.plan_direct): soundness
against brute-force point sampling, and the decisions on small synthetic scenes."""

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.scene import scene_model, visibility

TOL = 1e-9


def _square(z, half=0.5, cx=0.0, cy=0.0):
    return np.array([[cx - half, cy - half, z], [cx + half, cy - half, z], [cx + half, cy + half, z],
                     [cx - half, cy + half, z]])


def _inside_pyramid(points, apex, base):
    """Brute force: a point is inside the pyramid when it is a convex combination apex + s*(q - apex),
    q in the base polygon, 0 <= s <= 1 (checked with half-spaces of the hull faces)."""
    verts, normals, _ = visibility.pyramid(apex, base)
    centroid = verts.mean(axis=0)
    inside = np.ones(len(points), bool)
    faces = [base[0]] + [apex] * len(base)
    for n, q in zip(normals, faces):
        s = np.sign((centroid - q) @ n)
        inside &= ((points - q) @ n) * s >= -1e-12
    return inside


def test_sat_never_calls_a_meeting_triangle_clear():
    rng = np.random.default_rng(3)
    apex = np.array([0.0, 0.0, 0.0])
    base = _square(2.0, half=0.6)
    poly = visibility.pyramid(apex, base)
    tris = rng.uniform(-1.5, 2.5, size=(3000, 3, 3)) * np.array([1, 1, 1]) * 0.8
    tris[:, :, 2] = rng.uniform(-0.5, 2.5, size=(3000, 3))
    meets = visibility.triangles_meet_polytope(tris, poly, TOL)
    # Dense barycentric samples of each triangle: any sample inside the pyramid proves a meeting.
    a, b = np.meshgrid(np.linspace(0, 1, 25), np.linspace(0, 1, 25))
    keep = a + b <= 1
    a, b = a[keep], b[keep]
    for k in range(len(tris)):
        t = tris[k]
        pts = t[0] + a[:, None] * (t[1] - t[0]) + b[:, None] * (t[2] - t[0])
        if _inside_pyramid(pts, apex, base).any():
            assert meets[k], f"triangle {k} meets the pyramid but was called clear"
    # ... and the test is not trivially "always meets": most random triangles are far off.
    assert 0.1 < meets.mean() < 0.9


def test_sat_cases():
    apex = np.zeros(3)
    poly = visibility.pyramid(apex, _square(2.0))
    inside = np.array([[[0, 0, 1.0], [0.05, 0, 1.0], [0, 0.05, 1.0]]])        # wholly inside
    crossing = np.array([[[-5, -5, 1.0], [5, -5, 1.0], [0, 5, 1.0]]])          # big plane through it
    aside = np.array([[[3, 3, 1.0], [4, 3, 1.0], [3, 4, 1.0]]])
    behind = np.array([[[-5, -5, 2.01], [5, -5, 2.01], [0, 5, 2.01]]])         # above the light
    below = np.array([[[-5, -5, -1e-6], [5, -5, -1e-6], [0, 5, -1e-6]]])       # floor under the apex
    touching = np.array([[[-5, -5, 2.0], [5, -5, 2.0], [0, 5, 2.0]]])         # ceiling flush with light
    got = [visibility.triangles_meet_polytope(t, poly, TOL)[0]
           for t in (inside, crossing, aside, behind, below, touching)]
    assert got == [True, True, False, False, False, True]


def test_segment_status():
    opaque = np.array([True])
    wall = np.array([[[-1, -1, 0.5], [3, -1, 0.5], [-1, 3, 0.5]]])
    assert visibility.segment_status([0, 0, 0], [0, 0, 1], wall, opaque, TOL)[0] == visibility.BLOCKED
    assert visibility.segment_status([0, 0, 0], [0, 0, 1], wall, np.array([False]), TOL)[0] == visibility.PARTIAL
    assert visibility.segment_status([0, 0, 0], [0, 0, 0.4], wall, opaque, TOL)[0] == visibility.CLEAR
    assert visibility.segment_status([5, 5, 0], [5, 5, 1], wall, opaque, TOL)[0] == visibility.CLEAR
    # The segment passes exactly through the triangle's edge: undecidable, never "clear".
    edge = np.array([[[0, -1, 0.5], [0, 1, 0.5], [2, 0, 0.5]]])
    assert visibility.segment_status([0, 0, 0], [0, 0, 1], edge, opaque, TOL)[0] == visibility.PARTIAL


def _model(tris, *specs, opaque=True):
    tris = np.asarray(tris, float).reshape(-1, 3, 3)
    geometry = scene_model.SceneGeometry(
        triangles=tris, object_index=np.zeros(len(tris), int), object_names=["Box"],
        casts_shadow=np.array([True]), opaque=np.full(len(tris), opaque), reflects=np.array([True]),
        emissive=np.zeros(len(tris), bool))
    return scene_model.SceneModel(lights=[scene_model.ModelLight(s.name, s) for s in specs], geometry=geometry)


def test_plan_direct_area_light_over_a_desk():
    panel = emitters.CyclesLight(name="panel", kind="AREA", position=(0, 0, 2.0), size=0.6)
    desk = [[[-1, -1, 0.0], [1, -1, 0.0], [1, 1, 0.0]], [[-1, -1, 0.0], [1, 1, 0.0], [-1, 1, 0.0]]]
    model = _model(desk, panel)
    eps = scene_model.receiver_offset([[0, 0, 0.0]])[0]
    plan = scene_model.plan_direct(model, [[0, 0, eps], [0.3, 0.2, eps]], [[0, 0, 1]] * 2)
    assert list(plan.status[0]) == [scene_model.EXACT] * 2
    assert plan.exact_points().all()  # the desk lies below the meters' horizon: no indirect light
    # Exactly on the desk: the desk is in the horizon plane, so it cuts no light arriving from above.
    plan0 = scene_model.plan_direct(model, [[0, 0, 0.0]], [[0, 0, 1]])
    assert plan0.exact_points().all()
    # A meter under the desk, facing up: the desk covers the whole panel (and reflects nothing down).
    under = scene_model.plan_direct(model, [[0, 0, -0.1]], [[0, 0, 1]])
    assert under.status[0, 0] == scene_model.RENDER and under.indirect[0]


def test_plan_direct_partial_and_blocked():
    panel = emitters.CyclesLight(name="panel", kind="AREA", position=(0, 0, 2.0), size=0.6)
    lamp = emitters.CyclesLight(name="lamp", kind="POINT", position=(0, 0, 2.0), radius=0.0)
    # A small card at 1 m that covers the panel's centre but not its corners.
    # (Its diagonal misses the lamp's segment: a segment through a shared edge is undecidable.)
    card = [[[-0.05, -0.05, 1.0], [0.05, -0.05, 1.0], [0.05, 0.07, 1.0]],
            [[-0.05, -0.05, 1.0], [0.05, 0.07, 1.0], [-0.05, 0.07, 1.0]]]
    model = _model(card, panel, lamp)
    plan = scene_model.plan_direct(model, [[0, 0, 0.0], [3, 0, 0.0]], [[0, 0, 1]] * 2)
    assert plan.status[0, 0] == scene_model.RENDER and "Box" in plan.reason[0, 0]
    assert plan.status[1, 0] == scene_model.ZERO and "blocked" in plan.reason[1, 0]
    assert plan.status[0, 1] == scene_model.EXACT and plan.status[1, 1] == scene_model.EXACT
    # The card is above both meters' horizon and reflects: the readings need rendering anyway.
    assert plan.indirect.all() and not plan.exact_points().any()
    # A glass card blocks nothing for sure: the delta light is then undecidable, not zero.
    glass = _model(card, panel, lamp, opaque=False)
    assert scene_model.plan_direct(glass, [[0, 0, 0.0]], [[0, 0, 1]]).status[1, 0] == scene_model.RENDER


def test_plan_direct_flags():
    lamp = emitters.CyclesLight(name="lamp", kind="POINT", position=(0, 0, 2.0))
    wall = [[[-5, -5, 1.0], [5, -5, 1.0], [0, 5, 1.0]]]
    model = _model(wall, lamp, lamp, lamp)
    model.lights[0].casts_shadow = False
    model.lights[1].reaches_diffuse = False
    model.lights[2].portal = True
    plan = scene_model.plan_direct(model, [[0, 0, 0.0]], [[0, 0, 1]])
    assert list(plan.status[:, 0]) == [scene_model.EXACT, scene_model.ZERO, scene_model.ZERO]


@pytest.mark.parametrize("point", [[0, 0, 0.0], [0.2, -0.1, 0.5]])
def test_receiver_inside_a_sphere_light_is_never_proved(point):
    ball = emitters.CyclesLight(name="ball", kind="POINT", position=(0, 0, 0.3), radius=0.5, soft_falloff=False)
    tiny = [[[10, 10, 10.0], [10.1, 10, 10.0], [10, 10.1, 10.0]]]
    plan = scene_model.plan_direct(_model(tiny, ball), [point], [[0, 0, 1]])
    assert plan.status[0, 0] == scene_model.RENDER


def test_segment_through_the_diagonal_of_a_split_quad_is_blocked():
    # A quad split into two triangles along its diagonal, a lamp right above the centre: the
    # segment meets the shared edge, and the two coplanar triangles cover both sides of it.
    quad = np.array([[[-1, -1, 1.0], [1, -1, 1.0], [1, 1, 1.0]], [[-1, -1, 1.0], [1, 1, 1.0], [-1, 1, 1.0]]])
    status, _ = visibility.segment_status([0, 0, 0], [0, 0, 2], quad, np.array([True, True]), TOL)
    assert status == visibility.BLOCKED
    # The same edge on its own (one triangle) stays undecidable, as does a crease (non-coplanar).
    assert visibility.segment_status([0, 0, 0], [0, 0, 2], quad[:1], np.array([True]), TOL)[0] == visibility.PARTIAL
    crease = quad.copy()
    crease[1, 2] = [-1, 1, 1.5]
    assert visibility.segment_status([0, 0, 0], [0, 0, 2], crease, np.array([True, True]), TOL)[0] == visibility.PARTIAL


def test_triangle_grid_finds_exactly_the_overlapping_boxes():
    rng = np.random.default_rng(5)
    centres = rng.uniform(-10, 10, (5000, 1, 3))
    tris = centres + rng.normal(0, 0.3, (5000, 3, 3)) * rng.uniform(0.1, 20, (5000, 1, 1))
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    grid = visibility.TriangleGrid(lo, hi)
    for _ in range(50):
        a = rng.uniform(-12, 12, 3)
        b = a + rng.uniform(0, 6, 3)
        want = np.flatnonzero(visibility.aabb_overlap(lo, hi, a, b, 1e-6))
        assert np.array_equal(grid.query(a, b, 1e-6), want)

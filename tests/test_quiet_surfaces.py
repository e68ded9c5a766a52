"""Issue 32: finite, true statements. A surface above a meter's horizon that provably sends it no light
does not make the reading 'may be lit by reflection': a pane whose mirror image of the sun misses the
meter (``scene_model.mirror_misses``), and an opaque plane whose side towards the meter nothing can
light (``scene_model.dark_planes``, a lamp with shadows off behind a wall)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.scene import scene_model, thin_glass

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_thin_glass import _box  # noqa: E402
from test_thin_glass_recognition import _axes_towards  # noqa: E402


def _quad(a, b, c, d):
    return [[a, b, c], [a, c, d]]


def _sun(to_sun, angle_deg=0.53):
    return emitters.CyclesLight(name="sun", kind="SUN", axes=_axes_towards(-np.asarray(to_sun, float)),
                                rgb_power=(100.0,) * 3, angle=math.radians(angle_deg))


def _window_model(light):
    """A vertical 6 mm pane (2 x 2 m, in the plane y = 0, sill at z = 0.5 m) and nothing else."""
    tris = _box((-1.0, -0.003, 0.5), (1.0, 0.003, 2.5))
    geom, why = thin_glass.pane_geometry(tris, thin_glass.coordinate_tolerance(2.0))
    assert geom is not None, why
    pane = thin_glass.Pane(name="Window", ior=1.52, thickness=geom.thickness, geometry=geom, model="test")
    geometry = scene_model.SceneGeometry(
        triangles=tris, object_index=np.zeros(len(tris), int), object_names=["Window"],
        casts_shadow=np.array([True]), opaque=np.zeros(len(tris), bool), reflects=np.array([True]),
        emissive=np.zeros(len(tris), bool), pane_of=np.zeros(len(tris), int))
    return scene_model.SceneModel(lights=[scene_model.ModelLight("light", light)], geometry=geometry,
                                  panes={0: pane})


def test_open_floor_sun_is_exact_where_the_panes_mirror_image_misses():
    """The sun at 40 deg elevation on the meter's side of a window: its mirror image comes up from the
    floor at tan(40 deg) x distance: 4.2 m at 5 m away (above the pane's 2.5 m head: missed, the reading
    is exact), 0.84 m at 1 m away (in the pane: the meter sees the sun in it; not exact), and 3.5 m to
    the side it passes the pane's edge (exact)."""
    e = math.radians(40.0)
    model = _window_model(_sun((0.0, -math.cos(e), math.sin(e))))
    points = [[0.0, -5.0, 0.0], [0.0, -1.0, 0.0], [3.5, -1.0, 0.0]]
    plan = scene_model.plan_direct(model, points, [[0, 0, 1]] * 3)
    assert list(plan.status[0]) == [scene_model.EXACT] * 3  # the sun shines away from the pane
    assert list(plan.indirect) == [False, True, False], plan.indirect_reason
    assert list(plan.exact_points()) == [True, False, True]
    # A second pane on the meter's side could send the first light to mirror: no proof then.
    tris = np.concatenate([model.geometry.triangles, _box((-1.0, -3.003, 0.5), (1.0, -2.997, 1.0))])
    geoms = [model.panes[0].geometry, thin_glass.pane_geometry(tris[12:], 1e-6)[0]]
    geometry = scene_model.SceneGeometry(
        triangles=tris, object_index=np.repeat([0, 1], 12), object_names=["Window", "Low pane"],
        casts_shadow=np.array([True, True]), opaque=np.zeros(24, bool), reflects=np.array([True, True]),
        emissive=np.zeros(24, bool), pane_of=np.repeat([0, 1], 12))
    two = scene_model.SceneModel(lights=model.lights, geometry=geometry, panes={
        k: thin_glass.Pane(name=str(k), ior=1.52, thickness=g.thickness, geometry=g) for k, g in enumerate(geoms)})
    assert scene_model.plan_direct(two, [[0.0, -5.0, 0.0]], [[0, 0, 1]]).indirect[0]


def test_point_light_mirror_image_and_its_radius():
    """A lamp 1 m before the window: seen from a meter whose line to the lamp's image crosses the pane it
    is not quiet; beside it, quiet; a lamp of 0.5 m radius near the edge is not proven either."""
    lamp = emitters.CyclesLight(name="lamp", kind="POINT", position=(0.0, -1.0, 1.5), radius=0.0)
    model = _window_model(lamp)
    plan = scene_model.plan_direct(model, [[0.0, -2.0, 0.0], [6.0, -1.0, 0.0]], [[0, 0, 1]] * 2)
    assert list(plan.indirect) == [True, False]
    big = emitters.CyclesLight(name="lamp", kind="POINT", position=(-1.3, -1.0, 1.5), radius=0.5)
    tris = np.asarray(_window_model(big).geometry.triangles)
    p = np.array([3.5, -1.0, 0.0])
    assert not scene_model.mirror_misses(tris, p, big, 1e-9)
    small = emitters.CyclesLight(name="lamp", kind="POINT", position=(-1.3, -1.0, 1.5), radius=0.0)
    # Its image line crosses the pane's plane at x = 1.1 m, 0.1 m beside the edge: a point lamp misses,
    # the 0.5 m lamp's image cone (5.3 deg, 0.25 m wide there) does not provably.
    assert scene_model.mirror_misses(tris, p, small, 1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_mirror_misses_is_never_wrong(seed):
    """Soundness: whenever a direction inside the sun's disc, mirrored by a triangle, reaches the meter
    (found by sampling the disc and its rim), ``mirror_misses`` does not claim a miss."""
    rng = np.random.default_rng(seed)
    claimed, hits = 0, 0
    for _ in range(400):
        tri = rng.uniform(-1, 1, (1, 3, 3))
        p = rng.uniform(-2, 2, 3)
        s = rng.normal(size=3)
        if rng.uniform() < 0.6:  # aim the sun's image near the triangle (barycentrics -0.2 .. 1.2)
            bary = rng.uniform(-0.2, 1.2, 2)
            x = tri[0, 0] + bary[0] * (tri[0, 1] - tri[0, 0]) + bary[1] * (tri[0, 2] - tri[0, 0])
            nn = np.cross(tri[0, 1] - tri[0, 0], tri[0, 2] - tri[0, 0])
            nn /= np.linalg.norm(nn)
            r = (x - p) / np.linalg.norm(x - p)
            s = r - 2 * (r @ nn) * nn
        s /= np.linalg.norm(s)
        angle = rng.choice([0.0, 0.53, 8.0])
        sun = _sun(s, angle)
        miss = scene_model.mirror_misses(tri, p, sun, 1e-9)
        claimed += miss
        # Sample directions to the sun within its disc, mirror each in the triangle's plane, and trace it
        # back from p (the reflected ray arrives at p from the mirror point).
        v0, e1, e2 = tri[0, 0], tri[0, 1] - tri[0, 0], tri[0, 2] - tri[0, 0]
        n = np.cross(e1, e2)
        n /= np.linalg.norm(n)
        if n @ (p - v0) < 0:
            n = -n
        a = np.cross(s, [1.0, 0, 0] if abs(s[0]) < 0.9 else [0, 1.0, 0])
        a /= np.linalg.norm(a)
        b = np.cross(s, a)
        half = math.radians(angle) / 2
        phis = rng.uniform(0, 2 * np.pi, 64)
        radii = np.concatenate([np.ones(32), rng.uniform(0, 1, 32)]) * np.tan(half)
        dirs = s + radii[:, None] * (np.cos(phis)[:, None] * a + np.sin(phis)[:, None] * b)
        dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
        for w in dirs:
            if w @ n <= 0:
                continue  # that part of the sun lights the far side
            r = w - 2 * (w @ n) * n  # from p back towards the mirror
            denom = r @ n
            if denom >= 0:
                continue
            t = (n @ (v0 - p)) / denom
            x = p + t * r - v0
            m = np.array([[e1 @ e1, e1 @ e2], [e1 @ e2, e2 @ e2]])
            uv = np.linalg.solve(m, [x @ e1, x @ e2])
            if t > 0 and uv.min() >= 0 and uv.sum() <= 1:
                hits += 1
                assert not miss, (tri, p, s, angle)
                break
    assert claimed > 100 and hits > 20  # both outcomes were exercised


def test_lamp_without_shadow_behind_a_wall_is_exact():
    """A lamp with shadows off 1 m behind a wall shines through it at a meter 1 m before it (the closed
    form, exact); the wall's side towards the meter is lit by nothing, so no reflected light: exact. A
    floor on the meter's side, lit through the wall, could light the wall's front: not exact."""
    lamp = emitters.CyclesLight(name="lamp", kind="POINT", position=(0.0, 2.0, 1.0), radius=0.0)
    wall = _quad((-3, 1.0, 0), (3, 1.0, 0), (3, 1.0, 2.5), (-3, 1.0, 2.5))

    def model(tris, names):
        tris = np.asarray(tris, float)
        index = np.repeat(np.arange(len(names)), 2)
        geometry = scene_model.SceneGeometry(
            triangles=tris, object_index=index, object_names=names, casts_shadow=np.ones(len(names), bool),
            opaque=np.ones(len(tris), bool), reflects=np.ones(len(names), bool), emissive=np.zeros(len(tris), bool))
        return scene_model.SceneModel(lights=[scene_model.ModelLight("lamp", lamp, casts_shadow=False)],
                                      geometry=geometry)

    point, normal = [[0.0, 0.0, 1.0]], [[0.0, 1.0, 0.0]]
    plan = scene_model.plan_direct(model(wall, ["Wall"]), point, normal)
    assert plan.status[0, 0] == scene_model.EXACT and not plan.indirect[0] and plan.exact_points()[0]
    floor = _quad((-3, -3, -0.5), (3, -3, -0.5), (3, 3, -0.5), (-3, 3, -0.5))
    plan = scene_model.plan_direct(model(wall + floor, ["Wall", "Floor"]), point, normal)
    assert plan.indirect[0] and not plan.exact_points()[0]
    # With the lamp on the meter's side the wall's front is lit: reflected light, not exact.
    near = emitters.CyclesLight(name="lamp", kind="POINT", position=(1.0, 0.5, 1.0), radius=0.0)
    m = model(wall, ["Wall"])
    m.lights = [scene_model.ModelLight("lamp", near, casts_shadow=False)]
    assert scene_model.plan_direct(m, point, normal).indirect[0]

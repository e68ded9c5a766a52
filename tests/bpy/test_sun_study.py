"""Sun studies (issue 19 item 5): unobstructed meters are the closed form E_dn max(0, n.s) exactly,
meters in a building's shade read the shade, sunlit/sunlight hours, the scene is unchanged, and the
step function is what a Dask client would run."""

import datetime as dt
import math
import sys
import types

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.errors import MeasurementCancelled, RadiometerError
from radiometer.measure.analyses import sun_study
from radiometer.measure.blender.scene_guard import scene_fingerprint
from tests.bpy.conftest import add_light, add_plane, make_black_world

UTC = dt.timezone.utc
LAT, LON = 51.5, -0.12


def _box(scene, name, lo, hi, albedo=0.0):
    """An axis-aligned closed box (outward normals) with a pure Diffuse BSDF of ``albedo`` (no specular)."""
    from radiometer.compat import ensure_node_tree

    (x0, y0, z0), (x1, y1, z1) = lo, hi
    verts = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
             (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def test_pure_helpers():
    d = np.array([0.3, -0.4, 0.866])
    rays = sun_study.disc_directions(d)
    unit = d / np.linalg.norm(d)
    angles = np.degrees(np.arccos(np.clip(rays @ unit, -1, 1)))
    assert len(rays) == 61 and angles[0] < 1e-6 and angles.max() <= sun_study.SUN_RADIUS_DEG + 1e-9
    assert np.allclose(np.linalg.norm(rays, axis=1), 1.0)
    # trapezoid weights: hourly samples 06..18 give 12 h in all, the ends half an hour each
    hours = sun_study.sample_hours([6 * 3600.0 * 1 + 3600.0 * k for k in range(13)])
    assert hours[0] == hours[-1] == 0.5 and np.all(hours[1:-1] == 1.0) and hours.sum() == 12.0
    assert sun_study.sample_hours([5.0]).tolist() == [0.0]
    # one triangle over the origin blocks the upward ray, not a sideways one, nor one starting above it
    tri = np.array([[[-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [0.0, 1.0, 1.0]]])
    blocked = sun_study.rays_blocked([[0, 0, 0], [0, 0, 2], [5, 5, 0]], [[0, 0, 1], [1, 0, 0]], tri, 1e-9)
    assert blocked.tolist() == [[True, False], [False, False], [False, False]]


def test_rays_blocked_agrees_with_solving_each_ray_triangle_system():
    """``rays_blocked`` (Moller-Trumbore in blocks of points x directions x triangles, triangles behind every
    origin culled) against an independent solve of o + t d = v0 + u e1 + v e2 for every ray and triangle.
    Sizes large enough for several direction blocks; pairs within 1e-7 of a triangle's edge or of t = tol are
    left out (either answer is right there)."""
    rng = np.random.default_rng(4)
    o = rng.uniform(-2, 2, (200, 3))
    d = rng.normal(size=(100, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    tris = rng.uniform(-3, 3, (120, 3, 3))
    tol = 0.05
    got = sun_study.rays_blocked(o, d, tris, tol)
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    # A [t, u, v] = o - v0 with A = [-d, e1, e2], for every (point, direction, triangle)
    a = np.stack(np.broadcast_arrays(-d[None, :, None, :], e1[None, None], e2[None, None]), axis=-1)
    rhs = (o[:, None, :] - v0[None])[:, None, :, :, None]  # (P, 1, T, 3, 1) against A (1, R, T, 3, 3)
    t, u, v = np.moveaxis(np.linalg.solve(a, rhs)[..., 0], -1, 0)
    hit = (u >= 0) & (v >= 0) & (u + v <= 1) & (t > tol)
    margin = np.minimum.reduce([np.abs(u), np.abs(v), np.abs(1 - u - v), np.abs(t - tol)])
    clear = np.all(hit | (margin > 1e-7), axis=2) | hit.any(axis=2)  # no borderline pair decides the ray
    assert clear.mean() > 0.99
    expected = hit.any(axis=2)
    assert np.array_equal(got[clear], expected[clear])
    assert 0.05 < expected.mean() < 0.95  # both answers occur


def test_unobstructed_meters_are_the_closed_form_and_the_scene_is_unchanged(clean_blender):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("user world")
    scene.world = world
    lamp = add_light(scene, "POINT", location=(0, 0, 3), energy=500.0)
    user_sun = add_light(scene, "SUN", energy=3.0)
    bpy.context.view_layer.objects.active = lamp
    before = scene_fingerprint(scene)
    times = [dt.datetime(2026, 3, 20, h, 30, tzinfo=UTC) for h in (3, 6, 9, 12, 15, 18, 21)]
    normals = np.array([[0, 0, 1], [1, 0, 0], [0, -1, 0], [0, 1, 0], [-0.5, 0.3, 0.8], [0, 0, -1]], float)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    locations = np.array([[0, 0, 0], [10, 0, 1], [0, 5, 2], [-3, -3, 0], [1, 2, 3], [0, 0, 10]], float)
    r = api.sun_study(locations, normals, times, latitude_deg=LAT, longitude_deg=LON,
                      direct_normal_illuminance_lux=100_000.0, quality="preview")
    assert scene_fingerprint(scene) == before
    assert scene.world == world and not lamp.hide_render and not user_sun.hide_render
    pos = api.sun_position(LAT, LON, times)
    up = pos.elevation_deg > 0
    expected = 100_000.0 * np.maximum(0.0, pos.direction @ normals.T) * up[:, None]
    assert r.illuminance.shape == (7, 6) and r.rel_std_error.shape == (7, 6)
    assert np.allclose(r.illuminance, expected, rtol=1e-4, atol=1e-4 * 100_000.0 * 1e-3)
    assert r.exact.all() and np.all(r.rel_std_error == 0.0)
    assert np.array_equal(r.sunlit, np.repeat(up[:, None], 6, axis=1))
    assert np.allclose([s["elevation_deg"] for s in r.sun], pos.elevation_deg)
    assert np.allclose([s["azimuth_deg"] for s in r.sun], pos.azimuth_deg)
    # sunlight hours: 3-hourly samples, trapezoid weights (1.5 h at the ends, 3 h inside)
    weights = np.array([1.5, 3, 3, 3, 3, 3, 1.5])
    assert np.allclose(r.sunlight_hours, weights @ up)
    assert r.to_dict()["illuminance_lx"][3][0] == pytest.approx(expected[3, 0], rel=1e-4)
    assert r.csv_text().count("\n") == 1 + 7 * 6


def test_meters_in_a_buildings_shade_read_the_shade(clean_blender):
    scene = bpy.context.scene
    # A black block 4 m tall south of the first meter; the second meter is in the open.
    _box(scene, "building", (-5.0, -3.0, 0.0), (5.0, -1.0, 4.0), albedo=0.0)
    make_black_world(scene)
    times = [dt.datetime(2026, 12, 21, 12, 0, tzinfo=UTC)]  # London winter noon: the sun 15 deg high, south
    pos = api.sun_position(LAT, LON, times)
    assert 10 < pos.elevation_deg[0] < 20 and abs(pos.azimuth_deg[0] - 180) < 5
    r = api.sun_study([(0.0, 0.0, 0.0), (0.0, -8.0, 0.0)], (0, 0, 1), times, latitude_deg=LAT, longitude_deg=LON,
                      direct_normal_illuminance_lux=80_000.0, quality="preview")
    open_e = 80_000.0 * math.sin(math.radians(pos.elevation_deg[0]))
    assert r.sunlit.tolist() == [[False, True]] and r.sunlit_fraction[0].tolist() == [0.0, 1.0]
    # in the shade of a black building nothing reaches the meter: the render reads 0
    assert r.illuminance[0, 0] == pytest.approx(0.0, abs=1e-3 * open_e)
    assert r.illuminance[0, 1] == pytest.approx(open_e, rel=max(1e-4, 3 * r.rel_std_error[0, 1]))
    assert r.sunlight_hours.tolist() == [0.0, 0.0]  # one sample stands for no time


def test_cluster_path_runs_the_step_function_per_time(clean_blender, monkeypatch):
    scene = bpy.context.scene
    times = [dt.datetime(2026, 6, 21, h, tzinfo=UTC) for h in (8, 12, 16)]
    calls = {}

    def run_scene_tasks(scene_arg, step_fn, kwargs_list, *, client, progress=None, cancelled=None, **_options):
        calls.update(scene=scene_arg, step=step_fn, kwargs=kwargs_list, client=client)
        return [step_fn(scene_arg, **kw) for kw in kwargs_list]

    fake = types.ModuleType("radiometer.cluster")
    fake.run_scene_tasks = run_scene_tasks
    monkeypatch.setitem(sys.modules, "radiometer.cluster", fake)
    r = api.sun_study([(0, 0, 0)], (0, 0, 1), times, latitude_deg=LAT, longitude_deg=LON, client="a client",
                      seed=5)
    assert calls["step"] is sun_study.sun_study_step and calls["client"] == "a client"
    assert [kw["seed"] for kw in calls["kwargs"]] == [5, 5 + 1009, 5 + 2 * 1009]
    assert [kw["when"] for kw in calls["kwargs"]] == times
    assert all(kw["time_budget_s"] is None for kw in calls["kwargs"])
    local = api.sun_study([(0, 0, 0)], (0, 0, 1), times, latitude_deg=LAT, longitude_deg=LON, seed=5)
    assert np.array_equal(r.illuminance, local.illuminance)
    monkeypatch.setitem(sys.modules, "radiometer.cluster", types.ModuleType("radiometer.cluster"))
    with pytest.raises(RadiometerError, match="cluster"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), times, latitude_deg=LAT, longitude_deg=LON, client="a client")


def test_bad_input_and_cancel_leave_the_scene_alone(clean_blender):
    scene = bpy.context.scene
    add_plane(scene, size=2.0, location=(0, 0, -0.5))
    before = scene_fingerprint(scene)
    t = [dt.datetime(2026, 6, 21, 12, tzinfo=UTC)]
    with pytest.raises(RadiometerError, match="time zone"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), [dt.datetime(2026, 6, 21, 12)], latitude_deg=LAT, longitude_deg=LON)
    with pytest.raises(RadiometerError, match="sky"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), t, latitude_deg=LAT, longitude_deg=LON, sky="sunny")
    with pytest.raises(RadiometerError):
        api.sun_study([(0, 0, 0)], (0, 0, 1), t, latitude_deg=LAT, longitude_deg=LON,
                      direct_normal_illuminance_lux=-1.0)
    with pytest.raises(RadiometerError, match="time_budget_s"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), t, latitude_deg=LAT, longitude_deg=LON, time_budget_s=0.0)
    with pytest.raises(RadiometerError, match="no times"):
        api.sun_study([(0, 0, 0)], (0, 0, 1), [], latitude_deg=LAT, longitude_deg=LON)
    if not hasattr(api, "set_cie_sky"):
        with pytest.raises(RadiometerError, match="set_cie_sky"):
            api.sun_study([(0, 0, 0)], (0, 0, 1), t, latitude_deg=LAT, longitude_deg=LON, sky="overcast")
    with pytest.raises(MeasurementCancelled):
        api.sun_study([(0, 0, 0)], (0, 0, 1), t, latitude_deg=LAT, longitude_deg=LON, cancelled=lambda: True)
    assert scene_fingerprint(scene) == before


@pytest.mark.skipif(not hasattr(api, "set_cie_sky"), reason="the CIE skies (api.set_cie_sky) are not in this build")
def test_sun_and_overcast_sky_add_up_on_an_unobstructed_meter(clean_blender):
    scene = bpy.context.scene
    before = scene_fingerprint(scene)
    times = [dt.datetime(2026, 6, 21, h, tzinfo=UTC) for h in (1, 12)]
    r = api.sun_study([(0, 0, 0)], (0, 0, 1), times, latitude_deg=LAT, longitude_deg=LON,
                      direct_normal_illuminance_lux=100_000.0, sky="overcast", sky_horizontal_illuminance_lux=20_000.0)
    pos = api.sun_position(LAT, LON, times)
    sun = 100_000.0 * np.maximum(0.0, pos.direction[:, 2]) * (pos.elevation_deg > 0)
    assert np.allclose(r.illuminance[:, 0], 20_000.0 + sun, rtol=1e-4)
    assert scene_fingerprint(scene) == before

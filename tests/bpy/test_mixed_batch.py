"""Mixed batches (issue 18): a meter whose every contribution is a verified closed form reads that
closed form, exact, whatever its neighbours need; ``auto`` renders only the meters that need it.

Reference: E = I cos(theta) / r^2 with I = P / (4 pi) for a radius-0 point light (FACTS.md, checked
against Cycles renders in test_cycles_lights_render.py)."""

import math

import bpy
import pytest

from radiometer import api
from radiometer.measure.render import adaptive


@pytest.fixture
def rendered_counts(monkeypatch):
    """How many meters each Cycles run was given."""
    counts = []
    original = adaptive.render_hybrid

    def spy(request, points_scene, *args, **kwargs):
        counts.append(len(points_scene))
        return original(request, points_scene, *args, **kwargs)

    monkeypatch.setattr(adaptive, "render_hybrid", spy)
    return counts


def floor_and_point(build):
    """A 100 W point light 3 m above a white floor. At (0, 0, 1) facing up the floor lies below the
    meter's horizon (closed form, exact); facing down the meter reads only the floor's reflection."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.0, 0.0, 3.0), energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=2.0, albedo=0.8, name="floor")
    return [(0.0, 0.0, 1.0), (0.0, 0.0, 1.0), (0.3, 0.0, 0.5)], [(0, 0, 1), (0, 0, -1), (0, 0, 1)]


def closed_form(point, light=(0.0, 0.0, 3.0), power=100.0):
    d = [l - p for l, p in zip(light, point)]
    r = math.sqrt(sum(x * x for x in d))
    return power / (4 * math.pi) * (d[2] / r) / r ** 2  # W/m^2, meters facing +Z


@pytest.mark.parametrize("method", ["auto", "hybrid"])
def test_exact_meters_stay_exact_beside_rendered_ones(clean_blender, build, rendered_counts, method):
    points, normals = floor_and_point(build)
    up, down, low = api.measure_illuminance(points, normals, method=method, quality="preview")
    for r, p in ((up, points[0]), (low, points[2])):
        assert r.exact and r.method == "analytic" and r.rel_std_error == 0.0 and r.samples == 0, r.notes
        assert r.irradiance == pytest.approx(closed_form(p), rel=1e-7)
        assert any(note.startswith("exact:") for note in r.notes)
    assert not down.exact and down.method in ("render", "hybrid") and down.samples > 0
    assert 0 < down.rel_std_error < 0.2 and down.irradiance > 0
    assert any("1 of 3 meters rendered" in note for note in down.notes), down.notes
    assert rendered_counts == [1]  # only the meter that needs it went to Cycles


def test_render_method_renders_every_meter(clean_blender, build, rendered_counts):
    points, normals = floor_and_point(build)
    readings = api.measure_illuminance(points, normals, method="render", quality="preview")
    assert rendered_counts == [3]
    assert not any(r.exact for r in readings) and all(r.method == "render" for r in readings)
    up = readings[0]  # rendered, so within its stated error of the closed form (4 s.e. + float32)
    assert abs(up.irradiance - closed_form(points[0])) <= 4 * up.rel_std_error * up.irradiance + 1e-6


def test_all_exact_batch_renders_nothing(clean_blender, build, rendered_counts):
    points, normals = floor_and_point(build)
    readings = api.measure_illuminance([points[0], points[2]], [normals[0], normals[2]])
    assert rendered_counts == [] and all(r.exact and r.method == "analytic" for r in readings)

"""The hybrid estimator (closed-form direct light + rendered rest) is unbiased against the full
render, and error-targeted allocation spends samples where they are needed.

Reference: the same meters measured with ``method="render"`` (Cycles for everything, no closed
form involved), independent seeds; agreement is judged with both readings' stated errors.
"""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.demo.builders import diffuse_material  # noqa: E402
from radiometer.measure.blender.scene_guard import scene_fingerprint  # noqa: E402


def _box(name, centre, half, albedo):
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=centre)
    obj = bpy.context.object
    obj.name = name
    obj.scale = half
    obj.data.materials.append(diffuse_material(name, (albedo,) * 3))
    return obj


def _room(clean_blender, build):
    """A closed 4 x 3 x 2.7 m room (one scaled cube), a ceiling panel, two radius-0 point lights
    and a cabinet that shadows part of the floor."""
    scene = bpy.context.scene
    build.black_world(scene)
    _box("Room", (0, 0, 1.35), (2.0, 1.5, 1.35), 0.6)
    _box("Cabinet", (0.8, 0.0, 0.6), (0.25, 0.25, 0.6), 0.5)
    build.light(scene, "AREA", (0.0, 0.0, 2.69), energy=60.0, size=0.6)
    build.light(scene, "POINT", (-1.2, 0.8, 1.8), energy=30.0)
    build.light(scene, "POINT", (1.6, 0.0, 1.0), energy=20.0)   # behind the cabinet for some meters
    return scene


POINTS = [(-1.0, -0.5, 0.0), (0.0, 0.0, 0.0), (1.3, 0.0, 0.0), (1.3, 0.2, 0.4), (0.3, 0.9, 0.0),
          (1.5, -1.0, 0.0)]


def test_hybrid_equals_full_render(clean_blender, build):
    scene = _room(clean_blender, build)
    before = scene_fingerprint(scene)
    hybrid = api.measure_illuminance(POINTS, (0, 0, 1), method="hybrid", target_rel_error=0.003, seed=1)
    full = api.measure_illuminance(POINTS, (0, 0, 1), method="render", target_rel_error=0.003, seed=500)
    assert scene_fingerprint(scene) == before
    assert all(ob.light_linking.receiver_collection is None for ob in scene.objects if ob.type == "LIGHT")
    # The split is real: every meter takes some light from closed forms, and not all the same.
    parts = [tuple(r.parts["analytic"]) for r in hybrid]
    assert all(parts) and len(set(parts)) > 1, parts
    z = []
    for h, f in zip(hybrid, full):
        assert h.method == "hybrid" and f.method == "render"
        assert h.rel_std_error <= 0.003 and f.rel_std_error <= 0.003
        se = math.hypot(h.rel_std_error * h.irradiance, f.rel_std_error * f.irradiance)
        z.append((h.irradiance - f.irradiance) / se)
        assert abs(z[-1]) < 3.5, (h.location, h.irradiance, f.irradiance, h.parts)
    # Pooled: the mean difference is no bias either (6 meters, independent).
    assert abs(np.mean(z)) * math.sqrt(len(z)) < 3.0


def test_allocation_gives_the_shadowed_meter_more_samples(clean_blender, build):
    scene = _room(clean_blender, build)
    readings = api.measure_illuminance(POINTS, (0, 0, 1), method="render", quality="standard")
    assert all(r.rel_std_error <= 0.01 and r.target_rel_error == 0.01 for r in readings)
    samples = np.array([r.samples for r in readings])
    assert samples.max() >= 2 * samples.min()   # not one count for the whole batch
    fixed = api.measure_illuminance(POINTS[:2], (0, 0, 1), method="render", samples=2048)
    assert [r.samples for r in fixed] == [2048, 2048] and all(r.target_rel_error is None for r in fixed)


def test_time_budget_gives_finite_readings(clean_blender, build):
    # How closely the budget is kept is wall time: measured by bench/time_budget.py, not asserted here
    # (a loaded machine made the old bound fail).
    _room(clean_blender, build)
    readings = api.measure_illuminance(POINTS, (0, 0, 1), method="render", time_budget_s=1.5)
    assert all(math.isfinite(r.rel_std_error) and r.rel_std_error < 0.2 for r in readings)


def test_progress_reports_fraction_and_eta(clean_blender, build):
    _room(clean_blender, build)
    calls = []
    api.measure_illuminance(POINTS[:3], (0, 0, 1), method="render", quality="preview",
                            progress=lambda done, total, eta=None: calls.append((done, total, eta)))
    assert calls and calls[-1][0] == calls[-1][1] == 1000
    assert all(eta is not None and eta >= 0 for _d, _t, eta in calls)
    assert [d for d, _t, _e in calls] == sorted(d for d, _t, _e in calls)


def test_long_rounds_are_split_so_cancel_answers(clean_blender, build, monkeypatch):
    """With a cancel callback a round is baked in chunks of ~CHUNK_SECONDS; the chunks give the
    same statistics (same spp, independent seeds), and a cancel between chunks stops the run."""
    from radiometer.errors import MeasurementCancelled
    from radiometer.measure.render import adaptive, sensors

    _room(clean_blender, build)
    monkeypatch.setattr(adaptive, "CHUNK_SECONDS", 1e-4)  # every block its own bake
    calls = {"bakes": 0}
    real = sensors.run_bake

    def counting(*args, **kwargs):
        calls["bakes"] += 1
        return real(*args, **kwargs)

    monkeypatch.setattr(sensors, "run_bake", counting)
    readings = api.measure_illuminance(POINTS[:2], (0, 0, 1), method="render", target_rel_error=0.01,
                                       cancelled=lambda: False)
    assert calls["bakes"] > readings[0].render_settings["rounds"]
    assert all(r.rel_std_error <= 0.01 for r in readings)
    state = {"n": 0}

    def cancel_after_three():
        state["n"] += 1
        return state["n"] > 3

    with pytest.raises(MeasurementCancelled):
        api.measure_illuminance(POINTS[:2], (0, 0, 1), method="render", target_rel_error=0.002,
                                cancelled=cancel_after_three)

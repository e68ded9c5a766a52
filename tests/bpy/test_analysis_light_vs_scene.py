"""Law checks see the light and the room apart (issue 10 item 6), and analyses take the meter's
accuracy settings (item 5).

References: the inverse-square law and Lambert's cosine law hold for a light's OWN direct light
(lecture); an extended source follows cos(theta) only while it is wholly above the receiver's
horizon; Blender's soft falloff gives E = I / (R^2 + d^2) (FACTS.md). What a closed room adds is
interreflection, measured as total - direct (direct: closed forms where the scene model proves
them, else Cycles at 0 bounces).
"""

import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.demo import scene as demo
from radiometer.measure.blender.scene_guard import scene_fingerprint


def _split_consistent(rows):
    for row in rows:
        assert row.scene == pytest.approx(row.measured - row.direct, abs=1e-12)
        assert row.scene_share == pytest.approx(row.scene / row.measured, rel=1e-9)


def test_demo_room_is_not_the_lights_fault(clean_blender):
    scene = demo.build(bpy.context.scene, with_meters=False)
    before = scene_fingerprint(scene)
    r = api.check_inverse_square("Ceiling Panel", target_rel_error=1e-2)
    assert scene_fingerprint(scene) == before
    _split_consistent(r.rows)
    # The sweep stays in the free space above the desk (2.24 m below the panel).
    assert max(row.distance for row in r.rows) < 2.24
    # The light's own direct light is its closed form (nothing shadows it on the axis) ...
    for row in r.rows:
        assert row.shadowed == pytest.approx(0.0, abs=1e-9)
        assert row.direct_deviation == pytest.approx(row.model_deviation, abs=3 * row.direct_rel_std_error + 1e-9)
    # ... while the room's interreflection lifts the far readings far above I/d^2.
    far = r.rows[-1]
    assert far.scene > 0 and far.scene_share > 0.1 and not far.total_ok
    assert not r.total_passed and r.max_scene_share > 0.1 and "scene" in r.broken_by
    # The light is flagged only for its own size (the room is too small for its far field).
    light_causes = [c for c in r.causes if c.startswith("light:")]
    assert light_causes and all("size of the area light" in c for c in light_causes), r.causes
    assert any(c.startswith("scene:") and "interreflection" in c for c in r.causes), r.causes

    c = api.check_cosine_law("Ceiling Panel", target_rel_error=1e-2)
    _split_consistent(c.rows)
    assert c.total_max_rel_deviation > 1.0  # the room's light at grazing tilts: far from cos(theta)
    # While the panel is wholly above the meter's horizon the light's own cosine law holds, even
    # where the total (light + room) breaks it.
    below = [row for row in c.rows if row.angle < c.horizon_onset_deg]
    assert all(row.ok for row in below)
    assert any(not row.total_ok for row in below)
    assert all(row.scene > 0 for row in c.rows)
    assert all(not x.startswith("light:") or "horizon" in x for x in c.causes), c.causes
    assert any(x.startswith("scene:") for x in c.causes)


def test_the_light_still_breaks_its_own_law_in_a_room(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=6.0, location=(0, 0, 0), albedo=0.8, name="floor")
    radius = 0.2
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=radius, use_soft_falloff=True)
    r = api.check_inverse_square(light, target_rel_error=1e-2)
    _split_consistent(r.rows)
    assert not r.passed and "light" in r.broken_by
    assert any(c.startswith("light:") and "soft falloff" in c for c in r.causes), r.causes
    d = np.array([row.distance for row in r.rows])
    own = np.array([row.direct_deviation for row in r.rows])
    assert own == pytest.approx(-radius**2 / (radius**2 + d**2), abs=1e-4)  # Cycles' soft falloff, closed form
    assert r.near_field_limit == pytest.approx(math.sqrt(99) * radius, rel=0.03)
    # The floor lies below every meter's horizon (they face up at the light): nothing to add, exact.
    assert r.method == "analytic" and r.max_scene_share == 0.0

    area = build.light(scene, "AREA", (0, 0, 1.0), energy=100.0, shape="SQUARE", size=2.0)
    light.hide_render = True
    c = api.check_cosine_law(area, location=(0, 0, 0.5), target_rel_error=1e-2)
    assert not c.passed and "light" in c.broken_by
    assert any(x.startswith("light:") and "horizon" in x for x in c.causes), c.causes
    assert c.onset_deg >= c.horizon_onset_deg


def test_instanced_lights_are_switched_off_for_the_check(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=0.0)
    lamps = bpy.data.collections.new("Lamps")  # not in the scene: only instanced
    data = bpy.data.lights.new("other", "POINT")
    data.energy, data.shadow_soft_size = 1000.0, 0.0
    other = bpy.data.objects.new("other", data)
    other.location = (0.5, 0, 2.2)
    lamps.objects.link(other)
    empty = bpy.data.objects.new("Lamp Instance", None)
    empty.instance_type, empty.instance_collection = "COLLECTION", lamps
    scene.collection.objects.link(empty)
    assert other.name not in scene.objects
    before = scene_fingerprint(scene)
    r = api.check_inverse_square(light, distances=[0.5, 1.0, 2.0], method="render", quality="preview")
    assert scene_fingerprint(scene) == before and not other.hide_render
    assert r.passed and r.max_scene_share == pytest.approx(0.0, abs=1e-4), [row.measured for row in r.rows]
    assert any("other" in n for n in r.notes)
    # Without the isolation the instanced lamp would be in the reading: the meter sees it.
    e = api.measure_illuminance((0, 0, 2.0), (0, 0, 1), method="render", quality="preview")
    assert e.irradiance > 10 * 100 / (4 * math.pi)  # the instanced 1000 W lamp 0.54 m away dominates


def test_analyses_take_target_error_and_time_budget(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=4.0, location=(0, 0, 0), albedo=0.5, name="floor")
    area = build.light(scene, "AREA", (0, 0, 2.0), energy=100.0, shape="SQUARE", size=0.5)
    r = api.check_cosine_law(area, target_rel_error=5e-3, angles_deg=(0, 30, 60))
    assert r.target_rel_error == 5e-3
    assert all(row.direct > 0 for row in r.rows)
    r = api.check_inverse_square(area, distances=[0.5, 1.0, 1.5], time_budget_s=0.5)
    assert r.target_rel_error is None and r.seconds < 10
    plane = build.plane(scene, size=2.0, location=(0, 0, 0.75), name="Work Plane")
    plane.hide_render = True
    g = api.illuminance_grid(plane, resolution=(3, 3), target_rel_error=1e-2)
    assert g.target_rel_error == 1e-2 and g.max_rel_std_error <= 1e-2
    g = api.illuminance_grid(plane, resolution=(3, 3), time_budget_s=0.3)
    assert g.target_rel_error is None and g.seconds < 10
    c = api.convergence_study(location=(0.3, 0.2, 0.75), samples=(4, 16, 64), target_rel_error=1e-2, replicas=4)
    assert c.target_error == 1e-2
    assert c.targeted.reached and c.targeted.rel_std_error <= 1e-2 and c.targeted.seconds > 0
    assert c.targeted.rms_error < 0.03  # within 3 sigma of the 1 % asked
    assert math.isfinite(c.time_slope) and c.fit["time_slope"] == c.time_slope
    # seconds_for_target: t0 + c N(target), fitted on bakes of the target alone
    assert c.seconds_for_target == pytest.approx(c.fit["t0_s"] + c.fit["c_s_per_sample"] * c.samples_for_target)
    assert all(row.seconds > 0 for row in c.rows)


def test_convergence_reference_counts_the_world(clean_blender, build):
    """An open meter under a uniform world (radiance s per channel: E = pi s, nothing above its horizon) and a
    point light: the study's analytic reference is both (it left the world out, so a daylit room's roof meter
    read a constant 22 % 'error' at every sample count), and the renders converge to it."""
    from radiometer.compat import ensure_node_tree

    scene = bpy.context.scene
    scene.world = bpy.data.worlds.new("white sky")
    background = ensure_node_tree(scene.world).nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 0.5
    build.plane(scene, size=4.0, location=(0.0, 0.0, 0.0), albedo=0.0, name="floor")
    build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0, use_soft_falloff=False)
    c = api.convergence_study(location=(0.0, 0.0, 0.0), samples=(16, 256), replicas=4)
    assert c.reference_kind == "analytic (exact)"
    want = math.pi * 0.5 + 100.0 / (4.0 * math.pi * 4.0)          # W/m^2: the world, and I / d^2 for P = 100 W
    assert c.reference[0] == pytest.approx(want, rel=1e-5)       # the sensor sits ~2 um up: 1e-6 on I / d^2
    last = c.rows[-1]
    assert last.rms_error < max(5.0 * last.std_error, 1e-3), (last.rms_error, last.std_error)

"""Law checks (issue 5) on scenes with closed-form answers.

References: the lecture's isotropic point source E = Phi cos(theta) / (4 pi r^2) and Lambert's cosine
law; Blender's soft falloff E = I / (R^2 + d^2) (FACTS.md: measured 59 %, 80 %, 94 % of I/d^2 at
0.6, 1, 2 m for R = 0.5); the on-axis square E = L * 4 (b/s) atan(b/s), b = a/2, s = sqrt(b^2+h^2)
(corner-rectangle view factor, Howell's catalogue C-11), whose 1 % crossing is 5.7431 side lengths.
"""

import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.errors import RadiometerError
from radiometer.measure.blender.scene_guard import scene_fingerprint


def square_on_axis_ratio(h, a):
    """E / (I/h^2) for a Lambertian square of side a on its axis at distance h (closed form above)."""
    b = a / 2
    s = np.sqrt(b * b + h * h)
    return 4 * (b / s) * np.arctan(b / s) * h**2 / a**2


@pytest.mark.parametrize("method", ["analytic", "render"])
def test_ideal_point_light_follows_inverse_square(clean_blender, build, method):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=0.0)
    r = api.check_inverse_square(light, method=method)
    assert r.method == method
    assert r.passed and r.near_field_limit == 0.0 and not r.causes
    assert r.exponent == pytest.approx(-2.0, abs=1e-4)
    # I = P / (4 pi) along any direction (lecture, isotropic point source)
    assert r.intensity == pytest.approx(100 / (4 * math.pi), rel=1e-9)
    for row in r.rows:
        assert row.measured == pytest.approx(100 / (4 * math.pi) / row.distance**2, rel=1e-4)


def test_soft_falloff_point_is_flagged_with_the_right_deviation(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    radius = 0.2
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=radius, use_soft_falloff=True)
    r = api.check_inverse_square(light, method="render", target_rel_error=1e-4)
    assert not r.passed and r.far_field_passed
    assert any("soft falloff" in c for c in r.causes)
    d = np.array([row.distance for row in r.rows])
    dev = np.array([row.rel_deviation for row in r.rows])
    se = np.array([row.rel_std_error for row in r.rows])
    expected = -radius**2 / (radius**2 + d**2)  # Cycles' soft falloff vs I/d^2
    assert np.all(np.abs(dev - expected) <= 4 * se + 1e-4), np.c_[d, dev, expected, se]
    # |dev| = 1 % where R^2/(R^2 + d^2) = 0.01: d = sqrt(99) R.
    assert r.near_field_limit == pytest.approx(math.sqrt(99) * radius, rel=0.03)
    assert r.exponent == pytest.approx(-2.0, abs=0.01)


@pytest.mark.parametrize("method", ["analytic", "render"])
def test_square_area_light_near_field_limit(clean_blender, build, method):
    scene = bpy.context.scene
    build.black_world(scene)
    side = 0.5
    light = build.light(scene, "AREA", (0, 0, 0), energy=50.0, shape="SQUARE", size=side)
    r = api.check_inverse_square(light, method=method)
    d = np.array([row.distance for row in r.rows])
    measured_ratio = np.array([row.measured / row.predicted for row in r.rows])
    se = np.array([row.rel_std_error for row in r.rows])
    assert np.all(np.abs(measured_ratio - square_on_axis_ratio(d, side)) <= 4 * se + 1e-6)
    assert r.near_field_limit / side == pytest.approx(5.7431, rel=0.01 if method == "analytic" else 0.03)
    assert not r.passed and not r.five_times["rule_holds"]  # 5.74 > 5: the rule is a little optimistic
    assert any("size of the area light" in c for c in r.causes)
    assert r.far_field_passed and r.exponent == pytest.approx(-2.0, abs=0.01)


def test_sun_cosine_law_to_1e3(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    sun = build.light(scene, "SUN", rotation=(0.4, 0.3, 0.0), energy=3.0, angle=math.radians(0.526))
    for method in ("analytic", "render"):
        r = api.check_cosine_law(sun, method=method, target_rel_error=1e-4)
        assert r.passed and r.max_rel_deviation < 1e-3, (method, r.max_rel_deviation)
        # E(0) = energy (W/m^2 facing the sun, FACTS.md)
        assert r.rows[0].measured == pytest.approx(3.0, rel=1e-3)
    assert r.horizon_onset_deg == pytest.approx(90 - 0.263, abs=1e-6)


def test_large_close_area_light_flags_cosine_law(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "AREA", (0, 0, 1), energy=100.0, shape="SQUARE", size=2.0)
    r = api.check_cosine_law(light, location=(0, 0, 0.5), method="render")
    # Corners 45 deg off the tilt plane: the source reaches the horizon when the tilt plus its angular
    # radius atan(1 / 0.5) along the tilt axis... the farthest point (a corner) is atan(sqrt 2 / 0.5).
    assert r.source_angular_radius_deg == pytest.approx(math.degrees(math.atan(math.sqrt(2) / 0.5)), rel=1e-6)
    assert not r.passed and r.max_rel_deviation > 0.1
    assert any("horizon" in c for c in r.causes)
    # While the whole source is above the horizon E is linear in the normal: the law holds there.
    for row in r.rows:
        if row.angle < r.horizon_onset_deg:
            assert row.ok, row
    assert r.onset_deg >= r.horizon_onset_deg


def test_sun_cannot_be_checked_for_inverse_square(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    sun = build.light(scene, "SUN", energy=3.0)
    with pytest.raises(RadiometerError, match="sun.*no position"):
        api.check_inverse_square(sun)
    with pytest.raises(RadiometerError, match="not a light"):
        api.check_inverse_square(build.plane(scene))
    with pytest.raises(RadiometerError, match="no object named"):
        api.check_cosine_law("nope")


def test_law_check_isolates_the_light_and_leaves_the_scene(clean_blender, build):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("grey sky")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=0.0)
    other = build.light(scene, "POINT", (0.5, 0, 2.2), energy=1000.0, shadow_soft_size=0.0)
    before = scene_fingerprint(scene)
    r = api.check_inverse_square(light, distances=[0.5, 1.0, 2.0], method="render", quality="preview")
    assert r.passed  # neither the other light nor the sky leaked into the sweep
    assert scene_fingerprint(scene) == before
    assert not other.hide_render and scene.world == world

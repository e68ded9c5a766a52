"""Extremes through the whole pipeline (issue 6): scene -> depsgraph -> sensor mesh -> Cycles bake ->
reading, and scene -> analytic models. Results must be finite and within their STATED error.

Reference values: point light of radius 0, E = P cos(theta) / (4 pi r^2) (FACTS.md, measured to 1e-6);
spot light inside its cone, same intensity P / (4 pi) (FACTS.md); sun, E = energy cos(theta) (FACTS.md).
A render reading's stated error is its rel_std_error; a delta light is sampled exactly, so a render
reading must agree to a small float32 allowance (1e-4) plus 3 stated standard errors.
"""

import math

import bpy
import numpy as np
import pytest

from radiometer import api

FLOAT32_ALLOWANCE = 1e-4  # relative: float32 geometry and film in Cycles


def black(build):
    scene = bpy.context.scene
    build.black_world(scene)
    return scene


def within_stated(reading, expected):
    assert math.isfinite(reading.irradiance) and math.isfinite(reading.rel_std_error)
    allowed = FLOAT32_ALLOWANCE + 3 * reading.rel_std_error
    assert reading.irradiance == pytest.approx(expected, rel=allowed), (reading.irradiance, expected,
                                                                        reading.rel_std_error)


@pytest.mark.parametrize("method", ["analytic", "render"])
@pytest.mark.parametrize("distance", [1e-4, 1e5])
@pytest.mark.parametrize("energy", [1e-6, 1e9])
def test_distance_and_energy_corners(clean_blender, build, method, distance, energy):
    scene = black(build)
    build.light(scene, "POINT", (0.0, 0.0, distance), energy=energy, shadow_soft_size=0.0)
    r = api.measure_illuminance((0, 0, 0), method=method)
    within_stated(r, energy / (4 * math.pi * distance ** 2))


@pytest.mark.parametrize("method", ["analytic", "render"])
def test_grazing_89_999_degrees(clean_blender, build, method):
    scene = black(build)
    build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    theta = math.radians(89.999)
    r = api.measure_illuminance((0, 0, 0), (math.sin(theta), 0, math.cos(theta)), method=method)
    expected = 100 / (4 * math.pi) * math.cos(theta) / 4
    if method == "analytic":
        assert r.irradiance == pytest.approx(expected, rel=1e-9)
    else:
        # cos(89.999 deg) = 1.7e-5: a float32 normal is good to ~6e-8 absolute, i.e. 4e-3 relative here.
        assert r.irradiance == pytest.approx(expected, rel=5e-3 + 3 * r.rel_std_error)


@pytest.mark.parametrize("method", ["analytic", "render"])
def test_light_behind_the_meter_reads_zero(clean_blender, build, method):
    scene = black(build)
    build.light(scene, "POINT", (0.0, 0.0, -2.0), energy=1e9, shadow_soft_size=0.0)
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method=method)
    assert r.irradiance == 0.0 and r.rel_std_error == 0.0




@pytest.mark.parametrize("method", ["analytic", "render"])
def test_meter_far_from_the_origin(clean_blender, build, method):
    """A meter at x = 1e4 m with the light 2 m above it (float32 spacing there is ~1 mm)."""
    scene = black(build)
    build.light(scene, "POINT", (1e4, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    r = api.measure_illuminance((1e4, 0, 0), method=method)
    within_stated(r, 100 / (4 * math.pi * 4))


@pytest.mark.parametrize("method", ["analytic", "render"])
@pytest.mark.parametrize("spot_size_deg, blend", [(1.0, 0.0), (180.0, 0.0), (90.0, 1.0)])
def test_spot_cone_limits_on_axis(clean_blender, build, method, spot_size_deg, blend):
    scene = black(build)
    build.light(scene, "SPOT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0,
                spot_size=math.radians(spot_size_deg), spot_blend=blend)
    r = api.measure_illuminance((0, 0, 0), method=method)
    within_stated(r, 100 / (4 * math.pi * 4))


@pytest.mark.parametrize("method", ["analytic", "render"])
@pytest.mark.parametrize("theta_deg", [0.0, 89.0])
@pytest.mark.parametrize("strength", [1e-6, 1e5])
def test_sun_strength_and_angle(clean_blender, build, method, theta_deg, strength):
    scene = black(build)
    theta = math.radians(theta_deg)
    build.light(scene, "SUN", (0, 0, 5), rotation=(0.0, theta, 0.0), energy=strength, angle=0.0)
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method=method)
    within_stated(r, strength * math.cos(theta))


@pytest.mark.parametrize("size", [1e-4, 1e3])
def test_area_light_size_extremes_render_within_stated_error(clean_blender, build, size):
    """Tiny (point-like) and huge (half-space) square area lights: render vs closed form."""
    scene = black(build)
    build.light(scene, "AREA", (0.0, 0.0, 1.0), energy=100.0, shape="SQUARE", size=size)
    exact = api.measure_illuminance((0, 0, 0), method="analytic").irradiance
    r = api.measure_illuminance((0, 0, 0), method="render", quality="standard")
    assert math.isfinite(exact) and exact > 0
    within_stated(r, exact)


def test_many_meters_spanning_eight_decades(clean_blender, build):
    """One batch with meters from 1e-3 m to 1e4 m from the light: every reading right (one bake)."""
    scene = black(build)
    build.light(scene, "POINT", (0.0, 0.0, 0.0), energy=1e3, shadow_soft_size=0.0)
    d = np.logspace(-3, 4, 8)
    pts = np.c_[np.zeros(8), np.zeros(8), -d]
    readings = api.measure_illuminance(pts, (0, 0, 1), method="render")
    for r, dist in zip(readings, d):
        within_stated(r, 1e3 / (4 * math.pi * dist ** 2))

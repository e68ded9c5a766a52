"""Validate the independent reference harness (tests/bpy/reference.py) against closed forms.

The harness is only trusted as a yardstick because it reproduces these exactly-known numbers:
* point light: E = I cos(theta) / r^2 with I = P / (4 pi) (Blender's point-light unit, FACTS.md;
  inverse-square and cosine law);
* a 1 x 1 m Lambertian area light 1 m above the sensor: E = L * (projected solid angle), with
  L = P / (pi A) (normalised area light, FACTS.md) and the projected solid angle from Lambert's
  polygon formula (the exact contour integral, 0.5 * sum_i Gamma_i . n);
* a closed integrating sphere of albedo rho with a point light at the centre: the wall irradiance is
  E = P / (A (1 - rho)) for a true sphere (direct P / A plus the uniform indirect rho P / (A (1 - rho)):
  in a sphere every wall element sees every other with view factor dA / A). For the polygonal UV
  sphere we use the exact direct term at the facet centre plus rho P / ((1 - rho) A_poly), A_poly the
  sum of the facet areas, and say how far that is from the true-sphere number.
Each check asserts agreement within 3 of the harness's own standard errors AND within 0.5 %.
"""

import importlib.util
import math
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytest.importorskip("OpenEXR")


def _load(name):
    spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")
corpus = _load("corpus")


@pytest.fixture
def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    corpus.black_world(scene)
    yield scene
    bpy.ops.wm.read_factory_settings(use_empty=True)


def _agree(measured, expected, rel_se, what):
    err = measured / expected - 1.0
    assert abs(err) <= 0.005, f"{what}: {measured} vs {expected} ({100 * err:+.3f} %)"
    assert abs(measured - expected) <= 3.0 * rel_se * abs(measured) + 1e-6 * abs(expected), (
        f"{what}: {measured} vs {expected}: {err:+.2e} relative, > 3 standard errors ({rel_se:.2e})")


def _projected_solid_angle(polygon, point, normal):
    """Lambert's polygon formula: (1/2) sum over edges of angle_i * (unit edge-plane normal . n)."""
    p = np.asarray(point, float)
    n = np.asarray(normal, float)
    v = [np.asarray(c, float) - p for c in polygon]
    total = 0.0
    for i in range(len(v)):
        a, b = v[i] / np.linalg.norm(v[i]), v[(i + 1) % len(v)] / np.linalg.norm(v[(i + 1) % len(v)])
        cross = np.cross(a, b)
        angle = math.atan2(np.linalg.norm(cross), float(np.dot(a, b)))
        total += angle * float(np.dot(cross / np.linalg.norm(cross), n))
    return 0.5 * abs(total)


def test_point_light_inverse_square_and_cosine(empty_scene):
    scene = empty_scene
    corpus.add_light(scene, "POINT", (0.3, 0.4, 2.0), energy=100.0, shadow_soft_size=0.0)
    point, normal = (1.0, 2.0, 0.5), np.array([0.0, 0.6, 0.8])
    watched = [(scene.cycles, "samples"), (scene.cycles, "light_sampling_threshold"), (scene.cycles, "seed"),
               (scene.cycles, "transparent_max_bounces"), (scene.cycles, "blur_glossy"), (scene.render, "engine"),
               (scene.render, "filepath"), (scene.render, "resolution_x"), (scene.view_settings, "view_transform"),
               (scene.render.image_settings, "file_format")]
    before = [getattr(o, a) for o, a in watched]
    e, rel, info = reference.reference_irradiance(scene, point, normal)
    assert [getattr(o, a) for o, a in watched] == before
    d = np.array([0.3, 0.4, 2.0]) - point
    r = np.linalg.norm(d)
    expected = 100.0 / (4 * math.pi) * float(np.dot(d / r, normal)) / r ** 2  # I cos / r^2
    # A delta light and no geometry: every camera sample is exact, so the only spread is the real
    # variation of E over the 0.5 mm sensor (second order in its mean). Tight bound: 1e-5.
    assert abs(e[0] / expected - 1) < 1e-5, (e[0], expected)
    _agree(e[0], expected, rel, "point light")
    # The scene is back as it was: only the light remains, no camera, no images.
    assert [o.name for o in scene.objects] == ["point"], list(scene.objects)
    assert scene.camera is None and len(bpy.data.images) == 0 and len(bpy.data.meshes) == 0


def test_unit_scale_converts_to_si(empty_scene):
    # The same SI scene (point light 2 m above the sensor, 100 W) built at scale_length 0.001 (scene
    # unit = 1 mm): Cycles renders per scene unit^2 (FACTS.md), the harness divides by scale^2.
    scene = empty_scene
    scene.unit_settings.scale_length = 0.001
    corpus.add_light(scene, "POINT", (0.0, 0.0, 2000.0), energy=100.0)
    e, rel, _ = reference.reference_irradiance(scene, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    expected = 100.0 / (4 * math.pi * 2.0 ** 2)  # I / r^2 with r = 2 m
    assert abs(e[0] / expected - 1) < 1e-5, (e[0], expected)


def test_square_area_light_at_one_metre(empty_scene):
    scene = empty_scene
    corpus.add_light(scene, "AREA", (0.0, 0.0, 1.0), energy=100.0, size=1.0, shape="SQUARE")
    e, rel, _ = reference.reference_irradiance(scene, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), target_rel_error=5e-4)
    radiance = 100.0 / (math.pi * 1.0)  # L = P / (pi A), normalised Lambertian emitter
    square = [(-0.5, -0.5, 1.0), (0.5, -0.5, 1.0), (0.5, 0.5, 1.0), (-0.5, 0.5, 1.0)]
    expected = radiance * _projected_solid_angle(square, (0, 0, 0), (0, 0, 1))
    assert abs(expected - 23.9459) < 1e-3  # the same number from the on-axis rectangle form factor
    _agree(e[0], expected, rel, "1x1 area light at 1 m")
    # Tilted sensor 1 m off axis: the polygon formula again (light partly below its horizon is
    # impossible here, all corners are above the tilted plane).
    normal = np.array([0.0, math.sin(0.4), math.cos(0.4)])
    e2, rel2, _ = reference.reference_irradiance(scene, (0.0, -1.0, 0.0), normal, target_rel_error=5e-4)
    expected2 = radiance * _projected_solid_angle(square, (0, -1, 0), normal)
    _agree(e2[0], expected2, rel2, "tilted, off-axis area light")


@pytest.mark.slow
def test_integrating_sphere_all_bounces(empty_scene):
    rho, power = 0.8, 100.0
    built = corpus.integrating_sphere(rho=rho, power=power, segments=128, rings=64, do_reset=False)
    scene = built["scene"]
    a_poly, a_true = built["area_poly"], 4 * math.pi * built["radius"] ** 2
    # The polygonal sphere is slightly smaller than the true one (measured: A_poly / A_true = 0.99950 for 128 x 64).
    assert 0.998 < a_poly / a_true < 1.0
    for label, point, normal, *_ in built["cases"][:2]:
        # case points are ON the wall; the sensor sits 1e-5 m inside it (free space).
        ref_point = reference.lift_off_surface(scene, point, normal)
        e, rel, info = reference.reference_irradiance(scene, ref_point, normal, target_rel_error=5e-4,
                                                      max_seconds=30)
        c = np.asarray(ref_point)
        direct = power / (4 * math.pi) * float(np.dot(-c / np.linalg.norm(c), normal)) / float(np.dot(c, c))
        expected = direct + rho * power / ((1 - rho) * a_poly)
        # The true-sphere closed form P / (A (1 - rho)) differs from this by 0.07 % (polygon effects).
        assert abs(expected / (power / (a_true * (1 - rho))) - 1) < 3e-3
        _agree(e[0], expected, rel, f"integrating sphere {label}")
        assert rel < 1e-3, rel


def test_stacked_lights_are_transparent(empty_scene):
    # Two 1 m square 50 W panels 1 m and 2 m above the sensor. Cycles lights are transparent to rays
    # (FACTS.md): the upper panel shines through the lower one, so E is the plain sum of the two
    # Lambert-polygon closed forms. With transparent_max_bounces = 0 it would lose ~2.8 % (FACTS.md).
    built = corpus.stacked_lights(do_reset=False)
    (label, point, normal, *_), = built["cases"]
    e, rel, _ = reference.reference_irradiance(built["scene"], point, normal, target_rel_error=5e-4)
    radiance = 50.0 / math.pi
    expected = sum(radiance * _projected_solid_angle([(-0.5, -0.5, h), (0.5, -0.5, h), (0.5, 0.5, h),
                                                      (-0.5, 0.5, h)], point, normal) for h in (1.0, 2.0))
    _agree(e[0], expected, rel, "stacked area lights")


def test_standard_error_is_honest(empty_scene):
    # The stated standard error (batch means over independent pixels) must predict the scatter of
    # independent runs. Ten runs (seeds 0, 100, ...) in the integrating sphere (multi-bounce noise):
    # the sample standard deviation of the ten results over the mean stated s.e. has 9 degrees of
    # freedom; its 99 % range is about [0.47, 1.54]. Correlated pixels (blue-noise sampling) or
    # per-sample variance would push it out.
    built = corpus.integrating_sphere(rho=0.8, power=100.0, segments=64, rings=32, do_reset=False)
    _, point, normal, *_ = built["cases"][0]
    ref_point = reference.lift_off_surface(built["scene"], point, normal)
    values, stated = [], []
    for k in range(10):
        e, rel, _ = reference.reference_irradiance(built["scene"], ref_point, normal, target_rel_error=3e-3,
                                                   seed=100 * k)
        values.append(e[0])
        stated.append(rel)
    values = np.asarray(values)
    ratio = (values.std(ddof=1) / values.mean()) / float(np.mean(stated))
    assert 0.45 < ratio < 1.6, (ratio, values, stated)

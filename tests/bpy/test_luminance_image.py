"""Luminance images of the camera view (issue 23 item 2): pixels against a closed form on an emitter and
against the reference patch render (tests/bpy/reference.py) on a lit wall, within 3 standard errors."""

import math
import os
import sys

import bpy
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import reference  # noqa: E402

from radiometer import api  # noqa: E402
from radiometer.measure.blender.scene_guard import scene_fingerprint  # noqa: E402


def _ortho_camera(scene, location, rotation, scale):
    data = bpy.data.cameras.new("cam")
    data.type = "ORTHO"
    data.ortho_scale = scale
    cam = bpy.data.objects.new("cam", data)
    cam.location, cam.rotation_euler = location, rotation
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def test_emitter_pixels_equal_the_panel_luminance(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0.0, 0.0, 2.0), energy=20.0, shape="SQUARE", size=1.0)
    _ortho_camera(scene, (0.0, 0.0, 1.0), (0.0, 0.0, 0.0), 0.3)  # looks along -Z... turned to look up below
    scene.camera.rotation_euler = (math.pi, 0.0, 0.0)             # camera -Z now points to +Z, at the panel
    before = scene_fingerprint(scene)
    img = api.luminance_image(str(tmp_path / "panel.exr"), scene=scene, resolution=(6, 4), quality="preview")
    assert scene_fingerprint(scene) == before
    expected = 683.0 * 20.0 / math.pi  # L = P / (pi A), A = 1 m², white (FACTS.md), K = 683
    assert img.luminance.shape == (4, 6)
    tol = np.maximum(3 * np.nan_to_num(img.rel_std_error) * img.luminance, 1e-5 * expected)
    assert np.all(np.abs(img.luminance - expected) <= tol), (img.luminance, expected)
    assert os.path.exists(img.paths["exr"]) and open(img.paths["png"], "rb").read(4) == b"\x89PNG"
    from radiometer.measure.blender import exr

    assert exr.read_rgb(img.paths["exr"])[..., 0] == pytest.approx(img.luminance, rel=1e-6)  # float32 file


def test_lit_wall_pixels_match_the_patch_reference(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.3, 0.0, 0.6), energy=200.0, shadow_soft_size=0.0)
    albedo = 0.8
    build.plane(scene, size=4.0, location=(0.0, 1.0, 0.5), rotation=(math.pi / 2, 0.0, 0.0), albedo=albedo,
                name="Wall")  # normal -y, facing the camera and the light
    side = 0.04
    _ortho_camera(scene, (0.0, 0.0, 0.5), (math.pi / 2, 0.0, 0.0), side)  # looks along +y at the wall
    n = 8
    img = api.luminance_image(str(tmp_path / "wall.exr"), scene=scene, resolution=(n, n), quality="standard")
    # pixel (row 0, col 0) is the top-left one; pixel centres on the wall y = 1
    for (row, col) in ((0, 0), (3, 6), (7, 7)):
        x = (col + 0.5) / n * side - side / 2
        z = 0.5 + side / 2 - (row + 0.5) / n * side
        point = reference.lift_off_surface(scene, (x, 1.0, z), (0.0, -1.0, 0.0))
        e_rgb, se, _info = reference.reference_irradiance(scene, point, (0.0, -1.0, 0.0), target_rel_error=1e-3)
        expected = albedo * reference.luminance(e_rgb)[1] / math.pi  # Lambert: L = rho E / pi, in cd/m²
        pixel, pixel_se = img.luminance[row, col], img.rel_std_error[row, col] * img.luminance[row, col]
        # the pixel averages E over its 5 mm footprint; E's curvature there changes the mean by
        # (h^2 / 6) |E''/E| ~ 3e-6 of E (h = 2.5 mm, |E''/E| ~ 3 / r^2 at r ~ 1 m): 1e-5 allowed
        assert abs(pixel - expected) <= 3 * math.hypot(pixel_se, se * expected) + 1e-5 * expected, \
            (pixel, expected, pixel_se, se)


def test_operator_loads_the_image(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0.0, 0.0, 2.0), energy=20.0, shape="SQUARE", size=1.0)
    _ortho_camera(scene, (0.0, 0.0, 1.0), (math.pi, 0.0, 0.0), 0.3)
    scene.render.resolution_x, scene.render.resolution_y = 16, 12
    scene.radiometer.quality = "preview"
    assert bpy.ops.radiometer.luminance_image(scale="linear") == {"FINISHED"}
    assert any(img.name.endswith("_luminance.png") for img in bpy.data.images)
    if bpy.app.version < (5, 0, 0):  # illuminance images need 5.0's compositor node groups: said in one line
        with pytest.raises(RuntimeError, match="need Blender 5.0"):
            bpy.ops.radiometer.luminance_image(quantity="ILLUMINANCE")
        return
    assert bpy.ops.radiometer.luminance_image(quantity="ILLUMINANCE") == {"FINISHED"}
    assert any(img.name.endswith("_illuminance.png") for img in bpy.data.images)


@pytest.mark.skipif(bpy.app.version < (5, 0, 0), reason="illuminance images need Blender 5.0's compositor node "
                    "groups; on 4.5 the API says so in one line (test_operator_loads_the_image)")
def test_illuminance_image_of_a_lit_wall(clean_blender, build, tmp_path):
    """E = pi (Diffuse Direct + Diffuse Indirect) on a Lambertian wall of albedo 0.3, against the patch
    reference (tests/bpy/reference.py), within 3 standard errors; the scene is left as it was."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.3, 0.0, 0.6), energy=200.0, shadow_soft_size=0.0)
    build.plane(scene, size=4.0, location=(0.0, 1.0, 0.5), rotation=(math.pi / 2, 0.0, 0.0), albedo=0.3,
                name="Wall")
    side, n = 0.04, 8
    _ortho_camera(scene, (0.0, 0.0, 0.5), (math.pi / 2, 0.0, 0.0), side)
    before = scene_fingerprint(scene)
    groups = len(bpy.data.node_groups)
    img = api.illuminance_image(str(tmp_path / "e.exr"), scene=scene, resolution=(n, n), quality="standard")
    assert scene_fingerprint(scene) == before and len(bpy.data.node_groups) == groups
    assert open(img.paths["png"], "rb").read(4) == b"\x89PNG"
    for (row, col) in ((0, 0), (5, 2)):
        x = (col + 0.5) / n * side - side / 2
        z = 0.5 + side / 2 - (row + 0.5) / n * side
        point = reference.lift_off_surface(scene, (x, 1.0, z), (0.0, -1.0, 0.0))
        e_rgb, se, _info = reference.reference_irradiance(scene, point, (0.0, -1.0, 0.0), target_rel_error=1e-3)
        expected = reference.luminance(e_rgb)[1]
        pixel = img.illuminance[row, col]
        pixel_se = img.rel_std_error[row, col] * pixel
        assert abs(pixel - expected) <= 3 * math.hypot(pixel_se, se * expected) + 1e-5 * expected, \
            (pixel, expected, pixel_se, se)


class _Clock:
    """A fake perf_counter: each render advances it by ``cost`` s per sample per pixel."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def _noisy_rounds(monkeypatch, *, cap, budget, cost=0.01, spread=2.0):
    """``_rounds_to_target`` on renders of pure noise (relative spread ``spread`` per sample), whose
    error never reaches a 5 % target below 1024 x 8 samples: what stops the rounds is the cap or the budget."""
    import types

    from radiometer.measure.analyses import luminance_image as li

    clock = _Clock()
    monkeypatch.setattr(li.time, "perf_counter", clock)
    rng = np.random.default_rng(5)
    scene = types.SimpleNamespace(cycles=types.SimpleNamespace(seed=0, samples=0))
    rendered = []

    def render(_k):
        spp = scene.cycles.samples
        rendered.append(spp)
        clock.now += cost * spp
        return 1.0 + spread / math.sqrt(spp) * rng.standard_normal((6, 8, 3))

    from radiometer.measure.blender.request import Request

    request = Request(scene=scene, view_layer=None, scale_length=1.0, colour_space="Linear Rec.709",
                      luminance_weights=(0.2126, 0.7152, 0.0722), efficacy=683.0, time_budget_s=budget)
    out = li._rounds_to_target(request, render, 0.05, cap)
    return out, rendered


def test_picture_rounds_stop_at_the_cap_and_the_time_budget(monkeypatch):
    from radiometer.measure.analyses import luminance_image as li

    (_stack, _m, lit, spp, stopped), rendered = _noisy_rounds(monkeypatch, cap=li._cap("preview", None), budget=None)
    assert li._cap("preview", None) == li.PREVIEW_MAX_SPP == 16 and li._cap("standard", None) == 1024
    assert spp == 16 and rendered == [16] * li.RENDERS and "cap of 16" in stopped
    assert np.percentile(lit, 90) > 0.05  # the picture did not reach the target: the caller says so
    # Budget: rounds of 8 renders cost 0.01 s per sample per pixel (16 spp: 1.28 s; 64: 5.12 s; 256: 20.5 s).
    # With 10 s the 64-spp round (predicted 5.12 s, ending at 6.4 s) runs; the 256 one (ending at 26.9 s) does not.
    (_stack, _m, _lit, spp, stopped), rendered = _noisy_rounds(monkeypatch, cap=1024, budget=10.0)
    assert spp == 64 and rendered == [16] * li.RENDERS + [64] * li.RENDERS and "time budget of 10 s" in stopped
    # the first round always runs, whatever the budget
    (_stack, _m, _lit, spp, stopped), rendered = _noisy_rounds(monkeypatch, cap=1024, budget=0.001)
    assert spp == 16 and len(rendered) == li.RENDERS and "time budget" in stopped


def test_api_luminance_image_takes_a_cap_and_a_budget(clean_blender, build, tmp_path):
    from radiometer.errors import RadiometerError

    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0.0, 0.0, 2.0), energy=20.0, shape="SQUARE", size=1.0)
    _ortho_camera(scene, (0.0, 0.0, 1.0), (math.pi, 0.0, 0.0), 0.3)
    before = scene_fingerprint(scene)
    img = api.luminance_image(str(tmp_path / "l.exr"), scene=scene, resolution=(8, 6), quality="preview",
                              time_budget_s=60.0)
    assert img.samples <= 8 * 16 and os.path.exists(img.paths["exr"])
    assert scene_fingerprint(scene) == before
    for bad in ({"max_spp": 8}, {"max_spp": 2000}, {"time_budget_s": -1.0}, {"time_budget_s": "x"}):
        with pytest.raises(RadiometerError):
            api.luminance_image(str(tmp_path / "m.exr"), scene=scene, resolution=(8, 6), quality="preview", **bad)

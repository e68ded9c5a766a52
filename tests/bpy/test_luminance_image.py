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

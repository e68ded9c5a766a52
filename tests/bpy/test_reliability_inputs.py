"""Issue 21, bad world inputs: a world image with NaN/inf pixels, a missing or empty image file is an
error naming the image, never a NaN reading or Blender's magenta placeholder measured as light
(findings 4, 5, 6). The EXR source of an irradiance map with non-finite pixels is refused too.
No Cycles render runs: every case is refused while the scene is read."""

import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.errors import RadiometerError


def env_world(scene, image):
    world = bpy.data.worlds.new("env")
    tree = ensure_node_tree(world)
    env = tree.nodes.new("ShaderNodeTexEnvironment")
    env.image, env.interpolation = image, "Closest"
    tree.links.new(env.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    scene.world = world
    return world


def float_image(pixels):
    h, w = pixels.shape[:2]
    img = bpy.data.images.new("env", w, h, float_buffer=True, alpha=False)
    rgba = np.concatenate([pixels, np.ones((h, w, 1))], axis=-1).astype(np.float32)
    img.pixels.foreach_set(rgba.ravel())
    return img


def one_line(exc):
    text = str(exc.value)
    assert "\n" not in text and len(text) < 400
    return text


MEASURES = {
    "measure_illuminance": lambda: api.measure_illuminance((0, 0, 0), (0, 0, 1), quality="preview"),
    "world_illuminance": lambda: api.world_illuminance(),
    "irradiance_environment_map": None,  # needs a path: see the test
}


@pytest.mark.parametrize("bad", [math.inf, math.nan])
@pytest.mark.parametrize("call", ["measure_illuminance", "world_illuminance"])
def test_world_image_with_one_non_finite_pixel_is_an_error(clean_blender, bad, call):
    # Finding 4: one inf pixel gave lux = nan with rel_std_error = nan, and world_illuminance nan.
    px = np.full((8, 16, 3), 0.5)
    px[2, 3, 0] = bad
    env_world(bpy.context.scene, float_image(px))
    with pytest.raises(RadiometerError) as info:
        MEASURES[call]()
    assert "NaN or infinite" in one_line(info) and "env" in str(info.value)


def test_world_image_with_non_finite_pixel_gives_no_irradiance_map(clean_blender, tmp_path):
    px = np.full((8, 16, 3), 0.5)
    px[0, 0, 2] = math.inf
    env_world(bpy.context.scene, float_image(px))
    with pytest.raises(RadiometerError):
        api.irradiance_environment_map("world", str(tmp_path / "e.exr"), resolution=(8, 4))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("call", ["measure_illuminance", "world_illuminance"])
def test_missing_world_image_file_is_an_error_naming_it(clean_blender, tmp_path, call):
    # Finding 5: a missing file was measured from Blender's magenta placeholder (608 lx), with a note.
    path = str(tmp_path / "sky_that_is_not_there.exr")
    img = bpy.data.images.new("sky", 4, 4, float_buffer=True)
    img.source, img.filepath = "FILE", path
    env_world(bpy.context.scene, img)
    with pytest.raises(RadiometerError) as info:
        MEASURES[call]()
    assert "sky_that_is_not_there.exr" in one_line(info) and "magenta" in str(info.value)


def test_empty_world_image_file_is_an_error(clean_blender, tmp_path):
    path = tmp_path / "empty.exr"
    path.write_bytes(b"")
    img = bpy.data.images.new("empty", 4, 4, float_buffer=True)
    img.source, img.filepath = "FILE", str(path)
    env_world(bpy.context.scene, img)
    with pytest.raises(RadiometerError) as info:
        api.world_illuminance()
    assert "empty.exr" in one_line(info)


def test_environment_texture_without_image_is_an_error(clean_blender):
    env_world(bpy.context.scene, None)
    with pytest.raises(RadiometerError, match="no image"):
        api.world_illuminance()


def test_irradiance_map_of_an_exr_with_non_finite_pixels_is_an_error(clean_blender, tmp_path):
    # Finding 6: NaN/inf SH coefficients were returned and the map written.
    from radiometer.measure.authoring.world import write_exr

    px = np.ones((8, 16, 3))
    px[4, 4] = np.nan
    src = str(tmp_path / "src.exr")
    write_exr(src, px)
    out = tmp_path / "out.exr"
    with pytest.raises(RadiometerError) as info:
        api.irradiance_environment_map(src, str(out), resolution=(8, 4))
    assert "NaN or infinite" in one_line(info)
    assert not out.exists()


def test_finite_world_image_still_reads_exactly(clean_blender):
    env_world(bpy.context.scene, float_image(np.full((8, 16, 3), 0.5)))
    info = api.world_illuminance()
    assert info["method"] == "analytic" and math.isfinite(info["illuminance"]) and info["illuminance"] > 0

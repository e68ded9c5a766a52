"""Issue 21, finding 11: the scene guard restores nested setting structs, and the fingerprint that the
tests compare walks every writable property recursively.

``measure_luminance`` and ``capture_radiance_map`` render EXRs: they set the output format, which
resets the image settings' linear colour space ('Linear Rec.2020' -> 'Linear Rec.709'); the guard
must give it back, after success and after an error. Tiny renders (8 x 8 / 8 x 4 px, preview)."""

import bpy
import pytest

from radiometer import api
from radiometer.errors import RadiometerError
from radiometer.measure.blender import scene_guard


def leaves(tree, prefix=""):
    """Flatten a fingerprint tree to {"path.ident": value}."""
    out = {f"{prefix}{k}": v for k, v in tree["values"].items()}
    for ident, child in tree["nested"].items():
        out.update(leaves(child, f"{prefix}{ident}."))
    return out


@pytest.fixture
def user_scene(clean_blender, build):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    build.black_world(s)
    build.light(s, "AREA", (0, 0, 2), energy=100.0, size=0.5)
    ims = s.render.image_settings
    ims.file_format = "OPEN_EXR"
    ims.color_management = "OVERRIDE"  # the linear colour space is the user's own only when overridden
    ims.linear_colorspace_settings.name = "Linear Rec.2020"
    ims.view_settings.exposure = 1.5
    s.view_settings.look = "None"
    s.view_settings.gamma = 1.2
    s.view_settings.use_curve_mapping = True
    s.render.bake.image_settings.file_format = "TIFF"
    return s


def test_fingerprint_walks_nested_structs(user_scene):
    fp = scene_guard.scene_fingerprint(user_scene)
    flat = leaves(fp["values"]["image_settings"])
    assert flat["linear_colorspace_settings.name"] == "Linear Rec.2020"
    assert flat["view_settings.exposure"] == 1.5
    assert "image_settings.file_format" in leaves(fp["values"]["bake"])
    assert any(k.startswith("curve_mapping.") for k in leaves(fp["values"]["view_settings"]))


def test_guard_restores_a_nested_value_changed_inside(user_scene):
    before = scene_guard.scene_fingerprint(user_scene)
    with scene_guard.preserved_scene(user_scene):
        ims = user_scene.render.image_settings
        ims.file_format = "PNG"
        ims.file_format = "OPEN_EXR"  # resets the linear colour space
        ims.view_settings.exposure = -3.0
        user_scene.view_settings.curve_mapping.black_level = (0.1, 0.1, 0.1)
        user_scene.render.bake.image_settings.file_format = "PNG"
    assert scene_guard.scene_fingerprint(user_scene) == before
    assert user_scene.render.image_settings.linear_colorspace_settings.name == "Linear Rec.2020"


@pytest.mark.parametrize("call", ["luminance", "radiance_map"])
def test_camera_readings_leave_every_nested_setting(user_scene, tmp_path, call):
    before = scene_guard.scene_fingerprint(user_scene)
    if call == "luminance":
        api.measure_luminance((0, 0, 0.5), (0, 0, 1), quality="preview", target_rel_error=0.4)
    else:
        api.capture_radiance_map((0, 0, 0.5), str(tmp_path / "m.exr"), resolution=4, quality="preview")
    assert scene_guard.scene_fingerprint(user_scene) == before


def test_failed_reading_leaves_every_nested_setting(user_scene, monkeypatch):
    from radiometer.measure.meter import camera

    before = scene_guard.scene_fingerprint(user_scene)

    def fail(*args, **kwargs):
        raise RadiometerError("render failed (test)")

    monkeypatch.setattr(camera, "render_exr", fail)
    with pytest.raises(RadiometerError):
        api.measure_luminance((0, 0, 0.5), (0, 0, 1), quality="preview")
    assert scene_guard.scene_fingerprint(user_scene) == before

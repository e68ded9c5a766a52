"""A measurement leaves the user's scene exactly as it was, also when it fails (issue 3)."""

import math

import bpy
import pytest

from radiometer import api
from radiometer.errors import MeasurementCancelled, RadiometerError
from radiometer.measure.blender.scene_guard import scene_fingerprint

# EEVEE's engine id: BLENDER_EEVEE_NEXT in Blender 4.2-4.5, BLENDER_EEVEE again since 5.0.
EEVEE = "BLENDER_EEVEE" if bpy.app.version >= (5, 0, 0) else "BLENDER_EEVEE_NEXT"


def user_scene(build):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "AREA", (0, 0, 2), energy=30.0, size=0.5)
    floor = build.plane(scene, size=4.0, albedo=0.5, name="floor")
    cam_data = bpy.data.cameras.new("user cam")
    cam = bpy.data.objects.new("user cam", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.engine = EEVEE
    scene.render.resolution_x, scene.render.resolution_y = 1234, 567
    scene.cycles.samples = 77
    scene.cycles.use_denoising = True
    scene.cycles.light_sampling_threshold = 0.05
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = "//user_out_"
    scene.frame_set(7)
    for ob in scene.objects:
        ob.select_set(ob is light)
    bpy.context.view_layer.objects.active = floor
    return scene


def test_render_measurement_leaves_scene_untouched(clean_blender, build):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    api.measure_illuminance([(0, 0, 0.5), (1, 0, 0.5)], (0, 0, 1), method="render", quality="preview")
    api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
    assert scene_fingerprint(scene) == before


def test_radiance_map_leaves_scene_untouched(clean_blender, build, tmp_path):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    api.capture_radiance_map((0, 0, 1.0), str(tmp_path / "m.exr"), resolution=16, quality="preview")
    assert scene_fingerprint(scene) == before


def test_cancelled_measurement_leaves_scene_untouched(clean_blender, build):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    with pytest.raises(MeasurementCancelled):
        api.measure_illuminance((0, 0, 0.5), method="render", cancelled=lambda: True)
    assert scene_fingerprint(scene) == before
    assert not [i for i in bpy.data.images if i.name.startswith("radiometer")]


def test_failing_bake_leaves_scene_untouched(clean_blender, build, monkeypatch):
    scene = user_scene(build)
    before = scene_fingerprint(scene)

    def broken(*_args, **_kwargs):
        raise RuntimeError("simulated Cycles failure")

    from radiometer.measure.render import sensors

    monkeypatch.setattr(sensors, "run_bake", broken)
    # The API boundary wraps what escapes from below as one RadiometerError, chained (issue 21).
    with pytest.raises(RadiometerError, match="simulated") as info:
        api.measure_illuminance((0, 0, 0.5), method="render")
    assert isinstance(info.value.__cause__, RuntimeError)
    assert scene_fingerprint(scene) == before


def test_keyboard_interrupt_leaves_scene_untouched(clean_blender, build):
    scene = user_scene(build)
    before = scene_fingerprint(scene)

    def interrupt(_done, _total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        api.measure_illuminance((0, 0, 0.5), method="render", progress=interrupt)
    assert scene_fingerprint(scene) == before


def test_bad_input_changes_nothing(clean_blender, build):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    with pytest.raises(RadiometerError):
        api.measure_illuminance((math.nan, 0, 0))
    assert scene_fingerprint(scene) == before


def test_measure_operator_stores_readings_and_restores_selection(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    meter = bpy.context.active_object
    before = scene_fingerprint(scene)
    assert bpy.ops.radiometer.measure() == {"FINISHED"}
    m = meter.radiometer_meter
    assert m.has_reading and m.exact and m.method == "analytic"
    assert m.photometric == pytest.approx(683 * 100 / (4 * math.pi * 4), rel=1e-6)
    after = scene_fingerprint(scene)
    assert after["selection"] == before["selection"] and after["active"] == before["active"]

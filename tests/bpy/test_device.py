"""Measurements render on the user's GPU where Cycles can (issue 17), else on the CPU with a note."""

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.measure.blender import device
from radiometer.measure.render import render_settings


def test_choice_follows_the_preferences_and_the_scene():
    assert device.choose("NONE", [], False) == ("CPU", "CPU", None)
    assert device.choose("CUDA", [], False)[0] == "CPU"  # back-end chosen, no device ticked
    assert device.choose("CUDA", ["RTX A"], False) == ("GPU", "GPU CUDA: RTX A", None)
    cpu, _label, note = device.choose("HIP", ["RX 7900"], True)
    assert cpu == "CPU" and "OSL" in note and "HIP" in note
    assert device.choose("OPTIX", ["RTX A", "RTX B"], True)[0] == "GPU"  # OptiX runs OSL


def test_factory_preferences_measure_on_the_cpu_and_say_so(clean_blender):
    scene = bpy.context.scene
    record = render_settings.apply(scene, samples=1, bounces=0, needs={
        "geometry": False, "glossy": False, "transmission": False, "volume": False})
    expected = device.measurement_device(scene)
    assert scene.cycles.device == expected[0]
    assert record["device"] == expected[0] and record["engine"] == f"CYCLES ({expected[1]})"


def _gpu_backend():
    prefs = bpy.context.preferences.addons["cycles"].preferences
    for backend in ("OPTIX", "CUDA", "HIP", "METAL", "ONEAPI"):
        try:
            devices = prefs.get_devices_for_type(backend)
        except (TypeError, ValueError, RuntimeError):
            continue
        if any(d.type != "CPU" for d in devices):
            return backend
    return None


def test_gpu_readings_agree_with_cpu_readings(clean_blender, build):
    backend = _gpu_backend()
    if backend is None:
        pytest.skip("no GPU that Cycles can use on this machine: the GPU-vs-CPU comparison did not run")
    prefs = bpy.context.preferences.addons["cycles"].preferences
    saved = (prefs.compute_device_type, {d.name: d.use for d in prefs.devices})
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", location=(0.0, 0.0, 2.5), energy=300.0, size=0.8)
    build.plane(scene, size=6.0, location=(0.0, 0.0, 3.0), rotation=(np.pi, 0.0, 0.0), albedo=0.7, name="ceiling")
    build.plane(scene, size=6.0, name="floor")
    points = np.array([[0.0, 0.0, 0.8], [1.0, 0.5, 0.8], [-1.5, 1.0, 0.8]])
    try:
        prefs.compute_device_type = "NONE"
        cpu = api.measure_illuminance(points, (0, 0, 1), method="render", target_rel_error=0.01)
        prefs.compute_device_type = backend
        for d in prefs.get_devices_for_type(backend):
            d.use = d.type != "CPU"
        gpu = api.measure_illuminance(points, (0, 0, 1), method="render", target_rel_error=0.01)
    finally:
        prefs.compute_device_type = saved[0]
        for d in prefs.devices:
            if d.name in saved[1]:
                d.use = saved[1][d.name]
    assert all(r.render_settings["device"] == "GPU" for r in gpu)
    assert all(r.render_settings["device"] == "CPU" for r in cpu)
    for c, g in zip(cpu, gpu):
        combined = np.hypot(c.rel_std_error * c.irradiance, g.rel_std_error * g.irradiance)
        assert abs(c.irradiance - g.irradiance) <= 4.0 * combined, (c.irradiance, g.irradiance, combined)


def test_choice_for_the_meter_camera():
    """The meter camera is an OSL custom camera: Cycles runs those on the CPU and OptiX only."""
    cpu, label, note = device.choose("CUDA", ["RTX A"], False, custom_camera=True)
    assert (cpu, label) == ("CPU", "CPU") and "custom camera" in note and "CUDA" in note
    assert device.choose("OPTIX", ["RTX A"], False, custom_camera=True) == ("GPU", "GPU OPTIX: RTX A", None)
    assert device.choose("NONE", [], False, custom_camera=True) == ("CPU", "CPU", None)


class _FakeDevice:
    def __init__(self, name, kind, use=True):
        self.name, self.type, self.use = name, kind, use


class _FakeCyclesPreferences:
    """A user who ticked a CUDA card in Preferences > System (this machine may have none)."""
    compute_device_type = "CUDA"

    def get_devices_for_type(self, backend):
        return [_FakeDevice("RTX A", "CUDA"), _FakeDevice("CPU", "CPU", use=False)]


def test_meter_camera_renders_on_the_cpu_where_the_users_gpu_cannot_run_it(clean_blender, build, monkeypatch):
    """With CUDA chosen in the preferences, bakes would go to the GPU, but the meter camera (an OSL custom camera)
    renders on the CPU and its readings say why; the scene's device is the user's afterwards."""
    from radiometer.measure.analyses import daylight_coefficients as dcm
    from radiometer.measure.blender import request as request_of

    scene = bpy.context.scene
    if "CUSTOM" not in bpy.types.Camera.bl_rna.properties["type"].enum_items.keys():
        pytest.skip("this Blender has no custom cameras")
    build.plane(scene, size=4.0, name="floor")
    world = bpy.data.worlds.new("grey sky")
    scene.world = world
    from radiometer.compat import ensure_node_tree

    bg = next(nd for nd in ensure_node_tree(world).nodes if nd.type == "BACKGROUND")
    bg.inputs["Strength"].default_value = 1.0
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    monkeypatch.setattr(device, "_cycles_preferences", lambda: _FakeCyclesPreferences())
    assert device.measurement_device(scene)[0] == "GPU"  # what a bake would use
    before = scene.cycles.device
    e_rgb, _cov, record = dcm.render_irradiance([(0.0, 0.0, 0.5)], [(0.0, 0.0, 1.0)],
                                                request=request_of.build(scene, quality="preview", seed=1),
                                                rounds=2)
    assert record["device"] == "CPU" and record["engine"] == "CYCLES (CPU)"
    assert "custom camera" in record["device_note"] and "CUDA" in record["device_note"]
    assert scene.cycles.device == before
    # a white sky of radiance 1 over an unobstructed up-facing point: E = pi (the camera really rendered)
    assert abs(float(e_rgb[0, 1]) - np.pi) < 0.01 * np.pi, e_rgb

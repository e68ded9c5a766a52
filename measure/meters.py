"""Measure meter objects and store their readings (the work behind ``radiometer.measure``).

Readings are computed first and written to the objects only when every step succeeded, so a
failed or cancelled run leaves the previous readings (and the rest of the scene) as they were.
"""

import bpy
import numpy as np

from ..errors import RadiometerError
from . import camera, meter


def meter_objects(scene, objects=None):
    if objects is None:
        objects = [ob for ob in scene.objects if ob.radiometer_meter.is_meter]
    else:
        objects = list(objects)
        bad = [ob.name for ob in objects if not ob.radiometer_meter.is_meter]
        if bad:
            raise RadiometerError(f"not light meters: {', '.join(bad)} (add one with Add > Light Meter)")
    if not objects:
        raise RadiometerError("no light meters to measure: add one with Add > Light Meter")
    return objects


def _pose(obj):
    """World location (scene units) and local +Z axis of a meter, from the evaluated depsgraph."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mw = obj.evaluated_get(depsgraph).matrix_world
    z = np.array(mw.to_3x3().col[2], float)
    return np.array(mw.translation, float), z


def plan_steps(scene, objects):
    """Steps of a measurement: one batch for all illuminance meters, one step per other meter."""
    illum = [ob for ob in objects if ob.radiometer_meter.kind == "ILLUMINANCE"]
    steps = []
    if illum:
        steps.append(("ILLUMINANCE", illum))
    steps += [(ob.radiometer_meter.kind, [ob]) for ob in objects if ob.radiometer_meter.kind != "ILLUMINANCE"]
    return steps


def run_step(scene, step, settings, *, progress=None, cancelled=None):
    kind, objs = step
    quality = settings["quality"]
    if kind == "ILLUMINANCE":
        poses = [_pose(ob) for ob in objs]
        readings = meter.measure_illuminance(
            np.array([p for p, _ in poses]), np.array([z for _, z in poses]), scene=scene,
            method=settings["method"], quality=quality, target_rel_error=settings["target_rel_error"],
            progress=progress, cancelled=cancelled, exclude={ob.name for ob in objs})
        return list(zip(objs, readings))
    ob = objs[0]
    location, z = _pose(ob)
    if kind == "LUMINANCE":
        reading = camera.measure_luminance(location, -z, acceptance_deg=ob.radiometer_meter.acceptance_deg,
                                           scene=scene, quality=quality, cancelled=cancelled,
                                           target_rel_error=settings["target_rel_error"])
        return [(ob, reading)]
    path = camera.default_map_path(ob.name)
    result = camera.capture_radiance_map(location, path, resolution=ob.radiometer_meter.map_resolution,
                                         scene=scene, quality=quality)
    return [(ob, result)]


def write_reading(obj, reading):
    m = obj.radiometer_meter
    m.has_reading = True
    if reading.quantity == "illuminance":
        m.value_rgb, m.value, m.photometric = reading.irradiance_rgb, reading.irradiance, reading.illuminance
    elif reading.quantity == "luminance":
        m.value_rgb, m.value, m.photometric = reading.radiance_rgb, reading.radiance, reading.luminance
    else:  # radiance map: store the irradiance it implies for the meter's +Z normal
        m.value_rgb, m.value, m.photometric = reading.irradiance_rgb, reading.irradiance, reading.illuminance
        m.map_path = reading.path
    m.rel_std_error = reading.rel_std_error if np.isfinite(reading.rel_std_error) else 0.0
    m.exact, m.method, m.samples = reading.exact, reading.method, int(reading.samples)
    m.seconds, m.efficacy = reading.seconds, reading.efficacy
    m.notes = " | ".join(reading.notes)


def scene_settings(scene, quality=None):
    s = scene.radiometer
    return {"method": s.method, "quality": quality or s.quality,
            "target_rel_error": s.target_rel_error if s.target_rel_error > 0 else None}


def measure_meters(objects=None, *, scene=None, quality=None, progress=None, cancelled=None):
    scene = scene or bpy.context.scene
    objects = meter_objects(scene, objects)
    settings = scene_settings(scene, quality)
    results = []
    steps = plan_steps(scene, objects)
    for i, step in enumerate(steps):
        results += run_step(scene, step, settings, cancelled=cancelled)
        if progress is not None:
            progress(i + 1, len(steps))
    for obj, reading in results:
        write_reading(obj, reading)
    return results

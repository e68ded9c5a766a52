"""Measure meter objects (the work behind ``radiometer.measure``).

A meter is an object and its settings, given as a :class:`Meter` by the caller (the api reads them from
the object's Radiometer properties: host code takes settings as arguments, issue 30). Readings are
computed first and handed back; the caller stores them only when every step succeeded, so a failed or
cancelled run leaves the previous readings (and the rest of the scene) as they were.
"""

import dataclasses
import os
import time

import bpy
import numpy as np

from ...errors import MeasurementCancelled, RadiometerError
from ...progress import reporter
from . import camera, point_meter as meter

_DISPLAY = {"ILLUMINANCE": ("SINGLE_ARROW", 0.3), "LUMINANCE": ("CONE", 0.1), "RADIANCE_MAP": ("SPHERE", 0.1)}

DEFAULT_ROTATION = {"LUMINANCE": (3.14159265358979 / 2, 0.0, 0.0)}  # a spot meter looks along +Y


@dataclasses.dataclass(frozen=True)
class Meter:
    """One meter: its object (pose, name) and its settings. ``kind``: "ILLUMINANCE", "LUMINANCE" or
    "RADIANCE_MAP"; ``acceptance_deg``: a spot meter's full cone angle (deg); ``map_resolution``: a
    radiance map's height (px, width 2x)."""

    obj: object
    kind: str = "ILLUMINANCE"
    acceptance_deg: float = 1.0
    map_resolution: int = 128


def add_meter_object(context, kind, location, rotation=None):
    """Create the empty of a new meter of ``kind`` at ``location`` (linked to the active collection),
    selected and active; the caller marks it a meter (its Radiometer properties). Returns it.

    ``rotation``: Euler angles (rad); None: the kind's default (a spot meter looks along +Y).
    """
    name = {"ILLUMINANCE": "Illuminance Meter", "LUMINANCE": "Luminance Meter", "RADIANCE_MAP": "Radiance Map"}[kind]
    obj = bpy.data.objects.new(name, None)
    obj.empty_display_type, obj.empty_display_size = _DISPLAY[kind]
    obj.rotation_euler = DEFAULT_ROTATION.get(kind, (0.0, 0.0, 0.0)) if rotation is None else tuple(rotation)
    obj.location = location
    context.collection.objects.link(obj)
    for other in context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return obj


def _call(progress, done, total, seconds_left=None):
    """Call a progress callback that takes (done, total, seconds_left) or only (done, total)."""
    if progress is not None:
        reporter(progress)(done, total, seconds_left)


def _two_args(progress):
    # camera.measure_luminance reports (done, total): pass them on with no ETA.
    return reporter(progress)


def map_path(name):
    """Where a radiance map of meter ``name`` goes: the extension's user folder, else a private temp folder.

    The file name keeps the meter's name readable and unique ("Lamp.1" and "Lamp_1" differ).
    """
    from ... import outputs

    return os.path.join(outputs.user_folder("radiance_maps"), outputs.file_stem(name) + ".exr")


def _pose(obj):
    """World location (scene units) and local +Z axis of a meter, from the evaluated depsgraph."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    mw = obj.evaluated_get(depsgraph).matrix_world
    z = np.array(mw.to_3x3().col[2], float)
    return np.array(mw.translation, float), z


def plan_steps(meters, batch=None):
    """Steps of a measurement of ``meters`` (:class:`Meter`): illuminance meters in batches (one batch of
    all when ``batch`` is None: cheapest; the UI uses smaller ones so a step is short), then one step per
    other meter. A step is (kind, [Meter])."""
    illum = [m for m in meters if m.kind == "ILLUMINANCE"]
    steps = []
    size = len(illum) if not batch else int(batch)
    for k in range(0, len(illum), max(size, 1)):
        steps.append(("ILLUMINANCE", illum[k:k + size]))
    steps += [(m.kind, [m]) for m in meters if m.kind != "ILLUMINANCE"]
    return steps


def run_step(request, step, *, method="auto"):
    """Measure one step of :func:`plan_steps`; returns [(object, reading)]. The request
    (``measure.blender.request``): the scene, "quality", "target_rel_error" (fraction or None),
    "time_budget_s" and "target_abs_error" (the illuminance meters'), progress and cancel."""
    kind, group = step
    if kind == "ILLUMINANCE":
        objs = [m.obj for m in group]
        poses = [_pose(ob) for ob in objs]
        readings = meter.measure_illuminance(
            np.array([p for p, _ in poses]), np.array([z for _, z in poses]), request, method=method,
            exclude={ob.name for ob in objs})
        return list(zip(objs, readings))
    m = group[0]
    ob = m.obj
    location, z = _pose(ob)
    # a camera reading takes the quality, its target and cancel (no time budget or absolute floor)
    camera_request = request.but(samples=None, time_budget_s=None, target_abs_error=None, seed=0)
    if kind == "LUMINANCE":
        reading = camera.measure_luminance(location, -z, acceptance_deg=m.acceptance_deg,
                                           request=camera_request.but(progress=_two_args(request.progress)))
        return [(ob, reading)]
    if request.cancelled is not None and request.cancelled():
        raise MeasurementCancelled("measurement cancelled; the scene was restored")
    path = map_path(ob.name)
    result = camera.capture_radiance_map(location, path, resolution=m.map_resolution, request=camera_request)
    return [(ob, result)]


def reading_values(reading):
    """The values a meter object stores for ``reading`` (ID properties of its reading, same names): a
    dict of plain numbers and text."""
    values = {}
    if reading.quantity == "illuminance":
        rgb, value, photometric = reading.irradiance_rgb, reading.irradiance, reading.illuminance
    elif reading.quantity == "luminance":
        rgb, value, photometric = reading.radiance_rgb, reading.radiance, reading.luminance
    else:  # radiance map: store the irradiance it implies for the meter's +Z normal
        rgb, value, photometric = reading.irradiance_rgb, reading.irradiance, reading.illuminance
        values["map_path"] = reading.path
    values["value_rgb"] = [float(v) for v in rgb]
    values["value"], values["photometric"] = float(value), float(photometric)
    # inf is kept: a rendered reading that found no light yet has no error bound, and 0 would
    # show "0 lx ±0 %" (issue 18); the sidebar says "n/a" for it.
    values["rel_std_error"] = float(reading.rel_std_error)
    values["exact"], values["method"], values["samples"] = bool(reading.exact), str(reading.method), int(reading.samples)
    values["seconds"], values["efficacy"] = float(reading.seconds), float(reading.efficacy)
    values["notes"] = " | ".join(reading.notes)
    values["has_reading"] = True
    values["spectral_status"] = ""  # a melanopic reading of an earlier pose or scene no longer applies
    return values


def direct_spectral_reading(obj, request, *, reflected=False):
    """``spectra.spectral_reading`` (the direct light's) where the meter object stands and faces; with
    ``reflected`` ``spectral_reflected.spectral_reading`` (direct + reflected, band renders at the request's
    quality and seed). ``request``: a request (``measure.blender.request``), a scene or None."""
    from . import spectra, spectral_reflected
    from ..blender import request as request_of

    request = request_of.of(request)
    location, z = _pose(obj)
    normal = tuple(z / np.linalg.norm(z))
    if reflected:
        return spectral_reflected.spectral_reading(tuple(location), normal, request=request)
    return spectra.spectral_reading(tuple(location), normal, request=request)


def spectral_values(reading):
    """The values a meter object stores for a direct spectral reading (``spectra.spectral_reading``'s dict)."""
    der, sp = reading.get("mel_der"), reading.get("sp_ratio")
    if reading.get("part") == "direct+reflected":
        iv = reading["interval_95"]["mel_edi_lx"]
        status = (f"direct + reflected (band renders): 95 % interval {iv['low_95']:.4g}-{iv['high_95']:.4g} lx"
                  + (f"; lower bound: {'; '.join(reading['notes'][:1])}" if not reading["complete"] else ""))
    elif reading["exact"]:
        status = "exact: every light's direct part in closed form with a known spectrum"
    else:
        status = "lower bound: " + "; ".join(reading["notes"] or ["some light has no closed form or spectrum"])
    status += "; not included: " + ", ".join(reading["not_included"])
    return {"mel_edi": float(reading["mel_edi_lx"]), "mel_der": float(der) if der is not None else float("nan"),
            "sp_ratio": float(sp) if sp is not None else float("nan"), "spectral_status": status}


def step_weights(steps):
    """Relative cost of each step for a progress bar (a batch of n meters ~ n, a map ~ 4 meters)."""
    return [float(len(objs)) if kind == "ILLUMINANCE" else (4.0 if kind == "RADIANCE_MAP" else 1.0)
            for kind, objs in steps]


def measurement_steps(request, meters, *, method="auto", batch=None):
    """Steps of a measurement of ``meters`` (:class:`Meter`) for a progress bar: [(label, weight, run)],
    where ``run(progress=None, cancelled=None)`` measures the step and returns [(object, reading)]
    (nothing stored). The request as :func:`run_step`'s; its ``time_budget_s`` caps each step (the target
    still ends it early; with no target set, the quality preset's)."""
    if request.time_budget_s is not None and request.target_rel_error is None:
        request = request.but(target_rel_error=request.preset()["target"])
    steps = plan_steps(meters, batch=batch)

    def runner(step):
        def run(progress=None, cancelled=None):
            return run_step(request.but(progress=progress, cancelled=cancelled), step, method=method)
        return run

    return [(group[0].obj.name if len(group) == 1 else f"{len(group)} meters", weight, runner((kind, group)))
            for (kind, group), weight in zip(steps, step_weights(steps))]


class StepProgress:
    """Maps each step's own progress (done/total) onto the whole run: ``fraction`` 0..1 and an ETA (s).

    ``report(fraction, seconds_left)`` receives the overall values. Shared by ``measure_meters`` and
    the modal operators.
    """

    def __init__(self, steps, report=None):
        w = step_weights(steps)
        self.bounds = np.concatenate([[0.0], np.cumsum(w)]) / max(sum(w), 1e-12)
        self.report = report
        self.index = 0
        self.fraction = 0.0
        self.seconds_left = None
        self.started = time.perf_counter()

    def start(self, index):
        self.index = index
        self._update(self.bounds[index], None)

    def __call__(self, done, total, seconds_left=None):
        lo, hi = self.bounds[self.index], self.bounds[self.index + 1]
        part = min(max(done / total, 0.0), 1.0) if total else 0.0
        self._update(lo + (hi - lo) * part, seconds_left)

    def _update(self, fraction, step_seconds_left):
        self.fraction = float(max(self.fraction, fraction))
        elapsed = time.perf_counter() - self.started
        # Whole-run ETA from the pace so far (the step's own ETA covers only the step).
        self.seconds_left = elapsed * (1 - self.fraction) / self.fraction if self.fraction > 0.02 else \
            step_seconds_left
        if self.report is not None:
            self.report(self.fraction, self.seconds_left)


def measure_meters(meters, request, *, method="auto"):
    """Measure ``meters`` (:class:`Meter`, at least one) with the request (as :func:`run_step`'s; its
    "target_abs_error": the illuminance meters' absolute error floor, lux, None the preset's); returns
    [(object, reading)], nothing stored.

    The request's ``progress(done, total, seconds_left)``: done/total in thousandths of the whole run, with
    an ETA in s (None until known), called within every step; its ``cancelled()``: polled before every
    allocation round; True raises MeasurementCancelled and leaves every reading as it was.
    """
    progress, cancelled = request.progress, request.cancelled
    if not meters:
        raise RadiometerError("no light meters to measure: add one with Add > Light Meter")
    results = []
    steps = plan_steps(meters)
    tracker = StepProgress(steps, None if progress is None else
                           (lambda f, eta: _call(progress, int(round(1000 * f)), 1000, eta)))
    for i, step in enumerate(steps):
        if cancelled is not None and cancelled():
            raise MeasurementCancelled("measurement cancelled; the scene was restored")
        tracker.start(i)
        results += run_step(request.but(progress=tracker), step, method=method)
        tracker(1, 1)
    return results

"""Convergence study (host side): error and wall time of rendered readings at increasing fixed
sample counts, the fits of log error vs log samples and vs log seconds (``radiometry.sampling.convergence``),
their inversion for a target error, and one error-targeted reading through the meter's per-meter
allocation to compare with the inversion.

The fixed-budget rows use ``meter.render_irradiance`` with controlled sample counts (the study
needs them); the targeted reading uses ``meter.measure_illuminance``. Units: seconds, samples per
reading, errors as fractions; points in scene coordinates.
"""

import dataclasses
import time

import bpy
import numpy as np

from ... import quality as quality_presets
from ...errors import RadiometerError
from ...radiometry.sampling import convergence as conv_math
from ...radiometry.metrics import grid as grid_math
from ...radiometry.sampling import stats
from . import analysis_common as common
from ..meter import point_meter as meter
from .grid import plane_frame


@dataclasses.dataclass
class ConvergenceRow(common.ToDict):
    """One fixed sample count of the study."""

    samples_per_texel: int
    samples: int               #: samples per reading (texels^2 x samples per texel)
    seconds: float             #: wall time of one reading of the target alone, s
    rms_error: float           #: RMS relative error against the reference (fraction)
    std_error: float           #: mean stated relative standard error (fraction)


@dataclasses.dataclass
class TargetedReading(common.ToDict):
    """One reading of the target through the meter's error-targeted, per-meter allocation."""

    target_rel_error: float    #: the 1-sigma relative error asked (fraction; None with a time budget only)
    time_budget_s: float       #: s, or None
    samples: float             #: mean samples per meter the allocator spent
    seconds: float             #: wall time of one reading of the target alone, s
    rel_std_error: float       #: largest stated relative standard error reached (fraction)
    rms_error: float           #: RMS relative error of the replicas against the reference (fraction)
    reached: bool              #: every stated error is within the target


@dataclasses.dataclass
class ConvergenceResult(common.ToDict):
    """Error vs samples and vs wall time of rendered readings of one target."""

    target: str
    reference_kind: str        #: "analytic (exact)" or "render, N samples per texel"
    reference: list            #: reference irradiance per point, W/m^2
    rows: list
    fit: dict                  #: convergence.ConvergenceFit.to_dict(): slope (vs samples), time_slope (vs s)
    target_error: float        #: fraction
    samples_for_target: float  #: samples per reading, from the fit of log error vs log samples
    seconds_for_target: float  #: s for one reading of the target alone: t0 + c N(target), both fitted on
    #:                            the rows' timings of the target alone
    notes: list
    plot: str = ""
    time_slope: float = float("nan")     #: exponent of error vs wall time (ideal -0.5 once t0 is small)
    time_slope_se: float = float("nan")
    seconds_for_target_by_time_fit: float = float("nan")  #: s, from the fit of log error vs log seconds
    bounces: int = 0           #: light bounces of every render of the study
    targeted: TargetedReading = None  #: the meter's own error-targeted reading (None when not run)


def convergence_study(target=None, *, request, location=None, normal=(0.0, 0.0, 1.0),
                      samples=(4, 16, 64, 256), texels=4, replicas=8, reference_samples=None, target_error=0.01,
                      bounces=None, targeted=True, plot=None, meter_kind=None):
    """Error and time of rendered readings at increasing samples per texel; fit and invert.

    ``target``: an illuminance meter object (or its name), a plane object (coarse 4 x 4 grid), or
    None with ``location``/``normal`` (scene coordinates); ``meter_kind``: the target's meter kind when
    it is a meter object (the caller reads it from the object's Radiometer properties), else None. For a meter the point is measured as
    ``replicas`` independent copies in one bake, so the RMS error against the reference is an
    honest estimate; a separate bake of the target alone gives the time. Reference: the analytic
    value when it is exact for this scene, else a render with ``reference_samples`` per texel
    (default 16 x the largest count). Every render uses ``bounces`` light bounces (default: the
    quality preset's, as the meter uses).

    Error against wall time: each row's ``seconds`` is a bake of the target alone; the fits of
    log error vs log samples and vs log seconds are both reported, and ``seconds_for_target`` is
    t0 + c N(target) from those timings. ``targeted`` (default True): also measure the target once
    through ``meter.measure_illuminance`` (method "render", the meter's per-meter allocation) at
    ``target_rel_error`` (fraction; default the ``quality`` preset's target when ``quality`` is
    given, else ``target_error``) and/or ``time_budget_s`` (s), and report its samples, seconds
    and error (:class:`TargetedReading`). ``target_rel_error`` also sets ``target_error``.
    The request (``measure.blender.request``) gives the scene, ``quality`` (None: not given),
    ``target_rel_error``, ``time_budget_s``, the seed and cancel.
    Returns :class:`ConvergenceResult`.
    """
    scene, seed = request.scene, request.seed
    quality, target_rel_error = request.quality, request.target_rel_error
    if target_rel_error is not None:
        target_error = float(target_rel_error)
    if not (0 < float(target_error) < 1):
        raise RadiometerError(f"target_error must be in (0, 1), got {target_error}")
    preset = quality_presets.preset(quality or "standard")
    bounces = int(preset["bounces"] if bounces is None else bounces)
    points, normals, label = _convergence_points(target, scene, location, normal, meter_kind)
    samples = sorted({int(s) for s in samples})
    if len(samples) < 2 or samples[0] < 1:
        raise RadiometerError("samples must hold at least 2 different counts >= 1")
    weights, view_layer, scale = request.weights, request.view_layer, request.scale_length
    notes = []
    model = meter.capture_model(scene, view_layer)
    meter_points = points  # where the meter is; the study's own bakes use the raised sensors below
    points, _eps = meter.sensor_points(points, normals, scale, model)
    decision = meter.plan(scene, model, points * scale, normals, "render")
    if decision["analytic_exact"]:
        per_light, _bounds, _info = meter.analytic_irradiance(model, decision["direct"], points * scale, normals)
        world, _world_bound, _note = meter.world_irradiance(model, decision["direct"], normals)  # the sky counts too
        reference = (per_light.sum(axis=0) + world) @ weights
        kind = "analytic (exact)"
    else:
        n_ref = int(reference_samples or 16 * samples[-1])
        est, _info, _rec = meter.render_irradiance(
            request.but(seed=seed + 10_000, progress=None), points, normals,
            {"samples": n_ref, "texels": texels, "bakes": 1, "bounces": bounces}, needs=decision["needs"])
        reference = est.mean(axis=0) @ weights
        kind = f"render, {n_ref} samples per texel x {texels * texels} texels"
        notes.append(f"reference noise ~ 1/sqrt({n_ref // samples[-1]}) of the last level's error")
    if np.any(reference <= 0):
        raise RadiometerError("the reference irradiance is 0 at the target: no light reaches it")
    single = len(points) == 1
    rep_points = np.repeat(points, replicas, axis=0) if single else points
    rep_normals = np.repeat(normals, replicas, axis=0) if single else normals
    rows = []
    for k, n in enumerate(samples):
        preset = {"samples": n, "texels": texels, "bakes": 1, "bounces": bounces}
        est, _info, _rec = meter.render_irradiance(request.but(seed=seed + 100 * k, progress=None), rep_points,
                                                   rep_normals, preset, needs=decision["needs"])
        scalar = est @ weights                              # (batches, M)
        mean, se = stats.batch_mean(scalar, axis=0)
        ref = np.repeat(reference, replicas) if single else reference
        rms = float(conv_math.rms_relative_error(mean, ref))
        t0 = time.perf_counter()
        meter.render_irradiance(request.but(seed=seed + 100 * k + 50, progress=None), points, normals, preset,
                                needs=decision["needs"])
        seconds = time.perf_counter() - t0
        rows.append(ConvergenceRow(n, n * texels * texels, seconds, rms, float(np.mean(se / np.abs(mean)))))
    errors = np.array([r.rms_error for r in rows])
    if np.any(errors <= 0):
        raise RadiometerError("an error of exactly 0 was measured (noise-free light such as a point or sun): "
                              "nothing to converge; use a scene with area lights or surfaces")
    fit = conv_math.fit_convergence([r.samples for r in rows], [r.seconds for r in rows], errors)
    notes.append(f"{bounces} light bounces in every render; seconds are bakes of the target alone (scene sync "
                 f"included: t0 = {fit.t0_s:.3g} s, {1e6 * fit.c_s_per_sample:.3g} us per sample)")
    if not 0.0 < fit.prefactor < float("inf"):
        notes.append("the sample counts barely varied: the fit of error against samples cannot be extrapolated")
    if not 0.0 < fit.time_prefactor < float("inf"):
        notes.append(f"the wall times barely varied ({min(r.seconds for r in rows):.3g}-"
                     f"{max(r.seconds for r in rows):.3g} s): the fit of error against time cannot be extrapolated")
    goal = None
    if targeted:
        goal = _targeted_reading(request.but(
            progress=None, samples=None, quality=quality or "standard",
            target_rel_error=target_error if target_rel_error is None and quality is None else target_rel_error),
            meter_points, normals, reference, replicas)
    result = ConvergenceResult(
        target=label, reference_kind=kind, reference=reference.tolist(), rows=rows, fit=fit.to_dict(),
        target_error=float(target_error), samples_for_target=fit.samples_for(target_error),
        seconds_for_target=fit.seconds_for(target_error), notes=notes, time_slope=fit.time_slope,
        time_slope_se=fit.time_slope_se, seconds_for_target_by_time_fit=fit.seconds_for_by_time(target_error),
        bounces=bounces, targeted=goal)
    if plot and common.can_plot(result.notes):
        write_convergence_plot(result, plot)
    return result


def _targeted_reading(request, sensors, normals, reference, replicas):
    """The meter's error-targeted reading of the target: replicas for its error, the target alone for
    its time. ``sensors``: the meter positions (scene coordinates; the meter raises them off surfaces)."""
    single = len(sensors) == 1
    if single and replicas > 1:
        copies = common.measure(request.but(seed=request.seed + 20_000), np.repeat(sensors, replicas, axis=0),
                                np.repeat(normals, replicas, axis=0), method="render")
        ref = np.repeat(reference, replicas)
    else:
        copies, ref = None, reference
    t0 = time.perf_counter()
    alone = common.measure(request.but(seed=request.seed + 30_000), sensors, normals, method="render")
    seconds = time.perf_counter() - t0
    copies = copies or alone
    values = np.array([r.irradiance for r in copies])
    stated = common.rel_errors(alone)
    asked = alone[0].target_rel_error
    return TargetedReading(
        target_rel_error=asked, time_budget_s=request.time_budget_s,
        samples=float(np.mean([r.samples for r in alone])), seconds=seconds, rel_std_error=float(np.max(stated)),
        rms_error=float(conv_math.rms_relative_error(values, ref)),
        reached=bool(asked is None or np.all(stated <= asked * (1 + 1e-9))))


def _convergence_points(target, scene, location, normal, meter_kind=None):
    if target is None:
        if location is None:
            raise RadiometerError("give a meter, a plane or a location for the convergence study")
        pts, _ = meter.as_points(location)
        return pts, meter.as_directions(normal, len(pts)), f"point {tuple(np.round(pts[0], 4))}"
    obj = scene.objects.get(target) if isinstance(target, str) else target
    if obj is None:
        raise RadiometerError(f"no object named {target!r} in scene {scene.name!r}")
    if meter_kind is not None:
        if meter_kind != "ILLUMINANCE":
            raise RadiometerError(f"{obj.name!r} is a {meter_kind.lower()} meter: the study uses illuminance meters")
        mw = np.array(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).matrix_world, float)
        z = mw[:3, 2] / np.linalg.norm(mw[:3, 2])
        return mw[None, :3, 3], z[None, :], f"meter {obj.name}"
    if obj.type == "MESH":
        (x0, x1, y0, y1, zc), mw, n = plane_frame(obj, scene)
        local = grid_math.cell_centres((x0, x1), (y0, y1), 4, 4).reshape(-1, 2)
        p = np.c_[local, np.full(len(local), zc), np.ones(len(local))] @ mw.T
        return p[:, :3], np.tile(n, (len(p), 1)), f"grid 4 x 4 on {obj.name}"
    raise RadiometerError(f"{obj.name!r} is neither an illuminance meter nor a plane")


def write_convergence_plot(result, path):
    from ...plots.convergence import convergence_plot

    r = result.rows
    convergence_plot(path, [x.samples for x in r], [x.seconds for x in r], [x.rms_error for x in r],
                     [x.std_error for x in r], fit=result.fit, target=result.target_error,
                     title=f"Convergence: {result.target} (reference: {result.reference_kind}); "
                           f"{result.target_error:.2%} needs ~{result.samples_for_target:.3g} samples, "
                           f"{result.seconds_for_target:.3g} s")
    result.plot = path
    return path

"""Inverse-square and cosine-law checks of one light in a Blender scene (host side).

Each check measures the light alone (``light_isolation.isolated_light``: every other light and the
world off, surfaces kept) at all its distances or tilts in one batch, SPLIT into the light's OWN
direct light and what the scene adds (``light_isolation.measure_light_and_scene``). The law is
judged on the light's own direct light, where it is physics (a point light beyond its soft-falloff
zone, a sun's cosine law, an area light in its far field); the scene's share (interreflection:
total minus direct) and its shadows (direct below the light's closed form) are reported beside it
at every distance or tilt, and every cause says whether the light or the scene broke the law.
The maths is ``radiometry.metrics.laws``.

Units: distances in m, irradiance in W/m^2 (CIE Y weighted), illuminance in lux, angles in deg;
locations returned in scene coordinates (Blender units). Shares and deviations are fractions.
"""

import dataclasses
import math
import time
import typing

import numpy as np

from ...errors import RadiometerError
from ...radiometry.emitters import light_class
from ...radiometry.metrics import laws
from . import analysis_common as common
from .light_isolation import free_distance, light_object, light_spec, measure_light_and_scene, model_irradiance, scene_model, source_size

DEFAULT_ANGLES_DEG = (0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 75.0, 80.0, 85.0, 87.0, 89.0)
#: The check blames the scene's shadows where the direct light falls short of the light's closed
#: form by more than the tolerance plus this many standard errors.
SHADOW_Z = laws.DEFAULT_Z


# --- result objects -----------------------------------------------------------------------------

# Rows are NamedTuples: they unpack as the documented tuples (distance, measured, predicted, ...)
# and keep their attribute names; fields added later go at the end.
class InverseSquareRow(typing.NamedTuple):
    """One distance of a sweep. distance m; irradiances W/m^2; deviations and shares fractions."""

    distance: float            #: m from the light's centre along its axis
    measured: float            #: W/m^2 measured with the light alone: direct + what the scene reflects
    predicted: float           #: W/m^2, I/d^2 with I the far-field radiant intensity along the axis
    rel_deviation: float       #: (measured - predicted) / predicted (the total: light and scene)
    rel_std_error: float       #: relative standard error of ``measured`` (0 when exact)
    model: float               #: W/m^2, closed-form model of the light alone (no scene surfaces)
    model_deviation: float     #: (model - predicted) / predicted: what the light's own shape explains
    ok: bool                   #: the light's own direct light follows I/d^2 here (|direct_deviation| within
    #:                            tolerance + 3 s.e.); a row in the scene's shadow does not fail the light
    illuminance: float = 0.0   #: lux measured
    direct: float = 0.0        #: W/m^2, the light's own direct light (closed form where proven, else rendered
    #:                            at 0 bounces); the scene's shadows lower it below ``model``
    scene: float = 0.0         #: W/m^2, measured - direct: what the scene's surfaces add (interreflection)
    direct_deviation: float = 0.0  #: (direct - predicted) / predicted: the light's own deviation (judged)
    scene_share: float = 0.0   #: scene / measured: the fraction of the reading the scene adds
    shadowed: float = 0.0      #: 1 - direct / model: the fraction of the light's direct light the scene blocks
    direct_rel_std_error: float = 0.0  #: relative standard error of ``direct``
    total_ok: bool = True      #: the total (``measured``) also follows I/d^2 here

    to_dict = common.row_dict


@dataclasses.dataclass
class InverseSquareResult(common.ToDict):
    """Inverse-square check of one light. Lengths in m, intensities in W/sr (CIE Y weighted)."""

    light: str
    kind: str
    method: str                #: how the total was measured ("analytic", "hybrid" or "render")
    passed: bool               #: the light's own direct light follows the law at every unshadowed distance
    #:                            and its exponent is -2
    exponent: float            #: fitted d-exponent of the light's direct E over the far field (ideal -2)
    exponent_se: float
    near_field_limit: float    #: m, of the light's direct light; 0 when the law holds at every distance
    #:                            tried, inf if never reached
    far_field_passed: bool     #: the law holds beyond the near-field limit with exponent -2
    source_size: float         #: m, largest dimension of the luminous area (0 for a point)
    five_times: dict           #: laws.five_times_rule output
    intensity: float           #: W/sr along the axis
    axis: tuple                #: unit world direction of the sweep
    tolerance: float
    rows: list
    causes: list               #: named causes of deviations, each "light: ..." or "scene: ..."
    notes: list
    fit_from: float = 0.0      #: m, first distance used in the exponent fit
    seconds: float = 0.0
    plot: str = ""
    total_passed: bool = True  #: the total reading (light + scene) follows the law at every distance too
    broken_by: str = ""        #: "", "light", "scene" or "light and scene": who broke the law
    max_scene_share: float = 0.0  #: largest scene / measured over the sweep (fraction)
    direct_method: str = ""    #: how the direct light was obtained
    target_rel_error: float = None  #: the 1-sigma relative error asked of every reading (None: fixed samples)
    expected_departure: bool = False  #: the light departs from I/d² exactly as the closed form of its own
    #:                                   shape predicts (an extended source's near field, soft falloff): physics
    departure: str = ""        #: that departure in words ("" when the light follows the law or it is unexplained)
    efficacy: float = 0.0      #: lm/W of the scene: lux = efficacy x the W/m² above (0: no photometric meaning)
    description: str = ""      #: the light in words ("area light 0.6 x 0.6 m")


class CosineRow(typing.NamedTuple):
    """One tilt. angle deg; irradiances W/m^2; predicted cos(theta); ratios, deviations and shares fractions."""

    angle: float
    measured: float            #: W/m^2 with the light alone: direct + what the scene reflects
    predicted: float           #: cos(theta)
    ratio: float               #: E(theta) / E(0) of the total
    rel_deviation: float       #: ratio / cos(theta) - 1 of the total (light and scene)
    ratio_rel_se: float
    model_ratio: float         #: the closed-form model's E(theta)/E(0) (no scene surfaces)
    ok: bool                   #: the light's own direct light follows cos(theta) here (judged)
    direct: float = 0.0        #: W/m^2, the light's own direct light (closed form where proven, else 0 bounces)
    direct_ratio: float = 0.0  #: direct(theta) / direct(0)
    direct_deviation: float = 0.0  #: direct_ratio / cos(theta) - 1: the light's own deviation (judged)
    scene: float = 0.0         #: W/m^2, measured - direct: what the scene's surfaces add
    scene_share: float = 0.0   #: scene / measured
    total_ok: bool = True      #: the total's ratio also follows cos(theta) here

    to_dict = common.row_dict


@dataclasses.dataclass
class CosineResult(common.ToDict):
    """Cosine-law check of one light at one point (scene coordinates), angles in deg."""

    light: str
    kind: str
    method: str
    passed: bool               #: the light's own direct light follows cos(theta) at every tilt
    max_rel_deviation: float   #: max |direct(theta)/(direct(0) cos theta) - 1| (the light's own)
    max_at_deg: float
    onset_deg: float           #: smallest tilt at which the light's own deviation fails (nan when none)
    horizon_onset_deg: float   #: tilt at which the source starts to sink below the horizon
    source_angular_radius_deg: float
    location: tuple
    facing: tuple              #: unit normal at 0 deg (toward the light)
    tilt_toward: tuple         #: unit direction the normal tilts toward
    tolerance: float
    rows: list
    causes: list               #: each "light: ..." or "scene: ..."
    notes: list
    seconds: float = 0.0
    plot: str = ""
    total_passed: bool = True  #: the total reading (light + scene) follows cos(theta) too
    total_max_rel_deviation: float = 0.0  #: max |ratio / cos - 1| of the total
    broken_by: str = ""        #: "", "light", "scene" or "light and scene"
    max_scene_share: float = 0.0  #: largest scene / measured over the tilts (fraction)
    direct_method: str = ""
    target_rel_error: float = None
    expected_departure: bool = False  #: the light departs from cos θ exactly as its own shape's closed form
    #:                                   predicts (an extended source partly below the meter's horizon)
    departure: str = ""        #: that departure in words
    description: str = ""      #: the light in words


def _broken_by(light_broke, scene_broke):
    return " and ".join(who for who, broke in (("light", light_broke), ("scene", scene_broke)) if broke)


def _noise_cause(who):
    return f"{who}: deviation within noise of the tolerance: measure at a smaller target_rel_error"


def _interreflection_cause(split, where, total_dev, direct_dev, unit):
    """The scene's cause, told at the row ``where`` (index) where its part moves the reading most."""
    share = split.scene_share[where]
    return (f"scene: its surfaces reflect the light back onto the meter: {100 * share:.3g} % of the reading at "
            f"{unit} is interreflection ({split.scene[where]:.4g} W/m²); the total deviates by "
            f"{100 * total_dev:+.4g} %, the light's own direct light by {100 * direct_dev:+.3g} %")


# --- inverse square ------------------------------------------------------------------------------

def default_distances(spec, count=24):
    """From close to the source to far away: 0.6 to 60 source sizes (0.06 to 6 m for a point)."""
    base = source_size(spec) or 0.1
    return np.geomspace(0.6 * base, 60.0 * base, count)


def check_inverse_square(light, *, request, distances=None, method="auto", tolerance=laws.DEFAULT_TOLERANCE,
                         exponent_tolerance=0.01, plot=None, points=24):
    """Sweep a meter facing ``light`` along its axis and compare the light's direct E with I/d^2.

    ``distances`` in m from the light's centre (default :func:`default_distances` with ``points``
    distances, shortened to the free space in front of the light). The request
    (``measure.blender.request``) gives the scene and the budget: ``quality`` / ``target_rel_error``
    (fraction) / ``samples`` (per meter) / ``time_budget_s`` (s, per measurement) as in
    ``meter.measure_illuminance``, the seed, progress and cancel. Returns :class:`InverseSquareResult`.
    """
    scene = request.scene
    obj = light_object(light, scene)
    model = scene_model(scene)  # one capture for the whole check (issue 17)
    spec = light_spec(obj, scene, model)
    if not spec.has_position:
        raise RadiometerError(f"light {obj.name!r} is a sun: it has no position, so the inverse-square law does "
                              "not apply (its irradiance does not change with distance); check its cosine law")
    weights, efficacy, scale = request.weights, request.efficacy, request.scale_length
    axis = np.asarray(spec.emission_direction, float)
    intensity = float(np.asarray(spec.intensity_towards(axis)) @ weights)
    if intensity <= 0:
        raise RadiometerError(f"light {obj.name!r} sends no light along its axis (intensity 0): nothing to check")
    notes, causes = [], []
    free = free_distance(scene, spec.position, axis, model)  # m
    if distances is None:
        points = int(points)
        if points < 4:
            raise RadiometerError(f"points must be at least 4 distances, got {points}")
        d = default_distances(spec, points)
        if math.isfinite(free) and d[-1] > 0.95 * free:
            d = d[d < 0.95 * free]
            if d.size < 4:
                d = np.geomspace(min(0.6 * (source_size(spec) or 0.1), 0.3 * free), 0.95 * free, min(12, points))
            notes.append(f"sweep shortened to the free space in front of the light: a surface {free:.3g} m away")
    else:
        d = np.sort(np.asarray(distances, float).ravel())
        if d.size < 2 or not np.all(np.isfinite(d)) or np.any(d <= 0):
            raise RadiometerError("distances must be at least 2 finite values > 0 (m)")
    if spec.interior_radius_m > 0 and d[0] <= spec.interior_radius_m:
        raise RadiometerError(f"distance {d[0]:.3g} m is inside light {obj.name!r}'s sphere (radius "
                              f"{spec.interior_radius_m:.3g} m): start the sweep outside it")
    points_m = spec.position + d[:, None] * axis
    normals = np.tile(-axis, (d.size, 1))
    started = time.perf_counter()
    split = measure_light_and_scene(request, obj, points_m / scale, normals, method=method, model=model)
    seconds = time.perf_counter() - started
    measured, se, direct, dse = split.total, split.total_se, split.direct, split.direct_se
    predicted = intensity / d**2
    model = model_irradiance(spec, points_m, normals, weights)
    dev = laws.relative_deviation(measured, predicted)
    direct_dev = laws.relative_deviation(direct, predicted)
    model_dev = laws.relative_deviation(model, predicted)
    shadowed = np.where(model > 0, 1.0 - direct / np.where(model > 0, model, 1.0), 0.0)
    in_shadow = shadowed > tolerance + SHADOW_Z * dse
    ok = laws.within_tolerance(direct_dev, dse, tolerance)
    total_ok = laws.within_tolerance(dev, se, tolerance)
    judged = ~in_shadow
    limit = laws.near_field_limit(d[judged], direct_dev[judged], dse[judged], tolerance) if judged.any() \
        else float("inf")
    size = source_size(spec)
    rule = laws.five_times_rule(size, limit)
    # Exponent of the light's direct E over the far field: beyond the near-field limit when >= 3
    # unshadowed points remain there, else the farthest third of the sweep (far field not reached).
    lit = (direct > 0) & judged
    far = (d >= limit) & lit if math.isfinite(limit) else np.zeros_like(lit)
    if far.sum() < 3:
        far = np.zeros_like(lit)
        far[-max(3, d.size // 3):] = True
        far &= lit
    if far.sum() >= 2:
        fit = laws.fit_power_law(d[far], direct[far], dse[far])
        exponent, exponent_se, fit_from = fit.exponent, fit.exponent_se, float(d[far][0])
    else:
        exponent, exponent_se, fit_from = float("nan"), float("nan"), float("nan")
    exponent_ok = bool(abs(exponent + 2.0) <= exponent_tolerance + 3 * exponent_se) if math.isfinite(exponent) else False
    passed = bool((ok | in_shadow).all() and judged.any() and exponent_ok)
    far_passed = bool(math.isfinite(limit) and exponent_ok)
    total_passed = bool(total_ok.all())
    # The scene broke the law where its own part (interreflection) alone moves the reading off
    # I/d^2 by more than the tolerance, or where it shadows the light.
    scene_dev = split.scene / predicted
    by_scene = np.abs(scene_dev) > tolerance + 3 * split.scene_abs_se / predicted
    scene_broke = bool(in_shadow.any() or (by_scene & ~total_ok).any())
    notes.append(f"total measured by {split.method}" + (" (closed form, exact: nothing in the scene reflects or "
                                                        "blocks the light)" if split.exact else ""))
    if not split.exact:
        notes.append(f"the light's direct light by {split.direct_method}; the scene's part is total − direct")
    notes.append("other lights and the world switched off during the check"
                 + (f" ({len(split.lights_off)} light objects: {', '.join(split.lights_off[:4])}"
                    f"{', ...' if len(split.lights_off) > 4 else ''})" if split.lights_off else ""))
    if not passed:
        causes += _light_causes_inverse_square(spec, d, model_dev, direct_dev, dse, ok | in_shadow, tolerance)
    if scene_broke:
        causes += _scene_causes_inverse_square(split, d, dev, direct_dev, in_shadow, shadowed, by_scene & ~total_ok,
                                               scene_dev)
    if not passed and math.isfinite(free) and free < 5 * max(size, 0.01) and not in_shadow.any():
        causes.append(f"scene: a surface {free:.3g} m in front of the light leaves no room for the far field")
    expected, departure = _expected_inverse_square(spec, d, direct, dse, model, model_dev, ok, judged, limit,
                                                   far_passed, passed, tolerance)
    share = split.scene_share
    rows = [InverseSquareRow(float(d[k]), float(measured[k]), float(predicted[k]), float(dev[k]), float(se[k]),
                             float(model[k]), float(model_dev[k]), bool(ok[k] or in_shadow[k]),
                             float(efficacy * measured[k]), float(direct[k]), float(split.scene[k]),
                             float(direct_dev[k]), float(share[k]), float(shadowed[k]), float(dse[k]),
                             bool(total_ok[k]))
            for k in range(d.size)]
    result = InverseSquareResult(
        light=obj.name, kind=spec.kind, method=split.method, passed=passed, exponent=float(exponent),
        exponent_se=float(exponent_se), near_field_limit=float(limit), far_field_passed=far_passed,
        source_size=size, five_times=rule, intensity=intensity, axis=tuple(axis.tolist()), tolerance=tolerance,
        rows=rows, causes=causes, notes=notes, fit_from=fit_from, seconds=seconds, total_passed=total_passed,
        broken_by=_broken_by(not passed, scene_broke), max_scene_share=float(np.max(share)),
        direct_method=split.direct_method, target_rel_error=split.readings[0].target_rel_error,
        expected_departure=expected, departure=departure, efficacy=float(efficacy), description=describe_light(spec))
    if plot and common.can_plot(result.notes):
        write_inverse_square_plot(result, plot)
    return result


def describe_light(spec):
    """The light in a designer's words: 'area light 0.6 x 0.6 m', 'point light, radius 0.1 m (soft falloff)'."""
    return light_class(spec).describe(spec)


def _explained(direct, direct_se, model, tolerance):
    """Where the light's direct light equals the closed form of its own shape (within tolerance + 3 s.e.)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return (model > 0) & (np.abs(direct / np.where(model > 0, model, 1.0) - 1.0) <= tolerance + 3 * direct_se)


def _expected_inverse_square(spec, d, direct, dse, model, model_dev, ok, judged, limit, far_passed, passed,
                             tolerance):
    """(expected, words): does the light depart from I/d² only where, and as, its own shape's closed form
    says it must? Then the departure is physics (the near field), not a fault of the light or the meter."""
    fail = ~ok & judged
    if passed or not fail.any():
        return False, ""
    shape = _explained(direct, dse, model, tolerance) & (np.abs(model_dev) > tolerance)
    if not shape[fail].all() or not (far_passed or not math.isfinite(limit)):
        return False, ""
    k = int(np.flatnonzero(fail)[np.argmax(np.abs(model_dev[fail]))])
    what = light_class(spec).near_field_words(spec)
    where = (f"within {limit:.2g} m" if math.isfinite(limit)
             else f"at every distance checked (to {d[-1]:.2g} m: the far field lies farther)")
    return True, (f"near field {where}: {what}; its closed form predicts the departure measured "
                  f"({100 * model_dev[k]:+.3g} % at {d[k]:.2g} m)")


def _light_causes_inverse_square(spec, d, model_dev, direct_dev, dse, judged_ok, tolerance):
    """Why the light's OWN direct light departs from I/d^2 (its shape, falloff, spread)."""
    causes = []
    own = np.abs(model_dev) > tolerance
    if own.any():
        causes += spec.inverse_square_causes(d)
    if not causes:
        bad = ~judged_ok
        if bad.any() and (np.abs(direct_dev[bad]) > tolerance + 3 * dse[bad]).any():
            k = int(np.flatnonzero(bad)[np.argmax(np.abs(direct_dev[bad]))])
            causes.append(f"light: its direct light deviates by {100 * direct_dev[k]:+.3g} % from I/d² at "
                          f"{d[k]:.3g} m, and its closed form does not explain it")
        else:
            causes.append(_noise_cause("light"))
    return causes


def _scene_causes_inverse_square(split, d, dev, direct_dev, in_shadow, shadowed, reflected, scene_dev):
    """What the SCENE does to the light: shadows on the direct light (``in_shadow``), interreflection
    that breaks the law on the total (``reflected``)."""
    causes = []
    if in_shadow.any():
        k = int(np.flatnonzero(in_shadow)[0])
        causes.append(f"scene: occluders block the light's direct path from {d[k]:.3g} m on "
                      f"({100 * float(np.max(shadowed[in_shadow])):.3g} % of its direct light blocked at most)")
    if reflected.any():
        k = int(np.flatnonzero(reflected)[np.argmax(np.abs(scene_dev[reflected]))])
        causes.append(_interreflection_cause(split, k, dev[k], direct_dev[k], f"{d[k]:.3g} m"))
    return causes


def _room_words(share):
    return f"the room's interreflection adds up to {100 * share:.2g} % (not drawn)" if share > 0.0005 else \
        "nothing from the room"


def write_inverse_square_plot(result, path):
    """The check's PNG: in lux when the scene has a luminous efficacy, else W/m²."""
    from ...plots.laws import inverse_square_plot

    r = result.rows
    k, unit = (result.efficacy, "lx") if result.efficacy > 0 else (1.0, "W/m²")
    limit = result.near_field_limit
    if limit == 0:
        field = "follows I/d² at every distance checked"
    elif math.isfinite(limit):
        field = f"near field to {limit:.2g} m, then I/d²"
    else:
        field = f"near field at every distance checked (to {r[-1].distance:.2g} m)"
    if not math.isfinite(result.exponent):
        exponent = "no exponent fitted"
    elif result.exponent_se < 5e-7:  # a fit through closed-form values: its error is rounding noise
        exponent = f"exponent {result.exponent:.3f} (point: −2)"
    else:
        exponent = f"exponent {result.exponent:.3f} ± {result.exponent_se:.1g} (point: −2)"
    how = "closed form" if result.direct_method == "analytic" else result.direct_method
    inverse_square_plot(path, [x.distance for x in r], [k * x.direct for x in r], [k * x.predicted for x in r],
                        [x.direct_rel_std_error for x in r], near_field_limit=limit,
                        rule_distance=result.five_times["rule_distance"] or None, tolerance=result.tolerance,
                        unit=unit, model=[k * x.model for x in r],
                        model_label=f"closed form of this {result.description or 'light'} (no room)",
                        title=f"Inverse-square law: {result.light}, {result.description or result.kind.lower()}\n"
                              f"{field}\n{exponent}; direct light by {how}\n{_room_words(result.max_scene_share)}")
    result.plot = path
    return path


# --- cosine law ----------------------------------------------------------------------------------

def default_location(spec, request, model=None):
    """Scene coordinates: 2 source sizes (at least 1 m) in front of the light, but no farther than
    half-way to the first surface on its axis; the origin for a sun."""
    if not spec.has_position:
        return np.zeros(3)
    scene, scale = request.scene, request.scale_length
    axis = np.asarray(spec.emission_direction, float)
    d = max(1.0, 2.0 * source_size(spec))
    free = free_distance(scene, spec.position, axis, model)
    if math.isfinite(free):
        d = min(d, 0.5 * free)
    return (np.asarray(spec.position) + d * axis) / scale


def angular_radius(spec, point_m, facing):
    """Largest angle (rad) between ``facing`` and a direction to a point of the source."""
    return spec.angular_radius(point_m, facing)


def _tilted_normals(spec, point_m, angles, name):
    """(facing, tilt direction, normals (n, 3)): from facing the light toward one of its axes."""
    facing = spec.towards_centre(point_m)  # a sun: the unit vector towards it
    if spec.has_position:
        dist = np.linalg.norm(facing)
        if dist < 1e-9:
            raise RadiometerError(f"the location is at light {name!r}'s centre: move it away from the light")
        facing = facing / dist
    helper = np.asarray(spec.axes)[:, 0]
    toward = helper - (helper @ facing) * facing
    if np.linalg.norm(toward) < 1e-6:
        helper = np.asarray(spec.axes)[:, 1]
        toward = helper - (helper @ facing) * facing
    toward /= np.linalg.norm(toward)
    th = np.radians(angles)
    return facing, toward, np.cos(th)[:, None] * facing + np.sin(th)[:, None] * toward


def check_cosine_law(light, *, request, location=None, angles_deg=None, method="auto",
                     tolerance=laws.DEFAULT_TOLERANCE, plot=None):
    """Tilt a meter at ``location`` (scene coordinates) from facing ``light`` to 89 deg.

    Compares the light's own direct E(theta)/E(0) with cos(theta) and reports the total's and the
    scene's share beside it. The request as in :func:`check_inverse_square`. Returns
    :class:`CosineResult`.
    """
    scene = request.scene
    obj = light_object(light, scene)
    model = scene_model(scene)  # one capture for the whole check (issue 17)
    spec = light_spec(obj, scene, model)
    weights, scale = request.weights, request.scale_length
    loc = default_location(spec, request, model) if location is None else np.asarray(location, float)
    if loc.shape != (3,) or not np.all(np.isfinite(loc)):
        raise RadiometerError(f"location must be 3 finite numbers (scene coordinates), got {location!r}")
    angles = np.asarray(DEFAULT_ANGLES_DEG if angles_deg is None else angles_deg, float).ravel()
    if angles.size < 2 or not np.all(np.isfinite(angles)) or np.any((angles < 0) | (angles >= 90)):
        raise RadiometerError("angles_deg must be at least 2 tilts in [0, 90) deg")
    if not np.any(angles == 0):
        angles = np.concatenate([[0.0], angles])
    angles = np.unique(angles)
    point_m = loc * scale
    facing, toward, normals = _tilted_normals(spec, point_m, angles, obj.name)
    points = np.tile(loc, (angles.size, 1))
    started = time.perf_counter()
    split = measure_light_and_scene(request, obj, points, normals, method=method, model=model)
    seconds = time.perf_counter() - started
    where = tuple(np.round(loc, 4))
    if not split.direct[0] > 0:
        raise RadiometerError(f"cosine law at {where}: the light's direct light does not reach the meter facing it "
                              "(E(0) = 0: a surface shadows it, or the point is inside an object): pick a location "
                              "in the light's view")
    try:
        total = laws.cosine_law_analysis(angles, split.total, split.total_se, tolerance)
        own = laws.cosine_law_analysis(angles, split.direct, split.direct_se, tolerance)
    except ValueError as exc:
        raise RadiometerError(f"cosine law at {where}: {exc}") from None
    model = model_irradiance(spec, np.tile(point_m, (angles.size, 1)), normals, weights)
    model_ratio = model / model[0] if model[0] > 0 else np.full(angles.size, np.nan)
    alpha = angular_radius(spec, point_m, facing)
    horizon = float(laws.horizon_onset_deg(alpha))
    causes = []
    if not own["passed"]:
        causes += _light_causes_cosine(spec, angles, own, model_ratio, alpha, horizon, tolerance)
    # The scene broke the law where its part alone moves E(theta)/E(0) off cos(theta) by more
    # than the tolerance (the total's and the direct's deviations differ by that much).
    scene_dev = total["rel_deviation"] - own["rel_deviation"]
    by_scene = ~total["ok"] & (np.abs(scene_dev) > tolerance + 3 * np.hypot(total["ratio_rel_se"],
                                                                              own["ratio_rel_se"]))
    if by_scene.any():
        k = int(np.flatnonzero(by_scene)[np.argmax(np.abs(scene_dev[by_scene]))])
        causes.append(_interreflection_cause(split, k, total["rel_deviation"][k], own["rel_deviation"][k],
                                             f"{angles[k]:g} deg"))
    scene_broke = bool(by_scene.any() or any(c.startswith("scene:") for c in causes))
    expected, departure = _expected_cosine(spec, angles, own, model_ratio, horizon, tolerance)
    share = split.scene_share
    rows = [CosineRow(float(angles[k]), float(split.total[k]), float(total["predicted"][k]),
                      float(total["ratio"][k]), float(total["rel_deviation"][k]), float(total["ratio_rel_se"][k]),
                      float(model_ratio[k]), bool(own["ok"][k]), float(split.direct[k]), float(own["ratio"][k]),
                      float(own["rel_deviation"][k]), float(split.scene[k]), float(share[k]), bool(total["ok"][k]))
            for k in range(angles.size)]
    notes = [f"total measured by {split.method}"
             + ("" if split.exact else f"; the light's direct light by {split.direct_method}"),
             "other lights and the world switched off during the check",
             f"meter tilts from facing the light toward {tuple(np.round(toward, 4))}"]
    result = CosineResult(
        light=obj.name, kind=spec.kind, method=split.method, passed=own["passed"],
        max_rel_deviation=own["max_rel_deviation"], max_at_deg=own["max_at_deg"], onset_deg=own["onset_deg"],
        horizon_onset_deg=horizon, source_angular_radius_deg=math.degrees(alpha), location=tuple(loc.tolist()),
        facing=tuple(facing.tolist()), tilt_toward=tuple(toward.tolist()), tolerance=tolerance, rows=rows,
        causes=causes, notes=notes, seconds=seconds, total_passed=total["passed"],
        total_max_rel_deviation=total["max_rel_deviation"],
        broken_by=_broken_by(not own["passed"], scene_broke), max_scene_share=float(np.max(share)),
        direct_method=split.direct_method, target_rel_error=split.readings[0].target_rel_error,
        expected_departure=expected, departure=departure, description=describe_light(spec))
    if plot and common.can_plot(result.notes):
        write_cosine_plot(result, plot)
    return result


def _expected_cosine(spec, angles, own, model_ratio, horizon, tolerance):
    """(expected, words): does the light depart from cos θ only as its own shape's closed form predicts
    (an extended source partly below the meter's horizon at large tilts)?"""
    fail = ~own["ok"]
    if own["passed"] or not fail.any() or not np.all(np.isfinite(model_ratio)):
        return False, ""
    cos = np.cos(np.radians(angles))
    shape = _explained(own["ratio"], own["ratio_rel_se"], model_ratio, tolerance) & (np.abs(model_ratio / cos - 1) > tolerance)
    if not shape[fail].all():
        return False, ""
    k = int(np.flatnonzero(fail)[np.argmax(np.abs(own["rel_deviation"][fail]))])
    if angles[fail].min() >= horizon - 1e-9 - (angles[1] - angles[0] if angles.size > 1 else 0):
        why = (f"from {horizon:.3g}° on part of the source ({describe_light(spec)}) is below the meter's horizon, "
               "so E falls slower than cos θ")
    else:
        why = f"the source ({describe_light(spec)}) is not a point seen from here"
    return True, (f"extended source: {why}; its closed form predicts the departure measured "
                  f"({100 * own['rel_deviation'][k]:+.3g} % of a small E at {angles[k]:g}°)")


def _light_causes_cosine(spec, angles, own, model_ratio, alpha, horizon, tolerance):
    """Why the light's OWN direct light departs from cos(theta) (its extent, its spread, shadows)."""
    causes = []
    onset = own["onset_deg"]
    step = angles[1] - angles[0] if angles.size > 1 else 0
    if alpha > 0 and onset >= horizon - 1e-9 - step:
        causes.append(f"light: the extended source sinks below the meter's horizon from {horizon:.3g} deg on (it "
                      f"spans {math.degrees(alpha):.3g} deg from its centre as seen from here), so E falls slower "
                      "than cos θ")
    causes += spec.cosine_causes()
    shade = laws.relative_deviation(own["ratio"], model_ratio)
    if np.any(np.abs(shade) > tolerance + 3 * own["ratio_rel_se"]):
        causes.append("scene: occluders hide part of the light, differently at different tilts")
    if not causes:
        causes.append(_noise_cause("light"))
    return causes


def write_cosine_plot(result, path):
    """The check's PNG (ratios: no unit)."""
    from ...plots.laws import cosine_plot

    r = result.rows
    how = "closed form" if result.direct_method == "analytic" else result.direct_method
    at = tuple(round(v, 2) for v in result.location)
    if result.passed:
        verdict = f"follows cos θ to {r[-1].angle:g}° (largest departure {100 * result.max_rel_deviation:.2g} %)"
    elif result.expected_departure:
        verdict = (f"follows cos θ to {result.horizon_onset_deg:.3g}°\nbeyond, part of the source is below the "
                   "meter's horizon, as its shape predicts")
    else:
        verdict = f"departs by {100 * result.max_rel_deviation:.3g} % at {result.max_at_deg:g}° (see causes)"
    cosine_plot(path, [x.angle for x in r], [x.direct_ratio for x in r], [x.ratio_rel_se for x in r],
                tolerance=result.tolerance, model_ratio=[x.model_ratio for x in r],
                horizon_deg=result.horizon_onset_deg if result.horizon_onset_deg < 90 - 1e-6 else None,
                model_label=f"closed form of this {result.description or 'light'} (no room)",
                title=f"Cosine law: {result.light}, {result.description or result.kind.lower()}\nmeter at {at} m; "
                      f"{verdict}\ndirect light by {how}; {_room_words(result.max_scene_share)}")
    result.plot = path
    return path

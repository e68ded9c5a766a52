"""Law checks, illuminance grids and convergence studies on a Blender scene (host side).

Every check measures through ``meter.measure_illuminance`` with ONE batch (one scene sync, one
bake when rendering) for all its distances, tilts or grid points, and compares with the pure maths
in ``radiometry.laws``/``grid``/``convergence``. Law checks isolate the light under test: the
other lights are switched off in renders and the world is removed for the duration (inside
``scene_guard.preserved_scene``, so the user's scene comes back unchanged); surfaces stay, so
occluders and reflections show up as deviations and are named.

Units: distances in m, irradiance in W/m^2 (CIE Y weighted), illuminance in lux, angles in deg;
locations returned in scene coordinates (Blender units).
"""

import contextlib
import csv
import dataclasses
import math
import time
import typing

import bpy
import numpy as np

from .. import plots as _plots
from ..errors import RadiometerError
from ..radiometry import convergence as conv_math
from ..radiometry import grid as grid_math
from ..radiometry import laws
from . import meter, render_settings, scene_guard, scene_lights


def _can_plot(notes):
    """True if matplotlib is installed; else add the reason to ``notes`` (the numbers need no plot)."""
    if _plots.matplotlib_available():
        return True
    notes.append("no plot written: " + _plots.missing_message())
    return False


DEFAULT_ANGLES_DEG = (0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 75.0, 80.0, 85.0, 87.0, 89.0)
#: Lift of the viewport-only isolux copy above its plane (scene units), so it is not hidden in it.
DISPLAY_OFFSET = 1e-4


# --- result objects -----------------------------------------------------------------------------

def _plain(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None  # JSON has no inf/nan
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if dataclasses.is_dataclass(value) or hasattr(value, "_asdict"):
        return value.to_dict()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


class _ToDict:
    def to_dict(self):
        """JSON-safe dict (numpy arrays as lists, inf/nan as None)."""
        return {f.name: _plain(getattr(self, f.name)) for f in dataclasses.fields(self)}


def _row_dict(row):
    """JSON-safe dict of a NamedTuple row (inf/nan as None)."""
    return {k: _plain(v) for k, v in row._asdict().items()}


# Rows are NamedTuples: they unpack as the documented tuples (distance, measured, predicted, ...)
# and keep their attribute names.
class InverseSquareRow(typing.NamedTuple):
    """One distance of a sweep. distance m; measured, predicted, model W/m^2; deviations fractions."""

    distance: float            #: m from the light's centre along its axis
    measured: float            #: W/m^2 measured (CIE Y weighted irradiance)
    predicted: float           #: W/m^2, I/d^2 with I the far-field radiant intensity along the axis
    rel_deviation: float       #: (measured - predicted) / predicted
    rel_std_error: float       #: relative standard error of ``measured`` (0 when exact)
    model: float               #: W/m^2, closed-form model of the light alone (no scene surfaces)
    model_deviation: float     #: (model - predicted) / predicted: what the light's own shape explains
    ok: bool                   #: |rel_deviation| <= tolerance + z * rel_std_error
    illuminance: float = 0.0   #: lux measured

    to_dict = _row_dict


@dataclasses.dataclass
class InverseSquareResult(_ToDict):
    """Inverse-square check of one light. Lengths in m, intensities in W/sr (CIE Y weighted)."""

    light: str
    kind: str
    method: str                #: "analytic" or "render" (how E was measured)
    passed: bool               #: the law holds at every distance tried and the exponent is -2
    exponent: float            #: fitted d-exponent of E over the far field (ideal -2)
    exponent_se: float
    near_field_limit: float    #: m; 0 when the law holds at every distance tried, inf if never reached
    far_field_passed: bool     #: the law holds beyond the near-field limit with exponent -2
    source_size: float         #: m, largest dimension of the luminous area (0 for a point)
    five_times: dict           #: laws.five_times_rule output
    intensity: float           #: W/sr along the axis
    axis: tuple                #: unit world direction of the sweep
    tolerance: float
    rows: list
    causes: list               #: named causes of deviations (empty when the law holds)
    notes: list
    fit_from: float = 0.0      #: m, first distance used in the exponent fit
    seconds: float = 0.0
    plot: str = ""


class CosineRow(typing.NamedTuple):
    """One tilt. angle deg; measured W/m^2; predicted cos(theta); deviations fractions."""

    angle: float
    measured: float
    predicted: float           #: cos(theta)
    ratio: float               #: E(theta) / E(0)
    rel_deviation: float       #: ratio / cos(theta) - 1
    ratio_rel_se: float
    model_ratio: float         #: the closed-form model's E(theta)/E(0) (no scene surfaces)
    ok: bool

    to_dict = _row_dict


@dataclasses.dataclass
class CosineResult(_ToDict):
    """Cosine-law check of one light at one point (scene coordinates), angles in deg."""

    light: str
    kind: str
    method: str
    passed: bool
    max_rel_deviation: float   #: max |E(theta)/(E(0) cos theta) - 1|
    max_at_deg: float
    onset_deg: float           #: smallest tilt failing the tolerance (nan when none)
    horizon_onset_deg: float   #: tilt at which the source starts to sink below the horizon
    source_angular_radius_deg: float
    location: tuple
    facing: tuple              #: unit normal at 0 deg (toward the light)
    tilt_toward: tuple         #: unit direction the normal tilts toward
    tolerance: float
    rows: list
    causes: list
    notes: list
    seconds: float = 0.0
    plot: str = ""


@dataclasses.dataclass
class GridResult(_ToDict):
    """Illuminance on a work-plane grid. lux (ny, nx); points (ny, nx, 3) scene coordinates."""

    target: str
    nx: int
    ny: int
    spacing: tuple             #: (dx, dy) cell size, m
    size: tuple                #: (width, depth) of the plane, m
    lux: np.ndarray            #: (ny, nx) illuminance, lx
    irradiance: np.ndarray     #: (ny, nx) W/m^2
    rel_std_error: np.ndarray  #: (ny, nx)
    points: np.ndarray         #: (ny, nx, 3) scene coordinates
    local_extent: tuple        #: (x0, x1, y0, y1) in the plane's local coordinates (scene units)
    normal: tuple
    stats: dict                #: avg, min, max, u0 (lux; u0 dimensionless), count
    method: str
    exact: bool
    seconds: float
    notes: list
    spacing_rule: str = ""
    image: str = ""
    csv: str = ""

    def write_csv(self, path):
        """x, y, z (scene coordinates), lux, W/m^2 and relative s.e. per point, row by row."""
        with open(path, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(["row", "col", "x", "y", "z", "illuminance_lx", "irradiance_W_m2", "rel_std_error"])
            for j in range(self.ny):
                for i in range(self.nx):
                    x, y, z = self.points[j, i]
                    w.writerow([j, i, f"{x:.6g}", f"{y:.6g}", f"{z:.6g}", f"{self.lux[j, i]:.6g}",
                                f"{self.irradiance[j, i]:.6g}", f"{self.rel_std_error[j, i]:.3g}"])
        self.csv = path
        return path

    def write_png(self, path):
        from ..plots.isolux import isolux_png

        x0, x1, y0, y1 = self.local_extent
        isolux_png(path, self.lux, (x0, x1, y0, y1), title=f"Isolux: {self.target} ({self.nx} x {self.ny}, "
                   f"{self.method})", stats=self.stats)
        self.image = path
        return path


@dataclasses.dataclass
class ConvergenceRow(_ToDict):
    samples_per_texel: int
    samples: int               #: samples per reading (texels^2 x samples per texel)
    seconds: float             #: wall time of one reading of the target alone, s
    rms_error: float           #: RMS relative error against the reference (fraction)
    std_error: float           #: mean stated relative standard error (fraction)


@dataclasses.dataclass
class ConvergenceResult(_ToDict):
    target: str
    reference_kind: str        #: "analytic (exact)" or "render, N samples per texel"
    reference: list            #: reference irradiance per point, W/m^2
    rows: list
    fit: dict                  #: convergence.ConvergenceFit.to_dict()
    target_error: float        #: fraction
    samples_for_target: float  #: samples per reading
    seconds_for_target: float  #: s
    notes: list
    plot: str = ""


# --- shared helpers -----------------------------------------------------------------------------

def _scene(scene):
    return scene or bpy.context.scene


def light_object(light, scene):
    """The light object named or given; clear errors for everything else."""
    obj = scene.objects.get(light) if isinstance(light, str) else light
    if obj is None:
        raise RadiometerError(f"no object named {light!r} in scene {scene.name!r}")
    if getattr(obj, "type", None) != "LIGHT":
        raise RadiometerError(f"{obj.name!r} is not a light (it is a {getattr(obj, 'type', type(obj).__name__)})")
    if obj.hide_render:
        raise RadiometerError(f"light {obj.name!r} is disabled in renders: enable it to check it")
    if obj.name not in scene.objects:
        raise RadiometerError(f"light {obj.name!r} is not in scene {scene.name!r}")
    return obj


def light_spec(obj, scene):
    """The LightSpec (SI) of a light object as Cycles renders it, or a clear error when no closed
    form describes it."""
    model = meter.capture_model(scene)
    for light in model.lights:
        if light.name == obj.name:
            if light.spec is None:
                raise RadiometerError(f"light {obj.name!r} {light.uncovered}: Radiometer has no far-field "
                                      "intensity to compare with")
            return light.spec
    raise RadiometerError(f"light {obj.name!r} does not render (hidden in renders or by its collection)")


def scene_lights_to_check(scene):
    return [ob for ob in scene.objects if ob.type == "LIGHT" and not ob.hide_render]


@contextlib.contextmanager
def isolated_light(scene, obj):
    """Only ``obj`` lights the scene inside the block: other lights off in renders, no world."""
    with scene_guard.preserved_scene(scene) as snapshot:
        for other in scene.objects:
            if other.type == "LIGHT" and other != obj and not other.hide_render:
                snapshot.remember(other, "hide_render")
                other.hide_render = True
        if scene.world is not None:
            scene.world = None  # the snapshot puts the world back
        bpy.context.view_layer.update()
        yield


def source_size(spec):
    """Largest dimension of the luminous area, m: longer side or diameter; 2R for a sphere; 0 for delta."""
    if spec.kind == "AREA":
        return float(max(spec.extents))
    if spec.kind in ("POINT", "SPOT"):
        return 2.0 * spec.radius
    return 0.0


def _weights(scene):
    _space, weights, efficacy = meter.scene_photometry(scene)
    return weights, efficacy


def _free_distance(scene, origin_scene, direction, skip_light):
    """Distance (scene units) along ``direction`` to the first surface that renders, inf if none."""
    from mathutils import Vector

    depsgraph = bpy.context.evaluated_depsgraph_get()
    o, d = Vector(origin_scene), Vector(direction).normalized()
    travelled = 1e-6
    for _ in range(64):
        hit, loc, _n, _i, ob, _m = scene.ray_cast(depsgraph, o + d * travelled, d)
        if not hit:
            return math.inf
        original = ob.original if ob.original is not None else ob
        if not original.hide_render and (original.visible_shadow or original.visible_diffuse):
            return (loc - o).length
        travelled = (loc - o).length + 1e-6
    return math.inf


def _model_irradiance(spec, points_m, normals, weights):
    from ..radiometry import lights as light_models

    return light_models.irradiance(spec, points_m, normals) @ weights


def _measure(scene, points_scene, normals, method, quality, target_rel_error, seed, progress, cancelled):
    readings = meter.measure_illuminance(points_scene, normals, scene=scene, method=method, quality=quality,
                                         target_rel_error=target_rel_error, seed=seed, progress=progress,
                                         cancelled=cancelled)
    return readings if isinstance(readings, list) else [readings]


# --- inverse square ------------------------------------------------------------------------------

def default_distances(spec, count=24):
    """From close to the source to far away: 0.6 to 60 source sizes (0.06 to 6 m for a point)."""
    base = source_size(spec) or 0.1
    return np.geomspace(0.6 * base, 60.0 * base, count)


def check_inverse_square(light, *, scene=None, distances=None, method="auto", quality="standard",
                         tolerance=laws.DEFAULT_TOLERANCE, exponent_tolerance=0.01, target_rel_error=None,
                         seed=0, plot=None, progress=None, cancelled=None):
    """Sweep a meter facing ``light`` along its axis and compare E with I/d^2.

    ``distances`` in m from the light's centre (default :func:`default_distances`, shortened to the
    free space in front of the light). Returns :class:`InverseSquareResult`.
    """
    scene = _scene(scene)
    obj = light_object(light, scene)
    spec = light_spec(obj, scene)
    if spec.kind == "SUN":
        raise RadiometerError(f"light {obj.name!r} is a sun: it has no position, so the inverse-square law does "
                              "not apply (its irradiance does not change with distance); check its cosine law")
    weights, efficacy = _weights(scene)
    scale = scene.unit_settings.scale_length
    axis = np.asarray(spec.emission_direction, float)
    intensity = float(np.asarray(_radiant_intensity(spec, axis)) @ weights)
    if intensity <= 0:
        raise RadiometerError(f"light {obj.name!r} sends no light along its axis (intensity 0): nothing to check")
    notes, causes = [], []
    centre_scene = np.asarray(spec.position) / scale
    free = _free_distance(scene, centre_scene, axis, obj) * scale  # m
    if distances is None:
        d = default_distances(spec)
        if math.isfinite(free) and d[-1] > 0.95 * free:
            d = d[d < 0.95 * free]
            if d.size < 4:
                d = np.geomspace(min(0.6 * (source_size(spec) or 0.1), 0.3 * free), 0.95 * free, 12)
            notes.append(f"sweep shortened to the free space in front of the light: a surface {free:.3g} m away")
    else:
        d = np.sort(np.asarray(distances, float).ravel())
        if d.size < 2 or not np.all(np.isfinite(d)) or np.any(d <= 0):
            raise RadiometerError("distances must be at least 2 finite values > 0 (m)")
    if spec.kind in ("POINT", "SPOT") and spec.radius > 0 and not spec.soft_falloff and d[0] <= spec.radius:
        raise RadiometerError(f"distance {d[0]:.3g} m is inside light {obj.name!r}'s sphere (radius "
                              f"{spec.radius:.3g} m): start the sweep outside it")
    points_m = spec.position + d[:, None] * axis
    normals = np.tile(-axis, (d.size, 1))
    started = time.perf_counter()
    with isolated_light(scene, obj):
        readings = _measure(scene, points_m / scale, normals, method, quality, target_rel_error, seed,
                            progress, cancelled)
    seconds = time.perf_counter() - started
    measured = np.array([r.irradiance for r in readings])
    se = np.array([r.rel_std_error if math.isfinite(r.rel_std_error) else 1.0 for r in readings])
    predicted = intensity / d**2
    model = _model_irradiance(spec, points_m, normals, weights)
    dev = laws.relative_deviation(measured, predicted)
    model_dev = laws.relative_deviation(model, predicted)
    ok = laws.within_tolerance(dev, se, tolerance)
    limit = laws.near_field_limit(d, dev, se, tolerance)
    size = source_size(spec)
    rule = laws.five_times_rule(size, limit)
    # Exponent over the far field: beyond the near-field limit when >= 3 points remain there,
    # else the farthest third of the sweep (the far field was not reached).
    lit = measured > 0
    far = (d >= limit) & lit if math.isfinite(limit) else np.zeros_like(lit)
    if far.sum() < 3:
        far = np.zeros_like(lit)
        far[-max(3, d.size // 3):] = True
        far &= lit
    if far.sum() >= 2:
        fit = laws.fit_power_law(d[far], measured[far], se[far])
        exponent, exponent_se, fit_from = fit.exponent, fit.exponent_se, float(d[far][0])
    else:
        exponent, exponent_se, fit_from = float("nan"), float("nan"), float("nan")
    exponent_ok = bool(abs(exponent + 2.0) <= exponent_tolerance + 3 * exponent_se) if math.isfinite(exponent) else False
    passed = bool(ok.all() and exponent_ok)
    far_passed = bool(math.isfinite(limit) and exponent_ok)
    method_used = readings[0].method
    notes.append(f"measured by {method_used}" + (" (the light needs no rendering here: closed form, exact)"
                                                  if method_used == "analytic" and readings[0].exact else ""))
    notes.append("other lights and the world switched off during the check")
    if not passed:
        causes += _inverse_square_causes(spec, scene, d, dev, model_dev, se, measured, predicted, tolerance, free)
    rows = [InverseSquareRow(float(d[k]), float(measured[k]), float(predicted[k]), float(dev[k]), float(se[k]),
                             float(model[k]), float(model_dev[k]), bool(ok[k]), float(efficacy * measured[k]))
            for k in range(d.size)]
    result = InverseSquareResult(
        light=obj.name, kind=spec.kind, method=method_used, passed=passed, exponent=float(exponent),
        exponent_se=float(exponent_se), near_field_limit=float(limit), far_field_passed=far_passed,
        source_size=size, five_times=rule, intensity=intensity, axis=tuple(axis.tolist()), tolerance=tolerance,
        rows=rows, causes=causes, notes=notes, fit_from=fit_from, seconds=seconds)
    if plot and _can_plot(result.notes):
        write_inverse_square_plot(result, plot)
    return result


def _radiant_intensity(spec, direction):
    from ..radiometry import lights as light_models

    return light_models.radiant_intensity(spec, direction)


def _inverse_square_causes(spec, scene, d, dev, model_dev, se, measured, predicted, tolerance, free):
    causes = []
    own = np.abs(model_dev) > tolerance
    if spec.kind in ("POINT", "SPOT") and spec.radius > 0 and spec.soft_falloff and own.any():
        r = spec.radius
        causes.append(f"Blender's soft falloff on a {spec.kind.lower()} light with radius {r:.3g} m: Cycles renders "
                      f"E = I/(R² + d²), a deviation of -R²/(R² + d²) (-{100 * r * r / (r * r + d[0] ** 2):.3g} % at "
                      f"{d[0]:.3g} m; under 1 % beyond {math.sqrt(99) * r:.3g} m); turn Soft Falloff off for an "
                      "inverse-square sphere")
    if spec.kind == "AREA" and spec.spread >= np.pi and own.any():
        u, v = spec.extents
        causes.append(f"the size of the area light ({u:.3g} x {v:.3g} m): an extended source follows I/d² only "
                      f"in the far field (five-times rule: {5 * source_size(spec):.3g} m)")
    if spec.kind == "AREA" and spec.spread < np.pi and own.any():
        causes.append(f"the area light's spread ({math.degrees(spec.spread):.3g} deg): close to the light only part "
                      "of it shines on the meter, so E grows slower than 1/d² there")
    blocked = (measured <= 0.02 * predicted) & (predicted > 0)
    if blocked.any():
        causes.append(f"occluders: the meter is in shadow from {d[blocked][0]:.3g} m on")
    resid = laws.relative_deviation(measured, predicted * (1.0 + np.nan_to_num(model_dev)))  # vs the model
    scene_part = np.abs(resid) > tolerance + 3 * se
    if (scene_part & ~blocked).any():
        needs = meter.capture_model(scene).needs
        what = "surfaces in the scene reflect or partly block light" if needs["geometry"] else "unexplained"
        k = int(np.argmax(np.where(scene_part & ~blocked, np.abs(resid), -1)))
        causes.append(f"{what}: measured differs from the light's own closed form by {100 * resid[k]:+.3g} % at "
                      f"{d[k]:.3g} m")
    if not causes and math.isfinite(free) and free < 5 * max(source_size(spec), 0.01):
        causes.append(f"a surface {free:.3g} m in front of the light leaves no room for the far field")
    if not causes:
        causes.append("deviation within noise of the tolerance: measure at higher quality")
    return causes


def write_inverse_square_plot(result, path):
    from ..plots.laws import inverse_square_plot

    r = result.rows
    inverse_square_plot(path, [x.distance for x in r], [x.measured for x in r], [x.predicted for x in r],
                        [x.rel_std_error for x in r], near_field_limit=result.near_field_limit,
                        rule_distance=result.five_times["rule_distance"] or None, tolerance=result.tolerance,
                        title=f"Inverse square: {result.light} ({result.kind}, {result.method}); exponent "
                              f"{result.exponent:.4f} ± {result.exponent_se:.2g}, near-field limit "
                              f"{result.near_field_limit:.3g} m")
    result.plot = path
    return path


# --- cosine law ----------------------------------------------------------------------------------

def default_location(spec, scene):
    """Scene coordinates: 2 source sizes (at least 1 m) in front of the light; the origin for a sun."""
    if spec.kind == "SUN":
        return np.zeros(3)
    scale = scene.unit_settings.scale_length
    d = max(1.0, 2.0 * source_size(spec))
    return (np.asarray(spec.position) + d * np.asarray(spec.emission_direction)) / scale


def angular_radius(spec, point_m, facing):
    """Largest angle (rad) between ``facing`` and a direction to a point of the source."""
    if spec.kind == "SUN":
        return 0.5 * spec.angle
    to_c = np.asarray(spec.position) - point_m
    dist = float(np.linalg.norm(to_c))
    if spec.kind == "AREA":
        u, v = spec.extents
        ax = np.asarray(spec.axes)
        phi = np.linspace(0, 2 * np.pi, 73)
        if spec.shape in ("DISK", "ELLIPSE"):
            outline = np.c_[0.5 * u * np.cos(phi), 0.5 * v * np.sin(phi)]
        else:
            outline = np.array([[-u, -v], [u, -v], [u, v], [-u, v]]) / 2
        verts = spec.position + outline[:, :1] * ax[:, 0] + outline[:, 1:] * ax[:, 1]
        dirs = verts - point_m
        dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
        return float(np.max(np.arccos(np.clip(dirs @ facing, -1, 1))))
    if spec.radius > 0:
        # soft falloff: a disk of radius R facing the receiver; otherwise a sphere of radius R
        return float(math.atan2(spec.radius, dist) if spec.soft_falloff else math.asin(min(1.0, spec.radius / dist)))
    return 0.0


def check_cosine_law(light, *, scene=None, location=None, angles_deg=None, method="auto", quality="standard",
                     tolerance=laws.DEFAULT_TOLERANCE, target_rel_error=None, seed=0, plot=None, progress=None,
                     cancelled=None):
    """Tilt a meter at ``location`` (scene coordinates) from facing ``light`` to 89 deg.

    Compares E(theta)/E(0) with cos(theta). Returns :class:`CosineResult`.
    """
    scene = _scene(scene)
    obj = light_object(light, scene)
    spec = light_spec(obj, scene)
    weights, _eff = _weights(scene)
    scale = scene.unit_settings.scale_length
    loc = default_location(spec, scene) if location is None else np.asarray(location, float)
    if loc.shape != (3,) or not np.all(np.isfinite(loc)):
        raise RadiometerError(f"location must be 3 finite numbers (scene coordinates), got {location!r}")
    angles = np.asarray(DEFAULT_ANGLES_DEG if angles_deg is None else angles_deg, float).ravel()
    if angles.size < 2 or not np.all(np.isfinite(angles)) or np.any((angles < 0) | (angles >= 90)):
        raise RadiometerError("angles_deg must be at least 2 tilts in [0, 90) deg")
    if not np.any(angles == 0):
        angles = np.concatenate([[0.0], angles])
    angles = np.unique(angles)
    point_m = loc * scale
    if spec.kind == "SUN":
        facing = np.asarray(spec.axes)[:, 2]
    else:
        to_light = np.asarray(spec.position) - point_m
        if np.linalg.norm(to_light) < 1e-9:
            raise RadiometerError(f"the location is at light {obj.name!r}'s centre: move it away from the light")
        facing = to_light / np.linalg.norm(to_light)
    helper = np.asarray(spec.axes)[:, 0]
    toward = helper - (helper @ facing) * facing
    if np.linalg.norm(toward) < 1e-6:
        helper = np.asarray(spec.axes)[:, 1]
        toward = helper - (helper @ facing) * facing
    toward /= np.linalg.norm(toward)
    th = np.radians(angles)
    normals = np.cos(th)[:, None] * facing + np.sin(th)[:, None] * toward
    points = np.tile(loc, (angles.size, 1))
    started = time.perf_counter()
    with isolated_light(scene, obj):
        readings = _measure(scene, points, normals, method, quality, target_rel_error, seed, progress, cancelled)
    seconds = time.perf_counter() - started
    measured = np.array([r.irradiance for r in readings])
    se = np.array([r.rel_std_error if math.isfinite(r.rel_std_error) else 1.0 for r in readings])
    try:
        analysis = laws.cosine_law_analysis(angles, measured, se, tolerance)
    except ValueError as exc:
        raise RadiometerError(f"cosine law at {tuple(np.round(loc, 4))}: {exc}") from None
    model = _model_irradiance(spec, np.tile(point_m, (angles.size, 1)), normals, weights)
    model_ratio = model / model[0] if model[0] > 0 else np.full(angles.size, np.nan)
    alpha = angular_radius(spec, point_m, facing)
    horizon = float(laws.horizon_onset_deg(alpha))
    causes = []
    if not analysis["passed"]:
        onset = analysis["onset_deg"]
        if alpha > 0 and onset >= horizon - 1e-9 - (angles[1] - angles[0] if angles.size > 1 else 0):
            causes.append(f"the extended source sinks below the meter's horizon from {horizon:.3g} deg on (it spans "
                          f"{math.degrees(alpha):.3g} deg from its centre as seen from here), so E falls slower "
                          "than cos θ")
        if spec.kind == "AREA" and spec.spread < np.pi:
            causes.append(f"the area light's spread ({math.degrees(spec.spread):.3g} deg) makes its radiance depend "
                          "on direction")
        scene_dev = laws.relative_deviation(analysis["ratio"], model_ratio)
        if np.any(np.abs(scene_dev) > tolerance + 3 * analysis["ratio_rel_se"]):
            causes.append("surfaces in the scene reflect or block light differently at different tilts")
        if not causes:
            causes.append("deviation within noise of the tolerance: measure at higher quality")
    rows = [CosineRow(float(angles[k]), float(measured[k]), float(analysis["predicted"][k]),
                      float(analysis["ratio"][k]), float(analysis["rel_deviation"][k]),
                      float(analysis["ratio_rel_se"][k]), float(model_ratio[k]), bool(analysis["ok"][k]))
            for k in range(angles.size)]
    notes = [f"measured by {readings[0].method}", "other lights and the world switched off during the check",
             f"meter tilts from facing the light toward {tuple(np.round(toward, 4))}"]
    result = CosineResult(
        light=obj.name, kind=spec.kind, method=readings[0].method, passed=analysis["passed"],
        max_rel_deviation=analysis["max_rel_deviation"], max_at_deg=analysis["max_at_deg"],
        onset_deg=analysis["onset_deg"], horizon_onset_deg=horizon, source_angular_radius_deg=math.degrees(alpha),
        location=tuple(loc.tolist()), facing=tuple(facing.tolist()), tilt_toward=tuple(toward.tolist()),
        tolerance=tolerance, rows=rows, causes=causes, notes=notes, seconds=seconds)
    if plot and _can_plot(result.notes):
        write_cosine_plot(result, plot)
    return result


def write_cosine_plot(result, path):
    from ..plots.laws import cosine_plot

    r = result.rows
    cosine_plot(path, [x.angle for x in r], [x.ratio for x in r], [x.ratio_rel_se for x in r],
                tolerance=result.tolerance,
                title=f"Cosine law: {result.light} ({result.kind}, {result.method}); max deviation "
                      f"{100 * result.max_rel_deviation:.3g} % at {result.max_at_deg:g} deg")
    result.plot = path
    return path


# --- illuminance grid ----------------------------------------------------------------------------

def _plane_frame(obj, scene):
    """(local extent x0, x1, y0, y1, z) in scene units, matrix_world as numpy 4x4, normal."""
    if obj.type != "MESH":
        raise RadiometerError(f"{obj.name!r} is not a mesh plane (it is a {obj.type}): pick a plane object")
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        n = len(mesh.vertices)
        if n == 0:
            raise RadiometerError(f"plane {obj.name!r} has no vertices (empty mesh): give it a face")
        co = np.empty(n * 3)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(n, 3)
    finally:
        evaluated.to_mesh_clear()
    mw = np.array(evaluated.matrix_world, float)
    x0, y0, z0 = co.min(axis=0)
    x1, y1, z1 = co.max(axis=0)
    sx = (x1 - x0) * np.linalg.norm(mw[:3, 0])
    sy = (y1 - y0) * np.linalg.norm(mw[:3, 1])
    if not (sx > 0 and sy > 0):
        raise RadiometerError(f"plane {obj.name!r} has no area in its local XY (size {sx:.3g} x {sy:.3g}): "
                              "give it a face in its local XY plane")
    normal = np.linalg.inv(mw[:3, :3]).T @ np.array([0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal)
    return (x0, x1, y0, y1, 0.5 * (z0 + z1)), mw, normal


def illuminance_grid(target, *, resolution=None, spacing=None, scene=None, method="auto", quality="standard",
                     target_rel_error=None, seed=0, png=None, csv_path=None, progress=None, cancelled=None):
    """Illuminance at the cell centres of a grid on a plane object's local XY (its +Z side).

    ``target``: a mesh object or its name. ``resolution``: (nx, ny); ``spacing``: cell size in m;
    neither: the EN 12464-1 spacing p = 0.2 x 5^log10(d). Returns :class:`GridResult`.
    """
    scene = _scene(scene)
    obj = scene.objects.get(target) if isinstance(target, str) else target
    if obj is None:
        raise RadiometerError(f"no object named {target!r} in scene {scene.name!r}")
    (x0, x1, y0, y1, zc), mw, normal = _plane_frame(obj, scene)
    scale = scene.unit_settings.scale_length
    size_x = (x1 - x0) * np.linalg.norm(mw[:3, 0]) * scale
    size_y = (y1 - y0) * np.linalg.norm(mw[:3, 1]) * scale
    if resolution is not None and spacing is not None:
        raise RadiometerError("give a resolution or a spacing, not both")
    rule = ""
    if resolution is not None:
        try:
            nx, ny = (int(v) for v in resolution)
        except (TypeError, ValueError):
            raise RadiometerError(f"resolution must be two integers (nx, ny), got {resolution!r}") from None
        if nx < 1 or ny < 1:
            raise RadiometerError(f"resolution must be at least 1 x 1 points, got {nx} x {ny}")
    else:
        if spacing is not None and not (float(spacing) > 0 and math.isfinite(float(spacing))):
            raise RadiometerError(f"spacing must be > 0 m, got {spacing}")
        if spacing is None:
            p = float(grid_math.en12464_spacing(max(size_x, size_y)))
            rule = f"EN 12464-1: p = 0.2 x 5^log10({max(size_x, size_y):.3g} m) = {p:.3g} m"
        else:
            p = float(spacing)
        nx, ny = grid_math.grid_counts(size_x, size_y, p)
    if nx * ny > 250_000:
        raise RadiometerError(f"{nx} x {ny} points is too many for one measurement: use a coarser grid")
    local = grid_math.cell_centres((x0, x1), (y0, y1), nx, ny)
    local3 = np.concatenate([local, np.full(local.shape[:2] + (1,), zc), np.ones(local.shape[:2] + (1,))], axis=-1)
    points = local3 @ mw.T
    points = points[..., :3]
    started = time.perf_counter()
    readings = _measure(scene, points.reshape(-1, 3), normal, method, quality, target_rel_error, seed,
                        progress, cancelled)
    seconds = time.perf_counter() - started
    irr = np.array([r.irradiance for r in readings]).reshape(ny, nx)
    lux = np.array([r.illuminance for r in readings]).reshape(ny, nx)
    se = np.array([r.rel_std_error for r in readings]).reshape(ny, nx)
    notes = [f"{nx} x {ny} points at cell centres on the plane (each sensor raised by a scale-aware epsilon "
             "along the normal when a surface is there: see the readings' notes)"]
    if obj.hide_render:
        notes.append("the plane is hidden in renders: an imaginary work plane that neither blocks nor reflects")
    notes += readings[0].notes
    result = GridResult(
        target=obj.name, nx=nx, ny=ny, spacing=(size_x / nx, size_y / ny), size=(size_x, size_y), lux=lux,
        irradiance=irr, rel_std_error=se, points=points, local_extent=(x0, x1, y0, y1),
        normal=tuple(normal.tolist()), stats=grid_math.grid_stats(lux), method=readings[0].method,
        exact=all(r.exact for r in readings), seconds=seconds, notes=notes, spacing_rule=rule)
    if png and _can_plot(result.notes):
        result.write_png(png)
    if csv_path:
        result.write_csv(csv_path)
    return result


def colour_plane(result, scene=None, name=None):
    """A viewport-only copy of the grid as coloured quads (colour attribute 'lux_colour').

    Creates (or replaces) an object named ``Isolux <plane>`` hidden in renders; set the viewport's
    Solid shading colour to Attribute to see it. Returns the object.
    """
    matplotlib = _plots.require_matplotlib()  # RadiometerError in Blender's own Python

    scene = _scene(scene)
    name = name or f"Isolux {result.target}"
    old = bpy.data.objects.get(name)
    if old is not None:
        mesh_old = old.data
        bpy.data.objects.remove(old, do_unlink=True)
        if mesh_old is not None and mesh_old.users == 0:
            bpy.data.meshes.remove(mesh_old)
    obj_plane = scene.objects.get(result.target)
    (x0, x1, y0, y1, zc), mw, normal = _plane_frame(obj_plane, scene)
    ny, nx = result.lux.shape
    xs, ys = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1)
    verts, faces, colours = [], [], []
    lo, hi = float(result.lux.min()), float(result.lux.max())
    cmap = matplotlib.colormaps["inferno"]
    for j in range(ny):
        for i in range(nx):
            base = len(verts)
            verts += [(xs[i], ys[j], zc), (xs[i + 1], ys[j], zc), (xs[i + 1], ys[j + 1], zc), (xs[i], ys[j + 1], zc)]
            faces.append((base, base + 1, base + 2, base + 3))
            c = cmap((result.lux[j, i] - lo) / (hi - lo) if hi > lo else 0.5)
            colours += [c] * 4
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    attr = mesh.color_attributes.new("lux_colour", "FLOAT_COLOR", "CORNER")
    attr.data.foreach_set("color", np.array(colours, np.float32).ravel())
    obj = bpy.data.objects.new(name, mesh)
    obj.matrix_world = obj_plane.matrix_world.copy()
    obj.location = obj_plane.matrix_world.translation + DISPLAY_OFFSET * __import__("mathutils").Vector(normal)
    obj.hide_render = True
    scene.collection.objects.link(obj)
    return obj


# --- convergence ---------------------------------------------------------------------------------

def convergence_study(target=None, *, scene=None, location=None, normal=(0.0, 0.0, 1.0),
                      samples=(4, 16, 64, 256), texels=4, replicas=8, reference_samples=None, target_error=0.01,
                      bounces=8, seed=0, plot=None, cancelled=None):
    """Error and time of rendered readings at increasing samples per texel; fit and invert.

    ``target``: an illuminance meter object (or its name), a plane object (coarse 4 x 4 grid), or
    None with ``location``/``normal`` (scene coordinates). For a meter the point is measured as
    ``replicas`` independent copies in one bake, so the RMS error against the reference is an
    honest estimate; a separate bake of the target alone gives the time. Reference: the analytic
    value when it is exact for this scene, else a render with ``reference_samples`` per texel
    (default 16 x the largest count). Returns :class:`ConvergenceResult`.
    """
    scene = _scene(scene)
    points, normals, label = _convergence_points(target, scene, location, normal)
    samples = sorted({int(s) for s in samples})
    if len(samples) < 2 or samples[0] < 1:
        raise RadiometerError("samples must hold at least 2 different counts >= 1")
    weights, _eff = _weights(scene)
    view_layer = bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]
    notes = []
    scale = scene.unit_settings.scale_length
    model = meter.capture_model(scene, view_layer)
    points, _eps = meter.sensor_points(points, normals, scale, model)
    decision = meter.plan(scene, model, points * scale, normals, "render")
    if decision["analytic_exact"]:
        per_light, _bounds, _info = meter.analytic_irradiance(model, decision["direct"], points * scale, normals)
        reference = per_light.sum(axis=0) @ weights
        kind = "analytic (exact)"
    else:
        n_ref = int(reference_samples or 16 * samples[-1])
        est, _info, _rec = meter.render_irradiance(
            scene, view_layer, points, normals, {"samples": n_ref, "texels": texels, "bakes": 1, "bounces": bounces},
            needs=decision["needs"], seed=seed + 10_000, cancelled=cancelled)
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
        est, _info, _rec = meter.render_irradiance(scene, view_layer, rep_points, rep_normals, preset,
                                                   needs=decision["needs"], seed=seed + 100 * k, cancelled=cancelled)
        scalar = est @ weights                              # (batches, M)
        mean = scalar.mean(axis=0)
        se = scalar.std(axis=0, ddof=1) / math.sqrt(scalar.shape[0])
        ref = np.repeat(reference, replicas) if single else reference
        rms = float(conv_math.rms_relative_error(mean, ref))
        t0 = time.perf_counter()
        meter.render_irradiance(scene, view_layer, points, normals, preset, needs=decision["needs"],
                                seed=seed + 100 * k + 50, cancelled=cancelled)
        seconds = time.perf_counter() - t0
        rows.append(ConvergenceRow(n, n * texels * texels, seconds, rms, float(np.mean(se / np.abs(mean)))))
    errors = np.array([r.rms_error for r in rows])
    if np.any(errors <= 0):
        raise RadiometerError("an error of exactly 0 was measured (noise-free light such as a point or sun): "
                              "nothing to converge; use a scene with area lights or surfaces")
    fit = conv_math.fit_convergence([r.samples for r in rows], [r.seconds for r in rows], errors)
    result = ConvergenceResult(
        target=label, reference_kind=kind, reference=reference.tolist(), rows=rows, fit=fit.to_dict(),
        target_error=float(target_error), samples_for_target=fit.samples_for(target_error),
        seconds_for_target=fit.seconds_for(target_error), notes=notes)
    if plot and _can_plot(result.notes):
        write_convergence_plot(result, plot)
    return result


def _convergence_points(target, scene, location, normal):
    if target is None:
        if location is None:
            raise RadiometerError("give a meter, a plane or a location for the convergence study")
        pts, _ = meter.as_points(location)
        return pts, meter.as_directions(normal, len(pts)), f"point {tuple(np.round(pts[0], 4))}"
    obj = scene.objects.get(target) if isinstance(target, str) else target
    if obj is None:
        raise RadiometerError(f"no object named {target!r} in scene {scene.name!r}")
    if getattr(obj, "radiometer_meter", None) is not None and obj.radiometer_meter.is_meter:
        if obj.radiometer_meter.kind != "ILLUMINANCE":
            raise RadiometerError(f"{obj.name!r} is a {obj.radiometer_meter.kind.lower()} meter: the study uses "
                                  "illuminance meters")
        mw = np.array(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).matrix_world, float)
        z = mw[:3, 2] / np.linalg.norm(mw[:3, 2])
        return mw[None, :3, 3], z[None, :], f"meter {obj.name}"
    if obj.type == "MESH":
        (x0, x1, y0, y1, zc), mw, n = _plane_frame(obj, scene)
        local = grid_math.cell_centres((x0, x1), (y0, y1), 4, 4).reshape(-1, 2)
        p = np.c_[local, np.full(len(local), zc), np.ones(len(local))] @ mw.T
        return p[:, :3], np.tile(n, (len(p), 1)), f"grid 4 x 4 on {obj.name}"
    raise RadiometerError(f"{obj.name!r} is neither an illuminance meter nor a plane")


def write_convergence_plot(result, path):
    from ..plots.convergence import convergence_plot

    r = result.rows
    convergence_plot(path, [x.samples for x in r], [x.seconds for x in r], [x.rms_error for x in r],
                     [x.std_error for x in r], fit=result.fit, target=result.target_error,
                     title=f"Convergence: {result.target} (reference: {result.reference_kind}); "
                           f"{result.target_error:.2%} needs ~{result.samples_for_target:.3g} samples, "
                           f"{result.seconds_for_target:.3g} s")
    result.plot = path
    return path

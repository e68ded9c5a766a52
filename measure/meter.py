"""The light meter: illuminance at points (analytic, render or auto) and luminance in a cone.

Host code: gathers the scene, calls the pure models in ``radiometry`` or renders with Cycles inside
``scene_guard.preserved_scene``, and packs SI readings. All locations come in scene units and are
converted with ``scene.unit_settings.scale_length``.
"""

import math
import time

import bpy
import numpy as np

from .. import quality as quality_presets
from ..radiometry import stats
from ..errors import RadiometerError
from ..readings import IlluminanceReading
from . import render_settings, scene_guard, scene_lights, sensors

DEFAULT_EFFICACY = 683.0  # lm/W, Blender's glTF convention; see README "Conventions"


# --- inputs ---------------------------------------------------------------------------------------

def as_points(location, name="location"):
    pts = np.asarray(location, dtype=float)
    single = pts.ndim == 1
    pts = np.atleast_2d(pts)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise RadiometerError(f"{name} must be 3 numbers or an (N, 3) array, got shape {np.shape(location)}")
    if not np.all(np.isfinite(pts)):
        bad = int(np.argmax(~np.all(np.isfinite(pts), axis=1)))
        raise RadiometerError(f"{name} #{bad} is not finite ({pts[bad].tolist()}): give a real position")
    return pts, single


def as_directions(direction, count, name="normal"):
    d = np.asarray(direction, dtype=float)
    d = np.broadcast_to(np.atleast_2d(d), (count, 3)) if d.ndim == 1 or d.shape[0] == 1 else np.atleast_2d(d)
    if d.shape != (count, 3):
        raise RadiometerError(f"{name} must be 3 numbers or ({count}, 3), got shape {np.shape(direction)}")
    if not np.all(np.isfinite(d)):
        raise RadiometerError(f"{name} is not finite: give a real direction")
    length = np.linalg.norm(d, axis=1)
    if np.any(length < 1e-12):
        raise RadiometerError(f"{name} has zero length: a meter needs a direction to face")
    return d / length[:, None]


def scene_photometry(scene):
    """(colour space name, luminance weights (3,), efficacy lm/W) for this scene."""
    from ..radiometry import photometry

    space = bpy.data.colorspace.working_space if hasattr(bpy.data, "colorspace") else "Linear Rec.709"
    settings = getattr(scene, "radiometer", None)
    efficacy = float(settings.efficacy) if settings is not None else DEFAULT_EFFICACY
    return space, np.asarray(photometry.luminance_weights(space), float), efficacy


# --- deciding how to measure ----------------------------------------------------------------------

def plan(scene, depsgraph, method, exclude=()):
    """Decide analytic vs render for this scene and say why. Returns a dict."""
    if method not in quality_presets.METHODS:
        raise RadiometerError(f"unknown method {method!r}; choose one of {', '.join(quality_presets.METHODS)}")
    needs = render_settings.scene_needs(scene, depsgraph, exclude=exclude)
    specs, uncovered = scene_lights.light_specs(scene, depsgraph)
    if not specs and not uncovered and not needs["world_emits"] and not needs["emissive_surfaces"]:
        raise RadiometerError("the scene has no light sources (no lights, a black world, no emitting surfaces)")
    reasons = []
    if needs["geometry"]:
        reasons.append("surfaces can reflect or block light")
    if needs["world_emits"]:
        reasons.append("the world emits light")
    if needs["emissive_surfaces"]:
        reasons.append("surfaces emit light")
    for name, why in uncovered:
        reasons.append(f"light {name!r} {why}")
    analytic_ok = not reasons
    if method == "auto":
        chosen = "analytic" if analytic_ok else "render"
    elif method == "analytic" and uncovered:
        raise RadiometerError(
            f"light {uncovered[0][0]!r} {uncovered[0][1]}: no closed form covers it; use method='render'")
    else:
        chosen = method
    return {"method": chosen, "needs": needs, "specs": specs, "uncovered": uncovered,
            "reasons": reasons, "analytic_exact": analytic_ok}


# --- analytic ---------------------------------------------------------------------------------------

def _occluded(scene, depsgraph, origin_scene, target_scene, max_hits=64):
    """True when an object that casts shadows in renders blocks the segment origin -> target.

    Objects hidden in renders or invisible to shadow rays (work planes, meters' helpers) are
    stepped through, as Cycles would.
    """
    from mathutils import Vector

    o, t = Vector(origin_scene), Vector(target_scene)
    d = t - o
    dist = d.length
    if dist == 0:
        return False
    d /= dist
    eps = 1e-6 * max(1.0, o.length)  # float32 BVH: offsets relative to the coordinates
    travelled = eps
    for _ in range(max_hits):
        if travelled >= dist * (1 - 1e-9):
            return False
        hit, loc, _n, _i, obj, _m = scene.ray_cast(depsgraph, o + d * travelled, d,
                                                   distance=dist - travelled - eps)
        if not hit:
            return False
        original = obj.original if obj.original is not None else obj
        if not original.hide_render and original.visible_shadow:
            return True
        travelled = (loc - o).length + eps
    return True


def analytic_irradiance(specs, points_m, normals, *, scene=None, depsgraph=None, points_scene=None):
    """Per-light direct irradiance (L, N, 3) W/m^2 plus per-light (exact, model, note)."""
    from ..radiometry import lights as light_models

    per_light = np.zeros((len(specs), len(points_m), 3))
    info = []
    check_occlusion = scene is not None and depsgraph is not None and scene_has_geometry(scene)
    for i, spec in enumerate(specs):
        per_light[i] = light_models.irradiance(spec, points_m, normals)
        exact, model, note = light_models.exactness(spec)
        if check_occlusion:
            note, whole = _apply_occlusion(scene, depsgraph, spec, points_scene, per_light[i], note)
            exact = exact and whole
        info.append((exact, model, note))
    return per_light, info


def scene_has_geometry(scene):
    return any(ob.type in render_settings._GEOMETRY_TYPES and not ob.hide_render for ob in scene.objects)


def _visibility_targets(spec, scale):
    """Points (scene units) on the light whose visibility decides occlusion: the centre for point-like
    lights, centre + corners + edge midpoints for area lights, centre + 6 poles for spheres."""
    centre = np.asarray(spec.position) / scale
    axes = np.asarray(spec.axes)
    if spec.kind == "AREA":
        hx = spec.size * spec.scale[0] / 2 / scale
        hy = (spec.size_y if spec.shape in ("RECTANGLE", "ELLIPSE") else spec.size) * spec.scale[1] / 2 / scale
        if spec.shape in ("DISK", "ELLIPSE"):
            hx, hy = hx * 0.7071, hy * 0.7071  # corners of the inscribed square
        offsets = [(a * hx, b * hy, 0.0) for a in (-1, 0, 1) for b in (-1, 0, 1)]
        return [centre + axes @ np.array(o) for o in offsets]
    if spec.radius > 0:
        r = spec.radius / scale
        return [centre] + [centre + s * r * axes[:, k] for k in range(3) for s in (-1, 1)]
    return [centre]


def _apply_occlusion(scene, depsgraph, spec, points_scene, values, note):
    """Zero a light's contribution where opaque objects block it; flag partial occlusion."""
    scale = scene.unit_settings.scale_length
    blocked = partial = 0
    for k, p in enumerate(points_scene):
        if not values[k].any():
            continue
        if spec.kind == "SUN":
            toward_sun = np.asarray(spec.axes)[:, 2]  # the sun emits along its local -Z
            targets = [p + toward_sun * 1e7]
        else:
            targets = _visibility_targets(spec, scale)
        hits = [_occluded(scene, depsgraph, p, t) for t in targets]
        if all(hits):
            values[k] = 0.0
            blocked += 1
        elif any(hits):
            partial += 1
    if blocked:
        note = f"{note}; blocked at {blocked} point(s) (opaque occluders assumed)"
    if partial:
        note = f"{note}; PARTIALLY occluded at {partial} point(s): value ignores the occlusion, not exact"
    return note, partial == 0


# --- render -----------------------------------------------------------------------------------------

def render_irradiance(scene, view_layer, points_scene, normals, preset, *, target_rel_error=None,
                      progress=None, cancelled=None, needs=None, exclude=(), seed=0):
    """Bake the sensors; returns (estimates (B, N, 3) in W/m^2 SI, info, render record)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    needs = needs or render_settings.scene_needs(scene, depsgraph, exclude=exclude)
    scale = scene.unit_settings.scale_length
    with scene_guard.preserved_scene(scene):
        record = render_settings.apply(scene, samples=preset["samples"], bounces=preset["bounces"], needs=needs)
        estimates, info = sensors.bake_irradiance(
            scene, view_layer, points_scene, normals, samples=preset["samples"], texels=preset["texels"],
            bakes=preset["bakes"], target_rel_error=target_rel_error, progress=progress, cancelled=cancelled,
            seed0=seed)
    # Cycles ignores the unit scale: it renders W per scene-unit^2. E_SI = E_render / scale^2.
    return estimates / scale ** 2, info, record


def only_delta_light(decision):
    """True when light arrives only straight from delta lights (radius-0 point/spot, sun of angle 0)."""
    needs = decision["needs"]
    if needs["geometry"] or needs["world_emits"] or needs["emissive_surfaces"] or decision["uncovered"]:
        return False
    return all((spec.kind in ("POINT", "SPOT") and spec.radius == 0.0) or (spec.kind == "SUN" and spec.angle == 0.0)
               for spec in decision["specs"])


# --- the public entry used by api.py ----------------------------------------------------------------

def measure_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None, method="auto", quality="standard",
                        target_rel_error=None, progress=None, cancelled=None, exclude=(), seed=0):
    """Readings (one per location) of irradiance/illuminance. See ``radiometer.api``."""
    scene = scene or bpy.context.scene
    view_layer = bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]
    points_scene, single = as_points(location)
    normals = as_directions(normal, len(points_scene))
    if target_rel_error is not None and not (0 < float(target_rel_error) < 1):
        raise RadiometerError(f"target_rel_error must be in (0, 1), got {target_rel_error}")
    preset = quality_presets.preset(quality)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    has_geometry = scene_has_geometry(scene)
    for k, p in enumerate(points_scene[:1000] if has_geometry else ()):
        if scene_lights.is_inside_closed_mesh(scene, depsgraph, p):
            raise RadiometerError(f"meter #{k} at {tuple(round(v, 4) for v in p)} is inside a closed mesh: "
                                  "move it into free space")
    decision = plan(scene, depsgraph, method, exclude=exclude)
    space, weights, efficacy = scene_photometry(scene)
    scale = scene.unit_settings.scale_length
    points_m = points_scene * scale
    started = time.perf_counter()
    notes = [f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}"]
    if decision["method"] == "analytic":
        per_light, info = analytic_irradiance(decision["specs"], points_m, normals, scene=scene,
                                              depsgraph=depsgraph, points_scene=points_scene)
        mean_rgb = per_light.sum(axis=0)
        se_rgb = np.zeros_like(mean_rgb)
        exact = decision["analytic_exact"] and all(e for e, _m, _n in info)
        notes.append("analytic direct light: " + "; ".join(f"{s.name}: {m} ({n})" for s, (e, m, n) in
                                                            zip(decision["specs"], info)))
        if not decision["analytic_exact"]:
            notes.append("NOT exact for this scene: " + ", ".join(decision["reasons"]))
        else:
            notes.append("exact: nothing in the scene but lights can add or block light")
        samples, record, scalar_se = 0, None, np.zeros(len(points_m))
    else:
        if only_delta_light(decision):
            # Next-event estimation samples a delta light exactly: every path gives the same value,
            # so one sample per texel is the exact render (more would only add float32 rounding).
            preset = dict(preset, samples=1, texels=2, bakes=1)
            notes.append("only delta lights and nothing to reflect light: 1 sample per texel is exact "
                         "(next-event estimation of a delta light has no variance)")
        estimates, run, record = render_irradiance(scene, view_layer, points_scene, normals, preset,
                                                   target_rel_error=target_rel_error, progress=progress,
                                                   cancelled=cancelled, needs=decision["needs"], exclude=exclude,
                                                   seed=seed)
        batches = estimates.shape[0]
        mean_rgb, se_rgb = stats.batch_mean(estimates, axis=0)
        _scalar_mean, scalar_se = stats.batch_mean(estimates @ weights, axis=0)
        exact = False
        samples = run["bakes"] * run["texels_per_meter"] * run["samples_per_texel"]
        why = ", ".join(decision["reasons"]) or "requested"
        notes.append(f"rendered with Cycles ({why}); standard error from {batches} independent batches "
                     f"(batch means of {run['samples_per_texel']} samples each)")
        if scale != 1.0:
            notes.append(f"unit scale {scale:g} m per unit: Cycles' scene-unit result divided by scale²")
    seconds = time.perf_counter() - started
    scalar_mean = mean_rgb @ weights
    readings = []
    for k in range(len(points_m)):
        e = float(scalar_mean[k])
        rel = float(scalar_se[k] / abs(e)) if e != 0 else (0.0 if scalar_se[k] == 0 else math.inf)
        readings.append(IlluminanceReading(
            irradiance_rgb=tuple(float(v) for v in mean_rgb[k]), irradiance=e, illuminance=efficacy * e,
            rel_std_error=rel, method=decision["method"], samples=int(samples), seconds=seconds / len(points_m),
            efficacy=efficacy, colour_space=space, location=tuple(points_scene[k]), normal=tuple(normals[k]),
            exact=bool(exact), std_error_rgb=tuple(float(v) for v in se_rgb[k]), notes=list(notes),
            render_settings=record))
    return readings[0] if single else readings


def predict_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None):
    """Analytic per-light breakdown at one point: list of dicts (SI), occlusion by ray casts."""
    scene = scene or bpy.context.scene
    points_scene, _ = as_points(location)
    normals = as_directions(normal, 1)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    specs, uncovered = scene_lights.light_specs(scene, depsgraph)
    space, weights, efficacy = scene_photometry(scene)
    points_m = points_scene * scene.unit_settings.scale_length
    per_light, info = analytic_irradiance(specs, points_m, normals, scene=scene, depsgraph=depsgraph,
                                          points_scene=points_scene)
    rows = []
    for spec, values, (exact, model, note) in zip(specs, per_light, info):
        e = float(values[0] @ weights)
        rows.append({"light": spec.name, "irradiance_rgb": tuple(map(float, values[0])), "irradiance": e,
                     "illuminance": efficacy * e, "model": model, "exact": bool(exact), "note": note})
    for name, why in uncovered:
        rows.append({"light": name, "irradiance_rgb": None, "irradiance": None, "illuminance": None,
                     "model": None, "exact": False, "note": f"not covered: {why}; measure by rendering"})
    return rows

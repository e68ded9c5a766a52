"""The light meter: illuminance at points (analytic, render or auto) and luminance in a cone.

Host code: gathers the scene, calls the pure models in ``radiometry`` or renders with Cycles inside
``scene_guard.preserved_scene``, and packs SI readings. All locations come in scene units and are
converted with the request's ``scale_length`` (``measure.blender.request``: the scene, its photometry and
unit scale and the caller's budget, derived once and passed down, issue 30).
"""

import dataclasses
import math
import time

import numpy as np

from ... import quality as quality_presets
from ...radiometry.sampling import allocation
from ...errors import RadiometerError
from ...radiometry.emitters import EmitterFlags
from ...readings import IlluminanceReading
from ..capture import glass
from ..render import render_settings, rounds, sensors
from . import sample_floors
from ..blender import scene_guard

FLOAT32_FLOOR = rounds.FLOAT32_FLOOR  # (render/rounds.py: the reason and the measurement)


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


# --- deciding how to measure ----------------------------------------------------------------------

def capture_model(scene, view_layer=None, exclude=()):
    """The scene as Cycles renders it (``radiometry.scene.scene_model.SceneModel``, metres)."""
    from ..capture import capture_cache  # the capture, again only when the scene changed (issue 17)

    return capture_cache.capture(scene, view_layer, exclude=exclude)


def plan(scene, model, points_m, normals, method, direct_only=False, proofs=None):
    """Decide how every reading is obtained and say why. Returns a dict (pure data inside).

    ``direct``: the per-light, per-point :class:`~radiometer.radiometry.scene.scene_model.DirectPlan`;
    ``method``: "analytic" when every contribution at every point is a closed form (exact or with a
    bound) and no light can arrive by reflection, else "render" (``auto``), or as requested.
    ``direct_only``: only light straight from the sources is wanted (reflections do not count;
    light from the world or emitting surfaces still needs a render).
    ``proofs``: the ``DirectPlan`` of these points on this model when the caller has it (the parts of one
    ``measure_illuminance(parts=...)``), else proved here.
    """
    from ...radiometry.scene import scene_model

    if method not in quality_presets.METHODS:
        raise RadiometerError(f"unknown method {method!r}; choose one of {', '.join(quality_presets.METHODS)}")
    emitting = [lt for lt in model.lights if not lt.portal]
    if not emitting and not model.world_emits and not model.emissive_surfaces:
        raise RadiometerError("the scene has no light sources (no lights, a black world, no emitting surfaces)")
    direct = _plan_direct(model, points_m, normals) if proofs is None else _copy_plan(proofs)
    world_render = _world_rendered(direct)
    unmodelled = (world_render or bool(model.emissive_surfaces)) if direct_only else direct.indirect.any()
    analytic_ok = np.isin(direct.status, (scene_model.EXACT, scene_model.ZERO, scene_model.BOUNDED)).all() \
        and not unmodelled and not world_render
    reasons = []
    if world_render:
        k = int(np.argmax(direct.world_status == scene_model.RENDER))
        reasons.append("the world emits light" + (f" ({direct.world_reason[k]})" if direct.world_reason[k] else ""))
    if model.emissive_surfaces:
        reasons.append("surfaces emit light")
    if direct.indirect.any() and not direct_only:
        k = int(np.argmax(direct.indirect))
        reasons.append(str(direct.indirect_reason[k]))
    for i, light in enumerate(model.lights):
        render_k = np.flatnonzero(direct.status[i] == scene_model.RENDER)
        if render_k.size:
            reasons.append(f"light {light.name!r}: {direct.reason[i, render_k[0]]}"
                           + (f" (at {render_k.size} of {len(points_m)} points)" if len(points_m) > 1 else ""))
    uncovered = [(lt.name, lt.uncovered) for lt in model.lights if lt.spec is None and not lt.portal
                 and lt.reaches_diffuse]
    if method == "auto":
        chosen = "analytic" if analytic_ok else "render"
    elif method == "hybrid" and analytic_ok and direct.exact_points().all():
        # Nothing is left to render: the hybrid is the closed forms themselves, exactly.
        chosen = "analytic"
    elif method == "analytic" and uncovered:
        raise RadiometerError(
            f"light {uncovered[0][0]!r} {uncovered[0][1]}: no closed form covers it; use method='render'")
    else:
        chosen = method
    exact = np.all(np.isin(direct.status, (scene_model.EXACT, scene_model.ZERO)), axis=0) if direct_only \
        else direct.exact_points()
    closed = closed_form_points(model, direct, method, chosen, direct_only)
    return {"method": chosen, "needs": model.needs, "model": model, "direct": direct, "uncovered": uncovered,
            "reasons": reasons, "analytic_exact": bool(analytic_ok and exact.all()), "exact_points": exact,
            "closed_points": closed & (exact if method == "hybrid" and chosen != "analytic" else True)}


#: The latest proofs (``_plan_direct``): (key, the model parts the key names by identity, DirectPlan).
_LAST_PLAN = [None, None, None]


def _model_parts(model):
    """Every value a ``SceneModel`` holds, its lists' and dicts' items one by one: a capture served again
    from ``capture_cache`` (nothing changed) shares them all, a light read again gives new ones."""
    parts = []
    for field in dataclasses.fields(model):
        value = getattr(model, field.name)
        if isinstance(value, dict):
            parts += [(field.name, key, item) for key, item in value.items()]
        elif isinstance(value, list):
            parts += [(field.name, k, item) for k, item in enumerate(value)]
        else:
            parts.append((field.name, None, value))
    return parts


def _plan_direct(model, points_m, normals):
    """``scene_model.plan_direct(model, points_m, normals)``, kept for the next call when that call has the
    same points and normals and a model made of the same objects (issue 17: a reading repeated on an
    unchanged scene proves the same visibility again otherwise). The model's parts are pure data, never
    changed in place, and the entry holds them, so equal identities mean equal values; the plan handed
    out is a copy (its arrays are the caller's)."""
    from ...radiometry.scene import scene_model

    if model.world is not None:  # read again on every capture served (image pixels): never the same object
        return scene_model.plan_direct(model, points_m, normals)
    parts = _model_parts(model)
    points_m, normals = np.asarray(points_m, float), np.asarray(normals, float)
    key = (tuple((name, k, id(value)) for name, k, value in parts), points_m.shape, points_m.tobytes(),
           normals.tobytes())
    if _LAST_PLAN[0] != key:
        _LAST_PLAN[:] = [key, parts, scene_model.plan_direct(model, points_m, normals)]
    return _copy_plan(_LAST_PLAN[2])


def _copy_plan(kept):
    """A copy of a ``DirectPlan`` whose arrays are the caller's own."""
    return dataclasses.replace(kept, **{f.name: value.copy() for f in dataclasses.fields(kept)
                                        if isinstance(value := getattr(kept, f.name), np.ndarray)})


def closed_form_points(model, direct, method, chosen, direct_only=False):
    """(N,) bool: the meters read from closed forms alone, whatever their neighbours need (issue 18).

    A meter qualifies when every light's contribution there is EXACT, ZERO or BOUNDED, no light can
    reach it by reflection (or, ``direct_only``, no emitting surface needs a render) and the world's
    light there is not rendered. ``method``: as requested; ``chosen``: as planned. A plan of
    "analytic" reads every meter from closed forms; a requested "render" renders every meter (the user
    asked for it). (The hybrid takes only the EXACT ones: ``plan`` intersects.)
    """
    from ...radiometry.scene import scene_model

    n = direct.status.shape[1]
    if chosen == "analytic":
        return np.ones(n, bool)
    if method == "render":
        return np.zeros(n, bool)
    ok = np.all(np.isin(direct.status, (scene_model.EXACT, scene_model.ZERO, scene_model.BOUNDED)), axis=0)
    ok &= ~(np.full(n, bool(model.emissive_surfaces)) if direct_only else np.asarray(direct.indirect, bool))
    if direct.world_status is not None:
        ok &= direct.world_status != scene_model.RENDER
    return ok


def _world_rendered(direct):
    """True when the world's light must be rendered at some receiver (issue 14)."""
    from ...radiometry.scene import scene_model

    return direct.world_status is not None and bool(np.any(direct.world_status == scene_model.RENDER))


def world_irradiance(model, direct, normals):
    """The world's own contribution (N, 3) W/m^2 SI, its absolute error bound (N, 3) and a note, or
    (zeros, zeros, None) when the world is black or not modelled (issue 14). A receiver where the
    world is RENDER (forced analytic) keeps the unoccluded value with a 100 % bound, as lights do."""
    from ...radiometry.scene import scene_model

    n = len(normals)
    zeros = np.zeros((n, 3))
    if direct.world_status is None or not scene_model.world_modelled(model) or model.world.kind == "black":
        return zeros, zeros, None
    e, err = model.world.irradiance(normals)
    unit = model.scale_length ** 2  # world radiance is per scene unit^2 (README "Conventions")
    e, err = e / unit, np.abs(err) / unit
    partial = direct.world_status == scene_model.RENDER
    err = np.where(partial[:, None], np.abs(e), err)
    cut_off = direct.world_status == scene_model.ZERO  # proven unreachable (a sealed shell: scene.sealed)
    e, err = np.where(cut_off[:, None], 0.0, e), np.where(cut_off[:, None], 0.0, err)
    w = model.world
    note = (f"world ({w.kind}{', image ' + repr(w.image) if w.image else ''}, strength {w.strength:g}): "
            "E = integral of L cos(theta) d omega over its pixels, nothing rendered"
            + (f"; {'; '.join(w.notes)}" if w.notes else ""))
    return e, err, note


# --- analytic ---------------------------------------------------------------------------------------

def analytic_irradiance(model, direct, points_m, normals):
    """Per-light direct irradiance (L, N, 3) W/m^2, absolute error bounds (L, N, 3), per-light notes.

    Contributions planned ZERO are exactly 0; RENDER ones (possible partial occlusion, forced
    analytic) keep the unoccluded value with a bound of 100 % (the truth lies between 0 and it).
    """
    from ...radiometry.scene import scene_model

    n_pts = len(points_m)
    per_light = np.zeros((len(model.lights), n_pts, 3))
    bounds = np.zeros_like(per_light)
    info = []
    for i, light in enumerate(model.lights):
        status = direct.status[i]
        if light.spec is None:
            info.append((False, None, f"no closed form: {light.uncovered}"))
            continue
        values, rel = light.spec.relative_irradiance(points_m, normals)  # the emitter's model and relative bound
        rel = np.broadcast_to(np.asarray(rel, float), (n_pts,))
        values = np.where((status == scene_model.ZERO)[:, None], 0.0, values)
        pane_bound = np.zeros(n_pts)
        if direct.transmittance is not None:  # thin panes on the way (issue 18): T, and its bound
            values = values * direct.transmittance[i]
            pane_bound = direct.glass_bound[i]
        partial = status == scene_model.RENDER
        bounds[i] = np.abs(values) * np.where(partial, 1.0, rel + pane_bound)[:, None]
        per_light[i] = values
        exact, model_name, note = light.spec.exactness()
        states = sorted(set(str(r) for r in direct.reason[i]))
        info.append((bool(np.all(np.isin(status, (scene_model.EXACT, scene_model.ZERO)))), model_name,
                     f"{note}; " + " | ".join(states)))
    return per_light, bounds, info


# --- render -----------------------------------------------------------------------------------------

def render_irradiance(request, points_scene, normals, preset, *, needs):
    """Bake the sensors with a FIXED budget (``preset``: samples, texels, bakes, bounces); returns
    (estimates (B, N, 3) in W/m^2 SI, info, render record). Error-targeted readings use
    ``measure.render.adaptive.render_hybrid``.

    ``needs``: what light transport must simulate (``SceneModel.needs``). ``points_scene`` are the
    sensor positions themselves (callers offset meters from surfaces first). The request gives the scene,
    view layer, seed, progress and cancel.
    """
    scene = request.scene
    with scene_guard.preserved_scene(scene) as snapshot:
        record = render_settings.apply(scene, samples=preset["samples"], bounces=preset["bounces"], needs=needs)
        if needs.get("thin_panes"):  # issue 18: planar panes render as thin glass
            record = dict(record, thin_panes=glass.swap_panes(snapshot, needs["thin_panes"]))
        estimates, info = sensors.bake_irradiance(
            scene, request.view_layer, points_scene, normals, samples=preset["samples"], texels=preset["texels"],
            bakes=preset["bakes"], progress=request.progress, cancelled=request.cancelled, seed0=request.seed)
    # Cycles ignores the unit scale: it renders W per scene-unit^2. E_SI = E_render / scale^2.
    return estimates / request.unit_area, info, record


def single_delta_light(decision):
    """True when light arrives only straight from ONE delta light (radius-0 point/spot, sun of angle 0).

    Then next-event estimation has no variance and one sample per texel is exact. With two or more
    lights Cycles picks one light per estimate, which is noisy (three point lights: +13 % at one
    sample), so this shortcut needs exactly one.
    """
    model = decision["model"]
    if model.needs.get("geometry") or model.needs.get("volume") or model.world_emits or model.emissive_surfaces \
            or decision["uncovered"]:
        return False
    emitting = [lt for lt in model.lights if not lt.portal]
    if len(emitting) != 1 or emitting[0].spec is None:
        return False
    spec = emitting[0].spec
    return spec.is_delta  # a point or spot of radius 0, a sun of angle 0


# --- the public entry used by api.py ----------------------------------------------------------------

def sensor_points(points_scene, normals, scale, model=None):
    """Sensor positions (scene units) and their offsets: a meter within a few offsets of a surface is
    raised by a scale-aware epsilon along its normal (``radiometry.scene.scene_model.receiver_offset``),
    so a meter placed on a surface reads the light arriving at that surface instead of the inside
    of the surface in Cycles' float32 geometry; meters in free space stay where they are."""
    from ...radiometry.scene import scene_model

    eps = scene_model.receiver_offset(points_scene, unit_length=1.0 / scale)
    if model is not None:
        g = model.geometry
        key = ("near", id(g), float(scale), np.asarray(points_scene, float).tobytes(), eps.tobytes())
        near = _placement_memo(g, key)
        if near is None:
            near = np.zeros(len(points_scene), bool)
            if g.count:
                for k, p in enumerate(points_scene):
                    near[k] = g.grid.query(p * scale, p * scale, 8 * eps[k] * scale).size > 0
            _placement_memo(g, key, near)
        eps = np.where(near, eps, 0.0)
    return points_scene + normals * eps[:, None], eps


#: (geometry, {key: value}) of the latest geometry: what ``sensor_points`` and ``placement_notes`` found
#: there (they read the triangles alone, which a kept capture shares: issue 17).
_PLACEMENT = [None, {}]


def _placement_memo(geometry, key, value=None):
    """The value kept for ``key`` on ``geometry`` (None if none), or keep ``value`` there. The geometry
    is held, so its ``id`` in the key names it alone; a new geometry starts afresh."""
    if _PLACEMENT[0] is not geometry:
        _PLACEMENT[:] = [geometry, {}]
    if value is None:
        return _PLACEMENT[1].get(key)
    if len(_PLACEMENT[1]) >= 64:
        _PLACEMENT[1].clear()
    _PLACEMENT[1][key] = value
    return value


def placement_notes(model, points_m, normals, eps_m):
    """Notes for meters that lie on a surface (the usual desk case)."""
    from ...radiometry.scene import scene_model

    key = ("notes", id(model.geometry), np.asarray(points_m, float).tobytes(), np.asarray(normals, float).tobytes(),
           np.asarray(eps_m, float).tobytes())
    kept = _placement_memo(model.geometry, key)
    if kept is not None:
        return list(kept)
    notes = []
    on = {}
    for k, (p, n) in enumerate(zip(points_m, normals)):
        if eps_m[k] == 0.0:
            continue
        name, dist = scene_model.surface_under(model.geometry, p - n * eps_m[k], n, within=1e-3)
        if name is not None:
            on.setdefault(name, []).append(k)
    for name, ks in on.items():
        where = f"meter #{ks[0]}" if len(ks) == 1 else f"{len(ks)} meters"
        notes.append(f"{where} on the surface of {name!r}: the sensor sits {eps_m[ks[0]] * 1e6:.2g} um above it "
                     "along its normal and reads the light arriving at that surface")
    _placement_memo(model.geometry, key, tuple(notes))
    return notes


def enclosure_notes(model, points_m, values):
    """For meters that read ~0: say when a closed mesh encloses them (light cannot get in)."""
    from ...radiometry.scene import scene_model

    notes = []
    for k in np.flatnonzero(np.abs(values) <= 1e-12 * max(1.0, float(np.max(np.abs(values))))):
        name = scene_model.enclosing_object(model.geometry, points_m[k])
        if name is not None:
            notes.append(f"meter #{k} is inside the closed mesh {name!r}: no light reaches it")
    return notes


def light_object_key(light):
    """The light OBJECT a ``ModelLight`` comes from, as (session uid, library) of its ``source_id``:
    all instances of one object share it (light linking acts on objects); never its name. A light
    built outside a capture (no ``source_id``) is keyed (0, its name)."""
    sid = light.source_id
    return (sid.object_uid, sid.library) if sid is not None else (0, light.source or light.name)


def hybrid_split(model, direct, count, also=None):
    """Per meter: the light OBJECTS (``light_object_key``) whose direct light is a proven closed form there (EXACT, or
    ZERO because an opaque surface blocks it) for every instance of that object, to be added
    analytically and excluded from the sensor (light linking acts on objects, so all instances of
    an object must qualify). ``also`` (L, N) bool: more contributions known in closed form (a delta
    light through a homogeneous medium, ``through_medium``). Returns a list of frozensets."""
    from ...radiometry.scene import scene_model

    by_source = {}
    for i, light in enumerate(model.lights):
        by_source.setdefault(light_object_key(light), []).append(i)
    out = []
    for k in range(count):
        chosen = set()
        for source, idx in by_source.items():
            ok = all(model.lights[i].spec is not None and not model.lights[i].portal
                     and model.lights[i].reaches_diffuse
                     and (direct.status[i, k] in (scene_model.EXACT, scene_model.ZERO)
                          or _glass_bounded(model.lights[i], direct, i, k)
                          or (also is not None and bool(also[i, k])))
                     for i in idx)
            if ok:
                chosen.add(source)
        out.append(frozenset(chosen))
    return out


#: The planner's reason when a world volume alone stands between a meter and a light it proved clear.
_WORLD_VOLUME_REASON = "the world's volume may lie between"


def through_medium(model, direct, medium):
    """(L, N) bool: contributions whose direct light is a closed form times the medium's exp(-sigma_t d)
    (issue 18): a delta point or spot light (radius 0, exact closed form) that the planner proved
    unoccluded but for a homogeneous world volume (``medium``, or None: nothing)."""
    from ...radiometry.scene import scene_model

    out = np.zeros(direct.status.shape, bool)
    if medium is None:
        return out
    for i, light in enumerate(model.lights):
        spec = light.spec
        if (spec is None or light.portal or not light.reaches_diffuse or EmitterFlags.DELTA_POSITION not in spec.flags
                or not spec.exactness()[0]):
            continue
        out[i] = (direct.status[i] == scene_model.RENDER) & np.array(
            [str(r).startswith(_WORLD_VOLUME_REASON) for r in direct.reason[i]], bool)
    return out


def medium_transmittance(model, points_m, medium, through):
    """(L, N, 3): exp(-sigma_t d) where ``through`` (d: meter to light, m), 1 elsewhere."""
    out = np.ones(through.shape + (3,))
    for i in np.flatnonzero(through.any(axis=1)):
        d = np.linalg.norm(points_m - np.asarray(model.lights[i].spec.position, float), axis=1)
        out[i, through[i]] = medium.transmittance(d[through[i]])
    return out


def mirror_bounds(model, points_m, normals):
    """Sharp mirror images of small lights (issue 18): ((N, 3) W/m^2 bound, ["'light' in 'mirror'"...]).

    For a point, spot or sun light and every meter that sees its image in a triangle of a sharp
    mirror (``glass.mirror_triangles``), the image's closed form with reflectance 1: I(towards the
    mirror point) cos / r^2 from the mirrored position, or the sun's normal irradiance x cos of its
    mirrored direction; one per distinct image (summed). Occlusion is ignored (a bound)."""
    from ...radiometry.scene import visibility

    n = len(points_m)
    out = np.zeros((n, 3))
    small = [(i, lt) for i, lt in enumerate(model.lights)
             if lt.spec is not None and not lt.portal and lt.reaches_diffuse and lt.spec.may_render_small]
    if not small or not model.geometry.count:
        return out, []
    tris, owners = glass.mirror_triangles(model)
    if not len(tris):
        return out, []
    names = set()
    for i, light in small:
        spec = light.spec
        sun = not spec.has_position
        to_sun = -np.asarray(spec.emission_direction, float) if sun else None
        if sun:
            e_normal = spec.irradiance_at(points_m[:1], to_sun[None, :])[0][0]
        for k in range(n):
            hit, image, at = visibility.mirror_images(points_m[k], tris, None if sun else spec.position, to_sun)
            seen = set()
            for j in np.flatnonzero(hit):
                key = tuple(np.round(image[j], 9))
                if key in seen:
                    continue
                seen.add(key)
                if sun:
                    out[k] += e_normal * max(0.0, float(normals[k] @ image[j]))
                else:
                    d = image[j] - points_m[k]
                    r = float(np.linalg.norm(d))
                    cos = max(0.0, float(normals[k] @ d) / r)
                    out[k] += spec.intensity_towards(at[j] - np.asarray(spec.position, float)) * cos / r ** 2
            if seen:
                names.add(f"{light.name!r} in {owners[np.flatnonzero(hit)[0]]!r}")
    return out, sorted(names)


def world_floor(model, direct):
    """(N,) samples each meter takes at least, or None (issue 18): DARK_FLOOR where the world's light is
    rendered there and the world has no closed form (``scene_model.world_modelled``: sky textures, node
    worlds such as one-patch skies), whose small bright regions a pilot misses while its variance
    looks tiny."""
    from ...radiometry.scene import scene_model

    if direct.world_status is None or not model.world_emits or scene_model.world_modelled(model):
        return None
    rendered = np.asarray(direct.world_status == scene_model.RENDER, bool)
    return np.where(rendered, allocation.DARK_FLOOR, 0) if rendered.any() else None


def may_be_lit(direct, direct_only=False):
    """(N,) bool: meters that rendered light may reach by a path a pilot can miss (issue 18): a
    reflecting surface above the horizon, a light that must be rendered there, or the world."""
    from ...radiometry.scene import scene_model

    out = np.any(direct.status == scene_model.RENDER, axis=0)
    if not direct_only:
        out = out | np.asarray(direct.indirect, bool)
    if direct.world_status is not None:
        out = out | (direct.world_status == scene_model.RENDER)
    return out


def glass_notes(model):
    """Notes naming every thin pane and how it was read, and every refractor rendered as it is."""
    notes = []
    seen = set()
    for pane in model.panes.values():
        if pane.source in seen:
            continue
        seen.add(pane.source)
        trick = " (the 'Is Shadow Ray' trick read as the real pane, not transmittance 1)" if pane.trick else ""
        notes.append(f"thin glass {pane.name!r}: {pane.model}{trick}; exact Fresnel at both interfaces with "
                     "internal reflections, light continuing undeflected (lateral shift not modelled); rendered "
                     "as a thin pane (transparent + specular shader swapped in for the measurement)")
    rough = model.needs.get("rough_refractors", ())
    for name, why in model.refractors:
        notes.append(f"{name!r} transmits light but is not a thin pane ({why}): rendered as it is"
                     + ("; its refraction is rough enough that light sampling finds small lights through it: "
                        "a stochastic error like any glossy path, no caustic bound" if name in rough else ""))
    notes += glass.stack_notes(model)  # multiple glazing: rendered whole as a stand-in, or what it misses
    return notes


def caustic_risk(model, direct, split, sensors_m=None):
    """(L, N) bool: a small light (delta, sun, or a sphere/area light seen under a small angle) that
    is rendered at a meter because a refractor (``model.refractors``) may stand on its way there: the
    planner's reason names it, or (``sensors_m`` (N, 3) m given) its bounding box meets the region
    between the meter and the light (``scene_model.boxes_on_paths``)."""
    from ...radiometry.scene import scene_model

    out = np.zeros(direct.status.shape, bool)
    # Rough refraction is no caustic: light sampling at the refraction vertex finds the light (glass.ROUGH_REFRACTION).
    rough = model.needs.get("rough_refractors", ())
    names = [name for name, _why in model.refractors if name not in rough]
    if not names:
        return out
    # The planner's reason names one blocker; a refractor farther along is found by its box (issue 32:
    # a rejected roof pane behind a wall read the sun 0 lx +-inf).
    g = model.geometry
    wanted = set(names)
    boxes = [(g.object_names[k], corners.min(axis=0), corners.max(axis=0))
             for k, _verts, corners, _e in g.object_vertices() if g.object_names[k] in wanted]
    points = sensors_m if sensors_m is not None else np.zeros((0, 3))
    for i, light in enumerate(model.lights):
        spec = light.spec
        if spec is None or not spec.may_render_small:  # area lights: not small
            continue
        rendered = [k for k in range(direct.status.shape[1]) if direct.status[i, k] == scene_model.RENDER
                    and not (split and light_object_key(light) in split[k])]
        named = [k for k in rendered if any(repr(nm) in str(direct.reason[i, k]) for nm in names)]
        out[i, named] = True
        rest = [k for k in rendered if k not in named]
        if rest and boxes and len(points):
            on = scene_model.boxes_on_paths(spec, points[rest], boxes, scene_model.length_tolerance(points),
                                            scene_model.scene_reach(g, points))
            out[i, np.asarray(rest)[on != None]] = True  # noqa: E711 - object array
    return out


def _glass_bounded(light, direct, i, k):
    """True when light i at meter k is BOUNDED only by the spread of a thin pane's T over the light's
    extent (its own closed form is exact; issue 18): its closed form is added with that bound,
    stated in the reading."""
    from ...radiometry.scene import scene_model

    return (direct.status[i, k] == scene_model.BOUNDED and direct.glass_bound is not None
            and direct.glass_bound[i, k] > 0.0 and bool(light.spec.exactness()[0]))


def _budget_mode(preset, target_rel_error, samples, time_budget_s):
    """(target, time budget s, fixed samples) from the user's choice; exactly one rule drives it."""
    if samples is not None:
        if not (float(samples) >= 1 and math.isfinite(float(samples))):
            raise RadiometerError(f"samples must be a whole number >= 1 per meter, got {samples}")
        return None, None, int(samples)
    if time_budget_s is not None:
        if not (float(time_budget_s) > 0 and math.isfinite(float(time_budget_s))):
            raise RadiometerError(f"time_budget_s must be > 0 seconds, got {time_budget_s}")
        return (float(target_rel_error) if target_rel_error is not None else None), float(time_budget_s), None
    if target_rel_error is not None:
        if not (0 < float(target_rel_error) < 1):
            raise RadiometerError(f"target_rel_error must be in (0, 1), got {target_rel_error}")
        return float(target_rel_error), None, None
    return float(preset["target"]), None, None


def _world_medium(scene, model):
    """The homogeneous world volume (``measure.capture.media.world_medium``) when it is the scene's only medium."""
    if not model.world_volume or model.volumes:
        return None
    from ..capture import media

    return media.world_medium(scene)


def _plan_at(direct, idx):
    """The DirectPlan restricted to the receivers ``idx`` (per-receiver arrays cut on their first
    axis, per-light-and-receiver arrays on their second)."""
    import dataclasses

    per_receiver = {"indirect", "indirect_reason", "world_status", "world_reason"}
    cut = {}
    for field in dataclasses.fields(direct):
        value = getattr(direct, field.name)
        if isinstance(value, np.ndarray):
            cut[field.name] = value[idx] if field.name in per_receiver else value[:, idx]
    return dataclasses.replace(direct, **cut)


def _closed_form_part(model, decision, sensors_m, normals, direct_only):
    """Closed-form readings at every meter: mean (N, 3) and bound (N, 3) W/m^2 SI, notes and parts
    per meter. The caller keeps the meters that ``plan`` found need no render."""
    from ...radiometry.scene import scene_model

    direct = decision["direct"]
    n = len(sensors_m)
    per_light, bounds, info = analytic_irradiance(model, direct, sensors_m, normals)
    world_rgb, world_bound, world_note = world_irradiance(model, direct, normals)
    head = ["analytic direct light: " + "; ".join(f"{lt.name}: {m} ({n_})" for lt, (_e, m, n_) in
                                                  zip(model.lights, info))]
    if world_note:
        head.append(world_note)
    exact = np.asarray(decision["exact_points"], bool)
    forced = decision["method"] == "analytic" and not decision["analytic_exact"]
    notes, parts = [], []
    for k in range(n):
        mine = list(head)
        if str(direct.indirect_reason[k]).startswith("sealed off"):  # scene.sealed: every source cut off
            mine.append(str(direct.indirect_reason[k]))
        if exact[k]:
            mine.append("exact: every contribution is a closed form and nothing can reflect or block it")
        elif forced and decision["reasons"]:
            mine.append("NOT exact for this scene: " + ", ".join(decision["reasons"]))
        else:
            why = [f"light {lt.name!r}: {direct.reason[i, k]}" for i, lt in enumerate(model.lights)
                   if direct.status[i, k] != scene_model.EXACT and direct.status[i, k] != scene_model.ZERO]
            if direct.world_status is not None and direct.world_status[k] not in (scene_model.EXACT, scene_model.ZERO):
                why.append(f"world: {direct.world_reason[k]}")
            mine.append("NOT exact at this meter: " + ("; ".join(why) or "quadrature"))
        if direct.indirect[k] and not direct_only:
            mine.append("direct light only: light reflected by surfaces or from the world is NOT included")
        notes.append(mine)
        parts.append({"analytic": [lt.name for lt in model.lights] + (["world"] if world_note else []),
                      "rendered": []})
    return per_light.sum(axis=0) + world_rgb, bounds.sum(axis=0) + world_bound, notes, parts


@dataclasses.dataclass
class ProvenPart:
    """A part of the light at every meter that the caller proved in closed form (or bounded) and keeps out
    of what Cycles renders (issue 31: the daylight factor's sky component, the world's direct emission
    gated off, or the openings' emitters). ``rgb`` (N, 3) W/m^2 SI, ``name`` for the reading's parts,
    ``linked_out``: identities (session uid, library) of the objects linked out of every sensor (the
    openings' emitters), ``bound_rgb`` (N, 3) W/m^2: the part's own hard bound (a pane's T(theta) by
    subdivision), counted in the error as the meter's other bounds. ``covers_world``: the part is ALL the light
    that comes straight from the world to each meter (the sky and the ground through proven openings): where
    no light is rendered and nothing can reflect or emit towards a meter (every surface above its horizon
    black, a quiet pane, no medium), the render would read exactly 0 and the reading is this part alone."""

    rgb: object
    name: str
    linked_out: frozenset = frozenset()
    bound_rgb: object = 0.0
    covers_world: bool = False
    #: a ``surface_gather.GatherPlan`` whose wall cells every one of these meters sees whole: the rest is gathered
    #: from bakes on the walls (``surface_gather.measure``), not rendered at the meters
    gather: object = None

    def per_meter(self, n):
        """This part with ``rgb`` and ``bound_rgb`` as (n, 3) arrays."""
        return dataclasses.replace(self, rgb=np.broadcast_to(np.asarray(self.rgb, float), (n, 3)),
                                   bound_rgb=np.broadcast_to(np.asarray(self.bound_rgb, float), (n, 3)),
                                   linked_out=frozenset(self.linked_out))

    def at(self, idx):
        """This part at the meters ``idx`` (after ``per_meter``)."""
        return dataclasses.replace(self, rgb=self.rgb[idx], bound_rgb=self.bound_rgb[idx])


def _render_part(request, model, decision, direct, sensors_scene, sensors_m, normals, *, preset,
                 method, direct_only, target, budget, fixed, n_closed,
                 target_abs=None, medium=None, pooling=False, stop_dark=False, proven=None):
    """Cycles (hybrid or render) at the meters that need it; ``direct`` is the plan cut to them
    (``_plan_at``), as are the sensors and normals. ``proven``: a :class:`ProvenPart` cut to them, kept
    out of the render, added to it and counted in the target.
    Returns a dict: mean_rgb, bound_rgb, se_rgb (M, 3), se, samples (M,), method, record, notes
    (common to these meters), parts (per meter)."""
    from ..render import adaptive

    n = len(sensors_scene)
    notes = []
    # Two kinds of hard bound, added up below: the closed forms' own (a pane's T(theta) over a light's extent or
    # over a proven part) and those on light the render may miss (a caustic's, a mirror image's, the light
    # between stacked panes); only the second can stand for what a dark meter's render did not find.
    bound_rgb = np.zeros((n, 3))
    missing_rgb = np.zeros((n, 3))
    if fixed is None and single_delta_light(decision):
        # Next-event estimation samples a single delta light exactly: every path gives the same
        # value, so one sample per texel is the exact render (more would only add float32 rounding).
        fixed = allocation.MIN_BLOCKS * allocation.BLOCK_TEXELS ** 2
        notes.append("a single delta light and nothing to reflect light: 1 sample per texel is exact "
                     "(next-event estimation of one delta light has no variance)")
    hybrid = method in ("auto", "hybrid")
    through = through_medium(model, direct, medium) if hybrid else np.zeros(direct.status.shape, bool)
    split = hybrid_split(model, direct, n, also=through) if hybrid else [frozenset()] * n
    linked_out = proven.linked_out if proven is not None else frozenset()
    offset_rgb = np.zeros((n, 3))
    # Light bouncing between the panes of multiple glazing: a stand-in pane renders it (glass.stand_in_stacks);
    # separate thin panes do not, so where any stack stays separate a rendered light's share is a bound.
    stacked = (direct.interpane is not None and bool(np.any(direct.interpane > 0))
               and not glass.stacks_rendered_whole(model.panes))
    if any(split) or stacked:
        per_light, light_bounds, _info = analytic_irradiance(model, direct, sensors_m, normals)
        if through.any():
            # Issue 18: the direct light through a homogeneous world volume is its closed form times
            # exp(-sigma_t d) (no bound beyond thin glass's); the volume's in-scattered light is rendered.
            per_light = per_light * medium_transmittance(model, sensors_m, medium, through)
            pane_bound = direct.glass_bound if direct.glass_bound is not None else np.zeros(through.shape)
            light_bounds = np.where(through[..., None], np.abs(per_light) * pane_bound[..., None], light_bounds)
            names = sorted({lt.name for i, lt in enumerate(model.lights) if through[i].any()})
            notes.append(f"{medium.name}: sigma_t = {', '.join(f'{v:.4g}' for v in medium.sigma_t)} 1/m (RGB); "
                         f"the direct light of {', '.join(repr(x) for x in names)} is its closed form x "
                         "exp(-sigma_t d), d the meter-light distance (homogeneous medium, Beer-Lambert); "
                         "the light the medium scatters towards the meter is rendered")
        for i, light in enumerate(model.lights):
            take = np.array([light_object_key(light) in split[k] for k in range(n)])
            offset_rgb[take] += per_light[i, take]
            bound_rgb[take] += light_bounds[i, take]  # thin glass over a light's extent (issue 18)
            if stacked:
                # Rendered through two or more panes, the light bouncing between them is a
                # specular chain to the light that no render finds: counted as a bound.
                missing = ~take & (direct.interpane[i] > 0)
                missing_rgb[missing] += np.abs(per_light[i, missing]) * direct.interpane[i, missing, None]
    if proven is not None:
        offset_rgb += proven.rgb
        bound_rgb += np.abs(proven.bound_rgb)  # the proven part's own hard bound (a pane's T(theta))
    caustic = caustic_risk(model, direct, split, sensors_m)
    if caustic.any():
        per_light, _b, _i = analytic_irradiance(model, direct, sensors_m, normals)
        missing_rgb += np.einsum("ln,lnc->nc", caustic, np.abs(per_light))
        notes.append("caustic light may be missing: a small light reaches some meter only through a refracting "
                     "object that is not a thin pane (Cycles rarely finds such paths); its unoccluded closed "
                     "form is counted as the error bound, not a small error")
    mirrored, names = mirror_bounds(model, sensors_m, normals)
    if names:
        missing_rgb += mirrored
        notes.append(f"a sharp mirror image of a small light may be missing ({'; '.join(names)}): a path tracer "
                     "rarely finds a small light seen in a sharp mirror (a caustic); the image's closed form "
                     "(reflectance 1, occlusion ignored) is counted as the error bound, not a small error")
    if stacked and missing_rgb.any():
        notes.append("light bouncing between panes of multiple glazing rendered as separate thin panes: its "
                     "closed-form share for the rendered direct light is counted in the stated error bound (a "
                     "render of separate thin panes does not find it)")
    bound_rgb = bound_rgb + missing_rgb
    floor = world_floor(model, direct)
    if floor is not None and fixed is None:
        notes.append(f"the world's light is rendered from a world with no closed form (small bright regions, a sun "
                     f"disc or a sky patch come by rare paths): at least {allocation.DARK_FLOOR:,} samples per "
                     "such meter before the error is trusted (issue 18: a 256-sample pilot read a one-patch "
                     "world 0.8 % low while stating 0.04 %)")
    highlight, lit_by = sample_floors.highlight_floor(model, sensors_m, normals)
    if highlight is not None and fixed is None:
        floor = highlight if floor is None else np.maximum(floor, highlight)
        notes.append(f"a light's glossy highlight may reach some meter(s) ({'; '.join(lit_by)}): a small bright "
                     f"region a pilot can miss, so up to {int(highlight.max()):,} samples per such meter (about "
                     f"{sample_floors.HIGHLIGHT_HITS} paths expected to find it) before the error is trusted "
                     "(issue 18: 512-sample pilots read a roughness-0.15 floor's highlight 25-29 % low)")
    parts = [{"analytic": [lt.name for lt in model.lights if light_object_key(lt) in split[k]]
              + ([proven.name] if proven is not None else []),
              "rendered": ["everything else (reflected light, other lights, world, emitting surfaces)"]}
             for k in range(n)]
    weights = request.weights
    if proven is not None and proven.gather is not None and fixed is None and budget is None and target is not None:
        from . import surface_gather

        run = surface_gather.measure(request, model, proven.gather, sensors_m, normals, offset_rgb @ weights,
                                     target=target, target_abs=target_abs)
        notes.append(f"the light the room's surfaces reflect gathered from {run['cells']:,} cells of its walls: "
                     f"{run['draws']} independent draws of a random point in each, its irradiance baked there (one "
                     "sample, the openings' emitters sampled as lights) times rho / pi, weighed by each meter's own "
                     "cos cos / r^2 x the cell's area; unbiased, the same bakes for every meter, the error from batch "
                     "means over the draws (radiometry/sampling/surface_gather.py)")
        parts = [{"analytic": [proven.name], "rendered": ["the light the room's surfaces reflect (gathered)"]}
                 for _k in range(n)]
    else:
        run = adaptive.render_hybrid(request, sensors_scene, normals, needs=model.needs,
                                     bounces=0 if direct_only else preset["bounces"], target=target,
                                     time_budget=budget, fixed_samples=fixed,
                                     exclusions=[ex | linked_out for ex in split] if linked_out else split,
                                     offset=offset_rgb @ weights,
                                     panes=model.panes, may_be_lit=may_be_lit(direct, direct_only),
                                     min_samples=floor, pooled=pooling, target_abs=target_abs,
                                     stop_dark=stop_dark)
    mean_rgb = run["mean_rgb"] + offset_rgb
    # Issue 18 (F3): Cycles computes and accumulates in float32, so no rendered part is known better
    # than its float32 rounding, even where every sample agrees (one delta light: batch-means s.e. ~0);
    # per channel too (issue 32: std_error_rgb stated 0 for a rendered part).
    se_rgb = np.hypot(np.nan_to_num(run["se_rgb"]), FLOAT32_FLOOR * np.abs(run["mean_rgb"]))
    scalar_se = np.hypot(np.nan_to_num(run["se"]), FLOAT32_FLOOR * np.abs(run["mean_rgb"] @ weights))
    dark = np.asarray(run.get("dark", np.zeros(n, bool)), bool)
    upper = np.full(n, np.nan)
    if dark.any():
        # Issue 18: no rendered light found although some may arrive (a small bright region past
        # an obstruction): the error is unknown, never 0, also where closed forms add light (hybrid),
        # unless a deterministic bound (a caustic's closed form) already states what may be missing.
        # A pane's quadrature bound on a proven part says nothing of what the render missed (issue 31: a
        # dark meter under a proven sky component through a pane stated only that bound).
        unbounded = dark & ~(np.abs(missing_rgb) @ np.abs(weights) > 0.0)
        taken = int(run['samples'][dark].min())
        if stop_dark and target_abs is not None and fixed is None:
            # Issue 31: the meter stopped after its pilot; it states the absolute floor as a one-sided bound.
            scalar_se = np.where(unbounded, target_abs, scalar_se)
            upper = np.where(unbounded, target_abs, np.nan)
            floor_lux = target_abs * request.efficacy
            notes.append(f"{int(dark.sum())} meter(s) found no rendered light in {taken:,} samples (their pilot) "
                         "although lit surfaces or partly hidden lights lie above their horizon: by the rule of "
                         f"three, fewer than 3/{taken:,} of their sample paths carry light (95 %); they read 0 and "
                         f"state the absolute floor {floor_lux:.3g} lx as a one-sided bound, which holds "
                         f"unless one light-carrying sample would carry more than {taken / 3:,.0f} x that floor (a "
                         "small bright region seen past an obstruction can: measure it with a relative target and "
                         "target_abs_error=0 to sample on)")
        else:
            scalar_se = np.where(unbounded, np.inf, scalar_se)
            notes.append(f"{int(dark.sum())} meter(s) found no rendered light in {taken:,}+ samples "
                         "although lit surfaces or partly hidden lights lie above their horizon: light from a small "
                         "bright region may be missing, so their error is unknown (stated as infinite unless a "
                         "caustic's bound states it)")
    spent = run["samples"]
    why = "; ".join(decision["reasons"]) or "requested"
    rule = (f"{fixed} samples per meter" if fixed is not None else
            f"time budget {budget:g} s" + (f", target {100 * target:g} %" if target else "")
            if budget is not None else f"target {100 * target:g} % (1 s.e.)")
    notes.append(f"rendered with Cycles ({why}); {rule}: {run['rounds']} rounds, {run['groups']} sensor "
                 f"group(s), samples per meter {int(np.min(spent))}..{int(np.max(spent))}; standard error from "
                 "batch means over independent texels")
    if n_closed:
        notes.append(f"{n} of {n + n_closed} meters rendered; the other {n_closed} need no render (closed forms "
                     "of every contribution, nothing to reflect light there) and were read from them")
    if any(split):
        keys = set().union(*split)  # light objects by identity: name them for the note
        names = sorted({lt.source or lt.name for lt in model.lights if light_object_key(lt) in keys})
        notes.append(f"hybrid: direct light of {', '.join(repr(x) for x in names)} added from closed forms "
                     "where proven (excluded from the sensor by light linking); Cycles rendered the rest")
    if target is not None and not run["reached"]:
        missed = int(np.sum(np.nan_to_num(scalar_se) > np.maximum(target * np.abs(run["mean_rgb"] @ weights
                                                                                     + offset_rgb @ weights),
                                                                   0.0 if target_abs is None else target_abs)))
        notes.append(f"target {100 * target:g} % NOT reached at {missed} of {n} rendered meter(s) ({run['stopped']}; "
                     f"at most {allocation.MAX_SAMPLES_PER_METER:,} samples per meter)")
    record = run["record"]
    if record and record.get("volume_bounces"):
        notes.append(f"a participating medium: up to {record['volume_bounces']} volume scatterings per path "
                     "(light in a medium that does not absorb fades slowly with its order of scattering: in an "
                     "open fog 16 read 0.24 % low, 128 0.05 %, bench/volume_bounces.md)")
    if record and record.get("settings_missing"):
        notes.append("render settings this Blender lacks (skipped): " + "; ".join(record["settings_missing"]))
    if request.scale_length != 1.0:
        notes.append(f"unit scale {request.scale_length:g} m per unit: Cycles' scene-unit result divided by scale²")
    methods, meter_notes = pooled_notes(run, "hybrid" if any(split) else "render", n)
    return {"mean_rgb": mean_rgb, "bound_rgb": bound_rgb, "se_rgb": se_rgb, "se": scalar_se, "samples": spent,
            "upper": upper,
            "method": methods, "record": record, "notes": notes, "parts": parts, "meter_notes": meter_notes}


def pooled_notes(run, method, n):
    """Per rendered meter: its method (``method``, or ``method + '+pooled'`` where the reading is a pooled
    field's) and its own notes saying how it was pooled, held out or refused (issue 17)."""
    from ...radiometry.sampling import pooled_field

    methods = np.full(n, method, dtype=object)
    notes = [[] for _ in range(n)]
    for g in run.get("pool_groups") or []:
        c = g.check
        if c.passed and len(g.pooled):
            methods[g.pooled] = method + "+pooled"
            took = np.asarray(run["samples"])[g.pooled]  # what the fit used (refused meters sample on)
            text = (f"pooled (issue 17): the rendered part is a smooth field (Legendre polynomial of degree "
                    f"{g.fit.degree} in the meters' plane) fitted over {g.fit.meters} meters of this plane, "
                    f"{int(took.min()):,}-{int(took.max()):,} samples each (by the field's leverage); its error is the fit's standard error (+) "
                    f"the misfit measured on {c.held_out} held-out meters sampled on their own "
                    f"({100 * pooled_field.CONFIDENCE:g} % upper bound {c.misfit_upper:.3g} W/m², estimate "
                    f"{c.misfit:.3g} W/m²); a mean misfit over the plane, never exact")
            for k in g.pooled:
                notes[k].append(text)
        for k in g.held_out:
            notes[k].append(f"held out to check a pooled field over {len(g.fitted) + len(g.held_out)} meters: "
                            "read on its own samples")
        refused = np.setdiff1d(g.fitted, g.pooled if g.pooled is not None else [])
        why = c.reason if not c.passed else (
            f"the field does not follow the meters here (a sharp feature: {c.flagged} meters) or its error "
            "misses the target")
        for k in refused:
            notes[k].append(f"not pooled ({why}): read on its own samples")
    return methods, notes


def measure_illuminance(location, normal, request, *, method="auto", exclude=(), direct_only=False, model=None,
                        pooling=True, stop_dark=False, proven=None, parts=None, proofs=None):
    """Readings (one per location) of irradiance/illuminance. See ``radiometer.api``.

    ``request``: a ``measure.blender.request.Request`` (scene, view layer, photometry, unit scale, the
    budget: quality, target_rel_error, samples, time_budget_s, target_abs_error; seed, progress, cancelled).

    ``direct_only``: light straight from the sources only (closed forms where proven, else Cycles
    with 0 bounces): what the scene's surfaces reflect is left out, their shadows are kept.
    ``model``: this scene's ``SceneModel`` (with ``exclude`` applied) when an analysis already has it
    for the scene as it is now (issue 17: capture once); None captures it.
    ``pooling``: with a target, groups of at least ``pooled_field.POOL_MIN_METERS`` rendered meters on
    one plane read their rendered part from a fitted field checked on held-out meters (issue 17).
    The request's ``target_abs_error``: the absolute floor of the 1-sigma error in lux (None: the preset's
    ``target_abs_lux``); a meter stops where its error is below it or below the relative target.
    ``stop_dark``: a meter whose pilot finds no light stops there and states the rule-of-three bound
    (see ``radiometer.api.measure_illuminance``); "all": where one does, every meter stops after its pilot
    (a caller that then reads them another way: the sun study's low sun).
    ``proven``: a :class:`ProvenPart` the caller proved (or bounded) and keeps out of what Cycles renders;
    it is added to the rendered rest, the relative target counts it, and every meter is rendered (the
    meter's own closed forms would count that part again).
    ``parts``: names from ``PARTS`` ("total": all the light, "direct": light straight from the sources, as
    ``direct_only``); returns {part: readings} from one capture and one visibility proof
    (:func:`measure_parts`); the request's ``target_rel_error`` may then be a dict by part. ``proofs``: the
    points' ``DirectPlan`` on ``model`` (``measure_parts`` hands it down).
    """
    if parts is not None:
        return measure_parts(location, normal, parts, request, method=method, exclude=exclude, model=model,
                             pooling=pooling, stop_dark=stop_dark, proven=proven, direct_only=direct_only)
    scene, view_layer = request.scene, request.view_layer
    points_scene, single = as_points(location)
    normals = as_directions(normal, len(points_scene))
    preset = request.preset()
    target, budget, fixed = _budget_mode(preset, request.target_rel_error, request.samples, request.time_budget_s)
    scale = request.scale_length
    started = time.perf_counter()
    model = capture_model(scene, view_layer, exclude=exclude) if model is None else model
    from ..capture import capture_cache  # keeps that capture valid across this measurement's own bakes (issue 17)

    watch = capture_cache.Watch(scene, view_layer, exclude)
    request = request.but(progress=watch.wrap(request.progress), cancelled=watch.wrap(request.cancelled))
    sensors_scene, eps = sensor_points(points_scene, normals, scale, model)
    sensors_m, eps_m = sensors_scene * scale, eps * scale
    decision = plan(scene, model, sensors_m, normals, method, direct_only=direct_only, proofs=proofs)
    space, weights, efficacy = request.photometry
    notes = [f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}"]
    target_abs_error = request.target_abs_error
    floor_lux = preset["target_abs_lux"] if target_abs_error is None else float(target_abs_error)
    abs_floor = None if target is None or not floor_lux > 0 else floor_lux / efficacy  # W/m^2, CIE Y weighted
    if abs_floor is not None:
        notes.append(f"absolute error floor {floor_lux:g} lx (1 s.e.): a meter stops where its error is below "
                     f"it or below the relative target, whichever is larger (issue 31)")
    if direct_only:
        notes.append("direct light only (requested): light reflected by surfaces is NOT included (rendered "
                     "parts use 0 bounces); shadows are")
    notes += [note for light in model.lights for note in light.notes]
    notes += placement_notes(model, sensors_m, normals, eps_m)
    notes += glass_notes(model)
    n = len(points_scene)
    direct = decision["direct"]
    closed = np.asarray(decision["closed_points"], bool)
    alone = np.zeros(n, bool)  # the caller's proven part is all the light there (ProvenPart.covers_world)
    if proven is not None:
        proven = proven.per_meter(n)
        # Every meter is rendered (the meter's own closed forms would count the proven part again), except one
        # sealed off from every source (radiometry/scene/sealed.py): exactly 0, when the caller's part is 0 there
        # too (a part the caller proved non-zero behind a shell that the proof says no light crosses: rendered).
        sealed = np.array([str(r).startswith("sealed off") for r in direct.indirect_reason], bool)
        closed = (sealed & ~np.any(proven.rgb != 0.0, axis=1) & ~np.any(proven.bound_rgb != 0.0, axis=1)
                  & np.asarray(decision["exact_points"], bool))
        if proven.covers_world:  # issue 31: a black room's daylight is the proven part alone
            from ...radiometry.scene import scene_model

            quiet_lights = (np.all(direct.status == scene_model.ZERO, axis=0) if len(model.lights)
                            else np.ones(n, bool))
            # (a meter the sealing proof cuts off while the caller's part is not 0: rendered, as above; the world's
            # own status is not asked: covers_world says the caller's part is all of the world's direct light)
            alone = quiet_lights & ~np.asarray(direct.indirect, bool) & ~closed & ~sealed
    mean_rgb, bound_rgb = np.zeros((n, 3)), np.zeros((n, 3))
    se_rgb, scalar_se, spent = np.zeros((n, 3)), np.zeros(n), np.zeros(n)
    upper = np.full(n, np.nan)  # one-sided 95 % bound (W/m^2) of a meter that found no light (issue 31)
    own_notes = [[] for _ in range(n)]
    parts = [{"analytic": [], "rendered": []} for _ in range(n)]
    methods = np.full(n, "analytic", dtype=object)
    record = None
    if closed.any():
        c_mean, c_bound, c_notes, c_parts = _closed_form_part(model, decision, sensors_m, normals, direct_only)
        mean_rgb[closed], bound_rgb[closed] = c_mean[closed], c_bound[closed]
        for k in np.flatnonzero(closed):
            own_notes[k], parts[k] = c_notes[k], c_parts[k]
    for k in np.flatnonzero(alone):
        # nothing is left to render: no light is, and no surface above the meter's horizon can send light
        mean_rgb[k], bound_rgb[k] = proven.rgb[k], np.abs(proven.bound_rgb[k])
        own_notes[k] = [f"{proven.name} is all the light here: no light is rendered and nothing above the meter's "
                        "horizon can reflect or emit (its surfaces are black: a Diffuse BSDF of colour 0, or quiet "
                        "panes), so what Cycles would render is exactly 0 and nothing was rendered"]
        parts[k] = {"analytic": [proven.name], "rendered": []}
    closed = closed | alone
    rendered = np.flatnonzero(~closed)
    if rendered.size:
        run = _render_part(request, model, decision, _plan_at(direct, rendered),
                           sensors_scene[rendered], sensors_m[rendered], normals[rendered], preset=preset,
                           method=method, direct_only=direct_only, target=target, budget=budget,
                           fixed=fixed, n_closed=int(closed.sum()), medium=_world_medium(scene, model), pooling=pooling,
                           target_abs=abs_floor, stop_dark=stop_dark,
                           proven=None if proven is None else proven.at(rendered))
        mean_rgb[rendered], bound_rgb[rendered] = run["mean_rgb"], run["bound_rgb"]
        se_rgb[rendered], scalar_se[rendered], spent[rendered] = run["se_rgb"], run["se"], run["samples"]
        upper[rendered] = run["upper"]
        methods[rendered], record = run["method"], run["record"]
        for j, k in enumerate(rendered):
            own_notes[k], parts[k] = list(run["notes"]) + run["meter_notes"][j], run["parts"][j]
    exact_points = ((closed & ~alone & np.asarray(decision["exact_points"], bool))
                    | (alone & ~np.any(bound_rgb != 0.0, axis=1)))  # the proven part alone: exact but for its bound
    seconds = time.perf_counter() - started
    scalar_mean = mean_rgb @ weights
    scalar_bound = np.abs(bound_rgb) @ np.abs(weights)
    notes += enclosure_notes(model, sensors_m, scalar_mean)
    readings = []
    for k in range(n):
        e = float(scalar_mean[k])
        # 1-sigma uncertainty: the stochastic standard error, plus a deterministic bound counted
        # as one sigma (conservative: 3 sigma then covers 3 bounds).
        abs_err = math.hypot(float(scalar_se[k]), float(scalar_bound[k]))
        rel = abs_err / abs(e) if e != 0 else (0.0 if abs_err == 0 else math.inf)
        rel_bound = float(scalar_bound[k] / abs(e)) if e != 0 else (0.0 if scalar_bound[k] == 0 else math.inf)
        if e == 0 and np.isnan(upper[k]) and 0 < abs_err < math.inf:
            # A zero reading has no finite relative error: its absolute one is stated as a one-sided bound
            # (the deterministic bound, e.g. a caustic's closed form, plus 2 standard errors; issue 32).
            upper[k] = float(scalar_bound[k]) + 2.0 * float(scalar_se[k])
        readings.append(IlluminanceReading(
            irradiance_rgb=tuple(float(v) for v in mean_rgb[k]), irradiance=e, illuminance=efficacy * e,
            rel_std_error=rel, method=str(methods[k]), samples=int(spent[k]), seconds=seconds / n,
            efficacy=efficacy, colour_space=space, location=tuple(points_scene[k]), normal=tuple(normals[k]),
            exact=bool(exact_points[k]), std_error_rgb=tuple(float(v) for v in se_rgb[k]),
            notes=list(notes) + own_notes[k], render_settings=None if closed[k] else record,
            rel_error_bound=rel_bound, target_rel_error=target, parts=parts[k],
            upper_bound_lux=None if np.isnan(upper[k]) else float(efficacy * (e + upper[k]))))
    watch.done()  # only on success, after the guard restored the scene
    return readings[0] if single else readings


#: The parts of the light one ``measure_illuminance(parts=...)`` call reads: "total" (everything the
#: meter sees) and "direct" (straight from the sources: what ``direct_only=True`` reads).
PARTS = ("total", "direct")


def measure_parts(location, normal, parts, request, *, exclude=(), model=None, direct_only=False, **options):
    """{part: readings} for ``parts`` (names from ``PARTS``) at the same meters, from ONE capture of the
    scene and ONE visibility proof (the lights' and the world's status at every sensor), shared by the
    parts; the request's ``target_rel_error``: one value or a dict by part. The other options are
    ``measure_illuminance``'s; a part's readings are what ``measure_illuminance`` alone gives (with
    ``direct_only`` for "direct") on the same seed.

    Why each rendered part still has its own Cycles bakes: a bake writes one pass combination per call
    (``type='DIFFUSE'`` with ``pass_filter`` {DIRECT, INDIRECT} for the total, {DIRECT} would be the
    direct part) into one image per object, and bpy gives no way to keep both of one path-tracing run's
    passes; the direct part is also rendered at 0 bounces (its closed forms, hybrid exclusions and
    sample floors differ from the total's: ``plan(direct_only=True)``). What the parts share is
    everything before the bake."""
    if direct_only:
        raise RadiometerError("direct_only and parts go separately: ask for parts=('direct',)")
    names = tuple(parts) if not isinstance(parts, str) else (parts,)
    if not names or len(set(names)) != len(names) or not set(names) <= set(PARTS):
        raise RadiometerError(f"parts must be distinct names from {PARTS}, got {parts!r}")
    target_rel_error = request.target_rel_error
    targets = dict(target_rel_error) if isinstance(target_rel_error, dict) else \
        {name: target_rel_error for name in names}
    if not set(targets) <= set(names):
        raise RadiometerError("target_rel_error names parts that were not asked for: "
                              f"{sorted(set(targets) - set(names))}")
    model = capture_model(request.scene, request.view_layer, exclude=exclude) if model is None else model
    points_scene, _single = as_points(location)
    normals = as_directions(normal, len(points_scene))
    scale = request.scale_length
    sensors_scene, _eps = sensor_points(points_scene, normals, scale, model)  # as measure_illuminance places them
    proofs = _plan_direct(model, sensors_scene * scale, normals)
    return {name: measure_illuminance(location, normal, dataclasses.replace(request, target_rel_error=targets.get(name)),
                                      exclude=exclude, model=model, direct_only=name == "direct", proofs=proofs,
                                      **options)
            for name in names}


def _world_row(model, direct, normals, weights, efficacy):
    """The world's direct light at the one receiver as a breakdown row (``source`` None, ``world`` True):
    its closed form where the plan proves it (``illuminance`` None where it is rendered, with why), or
    None when the world emits nothing."""
    from ...radiometry.scene import scene_model

    status = None if direct.world_status is None else direct.world_status[0]
    if status is None or not model.world_emits:
        return None
    reason = str(direct.world_reason[0]) if getattr(direct, "world_reason", None) is not None else ""
    if status == scene_model.RENDER:
        return {"light": "world", "source": None, "world": True, "irradiance_rgb": None, "irradiance": None,
                "illuminance": None, "model": None, "exact": False, "status": str(status),
                "note": f"rendered, not in closed form: {reason or 'the world is not modelled here'}"}
    e_rgb, err_rgb, note = world_irradiance(model, direct, normals)
    e = float(e_rgb[0] @ weights)
    err = float(abs(err_rgb[0] @ weights))
    return {"light": "world", "source": None, "world": True, "irradiance_rgb": tuple(map(float, e_rgb[0])),
            "irradiance": e, "illuminance": efficacy * e, "model": "world", "exact": status in (scene_model.EXACT,
                                                                                              scene_model.ZERO),
            "status": str(status), "reason": reason, "rel_error_bound": err / abs(e) if e else 0.0, "note": note}


def analytic_light_irradiance(locations, normals, request):
    """{light name: (N, 3) W/m^2 SI}: every light's direct closed form at N meters (lights with no closed
    form left out), in one plan (what :func:`predict_illuminance` gives one point at a time)."""
    from ...radiometry.scene import scene_model

    points_scene, _single = as_points(locations)
    normals = as_directions(normals, len(points_scene))
    scale = request.scale_length
    model = capture_model(request.scene, request.view_layer)
    sensors_scene, _eps = sensor_points(points_scene, normals, scale, model)
    sensors_m = sensors_scene * scale
    direct = scene_model.plan_direct(model, sensors_m, normals)
    per_light, _bounds, _info = analytic_irradiance(model, direct, sensors_m, normals)
    return {light.name: per_light[i] for i, light in enumerate(model.lights) if light.spec is not None}


def predict_illuminance(location, normal, request, *, with_world=False):
    """Analytic per-light breakdown at one point: list of dicts (SI), with each light's verdict; with
    ``with_world`` the world's row first (:func:`_world_row`: None when it emits nothing)."""
    from ...radiometry.scene import scene_model

    points_scene, _ = as_points(location)
    normals = as_directions(normal, 1)
    scale = request.scale_length
    model = capture_model(request.scene, request.view_layer)
    sensors_scene, _eps = sensor_points(points_scene, normals, scale, model)
    sensors_m = sensors_scene * scale
    direct = scene_model.plan_direct(model, sensors_m, normals)
    space, weights, efficacy = request.photometry
    per_light, bounds, info = analytic_irradiance(model, direct, sensors_m, normals)
    rows = []
    if with_world:
        rows.append(_world_row(model, direct, normals, weights, efficacy))
    for i, (light, (exact, model_name, note)) in enumerate(zip(model.lights, info)):
        if light.spec is None:
            rows.append({"light": light.name, "source": light.source, "irradiance_rgb": None, "irradiance": None,
                         "illuminance": None, "model": None, "exact": False, "status": str(direct.status[i, 0]),
                         "note": f"not covered: {light.uncovered}; measure by rendering"})
            continue
        e = float(per_light[i, 0] @ weights)
        rows.append({"light": light.name, "source": light.source, "irradiance_rgb": tuple(map(float, per_light[i, 0])),
                     "irradiance": e,
                     "illuminance": efficacy * e, "model": model_name, "exact": bool(exact),
                     "status": str(direct.status[i, 0]), "reason": str(direct.reason[i, 0]),
                     "rel_error_bound": float(abs(bounds[i, 0] @ weights) / abs(e)) if e else 0.0, "note": note})
    return rows

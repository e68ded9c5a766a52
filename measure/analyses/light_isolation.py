"""The light under test, alone: find it, switch every other light and the world off, and measure
what it gives at points split into its OWN direct light and what the scene adds.

Host side (bpy) of the law checks. ``isolated_light`` hides every light object that renders
(including lights inside instanced collections, found through the scene model's light sources by
their ``source_id``, never by name)
and removes the world, inside ``scene_guard.preserved_scene``: the user's scene comes back
unchanged. ``measure_light_and_scene`` measures the total (the light plus everything the scene's
surfaces reflect of it) and the light's direct light alone (closed forms where
``scene_model.plan_direct`` proves them, EXACT or ZERO; otherwise Cycles with 0 bounces); the
scene's part is their difference. Units: W/m^2 (CIE Y weighted irradiance), m.
"""

import contextlib
import dataclasses

import numpy as np

from ...errors import RadiometerError
from . import analysis_common as common
from ..meter import point_meter as meter
from ..capture import scene_capture
from ..blender import scene_guard


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


def scene_model(scene):
    """The scene as Cycles renders it (``SceneModel``, m): captured once per analysis and handed to
    the helpers below (and served from ``capture_cache`` while the scene is unchanged)."""
    return meter.capture_model(scene, common.view_layer_of(scene))


def light_spec(obj, scene, model=None):
    """The emitter (SI) of a light object as Cycles renders it, or a clear error when no closed
    form describes it. ``model``: the scene's ``SceneModel`` when the caller has it. The object is
    found by its identity (``ModelLight.source_id``: session uid and library, not an instance), never
    by name: a renamed light, or one of several objects sharing one light data-block, is its own."""
    model = scene_model(scene) if model is None else model
    own = scene_capture.object_identity(obj)
    for light in model.lights:
        sid = light.source_id
        if sid is not None and (sid.object_uid, sid.library) == own and not sid.instance:
            if light.spec is None:
                raise RadiometerError(f"light {obj.name!r} {light.uncovered}: Radiometer has no far-field "
                                      "intensity to compare with")
            return light.spec
    raise RadiometerError(f"light {obj.name!r} does not render (hidden in renders or by its collection)")


def scene_lights_to_check(scene):
    return [ob for ob in scene.objects if ob.type == "LIGHT" and not ob.hide_render]


def source_size(spec):
    """Largest dimension of the luminous area, m: longer side or diameter; 2R for a sphere; 0 for delta."""
    return spec.size_m


def rendering_light_objects(scene, model=None):
    """Every light OBJECT that renders in ``scene``: the scene model's light sources (which include
    lights inside instanced collections) and the scene's own visible light objects."""
    model = scene_model(scene) if model is None else model
    objects = {ob for ob in scene.objects if ob.type == "LIGHT" and not ob.hide_render}
    objects |= set(scene_capture.source_objects(lt.source_id for lt in model.lights).values())
    return sorted((ob for ob in objects if ob.type == "LIGHT"), key=lambda ob: ob.name)


@contextlib.contextmanager
def isolated_light(scene, obj, model=None):
    """Only ``obj`` lights the scene inside the block: every other light object off in renders
    (instanced ones too), no world. Yields the names of the lights switched off."""
    with scene_guard.preserved_scene(scene) as snapshot:
        off = []
        for other in rendering_light_objects(scene, model):
            if other != obj and not other.hide_render:
                snapshot.remember(other, "hide_render")
                other.hide_render = True
                off.append(other.name)
        if scene.world is not None:
            scene.world = None  # the snapshot puts the world back
        common.view_layer_of(scene).update()
        yield off


@contextlib.contextmanager
def electric_lighting_only(scene, model=None):
    """Daylight off inside the block: every sun light object off in renders and no world where the world
    emits (a sky, an HDRI), as the daylight factor isolates the sky the other way round; the scene guard
    restores both. Yields one sentence saying what was switched off ("" when the scene had no daylight)."""
    model = scene_model(scene) if model is None else model
    with scene_guard.preserved_scene(scene) as snapshot:
        suns = [ob for ob in rendering_light_objects(scene, model)
                if getattr(ob.data, "type", "") == "SUN" and not ob.hide_render]
        for ob in suns:
            snapshot.remember(ob, "hide_render")
            ob.hide_render = True
        world = scene.world is not None and bool(model.world_emits)
        if world:
            scene.world = None  # the snapshot puts the world back
        common.view_layer_of(scene).update()
        off = [f"sun(s) {', '.join(repr(ob.name) for ob in suns)}" if suns else "",
               "the emitting world" if world else ""]
        off = [x for x in off if x]
        yield (f"electric lighting only: {' and '.join(off)} switched off for this measurement" if off else "")


def free_distance(scene, origin_m, direction, model=None):
    """Distance (m) along ``direction`` from ``origin_m`` (m) to the first surface that renders, inf
    if none. Cast against the scene model's triangles (what Cycles renders, instances included),
    so a surface hidden in renders that coincides with a real one (a work plane on a desk) does not
    hide it."""
    from ...radiometry.scene import visibility

    model = scene_model(scene) if model is None else model
    d = np.asarray(direction, float)
    dist, _index, _facing = visibility.first_hits(np.asarray(origin_m, float), (d / np.linalg.norm(d))[None],
                                                  model.geometry.triangles)
    return float(dist[0])


def model_irradiance(spec, points_m, normals, weights):
    """The light's closed form alone (no scene surfaces: unoccluded), W/m^2 CIE Y weighted."""
    return spec.irradiance_at(points_m, normals)[0] @ weights


@dataclasses.dataclass
class LightAndScene:
    """What one light gives at N points, split. Irradiance in W/m^2 (CIE Y weighted); errors are
    1-sigma, relative (``*_se``) or absolute (``scene_abs_se``)."""

    total: np.ndarray          #: the light's light as measured: direct + what the scene reflects of it
    total_se: np.ndarray       #: relative standard error of ``total``
    direct: np.ndarray         #: the light's own direct light (shadows of the scene included)
    direct_se: np.ndarray      #: relative standard error of ``direct`` (0 for closed forms)
    scene: np.ndarray          #: total - direct: interreflection (what the scene adds)
    scene_abs_se: np.ndarray   #: absolute standard error of ``scene``, W/m^2
    method: str                #: how ``total`` was measured
    direct_method: str         #: how ``direct`` was obtained ("analytic", "hybrid" or "render" at 0 bounces)
    exact: bool                #: every total reading is a closed form (then direct == total)
    lights_off: list           #: the other light objects switched off
    readings: list             #: the total readings (``IlluminanceReading``)

    @property
    def scene_share(self):
        """(scene / total) per point: the fraction of the reading the scene adds (0 where total is 0)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.total > 0, self.scene / np.where(self.total > 0, self.total, 1.0), 0.0)


def _part(progress, lo, hi):
    """A progress callback that maps 0..1 of one measurement onto lo..hi of two."""
    if progress is None:
        return None

    def report(done, total, *rest):
        progress(int(round(1000 * (lo + (hi - lo) * done / max(total, 1)))), 1000, *rest)
    return report


def measure_light_and_scene(request, obj, points_scene, normals, *, method, model=None):
    """Measure ``obj`` alone at the points: the total and the light's direct light. Returns
    :class:`LightAndScene`. The direct part uses closed forms where the scene model proves them
    (``method`` "analytic": always) and Cycles at 0 bounces elsewhere, with the same budget (the
    request's: ``measure.blender.request``)."""
    scene, progress = request.scene, request.progress
    with isolated_light(scene, obj, model) as off:
        # The light alone, captured once: the total's bakes restore the scene exactly (scene_guard), so
        # the direct-light measurement reuses it instead of capturing again (issue 17).
        alone = scene_model(scene)
        total = common.measure(request.but(progress=_part(progress, 0.0, 0.5)), points_scene, normals,
                               method=method, model=alone)
        exact = all(r.exact for r in total)
        if exact:
            direct = total
        else:
            direct = common.measure(request.but(seed=request.seed + 7919, progress=_part(progress, 0.5, 1.0)),
                                    points_scene, normals, method="analytic" if method == "analytic" else "auto",
                                    direct_only=True, model=alone)
    t = np.array([r.irradiance for r in total])
    t_se = common.rel_errors(total)
    d = np.array([r.irradiance for r in direct])
    d_se = common.rel_errors(direct)
    scene_abs_se = np.hypot(t_se * np.abs(t), d_se * np.abs(d)) if not exact else np.zeros_like(t)
    if exact:
        direct_method = total[0].method
    else:
        direct_method = direct[0].method if direct[0].method == "analytic" else f"{direct[0].method}, 0 bounces"
    return LightAndScene(total=t, total_se=t_se, direct=d, direct_se=d_se, scene=t - d, scene_abs_se=scene_abs_se,
                         method=total[0].method, direct_method=direct_method, exact=exact, lights_off=off,
                         readings=total)

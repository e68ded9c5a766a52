"""Live meter mode: meters update as the user moves lights, meters or geometry (``scene.radiometer.live``).

* A ``depsgraph_update_post`` handler (:func:`on_depsgraph_update`) marks what a change makes stale:
  every meter (a light, a mesh, a material or the world changed, an object was added or removed) or
  only the meters that moved. It ignores what Radiometer does itself: updates fired while a live
  measurement runs (probe renders, the scene guard's restore), its temporary ``radiometer_*``
  objects, selection-only changes, and meter updates whose pose equals the pose last measured
  (writing a reading does not move a meter).
* A persistent ``bpy.app.timers`` function (:func:`tick`, every ``TICK_S``) waits until the scene has
  been still for ``DEBOUNCE_S``, then measures the stale meters at once with the scene's method at
  *preview* quality: with method auto, closed forms wherever they are exact for the scene (no noise,
  milliseconds), else a 5 % preview. While the user stays idle (``REFINE_IDLE_S``) it then refines the
  non-exact readings to the scene's quality, ``REFINE_BATCH`` meters per tick, so that a change made
  between two ticks drops the refinement and starts again with a preview.

Illuminance meters are measured at once; luminance (spot) meters, whose camera render costs ~1 s
even at preview quality, are measured in the idle phase, one per tick; radiance maps (panoramic
renders) are left to Measure.
A refinement tick blocks the UI while its batch renders (no event can interrupt a timer): the batch
is small for that reason. Readings go to the meters (panel and viewport overlay show them);
``status(scene)`` is the one-line state the panel and the overlay print.

The mode reads the scene's and the meters' Radiometer properties and measures through the api; its
per-scene state (``props/live_state.py``) is what the ``live`` property's update callback marks and the
panels print. Registered with the other operators (``register_extra``).
"""

import time

import bpy
from bpy.app.handlers import persistent

from .. import api
from ..errors import RadiometerError
from ..props.live_state import key, mark_dirty, reset, state, status  # noqa: F401 - the mode's state
from ..props import live_state
from ..quality import preset

DEBOUNCE_S = 0.2      # the scene must be still this long before a live reading starts
REFINE_IDLE_S = 0.5   # and this long after a preview before refining it
TICK_S = 0.05         # timer period
REFINE_BATCH = 4      # meters per refinement tick
#: A preview stops at its target or after about this long (s), whichever comes first: in a big scene
#: (130k triangles) a 5 % preview of a few rendered meters took 2.4-2.7 s of bakes, all of it
#: blocking the UI; the idle refinement then brings the readings to the scene's quality.
PREVIEW_BUDGET_S = 0.5
LIVE_KINDS = ("ILLUMINANCE", "LUMINANCE")
FAST_KINDS = ("ILLUMINANCE",)  # measured at once; the others (camera renders) in the idle phase
_DATA_TYPES = ("Light", "Mesh", "Curve", "MetaBall", "Material", "World", "NodeTree", "Image", "Volume",
               "PointCloud", "Curves", "GreasePencil")
_busy = False  # a live measurement is running: its own depsgraph updates are not changes


def _pose(ob):
    m = ob.radiometer_meter
    return (m.kind, round(m.acceptance_deg, 6)) + tuple(round(v, 7) for row in ob.matrix_world for v in row)


def _settings(scene):
    s = scene.radiometer
    return (s.method, s.quality, round(s.target_rel_error, 9), round(s.efficacy, 9),
            scene.world.name if scene.world else "", scene.unit_settings.scale_length)


def changes(scene, updates, st):
    """(everything stale?, names of moved meters) from a depsgraph's ``updates``."""
    everything, moved = False, set()
    for u in updates:
        idt = u.id
        name = getattr(idt, "name", "")
        if name.startswith("radiometer_"):
            continue  # Radiometer's temporary objects (probe camera, bake planes)
        if isinstance(idt, bpy.types.Object):
            ob = idt.original
            if ob.radiometer_meter.is_meter:
                if ob.radiometer_meter.kind in LIVE_KINDS and _pose(idt) != st.poses.get(ob.name):
                    moved.add(ob.name)
                continue
            if not (u.is_updated_transform or u.is_updated_geometry):
                continue  # selection, display
            if ob.type == "CAMERA" or (ob.type == "EMPTY" and ob.instance_type == "NONE"):
                continue
            everything = True
        elif isinstance(idt, bpy.types.Collection):
            everything = everything or u.is_updated_geometry or u.is_updated_transform
        elif isinstance(idt, bpy.types.Scene):
            everything = everything or _settings(scene) != st.settings
        elif any(isinstance(idt, getattr(bpy.types, t)) for t in _DATA_TYPES if hasattr(bpy.types, t)):
            everything = True
    return everything, moved


@persistent
def on_depsgraph_update(scene, depsgraph):
    """depsgraph_update_post handler: mark the scene's live meters stale after a change."""
    if _busy:
        return
    settings = getattr(scene, "radiometer", None)
    if settings is None or not settings.live:
        return
    st = state(scene)
    everything, moved = changes(scene, depsgraph.updates, st)
    if everything:
        mark_dirty(scene)
    elif moved:
        mark_dirty(scene, moved)


def _live_meters(scene, names=None):
    obs = [ob for ob in scene.objects if ob.radiometer_meter.is_meter and ob.radiometer_meter.kind in LIVE_KINDS]
    if names is not None:
        obs = [ob for ob in obs if ob.name in names]
    return obs


def _measure(scene, objects, quality, batch=None, time_budget_s=None):
    """Measure ``objects`` (blocking) and write their readings; returns [(object, reading)]. A time budget
    caps each step (the target still ends it early)."""
    results = []
    for _label, _weight, run in api.meter_steps(objects, scene=scene, quality=quality, batch=batch,
                                                time_budget_s=time_budget_s):
        results += run()
    for obj, reading in results:
        api.store_reading(obj, reading)
    return results


def _record(scene, st, results):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for obj, _reading in results:
        st.poses[obj.name] = _pose(obj.evaluated_get(depsgraph))
    st.settings = _settings(scene)


def _redraw():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else ()):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def _preview(scene, st, now):
    names = None if st.dirty_all else set(st.dirty_meters)
    st.dirty_all, st.dirty_meters = False, set()
    objects = _live_meters(scene, names)
    if not objects:
        st.status = "Live: no illuminance or luminance meters"
        st.settings = _settings(scene)
        return
    # Spot (luminance) meters render a camera view (~1 s even at preview): they wait for the idle phase.
    fast = [ob for ob in objects if ob.radiometer_meter.kind in FAST_KINDS]
    slow = [ob.name for ob in objects if ob.radiometer_meter.kind not in FAST_KINDS]
    started = time.perf_counter()
    try:
        results = _measure(scene, fast, "preview", time_budget_s=PREVIEW_BUDGET_S) if fast else []
    except RadiometerError as exc:
        st.status = f"Live: {exc}"
        return
    st.preview_seconds = time.perf_counter() - started
    st.measurements += 1
    _record(scene, st, results)
    if not fast:
        st.settings = _settings(scene)
    st.measured_at = now if now is not None else time.perf_counter()
    rough = [obj.name for obj, r in results if not r.exact]
    pending = set(st.refine) - {ob.name for ob in objects} if names is not None else set()
    # A preview cut short by its budget is refined even when the scene's quality is preview.
    target = scene.radiometer.target_rel_error if scene.radiometer.target_rel_error > 0 else preset("preview")["target"]
    short = {obj.name for obj, r in results if not r.exact and not r.rel_std_error <= target}
    refine = set(rough) if scene.radiometer.quality != "preview" else short
    st.refine = sorted(pending | refine) + [n for n in slow if n not in pending]
    exact = len(results) - len(rough)
    st.status = (f"Live: {exact} exact, {len(rough)} preview ({st.preview_seconds:.2g} s)"
                 + (f", {len(slow)} spot meter(s) when idle" if slow else "")
                 + (", refining while idle" if set(st.refine) - set(slow) else ""))
    _redraw()


def _refine(scene, st):
    # Illuminance meters first (one batch, one bake), then one spot meter per tick.
    objects = _live_meters(scene, set(st.refine))
    fast = [ob for ob in objects if ob.radiometer_meter.kind in FAST_KINDS][:REFINE_BATCH]
    objects = fast or objects[:1]
    done = {ob.name for ob in objects}
    st.refine = [n for n in st.refine if n not in done and n in {ob.name for ob in _live_meters(scene)}]
    if not objects:
        return
    try:
        results = _measure(scene, objects, scene.radiometer.quality, batch=REFINE_BATCH)
    except RadiometerError as exc:
        st.status, st.refine = f"Live: {exc}", []
        return
    st.measurements += 1
    _record(scene, st, results)
    st.status = (f"Live: refining, {len(st.refine)} to go" if st.refine else
                 f"Live: every reading at {scene.radiometer.quality} quality or exact")
    _redraw()


def _live_scenes():
    seen = {}
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else ()):
        if window.scene is not None:
            seen.setdefault(key(window.scene), (window.scene, window))
    scene = bpy.context.scene
    if scene is not None:
        seen.setdefault(key(scene), (scene, None))
    return [(s, w) for s, w in seen.values() if getattr(s, "radiometer", None) is not None and s.radiometer.live]


def tick(now=None):
    """The live timer: after ``DEBOUNCE_S`` of stillness a preview, then refinement while idle.

    ``now`` (perf_counter seconds) lets tests step time; returns the delay to the next call.
    """
    global _busy
    if _busy:
        return TICK_S
    now = time.perf_counter() if now is None else now
    live = _live_scenes()
    live_state.forget_all_but({key(s) for s, _ in live})  # live turned off (or the scene is gone): forget
    for scene, window in live:
        st = state(scene)
        if scene.radiometer.progress_text:
            continue  # a modal Radiometer operation is running on this scene: wait for it
        if st.dirty and now - st.changed_at < DEBOUNCE_S:
            continue
        if not st.dirty and not (st.refine and now - st.measured_at >= REFINE_IDLE_S):
            continue
        override = {"scene": scene}
        if window is not None:
            override.update(window=window, view_layer=window.view_layer)
        _busy = True  # every depsgraph update from here to the flush below is Radiometer's own
        try:
            with bpy.context.temp_override(**override):
                (_preview if st.dirty else _refine_now)(scene, st, now)
                bpy.context.evaluated_depsgraph_get()  # flush the updates the measurement tagged
        except Exception as exc:  # a timer that raises is unregistered by Blender: keep the mode alive
            st.dirty_all, st.dirty_meters, st.refine = False, set(), []
            st.status = f"Live: failed ({exc.__class__.__name__}: {exc})"
        finally:
            _busy = False
    return TICK_S


def _refine_now(scene, st, _now):
    _refine(scene, st)


classes = ()


def register_extra():  # ModuleGroup calls it with the other operators
    if on_depsgraph_update not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(on_depsgraph_update)
    if not bpy.app.timers.is_registered(tick):
        bpy.app.timers.register(tick, first_interval=TICK_S, persistent=True)


def unregister_extra():
    while on_depsgraph_update in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(on_depsgraph_update)
    if bpy.app.timers.is_registered(tick):
        bpy.app.timers.unregister(tick)
    reset()

"""Live meter mode (issue 13): the depsgraph handler marks meters stale, the timer measures them after a
debounce (exact where closed forms are, else a preview refined while idle), and Radiometer's own
measurements do not retrigger it. The handler runs for real (``view_layer.update()`` fires
depsgraph_update_post headless); the timer function is called directly with a stepped clock."""

import math
import time

import bpy
import pytest

E_AT_2M = 683 * 100 / (4 * math.pi * 4)  # lux of a 100 W point light 2 m above


def live():
    from radiometer.operators import live as mod

    return mod


def point_scene(build, height=2.0):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "POINT", (0, 0, height), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(0, 0, 0))
    return scene, light, bpy.context.active_object


def meter_over_a_lit_floor(build):
    """A meter 1 m above a lit 0.8-albedo floor, facing it: its light is reflected, so it needs Cycles."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=4.0, albedo=0.8, name="floor")
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(0, 0, 1), rotation=(math.pi, 0, 0))
    return scene, bpy.context.active_object


def settle(t):
    """Let the (stepped) clock run past the debounce and tick."""
    bpy.context.view_layer.update()
    return live().tick(now=t)


def test_handler_and_timer_are_registered(clean_blender):
    mod = live()
    assert mod.on_depsgraph_update in bpy.app.handlers.depsgraph_update_post
    assert bpy.app.timers.is_registered(mod.tick)
    assert bpy.context.scene.radiometer.live is False


def test_moving_a_light_updates_the_exact_reading_and_own_measurement_does_not_retrigger(clean_blender, build):
    mod = live()
    scene, light, meter = point_scene(build)
    scene.radiometer.live = True
    st = mod.state(scene)
    assert st.dirty
    t = time.perf_counter() + 10
    settle(t)
    m = meter.radiometer_meter
    assert m.has_reading and m.exact and m.photometric == pytest.approx(E_AT_2M, rel=1e-6)
    assert st.measurements == 1 and not st.dirty and not st.refine
    # Radiometer's own measurement and reading writes are not changes.
    bpy.context.view_layer.update()
    assert not st.dirty
    settle(t + 10)
    assert st.measurements == 1
    # Move the light: the handler marks every meter; the debounce holds the reading back ...
    light.location.z = 4.0
    bpy.context.view_layer.update()
    assert st.dirty_all
    mod.tick(now=st.changed_at + 0.5 * mod.DEBOUNCE_S)
    assert st.measurements == 1 and m.photometric == pytest.approx(E_AT_2M, rel=1e-6)
    # ... until the scene has been still long enough.
    mod.tick(now=st.changed_at + 2 * mod.DEBOUNCE_S)
    assert st.measurements == 2
    assert m.exact and m.photometric == pytest.approx(E_AT_2M / 4, rel=1e-6)
    assert "exact" in mod.status(scene)
    # Changing the light's power (data, not transform) is a change too.
    light.data.energy = 50.0
    bpy.context.view_layer.update()
    assert st.dirty_all
    settle(st.changed_at + 1)
    assert m.photometric == pytest.approx(E_AT_2M / 8, rel=1e-6)


def test_moving_a_meter_marks_only_that_meter_and_selection_marks_nothing(clean_blender, build):
    mod = live()
    scene, light, meter = point_scene(build)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(1, 0, 0))
    other = bpy.context.active_object
    scene.radiometer.live = True
    st = mod.state(scene)
    settle(time.perf_counter() + 10)
    assert st.measurements == 1
    meter.select_set(True)
    light.select_set(True)
    bpy.context.view_layer.update()
    assert not st.dirty
    other.location.x = 2.0
    bpy.context.view_layer.update()
    assert not st.dirty_all and st.dirty_meters == {other.name}
    before = meter.radiometer_meter.seconds
    settle(st.changed_at + 1)
    assert other.radiometer_meter.photometric == pytest.approx(683 * 100 / (4 * math.pi * 8) * 2 / math.sqrt(8),
                                                              rel=1e-6)
    assert meter.radiometer_meter.seconds == before  # not remeasured


def test_live_off_does_nothing(clean_blender, build):
    mod = live()
    scene, light, meter = point_scene(build)
    light.location.z = 3.0
    settle(time.perf_counter() + 10)
    assert not meter.radiometer_meter.has_reading
    assert mod.status(scene) == ""


def test_preview_then_refinement_while_idle(clean_blender, build):
    """A meter facing a lit floor needs Cycles: a preview reading first, refined to the scene's quality."""
    mod = live()
    scene, meter = meter_over_a_lit_floor(build)
    scene.radiometer.quality = "standard"
    scene.radiometer.live = True
    st = mod.state(scene)
    t = time.perf_counter() + 10
    settle(t)
    m = meter.radiometer_meter
    assert m.has_reading and not m.exact
    assert m.rel_std_error <= 0.05 * 1.5
    assert st.refine == [meter.name]
    bpy.context.view_layer.update()  # the renders of the measurement are not changes
    assert not st.dirty
    mod.tick(now=t + 0.5 * mod.REFINE_IDLE_S)  # not idle long enough yet
    assert st.measurements == 1
    settle(t + 2 * mod.REFINE_IDLE_S)
    assert st.measurements == 2 and not st.refine and not st.dirty
    assert m.rel_std_error <= 0.01 * 1.5
    assert "standard" in mod.status(scene)
    settle(t + 10)
    assert st.measurements == 2


def test_spot_meter_waits_for_the_idle_phase(clean_blender, build):
    mod = live()
    scene = bpy.context.scene
    build.black_world(scene)
    build.plane(scene, size=4.0, albedo=0.8, name="floor")
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(1, 0, 0))
    illum = bpy.context.active_object
    bpy.ops.radiometer.add_meter(kind="LUMINANCE", location=(0, 0, 1), rotation=(0, 0, 0), acceptance_deg=5.0)
    spot = bpy.context.active_object  # looks along -Z: at the floor
    scene.radiometer.quality = "preview"
    scene.radiometer.live = True
    st = mod.state(scene)
    t = time.perf_counter() + 10
    settle(t)
    assert illum.radiometer_meter.has_reading and not spot.radiometer_meter.has_reading
    assert st.refine == [spot.name] and "spot" in mod.status(scene)
    settle(t + 2 * mod.REFINE_IDLE_S)
    assert spot.radiometer_meter.has_reading and spot.radiometer_meter.photometric > 0
    assert not st.refine and not st.dirty
    bpy.context.view_layer.update()  # the spot meter's camera render is not a change
    assert not st.dirty


def test_live_waits_while_a_radiometer_operation_runs(clean_blender, build):
    mod = live()
    scene, light, meter = point_scene(build)
    scene.radiometer.live = True
    scene.radiometer.progress_text = "Measure 10 %"
    settle(time.perf_counter() + 10)
    assert not meter.radiometer_meter.has_reading and mod.state(scene).dirty
    scene.radiometer.progress_text = ""
    settle(time.perf_counter() + 10)
    assert meter.radiometer_meter.has_reading


def test_a_preview_cut_short_by_its_budget_is_refined(clean_blender, build, monkeypatch):
    """The preview blocks the UI for at most about ``PREVIEW_BUDGET_S`` (plus its first bake); a reading
    it leaves above the target is refined while idle, even when the scene's quality is preview."""
    mod = live()
    monkeypatch.setattr(mod, "PREVIEW_BUDGET_S", 1e-6)  # only the first (pilot) bake fits
    scene, meter = meter_over_a_lit_floor(build)
    scene.radiometer.quality = "preview"
    scene.radiometer.target_rel_error = 0.004  # more than one pilot bake can reach
    scene.radiometer.live = True
    st = mod.state(scene)
    t = time.perf_counter() + 10
    settle(t)
    m = meter.radiometer_meter
    assert m.has_reading and not m.exact and m.rel_std_error > 0.004
    assert st.refine == [meter.name]
    settle(t + 2 * mod.REFINE_IDLE_S)
    assert st.measurements == 2 and not st.refine
    assert m.rel_std_error <= 0.004 * 1.5

"""The shared modal runner (operators/modal.py): steps, progress, Esc, event routing and restore.

Background bpy has no window, so the operators run their blocking path there; these tests drive
the same Task objects the modal operators run (one step per timer tick), and the mixin's modal()
with synthetic events on a stand-in operator.
"""

import math
import types

import bpy
import pytest

from radiometer.errors import MeasurementCancelled, RadiometerError
from radiometer.measure.blender import scene_guard
from radiometer.operators import modal


def _point_room(build, meters=3):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    objs = []
    for k in range(meters):
        bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
        ob = bpy.context.active_object
        ob.location = (0.2 * k, 0.0, 0.0)
        objs.append(ob)
    return scene, objs


def _rendered_room(build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0, 0, 2), energy=100.0, size=0.5)
    build.plane(scene, size=4, location=(0, 0, 0), name="Work Plane")
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    meter = bpy.context.active_object
    meter.location = (0.3, 0.0, 0.5)
    scene.radiometer.method = "render"
    scene.radiometer.quality = "preview"
    return scene, meter


# --- Task: the pure step machine -----------------------------------------------------------------

def test_task_progress_is_monotone_and_reaches_one():
    seen = []

    def fn(progress, cancelled):
        for done in (0, 250, 500, 1000):
            progress(done, 1000, None)
            seen.append(task.fraction)

    task = modal.Task("T", [modal.Step("a", fn, 1.0), modal.Step("b", fn, 3.0)])
    assert task.step() == modal.RUNNING and task.fraction == pytest.approx(0.25)
    assert task.step() == modal.DONE and task.fraction == 1.0
    assert seen == sorted(seen) and seen[4] == pytest.approx(0.25) and seen[-1] == pytest.approx(1.0)
    assert "Esc to cancel" in task.status_text()


def test_task_cancel_stops_before_the_next_step_and_inside_a_step():
    ran = []

    def ok(progress, cancelled):
        ran.append(1)

    task = modal.Task("T", [modal.Step("a", ok), modal.Step("b", ok)])
    task.step()
    task.request_cancel()
    assert task.step() == modal.CANCELLED and ran == [1]

    def polls(progress, cancelled):
        task2.request_cancel()  # Esc seen by the measurement's cancelled() mid-step
        if cancelled():
            raise MeasurementCancelled("cancelled")

    task2 = modal.Task("T", [modal.Step("a", polls), modal.Step("b", ok)])
    assert task2.step() == modal.CANCELLED and ran == [1]


def test_task_error_is_failed_with_the_step_label():
    def bad(progress, cancelled):
        raise RadiometerError("no lights")

    task = modal.Task("T", [modal.Step("Lamp", bad)])
    assert task.run_all() == modal.FAILED and task.error == "Lamp: no lights"


# --- the mixin's modal(): event routing with a stand-in operator -----------------------------------

class _StandIn(modal.TaskOperator):
    def __init__(self, task):
        self._task, self._timer, self.reports, self.finished = task, None, [], False

    def report(self, kind, text):
        self.reports.append((set(kind), text))

    def finish(self, context, task):
        self.finished = True
        return "done"


def _context():
    settings = types.SimpleNamespace(progress=0.0, progress_text="")
    wm = types.SimpleNamespace(progress_update=lambda v: None, progress_end=lambda: None,
                               event_timer_remove=lambda t: None)
    return types.SimpleNamespace(scene=types.SimpleNamespace(radiometer=settings), window_manager=wm,
                                 workspace=None, screen=None)


def _event(kind, value="PRESS"):
    return types.SimpleNamespace(type=kind, value=value, time_duration=0.0)


def test_modal_routes_events_navigation_passes_edits_are_swallowed_timer_steps():
    calls = []
    task = modal.Task("T", [modal.Step("a", lambda p, c: calls.append("a")),
                            modal.Step("b", lambda p, c: calls.append("b"))])
    op, ctx = _StandIn(task), _context()
    assert op.modal(ctx, _event("MIDDLEMOUSE")) == {"PASS_THROUGH"}
    assert op.modal(ctx, _event("WHEELUPMOUSE")) == {"PASS_THROUGH"}
    for key in ("X", "DEL", "G", "LEFTMOUSE", "Z"):  # delete, grab, select, undo: not mid-run
        assert op.modal(ctx, _event(key)) == {"RUNNING_MODAL"}
    assert op.modal(ctx, _event("TIMER")) == {"RUNNING_MODAL"} and calls == ["a"]
    assert ctx.scene.radiometer.progress == pytest.approx(0.5) and "50 %" in ctx.scene.radiometer.progress_text
    assert op.modal(ctx, _event("TIMER")) == {"FINISHED"} and op.finished
    assert ctx.scene.radiometer.progress_text == "" and modal.running_task() is None


def test_modal_esc_cancels_at_once_and_finishes_nothing():
    task = modal.Task("Measure", [modal.Step("a", lambda p, c: None), modal.Step("b", lambda p, c: None)])
    op, ctx = _StandIn(task), _context()
    op.modal(ctx, _event("TIMER"))
    assert op.modal(ctx, _event("ESC")) == {"CANCELLED"}
    assert not op.finished and task.state == modal.CANCELLED
    assert any("cancelled" in text for _, text in op.reports)


# --- real measurements through the tasks ---------------------------------------------------------

def test_measure_task_runs_one_step_per_batch_and_writes_nothing_until_finish(clean_blender, build):
    from radiometer.operators.meter import measure_task

    scene, objs = _point_room(build, meters=3)
    task = measure_task(scene, objs, batch=1)
    assert len(task.steps) == 3
    fractions = []
    while task.step() == modal.RUNNING:
        fractions.append(task.fraction)
        assert not any(ob.radiometer_meter.has_reading for ob in objs)
    assert task.state == modal.DONE and fractions == pytest.approx([1 / 3, 2 / 3])
    assert [ob.name for ob, _ in task.results] == [ob.name for ob in objs]
    expected = 683 * 100 / (4 * math.pi * 4)
    assert task.results[0][1].illuminance == pytest.approx(expected, rel=1e-6)


def test_esc_during_a_rendered_step_restores_the_scene(clean_blender, build):
    from radiometer.operators.meter import measure_task

    scene, meter = _rendered_room(build)
    scene.radiometer.target_rel_error = 0.0001  # several allocation rounds
    before = scene_guard.scene_fingerprint(scene)
    task = measure_task(scene, [meter])
    calls = []

    def progress(done, total, seconds_left=None):
        calls.append(done)
        task.request_cancel()  # Esc arrives while the bake runs: the next allocation round sees it

    task.progress = progress
    assert task.step() == modal.CANCELLED
    assert calls, "the measurement reported progress before its first round"
    assert task.results == []  # the step stopped inside the measurement (MeasurementCancelled), not after it
    assert scene_guard.scene_fingerprint(scene) == before
    assert not meter.radiometer_meter.has_reading


def test_law_check_and_report_tasks_step_per_light_and_part(clean_blender, build, tmp_path):
    from radiometer.operators import analysis as ops

    scene, meter = _rendered_room(build)
    scene.radiometer.method = "auto"
    scene.radiometer_analysis.output_dir = str(tmp_path) + "/"
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "s.blend"))
    before = scene_guard.scene_fingerprint(scene)
    task = ops.report_task(bpy.context, convergence=False)
    assert [s.label for s in task.steps] == ["meters", f"laws {bpy.data.lights[0].name}", "grid Work Plane"]
    fractions = []
    while task.step() == modal.RUNNING:
        fractions.append(task.fraction)
        assert not (tmp_path / "report.md").exists()  # files only at the end
    assert task.state == modal.DONE and fractions == sorted(fractions) and task.fraction == 1.0
    assert (tmp_path / "report.md").exists() and task.results["report"]["grids"][0]["nx"] > 0
    assert scene_guard.scene_fingerprint(scene) == before


def test_operators_keep_the_blocking_path_in_background(clean_blender, build):
    scene, objs = _point_room(build, meters=2)
    assert bpy.ops.radiometer.measure("INVOKE_DEFAULT", only_selected=False) == {"FINISHED"}  # no window: runs at once
    assert all(ob.radiometer_meter.has_reading for ob in objs)
    assert scene.radiometer.progress_text == ""

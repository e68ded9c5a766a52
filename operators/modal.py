"""One modal runner for every long Radiometer operation (measure, law checks, grid, convergence, report).

A long operation is a :class:`Task`: a list of short steps, each ``fn(progress, cancelled)``.
:class:`TaskOperator` runs it

* in the UI: modal, one step per timer tick, with ``wm.progress_*`` (the cursor's progress), a
  status-bar text with the ETA, and ``scene.radiometer.progress`` / ``progress_text`` that the
  panels draw with ``layout.progress``. Esc cancels: a step in flight sees it through the
  measurement's ``cancelled`` callback at its next allocation round, and no further step starts.
  Only view navigation passes through (orbit, pan, zoom, numpad views), so a meter or light cannot
  be deleted or moved mid-run; every other event is swallowed while the task runs;
* in background mode, from scripts or with no window: blocking, all steps at once (``execute``).

Every measurement restores the scene it borrowed (``scene_guard``); results are written by the
operator's ``finish`` only when every step succeeded, so a cancelled or failed run changes nothing.
Pure Python (no bpy at import), so tests drive a :class:`Task` step by step.
"""

import time

NAVIGATION_EVENTS = frozenset({
    "MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "WHEELINMOUSE", "WHEELOUTMOUSE", "MOUSEMOVE",
    "INBETWEEN_MOUSEMOVE", "TRACKPADPAN", "TRACKPADZOOM", "MOUSEROTATE", "MOUSESMARTZOOM",
    "NDOF_MOTION", "NUMPAD_0", "NUMPAD_1", "NUMPAD_2", "NUMPAD_3", "NUMPAD_4", "NUMPAD_5", "NUMPAD_6",
    "NUMPAD_7", "NUMPAD_8", "NUMPAD_9", "NUMPAD_PERIOD", "NUMPAD_PLUS", "NUMPAD_MINUS", "NUMPAD_SLASH",
    "WINDOW_DEACTIVATE",
})
CANCEL_EVENTS = frozenset({"ESC"})

RUNNING, DONE, CANCELLED, FAILED = "RUNNING", "DONE", "CANCELLED", "FAILED"


class Step:
    """One piece of a task: ``fn(progress, cancelled)``; ``weight`` its share of the progress bar."""

    def __init__(self, label, fn, weight=1.0):
        self.label, self.fn, self.weight = label, fn, float(weight)


class Task:
    """A long operation as short steps, with progress (0..1), an ETA and cancellation."""

    def __init__(self, label, steps):
        self.label = label
        self.steps = list(steps)
        total = sum(s.weight for s in self.steps) or 1.0
        self.bounds = [0.0]
        for s in self.steps:
            self.bounds.append(self.bounds[-1] + s.weight / total)
        self.index = 0
        self.fraction = 0.0
        self.seconds_left = None
        self.state = RUNNING if self.steps else DONE
        self.error = None
        self.cancel_requested = False
        self.started = time.perf_counter()
        #: Called once when the task ends, however (a report's generator is closed: its staging folder goes).
        self.on_end = None

    # --- polled by the measurements -------------------------------------------------------------
    def cancelled(self):
        return self.cancel_requested

    def request_cancel(self):
        self.cancel_requested = True
        if self.state == RUNNING:
            self.state = CANCELLED

    def progress(self, done, total=1000, seconds_left=None):
        """The running step's progress (done/total of that step) mapped onto the whole task."""
        if self.index >= len(self.steps):
            return
        lo, hi = self.bounds[self.index], self.bounds[self.index + 1]
        part = min(max(done / total, 0.0), 1.0) if total else 0.0
        self._set(lo + (hi - lo) * part)

    def _set(self, fraction):
        self.fraction = max(self.fraction, min(float(fraction), 1.0))
        elapsed = time.perf_counter() - self.started
        self.seconds_left = elapsed * (1.0 - self.fraction) / self.fraction if self.fraction > 0.02 else None

    # --- driven by the operator -----------------------------------------------------------------
    @property
    def current_label(self):
        return self.steps[self.index].label if self.index < len(self.steps) else ""

    def step(self):
        """Run the next step; returns the state (RUNNING while steps remain)."""
        from ..errors import MeasurementCancelled, RadiometerError

        if self.state != RUNNING:
            return self.state
        if self.cancel_requested:
            self.state = CANCELLED
            return self.state
        step = self.steps[self.index]
        try:
            step.fn(self.progress, self.cancelled)
        except MeasurementCancelled:
            self.state = CANCELLED
            return self.state
        except RadiometerError as exc:
            self.state, self.error = FAILED, f"{step.label}: {exc}" if step.label else str(exc)
            return self.state
        if self.cancel_requested:  # Esc during the step's last round: discard, like any cancel
            self.state = CANCELLED
            return self.state
        self.index += 1
        self._set(self.bounds[self.index])
        if self.index >= len(self.steps):
            self.state = DONE
        return self.state

    def run_all(self):
        while self.step() == RUNNING:
            pass
        return self.state

    def status_text(self):
        eta = ""
        if self.seconds_left is not None:
            s = self.seconds_left
            eta = f", about {s:.0f} s left" if s < 90 else f", about {s / 60:.0f} min left"
        where = f" ({self.current_label})" if self.current_label else ""
        return f"Radiometer {self.label}{where}: {100 * self.fraction:.0f} %{eta}   Esc to cancel"


def one_call_task(label, step_label, key, call):
    """A one-step Task: ``call(progress, cancelled)``'s result lands in ``task.results[key]``."""
    results = {}

    def fn(progress, cancelled):
        results[key] = call(progress, cancelled)

    task = Task(label, [Step(step_label, fn)])
    task.results = results
    return task


def is_navigation(event_type):
    return event_type in NAVIGATION_EVENTS


_running = {"task": None}


def running_task():
    """The task a modal Radiometer operator is running now (one at a time), or None."""
    return _running["task"]


class TaskOperator:
    """Mixin for ``bpy.types.Operator``: implement ``build_task(context) -> Task`` and
    ``finish(context, task) -> str`` (the INFO line); ``build_task`` may raise RadiometerError."""

    _timer = None
    _task = None

    def build_task(self, context):  # pragma: no cover - implemented by the operators
        raise NotImplementedError

    def finish(self, context, task):  # pragma: no cover
        raise NotImplementedError

    @classmethod
    def task_poll(cls, context):
        if running_task() is not None:
            cls.poll_message_set("a Radiometer measurement is running (Esc cancels it)")
            return False
        return True

    def _build(self, context):
        from ..errors import RadiometerError

        try:
            return self.build_task(context)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return None

    def execute(self, context):
        task = self._build(context)
        if task is None:
            return {"CANCELLED"}
        task.run_all()
        return self._end(context, task)

    def invoke(self, context, event):
        import bpy

        if bpy.app.background or context.window is None or context.window_manager is None:
            return self.execute(context)
        task = self._build(context)
        if task is None:
            return {"CANCELLED"}
        self._task = task
        _running["task"] = task
        wm = context.window_manager
        wm.progress_begin(0, 1000)
        self._timer = wm.event_timer_add(0.02, window=context.window)
        wm.modal_handler_add(self)
        self._show(context)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        task = self._task
        if event.type in CANCEL_EVENTS and event.value == "PRESS":
            task.request_cancel()
            return self._end(context, task)
        if event.type == "TIMER" and event.time_duration >= 0:
            if task.step() != RUNNING:
                return self._end(context, task)
            self._show(context)
            return {"RUNNING_MODAL"}
        if is_navigation(event.type):
            return {"PASS_THROUGH"}
        return {"RUNNING_MODAL"}  # no edits while measuring: the run uses the scene as it was

    def _show(self, context):
        task = self._task
        settings = getattr(context.scene, "radiometer", None)
        if settings is not None:
            settings.progress = task.fraction
            settings.progress_text = task.status_text()
        context.window_manager.progress_update(int(1000 * task.fraction))
        if context.workspace is not None:
            context.workspace.status_text_set(task.status_text())
        for area in context.screen.areas if context.screen else ():
            if area.type in {"VIEW_3D", "PROPERTIES"}:
                area.tag_redraw()

    def _end(self, context, task):
        if task.on_end is not None:
            task.on_end()
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
            wm.progress_end()
            if context.workspace is not None:
                context.workspace.status_text_set(None)
        if _running["task"] is task:
            _running["task"] = None
        settings = getattr(context.scene, "radiometer", None)
        if settings is not None:
            settings.progress, settings.progress_text = 0.0, ""
        if task.state == CANCELLED:
            self.report({"WARNING"}, f"{task.label} cancelled; the scene and earlier results are unchanged")
            return {"CANCELLED"}
        if task.state == FAILED:
            self.report({"ERROR"}, task.error)
            return {"CANCELLED"}
        from ..errors import RadiometerError

        try:
            line = self.finish(context, task)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        if line:
            self.report({"INFO"}, line)
        return {"FINISHED"}

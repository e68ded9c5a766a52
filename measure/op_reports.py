"""Keep Blender's operator reports off stdout while the API runs an operator.

``bpy.ops`` prints an operator's reports ("Info: Baking map saved to internal image, save it
externally or pack it", one per bake) through ``sys.stdout`` (``PySys_WriteStdout``), so a script
that calls ``api.measure_illuminance`` five times got five such lines on its stdout. The API prints
nothing to stdout: inside :func:`operator_reports_dropped`, "Info: " lines are dropped, "Warning: "
and "Error: " lines go to stderr (the operator also raises on an error), anything else passes.
"""

import contextlib
import sys

_DROP = ("Info: ",)

#: The CLI's ``--verbose`` sets this: Blender's own reports then pass as they are.
keep_reports = False
_TO_STDERR = ("Warning: ", "Error: ")


class _Filter:
    def __init__(self, out):
        self._out, self._pending = out, ""
        self.encoding = getattr(out, "encoding", "utf-8")
        self.errors = getattr(out, "errors", "strict")

    def write(self, text):
        self._pending += text
        while "\n" in self._pending:
            line, self._pending = self._pending.split("\n", 1)
            self._emit(line + "\n")
        return len(text)

    def _emit(self, line):
        if line.startswith(_DROP):
            return
        (sys.__stderr__ if line.startswith(_TO_STDERR) and sys.__stderr__ else self._out).write(line)

    def close_pending(self):
        if self._pending:
            self._emit(self._pending)
            self._pending = ""

    def flush(self):
        self._out.flush()

    def isatty(self):
        return False

    def fileno(self):
        return self._out.fileno()


@contextlib.contextmanager
def _c_progress_dropped():
    """Blender 4.x in background mode prints Cycles' progress ("Fra:1 Mem:8.49M ... Synchronizing
    object") from C straight to descriptor 1 during a bake; 5.0 does not. There, and only there,
    descriptor 1 points to /dev/null for the operator's duration (Python's own writes go through
    ``sys.stdout``, which the caller filters)."""
    import os

    import bpy

    if not bpy.app.background or bpy.app.version >= (5, 0, 0):
        yield
        return
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):
        yield
        return
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


@contextlib.contextmanager
def operator_reports_dropped():
    """Inside: operator reports printed by ``bpy.ops`` do not reach stdout (see the module docstring)."""
    original = sys.stdout
    if original is None or keep_reports:
        yield
        return
    filt = _Filter(original)
    sys.stdout = filt
    try:
        with _c_progress_dropped():
            yield
    finally:
        filt.close_pending()
        if sys.stdout is filt:
            sys.stdout = original

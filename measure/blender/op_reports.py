"""Keep Blender's operator reports off stdout while the API runs an operator.

``bpy.ops`` prints an operator's reports ("Info: Baking map saved to internal image, save it
externally or pack it", one per bake) through ``sys.stdout`` (``PySys_WriteStdout``), so a script
that calls ``api.measure_illuminance`` five times got five such lines on its stdout. The API prints
nothing to stdout: inside :func:`operator_reports_dropped`, "Info: " lines are dropped, "Warning: "
and "Error: " lines go to stderr (the operator also raises on an error), anything else passes.
"""

import contextlib
import sys

#: The CLI's ``--verbose`` sets this: Blender's own reports then pass as they are.
keep_reports = False


class ReportFilter:
    """A text stream for ``sys.stdout`` that drops Blender's operator reports, line by line.

    Lines starting with one of ``drop`` vanish, those starting with one of ``to_stderr`` go to
    ``err`` (default: ``sys.__stderr__`` when written), everything else to ``out``. ``fileno()`` is
    ``out``'s, or OSError with ``has_descriptor=False`` (the CLI, whose descriptor 1 is /dev/null).
    The API drops "Info: " and sends warnings and errors to stderr; the CLI (``commands/_io.py``)
    drops "Error: " too, since it says what failed in one line itself.
    """

    def __init__(self, out, err=None, *, drop=("Info: ",), to_stderr=("Warning: ", "Error: "), has_descriptor=True):
        self._out, self._err, self._pending = out, err, ""
        self._drop, self._to_stderr, self._has_descriptor = tuple(drop), tuple(to_stderr), has_descriptor
        self.encoding = getattr(out, "encoding", "utf-8")
        self.errors = getattr(out, "errors", "strict")

    def write(self, text):
        self._pending += text
        while "\n" in self._pending:
            line, self._pending = self._pending.split("\n", 1)
            self._emit(line + "\n")
        return len(text)

    def _emit(self, line):
        if line.startswith(self._drop):
            return
        err = self._err if self._err is not None else sys.__stderr__
        (err if line.startswith(self._to_stderr) and err else self._out).write(line)

    def close_pending(self):
        """Write (or drop) a last line that has no newline yet."""
        if self._pending:
            self._emit(self._pending)
            self._pending = ""

    def flush(self):
        self._out.flush()

    def close(self):
        self.close_pending()
        self.flush()

    def isatty(self):
        return False

    def fileno(self):
        if not self._has_descriptor:
            raise OSError("no descriptor: Radiometer's filtered stdout")
        return self._out.fileno()

    @property
    def closed(self):
        return False


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
    filt = ReportFilter(original)
    sys.stdout = filt
    try:
        with _c_progress_dropped():
            yield
    finally:
        filt.close_pending()
        if sys.stdout is filt:
            sys.stdout = original

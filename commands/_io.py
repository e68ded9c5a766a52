"""Command-line plumbing (not a subcommand): quiet file descriptors, Ctrl-C, progress, safe writes.

* :func:`blender_logs_silenced` points file descriptors 1 and 2 at ``/dev/null`` while Python's
  ``sys.stdout``/``sys.stderr`` keep writing to the real ones. Blender's C code (bake and render
  reports, "Read blend:", the Cycles device probe) writes to the descriptors directly, so only its
  lines disappear; our results, messages and Python tracebacks stay.
* :class:`Interrupt` turns Ctrl-C into a flag that the measurements poll (``cancelled=``). Cycles
  runs its Python callbacks inside Blender, which swallows a ``KeyboardInterrupt`` raised there:
  the flag survives that. A watchdog thread (woken by ``signal.set_wakeup_fd``; bakes release the
  GIL) ends the process with exit code 130 if the run has not stopped ``GRACE_S`` seconds after
  the signal (a long bake), or at once on a second Ctrl-C, but never while a result file is being
  written (:meth:`Interrupt.critical`).
* :func:`write_text` writes a whole file or nothing (``outputs.write_text``), uninterrupted.
* :func:`check_output_file` / :func:`check_output_dir` say before a long run that an output cannot
  be written.
* :func:`deliver` / :func:`write_json` / :func:`json_text` write a subcommand's result as JSON (the one
  JSON/NaN policy, ``outputs.json_safe``); :func:`ensure_registered` registers the extension when bpy
  runs as a module. Subcommands import these from here, never from ``cli`` (the import contract).
"""

import contextlib
import ctypes
import json
import os
import signal
import socket
import sys
import threading
import time

from ..errors import RadiometerError

GRACE_S = 3.0
EXIT_INTERRUPTED = 130


def _flush_c_streams():
    # Blender prints with C stdio: flush its buffers before a descriptor changes destination.
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


def _stream_fd(stream):
    try:
        return stream.fileno()
    except (AttributeError, OSError, ValueError):
        return None


@contextlib.contextmanager
def blender_logs_silenced(enabled=True, quiet=False):
    """Inside: C writes to fd 1/2 go to /dev/null; ``sys.stdout``/``sys.stderr`` to the real ones.

    ``quiet``: ``sys.stdout`` goes to /dev/null too (errors on stderr only). Yields the descriptor
    of the real stderr (for the isatty test of the progress line).
    """
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    if not enabled:
        if quiet:
            with open(os.devnull, "w") as null, contextlib.redirect_stdout(null):
                yield _stream_fd(sys.__stderr__)
        else:
            yield _stream_fd(sys.stderr)
        return
    _flush_c_streams()
    saved, originals, opened = {}, {}, []
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        for name, fd in (("stdout", 1), ("stderr", 2)):
            stream = getattr(sys, name)
            saved[fd] = os.dup(fd)
            if _stream_fd(stream) == fd:  # the real descriptor (not pytest's capsys, not a StringIO)
                mirror = open(saved[fd], "w", encoding=stream.encoding or "utf-8",
                              errors=getattr(stream, "errors", None) or "backslashreplace", buffering=1,
                              closefd=False)
                originals[name] = stream
                opened.append(mirror)
                setattr(sys, name, mirror)
            os.dup2(null, fd)
        originals.setdefault("stdout", sys.stdout)
        from ..api import operator_report_filter  # the one filter of operator reports (the API's too)

        out = open(os.devnull, "w") if quiet else sys.stdout
        sys.stdout = operator_report_filter(out, sys.stderr, drop=("Info: ", "Error: "), to_stderr=("Warning: ",),
                                  has_descriptor=False)
        opened.insert(0, sys.stdout)
        if quiet:
            opened.append(out)
        yield saved[2]
    finally:
        _flush_c_streams()
        for stream in opened:
            with contextlib.suppress(Exception):
                stream.flush()
        for name, original in originals.items():
            setattr(sys, name, original)
        for stream in opened:
            with contextlib.suppress(Exception):
                stream.close()
        for fd, copy in saved.items():
            os.dup2(copy, fd)
            os.close(copy)
        os.close(null)


def stop_message(signum, forced=False):
    """The one line said when a signal stops the CLI: which files were complete by then (a signal after
    the outputs were written must not say that nothing was), and that none is left half-written."""
    what = "terminated (SIGTERM)" if signum == signal.SIGTERM else "interrupted (Ctrl-C)"
    how = "the run did not stop in time, ended it" if forced else "stopped"
    return f"radiometer: {what}; {how}; {written_files_text()}"


def written_files_text(limit=6):
    """"wrote a.json, b.png" (the files this run completed, the first ``limit`` and a count) or
    "no result file was written"; never a half-written file."""
    from .. import outputs

    done = list(dict.fromkeys(outputs.written))  # each once, in order
    if not done:
        return "no result file was written"
    shown = ", ".join(outputs.shown(p, 100) for p in done[:limit])
    more = f" and {len(done) - limit} more" if len(done) > limit else ""
    return f"wrote {shown}{more} before stopping (each whole); no file left half-written"


def exit_code(signum):
    """128 + the signal number, as shells report a process ended by it (130 Ctrl-C, 143 SIGTERM)."""
    return 128 + int(signum or signal.SIGINT)


def remove_scratch():
    """Remove this process's private temporary folder and everything in it (also the render scratch
    folders the CLI puts there), now: used on every exit, forced ones included."""
    from .. import outputs

    outputs.remove_private_roots()


class Interrupt:
    """Ctrl-C (SIGINT) and SIGTERM as a flag polled by ``cancelled()``, with a watchdog that ends a
    run that does not stop. ``signum`` says which signal came first (the exit code is 128 + it)."""

    def __init__(self, grace_s=GRACE_S):
        self.grace_s = grace_s
        self.signum = None
        self.flag = threading.Event()
        self.finished = threading.Event()
        from .. import outputs

        self._writing = outputs.writing  # one lock with outputs.FileSet.commit: the watchdog waits for both
        self._installed = False
        self._signals = 0
        self.stderr_fd = 2  # main() sets the real stderr while fd 2 points at /dev/null

    def cancelled(self):
        return self.flag.is_set()

    @contextlib.contextmanager
    def critical(self):
        """A section the watchdog will not cut short (writing a result file)."""
        with self._writing:
            yield

    @property
    def exit_code(self):
        return exit_code(self.signum)

    @property
    def message(self):
        return stop_message(self.signum or signal.SIGINT)

    def _handler(self, signum, frame):
        if self.signum is None:
            self.signum = signum
        self.flag.set()
        # Only a flag, never an exception: a KeyboardInterrupt raised in Python that Blender's C code
        # runs (Cycles' render and bake callbacks, depsgraph handlers, property update callbacks,
        # bpy's start-up scripts, the add-on's registration) is printed by Blender as a traceback or
        # swallowed, and one raised in start-up or registration crashed it (issue 21, finding 10).
        # main() and every measurement poll cancelled() between steps (bakes, renders, start-up
        # steps); a step that does not poll is ended by the watchdog after GRACE_S with one line.

    def _watch(self, sock):
        while True:
            try:
                data = sock.recv(64)
            except OSError:
                return
            if not data or self.finished.is_set():
                return
            got = [s for s in (signal.SIGINT, signal.SIGTERM) if s in data]
            if not got:
                continue
            if self.signum is None:
                self.signum = got[0]
            self.flag.set()
            self._signals += 1
            if self._signals == 1 and self.finished.wait(self.grace_s):
                return
            with self._writing:
                if self.finished.is_set():
                    return
                remove_scratch()
                os.write(self.stderr_fd, (stop_message(self.signum, forced=True) + "\n").encode())
                os._exit(self.exit_code)

    def install(self):
        """Install the handler (main thread only; elsewhere Ctrl-C keeps its default behaviour)."""
        if threading.current_thread() is not threading.main_thread():
            return self
        self._old_handler = signal.signal(signal.SIGINT, self._handler)
        self._old_term = signal.signal(signal.SIGTERM, self._handler)
        self._read, self._write_end = socket.socketpair()
        self._write_end.setblocking(False)
        try:
            self._old_wakeup = signal.set_wakeup_fd(self._write_end.fileno(), warn_on_full_buffer=False)
        except ValueError:
            self._old_wakeup = None
        threading.Thread(target=self._watch, args=(self._read,), name="radiometer-sigint", daemon=True).start()
        self._installed = True
        return self

    def uninstall(self):
        self.finished.set()
        if not self._installed:
            return
        self._installed = False
        if self._old_wakeup is not None:
            signal.set_wakeup_fd(self._old_wakeup)
        signal.signal(signal.SIGINT, self._old_handler)
        signal.signal(signal.SIGTERM, self._old_term)
        with contextlib.suppress(OSError):
            self._write_end.send(b"\0")  # wake the watchdog so it sees `finished` and returns
        self._write_end.close()

    def __enter__(self):
        return self.install()

    def __exit__(self, *exc):
        self.uninstall()
        return False


class Progress:
    """A one-line progress display on stderr, drawn only when stderr is a terminal."""

    def __init__(self, fd, enabled=True, label=""):
        self.fd = fd
        self.enabled = bool(enabled and fd is not None and os.isatty(fd))
        self.label = label
        self._last = 0.0
        self._shown = False

    def __call__(self, done, total=1000, seconds_left=None, label=None):
        if not self.enabled:
            return
        if label is not None:
            self.label = label
        now = time.monotonic()
        if now - self._last < 0.1 and done < total:
            return
        self._last = now
        percent = 100.0 * done / total if total else 0.0
        eta = f", about {seconds_left:.0f} s left" if seconds_left is not None and seconds_left >= 1 else ""
        text = f"\r\x1b[2K{self.label + ': ' if self.label else ''}{percent:5.1f} %{eta}"
        os.write(self.fd, text.encode("utf-8", "replace"))
        self._shown = True

    def step(self, label):
        """A report's phase label (``export_report(progress=...)`` passes one string)."""
        self(0, 1, None, label=label)

    def clear(self):
        if self._shown:
            os.write(self.fd, b"\r\x1b[2K")
            self._shown = False


def _describe(exc):
    return exc.strerror or str(exc)


def check_picture_samples(spp):
    """--max-samples of a picture (samples per pixel per render): None, or 16-1024; one line if not."""
    if spp is not None and not 16 <= spp <= 1024:
        raise RadiometerError(f"--max-samples must be 16-1024 samples per pixel, got {spp}")


def check_output_file(path, what="output file"):
    """RadiometerError now if ``path`` cannot be written later (missing folder, a directory, a planted
    link, a folder where no file can be created): ``outputs.check_writable``, which tries instead of
    asking ``access()`` (that says yes to root and then the write fails after the whole run)."""
    if path is None:
        return
    from .. import outputs

    if path == "":
        raise RadiometerError(f"{what}: an empty file name was given")
    if path == "-":
        return
    outputs.check_writable(path, what)


def check_output_dir(path, what="output folder"):
    """Create ``path`` (and parents) now; RadiometerError if that fails or no file can be created in it."""
    if path is None:
        return None
    from .. import outputs

    if not str(path).strip():
        raise RadiometerError(f"{what}: an empty folder name was given")
    full = os.path.abspath(path)
    if os.path.islink(full):
        raise RadiometerError(f"cannot use {what} {outputs.shown(path)}: it is a symbolic link (refusing to follow it)")
    try:
        os.makedirs(full, exist_ok=True)
    except FileExistsError:
        raise RadiometerError(f"cannot use {what} {outputs.shown(path)}: it is a file, not a folder") from None
    except OSError as exc:
        raise RadiometerError(f"cannot create {what} {outputs.shown(path)}: {_describe(exc)}") from None
    outputs.check_writable(os.path.join(full, ".radiometer-probe"), what)
    return full


def write_text(path, text, interrupt=None):
    """``outputs.write_text`` inside the interrupt's critical section (the watchdog waits for it)."""
    from .. import outputs

    guard = interrupt.critical() if interrupt is not None else contextlib.nullcontext()
    with guard:
        return outputs.write_text(path, text)


# --- results of a subcommand: JSON and registration (shared by cli.py and the subcommands) -------------

def json_text(result):
    from ..outputs import json_safe  # the one JSON/NaN policy (NaN and inf as null)

    return json.dumps(json_safe(result), indent=2, allow_nan=False) + "\n"


def write_json(path, result, interrupt=None):
    """Write ``result`` as JSON to ``path`` whole or not at all (RadiometerError with one line if it cannot).
    ``path`` "-" means stdout: ``cli.main`` prints the final result there once the run is over."""
    if path == "-":
        return path
    check_output_file(path, "JSON file")
    return write_text(path, json_text(without_scratch_paths(result)), interrupt)


def without_scratch_paths(result):
    """``result`` with every path into this process's private temporary folder replaced by None:
    the CLI removes that folder when it exits, so a JSON file must not point into it."""
    from .. import outputs

    root = outputs.made_private_root()
    if root is None:
        return result
    prefix = os.path.join(root, "")

    def clean(value):
        if isinstance(value, str) and value.startswith(prefix):
            return None
        if isinstance(value, dict):
            return {k: clean(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [clean(v) for v in value]
        if hasattr(value, "to_dict"):
            return clean(value.to_dict())
        return value

    return clean(outputs.json_safe(result))


def deliver(args, result):
    """Write ``--json`` now (commands call this before optional plots, so a failing plot cannot lose it)."""
    if getattr(args, "json", None) and args.json != "-" and not getattr(args, "_json_written", False):
        write_json(args.json, result, getattr(args, "interrupt", None))
        args._json_written = True


def deliver_with_csv(args, result, csv_text):
    """:func:`deliver` the JSON, then write ``csv_text`` to ``--csv`` when one was asked for (and say so)."""
    deliver(args, result)
    if getattr(args, "csv", None):
        write_text(args.csv, csv_text, getattr(args, "interrupt", None))
        print(f"wrote {args.csv}")


def ensure_registered():
    """With bpy as a module the add-on is not enabled: register it (idempotent)."""
    import bpy

    if not hasattr(bpy.types.Scene, "radiometer"):
        from .. import register

        register()

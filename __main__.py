"""``python -m radiometer <subcommand> [scene.blend] ...`` with bpy installed as a module.

Ctrl-C (SIGINT) and SIGTERM are handled from the first statement, before bpy or the CLI is imported:
until the CLI installs its own handler (and again after it removes it) a signal ends the process at
once with one line and exit code 130 (SIGINT) or 143 (SIGTERM); nothing has been written then, and
the private temporary folder, if one exists, is removed. A KeyboardInterrupt raised inside bpy's
start-up or the add-on's registration crashed Blender (issue 21, finding 10), so none is raised.
"""

import _signal  # the builtin itself: `import signal` imports enum first, a window where Ctrl-C gave a traceback
import os
import sys


def _stop_at_once(signum, _frame):
    what = "terminated (SIGTERM)" if signum == _signal.SIGTERM else "interrupted (Ctrl-C)"
    # The CLI's plumbing may not be imported yet, or only half (the signal came during its import):
    # then the private folders that outputs made, if any, are removed here.
    # Nothing is imported here: the signal may have come in the middle of an import.
    said = "stopped, no file left half-written"
    try:
        io = sys.modules.get(f"{__package__}.commands._io")
        if getattr(io, "written_files_text", None) is not None:  # after the run: say what it wrote
            said = f"stopped; {io.written_files_text()}"
        remove = getattr(io, "remove_scratch", None)
        if remove is not None:
            remove()
        else:
            roots = getattr(sys.modules.get(f"{__package__}.outputs"), "created_roots", ())
            shutil = sys.modules.get("shutil")  # loaded whenever a folder was made (tempfile needs it)
            for folder in roots if shutil is not None else ():
                shutil.rmtree(folder, ignore_errors=True)
    except Exception:  # noqa: BLE001 - a half-imported module: the line and the exit code still follow
        pass
    os.write(2, f"radiometer: {what}; {said}\n".encode())
    os._exit(128 + signum)


if __name__ == "__main__":
    for _sig in (_signal.SIGINT, _signal.SIGTERM):
        _signal.signal(_sig, _stop_at_once)
    import signal

    from .cli import main

    code = main()
    # The run is over and its files are written: a signal now must not kill the interpreter's and
    # Blender's exit half-way (Python puts back the default action while finalising, and Blender's
    # threads would take it): ignore them, which finalisation keeps.
    for _sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(_sig, signal.SIG_IGN)
    bpy = sys.modules.get("bpy")
    if bpy is not None and tuple(getattr(getattr(bpy, "app", None), "version", (5,))) < (5, 0, 0):
        # Blender 4.x as a module can hang or crash while Python finalises (seen with gdb, and a
        # segmentation fault after a Dask run): the results are written, so leave now.
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError, AttributeError):
                pass
        os._exit(code if isinstance(code, int) else 1)
    sys.exit(code)

"""Worker side of the task model: a clean ``sys.path``, the scene opened once per worker process.

Nothing here imports ``bpy`` at module level: LocalCluster's workers are *spawned* with the
parent's ``sys.path``, where an earlier ``import bpy`` put Blender's ``.../bpy/5.0/scripts/...``
folders first; ``import bpy`` then finds Blender's inner ``bpy`` package and fails with "No module
named '_bpy'" (FACTS.md, measured). :func:`clean_sys_path` drops those folders; it runs before the
first ``import bpy`` of a worker (worker plugin, and again at the top of every task, which imports
the task function by name only after that).

The scene arrives as the .blend's bytes (scattered once per worker) or as a path on a shared file
system; the worker keeps one scene open, keyed by the content hash, so consecutive tasks of a run
reuse it. A task function must leave the scene as it found it (every Radiometer measurement does:
``measure/blender/scene_guard.py``), since the next task on that worker sees the same open scene.
"""

import importlib
import os
import re
import sys
import tempfile
import threading
import time

# Blender's own script folders ("bpy/5.0/scripts/modules", "~/.config/blender/5.0/scripts/addons/modules").
_BLENDER_SCRIPTS = re.compile(r"[/\\](bpy|blender)[/\\]\d+\.\d+[/\\]scripts([/\\]|$)", re.IGNORECASE)

# bpy is not thread-safe: a worker started with more than one thread (`dask worker --nthreads 4`) still
# runs one task at a time in this process.
_BPY_LOCK = threading.Lock()

# This process's open scene: content hash, name of the scene, seconds the load took.
_open = {"key": None, "loads": 0, "load_s": 0.0}


def clean_sys_path(path=None):
    """Remove Blender's script folders from ``path`` (default ``sys.path``) in place; returns what was removed.

    Harmless where bpy is already imported (bpy re-adds what it needs on import).
    """
    path = sys.path if path is None else path
    if "bpy" in sys.modules and path is sys.path:
        return []
    removed = [p for p in path if isinstance(p, str) and _BLENDER_SCRIPTS.search(p)]
    path[:] = [p for p in path if p not in removed]
    return removed


def resolve(name):
    """The function named ``"package.module:qualname"``."""
    module, _, qualname = name.partition(":")
    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj


def function_name(fn):
    """``"module:qualname"`` of an importable module-level function (the only kind a worker can run)."""
    from ..errors import RadiometerError

    module, qualname = getattr(fn, "__module__", None), getattr(fn, "__qualname__", "")
    if not module or "<" in qualname or module == "__main__":
        raise RadiometerError(f"{getattr(fn, '__name__', fn)!r} is not an importable module-level function; "
                              "cluster tasks need one (workers import it by name)")
    return f"{module}:{qualname}"


def forget_open_scene():
    """The next task opens its scene again (this process's open file changed under the cache)."""
    _open["key"] = None


def ensure_registered():
    import bpy

    if not hasattr(bpy.types.Scene, "radiometer"):
        import radiometer

        radiometer.register()


def absolute_external_paths(origin_dir):
    """Make the open file's relative external paths ("//tex.png") absolute against ``origin_dir``.

    The file was opened from a temporary copy; its relative paths mean the ORIGINAL file's folder.
    """
    import bpy

    if not origin_dir:
        return
    for collection in (bpy.data.images, bpy.data.libraries, bpy.data.sounds, bpy.data.movieclips,
                       bpy.data.fonts, bpy.data.cache_files, bpy.data.volumes):
        for block in collection:
            path = getattr(block, "filepath", "")
            if path.startswith("//") and not getattr(block, "packed_file", None):
                block.filepath = os.path.normpath(bpy.path.abspath(path, start=origin_dir))
                if collection is bpy.data.libraries:
                    block.reload()


def missing_external_files(label):
    """RadiometerError naming the first image or library the open file needs that is not on disk.

    Cycles renders a missing texture magenta and a missing library not at all: either would be a
    wrong reading, so the task fails instead.
    """
    import bpy

    from ..errors import RadiometerError

    for lib in bpy.data.libraries:
        path = bpy.path.abspath(lib.filepath)
        if not lib.packed_file and not os.path.exists(path):
            raise RadiometerError(f"{label}: linked library {lib.filepath} is missing ({path})")
    for image in bpy.data.images:
        if image.users == 0 or image.packed_file or image.source not in {"FILE", "SEQUENCE", "TILED"}:
            continue
        path = bpy.path.abspath(image.filepath_raw or image.filepath)
        if image.source == "FILE" and not os.path.exists(path):
            raise RadiometerError(f"{label}: texture file of image '{image.name}' is missing: {path}")


def open_scene(source):
    """The scene of ``source`` (a ``SceneSource``), opened in this process unless already open.

    Returns (scene, seconds spent loading: 0 when cached).
    """
    import bpy

    from ..errors import RadiometerError

    if _open["key"] == source.key:
        return _scene_of(source), 0.0
    started = time.perf_counter()
    if source.data is not None:
        folder = tempfile.mkdtemp(prefix="radiometer-scene-")
        path = os.path.join(folder, os.path.basename(source.name) or "scene.blend")
        with open(path, "wb") as f:
            f.write(source.data)
    else:
        path = source.path
        if not os.path.exists(path):
            raise RadiometerError(f"{source.name}: not found on this worker ({path}); a path source needs a "
                                  "file system shared by every worker")
    _open["key"] = None
    try:
        bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
    except RuntimeError as exc:
        lines = [line for line in str(exc).strip().splitlines() if line.strip()]
        raise RadiometerError(f"cannot open {source.name}: {lines[-1] if lines else 'not a .blend file'}") from None
    finally:
        if source.data is not None:  # Blender has read it; nothing of ours stays on the worker's disk
            os.remove(path)
            os.rmdir(folder)
    ensure_registered()
    if source.data is not None:
        absolute_external_paths(source.origin_dir)
    missing_external_files(source.name)
    scene = _scene_of(source)
    _open.update(key=source.key, loads=_open["loads"] + 1, load_s=time.perf_counter() - started)
    return scene, _open["load_s"]


def _scene_of(source):
    import bpy

    from ..errors import RadiometerError

    if not source.scene_name:
        return bpy.context.scene
    if source.scene_name not in bpy.data.scenes:
        raise RadiometerError(f"{source.name}: no scene named '{source.scene_name}'")
    return bpy.data.scenes[source.scene_name]


def set_cycles_threads(scene, threads):
    """Cycles threads for this worker's copy of the scene (cores of the host / workers on it)."""
    if threads:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = int(threads)


def run_task(source, fn_name, kwargs, index, label, threads_by_host):
    """One task on a worker: open (or reuse) the scene, run ``fn(scene, **kwargs)``.

    Returns (result, statistics dict). Any failure becomes ONE RadiometerError line that names the
    file and the task (no worker traceback reaches the user).
    """
    clean_sys_path()
    with _BPY_LOCK:
        return _run_task_locked(source, fn_name, kwargs, index, label, threads_by_host)


def _run_task_locked(source, fn_name, kwargs, index, label, threads_by_host):
    from ..errors import RadiometerError

    started = time.perf_counter()
    where = f"{label} task {index + 1}"
    try:
        fresh = "bpy" not in sys.modules
        import bpy  # noqa: F401  (first task of a worker: Blender's start-up, timed apart from the scene load)

        import_s = time.perf_counter() - started if fresh else 0.0
        fn = resolve(fn_name)
        scene, load_s = open_scene(source)
        host = _this_host()
        set_cycles_threads(scene, (threads_by_host or {}).get(host))
        result = fn(scene, **kwargs)
    except RadiometerError as exc:
        raise RadiometerError(f"{where} ({source.name}): {exc}") from None
    except Exception as exc:  # a scene or code failure: one line, not a traceback storm
        text = " ".join(str(exc).split()) or type(exc).__name__
        raise RadiometerError(f"{where} ({source.name}) failed: {type(exc).__name__}: {text}") from None
    stats = {"index": index, "worker": _worker_address(), "pid": os.getpid(), "import_s": import_s, "load_s": load_s,
             "seconds": time.perf_counter() - started}
    return result, stats


def _worker_address():
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return "local"


def _this_host():
    address = _worker_address()
    return host_of(address)


def host_of(address):
    """'tcp://10.0.0.5:40123' -> '10.0.0.5'."""
    rest = address.split("://", 1)[-1]
    return rest.rsplit(":", 1)[0] if ":" in rest else rest


def describe(scene):
    """A task that measures nothing: which process and Blender ran it, with which Cycles threads.

    A health check of a cluster (every worker opens the scene and answers) and the benchmark's
    measure of the per-task overhead (dispatch, arguments and result travelling, no rendering).
    """
    import bpy

    return {"pid": os.getpid(), "worker": _worker_address(), "blender": bpy.app.version_string, "scene": scene.name,
            "threads_mode": scene.render.threads_mode, "threads": scene.render.threads}

"""Run the task model in this process or on a Dask cluster; clients for ``--workers`` / ``--scheduler``.

A task is ``fn(scene, **kwargs)``: ``fn`` an importable module-level function, ``kwargs`` one time /
sky patch / frame / variant and a chunk of points, the result anything picklable (readings and
their statistics). Results come back in the order of ``kwargs_list`` whatever order the tasks ran
in. Seeds are the caller's: put the seed in each task's kwargs (e.g. ``seed=index`` or a fixed
one), so a task's seed does not depend on the number of workers or on which worker ran it. That
makes in-process and cluster runs agree within their stated errors, not digit for digit (docs/cluster.md).
"""

import contextlib
import logging
import os
import time
import uuid
from concurrent.futures import CancelledError as FutureCancelledError  # Dask's FutureCancelledError derives from it

from ..errors import MeasurementCancelled, RadiometerError
from . import source as sources
from . import worker

INSTALL_HINT = ("Dask is not installed: pip install dask==2026.8.0 distributed==2026.8.0 (the versions in "
                "requirements.txt) into the Python that runs Radiometer")
CONNECT_TIMEOUT_S = 5.0
#: Local worker processes allowed per usable core (``--workers``); see :func:`max_local_workers`.
WORKERS_PER_CORE = 4
_POLL_S = 0.02  # how often the client looks for finished tasks and polls cancelled() (s)
#: Times a finished task whose result was lost with its worker is run again before the run fails.
_MAX_RESUBMITS = 3
#: How long a resubmission waits for a worker when every worker was lost (the nannies restart them).
_WORKER_WAIT_S = 120.0


def available():
    """True when ``dask.distributed`` can be imported (the scale-out features are offered then)."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


def _require_distributed():
    if not available():
        raise RadiometerError(INSTALL_HINT)


def connect(address, *, timeout_s=CONNECT_TIMEOUT_S):
    """A ``distributed.Client`` for the scheduler at ``address`` ("tcp://host:8786" or "host:8786").

    Every way of not finding a scheduler there is one RadiometerError within ``timeout_s`` seconds
    (plus the client's own start), and nothing is printed afterwards:

    - a malformed address is refused before anything connects;
    - before a Client exists, a probe in its own event loop, bounded as a whole by ``timeout_s``,
      connects, does Dask's handshake and asks the peer who it is: an unreachable port, a service
      that never answers the handshake (an HTTP server, e.g. the dashboard's port 8787) or one that
      answers garbage (measured: "Maximum allowed dimension exceeded", or a MemoryError for a
      3 EiB frame) each become one line. ``distributed``'s own connect bounds the TCP connect but
      not the handshake read (measured: an HTTP server kept ``Client(...)`` waiting past 90 s);
    - a Client whose start fails anyway is closed there, so that its ``__del__`` does not print a
      ``TimeoutError`` traceback 10 s later (measured before this guard).
    """
    _require_distributed()
    address = _scheduler_address(address)
    _probe_scheduler(address, timeout_s)
    client_class = _guarded_client_class()
    try:
        return client_class(address, timeout=f"{timeout_s}s", set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise RadiometerError(f"cannot reach the Dask scheduler at {address} within {timeout_s:g} s "
                              f"({_short(exc)})") from None
    except Exception as exc:  # the probe passed, yet the client could not start: still one line
        raise RadiometerError(f"the Dask scheduler at {address} did not accept a client "
                              f"({type(exc).__name__}: {_short(exc)})") from None


def _short(exc, limit=160):
    reason = " ".join(str(exc).split()) or type(exc).__name__
    return reason if len(reason) <= limit else reason[:limit - 3] + "..."


def _scheduler_address(address):
    """The address with its scheme ("host:8786" -> "tcp://host:8786"); a malformed one is one line."""
    from distributed.comm.addressing import get_address_host_port, normalize_address, parse_address

    if not isinstance(address, str) or not address.strip():
        raise RadiometerError(f"not a scheduler address: {address!r} (expected e.g. tcp://host:8786)")
    address = address.strip()
    try:
        normal = normalize_address(address)
        if parse_address(normal)[0] != "inproc":  # a host and a port, for the schemes that have them
            port = get_address_host_port(normal)[1]
            if port is not None and not 0 < int(port) < 65536:
                raise ValueError(f"port {port} is not between 1 and 65535")
    except (ValueError, TypeError) as exc:
        raise RadiometerError(f"not a scheduler address: {address} ({_short(exc)}; expected e.g. "
                              "tcp://host:8786)") from None
    return normal


def _probe_scheduler(address, timeout_s):
    """Connect, handshake and ask ``identity`` within ``timeout_s`` in a private loop; one line if not.

    Runs in a daemon thread with its own event loop (the caller may be inside one: Jupyter), joined
    with a deadline, so nothing the peer does can keep the caller waiting longer.
    """
    import asyncio
    import threading

    outcome = {"stage": "connect"}

    async def probe():
        from distributed.comm import connect as comm_connect
        from distributed.comm.addressing import get_address_host_port
        from distributed.security import Security

        try:
            host, port = get_address_host_port(address)
        except ValueError:  # a scheme without host and port (inproc): Dask's connect alone
            host = None
        while host is not None:  # is anything listening? (refused: retried, a scheduler may be starting)
            try:
                _, writer = await asyncio.open_connection(host, port)
            except ConnectionRefusedError as exc:
                outcome["refused"] = exc
                await asyncio.sleep(0.2)
                continue
            writer.close()
            outcome.pop("refused", None)
            break
        outcome["stage"] = "handshake"
        comm = await comm_connect(address, timeout=timeout_s, **Security().get_connection_args("client"))
        try:
            outcome["stage"] = "identity"
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            with contextlib.suppress(BaseException):
                await asyncio.wait_for(comm.close(), 1.0)

    def run():
        try:
            outcome["reply"] = asyncio.run(asyncio.wait_for(probe(), timeout_s))
        except BaseException as exc:  # noqa: BLE001 - reported by the caller, never printed here
            outcome["error"] = exc

    thread = threading.Thread(target=run, name="radiometer-scheduler-probe", daemon=True)
    thread.start()
    thread.join(timeout_s + 1.0)
    error = outcome.get("error")
    timed_out = thread.is_alive() or isinstance(error, (asyncio.TimeoutError, TimeoutError))
    if outcome["stage"] == "connect" and (timed_out or isinstance(error, OSError)):
        reason = outcome.get("refused") or (error if not timed_out else None) or "no answer"
        raise RadiometerError(f"cannot reach the Dask scheduler at {address} within {timeout_s:g} s "
                              f"({_short(reason)})")
    if timed_out:
        raise RadiometerError(f"no Dask scheduler answered at {address} within {timeout_s:g} s: something listens "
                              "there but does not speak Dask's protocol (the dashboard's HTTP port, 8787, or "
                              "another service?); the scheduler's port is 8786 by default")
    if error is not None:
        raise RadiometerError(f"{address} is not a Dask scheduler: it answered Dask's handshake with something "
                              f"else ({type(error).__name__}: {_short(error, 100)})")
    reply = outcome.get("reply")
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        kind = reply.get("type") if isinstance(reply, dict) else type(reply).__name__
        raise RadiometerError(f"{address} is not a Dask scheduler (it says it is {kind!s:.40}): give the "
                              "scheduler's address, e.g. tcp://host:8786")


def _guarded_client_class():
    """``distributed.Client`` whose failed start leaves nothing behind to print from ``__del__``."""
    global _GuardedClient
    if _GuardedClient is None:
        from distributed import Client

        class GuardedClient(Client):
            def start(self, **kwargs):
                try:
                    return super().start(**kwargs)
                except BaseException:
                    # Half-made: Client.__del__ would call close(), which waits 10 s for a loop that
                    # never connected and prints "Exception ignored ... TimeoutError". Stop it here.
                    self.status = "closed"
                    with contextlib.suppress(Exception):
                        self._loop_runner.stop()
                    raise

        _GuardedClient = GuardedClient
    return _GuardedClient


_GuardedClient = None


def local_client(workers):
    """A ``Client`` on a new LocalCluster of ``workers`` processes, one thread each (bpy is not thread-safe).

    Close it (``client.close(); client.cluster.close()``, or use :func:`cluster_client`) to stop
    the worker processes.
    """
    _require_distributed()
    from distributed import Client, LocalCluster

    workers = check_workers(workers)
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR, host="127.0.0.1")
    return Client(cluster, set_as_default=False)


def max_local_workers():
    """The most worker processes :func:`local_client` starts: ``WORKERS_PER_CORE`` × this machine's cores.

    Each worker is a Python process with bpy loaded (hundreds of MB before a scene) rendering with
    cores / workers Cycles threads; past a few per core they only add memory and start-up time.
    """
    return WORKERS_PER_CORE * _usable_cores()


def check_workers(workers):
    """``workers`` as an int between 1 and :func:`max_local_workers`, or a one-line RadiometerError."""
    try:
        count = int(workers)
    except (TypeError, ValueError):
        raise RadiometerError(f"--workers must be a whole number, got {workers!r}") from None
    if count != workers or count < 1:
        raise RadiometerError(f"--workers must be a whole number of at least 1, got {workers!r}")
    limit = max_local_workers()
    if count > limit:
        raise RadiometerError(f"--workers {count} is more than {WORKERS_PER_CORE} per core ({limit} on the "
                              f"{_usable_cores()} cores here): each worker is a Blender process; use at most "
                              f"{limit}, or a cluster of several machines (--scheduler)")
    return count


@contextlib.contextmanager
def cluster_client(workers=None, scheduler=None):
    """Yields None (this process), a LocalCluster client (``workers``) or a scheduler's (``scheduler``).

    On exit (normal, error, Ctrl-C) the client is closed, and a LocalCluster this started is shut
    down with its worker processes: no worker is left running.
    """
    if workers and scheduler:
        raise RadiometerError("give either --workers (a local cluster) or --scheduler (an existing one), not both")
    if not workers and not scheduler:
        yield None
        return
    client = connect(scheduler) if scheduler else local_client(workers)
    try:
        yield client
    finally:
        cluster = None if scheduler else client.cluster
        with contextlib.suppress(Exception):
            client.close(timeout=10)
        if cluster is not None:
            with contextlib.suppress(Exception):
                cluster.close(timeout=10)


def _usable_cores():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def _prepare(client):
    """Worker plugin (clean sys.path) once per client; Cycles threads per host = cores / workers there."""
    if not getattr(client, "_radiometer_prepared", False):
        from .plugin import CleanSysPath

        client.register_plugin(CleanSysPath())
        client._radiometer_prepared = True
    workers = client.scheduler_info(n_workers=-1)["workers"] if _takes_n_workers(client) \
        else client.scheduler_info()["workers"]
    if not workers:
        raise RadiometerError("the Dask cluster has no workers (start some: dask worker ADDRESS --nthreads 1)")
    cores = client.run(_usable_cores)
    per_host = {}
    for address in workers:
        host = worker.host_of(address)
        per_host.setdefault(host, []).append(cores.get(address, 1))
    return {host: max(1, min(c) // len(c)) for host, c in per_host.items()}


def _takes_n_workers(client):
    import inspect

    return "n_workers" in inspect.signature(client.scheduler_info).parameters


def _notify(progress, done, total, started):
    if progress is None:
        return
    elapsed = time.monotonic() - started
    left = elapsed / done * (total - done) if done else None
    from ..progress import reporter  # one adapter for both callback forms

    reporter(progress)(done, total, left)


def run_scene_tasks(scene_or_path, fn, kwargs_list, *, client=None, progress=None, cancelled=None,
                    label="sun study", stats=None, shared=False):
    """``[fn(scene, **kw) for kw in kwargs_list]``, in this process or on a Dask cluster, in order.

    Parameters
    ----------
    scene_or_path : bpy.types.Scene, str or SceneSource
        The live scene (sent as a copy of the open file: the user's file is never written) or a
        .blend path. Without a client a path is opened in this process (see :func:`run_file_tasks`).
    fn : callable
        An importable module-level function ``fn(scene, **kwargs) -> picklable``; it must leave
        the scene as it found it (Radiometer's measurements do), since a worker reuses its scene.
    kwargs_list : iterable of dict
        One dict per task. Put the task's seed in it: results must not depend on workers.
    client : distributed.Client, optional
        None: sequentially in this process. A client: the scene travels once per worker (its
        bytes scattered to every worker, opened there and cached by content hash), one task per
        worker at a time, Cycles threads = the host's cores / its workers.
    progress : callable, optional
        ``progress(done, total, seconds_left)`` after every finished task (ETA from the mean so far).
    cancelled : callable, optional
        Polled between tasks; True cancels the remaining futures and raises MeasurementCancelled.
    label : str
        What error messages and the progress line call the run ("sun study task 7 (room.blend): ...").
    stats : dict, optional
        Filled with ``tasks`` (per task: worker, pid, load_s, seconds), ``workers`` (addresses that
        ran tasks), ``scene_bytes``, ``scatter_s`` and ``wall_s``.
    shared : bool
        Send the path instead of the bytes (a file system every worker shares).

    Returns
    -------
    list
        ``fn``'s results in the order of ``kwargs_list``.
    """
    kwargs_list = [dict(kw) for kw in kwargs_list]
    return run_file_tasks([scene_or_path] * len(kwargs_list), fn, kwargs_list, client=client, progress=progress,
                          cancelled=cancelled, label=label, stats=stats, shared=shared)


def run_file_tasks(scenes, fn, kwargs_list, *, client=None, progress=None, cancelled=None, label="batch",
                   stats=None, shared=False):
    """Like :func:`run_scene_tasks` with one scene (or path) per task (``measure_batch``: many files).

    Without a client, paths are opened in this process one after the other, as ``blender -b FILE``
    would, and afterwards the file that was open is opened again (an untitled session becomes a new
    empty file). In the Blender UI this is refused while the open file has unsaved changes; headless
    bpy cannot tell (it reports every session as changed), so a headless script's unsaved changes
    are not kept: pass a client to keep this process's session as it is. A bpy Scene runs as it is.
    """
    scenes, kwargs_list = list(scenes), [dict(kw) for kw in kwargs_list]
    if len(scenes) != len(kwargs_list):
        raise RadiometerError(f"{len(scenes)} scenes for {len(kwargs_list)} tasks")
    fn_name = worker.function_name(fn)
    stats = {} if stats is None else stats
    stats.update(tasks=[None] * len(scenes), workers=set(), scene_bytes=0, scatter_s=0.0, wall_s=0.0)
    started = time.monotonic()
    try:
        if client is None:
            return _run_in_process(scenes, fn, kwargs_list, progress, cancelled, label, stats)
        _require_distributed()
        return _run_on_cluster(scenes, fn_name, kwargs_list, client, progress, cancelled, label, stats, shared)
    finally:
        stats["wall_s"] = time.monotonic() - started


# --- in this process -----------------------------------------------------------------------------

def _run_in_process(scenes, fn, kwargs_list, progress, cancelled, label, stats):
    import bpy

    results, started = [], time.monotonic()
    total = len(kwargs_list)
    with _file_session(scenes) as open_file:
        for index, (item, kwargs) in enumerate(zip(scenes, kwargs_list)):
            if cancelled is not None and cancelled():
                raise MeasurementCancelled(f"{label} cancelled after {index} of {total} tasks; the scene was "
                                           "restored")
            t0 = time.perf_counter()
            name = _name_of(item)
            try:
                if hasattr(item, "view_layers"):
                    scene, load_s = item, 0.0
                    worker.missing_external_files(name)
                else:
                    scene, load_s, name = open_file(item)
                results.append(fn(scene, **kwargs))
            except MeasurementCancelled:
                raise
            except RadiometerError as exc:
                raise RadiometerError(f"{label} task {index + 1} ({name}): {exc}") from None
            stats["tasks"][index] = {"index": index, "worker": "local", "pid": os.getpid(), "load_s": load_s,
                                     "seconds": time.perf_counter() - t0}
            stats["workers"].add("local")
            _notify(progress, index + 1, total, started)
    return results


def _name_of(item):
    import bpy

    if hasattr(item, "view_layers"):
        return os.path.basename(bpy.data.filepath) or item.name
    if isinstance(item, sources.SceneSource):
        return item.name
    return os.path.basename(os.fspath(item))


@contextlib.contextmanager
def _file_session(scenes):
    """Opens paths in this process on demand; reopens the user's file afterwards."""
    import bpy

    paths = [s for s in scenes if not hasattr(s, "view_layers")]
    if not paths:
        yield None
        return
    if bpy.data.is_dirty and not bpy.app.background:  # (headless bpy reports every session as dirty)
        raise RadiometerError("running on .blend files in this process would replace the open file, which has "
                              "unsaved changes: save it first, or pass client= (e.g. a LocalCluster) to run in "
                              "worker processes")
    previous = bpy.data.filepath

    def open_file(item):
        source = item if isinstance(item, sources.SceneSource) else sources.from_path(os.fspath(item), shared=True)
        scene, load_s = worker.open_scene(source)
        return scene, load_s, source.name

    try:
        yield open_file
    finally:
        worker.forget_open_scene()
        with contextlib.suppress(Exception):
            if previous and os.path.exists(previous):
                bpy.ops.wm.open_mainfile(filepath=previous, load_ui=False)
            else:
                bpy.ops.wm.read_homefile(use_empty=True)
            worker.ensure_registered()


# --- on a Dask cluster ---------------------------------------------------------------------------

def _run_on_cluster(scenes, fn_name, kwargs_list, client, progress, cancelled, label, stats, shared):
    from distributed import as_completed

    total = len(kwargs_list)
    if total == 0:
        return []
    items = [sources.as_source(s, shared=shared) for s in scenes]
    distinct = {}
    for item in items:
        distinct.setdefault((item.key, item.scene_name, item.path), item)
    stats["scene_bytes"] = sum(s.size for s in distinct.values())
    threads_by_host = _prepare(client)
    t0 = time.perf_counter()
    uses = {k: sum(1 for i in items if (i.key, i.scene_name, i.path) == k) for k in distinct}
    # A scene many tasks share goes to every worker once (broadcast); one-task scenes go to one
    # worker each (round robin) and move only where their task runs.
    many = [k for k in distinct if uses[k] > 1]
    single = [k for k in distinct if uses[k] == 1]
    scattered = {}
    for k in many:
        scattered[k] = client.scatter(distinct[k], broadcast=True, hash=False)
    if single:
        scattered.update(zip(single, client.scatter([distinct[k] for k in single], hash=False)))
    stats["scatter_s"] = time.perf_counter() - t0
    run = uuid.uuid4().hex[:8]
    resubmits = [0] * total

    def submit(index):
        item, kwargs = items[index], kwargs_list[index]
        return client.submit(worker.run_task, scattered[(item.key, item.scene_name, item.path)], fn_name, kwargs,
                             index, label, threads_by_host, key=f"radiometer-{run}-{index}-{resubmits[index]}",
                             pure=False)

    def rescatter_if_lost(index):
        # A scene whose workers all died (a SIGKILL, or Blender crashing in a worker) is gone from the
        # cluster: a task resubmitted on it would come back cancelled again. Send it anew (measured: two
        # workers lost to signal 11 left a run failing "batch task 4 ... failed: NoneType: None").
        item = items[index]
        key = (item.key, item.scene_name, item.path)
        if scattered[key].status == "finished":
            return
        with contextlib.suppress(Exception):
            client.wait_for_workers(1, timeout=_WORKER_WAIT_S)
        scattered[key] = client.scatter(distinct[key], broadcast=uses[key] > 1, hash=False)

    futures = [submit(index) for index in range(total)]
    index_of = {f.key: i for i, f in enumerate(futures)}
    results = [None] * total
    pending, done_count, started = set(futures), 0, time.monotonic()
    try:
        arrivals = as_completed(futures, loop=client.loop)
        while pending:
            if cancelled is not None and cancelled():
                raise MeasurementCancelled(f"{label} cancelled after {done_count} of {total} tasks")
            finished = arrivals.next_batch(block=False)
            if not finished:
                time.sleep(_POLL_S)
                continue
            for future in finished:
                pending.discard(future)
                index = index_of[future.key]
                try:
                    # This loop cancels nothing: "cancelled" is a task lost with its worker. "lost" or
                    # "pending" is a finished task whose result died with its worker and that the scheduler
                    # is computing again (CI: a SIGKILL right after the first result gave status "lost",
                    # exception None, "failed: NoneType: None"): both are run again under a new key.
                    if future.status in ("cancelled", "lost", "pending"):
                        raise FutureCancelledError(future.key)
                    if future.status != "finished":
                        raise _task_error(future, index, label, items[index].name)
                    results[index], task_stats = future.result()
                except FutureCancelledError:
                    # Lost with a worker that died (measured, a SIGKILLed worker: the future came back
                    # cancelled, or finished with its result "already forgotten"): run the task again.
                    if resubmits[index] >= _MAX_RESUBMITS:
                        raise RadiometerError(
                            f"{label} task {index + 1} ({items[index].name}) was lost with its worker "
                            f"{resubmits[index] + 1} times (a crash in Blender or out of memory); see the "
                            "worker logs") from None
                    resubmits[index] += 1
                    with contextlib.suppress(Exception):
                        client.cancel([future], force=True)  # the scheduler's own recomputation, if any
                    rescatter_if_lost(index)
                    again = submit(index)
                    index_of[again.key] = index
                    pending.add(again)
                    arrivals.add(again)
                    continue
                stats["tasks"][index] = task_stats
                stats["workers"].add(task_stats["worker"])
                done_count += 1
                _notify(progress, done_count, total, started)
        return results
    finally:
        if pending:  # error, cancel or Ctrl-C: nothing of this run keeps running on the cluster
            with contextlib.suppress(Exception):
                client.cancel(list(pending), force=True)
        with contextlib.suppress(Exception):
            client.cancel(list(scattered.values()), force=True)


def _task_error(future, index, label, name):
    """ONE line for a failed task (the worker already made scene failures one line)."""
    try:
        exc = future.exception(timeout=10)
    except Exception as other:  # cancelled on the cluster, lost connection
        return RadiometerError(f"{label} task {index + 1} ({name}) did not finish: {type(other).__name__}")
    if isinstance(exc, RadiometerError):
        return RadiometerError(str(exc))
    text = " ".join(str(exc).split())
    if type(exc).__name__ == "KilledWorker":
        return RadiometerError(f"{label} task {index + 1} ({name}): the workers running it died repeatedly "
                               "(out of memory or a crash in Blender); see the worker logs")
    return RadiometerError(f"{label} task {index + 1} ({name}) failed: {type(exc).__name__}: {text}")


def cluster_info(address, *, timeout_s=CONNECT_TIMEOUT_S):
    """What the cluster at ``address`` offers: a dict with ``address``, ``workers``, ``threads``
    (Dask threads over all workers: 1 per worker is what Radiometer needs), ``hosts`` and
    ``memory_bytes``. An unreachable scheduler is a one-line RadiometerError."""
    client = connect(address, timeout_s=timeout_s)
    try:
        workers = (client.scheduler_info(n_workers=-1) if _takes_n_workers(client) else
                   client.scheduler_info())["workers"]
    finally:
        with contextlib.suppress(Exception):
            client.close(timeout=10)
    return {"address": address, "workers": len(workers),
            "threads": sum(int(w.get("nthreads", 0)) for w in workers.values()),
            "hosts": len({worker.host_of(a) for a in workers}),
            "memory_bytes": sum(int(w.get("memory_limit") or 0) for w in workers.values())}

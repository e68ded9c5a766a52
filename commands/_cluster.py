"""``--workers N`` / ``--scheduler ADDRESS`` for the subcommands that scale out on Dask (not a subcommand).

Use: ``add_arguments(parser)`` in a subcommand's ``add_arguments``, then
``with client(args) as c: api_function(..., client=c, progress=task_progress(args, "sun study"))``.
No option: the work runs in this process. ``--workers N`` starts a LocalCluster of N worker
processes (one thread each: bpy is not thread-safe) and stops it when the command ends, Ctrl-C
included; ``--scheduler`` uses an existing cluster (``dask scheduler`` / ``dask worker``).
"""


def add_arguments(parser):
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int, metavar="N", default=None,
                       help="run on a local Dask cluster of N worker processes (one thread each; Cycles threads "
                            "= cores / N; at most 4 per core); needs dask and distributed")
    group.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786 (started with `dask "
                            "scheduler` and `dask worker ADDRESS --nthreads 1`; see docs/cluster.md)")


def client(args):
    """Context manager yielding the Dask client the options ask for (None: this process)."""
    from ..cluster import check_workers, cluster_client

    workers = getattr(args, "workers", None)
    if workers is not None:
        check_workers(workers)  # before any work: 1 to 4 per core
    return cluster_client(workers=workers, scheduler=getattr(args, "scheduler", None))


def task_progress(args, label):
    """A ``progress(done, total, seconds_left)`` that shows "LABEL: 3/8 tasks  37.5 %, about 12 s left"."""
    shown = getattr(args, "progress", None)
    if shown is None:
        return None

    def progress(done, total, seconds_left=None):
        shown(done, total, seconds_left, label=f"{label} {done}/{total} tasks")

    return progress

"""Scale-out on Dask: the task model, run in this process or on any ``dask.distributed`` cluster.

Contract (other modules code against it)::

    from radiometer.cluster import run_scene_tasks
    results = run_scene_tasks(scene_or_path, fn, kwargs_list, *, client=None, progress=None,
                              cancelled=None, label="sun study")

Importing this package needs neither bpy nor dask (the UI checks :func:`available`).
"""

from .engine import (INSTALL_HINT, available, check_workers, cluster_client, cluster_info, connect,  # noqa: F401
                     local_client, max_local_workers, run_file_tasks, run_scene_tasks)

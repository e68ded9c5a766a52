"""The Dask worker plugin that cleans ``sys.path`` before any task imports bpy (imports distributed)."""

from distributed.diagnostics.plugin import WorkerPlugin

from .worker import clean_sys_path


class CleanSysPath(WorkerPlugin):
    """Drop Blender's script folders from ``sys.path`` when a worker starts.

    Registered by the engine on every cluster it uses; the scheduler also applies it to workers
    that join later (one the nanny restarts after a crash).
    """

    name = "radiometer-clean-sys-path"
    idempotent = True

    def setup(self, worker):
        clean_sys_path()

"""A temporary scene for Radiometer's own renders that must not see the user's objects (the world
alone on a sensor, the mirror-ball probe): a new scene that shares only what it is given (the world),
whose data-blocks and scratch folder are removed on exit, whatever happens. The user's own scene is
never rebuilt this way: measurements in it borrow and restore it (``scene_guard.preserved_scene``)."""

import contextlib
import shutil
import tempfile

from ...errors import RadiometerError


def scratch_folder():
    """A private temporary folder for render outputs (the caller removes it); one-line error if none."""
    try:
        return tempfile.mkdtemp(prefix="radiometer_")
    except OSError as exc:
        raise RadiometerError(f"cannot create a temporary folder for the render ({exc.strerror}: "
                              f"{tempfile.gettempdir()}); set TMPDIR to a writable folder") from None


class TemporaryScene:
    """``scene``: the new scene; :meth:`keep` / :meth:`link` record what was made for it,
    :meth:`scratch` gives a private folder for render outputs; all removed on exit."""

    def __init__(self, scene):
        self.scene = scene
        self.created = []
        self.folder = None

    def keep(self, block):
        """Remove ``block`` (a data-block made for this scene) on exit; returns it."""
        self.created.append(block)
        return block

    def link(self, obj):
        """Keep ``obj`` and link it into the scene; returns it."""
        self.scene.collection.objects.link(self.keep(obj))
        return obj

    def scratch(self):
        """A private temporary folder for this scene's render outputs (made once)."""
        if self.folder is None:
            self.folder = scratch_folder()
        return self.folder


@contextlib.contextmanager
def temporary_scene(name, *, like=None):
    """A new Cycles scene named ``name``; with ``like`` (the user's scene) it shares its world, copies its
    unit scale and reads its luminous efficacy (``efficacy.follow``), so that readings in it mean the same."""
    import bpy

    from . import efficacy

    rig = TemporaryScene(bpy.data.scenes.new(name))
    try:
        rig.scene.render.engine = "CYCLES"
        if like is None:
            yield rig
        else:
            rig.scene.world = like.world
            rig.scene.unit_settings.scale_length = like.unit_settings.scale_length
            with efficacy.follow(rig.scene, like):
                yield rig
    finally:
        bpy.data.scenes.remove(rig.scene)
        if rig.created:
            bpy.data.batch_remove(ids=tuple(reversed(rig.created)))
        if rig.folder is not None:
            shutil.rmtree(rig.folder, ignore_errors=True)

"""What travels to the workers: a scene as the .blend's bytes (or a path on a shared file system).

The live scene is written through ``save_as_mainfile(copy=True)`` into a private temporary folder
and read back as bytes: the user's file, its path and its dirty flag are untouched. Relative paths
to external files ("//tex.png") keep meaning the ORIGINAL file's folder (``origin_dir``); workers
make them absolute against it, so textures must be reachable at that path from every worker (a
shared file system) or packed (File > External Data > Pack Resources).
"""

import dataclasses
import hashlib
import os
import shutil
import tempfile

from ..errors import RadiometerError

_MAGICS = (b"BLENDER", b"\x28\xb5\x2f\xfd", b"\x1f\x8b")  # plain, zstd, gzip


@dataclasses.dataclass(frozen=True)
class SceneSource:
    """A scene a worker can open: ``data`` (bytes) or ``path`` (shared file system), never both.

    ``key``: SHA-256 of the content (the worker's cache key); ``name``: what messages call it
    (the file's name); ``scene_name``: the scene to measure in that file ("" = the file's active scene).
    """

    name: str
    key: str
    scene_name: str
    data: bytes = dataclasses.field(default=None, repr=False)
    path: str = None
    origin_dir: str = ""

    @property
    def size(self):
        return len(self.data) if self.data is not None else os.path.getsize(self.path)


def check_blend_file(path):
    """RadiometerError (one line) unless ``path`` is an existing .blend file."""
    if not os.path.exists(path):
        raise RadiometerError(f"no such file: {path}")
    if os.path.isdir(path):
        raise RadiometerError(f"{path} is a directory, not a .blend file")
    with open(path, "rb") as f:
        magic = f.read(7)
    if not any(magic.startswith(m) for m in _MAGICS):
        raise RadiometerError(f"{path} is not a .blend file")


def from_path(path, *, scene_name=None, shared=False):
    """A source for a .blend on disk: its bytes (default) or, with ``shared``, its path."""
    check_blend_file(path)
    path = os.path.abspath(path)
    with open(path, "rb") as f:
        data = f.read()
    key = hashlib.sha256(data).hexdigest()
    return SceneSource(name=os.path.basename(path), key=key, scene_name=scene_name or "",
                       data=None if shared else data, path=path if shared else None,
                       origin_dir=os.path.dirname(path))


def from_scene(scene):
    """A source for the live ``scene``: a copy of the open file saved to a private temp folder.

    The user's file is never written: ``copy=True`` keeps ``bpy.data.filepath`` and the dirty flag.
    """
    import bpy

    folder = tempfile.mkdtemp(prefix="radiometer-send-")
    name = os.path.basename(bpy.data.filepath) or "untitled.blend"
    path = os.path.join(folder, name)
    try:
        # relative_remap=False: "//" paths stay relative to the original folder (origin_dir).
        bpy.ops.wm.save_as_mainfile(filepath=path, copy=True, check_existing=False, relative_remap=False,
                                    compress=False)
        with open(path, "rb") as f:
            data = f.read()
    except RuntimeError as exc:
        raise RadiometerError(f"cannot copy the scene for the cluster: {str(exc).strip().splitlines()[-1]}") \
            from None
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    origin = os.path.dirname(bpy.path.abspath("//")) if bpy.data.filepath else ""
    return SceneSource(name=name, key=hashlib.sha256(data).hexdigest(), scene_name=scene.name, data=data,
                       origin_dir=origin)


def as_source(scene_or_path, *, shared=False):
    """``SceneSource`` from a bpy Scene, a path, or a source (returned as is)."""
    if isinstance(scene_or_path, SceneSource):
        return scene_or_path
    if isinstance(scene_or_path, (str, bytes, os.PathLike)):
        return from_path(os.fsdecode(scene_or_path), shared=shared)
    if hasattr(scene_or_path, "view_layers"):
        return from_scene(scene_or_path)
    raise RadiometerError(f"not a scene or a .blend path: {scene_or_path!r}")

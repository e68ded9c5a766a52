"""Where Radiometer writes files of its own, and how it names them after Blender objects.

* :func:`user_folder` is the extension's user directory (``bpy.utils.extension_path_user``); where
  that is unavailable (bpy as a module, a legacy add-on install) a PRIVATE temporary folder made by
  ``tempfile.mkdtemp`` (mode 0700, one per process), never a fixed ``/tmp/radiometer*`` path that
  another user could plant a symlink at.
* :func:`file_stem` turns any object name into a readable, file-system-safe stem that differs for
  different names: "Lamp.1" -> "Lamp_1-<hash>", "Lamp_1" -> "Lamp_1", "Lampe größer" ->
  "Lampe_größer-<hash>" (letters of any script are kept). :class:`Stems` gives the shorter
  lower-case stems of a report folder ("work_plane"), unique among the names it has seen
  (also when only letter case differs: case-insensitive file systems).
* :func:`write_text` writes a whole file or nothing; :func:`atomic_output` gives a library that
  writes files itself (matplotlib, OpenEXR, bpy images) a temporary path beside the destination
  that is renamed onto it only when the block succeeds. Every output of Radiometer goes through
  one of the two.
"""

import hashlib
import os
import re
import tempfile

_private_root = None
_WINDOWS_RESERVED = {"con", "prn", "aux", "nul", *(f"com{i}" for i in range(1, 10)), *(f"lpt{i}" for i in range(1, 10))}
MAX_STEM = 80


def private_temp_root():
    """This process's private temporary folder (created once with mkdtemp, mode 0700)."""
    global _private_root
    if _private_root is None or not os.path.isdir(_private_root):
        _private_root = tempfile.mkdtemp(prefix="radiometer-")
    return _private_root


def user_folder(sub):
    """The extension's user folder ``sub`` (created), else ``sub`` inside :func:`private_temp_root`."""
    try:
        import bpy

        return bpy.utils.extension_path_user(__package__, path=sub, create=True)
    except (ImportError, ValueError, KeyError, AttributeError, RuntimeError):
        pass
    path = os.path.join(private_temp_root(), sub)
    os.makedirs(path, mode=0o700, exist_ok=True)  # inside our own 0700 folder: nobody else can plant links
    return path


def _short_hash(name):
    return hashlib.sha1(name.encode("utf-8", "surrogatepass")).hexdigest()[:6]


def file_stem(name):
    """A readable file-name stem for ``name``, distinct for distinct names (see module doc)."""
    name = str(name)
    safe = re.sub(r"[^\w\-]+", "_", name, flags=re.UNICODE).strip("_")
    safe = safe[:MAX_STEM] or "item"
    if safe != name or safe.lower() in _WINDOWS_RESERVED:
        safe = f"{safe}-{_short_hash(name)}"
    return safe


def readable_slug(name):
    """Lower-case letters (any script), digits and "_" of ``name``: "Work Plane" -> "work_plane"."""
    return re.sub(r"[^\w\-]+", "_", str(name), flags=re.UNICODE).strip("_").lower()[:MAX_STEM] or "item"


class Stems:
    """Stems for several names in one folder: :func:`readable_slug`, plus a short hash of the exact
    name for every name after the first that would give the same stem ("Lamp.1", "Lamp_1", "LAMP 1")."""

    def __init__(self, names=()):
        self._owner = {}
        self._by_name = {}
        for name in names:
            self(name)

    def __call__(self, name):
        if name in self._by_name:
            return self._by_name[name]
        stem = readable_slug(name)
        if self._owner.setdefault(stem.casefold(), name) != name or stem in _WINDOWS_RESERVED:
            stem = f"{stem}-{_short_hash(name)}"
            self._owner[stem.casefold()] = name
        self._by_name[name] = stem
        return stem

def write_text(path, text):
    """Write ``text`` to ``path`` whole or not at all; an OSError becomes a one-line RadiometerError.

    A regular file is written to a temporary file beside it and renamed over it, so an error (full
    disk) or an interrupt leaves the old file as it was. Devices and pipes (``/dev/stdout``,
    ``/dev/full``) are written directly.
    """
    import contextlib

    from .errors import RadiometerError

    full = os.path.abspath(path)
    try:
        if os.path.exists(full) and not os.path.isfile(full):
            with open(full, "w", encoding="utf-8") as f:
                f.write(text)
            return path
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(full)}.", suffix=".tmp", dir=os.path.dirname(full))
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
            if os.path.exists(full):
                with contextlib.suppress(OSError):
                    os.chmod(tmp, os.stat(full).st_mode & 0o7777)
            else:
                umask = os.umask(0)
                os.umask(umask)
                os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, full)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise
    except OSError as exc:
        raise RadiometerError(f"cannot write {path}: {exc.strerror or exc}") from None
    return path


def _reject_symlink(full):
    # A link planted at the destination must not redirect the write (its target is not ours to replace).
    if os.path.islink(full):
        from .errors import RadiometerError

        raise RadiometerError(f"cannot write {full}: it is a symbolic link (refusing to follow it)")


import contextlib as _contextlib


@_contextlib.contextmanager
def atomic_output(path):
    """Yield a temporary path in ``path``'s folder (same suffix, so writers that infer the format from
    it still work); on success it is fsynced and renamed onto ``path``, on any error it is removed and
    ``path`` stays as it was. An OSError becomes a one-line RadiometerError naming ``path``.
    """
    from .errors import RadiometerError

    full = os.path.abspath(path)
    folder, base = os.path.split(full)
    stem, suffix = os.path.splitext(base)
    try:
        _reject_symlink(full)
        fd, tmp = tempfile.mkstemp(prefix=f".{stem}.", suffix=f".tmp{suffix}", dir=folder)
        os.close(fd)
    except OSError as exc:
        raise RadiometerError(f"cannot write {path}: {exc.strerror or exc}") from None
    try:
        yield tmp
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        _reject_symlink(full)
        os.replace(tmp, full)
    except OSError as exc:
        with _contextlib.suppress(OSError):
            os.unlink(tmp)
        raise RadiometerError(f"cannot write {path}: {exc.strerror or exc}") from None
    except BaseException:
        with _contextlib.suppress(OSError):
            os.unlink(tmp)
        raise

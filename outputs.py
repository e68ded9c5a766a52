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

import contextlib as _contextlib
import hashlib
import os
import re
import tempfile
import threading

_private_root = None
_WINDOWS_RESERVED = {"con", "prn", "aux", "nul", *(f"com{i}" for i in range(1, 10)), *(f"lpt{i}" for i in range(1, 10))}
MAX_STEM = 80


#: Every private folder this process made (removed together: one made after an earlier removal too).
created_roots = []
#: Files this process finished writing (absolute paths, in order): the CLI's stop messages name them.
written = []
#: Temporary files and staging folders alive now, beside their destinations: removed on every exit of
#: the CLI (:func:`remove_private_roots`), the watchdog's forced one included, if not gone already.
_temporaries = set()
#: Held while a result file or a set of files is put in place: the CLI's watchdog waits for it.
writing = threading.RLock()


def private_temp_root():
    """This process's private temporary folder (created once with mkdtemp, mode 0700)."""
    global _private_root
    if _private_root is None or not os.path.isdir(_private_root):
        # A signal between mkdtemp and the assignment would leave a folder that no handler knows of.
        import signal

        mask = getattr(signal, "pthread_sigmask", None)
        held = (signal.SIGINT, signal.SIGTERM)
        old = mask(signal.SIG_BLOCK, held) if mask else None
        try:
            _private_root = tempfile.mkdtemp(prefix="radiometer-")
            created_roots.append(_private_root)
        finally:
            if mask:
                mask(signal.SIG_SETMASK, old)
    return _private_root


def made_private_root():
    """This process's private temporary folder if :func:`private_temp_root` made one (and it has not
    been removed since), else None; creates nothing."""
    return _private_root


def remove_private_roots():
    """Remove every private temporary folder this process made, with everything in it, and forget them
    (the CLI on every exit, forced ones included)."""
    import shutil

    global _private_root
    root, _private_root = _private_root, None
    for folder in {root, *created_roots} - {None}:
        shutil.rmtree(folder, ignore_errors=True)
    created_roots.clear()
    remove_temporaries()


def remove_temporaries():
    """Remove every temporary file and staging folder this process has beside a destination now."""
    import shutil

    for path in list(_temporaries):
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        else:
            with _contextlib.suppress(OSError):
                os.unlink(path)
        _temporaries.discard(path)


def _note_written(full):
    """Record a finished file: not one in a staging folder (not in place yet), nor one in this
    process's private folder (scratch, removed when the CLI exits)."""
    if not any(full.startswith(os.path.join(t, "")) for t in [*_temporaries, *created_roots]):
        written.append(full)


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

def shown(path, limit=160):
    """``path`` as a message shows it: whole up to ``limit`` characters, else its head and tail
    (a 5000-character path is not echoed whole), control characters escaped (one line)."""
    text = os.fsdecode(path) if isinstance(path, (bytes, os.PathLike)) else str(path)
    text = "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)
    if len(text) > limit:
        keep = (limit - 3) // 2
        text = f"{text[:keep]}...{text[-keep:]}"
    return text


def _error(path, exc_or_text, what=""):
    from .errors import RadiometerError

    why = exc_or_text if isinstance(exc_or_text, str) else (exc_or_text.strerror or str(exc_or_text))
    return RadiometerError(f"cannot write {what + ' ' if what else ''}{shown(path)}: {why}")


def _is_special(full):
    """True for an existing destination that is not a regular file or a folder (a device, a FIFO)."""
    import stat

    try:
        mode = os.stat(full).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


def _umask():
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _check_destination(path, what=""):
    """The absolute destination, or a one-line RadiometerError: empty names, folders and links planted
    at the destination are refused (a link's target is not ours to replace)."""
    if path is None or (isinstance(path, str) and not path.strip()):
        raise _error("''", "no file name given", what)
    full = os.path.abspath(os.fspath(path))
    if os.path.islink(full):
        raise _error(path, "it is a symbolic link (refusing to follow it)", what)
    if os.path.isdir(full):
        raise _error(path, "it is a directory, not a file", what)
    return full


def write_bytes(path, data):
    """Write ``data`` (bytes) to ``path`` whole or not at all; an OSError becomes a one-line
    RadiometerError naming the file.

    A regular file is written to a temporary file beside it, fsynced and renamed over it, so an
    error (full disk) or an interrupt leaves the old file as it was. An existing device or pipe
    (``/dev/stdout``, ``/dev/full``) is written directly (never replaced), its errors reported.
    """
    full = _check_destination(path)
    try:
        if _is_special(full):
            # O_NONBLOCK: a FIFO nobody reads fails at once (ENXIO) instead of blocking forever.
            fd = os.open(full, os.O_WRONLY | os.O_NONBLOCK)
            try:
                view = memoryview(data)
                while view:
                    view = view[os.write(fd, view):]
            finally:
                os.close(fd)
            return path
        fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(full)}.", suffix=".tmp", dir=os.path.dirname(full))
        _temporaries.add(tmp)
        with _removed_on_failure(tmp):
            with os.fdopen(fd, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
            mode = 0o666 & ~_umask()
            if os.path.isfile(full):
                with _contextlib.suppress(OSError):
                    mode = os.stat(full).st_mode & 0o7777
            _put_in_place(tmp, full, path, mode)
    except OSError as exc:
        raise _error(path, exc) from None
    return path


@_contextlib.contextmanager
def _removed_on_failure(tmp):
    """Run the block that finishes the temporary file ``tmp``: on any error (an interrupt too) ``tmp`` is
    removed and the error goes on; either way it is no longer one of this process's temporaries."""
    try:
        yield
    except BaseException:
        with _contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    finally:
        _temporaries.discard(tmp)


def _put_in_place(tmp, full, path, mode):
    """Give the finished temporary file ``tmp`` its permissions ``mode`` and rename it onto ``full``
    (refused where a link was planted there while we wrote); record it as written."""
    os.chmod(tmp, mode)
    if os.path.islink(full):  # planted while we wrote
        raise _error(path, "it is a symbolic link (refusing to follow it)")
    os.replace(tmp, full)
    _note_written(full)


def write_text(path, text):
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (see :func:`write_bytes`)."""
    return write_bytes(path, text.encode("utf-8", "surrogateescape"))


@_contextlib.contextmanager
def atomic_output(path):
    """Yield a temporary path in ``path``'s folder (same suffix, so writers that infer the format from
    it still work); on success it is fsynced and renamed onto ``path``, on any error it is removed and
    ``path`` stays as it was. An OSError becomes a one-line RadiometerError naming ``path``. A writer
    that fails without raising (leaves an empty file) is an error too. A destination that is a device
    or a pipe gets the finished file's bytes written to it (never replaced).
    """
    full = _check_destination(path)
    folder, base = os.path.split(full)
    stem, suffix = os.path.splitext(base)
    special = _is_special(full)
    try:
        # A device's folder (/dev) is no place for our temp file: use this process's private folder.
        fd, tmp = tempfile.mkstemp(prefix=f".{stem}.", suffix=f".tmp{suffix}",
                                   dir=private_temp_root() if special else folder)
        _temporaries.add(tmp)
        os.close(fd)
    except OSError as exc:
        raise _error(path, exc) from None
    try:
        with _removed_on_failure(tmp):
            yield tmp
            if os.path.getsize(tmp) == 0:
                raise _error(path, "the writer produced no data")
            if special:
                with open(tmp, "rb") as f:
                    write_bytes(full, f.read())
                os.unlink(tmp)
                return
            with open(tmp, "rb+") as f:
                os.fsync(f.fileno())
            _put_in_place(tmp, full, path, 0o666 & ~_umask())
    except OSError as exc:
        raise _error(path, exc) from None


def check_writable(path, what="output file"):
    """Say now (one-line RadiometerError) that ``path`` could not be written later.

    No ``os.access`` (it says yes to root for read-only folders and no for files a rename could
    replace): a temporary file is actually created in the folder and removed. A device or pipe
    that exists is accepted (its write errors are reported when written); links, folders, missing
    folders are refused.
    """
    from .errors import RadiometerError

    full = _check_destination(path, what)
    folder = os.path.dirname(full)
    if _is_special(full):
        return full
    if not os.path.isdir(folder):
        raise RadiometerError(f"cannot write {what} {shown(path)}: folder {shown(folder)} does not exist")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".radiometer-check.", dir=folder)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise RadiometerError(f"cannot write {what} {shown(path)}: {exc.strerror or exc}") from None
    return full


def same_file(a, b):
    """True when paths ``a`` and ``b`` name the same file (real path, or same device and inode)."""
    try:
        if os.path.realpath(a) == os.path.realpath(b):
            return True
        return os.path.samefile(a, b)
    except (OSError, ValueError, TypeError):
        return False


def refuse_overlaps(outputs, inputs):
    """RadiometerError (one line) when an output names an input of the same run, or two outputs
    name one file: before any work, so no input is overwritten and no output silently replaces
    another. ``outputs``/``inputs``: iterables of (label, path); empty paths and "-" are ignored."""
    from .errors import RadiometerError

    outs = [(label, p) for label, p in outputs if p and p != "-"]
    ins = [(label, p) for label, p in inputs if p and p != "-"]
    for label, p in outs:
        for in_label, q in ins:
            if same_file(p, q):
                raise RadiometerError(f"{label} {shown(p)} is the input {in_label} of this run: "
                                      "refusing to overwrite it; choose another file")
    for i, (label, p) in enumerate(outs):
        for other, q in outs[i + 1:]:
            if same_file(p, q):
                raise RadiometerError(f"{label} and {other} name the same file {shown(p)}: choose two files")


def json_safe(value):
    """``value`` as plain JSON data: the one NaN/inf policy of every JSON file Radiometer writes.

    numpy arrays and scalars become lists and numbers; inf and NaN become ``None`` (JSON has neither,
    and ``null`` keeps the file readable by every tool); objects with ``to_dict()`` and NamedTuples
    become dicts; tuples become lists. Anything else is returned as it is (``json.dumps`` decides).
    """
    import math

    if hasattr(value, "to_dict"):
        return json_safe(value.to_dict())
    if hasattr(value, "_asdict"):
        return json_safe(value._asdict())
    if type(value).__module__ == "numpy":  # arrays and numpy scalars, without importing numpy here
        return json_safe(value.tolist() if hasattr(value, "tolist") else value.item())
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    return value


def check_set(folder, names, what="output"):
    """Say now (one-line RadiometerError) that a set of files ``names`` in ``folder`` could not be put in
    place later: every target is checked (a link, a folder, a device), and the folder once (a file is
    created there and removed). For multi-file outputs, before their work starts."""
    first = None
    for name in names:
        full = _check_destination(os.path.join(folder, name), what)
        if _is_special(full):
            raise _error(full, "it is a device or a pipe, not a file of a set", what)
        first = first or full
    if first is not None:
        check_writable(first, what)


class FileSet:
    """A set of files in ``folder`` replaced together or not at all (a report's html, pdf, md, json
    and pictures): a staging folder beside the targets, renamed into place file by file at the end.

    Why a staging folder and not only a manifest written last: with a manifest alone the new files
    would replace the old ones one by one while the run goes on, and a cancel halfway would leave a
    mix; staged, nothing in ``folder`` changes until every file of the new set is complete.

    Use::

        with FileSet(out, manifest="report.json", name="report") as stage:
            write(stage.path("report.html")) ...            # every file of the set into stage.folder
            stage.commit()                                   # the set, together

    :meth:`commit` checks every destination first (a link, a folder: one line, nothing moved), then
    renames every staged file onto its destination, the manifest last, holding :data:`writing` (the
    CLI's watchdog waits for it) and finishing the renames even if a KeyboardInterrupt arrives
    halfway (re-raised after). The renames take microseconds each: only a SIGKILL or a power cut in
    that window can leave a mix, and the manifest, renamed last, then still names the previous set.
    Files that the previous manifest listed (its ``"files"``) and the new set lacks are removed after.
    Leaving the block without a commit (an error, a cancel, Ctrl-C) removes the staging folder: the
    previous set stays as it was. The CLI removes a staging folder on every exit, forced ones too;
    one left by a killed process (SIGKILL) is removed by the next set written into that folder.
    """

    def __init__(self, folder, manifest, name="set"):
        self.target = os.path.abspath(os.fspath(folder))
        self.manifest = manifest
        self.name = name
        self.folder = None
        self.committed = []

    def __enter__(self):
        self._remove_orphans()
        try:
            self.folder = tempfile.mkdtemp(prefix=f".{self.name}.staging-{os.getpid()}-", dir=self.target)
        except OSError as exc:
            raise _error(self.target, exc, f"the {self.name} into") from None
        _temporaries.add(self.folder)
        return self

    def _remove_orphans(self):
        """Staging folders of processes that no longer run (a SIGKILL, a power cut): nothing else
        removes them. The folder names carry the process id; this process's own are left alone."""
        import shutil

        prefix = f".{self.name}.staging-"
        try:
            names = [n for n in os.listdir(self.target) if n.startswith(prefix)]
        except OSError:
            return
        for name in names:
            pid = name[len(prefix):].split("-", 1)[0]
            if not pid.isdigit() or int(pid) == os.getpid():
                continue
            try:
                os.kill(int(pid), 0)
                continue  # still running (another report into the same folder)
            except ProcessLookupError:
                pass
            except (PermissionError, OverflowError):
                continue  # another user's process runs, or no such process id: not ours to judge
            full = os.path.join(self.target, name)
            if os.path.isdir(full) and not os.path.islink(full):
                shutil.rmtree(full, ignore_errors=True)

    def path(self, name):
        """Where the file ``name`` of the set is written (inside the staging folder)."""
        return os.path.join(self.folder, name)

    def files(self):
        """The names of the files staged so far (no temporary files of writers still at work)."""
        return sorted(n for n in os.listdir(self.folder)
                      if not n.startswith(".") and os.path.isfile(os.path.join(self.folder, n)))

    def _previous(self):
        import json

        try:
            with open(os.path.join(self.target, self.manifest), encoding="utf-8") as f:
                listed = json.load(f).get("files")
        except (OSError, ValueError, AttributeError):
            return []
        if not isinstance(listed, list):
            return []
        # Only plain names of files in this folder: a damaged or hand-edited manifest deletes nothing else.
        return [n for n in listed if isinstance(n, str) and n and n == os.path.basename(n)
                and not n.startswith(".") and n not in (os.curdir, os.pardir)]

    def commit(self):
        """Put the staged set in place (see the class); returns the destinations, the manifest last."""
        names = self.files()
        if self.manifest in names:
            names = [n for n in names if n != self.manifest] + [self.manifest]
        check_set(self.target, names, f"{self.name} file")
        previous = self._previous()
        done, interrupted = [], None
        with writing:
            for name in names:
                while True:
                    try:
                        os.replace(self.path(name), os.path.join(self.target, name))
                        done.append(os.path.join(self.target, name))
                        break
                    except KeyboardInterrupt as exc:  # finish the set first
                        interrupted = exc
                    except FileNotFoundError as exc:
                        if not os.path.exists(self.path(name)) and os.path.isfile(os.path.join(self.target, name)):
                            done.append(os.path.join(self.target, name))  # moved just before an interrupt
                            break
                        raise _error(os.path.join(self.target, name), exc, f"{self.name} file") from None
                    except OSError as exc:
                        raise _error(os.path.join(self.target, name), exc,
                                     f"{self.name} file ({len(done)} of {len(names)} in place)") from None
            written.extend(done)
            self.committed = done
        for name in set(previous) - set(names):
            with _contextlib.suppress(OSError):
                full = os.path.join(self.target, name)
                if os.path.isfile(full) and not os.path.islink(full):
                    os.unlink(full)
        if interrupted is not None:
            raise interrupted
        return done

    def __exit__(self, *exc):
        import shutil

        shutil.rmtree(self.folder, ignore_errors=True)
        _temporaries.discard(self.folder)
        return False


def relocated(value, old_folder, new_folder):
    """``value`` (dicts, lists, tuples, strings) with every mention of ``old_folder`` (a staging
    folder) in its strings replaced by ``new_folder``: the paths the files have once moved there."""
    old, new = os.fspath(old_folder), os.fspath(new_folder)
    if isinstance(value, str):
        return value.replace(old, new)
    if isinstance(value, dict):
        return {k: relocated(v, old, new) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return type(value)(relocated(v, old, new) for v in value) if not hasattr(value, "_fields") else \
            type(value)(*(relocated(v, old, new) for v in value))
    return value

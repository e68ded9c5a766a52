"""Input files read only when they are regular files of a sane size (pure Python).

A FIFO blocks a reader forever and /dev/zero never ends; a folder is not a file. ``refusal`` says why
a file (its ``os.stat`` result) is not read; ``open_regular`` opens a path without blocking on a FIFO
(O_NONBLOCK) and checks what it opened, so nothing can be swapped in between.
"""

import os
import stat

__all__ = ["refusal", "open_regular", "read_text"]


def refusal(st, what, max_bytes):
    """None for a regular file of at most ``max_bytes``, else the reason, e.g. "is a directory, not a
    weather file" (``what`` = "weather"): to follow the file's name in a one-line message."""
    if stat.S_ISDIR(st.st_mode):
        return f"is a directory, not a {what} file"
    if not stat.S_ISREG(st.st_mode):
        return "is not a regular file (a pipe or a device): refusing to read it"
    if st.st_size > max_bytes:
        return f"is too large for a {what} file ({st.st_size} bytes; at most {max_bytes})"
    return None


def open_regular(path, what, max_bytes, error=ValueError):
    """``path`` opened for binary reading when it is a regular file of at most ``max_bytes``, else
    ``error("<path>: <why>")`` with one line (no such file, a folder, a pipe or device, too large)."""
    path = os.fspath(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except OSError as exc:
        raise error(f"{path}: cannot read it ({exc.strerror or exc})") from None
    try:
        why = refusal(os.fstat(fd), what, max_bytes)
        if why:
            raise error(f"{path}: {why}")
    except BaseException:
        os.close(fd)
        raise
    return os.fdopen(fd, "rb")


def read_text(path, what, max_bytes, error=ValueError):
    """The text of a data file (UTF-8, else Latin-1) read through ``open_regular``; binary data (a NUL
    in the first 4 KiB) is ``error("<path>: line 1: expected a text <what> file, got binary data")``."""
    try:
        with open_regular(path, what, max_bytes, error) as fh:
            data = fh.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"{os.fspath(path)}: cannot read it ({exc.strerror or exc})") from None
    if b"\0" in data[:4096]:
        raise error(f"{os.fspath(path)}: line 1: expected a text {what} file, got binary data")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")

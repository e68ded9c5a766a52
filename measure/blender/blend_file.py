"""Saving the open Blender file as a copy: the one way Radiometer writes a .blend (the CLI's
``sun --out`` and ``world --calibrate --out``, the daylit demo)."""

import contextlib
import os

from ...errors import RadiometerError
from ...outputs import atomic_output, shown


def save_copy(path, interrupt=None):
    """Save the open file as ``path``, whole or not at all, leaving the session's own file and path as
    they are (``copy=True``). ``interrupt``: the CLI's ``Interrupt``, whose watchdog must not cut the
    write short (its ``critical()`` section), or None. Returns ``path``; one-line RadiometerError when
    Blender cannot save."""
    import bpy

    guard = interrupt.critical() if interrupt is not None else contextlib.nullcontext()
    with guard:
        try:
            with atomic_output(path) as tmp:
                os.unlink(tmp)  # Blender keeps a .blend1 backup of a file it overwrites: give it none
                bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(tmp), check_existing=False, copy=True)
        except RuntimeError as exc:
            raise RadiometerError(f"cannot save {shown(path)}: {str(exc).strip().splitlines()[-1]}") from None
    return path

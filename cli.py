"""One command-line implementation for ``python -m radiometer`` and ``blender -b f.blend -c radiometer``.

``main(argv)`` returns an exit code and never lets a traceback reach the user for bad input:
argument errors, missing files and ``RadiometerError`` give one line on stderr and exit code 2.
"""

import argparse
import importlib
import json
import math
import os
import sys

from .commands import SUBCOMMANDS
from .errors import RadiometerError

PROG = "radiometer"
EXIT_BAD_INPUT = 2
EXIT_FAILURE = 1


class _ArgumentParser(argparse.ArgumentParser):
    # argparse prints usage + calls sys.exit(2); raise instead so both entry points decide.
    def error(self, message):
        raise RadiometerError(f"{self.prog}: {message} (see --help)")


def _command_module(name):
    return importlib.import_module(f".commands.{SUBCOMMANDS[name]}", __package__)


def build_parser():
    parser = _ArgumentParser(
        prog=PROG,
        description="Radiometer: light meters, law checks, BRDFs and reports for Blender scenes (SI units).",
    )
    sub = parser.add_subparsers(dest="command", metavar="<subcommand>", parser_class=_ArgumentParser)
    for name in SUBCOMMANDS:
        module = _command_module(name)
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        if module.NEEDS_SCENE:
            p.add_argument("blend", nargs="?", help="scene .blend file (default: the file Blender has open)")
        p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE")
        module.add_arguments(p)
    return parser


def _check_blend_path(path):
    if not os.path.exists(path):
        raise RadiometerError(f"no such file: {path}")
    if os.path.isdir(path):
        raise RadiometerError(f"{path} is a directory, not a .blend file")
    with open(path, "rb") as f:
        magic = f.read(7)
    # Blender files start with "BLENDER"; compressed ones with the zstd or gzip magic.
    if magic != b"BLENDER" and magic[:4] != b"\x28\xb5\x2f\xfd" and magic[:2] != b"\x1f\x8b":
        raise RadiometerError(f"{path} is not a .blend file")


def _open_blend(path):
    import bpy

    _check_blend_path(path)
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path), load_ui=False)
    except RuntimeError as exc:
        raise RadiometerError(f"cannot open {path}: {str(exc).strip().splitlines()[-1]}") from None


def _json_default(value):
    try:
        import numpy as np

        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, np.generic):
            return value.item()
    except ImportError:
        pass
    if hasattr(value, "to_dict"):
        return value.to_dict()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def _sanitise(value):
    # JSON has no NaN/inf; write null so other tools can read the file.
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _sanitise(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_sanitise(v) for v in value]
    return value


def write_json(path, result):
    text = json.dumps(_sanitise(json.loads(json.dumps(result, default=_json_default))), indent=2)
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise RadiometerError(f"cannot write {path}: directory {directory} does not exist")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text + "\n")


def main(argv=None, *, in_blender=False):
    """Run a subcommand; return the exit code. ``in_blender``: called by ``blender -c``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        parser = build_parser()
        if not argv:
            parser.print_help()
            return EXIT_BAD_INPUT
        args = parser.parse_args(argv)
        module = _command_module(args.command)
        if module.NEEDS_SCENE and args.blend:
            _open_blend(args.blend)
        if not in_blender:
            _ensure_registered()
        result = module.run(args)
        if args.json:
            write_json(args.json, result)
        return 0
    except RadiometerError as exc:
        print(f"radiometer: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("radiometer: interrupted; the scene was restored", file=sys.stderr)
        return 130
    except SystemExit as exc:  # --help
        return exc.code if isinstance(exc.code, int) else 0


def _ensure_registered():
    """With bpy as a module the add-on is not enabled: register it (idempotent)."""
    import bpy

    if not hasattr(bpy.types.Scene, "radiometer"):
        from . import register

        register()


# --- Blender's `-c radiometer` entry point -------------------------------------------------------

_cli_handle = None


def _blender_cli(argv):
    return main(argv, in_blender=True)


def register():
    global _cli_handle
    import bpy

    _cli_handle = bpy.utils.register_cli_command(PROG, _blender_cli)


def unregister():
    global _cli_handle
    import bpy

    if _cli_handle is not None:
        bpy.utils.unregister_cli_command(_cli_handle)
        _cli_handle = None

"""One command-line implementation for ``python -m radiometer`` and ``blender -b f.blend -c radiometer``.

``main(argv)`` returns an exit code and never lets a traceback reach the user for bad input:
argument errors, missing files, ``RadiometerError`` and OS errors (an unwritable or full output)
give one line on stderr and exit code 2; Ctrl-C gives exit code 130 with result files untouched.
Results go to stdout; Blender's own log lines (bake and render reports, "Read blend:", the Cycles
device probe) are dropped unless ``--verbose``; a progress line goes to stderr when it is a
terminal (not with ``--quiet``, which also drops the results text: use ``--json``).
"""

import argparse
import importlib
import json
import math
import os
import sys

from .commands import SUBCOMMANDS
from .commands import _io
from .errors import RadiometerError

PROG = "radiometer"
EXIT_BAD_INPUT = 2
EXIT_FAILURE = 1
EXIT_INTERRUPTED = _io.EXIT_INTERRUPTED


def version():
    """The extension's version from blender_manifest.toml (no bpy import)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_manifest.toml")
    try:
        with open(path, encoding="utf-8") as f:
            for line in f:
                key, sep, value = line.partition("=")
                if sep and key.strip() == "version":
                    return value.strip().strip('"')
    except OSError:
        pass
    return "unknown"


def _add_output_options(parser, default):
    # On the main parser and on every subcommand, so `radiometer measure f.blend --quiet` works too.
    parser.add_argument("-q", "--quiet", action="store_true", default=default,
                        help="print nothing but errors (no results text, no progress); use --json for results")
    parser.add_argument("-v", "--verbose", action="store_true", default=default,
                        help="also show Blender's own log lines (bake/render reports, file loading)")


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
        epilog="Exit codes: 0 done, 2 bad input or an output that cannot be written, 130 interrupted (Ctrl-C).",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {version()}")
    _add_output_options(parser, False)
    sub = parser.add_subparsers(dest="command", metavar="<subcommand>", parser_class=_ArgumentParser)
    for name in SUBCOMMANDS:
        module = _command_module(name)
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        if module.NEEDS_SCENE:
            p.add_argument("blend", nargs="?", help="scene .blend file (default: the file Blender has open)")
        p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE (written first, "
                       "before any plot or image)")
        _add_output_options(p, argparse.SUPPRESS)
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


def json_text(result):
    return json.dumps(_sanitise(json.loads(json.dumps(result, default=_json_default))), indent=2) + "\n"


def write_json(path, result, interrupt=None):
    """Write ``result`` as JSON to ``path`` whole or not at all (RadiometerError with one line if it cannot)."""
    _io.check_output_file(path, "JSON file")
    return _io.write_text(path, json_text(result), interrupt)


def deliver(args, result):
    """Write ``--json`` now (commands call this before optional plots, so a failing plot cannot lose it)."""
    if getattr(args, "json", None) and not getattr(args, "_json_written", False):
        write_json(args.json, result, getattr(args, "interrupt", None))
        args._json_written = True


def _os_error_message(exc):
    where = f" {exc.filename}" if getattr(exc, "filename", None) else ""
    return f"cannot write{where}: {exc.strerror or exc}"


def main(argv=None, *, in_blender=False):
    """Run a subcommand; return the exit code. ``in_blender``: called by ``blender -c``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    interrupt = _io.Interrupt()
    try:
        parser = build_parser()
        if not argv:
            parser.print_help()
            return EXIT_BAD_INPUT
        args = parser.parse_args(argv)
        if args.command is None:
            raise RadiometerError(f"{PROG}: a subcommand is required (see --help)")
        module = _command_module(args.command)
        if args.json:
            _io.check_output_file(args.json, "JSON file")  # before the run, not after it
        args.interrupt, args.cancelled = interrupt, interrupt.cancelled
        with interrupt, _io.blender_logs_silenced(enabled=not args.verbose, quiet=args.quiet) as err_fd:
            args.progress = _io.Progress(err_fd, enabled=not args.quiet)
            interrupt.stderr_fd = err_fd if err_fd is not None else 2
            try:
                if module.NEEDS_SCENE and args.blend:
                    _open_blend(args.blend)
                if not in_blender:
                    _ensure_registered()
                result = module.run(args)
                if interrupt.cancelled():
                    raise KeyboardInterrupt
                deliver(args, result)
            finally:
                args.progress.clear()
        return 0
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted (Ctrl-C); stopped, no file left half-written", file=sys.stderr)
        return EXIT_INTERRUPTED
    except RadiometerError as exc:
        if interrupt.cancelled():  # a measurement that saw the flag (MeasurementCancelled) or a cut-short bake
            print(f"{PROG}: interrupted (Ctrl-C); stopped, no file left half-written", file=sys.stderr)
            return EXIT_INTERRUPTED
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(f"{PROG}: error: {_os_error_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    finally:
        interrupt.uninstall()


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

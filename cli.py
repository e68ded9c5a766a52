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
        # argparse %-formats a subcommand's help: a plain "50 %" in HELP crashed --help and the usage.
        p = sub.add_parser(name, help=module.HELP.replace("%%", "%").replace("%", "%%"), description=module.HELP)
        if module.NEEDS_SCENE:
            p.add_argument("blend", nargs="?", help="scene .blend file (default: the file Blender has open)")
        p.add_argument("--json", metavar="FILE", help="also write the result as JSON to FILE (written first, "
                       "before any plot or image)")
        _add_output_options(p, argparse.SUPPRESS)
        module.add_arguments(p)
        _fill_standard_help(p)
    return parser


#: Help for the options many subcommands share, where a subcommand gives none of its own.
_STANDARD_HELP = {
    "--quality": "accuracy preset, the 1-sigma relative error every rendered reading must reach: preview 5 %%, "
                 "standard 1 %%, reference 0.2 %%",
    "--method": "auto (closed forms where proven, else hybrid), analytic (closed forms only), hybrid (closed "
                "forms + Cycles for the rest) or render (Cycles for everything)",
}


def _fill_standard_help(parser):
    for action in parser._actions:
        text = next((_STANDARD_HELP[o] for o in action.option_strings if o in _STANDARD_HELP), None)
        if text and not action.help:
            default = "the scene's setting" if action.default is None else "%(default)s"
            action.help = f"{text} (default: {default})"


def _check_blend_path(path):
    from .outputs import shown
    from .validation import check_input_file

    check_input_file(path, "scene")  # missing, a folder, a FIFO or a device: refused before reading
    with open(path, "rb") as f:
        magic = f.read(7)
    # Blender files start with "BLENDER"; compressed ones with the zstd or gzip magic.
    if magic != b"BLENDER" and magic[:4] != b"\x28\xb5\x2f\xfd" and magic[:2] != b"\x1f\x8b":
        raise RadiometerError(f"{shown(path)} is not a .blend file")


def _open_blend(path):
    import bpy

    _check_blend_path(path)
    try:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(path), load_ui=False)
    except RuntimeError as exc:
        from .outputs import shown

        raise RadiometerError(f"cannot open {shown(path)}: {str(exc).strip().splitlines()[-1]}") from None


#: Options that name files or folders a subcommand writes, and arguments naming files it reads.
OUTPUT_OPTIONS = {"json": "--json", "csv": "--csv", "png": "--png", "plot": "--plot", "plots": "--plots",
                  "irradiance_map": "--irradiance-map", "luminance_image": "--luminance-image", "out": "--out",
                  "exr": "--exr", "hdr": "--hdr"}
INPUT_ARGUMENTS = {"blend": "scene", "file": "file", "epw": "weather file"}


def _check_paths(args, in_blender, module=None):
    """Before any work: no empty file names, no output onto an input of this run, no two outputs
    onto one file, the files a subcommand writes without an option of their own included (the PNG
    beside a luminance EXR, a report's html/pdf/md/json: its ``implied_outputs(args)``), and each of
    those writable (not a link, a folder or in a missing folder): one line each."""
    outputs_, inputs = [], []
    for attr, label in OUTPUT_OPTIONS.items():
        value = getattr(args, attr, None)
        if isinstance(value, str):
            if not value.strip():
                raise RadiometerError(f"{label} needs a file name (got an empty one)")
            outputs_.append((label, value))
    implied = list(getattr(module, "implied_outputs", lambda _args: [])(args))
    if implied:
        outputs_ = [(label, p) for label, p in outputs_ if not os.path.isdir(p)]  # a folder is not a file
    outputs_ += implied
    for attr, label in INPUT_ARGUMENTS.items():
        value = getattr(args, attr, None)
        if isinstance(value, str) and value:
            inputs.append((label, value))
    if in_blender and not getattr(args, "blend", None):
        try:
            import bpy

            if bpy.data.filepath:
                inputs.append(("scene", bpy.data.filepath))
        except ImportError:
            pass
    from . import outputs

    outputs.refuse_overlaps(outputs_, inputs)
    for label, path in implied:
        if not os.path.isdir(os.path.dirname(os.path.abspath(path))):
            continue  # its folder is made by the run (a report's --out): checked as a folder there
        outputs.check_writable(path, label)


def _os_error_message(exc):
    from .outputs import shown

    where = f" {shown(exc.filename)}" if getattr(exc, "filename", None) else ""
    return f"cannot write{where}: {exc.strerror or exc}"


def main(argv=None, *, in_blender=False):
    """Run a subcommand; return the exit code. ``in_blender``: called by ``blender -c``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    interrupt = _io.Interrupt()
    try:
        parser = build_parser()
        if not argv:
            parser.print_help(sys.stderr)  # usage is an error here: stderr, exit 2 (stdout stays for results)
            return EXIT_BAD_INPUT
        args = parser.parse_args(argv)
        if args.command is None:
            raise RadiometerError(f"{PROG}: a subcommand is required (see --help)")
        module = _command_module(args.command)
        from . import outputs

        outputs.written.clear()  # this run's files, for the stop messages
        _check_paths(args, in_blender, module)
        json_to_stdout = args.json == "-"
        if args.json:
            _io.check_output_file(args.json, "JSON file")  # before the run, not after it
        if json_to_stdout:
            args.quiet = True  # stdout carries the JSON alone
        args.interrupt, args.cancelled = interrupt, interrupt.cancelled
        if not in_blender:
            _scratch_inside_private_root()
        if args.verbose:
            from . import api

            api.keep_blender_reports(True)  # --verbose shows Blender's own reports too
        with interrupt, _io.blender_logs_silenced(enabled=not args.verbose, quiet=args.quiet) as err_fd, \
                _quiet_numpy():
            args.progress = _io.Progress(err_fd, enabled=not args.quiet)
            interrupt.stderr_fd = err_fd if err_fd is not None else 2
            try:
                if module.NEEDS_SCENE and args.blend:
                    _open_blend(args.blend)
                if interrupt.cancelled():  # safe points between the start-up steps
                    raise KeyboardInterrupt
                if not in_blender:
                    _io.ensure_registered()
                if interrupt.cancelled():
                    raise KeyboardInterrupt
                result = module.run(args)
                if interrupt.cancelled():
                    raise KeyboardInterrupt
                _io.deliver(args, result)
            finally:
                args.progress.clear()
        if json_to_stdout:
            sys.stdout.write(_io.json_text(_io.without_scratch_paths(result)))
            sys.stdout.flush()
        return 0
    except KeyboardInterrupt:
        print(interrupt.message, file=sys.stderr)
        return interrupt.exit_code
    except RadiometerError as exc:
        if interrupt.cancelled():  # a measurement that saw the flag (MeasurementCancelled) or a cut-short bake
            print(interrupt.message, file=sys.stderr)
            return interrupt.exit_code
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(f"{PROG}: error: {_os_error_message(exc)}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else 0
    except Exception as exc:  # noqa: BLE001 - the last boundary: a bug is one line too, never a traceback
        if interrupt.cancelled():
            print(interrupt.message, file=sys.stderr)
            return interrupt.exit_code
        from .validation import _first_line, _where

        print(f"{PROG}: internal error: {type(exc).__name__}: {_first_line(exc)}{_where(exc)} (a bug: please "
              "report it with the command line)", file=sys.stderr)
        return EXIT_FAILURE
    finally:
        interrupt.uninstall()
        if not in_blender:
            _remove_scratch()


def _remove_scratch():
    """Remove this process's private temporary folder (radiance maps, plots with no other home,
    render scratch folders): nothing of a run is left in the temp folder once the CLI exits."""
    import tempfile

    if getattr(_remove_scratch, "saved_tempdir", False) is not False:
        tempfile.tempdir = _remove_scratch.saved_tempdir
        del _remove_scratch.saved_tempdir
    if getattr(_remove_scratch, "saved_env", False) is not False:
        saved = _remove_scratch.saved_env
        del _remove_scratch.saved_env
        if saved is None:
            os.environ.pop("TMPDIR", None)
        else:
            os.environ["TMPDIR"] = saved
    _io.remove_scratch()


def _scratch_inside_private_root():
    """Every temporary folder of the run (render scratch, probes) goes inside this process's private
    folder, so one removal cleans all of it, also after a forced exit (watchdog, SIGTERM)."""
    import tempfile

    from . import outputs

    try:
        root = outputs.private_temp_root()
    except OSError:
        return  # an unwritable TMPDIR: the measurements say so themselves when they need a folder
    _remove_scratch.saved_tempdir = tempfile.tempdir
    tempfile.tempdir = root
    if "bpy" not in sys.modules:  # Blender's own temporary folder (blender_XXXX) goes inside it too
        _remove_scratch.saved_env = os.environ.get("TMPDIR")
        os.environ["TMPDIR"] = root


class _quiet_numpy:
    """numpy's overflow/invalid warnings must not leak to stderr: non-finite results are checked
    and reported as errors where they matter."""

    def __enter__(self):
        import warnings

        self._warnings = warnings.catch_warnings()
        self._warnings.__enter__()
        warnings.simplefilter("ignore", RuntimeWarning)
        try:
            import numpy as np

            self._err = np.seterr(all="ignore")
        except ImportError:
            self._err = None
        return self

    def __exit__(self, *exc):
        if self._err is not None:
            import numpy as np

            np.seterr(**self._err)
        self._warnings.__exit__(*exc)
        return False


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

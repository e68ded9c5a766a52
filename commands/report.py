"""`report`: every meter, law checks for every light, grids on work planes and a convergence study."""

HELP = "write report.json, report.md and PNG plots (meters, law checks, grids, convergence) into --out"
NEEDS_SCENE = True

from .check import add_budget_arguments, budget_kwargs  # noqa: E402


def add_arguments(parser):
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="quality preset (default: the scene's setting)")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default=None)
    add_budget_arguments(parser)
    parser.add_argument("--no-convergence", action="store_true", help="skip the convergence study")


def run(args):
    import bpy

    from ..measure import report
    from . import _io

    _io.check_output_dir(args.out, "--out folder")
    progress = getattr(args, "progress", None)
    result = report.export_report(args.out, scene=bpy.context.scene, quality=args.quality, method=args.method,
                                  convergence=not args.no_convergence, progress=progress,
                                  phase=None if progress is None else progress.step,
                                  cancelled=getattr(args, "cancelled", None), **budget_kwargs(args))
    if progress is not None:
        progress.clear()
    print(result["summary"])
    print(f"\nWrote {result['paths']['markdown']} and {result['paths']['json']} ({result['seconds']:.1f} s)")
    return {"paths": result["paths"], "summary": result["summary"]}

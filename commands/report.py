"""`report`: every meter, law checks for every light, grids on work planes and a convergence study."""

HELP = ("write the client report (report.html, report.pdf) and report.json, report.md and PNG plots (meters, law "
        "checks, grids, compliance, glare, convergence) into --out")
NEEDS_SCENE = True

from .check import add_budget_arguments, budget_kwargs  # noqa: E402


def add_arguments(parser):
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder (created if missing)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="quality preset (default: the scene's setting)")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default=None)
    add_budget_arguments(parser)
    parser.add_argument("--no-convergence", action="store_true", help="skip the convergence study")
    parser.add_argument("--project", metavar="NAME", help="project name on the client report (default: the file name)")
    parser.add_argument("--task", metavar="KEY", help="EN 12464-1 task of the work planes for the compliance table, "
                        "e.g. office_writing, classroom, corridor (see docs/deliverables.md)")
    parser.add_argument("--maintenance-factor", type=float, default=0.8, metavar="MF",
                        help="maintenance factor: maintained illuminance = MF x the new installation's (default 0.8)")
    parser.add_argument("--observer", type=float, nargs=6, action="append", metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="eye position (m) and view direction for a UGR rating (repeatable)")
    parser.add_argument("--ra", type=float, default=None, help="the luminaires' rated colour rendering index Ra")
    parser.add_argument("--no-client", action="store_true", help="skip the client's report.html and report.pdf")
    day = parser.add_mutually_exclusive_group()
    day.add_argument("--daylight", action="store_true", help="add the daylight section (daylight factor, sDA/ASE/UDI "
                     "and sunlight hours with --epw, DGP at the camera, EN 17037, maps); default: when the scene has "
                     "a sun or an emitting world")
    day.add_argument("--no-daylight", action="store_true", help="no daylight section, even in a daylit scene")
    parser.add_argument("--epw", metavar="FILE", help="weather file (.epw) for the daylight section's annual metrics "
                        "and sunlight hours (its site and 21 March)")
    parser.add_argument("--median-external-lux", type=float, default=None, metavar="LX",
                        help="the site's median external diffuse illuminance E_v,d (lx) for EN 17037's DF method")
    parser.add_argument("--daylight-resolution", type=int, nargs=2, metavar=("NX", "NY"),
                        help="the daylight section's grid on each work plane (default: EN 12464-1's spacing)")


def implied_outputs(args):
    """The report set's fixed files in ``--out`` (the pictures' names depend on the scene: the report
    checks them once the scene is open, before measuring)."""
    import os

    from ..api import report_fixed_files

    return [(f"the report's {name}", os.path.join(args.out, name)) for name in report_fixed_files(not args.no_client)]


def run(args):
    import bpy

    from .. import api
    from . import _io

    _io.check_output_dir(args.out, "--out folder")
    from ..errors import RadiometerError

    if not 0 < args.maintenance_factor <= 1:
        raise RadiometerError(f"--maintenance-factor must be in (0, 1], got {args.maintenance_factor}")
    if args.task is not None:
        from ..radiometry.metrics import compliance

        if args.task not in compliance.TASKS:
            raise RadiometerError(f"unknown --task {args.task!r}; known: {', '.join(sorted(compliance.TASKS))}")
    if args.median_external_lux is not None and not args.median_external_lux > 0:
        raise RadiometerError(f"--median-external-lux must be > 0 lx, got {args.median_external_lux}")
    if args.daylight_resolution is not None and not all(1 <= n <= 500 for n in args.daylight_resolution):
        raise RadiometerError("--daylight-resolution needs 1-500 points along x and y")
    if args.epw:
        from .. import validation

        validation.check_input_file(args.epw, "weather")
    observers = [((o[0], o[1], o[2]), (o[3], o[4], o[5])) for o in (args.observer or [])]
    progress = getattr(args, "progress", None)
    result = api.export_report(args.out, scene=bpy.context.scene, quality=args.quality, method=args.method,
                                  convergence=not args.no_convergence, progress=progress,
                                  phase=None if progress is None else progress.step,
                                  cancelled=getattr(args, "cancelled", None), client=not args.no_client,
                                  project={"name": args.project} if args.project else None, task=args.task,
                                  maintenance_factor=args.maintenance_factor, observers=observers, ra=args.ra,
                                  daylight=True if args.daylight else False if args.no_daylight else "auto",
                                  epw=args.epw, median_external_illuminance_lux=args.median_external_lux,
                                  daylight_resolution=tuple(args.daylight_resolution) if args.daylight_resolution
                                  else None,
                                  **budget_kwargs(args))
    if progress is not None:
        progress.clear()
    print(result["summary"])
    written = [result["paths"][k] for k in ("html", "pdf", "markdown", "json") if k in result["paths"]]
    print(f"\nWrote {', '.join(written)} ({result['seconds']:.1f} s)")
    return {"paths": result["paths"], "summary": result["summary"]}

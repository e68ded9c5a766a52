"""`compliance`: EN 12464-1 compliance of a work plane (maintained illuminance, uniformity, UGR, Ra),
measured with the electric lighting only; the table the client report's compliance section holds."""

HELP = ("EN 12464-1 compliance of a work plane for a task (--task KEY, values cited in docs/deliverables.md) or "
        "your own requirement (--maintained-lx): Ēm (lx), U0, UGR at --observer eyes, Ra; electric lighting only "
        "(suns and an emitting world are off meanwhile); --list-tasks")
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--plane", metavar="NAME", help="work plane object (default: the first mesh named 'Work Plane')")
    parser.add_argument("--task", metavar="KEY", help="EN 12464-1 task, e.g. office_writing, classroom, corridor "
                        "(--list-tasks lists them with their values)")
    parser.add_argument("--maintained-lx", type=float, metavar="LX", help="your own required maintained illuminance "
                        "Ēm in lx (instead of, or overriding, the task's)")
    parser.add_argument("--uniformity", type=float, metavar="U0", help="required uniformity E_min / Ē (overrides the task's)")
    parser.add_argument("--ugr-limit", type=float, metavar="UGR", help="UGR limit (overrides the task's)")
    parser.add_argument("--ra-required", type=float, metavar="RA", help="required colour rendering index (overrides the task's)")
    parser.add_argument("--maintenance-factor", type=float, default=0.8, metavar="MF",
                        help="maintenance factor: maintained illuminance = MF x the new installation's (default 0.8)")
    parser.add_argument("--observer", type=float, nargs=6, action="append", metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="eye position (scene coordinates, m) and view direction for a UGR rating (repeatable)")
    parser.add_argument("--ra", type=float, default=None, metavar="RA", help="the luminaires' rated colour rendering index")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")
    parser.add_argument("--list-tasks", action="store_true", help="list the EN 12464-1 tasks and their values, then stop")


def _number(value):
    import math

    return None if value is None or (isinstance(value, float) and not math.isfinite(value)) else value


def _task_lines():
    from ... import api

    lines = [f"{'task':<26} {'Ēm lx':>6} {'U0':>5} {'UGR_L':>6} {'Ra':>4}  description (source)"]
    for key, req in api.en12464_tasks().items():
        lines.append(f"{key:<26} {req['maintained_lx']:6.0f} {req['uniformity']:5.2f} {req['ugr_limit']:6.0f} "
                     f"{req['ra']:4.0f}  {req['task']} ({req['source']}{', indicative' if req['indicative'] else ''})")
    return lines


def format_checks(checks):
    """The compliance table as text lines: quantity, required, achieved ± 1 s.e. in its unit, status, margin."""
    import math

    lines = [f"{'quantity':<22} {'required':>12} {'achieved':>18} {'margin':>10}  status"]
    for c in checks:
        unit = f" {c['unit']}" if c["unit"] else ""
        if math.isfinite(c["achieved"]):
            se = f" ±{c['std_error']:.2g}" if c["std_error"] else ""
            achieved = f"{c['achieved']:.4g}{se}{unit}"
            margin = f"{c['margin']:+.3g}{unit}" if math.isfinite(c["margin"]) else "-"
        else:
            achieved, margin = "-", "-"
        lines.append(f"{c['quantity']:<22} {c['required']:>12} {achieved:>18} {margin:>10}  {c['status']}"
                     + (f" ({c['note']})" if c["note"] else ""))
    return lines


def run(args):
    import bpy

    from ... import api
    from ...errors import RadiometerError
    from .. import _points

    if args.list_tasks:
        for line in _task_lines():
            print(line)
        return {"tasks": api.en12464_tasks()}
    if args.task is None and args.maintained_lx is None:
        raise RadiometerError("give --task KEY (see --list-tasks) or --maintained-lx LX")
    if not 0 < args.maintenance_factor <= 1:
        raise RadiometerError(f"--maintenance-factor must be in (0, 1], got {args.maintenance_factor}")
    scene = bpy.context.scene
    plane = _points.plane_object(scene, args.plane)
    observers = [((o[0], o[1], o[2]), (o[3], o[4], o[5])) for o in (args.observer or [])]
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = f"EN 12464-1 on {plane.name}"
    r = api.en12464_compliance(plane, args.task, maintained_lx=args.maintained_lx, uniformity=args.uniformity,
                               ugr_limit=args.ugr_limit, ra_required=args.ra_required,
                               maintenance_factor=args.maintenance_factor, observers=observers, ra=args.ra,
                               scene=scene, quality=args.quality)
    if progress is not None:
        progress.clear()
    req = r["requirement"]
    print(f"EN 12464-1 on {plane.name!r}: {req['task']} ({req['source']}"
          f"{'; values indicative' if req['indicative'] else ''}), maintenance factor {r['maintenance_factor']:g}")
    print(f"lighting: {r['lighting']}")
    for line in format_checks(r["checks"]):
        print(line)
    print(f"overall: {r['overall']}")
    result = api.compliance_to_dict(r)
    from .._io import deliver

    deliver(args, result)
    return result

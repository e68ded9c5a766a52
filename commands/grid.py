"""`grid`: illuminance on a work-plane grid (EN 12464-1 spacing by default), with CSV and isolux PNG."""

HELP = "measure illuminance on a grid over a plane (E_avg, E_min, E_max, U0), optional CSV and isolux PNG"
NEEDS_SCENE = True

from .check import add_budget_arguments, budget_kwargs  # noqa: E402


def add_arguments(parser):
    parser.add_argument("--plane", metavar="NAME", help="plane object (default: the first 'Work Plane')")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--spacing", type=float, metavar="M", help="cell size in m (default EN 12464-1)")
    size.add_argument("--resolution", type=int, nargs=2, metavar=("NX", "NY"), help="points along x and y")
    parser.add_argument("--csv", metavar="FILE", help="write the points and values as CSV")
    parser.add_argument("--png", metavar="FILE", help="write a false-colour isolux image")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default="auto")
    parser.add_argument("--quantity", choices=("photopic", "melanopic"), default="photopic",
                        help="melanopic: melanopic EDI (CIE S 026, lx) of the direct light at each point")
    parser.add_argument("--reflected", action="store_true",
                        help="with --quantity melanopic: add the reflected light and the world's (band renders, "
                             "95 %% intervals)")
    add_budget_arguments(parser)


def _melanopic(args, scene, plane):
    from .. import api
    from ..errors import RadiometerError
    from ._io import deliver

    if args.png:
        raise RadiometerError("--quantity melanopic writes no isolux --png yet: use --csv or --json")
    g = api.spectral_grid(plane, resolution=args.resolution, spacing=args.spacing, scene=scene,
                          reflected=args.reflected, quality=args.quality, progress=getattr(args, "progress", None),
                          cancelled=getattr(args, "cancelled", None))
    m, e = g["stats"]["mel_edi_lx"], g["stats"]["illuminance_lx"]
    what = "direct + reflected" if g["part"] == "direct+reflected" else "direct light only"
    print(f"melanopic grid {g['target']}: {g['nx']} x {g['ny']} points ({what}, {g['seconds']:.2f} s)")
    interval = m.get("avg_interval_95")
    band = f" (95 % {interval[0]:.4g}-{interval[1]:.4g} lx)" if interval else ""
    bound = ">= " if g["lower_bound"] else ""
    print(f"mel-EDI avg {bound}{m['avg']:.4g} lx{band}  min {bound}{m['min']:.4g} lx  max {bound}{m['max']:.4g} lx"
          f"  |  E_v avg {bound}{e['avg']:.4g} lx")
    if g["not_included"]:
        print("not included: " + "; ".join(g["not_included"]))
    deliver(args, g)
    if args.csv:
        api.write_spectral_grid_csv(g, args.csv)
        print(f"wrote {args.csv}")
    return g


def run(args):
    import bpy

    from ._io import deliver
    from .. import api
    from . import _io, _points

    if args.png:
        from ..plots import require_matplotlib

        require_matplotlib()  # asked for an image: say at once, before measuring, that it cannot be made
    _io.check_output_file(args.csv, "--csv file")
    _io.check_output_file(args.png, "--png file")
    scene = bpy.context.scene
    plane = _points.plane_object(scene, args.plane)
    if args.quantity == "melanopic":
        return _melanopic(args, scene, plane)
    if args.reflected:
        from ..errors import RadiometerError

        raise RadiometerError("--reflected needs --quantity melanopic")
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = f"grid {plane.name}"
    g = api.illuminance_grid(plane, resolution=args.resolution, spacing=args.spacing, scene=scene,
                                  method=args.method, quality=args.quality, progress=progress,
                                  cancelled=getattr(args, "cancelled", None), **budget_kwargs(args))
    if progress is not None:
        progress.clear()
    import numpy as np

    from ..readings import format_quantity, format_value

    s = g.stats
    print(f"grid {g.target}: {g.nx} x {g.ny} points, cells {g.spacing[0]:.3g} x {g.spacing[1]:.3g} m"
          + (f" ({g.spacing_rule})" if g.spacing_rule else ""))
    # the mean of independent readings: s.e. = sqrt(sum (E_i s_i)^2) / sum E_i; min/max: their point's error
    avg_se = float(np.sqrt(np.sum((g.lux * g.rel_std_error) ** 2)) / max(float(np.sum(g.lux)), 1e-300))
    se_min = float(g.rel_std_error.ravel()[int(np.argmin(g.lux))])
    se_max = float(g.rel_std_error.ravel()[int(np.argmax(g.lux))])
    print(f"E_avg {format_quantity(s['avg'], 'lx', avg_se, g.exact)}  E_min {format_value(s['min'], se_min, g.exact)} lx  "
          f"E_max {format_value(s['max'], se_max, g.exact)} lx  U0 {s['u0']:.2f}  "
          f"[{g.method}, {g.seconds:.2f} s, worst error {100 * g.max_rel_std_error:.2g} %]")
    deliver(args, g.to_dict())  # the numbers are safe on disk before the CSV and the image
    written = []
    if args.csv:
        g.write_csv(args.csv)
        g.csv = args.csv
        written.append(args.csv)
    if args.png:
        g.write_png(args.png)
        written.append(args.png)
    for path in written:
        print(f"wrote {path}")
    if written and getattr(args, "json", None):
        from ._io import write_json

        write_json(args.json, g.to_dict(), getattr(args, "interrupt", None))  # again, with the file paths
    return g.to_dict()

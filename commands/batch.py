"""`batch`: many .blend files (design variants) x their meters, in this process or on a Dask cluster."""

HELP = "measure the light meters of many .blend files (or given points), locally or on a Dask cluster"
NEEDS_SCENE = False

from . import _cluster  # noqa: E402


def add_arguments(parser):
    parser.add_argument("files", nargs="+", metavar="FILE.blend", help=".blend files, measured in this order")
    parser.add_argument("--point", type=float, nargs=6, action="append", metavar=("X", "Y", "Z", "NX", "NY", "NZ"),
                        help="measure illuminance at this point facing this normal (scene coordinates) in every "
                             "file, instead of the files' meter objects; repeat for more points")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard",
                        help="quality preset: 1-sigma target 5 %%, 1 %%, 0.2 %% (default standard)")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default=None,
                        help="measurement method (default: each file's own setting; auto for --point)")
    parser.add_argument("--seed", type=int, default=0, help="first Cycles seed of --point readings (default 0)")
    _cluster.add_arguments(parser)


def format_table(results):
    from .measure import format_value

    lines = [f"{'file':<24} {'meter':<22} {'reading':>14} {'unit':<6} {'± 1 s.e.':>9}  method"]
    for result in results:
        for name, r in zip(result.names, result.readings):
            value, unit = (r.luminance, "cd/m²") if r.quantity == "luminance" else (r.illuminance, "lx")
            se = r.rel_std_error
            err = "exact" if r.exact else (f"{100 * se:.2f} %" if se is not None and se == se else "n/a")
            lines.append(f"{_short(result.file):<24} {name:<22} {format_value(value):>14} {unit:<6} {err:>9}  "
                         f"{r.method}")
    return "\n".join(lines)


def _short(path):
    import os

    return os.path.basename(path)


def run(args):
    from .. import api

    meters = [((p[0], p[1], p[2]), (p[3], p[4], p[5])) for p in args.point] if args.point else None
    with _cluster.client(args) as client:
        results = api.measure_batch(args.files, meters, quality=args.quality, method=args.method, seed=args.seed,
                                    client=client, progress=_cluster.task_progress(args, "batch"),
                                    cancelled=getattr(args, "cancelled", None))
    if getattr(args, "progress", None) is not None:
        args.progress.clear()
    print(format_table(results))
    return {"files": [r.to_dict() for r in results]}

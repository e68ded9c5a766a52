"""`daylight-factor`: DF (%) under the CIE overcast sky at points from a CSV or on a work plane's grid."""

HELP = ("daylight factor under the CIE overcast sky (lights off, the world replaced for the run) at points "
        "(--points CSV) or on a work plane's grid (--plane NAME, with average/min/uniformity and EN 17037); "
        "--csv, --json and --png (a plan-view map)")
NEEDS_SCENE = True

from .. import _cluster, _points  # noqa: E402


def add_arguments(parser):
    _points.add_arguments(parser)
    parser.add_argument("--ground-reflectance", type=float, default=0.2, metavar="RHO",
                        help="reflectance of the uniform ground below the sharp horizon (default 0.2)")
    parser.add_argument("--target", type=float, default=None, metavar="PERCENT",
                        help="with --plane: report the share of the plane with DF >= this")
    parser.add_argument("--median-external-lux", type=float, default=None, metavar="LX",
                        help="with --plane: the site's median external diffuse illuminance E_v,d (EN 17037 "
                             "Annex A) for the D_T / D_TM checks")
    parser.add_argument("--method", choices=("auto", "camera"), default="auto",
                        help="auto: sensor bakes to the quality's target error; camera: cosine-weighted rays from "
                        "each point through a custom camera, a fixed number per quality (cheaper per unit of error)")
    _points.add_study_outputs(parser, csv_help="write one row per point",
                              png_help="with --plane: write a plan-view daylight factor map (the room cut at the "
                                       "plane's height, its openings, the stated error in the title)")


def run(args):
    import math

    import bpy
    import numpy as np

    from ... import api
    from ...readings import format_abs_error, format_value
    from ...errors import RadiometerError
    from .. import _io

    _io.check_output_file(args.csv, "--csv file")
    _io.check_output_file(args.png, "--png file")
    scene = bpy.context.scene
    progress = getattr(args, "progress", None)
    cancelled = getattr(args, "cancelled", None)
    _points.default_plane(args, scene)
    if args.points:
        for name in ("spacing", "resolution", "target", "median_external_lux", "png"):
            if getattr(args, name) is not None:
                raise RadiometerError(f"--{name.replace('_', '-')} goes with --plane, not --points")
        locations, normals = _points.read_points(args.points)
        if progress is not None:
            progress.label = f"daylight factor, {len(locations)} points"
        with _cluster.client(args) as client:
            rs = api.daylight_factor(locations, normals, scene=scene, quality=args.quality, method=args.method,
                                     ground_reflectance=args.ground_reflectance, progress=progress,
                                     cancelled=cancelled, **({"client": client} if client is not None else {}))
        if progress is not None:
            progress.clear()
        print(f"daylight factor at {len(rs)} points (CIE overcast sky, ground reflectance {args.ground_reflectance:g})")
        # the DF with the digits its error supports, the error in DF points (absolute, 1 s.e.)
        print(f"{'x (m)':>9} {'y (m)':>9} {'z (m)':>9} {'DF (%)':>9} {'1 s.e. (DF points)':>20} method")
        for r in rs:
            print(f"{r.location[0]:9.3f} {r.location[1]:9.3f} {r.location[2]:9.3f} "
                  f"{format_value(r.daylight_factor, r.rel_std_error, r.exact):>9} "
                  f"{format_abs_error(r.daylight_factor, r.rel_std_error, 'DF points', r.exact):>20} "
                  f"{r.method}{' exact' if r.exact else ''}")
        result = {"daylight_factor": [r.to_dict() for r in rs]}
        csv = "x,y,z,nx,ny,nz,daylight_factor_percent,rel_std_error,exact\n" + "".join(
            f"{r.location[0]:.6g},{r.location[1]:.6g},{r.location[2]:.6g},{r.normal[0]:.6g},{r.normal[1]:.6g},"
            f"{r.normal[2]:.6g},{r.daylight_factor:.6g},{r.rel_std_error:.4g},{int(r.exact)}\n" for r in rs)
    else:
        if progress is not None:
            progress.label = f"daylight factor on {args.plane}"
        with _cluster.client(args) as client:
            g = api.daylight_factor_grid(args.plane, resolution=args.resolution, spacing=args.spacing, scene=scene,
                                         quality=args.quality, ground_reflectance=args.ground_reflectance,
                                         target_percent=args.target, method=args.method,
                                         median_external_illuminance_lux=args.median_external_lux,
                                         progress=progress, cancelled=cancelled,
                                         **({"client": client} if client is not None else {}))
        if progress is not None:
            progress.clear()
        s = g.stats
        # absolute errors in DF points: the worst point's 1 s.e. sets the digits of every statistic
        abs_se = np.asarray(g.daylight_factor, float) * np.asarray(g.rel_std_error, float)
        worst = float(np.nanmax(abs_se)) if np.isfinite(abs_se).any() else float("nan")

        def df(v):
            return format_value(v, worst / v if v and math.isfinite(worst) else None, g.exact)

        error = "every point exact" if g.exact else f"worst stated error ±{worst:.2g} DF points, 1 s.e."
        print(f"daylight factor on {g.target!r}: {g.nx} x {g.ny} points, average {df(s['average'])} % "
              f"(BS 8206-2), min {df(s['minimum'])} %, max {df(s['maximum'])} %, median {df(s['median'])} %, "
              f"uniformity {s['uniformity']:.3f} ({error})")
        if "share_above_target" in s:
            print(f"share of the plane with DF >= {s['target_percent']:g} %: {100 * s['share_above_target']:.1f} %")
        if "en17037" in s:
            for name, lv in s["en17037"]["levels"].items():
                print(f"EN 17037 {name}: D_T {lv['D_T']:.2f} % over {100 * lv['share_D_T']:.0f} % (needs 50 %), "
                      f"D_TM {lv['D_TM']:.2f} % over {100 * lv['share_D_TM']:.0f} % (needs 95 %): "
                      f"{'met' if lv['met'] else 'not met'}")
        result = g.to_dict()
        csv = g.csv_text()
    _io.deliver_with_csv(args, result, csv)
    if args.png:  # after the numbers are saved: a failed picture loses no measurement
        print(f"wrote {api.daylight_map(g, args.png, scene=scene)}")
    return result

"""`sun-study`: illuminance from the sun over a day (or any span) at points from a CSV or a grid."""

HELP = ("sun study: illuminance from the sun (and --sky NAME) at points (--points CSV or --plane NAME) from "
        "--start to --end every --step minutes; sunlit flags and sunlight hours; --csv, --json and --png "
        "(a plan-view map of sunlight hours)")
NEEDS_SCENE = True

from .. import _cluster, _points  # noqa: E402


def add_arguments(parser):
    from ...radiometry.skies.sky_models import SKY_MODELS  # the same mapping as api.SKY_MODELS
    from .sun import add_place_arguments

    parser.add_argument("--start", required=True, metavar="ISO", help="first time, ISO 8601 (local with --tz)")
    parser.add_argument("--end", required=True, metavar="ISO", help="last time (included when on a step)")
    parser.add_argument("--step", type=float, default=60.0, metavar="MIN", help="minutes between times (default 60)")
    add_place_arguments(parser)
    _points.add_arguments(parser)
    parser.add_argument("--lux", type=float, default=None, metavar="LX",
                        help="direct normal illuminance of the sun (default: the IES clear-day model)")
    parser.add_argument("--sky", choices=tuple(SKY_MODELS), default=None, metavar="NAME",
                        help="add this sky (the world is off otherwise): " + ", ".join(SKY_MODELS)
                             + " (the types that depend on the sun follow it)")
    parser.add_argument("--sky-lux", type=float, default=None, metavar="LX",
                        help="with --sky: the sky's unobstructed horizontal illuminance (default 10 000 lx)")
    parser.add_argument("--min-elevation", type=float, default=0.0, metavar="DEG",
                        help="sun altitude below which a sample adds no sunlight hours (EN 17037 site minimum)")
    parser.add_argument("--time-budget", type=float, default=None, metavar="S",
                        help="seconds per time step at most: it stops at the quality's target or the budget, "
                             "whichever comes first (a low sun gives small, costly readings)")
    _points.add_study_outputs(parser, csv_help="write one row per time and point",
                              png_help="write a plan-view map of the sunlight hours per point (points on one "
                                       "horizontal plane)")


def time_range(start, end, step_min, tz):
    import datetime as dt
    import math

    from ...errors import RadiometerError
    from .sun import parse_times

    if not (step_min > 0 and math.isfinite(step_min)):
        raise RadiometerError(f"--step must be > 0 minutes, got {step_min}")
    first, last = parse_times([start, end], tz)
    if last < first:
        raise RadiometerError(f"--end {end} is before --start {start}")
    # Steps in absolute time (UTC), shown in the start's zone: a daylight-saving change neither skips
    # nor repeats a sample.
    count = int((last - first).total_seconds() // (60.0 * step_min)) + 1
    if count > 100_000:
        raise RadiometerError(f"{count} times is too many: use a larger --step")
    return [(first.astimezone(dt.timezone.utc) + dt.timedelta(minutes=step_min * k)).astimezone(first.tzinfo)
            for k in range(count)]


def run(args):
    import bpy
    import numpy as np

    from ... import api
    from ...errors import RadiometerError
    from .. import _io

    _io.check_output_file(args.csv, "--csv file")
    _io.check_output_file(args.png, "--png file")
    if args.lux is not None and not (args.lux >= 0 and np.isfinite(args.lux)):
        raise RadiometerError(f"--lux must be >= 0, got {args.lux}")
    if args.sky_lux is not None and (args.sky is None or not (args.sky_lux > 0 and np.isfinite(args.sky_lux))):
        raise RadiometerError(f"--sky-lux goes with --sky and must be > 0, got {args.sky_lux}")
    scene = bpy.context.scene
    times = time_range(args.start, args.end, args.step, args.tz)
    locations, normals = _points.from_args(args, scene)
    if args.png:  # a map is a plan view: say so before the work, not after it
        from ...plots.daylight_map import plan_height

        plan_height(np.asarray(locations, float)[:, 2] * scene.unit_settings.scale_length)
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = f"sun study, {len(times)} times x {len(locations)} points"
    with _cluster.client(args) as client:
        r = api.sun_study(locations, normals, times, latitude_deg=args.lat, longitude_deg=args.lon,
                          elevation_m=args.elevation, direct_normal_illuminance_lux=args.lux, sky=args.sky,
                          sky_horizontal_illuminance_lux=args.sky_lux, scene=scene,
                          quality=args.quality, north_offset_deg=args.north, min_elevation_deg=args.min_elevation,
                          time_budget_s=args.time_budget, client=client, progress=progress, cancelled=getattr(args, "cancelled", None))
    if progress is not None:
        progress.clear()
    print(f"sun study: {len(times)} times x {len(locations)} points at {args.lat:.4f} N, {args.lon:.4f} E "
          f"({np.sum(r.seconds):.1f} s, {np.mean(r.seconds):.3f} s per time step)")
    print(f"{'time':<26} {'azimuth':>8} {'elev.':>7} {'E_dn lx':>9} {'E mean lx':>10} {'E max lx':>10} sunlit")
    for i, sun in enumerate(r.sun):
        print(f"{sun['time']:<26} {sun['azimuth_deg']:8.2f} {sun['elevation_deg']:7.2f} "
              f"{sun['direct_normal_illuminance_lux']:9.0f} {r.illuminance[i].mean():10.1f} {r.illuminance[i].max():10.1f} "
              f"{int(r.sunlit[i].sum())}/{len(locations)}")
    h = r.sunlight_hours
    print(f"sunlight hours per point: min {h.min():.2f} h, mean {h.mean():.2f} h, max {h.max():.2f} h "
          f"(worst stated error {100 * float(np.max(r.rel_std_error)):.2g} %)")
    result = r.to_dict()
    result.update(latitude_deg=args.lat, longitude_deg=args.lon, north_offset_deg=args.north)
    _io.deliver_with_csv(args, result, r.csv_text())
    if args.png:
        print(f"wrote {api.daylight_map(r, args.png, scene=scene)}")
    return result

"""`sun-study`: illuminance from the sun over a day (or any span) at points from a CSV or a grid."""

HELP = ("sun study: illuminance from the sun at points (--points CSV or --plane NAME) from --start to --end "
        "every --step minutes; sunlit flags and sunlight hours; --csv and --json")
NEEDS_SCENE = True

from . import _cluster  # noqa: E402


def add_arguments(parser):
    from .sun import add_place_arguments

    parser.add_argument("--start", required=True, metavar="ISO", help="first time, ISO 8601 (local with --tz)")
    parser.add_argument("--end", required=True, metavar="ISO", help="last time (included when on a step)")
    parser.add_argument("--step", type=float, default=60.0, metavar="MIN", help="minutes between times (default 60)")
    add_place_arguments(parser)
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--points", metavar="CSV", help="points as CSV rows x,y,z[,nx,ny,nz] (scene units; a "
                       "header line is skipped; normal default +Z)")
    where.add_argument("--plane", metavar="NAME", help="a grid over this plane object's local XY (its +Z side)")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--spacing", type=float, metavar="M", help="with --plane: cell size in m (default EN 12464-1)")
    size.add_argument("--resolution", type=int, nargs=2, metavar=("NX", "NY"), help="with --plane: points along x, y")
    parser.add_argument("--lux", type=float, default=None, metavar="LX",
                        help="direct normal illuminance of the sun (default: the IES clear-day model)")
    parser.add_argument("--min-elevation", type=float, default=0.0, metavar="DEG",
                        help="sun altitude below which a sample adds no sunlight hours (EN 17037 site minimum)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")
    parser.add_argument("--time-budget", type=float, default=None, metavar="S",
                        help="seconds per time step at most: it stops at the quality's target or the budget, "
                             "whichever comes first (a low sun gives small, costly readings)")
    parser.add_argument("--csv", metavar="FILE", help="write one row per time and point")
    _cluster.add_arguments(parser)


def read_points(path):
    """(locations (N, 3), normals (N, 3)) from a CSV file; RadiometerError naming the line otherwise."""
    import numpy as np

    from ..errors import RadiometerError

    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise RadiometerError(f"cannot read --points {path}: {getattr(exc, 'strerror', None) or exc}") from None
    rows = []
    for number, line in enumerate(lines, start=1):
        cells = [c.strip() for c in line.split(",")]
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if not rows and number == 1:
                continue  # a header
            raise RadiometerError(f"{path} line {number}: expected numbers x,y,z[,nx,ny,nz], got {line!r}") from None
        if len(values) not in (3, 6) or not all(np.isfinite(values)):
            raise RadiometerError(f"{path} line {number}: expected 3 or 6 finite numbers, got {line!r}")
        rows.append(values if len(values) == 6 else values + [0.0, 0.0, 1.0])
    if not rows:
        raise RadiometerError(f"{path}: no points")
    a = np.array(rows)
    return a[:, :3], a[:, 3:]


def plane_points(scene, name, spacing=None, resolution=None):
    """Cell centres (N, 3) and the normal of a grid on a plane object (as the grid command lays it out)."""
    import math

    import numpy as np

    from ..errors import RadiometerError
    from ..measure.grid import plane_frame
    from ..radiometry import grid as grid_math

    obj = scene.objects.get(name)
    if obj is None:
        raise RadiometerError(f"no object named {name!r} in scene {scene.name!r}")
    (x0, x1, y0, y1, zc), mw, normal = plane_frame(obj, scene)
    scale = scene.unit_settings.scale_length
    sx, sy = (x1 - x0) * np.linalg.norm(mw[:3, 0]) * scale, (y1 - y0) * np.linalg.norm(mw[:3, 1]) * scale
    if resolution is not None:
        nx, ny = resolution
        if nx < 1 or ny < 1:
            raise RadiometerError(f"--resolution must be at least 1 1, got {nx} {ny}")
    else:
        if spacing is not None and not (spacing > 0 and math.isfinite(spacing)):
            raise RadiometerError(f"--spacing must be > 0 m, got {spacing}")
        nx, ny = grid_math.grid_counts(sx, sy, spacing)
    local = grid_math.cell_centres((x0, x1), (y0, y1), nx, ny).reshape(-1, 2)
    local4 = np.column_stack([local, np.full(len(local), zc), np.ones(len(local))])
    return (local4 @ mw.T)[:, :3], np.broadcast_to(normal, (len(local), 3))


def time_range(start, end, step_min, tz):
    import datetime as dt
    import math

    from ..errors import RadiometerError
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

    from .. import api
    from ._io import deliver
    from ..errors import RadiometerError
    from . import _io

    _io.check_output_file(args.csv, "--csv file")
    if args.lux is not None and not (args.lux >= 0 and np.isfinite(args.lux)):
        raise RadiometerError(f"--lux must be >= 0, got {args.lux}")
    scene = bpy.context.scene
    times = time_range(args.start, args.end, args.step, args.tz)
    if args.points:
        if args.spacing is not None or args.resolution is not None:
            raise RadiometerError("--spacing/--resolution go with --plane, not --points")
        locations, normals = read_points(args.points)
    else:
        locations, normals = plane_points(scene, args.plane, args.spacing, args.resolution)
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = f"sun study, {len(times)} times x {len(locations)} points"
    with _cluster.client(args) as client:
        r = api.sun_study(locations, normals, times, latitude_deg=args.lat, longitude_deg=args.lon,
                          elevation_m=args.elevation, direct_normal_illuminance_lux=args.lux, scene=scene,
                          quality=args.quality, north_offset_deg=args.north, min_elevation_deg=args.min_elevation,
                      time_budget_s=args.time_budget,
                          client=client, progress=progress, cancelled=getattr(args, "cancelled", None))
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
    deliver(args, result)
    if args.csv:
        _io.write_text(args.csv, r.csv_text(), getattr(args, "interrupt", None))
        print(f"wrote {args.csv}")
    return result

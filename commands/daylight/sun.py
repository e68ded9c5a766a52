"""`sun`: where the sun is at a place and time (NREL SPA); ``--set`` puts it into a .blend."""

HELP = "sun position (azimuth, elevation, direction) at a place and time; --set writes the sun into a .blend (--out)"
NEEDS_SCENE = True


def add_place_arguments(parser):
    """--lat/--lon/--elevation/--north/--tz, shared with sun-study."""
    parser.add_argument("--lat", type=float, required=True, metavar="DEG", help="latitude, degrees north")
    parser.add_argument("--lon", type=float, required=True, metavar="DEG", help="longitude, degrees east")
    parser.add_argument("--elevation", type=float, default=0.0, metavar="M", help="site height above sea level, m")
    parser.add_argument("--north", type=float, default=0.0, metavar="DEG",
                        help="north offset: angle from scene +Y to true north, counter-clockwise seen from above")
    parser.add_argument("--tz", default=None, metavar="ZONE",
                        help="time zone of times without an offset: an IANA name (Europe/London) or +02:00")


def add_arguments(parser):
    parser.add_argument("--time", nargs="+", required=True, metavar="ISO",
                        help="local time(s), ISO 8601: 2026-06-21T12:00 (with --tz) or 2026-06-21T12:00+01:00")
    add_place_arguments(parser)
    parser.add_argument("--lux", type=float, default=None, metavar="LX",
                        help="direct normal illuminance of the sun (default: the IES clear-day model)")
    parser.add_argument("--set", action="store_true",
                        help="create or update the scene's sun for the (first) time and save the scene to --out")
    parser.add_argument("--out", metavar="FILE", help="with --set: the .blend to write (never the input file)")


def parse_times(texts, tz_name):
    """Timezone-aware datetimes from ISO texts; naive ones take ``tz_name`` (RadiometerError without it)."""
    import datetime as dt

    from ...errors import RadiometerError
    from ...radiometry.sun import solar_position

    tz = None
    if tz_name:
        try:
            tz = solar_position.parse_time_zone(tz_name)
        except ValueError as exc:
            raise RadiometerError(f"--tz: {exc}") from None
    out = []
    for text in texts:
        try:
            t = dt.datetime.fromisoformat(text)
        except ValueError:
            raise RadiometerError(f"--time {text!r} is not an ISO 8601 time such as 2026-06-21T12:00") from None
        if t.tzinfo is None:
            if tz is None:
                raise RadiometerError(f"--time {text!r} has no UTC offset: add one (+01:00) or give --tz ZONE")
            try:
                t = solar_position.local_datetime(t.year, t.month, t.day, t.hour, t.minute, tz, t.second)
            except ValueError as exc:
                raise RadiometerError(str(exc)) from None
        out.append(t)
    return out


def run(args):
    import os

    import numpy as np

    from ... import api
    from ...errors import RadiometerError

    times = parse_times(args.time, args.tz)
    pos = api.sun_position(args.lat, args.lon, times, elevation_m=args.elevation, north_offset_deg=args.north)
    rows = []
    for i, t in enumerate(times):
        az, el = float(pos.azimuth_deg[i]), float(pos.elevation_deg[i])
        d = [float(v) for v in np.asarray(pos.direction)[i]]
        rows.append({"time": t.isoformat(), "azimuth_deg": az, "elevation_deg": el, "zenith_deg": 90.0 - el,
                     "direction": d})
        print(f"{t.isoformat()}  azimuth {az:8.3f} deg  elevation {el:7.3f} deg  "
              f"direction ({d[0]:.4f}, {d[1]:.4f}, {d[2]:.4f})" + ("" if el > 0 else "  (below the horizon)"))
    result = {"latitude_deg": args.lat, "longitude_deg": args.lon, "elevation_m": args.elevation,
              "north_offset_deg": args.north, "positions": rows,
              "conventions": "azimuth clockwise from true north; apparent elevation (refraction); direction "
                             "towards the sun, +X east, +Y north, +Z up turned by the north offset"}
    if args.set:
        import bpy

        if not args.out:
            raise RadiometerError("--set writes the scene with the sun to --out FILE.blend: give --out")
        source = bpy.data.filepath
        if not source:
            raise RadiometerError("--set needs a .blend to put the sun into")
        if os.path.abspath(args.out) == os.path.abspath(source):
            raise RadiometerError("--out must not be the input .blend (an output never overwrites an input)")
        from .. import _io

        _io.check_output_file(args.out, "--out file")
        out = api.set_sun(bpy.context.scene, args.lat, args.lon, times[0], direct_normal_illuminance_lux=args.lux,
                          north_offset_deg=args.north, elevation_m=args.elevation)
        api.save_copy(args.out, getattr(args, "interrupt", None))
        print(f"sun {out['object']!r}: {out['direct_normal_illuminance_lux']:.6g} lx direct normal "
              f"({out['model']}), strength {out['strength_w_m2']:.6g} W/m²; wrote {args.out}")
        result["set"] = dict(out, blend=args.out)
    return result

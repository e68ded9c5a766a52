"""`annual`: climate-based daylight (sDA, ASE, UDI) from an EPW file at points or on a work plane."""

HELP = ("annual daylight from an EPW weather file by daylight coefficients (all sky patches in one render): "
        "sDA300/50%, ASE1000/250h, UDI 100-2000 lx at points (--points CSV) or on a plane's grid; --csv, --json "
        "and --png (a plan-view map); or, with --dgp-observer, the hourly daylight glare probability at one eye")
NEEDS_SCENE = True

from .. import _cluster, _points  # noqa: E402


def add_arguments(parser):
    parser.add_argument("--epw", required=True, metavar="FILE", help="EnergyPlus weather file (.epw)")
    _points.add_arguments(parser)
    parser.add_argument("--subdivision", type=int, default=1, metavar="M",
                        help="Reinhart sky subdivision MF:M (1 = Tregenza, 146 patches with the ground)")
    parser.add_argument("--ground-reflectance", type=float, default=0.2, metavar="RHO",
                        help="reflectance of the ground (default 0.2)")
    parser.add_argument("--north", type=float, default=0.0, metavar="DEG",
                        help="angle from the scene's +Y axis to true north, counter-clockwise seen from above")
    parser.add_argument("--method", choices=("dome", "per_patch"), default="dome",
                        help="dome: every sky patch in one render (default); per_patch: one render per patch (slow)")
    parser.add_argument("--partial-period", action="store_true",
                        help="accept a weather file that is not a whole year (8760 or 8784 hourly records): the "
                        "metrics cover its period and the notes say which; without it such a file is refused")
    parser.add_argument("--map", choices=("sda", "ase", "udi"), default="sda",
                        help="the --png map: sda, the share of occupied hours at 300 lx (points whose pass/fail is "
                        "uncertain at 2 s.e. ringed; default); ase, hours of direct sun at 1000 lx; udi, the share "
                        "of occupied hours at 100-2000 lx")
    parser.add_argument("--dgp-observer", type=float, nargs=6, metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="instead of points: the annual daylight glare probability at this eye (scene "
                        "coordinates) looking along DX DY DZ (not vertical): full DGP with the sun's disc where it is "
                        "seen, the simplified DGPs elsewhere; hours above 0.35/0.40/0.45 and EN 17037's glare row "
                        "(--csv: one row per hour)")
    parser.add_argument("--low-light-correction", action="store_true",
                        help="with --dgp-observer: Wienold's low-light correction below 1000 lx")
    _points.add_study_outputs(parser, quality_default="preview",
                              quality_help="rays per point for the daylight coefficients (default preview: 8 rounds "
                                           "x 32 samples x 8 x 8 pixels, 16384 rays); the errors reached are stated",
                              csv_help="write one row per point",
                              png_help="write a plan-view map of --map per point (points on one horizontal plane)")


def run(args):
    import bpy
    import numpy as np

    from ... import api, validation
    from ...radiometry.sun import epw
    from .. import _io

    _io.check_output_file(args.csv, "--csv file")
    _io.check_output_file(args.png, "--png file")
    # a folder, a FIFO or a device is named as such (read_epw checks again when it opens the file)
    validation.check_input_file(args.epw, "weather", max_bytes=epw.MAX_FILE_BYTES)
    scene = bpy.context.scene
    if args.dgp_observer is not None:
        return _run_dgp(args, scene)
    if args.low_light_correction:
        from ...errors import RadiometerError

        raise RadiometerError("--low-light-correction goes with --dgp-observer")
    locations, normals = _points.from_args(args, scene)
    if args.png:  # a map is a plan view: say so before the work, not after it
        from ...plots.daylight_map import plan_height

        plan_height(np.asarray(locations, float)[:, 2] * scene.unit_settings.scale_length)
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = f"annual daylight, {len(locations)} points"
    with _cluster.client(args) as client:
        r = api.annual_daylight(locations, normals, args.epw, scene=scene, m=args.subdivision, quality=args.quality,
                                ground_reflectance=args.ground_reflectance, north_offset_deg=args.north,
                                progress=progress, cancelled=getattr(args, "cancelled", None), client=client,
                                method=args.method, partial_period=args.partial_period)
    if progress is not None:
        progress.clear()
    what = "annual daylight" if r.whole_year else f"daylight over a PARTIAL PERIOD ({r.weather_period})"
    print(f"{what} at {len(locations)} points: sDA300/50% {100 * r.sda:.1f} % (within 2 s.e.: "
          f"{100 * r.sda_range[0]:.1f}-{100 * r.sda_range[1]:.1f} %), ASE1000/250h (direct sun) "
          f"{100 * r.ase:.1f} %, mean UDI 100-2000 lx {100 * float(np.mean(r.udi[1])):.1f} % of occupied hours "
          f"(worst stated hourly error {100 * r.max_rel_std_error:.2g} %)")
    for note in r.notes:
        print(note)
    result = r.to_dict()
    _io.deliver_with_csv(args, result, r.csv_text())
    if args.png:
        print(f"wrote {api.daylight_map(r, args.png, metric=args.map, scene=scene)}")
    return result


def _run_dgp(args, scene):
    """``--dgp-observer``: the annual DGP at one eye (``api.annual_dgp``)."""
    from ... import api
    from ...errors import RadiometerError
    from .. import _io

    given = [name for name, v in (("--points", args.points), ("--plane", args.plane), ("--spacing", args.spacing),
                                  ("--resolution", args.resolution), ("--png", args.png)) if v is not None]
    if given:
        raise RadiometerError(f"--dgp-observer rates one eye: {', '.join(given)} go with points, not with it")
    if args.method != "dome":
        raise RadiometerError("--dgp-observer takes the dome method only")
    o = args.dgp_observer
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = "annual DGP"
    with _cluster.client(args) as client:
        r = api.annual_dgp(tuple(o[:3]), tuple(o[3:]), args.epw, scene=scene, m=args.subdivision,
                           quality=args.quality, ground_reflectance=args.ground_reflectance,
                           north_offset_deg=args.north, low_light_correction=args.low_light_correction,
                           client=client, partial_period=args.partial_period, progress=progress,
                           cancelled=getattr(args, "cancelled", None))
    if progress is not None:
        progress.clear()
    what = "" if r.whole_year else f" over a PARTIAL PERIOD ({r.weather_period})"
    print(f"observer ({o[0]:g}, {o[1]:g}, {o[2]:g}) looking ({o[3]:g}, {o[4]:g}, {o[5]:g}){what}: {r.summary()}")
    for note in r.notes:
        print(note)
    result = r.to_dict()
    _io.deliver_with_csv(args, result, r.csv_text())
    return result

"""`glare`: CIE 117 UGR (or, with ``--index dgp``, the daylight glare probability) at one or more
observers, and optionally a false-colour luminance image."""

HELP = ("UGR (CIE 117) or DGP (--index dgp, daylight glare) at observer positions; --luminance-image writes "
        "the camera's false-colour view (cd/m²)")
NEEDS_SCENE = True

#: Each glare index's own options (from the arguments) beside observer, direction, scene and quality; an
#: index is rated by ``api.GLARE_INDICES[name]`` (how to add one: the checklist there).
INDEX_OPTIONS = {
    "ugr": lambda args: {},
    "dgp": lambda args: {"resolution": args.resolution, "threshold_cd_m2": args.threshold, "hdr_path": args.hdr},
}


def _ugr_source(s, format_value):
    return (f"  {s['name']:<24} L {format_value(s['luminance'], 1e-3)} cd/m²  ω {s['solid_angle']:.3g} sr  "
            f"p {s['position_index']:.3g}"
            + ("" if s.get("visible_fraction_bounds", (1.0, 1.0)) == (1.0, 1.0) else f"  ({s['visibility']})"))


def _dgp_source(s, format_value):
    return (f"  source L {format_value(s['luminance'], 1e-3)} cd/m²  ω {s['solid_angle']:.3g} sr  "
            f"P {s['position_index']:.3g}  {s['sigma_deg']:.0f} deg off the line of sight")


#: One printed line per glare source, per index.
SOURCE_LINE = {"ugr": _ugr_source, "dgp": _dgp_source}


def add_arguments(parser):
    parser.add_argument("--observer", type=float, nargs=6, action="append", metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="eye position (scene coordinates) and view direction (repeatable)")
    parser.add_argument("--luminance-image", metavar="EXR", help="also write the scene camera's luminance as a "
                        "32-bit EXR (cd/m²) and a false-colour PNG beside it")
    parser.add_argument("--scale", choices=("log", "linear"), default="log", help="colour scale of the PNG")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")
    parser.add_argument("--index", choices=tuple(INDEX_OPTIONS), default="ugr",
                        help="ugr: CIE 117 (electric light, rated from the lights); dgp: daylight glare probability "
                             "(Wienold & Christoffersen 2006) from a rendered 180 deg fisheye at each observer")
    parser.add_argument("--resolution", type=int, default=128, metavar="PX",
                        help="with --index dgp: the fisheye's side in pixels (16-512; default 128)")
    parser.add_argument("--threshold", type=float, default=2000.0, metavar="CD_M2",
                        help="with --index dgp: glare-source luminance threshold in cd/m² (evalglare's default 2000)")
    parser.add_argument("--max-samples", type=int, default=None, metavar="SPP",
                        help="with --luminance-image: samples per pixel per render at most (16-1024; default 1024, "
                        "at --quality preview 16: one round, as the report's picture)")
    parser.add_argument("--time-budget", type=float, default=None, metavar="S",
                        help="with --luminance-image: start no round of renders that would end past S seconds; "
                        "the result says how many pixels reached the quality's target")
    parser.add_argument("--hdr", metavar="HDR", help="with --index dgp and one observer: also write the fisheye as a "
                        "Radiance HDR (angular fisheye view in its header) for evalglare")


def implied_outputs(args):
    """The false-colour PNG written beside ``--luminance-image X.exr`` (X.png): in the CLI's checks."""
    import os

    path = getattr(args, "luminance_image", None)
    if not path or not str(path).lower().endswith(".exr"):
        return []
    return [("the PNG beside --luminance-image", os.path.splitext(path)[0] + ".png")]


def run(args):
    import bpy

    from .. import api
    from ..errors import RadiometerError
    from ..readings import format_value
    from . import _io

    if args.index == "dgp" and not args.observer:
        raise RadiometerError("--index dgp needs --observer X Y Z DX DY DZ (the eye and its line of sight)")
    if not args.observer and not args.luminance_image:
        raise RadiometerError("give --observer X Y Z DX DY DZ (and/or --luminance-image FILE.exr)")
    if args.hdr and (args.index != "dgp" or len(args.observer or []) != 1):
        raise RadiometerError("--hdr needs --index dgp and exactly one --observer")
    _io.check_picture_samples(args.max_samples)
    if args.time_budget is not None and not (args.time_budget > 0 and args.time_budget < float("inf")):
        raise RadiometerError(f"--time-budget must be a number of seconds > 0, got {args.time_budget:g}")
    if (args.max_samples is not None or args.time_budget is not None) and not args.luminance_image:
        raise RadiometerError("--max-samples and --time-budget bound the --luminance-image picture: give it too")
    _io.check_output_file(args.luminance_image, "--luminance-image file")
    _io.check_output_file(args.hdr, "--hdr file")
    scene = bpy.context.scene
    out = {"scene": scene.name, "observers": []}
    rate, options, line = api.GLARE_INDICES[args.index], INDEX_OPTIONS[args.index](args), SOURCE_LINE[args.index]
    for o in args.observer or []:
        g = rate(tuple(o[:3]), tuple(o[3:]), scene=scene, quality=args.quality, **options)
        print(f"observer ({o[0]:g}, {o[1]:g}, {o[2]:g}) looking ({o[3]:g}, {o[4]:g}, {o[5]:g}): {g.summary()}")
        for s in g.sources:
            print(line(s, format_value))
        for d in getattr(g, "left_out", ()):
            print(f"  {d['name']:<24} left out: {d['reason']}")
        for path in getattr(g, "paths", {}).values():
            print(f"wrote {path}")
        out["observers"].append(g.to_dict())
    if args.luminance_image:
        img = api.luminance_image(args.luminance_image, scene=scene, quality=args.quality, scale=args.scale,
                                  max_spp=args.max_samples, time_budget_s=args.time_budget)
        print(f"luminance picture: {img.resolution[0]} x {img.resolution[1]} px, {img.samples} samples per pixel, "
              f"{100 * img.share_on_target:.0f} % of the lit pixels within {100 * img.target_rel_error:g} % "
              f"({img.seconds:.0f} s)")
        for path in img.paths.values():
            print(f"wrote {path}")
        out["luminance_image"] = img.to_dict()
    return out

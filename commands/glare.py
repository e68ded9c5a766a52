"""`glare`: CIE 117 UGR at one or more observers, and optionally a false-colour luminance image."""

HELP = "UGR (CIE 117) at observer positions; --luminance-image writes the camera's false-colour view (cd/m²)"
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--observer", type=float, nargs=6, action="append", metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="eye position (scene coordinates) and view direction (repeatable)")
    parser.add_argument("--luminance-image", metavar="EXR", help="also write the scene camera's luminance as a "
                        "32-bit EXR (cd/m²) and a false-colour PNG beside it")
    parser.add_argument("--scale", choices=("log", "linear"), default="log", help="colour scale of the PNG")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")


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

    if not args.observer and not args.luminance_image:
        raise RadiometerError("give --observer X Y Z DX DY DZ (and/or --luminance-image FILE.exr)")
    _io.check_output_file(args.luminance_image, "--luminance-image file")
    scene = bpy.context.scene
    out = {"scene": scene.name, "observers": []}
    for o in args.observer or []:
        g = api.glare_ugr(tuple(o[:3]), tuple(o[3:]), scene=scene, quality=args.quality)
        print(f"observer ({o[0]:g}, {o[1]:g}, {o[2]:g}) looking ({o[3]:g}, {o[4]:g}, {o[5]:g}): {g.summary()}")
        for s in g.sources:
            print(f"  {s['name']:<24} L {format_value(s['luminance'], 1e-3)} cd/m²  ω {s['solid_angle']:.3g} sr  "
                  f"p {s['position_index']:.3g}"
                  + ("" if s.get("visible_fraction_bounds", (1.0, 1.0)) == (1.0, 1.0) else f"  ({s['visibility']})"))
        for d in g.left_out:
            print(f"  {d['name']:<24} left out: {d['reason']}")
        out["observers"].append(g.to_dict())
    if args.luminance_image:
        img = api.luminance_image(args.luminance_image, scene=scene, quality=args.quality, scale=args.scale)
        for path in img.paths.values():
            print(f"wrote {path}")
        out["luminance_image"] = img.to_dict()
    return out

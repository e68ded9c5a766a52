"""`illuminance-image`: illuminance (lx) on the surfaces the scene camera sees, as a 32-bit EXR and a
false-colour PNG with its scale in lx beside it (``api.illuminance_image``)."""

HELP = ("illuminance (lx) on the surfaces the camera sees, E = pi x Cycles' diffuse light passes (exact on "
        "Lambertian surfaces): writes --exr FILE.exr (lx in every channel) and a false-colour PNG beside it")
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--exr", required=True, metavar="FILE", help="the image to write: a 32-bit .exr, lx in R, G "
                        "and B; the false-colour PNG (scale in lx) goes beside it with the same name")
    parser.add_argument("--camera", metavar="NAME", help="camera object to render from (default: the scene's camera)")
    parser.add_argument("--resolution", type=int, nargs=2, metavar=("W", "H"),
                        help="pixels (default: the scene's render size, at most 320 px a side)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="preview")
    parser.add_argument("--max-samples", type=int, default=1024, metavar="SPP",
                        help="samples per pixel per render at most (16-1024, default 1024): the renders stop there "
                        "even where the quality's target is not reached, and the output says how many pixels did")
    parser.add_argument("--scale", choices=("log", "linear"), default="log", help="colour scale of the PNG (default log)")
    parser.add_argument("--range", type=float, nargs=2, metavar=("LO", "HI"),
                        help="the PNG's colour range in lx (default: from the image)")


def implied_outputs(args):
    """The false-colour PNG written beside ``--exr X.exr`` (X.png): in the CLI's checks."""
    import os

    path = getattr(args, "exr", None)
    if not path or not str(path).lower().endswith(".exr"):
        return []
    return [("the PNG beside --exr", os.path.splitext(path)[0] + ".png")]


def run(args):
    import math

    import bpy
    import numpy as np

    from ... import api
    from ...errors import RadiometerError
    from .. import _io

    if not str(args.exr).lower().endswith(".exr"):
        raise RadiometerError(f"--exr must name an .exr file, got {args.exr!r:.200}")
    if args.resolution is not None and not all(0 < n <= 4096 for n in args.resolution):
        raise RadiometerError(f"--resolution must be 1-4096 px a side, got {args.resolution[0]} {args.resolution[1]}")
    if args.range is not None and not (0 <= args.range[0] < args.range[1] and math.isfinite(args.range[1])):
        raise RadiometerError(f"--range needs 0 <= LO < HI (lx), got {args.range[0]:g} {args.range[1]:g}")
    _io.check_picture_samples(args.max_samples)
    _io.check_output_file(args.exr, "--exr file")
    scene = bpy.context.scene
    if args.camera is not None:
        cam = scene.objects.get(args.camera)
        if cam is None or cam.type != "CAMERA":
            raise RadiometerError(f"no camera named {args.camera!r} in scene {scene.name!r}")
    elif scene.camera is None:
        raise RadiometerError(f"scene {scene.name!r} has no camera: add one or name it with --camera NAME")
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = "illuminance image"
    img = api.illuminance_image(args.exr, scene=scene, camera=args.camera,
                                resolution=tuple(args.resolution) if args.resolution else None,
                                quality=args.quality, scale=args.scale,
                                range=tuple(args.range) if args.range else None, max_spp=args.max_samples)
    if progress is not None:
        progress.clear()
    e = img.illuminance
    seen = e > 0
    rel = img.rel_std_error[seen & np.isfinite(img.rel_std_error)]
    width, height = img.resolution
    print(f"illuminance image from {img.camera!r}: {width} x {height} px, {img.samples} samples per pixel")
    if seen.any():
        print(f"E on the diffuse surfaces seen ({100 * float(np.mean(seen)):.0f} % of the pixels): min "
              f"{float(e[seen].min()):.4g} lx, mean {float(e[seen].mean()):.4g} lx, max {float(e[seen].max()):.4g} lx; "
              f"relative 1 s.e. median {100 * float(np.median(rel)) if rel.size else 0:.2g} %, 90th percentile "
              f"{100 * float(np.percentile(rel, 90)) if rel.size else 0:.2g} % (target {100 * img.target_rel_error:.2g} %, "
              f"reached by {100 * img.share_on_target:.0f} % of the lit pixels)")
    else:
        print("no diffuse surface lit in view: every pixel reads 0 lx")
    for note in img.notes:
        print(note)
    result = img.to_dict()
    _io.deliver(args, result)
    for path in img.paths.values():
        print(f"wrote {path}")
    return result

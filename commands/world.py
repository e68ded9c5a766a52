"""`world`: the world's illuminance (lux), brightest direction, calibration and irradiance map."""

HELP = "illuminance from the world alone (lux), its brightest direction; --calibrate LUX --out FILE.blend, --irradiance-map EXR"
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--normal", type=float, nargs=3, default=(0.0, 0.0, 1.0), metavar=("X", "Y", "Z"),
                        help="surface normal the illuminance is for (default +Z: horizontal illuminance)")
    parser.add_argument("--calibrate", type=float, metavar="LUX",
                        help="set the Background strength so the world alone gives LUX; with --out, save the "
                             "calibrated scene there (the input .blend is never overwritten)")
    parser.add_argument("--out", metavar="FILE.blend",
                        help="where --calibrate saves the calibrated .blend (a new file, not the input)")
    parser.add_argument("--irradiance-map", metavar="EXR", help="write the world's irradiance environment map")
    parser.add_argument("--method", choices=("exact", "sh9"), default="exact",
                        help="irradiance map method: exact (closed form per pixel) or sh9 (9 spherical "
                             "harmonics, Ramamoorthi & Hanrahan 2001); default exact")
    parser.add_argument("--resolution", type=int, nargs=2, default=(64, 32), metavar=("W", "H"),
                        help="irradiance map size (default 64 32)")


def format_info(info):
    from ..readings import format_quantity

    bound = info.get("rel_error_bound") or 0.0  # a rendered world: its standard error; analytic: its bound
    lines = [f"world illuminance {format_quantity(info['illuminance'], 'lx', bound, info['exact'])} on normal "
             f"{info['normal']} ({info['method']})"]
    if info.get("brightest_direction") is not None:
        d = ", ".join(f"{v:.4f}" for v in info["brightest_direction"])
        lines.append(f"brightest direction ({d}): {info['brightest_luminance']:.6g} cd/m²")
    lines += [f"  {note}" for note in info["notes"]]
    return "\n".join(lines)


def run(args):
    import math

    import bpy

    from .. import api
    from ..errors import RadiometerError

    scene = bpy.context.scene
    normal = tuple(args.normal)
    if not all(math.isfinite(v) for v in normal) or not any(normal):
        raise RadiometerError(f"--normal must be a non-zero finite direction, got {normal}")
    result = {"scene": scene.name, "file": bpy.data.filepath}
    if args.out is not None:
        import os

        from . import _io

        if args.calibrate is None:
            raise RadiometerError("--out saves a calibrated scene: give --calibrate LUX too")
        if not args.out.lower().endswith(".blend"):
            raise RadiometerError(f"--out must name a .blend file, got {args.out!r}")
        if bpy.data.filepath and os.path.realpath(args.out) == os.path.realpath(bpy.data.filepath):
            raise RadiometerError(f"--out {args.out} is the input file: choose a new file (inputs are never "
                                  "overwritten)")
        _io.check_output_file(args.out, "--out file")
    if args.irradiance_map:
        from . import _io

        _io.check_output_file(args.irradiance_map, "--irradiance-map file")
    if args.calibrate is not None:
        if not (args.calibrate > 0 and math.isfinite(args.calibrate)):
            raise RadiometerError(f"--calibrate must be > 0 lux, got {args.calibrate}")
        cal = api.calibrate_world(scene, args.calibrate, normal)
        if args.out:
            api.save_copy(args.out, getattr(args, "interrupt", None))  # whole or not at all; the session keeps its path
            cal["notes"].append(f"saved the calibrated scene to {args.out}")
            cal["saved"] = args.out
        else:
            cal["notes"].append("calibrated in this run only; --out FILE.blend saves the calibrated scene")
        print("\n".join(cal["notes"]))
        result["calibration"] = cal
    info = dict(api.world_illuminance(scene, normal), normal=normal)
    print(format_info(info))
    result["world"] = info
    if args.irradiance_map:
        w, h = args.resolution
        out = api.irradiance_environment_map("world", args.irradiance_map, method=args.method, resolution=(w, h),
                                             scene=scene)
        print(f"irradiance map {out['path']} ({w}x{h}, {args.method}); SH9 coefficients (RGB):")
        for name, value in out["coefficients"].items():
            print(f"  {name:>5} " + " ".join(f"{v:12.6g}" for v in value))
        print("\n".join(f"  {note}" for note in out["notes"]))
        result["irradiance_map"] = out
    return result

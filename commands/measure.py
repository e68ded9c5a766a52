"""`measure`: measure every light meter in a .blend and print the readings (SI units)."""

HELP = "measure every light meter in the scene (lux, cd/m²) and print the readings"
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="quality preset (default: the scene's setting)")
    parser.add_argument("--method", choices=("auto", "analytic", "render"), default=None,
                        help="measurement method (default: the scene's setting)")


def format_table(results):
    lines = [f"{'meter':<22} {'reading':>14} {'unit':<6} {'± 1 s.e.':>9}  method"]
    for obj, r in results:
        if r.quantity == "luminance":
            value, unit = r.luminance, "cd/m²"
        else:
            value, unit = r.illuminance, "lx"
        err = "exact" if r.exact else f"{100 * r.rel_std_error:.2f} %"
        lines.append(f"{obj.name:<22} {value:>14.6g} {unit:<6} {err:>9}  {r.method}")
    return "\n".join(lines)


def run(args):
    import bpy

    from ..measure import meters

    scene = bpy.context.scene
    if args.method:
        scene.radiometer.method = args.method
    results = meters.measure_meters(scene=scene, quality=args.quality)
    print(format_table(results))
    return {"scene": scene.name, "file": bpy.data.filepath,
            "meters": [dict(name=obj.name, **r.to_dict()) for obj, r in results]}

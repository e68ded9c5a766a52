"""`measure`: measure every light meter in a .blend and print the readings (SI units)."""

HELP = "measure every light meter in the scene (lux, cd/m²) and print the readings"
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="quality preset (default: the scene's setting)")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default=None,
                        help="measurement method (default: the scene's setting)")
    parser.add_argument("--target", type=float, default=None, metavar="FRACTION",
                        help="relative standard error (1 sigma) every reading must reach, e.g. 0.01 "
                             "(default: the quality preset's target: preview 0.05, standard 0.01, reference 0.002)")


def format_value(value, digits=6):
    """A reading with ``digits`` significant digits; "n/a" for a missing or non-finite one."""
    import math

    if value is None or not math.isfinite(value):
        return "n/a"
    return f"{value:.{digits}g}"


def format_table(results):
    """One line per meter: the reading with the digits its error supports ("402 lx ±1.1 %", as the
    sidebar shows it), the target, the method, then EV100 and the light's CCT/Duv."""
    from ..readings import format_error, photographic_summary
    from ..readings import format_value as supported

    lines = [f"{'meter':<22} {'reading':>10} {'unit':<6} {'± 1 s.e.':>9} {'target':>7}  method    photographic"]
    for obj, r in results:
        if r.quantity == "luminance":
            value, unit = r.luminance, "cd/m²"
        else:
            value, unit = r.illuminance, "lx"
        se = r.rel_std_error
        err = format_error(se if se is not None else float("nan"), r.exact)
        target = getattr(r, "target_rel_error", None)
        asked = f"{100 * target:g} %" if target else "-"
        reading = supported(value, se if se is not None else 0.0, r.exact)
        lines.append(f"{obj.name:<22} {reading:>10} {unit:<6} {err:>9} {asked:>7}  {r.method:<9} "
                     f"{photographic_summary(r)}".rstrip())
    return "\n".join(lines)


def run(args):
    import bpy

    from ..measure import meters

    scene = bpy.context.scene
    if args.method:
        scene.radiometer.method = args.method
    if args.target is not None:
        from ..errors import RadiometerError

        if not 0 < args.target < 0.5:
            raise RadiometerError(f"--target must be a fraction in (0, 0.5), got {args.target}")
        scene.radiometer.target_rel_error = args.target
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = "measuring"
    results = meters.measure_meters(scene=scene, quality=args.quality, progress=progress,
                                    cancelled=getattr(args, "cancelled", None))
    if progress is not None:
        progress.clear()
    print(format_table(results))
    return {"scene": scene.name, "file": bpy.data.filepath,
            "meters": [dict(name=obj.name, **r.to_dict()) for obj, r in results]}

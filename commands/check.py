"""`check`: inverse-square and cosine-law checks for every light (or one) in a .blend."""

HELP = "check the inverse-square and cosine laws for each light (near-field limit, exponent, deviations)"
NEEDS_SCENE = True


def add_budget_arguments(parser):
    """--target / --time-budget, shared by check, grid and report."""
    parser.add_argument("--target", type=float, default=None, metavar="FRACTION",
                        help="relative standard error (1 sigma) every reading must reach, e.g. 0.01 "
                             "(default: the quality preset's target: preview 0.05, standard 0.01, reference 0.002)")
    parser.add_argument("--time-budget", type=float, default=None, metavar="S",
                        help="seconds per measurement: the best accuracy within it (with --target: whichever "
                             "comes first)")


def budget_kwargs(args):
    return {"target_rel_error": args.target, "time_budget_s": args.time_budget}


def add_arguments(parser):
    parser.add_argument("--light", metavar="NAME", help="check only this light (default: every light)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="standard")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default="auto")
    add_budget_arguments(parser)
    parser.add_argument("--plots", metavar="DIR", help="also write a PNG plot per check into DIR")


def run(args):
    import os

    import bpy

    from ..errors import RadiometerError
    from ..measure import analysis, report

    scene = bpy.context.scene
    lights = [analysis.light_object(args.light, scene)] if args.light else analysis.scene_lights_to_check(scene)
    if not lights:
        raise RadiometerError(f"scene {scene.name!r} has no lights to check")
    if args.plots:
        from ..plots import require_matplotlib

        require_matplotlib()  # asked for plots: say at once, before the checks, that they cannot be made
        os.makedirs(args.plots, exist_ok=True)
    out = {"scene": scene.name, "inverse_square": [], "cosine": [], "meters": [], "grids": [], "convergence": None}
    for light in lights:
        slug = report._slug(light.name)
        plot = (lambda kind: os.path.join(args.plots, f"{kind}_{slug}.png")) if args.plots else (lambda kind: None)
        try:
            r = analysis.check_inverse_square(light, scene=scene, method=args.method, quality=args.quality,
                                              plot=plot("inverse_square"), **budget_kwargs(args))
            out["inverse_square"].append(r.to_dict())
        except RadiometerError as exc:
            if args.light and light.data.type != "SUN":
                raise
            out["inverse_square"].append({"light": light.name, "kind": light.data.type, "error": str(exc)})
        r = analysis.check_cosine_law(light, scene=scene, method=args.method, quality=args.quality,
                                      plot=plot("cosine"), **budget_kwargs(args))
        out["cosine"].append(r.to_dict())
    print(report.summary_table(out))
    for r in out["inverse_square"] + out["cosine"]:
        for cause in r.get("causes", []):
            print(f"  {r['light']}: {cause}")
        if "error" in r:
            print(f"  {r['light']}: {r['error']}")
    return out

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

    from .. import outputs
    from ._io import deliver, write_json
    from ..errors import MeasurementCancelled, RadiometerError
    from .. import api
    from . import _io

    scene = bpy.context.scene
    lights = [api.light_object(args.light, scene=scene)] if args.light else api.lights_to_check(scene)
    if not lights:
        raise RadiometerError(f"scene {scene.name!r} has no lights to check")
    if args.plots:
        from ..plots import require_matplotlib

        require_matplotlib()  # asked for plots: say at once, before the checks, that they cannot be made
        _io.check_output_dir(args.plots, "--plots folder")
        # Every plot's target before the checks (a link or a folder by that name), and not the --json file.
        stems = outputs.Stems(sorted(ob.name for ob in lights))
        planned = [f"{kind}_{stems(ob.name)}.png" for ob in lights for kind in ("inverse_square", "cosine")]
        outputs.check_set(os.path.abspath(args.plots), planned, "--plots file")
        outputs.refuse_overlaps([("--json", getattr(args, "json", None))]
                                + [("a --plots file", os.path.join(args.plots, n)) for n in planned], [])
    watch = {"cancelled": getattr(args, "cancelled", None)}
    progress = getattr(args, "progress", None)
    out = {"scene": scene.name, "inverse_square": [], "cosine": [], "meters": [], "grids": [], "convergence": None}
    done = []  # (kind, light name, result object) for the plots written after the JSON
    for light in lights:
        if progress is not None:
            progress.label = f"laws {light.name}"
        try:
            r = api.check_inverse_square(light, scene=scene, method=args.method, quality=args.quality,
                                              progress=progress, **watch, **budget_kwargs(args))
            out["inverse_square"].append(r.to_dict())
            done.append(("inverse_square", light.name, r))
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            if args.light and light.data.type != "SUN":
                raise
            out["inverse_square"].append({"light": light.name, "kind": light.data.type, "error": str(exc)})
        r = api.check_cosine_law(light, scene=scene, method=args.method, quality=args.quality,
                                      progress=progress, **watch, **budget_kwargs(args))
        out["cosine"].append(r.to_dict())
        done.append(("cosine", light.name, r))
    if progress is not None:
        progress.clear()
    print(api.report_summary_table(out))
    for r in out["inverse_square"] + out["cosine"]:
        if r.get("departure"):
            print(f"  {r['light']}: as expected: {r['departure']}")
        for cause in r.get("causes", []):
            print(f"  {r['light']}: {cause}")
        if "error" in r:
            print(f"  {r['light']}: {r['error']}")
    deliver(args, out)  # the numbers are safe on disk before any plot is drawn
    if args.plots:
        by_light = {}
        for kind, name, r in done:
            stem = by_light.setdefault(name, stems(name))
            path = os.path.join(args.plots, f"{kind}_{stem}.png")
            api.write_law_plot(r, path)
            next(d for d in out[kind] if d.get("light") == name)["plot"] = path
            print(f"wrote {path}")
        if getattr(args, "json", None):
            write_json(args.json, out, getattr(args, "interrupt", None))  # again, with the plot paths
    return out

"""`brdf`: describe a parametric BRDF, its directional albedo and how faithfully Cycles renders it."""

import math

HELP = "evaluate a BRDF model: parameters, albedo at a few angles, fidelity of its Cycles mapping, plot"
NEEDS_SCENE = False

ALBEDO_ANGLES_DEG = (0.0, 30.0, 60.0, 75.0)


def add_arguments(parser):
    parser.add_argument("model", nargs="?", help="BRDF model name (--list shows them)")
    parser.add_argument("--list", action="store_true",
                        help="list the BRDF models with their parameters (default, range) and exit")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="parameter value; a colour is r,g,b (repeatable)")
    parser.add_argument("--method", choices=("nodes", "osl"), default="nodes",
                        help="Cycles realisation to report (default: nodes)")
    parser.add_argument("--plot", metavar="PNG", help="write the summary plot to this PNG file (a folder: "
                        "<folder>/brdf_<model>.png; no extension: .png is added)")


def parse_params(pairs):
    """['alpha=0.3', 'f0=0.9,0.6,0.3'] -> {'alpha': 0.3, 'f0': [0.9, 0.6, 0.3]}; RadiometerError if bad."""
    from ..errors import RadiometerError

    out = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        name = name.strip()
        if not sep or not name:
            raise RadiometerError(f"--param expects NAME=VALUE, got {pair!r}")
        try:
            values = [float(v) for v in text.split(",")]
        except ValueError:
            out[name] = text.strip()  # e.g. variant=cycles
            continue
        if len(values) not in (1, 3):
            raise RadiometerError(f"--param {name}: give one number or three (r,g,b), got {text!r}")
        out[name] = values[0] if len(values) == 1 else values
    return out


def list_models():
    """{name: {"summary", "parameters": [{name, default, min, max, kind, unit, description}]}} of every model."""
    from .. import brdf

    out = {}
    for name in brdf.names():
        d = brdf.describe(name)
        params = [{k: p[k] for k in ("name", "default", "min", "max", "kind", "unit", "description")}
                  for p in d["parameters"]]
        first = " ".join(d["doc"].split("\n\n")[0].split())  # first paragraph, one line
        out[name] = {"summary": first.split(". ")[0].rstrip(".:") + ".", "parameters": params}
    return out


def format_models(models):
    lines = []
    for name, m in models.items():
        lines.append(f"{name:<18} {m['summary']}")
        for p in m["parameters"]:
            default = "-" if p["default"] is None else p["default"]
            lines.append(f"    {p['name']:<10} default {default}, {p['min']:g}..{p['max']:g} ({p['kind']})")
    return "\n".join(lines)


def run(args):
    import numpy as np

    from .. import brdf
    from ..errors import RadiometerError

    if args.list:
        models = list_models()
        print(format_models(models))
        return {"models": models}
    if not args.model:
        raise RadiometerError("give a BRDF model name, or --list to see them: " + ", ".join(brdf.names()))
    from ..shading.realise import check_params, realise, resolve_params

    params = parse_params(args.param)
    plot_path = plot_file(args.plot, args.model) if args.plot else None
    kwargs = check_params(args.model, params)  # raises for unknown model / params / bad values
    resolved = resolve_params(args.model, params)
    albedo = {}
    for deg in ALBEDO_ANGLES_DEG:
        a = np.asarray(brdf.albedo(args.model, math.radians(deg), **kwargs), dtype=float)
        albedo[f"{deg:g}"] = a.tolist() if a.ndim else float(a)
    _, fid = realise(args.model, args.method, **params)
    result = {"model": args.model, "params": resolved, "albedo": albedo, "albedo_angles_unit": "deg",
              "fidelity": fid.to_dict()}
    print(f"model   {args.model}")
    for k, v in resolved.items():
        print(f"  {k:<10} {v}")
    print("directional albedo (theta_i in deg):")
    for k, v in albedo.items():
        print(f"  {k:>4}  {np.round(v, 4).tolist() if isinstance(v, list) else round(v, 4)}")
    print(f"Cycles ({args.method}): {fid.closure}")
    print(f"fidelity: {fid.summary()}  (rms_rel_diff {fid.rms_rel_diff:.2e}, albedo_diff {fid.albedo_diff:.2e})")
    if fid.notes:
        print(f"notes: {fid.notes}")
    from ._io import deliver

    deliver(args, result)  # the numbers are on disk before the plot is drawn
    if plot_path:
        from ..plots.brdf import write_summary

        result["plot"] = write_summary(args.model, plot_path, **kwargs)
        print(f"plot written to {plot_path}")
        if getattr(args, "json", None):
            from ._io import write_json

            write_json(args.json, result, getattr(args, "interrupt", None))  # again, with the plot path
    return result


def plot_file(path, model):
    """The PNG that ``--plot path`` names: a folder gets brdf_<model>.png, a name without extension .png."""
    import os

    from .. import outputs
    from . import _io

    if os.path.isdir(path) or path.endswith(os.sep) or (os.altsep and path.endswith(os.altsep)):
        path = os.path.join(_io.check_output_dir(path, "--plot folder"), f"brdf_{outputs.file_stem(model)}.png")
    elif not os.path.splitext(path)[1]:
        path += ".png"
    _io.check_output_file(path, "--plot file")
    return path

"""`demo`: build the demo room, save it, measure it and print a summary (files under --out);
`demo --daylight`: the daylit room (``demo/daylight.py``) instead."""

import os

HELP = ("build the built-in demo room, measure it and write a summary under --out (default out/); --daylight: "
        "the daylit room (a south window with a 6 mm pane, the sun in London)")
NEEDS_SCENE = False


def add_arguments(parser):
    parser.add_argument("--out", default="out", help="output folder (created if missing)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="accuracy preset (preview 5 %%, standard 1 %%, reference 0.2 %% 1-sigma); default: the "
                             "demo's own target, 2 %% 1-sigma, with the standard preset's bounces; with --daylight: "
                             "preview")
    parser.add_argument("--daylight", action="store_true",
                        help="the daylit room instead: a 4 x 4 x 3 m room with a south window and a 6 mm glass pane, "
                             "the sun where it stands in London, five meters (saves daylight_room.blend)")
    parser.add_argument("--open", action="store_true",
                        help="with --daylight: hide the glass pane in renders (an open window)")
    parser.add_argument("--time", default=None, metavar="YYYY-MM-DDTHH:MM",
                        help="with --daylight: local time in London (default 2026-03-20T12:00, the March equinox)")


def run(args):
    import bpy

    from .. import api
    from ..demo import scene as demo_scene
    from .measure import format_table

    from . import _io

    out = _io.check_output_dir(args.out, "--out folder")
    if args.daylight:
        return _run_daylight(args, out)
    if args.open or args.time:
        from ..errors import RadiometerError

        raise RadiometerError("--open and --time go with --daylight")
    progress = getattr(args, "progress", None)
    cancelled = getattr(args, "cancelled", None)
    interrupt = getattr(args, "interrupt", None)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    from ._io import ensure_registered

    ensure_registered()
    scene = demo_scene.build(bpy.context.scene)
    # Interreflection in a room is noisy (light bounces off the small sunlit floor patch): ask for
    # 95 % intervals within 2 % (about 1 % standard error) rather than a fixed sample count.
    # --quality given: its preset's target wins (the command line wins over stored settings).
    if args.quality is None:
        scene.radiometer.target_rel_error = 0.02
    else:
        scene.radiometer.quality = args.quality
    blend = os.path.join(out, "demo_room.blend")
    _save(blend, interrupt)
    print(f"Radiometer demo: {blend}")
    print("Closed room 4 x 4 x 3 m (one mesh), desk with meters on its top, ceiling panel 6 W (4100 lm), "
          "table lamp 1 W (683 lm, 2700 K).")
    print(f"Luminous efficacy {scene.radiometer.efficacy:g} lm/W (Blender/glTF convention).\n")
    if progress is not None:
        progress.label = "measuring the meters"
    results = api.measure_meters(scene=scene, quality=args.quality, progress=progress, cancelled=cancelled)
    if progress is not None:
        progress.clear()
    from .measure import format_settings, used_settings

    s = scene.radiometer
    print(format_settings(used_settings(args, (s.method, s.quality, s.target_rel_error))))
    print(format_table(results))
    # Direct light alone, from the closed forms, for comparison with the rendered totals.

    print("\nDirect light at the meters from closed forms (no interreflection):")
    direct = {}
    for obj, r in results:
        if r.quantity != "illuminance":
            continue
        rows = api.predict_illuminance(r.location, r.normal, scene=scene)
        total = sum(row["illuminance"] or 0.0 for row in rows)
        direct[obj.name] = rows
        parts = ", ".join(f"{row['light']} {row['illuminance']:.4g} lx" for row in rows if row["illuminance"] is not None)
        print(f"  {obj.name:<20} {total:10.4g} lx direct ({parts}); rendered total {r.illuminance:.4g} lx")
    _save(blend, interrupt)  # with the readings stored
    result = {"blend": blend, "meters": [dict(name=o.name, **r.to_dict()) for o, r in results], "direct": direct}
    from ._io import deliver, write_json

    write_json(os.path.join(out, "demo.json"), result, interrupt)
    deliver(args, result)
    print(f"\nWrote {os.path.join(out, 'demo.json')}")
    # The analysis report: law checks per light, the EN 12464-1 grid on the Work Plane, convergence.
    print("\nAnalysis report (law checks per light, work-plane grid, convergence):")
    rep = api.export_report(os.path.join(out, "report"), scene=scene, quality=args.quality,
                               convergence_samples=(4, 16, 64), progress=progress, cancelled=cancelled,
                               phase=None if progress is None else progress.step)
    if progress is not None:
        progress.clear()
    print(rep["summary"])
    print(f"\nWrote {rep['paths']['markdown']} ({rep['seconds']:.1f} s)")
    result["report"] = rep["paths"]
    if getattr(args, "json", None):
        write_json(args.json, result, interrupt)  # again, with the report's paths
    return result


def _save(path, interrupt):
    import contextlib

    import bpy

    from ..errors import RadiometerError

    with interrupt.critical() if interrupt is not None else contextlib.nullcontext():
        try:
            bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
        except RuntimeError as exc:
            raise RadiometerError(f"cannot save {path}: {str(exc).strip().splitlines()[-1]}") from None


def _run_daylight(args, out):
    import datetime as dt
    import sys

    from ..demo import daylight
    from ..errors import RadiometerError
    from ._io import deliver

    when = daylight.WHEN
    if args.time:
        try:
            t = dt.datetime.fromisoformat(args.time)
        except ValueError:
            raise RadiometerError(f"--time must be YYYY-MM-DDTHH:MM (local time in London), got {args.time!r}") from None
        when = (t.year, t.month, t.day, t.hour, t.minute)
    result = daylight.run(out, quality=args.quality or "preview", when=when, glass=not args.open,
                          stream=sys.stdout, interrupt=getattr(args, "interrupt", None))
    deliver(args, result)
    return result

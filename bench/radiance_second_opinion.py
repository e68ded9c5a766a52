"""Radiance's second opinion on any scene (issue 34): export it (``api.export_radiance``), run Radiance's rtrace as
a path tracer on every exported sensor file (tests/bpy/radiance_run.py), measure the same points with
Radiometer, and print how many combined standard errors apart they are.

    python bench/radiance_second_opinion.py scene.blend [--quality standard] [--samples 100000] [--df]

Illuminance under the scene's own world and lights (sky.rad + scene.rad); with ``--df`` also the daylight
factor under the CIE overcast sky (sky_overcast.rad, ground reflectance 0.2) against
``api.daylight_factor``. Points are the work planes' grids and the illuminance meters. What the export
could not map (README.txt's list) is printed first: a difference there is the export's, not the meter's.
"""

import argparse
import importlib.util
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def _radiance_run():
    path = os.path.join(HERE, os.pardir, "tests", "bpy", "radiance_run.py")
    spec = importlib.util.spec_from_file_location("radiance_run", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("blend")
    parser.add_argument("--quality", default="standard", choices=("preview", "standard", "reference"))
    parser.add_argument("--samples", type=int, default=100_000, help="rtrace repeats per sensor (default 100000)")
    parser.add_argument("--df", action="store_true", help="also the daylight factor under the CIE overcast sky")
    parser.add_argument("--out", help="export folder (default: a temporary one)")
    args = parser.parse_args(argv)

    import bpy
    import numpy as np

    import radiometer
    from radiometer import api

    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend), load_ui=False)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = bpy.context.scene
    scale = scene.unit_settings.scale_length
    run = _radiance_run()
    with tempfile.TemporaryDirectory(prefix="radiance-second-opinion-") as tmp:
        out = args.out or tmp
        result = api.export_radiance(out)
        for line in result["unmapped"]:
            print(f"not mapped: {line}")
        files = [g["file"] for g in result["summary"]["grids"]] + (["meters.pts"] if result["summary"]["meters"] else [])
        if not files:
            print("no work plane and no illuminance meter: nothing to compare")
            return 1
        worst = 0.0
        for name in files:
            pts = np.loadtxt(os.path.join(out, name), ndmin=2)
            checks = [("E lx", "sky.rad", lambda p, n: [(r.illuminance, r.rel_std_error) for r in
                                                        api.measure_illuminance(p, n, quality=args.quality)], 1.0)]
            if args.df:
                checks.append(("DF %", "sky_overcast.rad", lambda p, n: [(r.daylight_factor, r.rel_std_error) for r in
                                                                        api.daylight_factor(p, n, quality=args.quality)],
                               0.01))
            for label, sky, measure, to_unit in checks:
                ref, ref_rel = run.rtrace_lux(out, sky, name, args.samples)
                ours = measure(pts[:, :3] / scale, pts[:, 3:])
                print(f"\n{name}, {label}: Radiometer ({args.quality}) | Radiance ({args.samples} paths) | sigma apart")
                for k, ((value, rel), e, e_rel) in enumerate(zip(ours, ref * to_unit, ref_rel)):
                    se = math.hypot(rel * value, e_rel * e)
                    z = (value - e) / se if se > 0 else (0.0 if value == e else math.inf)
                    worst = max(worst, abs(z))
                    print(f"  {k:3d} {tuple(np.round(pts[k, :3], 3))}: {value:.5g} +- {100 * rel:.2f} % | "
                          f"{e:.5g} +- {100 * e_rel:.2f} % | {z:+.2f}")
        print(f"\nlargest difference: {worst:.2f} combined standard errors")
    return 0


if __name__ == "__main__":
    sys.exit(main())

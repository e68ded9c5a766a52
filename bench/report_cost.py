"""What a report of an office with N luminaires costs, part by part (issue 23 item 4).

The office of tests/bpy/office.py (6 x 4 x 3 m grey room), N IES luminaires (a 0.6 m square opening,
I = I0 cos gamma) on a grid under the ceiling, a Work Plane at 0.75 m and one desk meter; ``export_report``
at the given quality without the client's pictures (the law checks, the grid and the meters are what is
timed). Prints the seconds of each part and writes a Markdown row. Usage:
``.venv/bin/python bench/report_cost.py [--lights 8] [--quality preview] [--out DIR]``.
"""

import argparse
import math
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "bpy"))

import bpy  # noqa: E402

import office  # noqa: E402
from radiometer import api  # noqa: E402

IES = """IESNA:LM-63-2002
[LUMINAIRE] cosine panel 0.6 m
TILT=NONE
1 -1 1 19 1 1 2 0.6 0.6 0
1 1 30
{v}
0
{cd}
"""


def build(n, folder, kind="ies"):
    import radiometer

    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    office.build(scene, panels=False)
    v = [5.0 * k for k in range(19)]
    path = os.path.join(folder, "panel.ies")
    with open(path, "w") as f:
        f.write(IES.format(v=" ".join(f"{a:g}" for a in v), cd=" ".join(f"{2500 * math.cos(math.radians(a)):.4f}"
                                                                        for a in v)))
    cols = max(1, math.ceil(math.sqrt(n * 1.5)))
    rows = math.ceil(n / cols)
    k = 0
    for j in range(rows):
        for i in range(cols):
            if k == n:
                break
            x, y = -3 + 6 * (i + 0.5) / cols, -2 + 4 * (j + 0.5) / rows
            if kind == "ies":
                api.import_luminaire(path, scene=scene, location=(x, y, office.PANEL_Z), name=f"Luminaire {k + 1}")
            else:  # Blender's square area light of the same size (office.py's panels)
                data = bpy.data.lights.new(f"Panel {k + 1}", "AREA")
                data.shape, data.size, data.energy = "SQUARE", office.PANEL, office.PANEL_POWER
                obj = bpy.data.objects.new(f"Panel {k + 1}", data)
                obj.location = (x, y, office.PANEL_Z)
                scene.collection.objects.link(obj)
            k += 1
    mesh = bpy.data.meshes.new("Work Plane")
    mesh.from_pydata([(-2.5, -1.5, 0), (2.5, -1.5, 0), (2.5, 1.5, 0), (-2.5, 1.5, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("Work Plane", mesh)
    plane.location = (0, 0, 0.75)
    plane.hide_render = True
    scene.collection.objects.link(plane)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE", location=(0.3, 0.2, 0.75)) if hasattr(
        bpy.ops.radiometer, "add_meter") else None
    bpy.context.view_layer.update()
    return scene


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lights", type=int, default=8)
    ap.add_argument("--quality", default="preview")
    ap.add_argument("--out", default=None)
    ap.add_argument("--kind", choices=("ies", "area"), default="ies", help="IES luminaires or Blender area lights")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        scene = build(args.lights, tmp, args.kind)
        phases = []
        last = [time.perf_counter(), None]

        def phase(label):
            now = time.perf_counter()
            if last[1] is not None:
                phases.append((last[1], now - last[0]))
            last[:] = [now, label]

        started = time.perf_counter()
        rep = api.export_report(args.out or os.path.join(tmp, "report"), scene=scene, quality=args.quality,
                                   convergence=False, client=False, phase=phase)
        total = time.perf_counter() - started
        phase("end")
        # What the report's law checks cost before issue 23 item 4, in the same process: every light,
        # the full sweep (24 distances, 13 tilts) at the report's quality target, both plots.
        from radiometer.measure.analyses import analysis
        from radiometer.measure.blender import request as request_of

        started = time.perf_counter()
        cpu = time.process_time()
        for light in analysis.scene_lights_to_check(scene):
            analysis.check_inverse_square(light, request=request_of.build(scene, quality=args.quality),
                                          plot=os.path.join(tmp, "i.png"))
            analysis.check_cosine_law(light, request=request_of.build(scene, quality=args.quality),
                                      plot=os.path.join(tmp, "c.png"))
        before = time.perf_counter() - started
        before_cpu = time.process_time() - cpu
    laws = sum(s for label, s in phases if label.startswith("laws"))
    print(f"{args.lights} {args.kind} luminaires, {args.quality}: report {total:.1f} s, its law checks {laws:.1f} s "
          f"({100 * laws / total:.0f} %); the former law checks (every light, full sweeps) {before:.1f} s "
          f"(CPU {before_cpu:.1f} s): {before / laws:.1f}x; load average {os.getloadavg()[0]:.1f}")
    for label, s in phases:
        print(f"  {label:<20} {s:7.2f} s")
    print(rep["summary"])
    return total, laws, before


if __name__ == "__main__":
    main()

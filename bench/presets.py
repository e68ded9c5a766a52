"""Measure the quality presets: seconds per reading and error on the demo room and a direct-lit scene.

Run once: ``.venv/bin/python -m radiometer.bench.presets`` (or ``python bench/presets.py``); writes
``bench/presets.md`` and ``bench/presets.json``. Errors are RMS relative errors over the meters and
over ``SEEDS`` independent runs, against
* the demo room: a high-sample render (``REFERENCE`` samples per texel, 16 bounces), whose own
  error is reported and is small next to every preset's;
* a direct-lit 1 x 1 m square area light 1.5 m above four meters, black world, no surfaces: the
  exact closed form (Lambert polygon) as reference.
Seconds: wall time of one ``measure_illuminance`` call for the four meters in one batch.
"""

import json
import math
import os
import sys
import time

import numpy as np

SEEDS = 5
REFERENCE = {"samples": 1024, "texels": 8, "bakes": 16, "bounces": 128}
HERE = os.path.dirname(os.path.abspath(__file__))


def _demo_points(scene):
    import bpy

    bpy.context.view_layer.update()  # matrix_world of objects created by the builder
    objs = [ob for ob in scene.objects if ob.radiometer_meter.is_meter and ob.radiometer_meter.kind == "ILLUMINANCE"]
    pts = np.array([np.array(ob.matrix_world.translation) for ob in objs])
    nrm = np.array([np.array(ob.matrix_world.to_3x3().col[2]) for ob in objs])
    return [ob.name for ob in objs], pts, nrm


def _run_presets(scene, names, pts, nrm, reference, weights):
    from radiometer import quality
    from radiometer.measure import meter

    rows = []
    for name in quality.PRESETS:
        values, ses, seconds = [], [], []
        for seed in range(SEEDS):
            t0 = time.perf_counter()
            rs = meter.measure_illuminance(pts, nrm, scene=scene, method="render", quality=name, seed=1000 * seed + 1,
                                           exclude=set(names))
            seconds.append(time.perf_counter() - t0)
            values.append([r.irradiance for r in rs])
            ses.append([r.rel_std_error for r in rs])
        values, ses = np.array(values), np.array(ses)
        rel = values / reference[None, :] - 1
        p = quality.PRESETS[name]
        rows.append({
            "preset": name, "samples_per_texel": p["samples"], "texels": p["texels"] ** 2, "bakes": p["bakes"],
            "bounces": p["bounces"], "samples_per_reading": p["samples"] * p["texels"] ** 2 * p["bakes"],
            "seconds_per_batch": float(np.median(seconds)), "meters_per_batch": len(pts),
            "rms_rel_error": float(np.sqrt(np.mean(rel**2))),
            "rms_rel_error_per_meter": {n: float(np.sqrt(np.mean(rel[:, k] ** 2))) for k, n in enumerate(names)},
            "mean_stated_rel_se": float(np.mean(ses)),
            "max_stated_rel_se": float(np.max(ses)),
            "mean_bias": float(np.mean(rel)),
        })
        print(rows[-1]["preset"], f"{rows[-1]['seconds_per_batch']:.3f} s", f"RMS {100 * rows[-1]['rms_rel_error']:.3g} %",
              f"stated {100 * rows[-1]['mean_stated_rel_se']:.3g} %", flush=True)
    return rows


def main():
    import bpy

    import radiometer
    from radiometer.compat import ensure_node_tree
    from radiometer.demo import scene as demo_scene
    from radiometer.measure import meter

    out = {"machine": f"{os.cpu_count()} CPU cores, Cycles CPU", "seeds": SEEDS, "scenes": {}}
    # 1. The demo room.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = demo_scene.build(bpy.context.scene)
    names, pts, nrm = _demo_points(scene)
    _space, weights, _eff = meter.scene_photometry(scene)
    view_layer = bpy.context.view_layer
    t0 = time.perf_counter()
    est, _info, _rec = meter.render_irradiance(scene, view_layer, pts, nrm, REFERENCE, exclude=set(names), seed=77)
    ref_seconds = time.perf_counter() - t0
    scalar = est @ weights
    reference = scalar.mean(axis=0)
    ref_se = scalar.std(axis=0, ddof=1) / math.sqrt(scalar.shape[0]) / reference
    print("demo reference", reference, ref_se, f"{ref_seconds:.1f} s", flush=True)
    rows = _run_presets(scene, names, pts, nrm, reference, weights)
    out["scenes"]["demo room"] = {
        "meters": names, "reference": f"render {REFERENCE['samples']} samples/texel x {REFERENCE['texels'] ** 2} "
                                      f"texels x {REFERENCE['bakes']} bakes, {REFERENCE['bounces']} bounces",
        "reference_irradiance_W_m2": reference.tolist(), "reference_rel_se": ref_se.tolist(),
        "reference_seconds": ref_seconds, "presets": rows}
    # 2. Direct light from a square area light, exact reference.
    radiometer.unregister()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    data = bpy.data.lights.new("panel", "AREA")
    data.shape, data.size, data.energy = "SQUARE", 1.0, 100.0
    obj = bpy.data.objects.new("panel", data)
    obj.location = (0.0, 0.0, 1.5)
    scene.collection.objects.link(obj)
    pts = np.array([[0, 0, 0], [0.5, 0, 0], [1.0, 0.5, 0], [-1.5, -1.0, 0]], float)
    nrm = np.tile([0, 0, 1.0], (4, 1))
    exact = np.array([r.irradiance for r in meter.measure_illuminance(pts, nrm, scene=scene, method="analytic")])
    rows = _run_presets(scene, [], pts, nrm, exact, weights)
    out["scenes"]["direct area light"] = {
        "meters": [str(p) for p in pts.tolist()], "reference": "closed form (Lambert polygon), exact",
        "reference_irradiance_W_m2": exact.tolist(), "presets": rows}
    with open(os.path.join(HERE, "presets.json"), "w", encoding="utf-8") as f:
        json.dump(out, f, indent=2)
    with open(os.path.join(HERE, "presets.md"), "w", encoding="utf-8") as f:
        f.write(markdown(out))
    print(markdown(out))


def markdown(data):
    lines = ["# Quality presets, measured\n",
             f"Written by `bench/presets.py` ({data['machine']}; {data['seeds']} independent seeds per preset). "
             "Error = RMS relative error of the readings against the reference, over meters and seeds; "
             "stated s.e. = the mean relative standard error the readings report; seconds = one batch of all "
             "meters (one bake).\n"]
    for name, s in data["scenes"].items():
        lines.append(f"## {name}\n\nReference: {s['reference']}" + (
            f" (its own relative s.e. ≤ {100 * max(s['reference_rel_se']):.2g} %, {s['reference_seconds']:.0f} s)"
            if "reference_rel_se" in s else "") + ".\n")
        lines.append("| preset | samples/reading | bounces | seconds per batch | meters | RMS error | stated s.e. "
                     "(mean / max) | mean bias |\n|---|---:|---:|---:|---:|---:|---:|---:|")
        for r in s["presets"]:
            lines.append(f"| {r['preset']} | {r['samples_per_reading']} | {r['bounces']} | {r['seconds_per_batch']:.3f} | "
                         f"{r['meters_per_batch']} | {100 * r['rms_rel_error']:.3g} % | "
                         f"{100 * r['mean_stated_rel_se']:.3g} % / {100 * r['max_stated_rel_se']:.3g} % | "
                         f"{100 * r['mean_bias']:+.2g} % |")
        lines.append("")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.exit(main())

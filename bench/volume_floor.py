"""Issue 18 (F2 of bench/qa_glass_fog.md): coverage of the stated error under world fog
(``glass_fog_unseen_scenes.fog_floor``: 0.1/m over a grey floor, a spot and an area light, three meters)
against the QA's patch-render references (tests/bpy/glass_fog_unseen_references.json), with a candidate
floor of samples for meters with a medium above their horizon (patched in here over ``sample_floors.highlight_floor``;
measured and not kept: bench/qa_glass_fog.md F2).

    .venv/bin/python bench/volume_floor.py FLOOR [--seeds 40] [--quality preview]

FLOOR 0 is the code without the floor. Appends a row per meter to bench/volume_floor.json.
"""

import json
import math
import pathlib
import sys
import time

import bpy  # noqa: F401  (Blender as a module)

ROOT = pathlib.Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests" / "bpy"
OUT = ROOT / "bench" / "volume_floor.json"


sys.path.insert(0, str(ROOT / "bench"))
from scenes import load_test_module as _load  # noqa: E402


def main(floor, seeds, quality):
    import numpy as np

    import radiometer
    from radiometer import api
    from radiometer.measure.meter import sample_floors
    from radiometer.radiometry.scene import scene_model

    highlight_floor = sample_floors.highlight_floor

    def with_volume_floor(model, points_m, normals):
        # the candidate: FLOOR samples for every meter with a medium above its horizon, on top of the
        # highlight floor (meter._render_part passes the floor on to the stopping rule)
        base, names = highlight_floor(model, points_m, normals)
        fog = np.array([floor if scene_model.volume_above(model, p, n, 1e-6) else 0 for p, n in zip(points_m, normals)])
        if not fog.any():
            return base, names
        return (fog if base is None else np.maximum(base, fog)), names + ["a medium (candidate volume floor)"]

    if floor:
        sample_floors.highlight_floor = with_volume_floor
    u = _load("glass_fog_unseen_scenes")
    stored = json.loads((TESTS / "glass_fog_unseen_references.json").read_text())["values"]
    rows = json.loads(OUT.read_text()) if OUT.exists() else []
    scene, cases = u.fog_floor()
    radiometer.register()
    try:
        for label, point, normal in cases:
            e = stored[f"fog_floor/{label}"]
            ref_lux, ref_se = u.lux(e["E_rgb"]), e["rel_std_error"]
            zs, errs, samples, t0 = [], [], [], time.perf_counter()
            for seed in range(seeds):
                r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality=quality, seed=seed)
                err = r.illuminance / ref_lux - 1.0
                errs.append(err)
                zs.append(err / math.hypot(r.rel_std_error, ref_se))
                samples.append(int(r.samples))
            row = {"floor": floor, "quality": quality, "volume_bounces": (r.render_settings or {}).get("volume_bounces"),
                   "sampling": (r.render_settings or {}).get("sampling"), "meter": label, "seeds": seeds, "ref_lux": ref_lux,
                   "ref_se": ref_se, "within_1.96": sum(abs(z) <= 1.96 for z in zs),
                   "within_3": sum(abs(z) <= 3 for z in zs), "mean_z": sum(zs) / seeds,
                   "worst_z": max(zs, key=abs), "mean_err": sum(errs) / seeds,
                   "sd_err": (sum((x - sum(errs) / seeds) ** 2 for x in errs) / (seeds - 1)) ** 0.5,
                   "samples_median": sorted(samples)[seeds // 2], "seconds": round(time.perf_counter() - t0, 1)}
            print(json.dumps(row), flush=True)
            rows.append(row)
            OUT.write_text("[\n" + ",\n".join(json.dumps(x) for x in rows) + "\n]\n")
    finally:
        radiometer.unregister()


if __name__ == "__main__":
    from scenes import pop_option

    args = sys.argv[1:]
    seeds, quality = pop_option(args, "--seeds", 40, int), pop_option(args, "--quality", "preview")
    main(int(args[0]), seeds, quality)

"""Issue 18 (F2 of bench/qa_glass_fog.md): how the volume bounce limit truncates the light of a medium
that does not absorb, and what a higher limit costs. ``glass_fog_unseen_scenes.fog_floor`` (a world
Volume Scatter 0.08/m over a grey floor, a spot and an area light, three meters) read with
``method="render"`` at a fixed sample count, the same seeds for every limit, against the QA's patch
renders (tests/bpy/glass_fog_unseen_references.json: Cycles with 1024 bounces of every kind).

    .venv/bin/python bench/volume_bounces.py [LIMIT ...] [--seeds 10] [--samples 16384]

LIMIT is the volume bounce limit (``quality="preview"``: 16 bounces of every other kind). Writes
bench/volume_bounces.json and bench/volume_bounces.md.
"""

import json
import math
import pathlib
import sys
import time

import bpy  # noqa: F401  (Blender as a module)

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "bench" / "volume_bounces"

sys.path.insert(0, str(ROOT / "bench"))
from scenes import load_test_module as _load  # noqa: E402


def main(limits, seeds, samples):
    import numpy as np

    import radiometer
    from radiometer import api, quality
    from radiometer.measure.render import render_settings

    preview_bounces = quality.PRESETS["preview"]["bounces"]
    u = _load("glass_fog_unseen_scenes")
    stored = json.loads((ROOT / "tests" / "bpy" / "glass_fog_unseen_references.json").read_text())["values"]
    scene, cases = u.fog_floor()
    rows = []
    radiometer.register()
    factor = render_settings.VOLUME_BOUNCE_FACTOR
    try:
        for limit in limits:
            render_settings.VOLUME_BOUNCE_FACTOR = limit / preview_bounces
            for label, point, normal in cases:
                e = stored[f"fog_floor/{label}"]
                ref_lux, ref_se = u.lux(e["E_rgb"]), e["rel_std_error"]
                errs, stated, t0 = [], [], time.perf_counter()
                for seed in range(seeds):
                    r = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview",
                                                samples=samples, seed=100 + seed)
                    errs.append(r.illuminance / ref_lux - 1.0)
                    stated.append(r.rel_std_error)
                errs, stated = np.array(errs), np.array(stated)
                z = errs / np.hypot(stated, ref_se)
                row = {"volume_bounces": limit, "meter": label, "seeds": seeds, "samples": samples,
                       "ref_lux": ref_lux, "ref_se": ref_se, "mean_err": float(errs.mean()),
                       "se_mean": float(errs.std(ddof=1) / math.sqrt(seeds)), "sd_err": float(errs.std(ddof=1)),
                       "stated_mean": float(stated.mean()), "within_1.96": int(np.sum(abs(z) <= 1.96)),
                       "seconds_per_reading": round((time.perf_counter() - t0) / seeds, 2)}
                print(json.dumps(row), flush=True)
                rows.append(row)
    finally:
        render_settings.VOLUME_BOUNCE_FACTOR = factor
        radiometer.unregister()
    OUT.with_suffix(".json").write_text("[\n" + ",\n".join(json.dumps(x) for x in rows) + "\n]\n")
    lines = ["# Volume bounce limit in a medium that does not absorb (issue 18, F2)", "",
             f"`bench/volume_bounces.py`: `fog_floor`, `method=\"render\"`, {samples} samples, seeds 100…{99 + seeds} "
             "(the same for every limit), against the QA's 1024-bounce patch renders (reference s.e. "
             "0.08 % each, common to a column). Mean error ± its standard error over the seeds.", "",
             "| volume bounces | meter | mean error | sd of error | stated (mean) | within 1.96 | s per reading |",
             "|---:|---|---:|---:|---:|---:|---:|"]
    for x in rows:
        lines.append(f"| {x['volume_bounces']} | {x['meter']} | {100 * x['mean_err']:+.3f} % ± {100 * x['se_mean']:.3f} | "
                     f"{100 * x['sd_err']:.3f} % | {100 * x['stated_mean']:.3f} % | {x['within_1.96']}/{x['seeds']} | "
                     f"{x['seconds_per_reading']:.2f} |")
    OUT.with_suffix(".md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    from scenes import pop_option

    args = sys.argv[1:]
    seeds, samples = pop_option(args, "--seeds", 10, int), pop_option(args, "--samples", 16384, int)
    main([int(a) for a in args] or [16, 32, 64, 128, 256, 512, 1024], seeds, samples)

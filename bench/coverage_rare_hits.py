"""Issue 32's rare-hit acceptance table: mean z within +-0.3 and at least 90 % coverage of the 95 %
intervals over at least 50 seeds, on the slit-sky DF point, the fin scene, the glossy highlight and the
metal floor in a spot's beam, at preview and standard, with the product's sampler and stopping rule.

    .venv/bin/python bench/coverage_rare_hits.py refs                  # the spot scene's patch render
    .venv/bin/python bench/coverage_rare_hits.py run [--scenes ...] [--quality preview standard]
        [--seeds 50]

Scenes and references: ``tests/bpy/rare_hit_scenes.py`` (slit sky: a Gauss-Legendre integral of the
CIE overcast sky over the visible window; glossy highlight and spot: patch renders by
``tests/bpy/reference.py``) and ``tests/bpy/fin_scene.py`` (exact: Lambert's contour formula).
z = (reading - reference) / hypot(stated s.e., reference s.e.). Writes bench/coverage_rare_hits.{md,json}
after every row.
"""

import argparse
import importlib.util
import json
import math
import pathlib
import re
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "bench" / "coverage_rare_hits.json"
COST = ROOT / "bench" / "coverage_rare_hits_cost.json"  # what rotating the table costs (``cost``)
MEAN_Z_LIMIT = 0.3
COVERAGE_LIMIT = 0.90


def _load(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "tests" / "bpy" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class Fin:
    """tests/bpy/fin_scene.py's 97 %-hidden meter, read with the absolute floor off (as
    bench/coverage_rare_paths_fin_stopping.md: the preset's 2 / 0.5 lx floor would loosen a 20 lx reading's
    target to 10 / 2.5 %)."""

    name = "fin"
    UNIT = "lx"

    def __init__(self):
        self.fin = _load("fin_scene")
        self.METERS = {"97 % hidden": (self.fin.METERS["97 % hidden"], self.fin.NORMAL)}
        self.description = [
            "A meter lit only by a 2 x 2 m sunlit Lambertian patch, 96.9 % of whose light a black fin hides",
            "(tests/bpy/fin_scene.py); read with the absolute floor off. Reference: exact (Lambert's contour",
            "formula for the visible rectangle x the patch's radiance)."]

    def build(self):
        import bpy

        bpy.ops.wm.read_factory_settings(use_empty=True)
        return self.fin.build(bpy.context.scene)

    def reference(self, label):
        ref, hidden = self.fin.reference_lux(label)
        return ref, 0.0, hidden

    def measure(self, api, scene, point, normal, quality, seed):
        t0 = time.perf_counter()
        r = api.measure_illuminance(point, normal, scene=scene, quality=quality, seed=seed, target_abs_error=0.0)
        return r.illuminance, r.rel_std_error, r.samples, r.exact, time.perf_counter() - t0


def _scenes():
    hits = _load("rare_hit_scenes")
    return {"slit sky": hits.SlitSky(), "fin": Fin(), "glossy highlight": hits.GlossyWall(),
            "spot metal": hits.SpotMetal()}


def _data():
    return json.loads(OUT.read_text()) if OUT.exists() else {"references": {}, "rows": []}


def _samples(samples, notes=()):
    if samples is not None:
        return float(np.mean(samples))
    found = [int(m.group(1)) for n in notes for m in [re.search(r"samples per meter (\d+)", n)] if m]
    return float(found[0]) if found else float("nan")


def refs():
    """The spot scene's patch render (tests/bpy/reference.py), 0.1 % target, seed 7."""
    reference = _load("reference")
    data = _data()
    spot = _scenes()["spot metal"]
    scene = spot.build()
    [(label, (point, normal))] = spot.METERS.items()
    at = reference.lift_off_surface(scene, point, normal)
    e_rgb, se, info = reference.reference_irradiance(scene, at, normal, target_rel_error=1e-3, max_seconds=480.0,
                                                     seed=7)
    data["references"]["spot metal"] = {"lux": spot.u.lux(e_rgb), "rel_std_error": se,
                                        "samples": info.get("samples"), "seconds": round(info["seconds"], 1)}
    print(data["references"]["spot metal"], flush=True)
    from radiometer.outputs import write_text

    write_text(OUT, json.dumps(data, indent=1) + "\n")


def cost(api, quality, seeds):
    """Issue 32: what rotating the table costs, in one run. The fin scene's 97 %-hidden meter (floor off)
    read with the rotated table (the product's) and the fixed table (as before), alternately on the same
    seeds; samples and this process's CPU seconds (Cycles' threads included: wall time on the shared
    machine depends on the other jobs)."""
    import resource

    sys.path.insert(0, str(ROOT / "bench"))
    from coverage_rare_paths_fin import _with_pattern

    fin = Fin()
    scene = fin.build()
    import radiometer

    radiometer.register()
    point, normal = fin.METERS["97 % hidden"]
    got = {"rotated": [], "tabulated": []}
    try:
        for seed in range(seeds):
            for pattern in got:
                with _with_pattern(pattern):
                    use = resource.getrusage(resource.RUSAGE_SELF)
                    value, rel, n, _exact, sec = fin.measure(api, scene, point, normal, quality, 1000 * seed + 1)
                    after = resource.getrusage(resource.RUSAGE_SELF)
                cpu = after.ru_utime + after.ru_stime - use.ru_utime - use.ru_stime
                got[pattern].append({"samples": float(np.mean(n)), "cpu_s": cpu, "wall_s": sec, "rel": rel})
                print(pattern, quality, seed, n, round(cpu, 2), round(sec, 2), flush=True)
    finally:
        radiometer.unregister()
    out = {p: {k: float(np.mean([g[k] for g in rows])) for k in ("samples", "cpu_s", "wall_s", "rel")}
           for p, rows in got.items()}
    out["seeds"], out["quality"] = seeds, quality
    return out


def run_row(api, scene_obj, scene, label, quality, seeds, partial=None):
    """One row over ``seeds`` seeds; ``partial(row)`` every 10 seeds (a long run keeps what it has)."""
    point, normal = scene_obj.METERS[label]
    ref, ref_se, share = scene_obj.reference(label)
    z, stated, errors, seconds, samples = [], [], [], [], []
    for seed in range(seeds):
        if partial is not None and seed and seed % 10 == 0:
            partial(_row(scene_obj, label, quality, ref, ref_se, share, z, stated, errors, samples, seconds))
        value, rel, n, exact, sec = scene_obj.measure(api, scene, point, normal, quality, 1000 * seed + 1)
        se = math.hypot(rel * value, ref_se * ref) if math.isfinite(rel) else math.inf
        if exact:  # a proof, not a statistic: held to 1e-4
            z.append(0.0 if abs(value / ref - 1.0) <= 1e-4 else math.inf)
        else:
            z.append((value - ref) / se if se > 0 else math.inf)
        stated.append(rel)
        errors.append(value / ref - 1.0)
        samples.append(n if n is not None else float("nan"))
        seconds.append(sec)
        print(scene_obj.name, label, quality, seed, value, rel, z[-1], n, round(sec, 2), flush=True)
    return _row(scene_obj, label, quality, ref, ref_se, share, z, stated, errors, samples, seconds)


def _row(scene_obj, label, quality, ref, ref_se, share, z, stated, errors, samples, seconds):
    seeds = len(z)
    z = np.array(z)
    mean_z, mean_z_se, coverage = float(np.mean(z)), float(np.std(z) / math.sqrt(len(z))), float(np.mean(np.abs(z) < 1.96))
    return {"scene": scene_obj.name, "meter": label, "quality": quality, "seeds": seeds, "unit": scene_obj.UNIT,
            "reference": ref, "reference_rel_se": ref_se, "share": share,
            "mean_z": mean_z, "mean_z_se": mean_z_se, "coverage": coverage, "sd_z": float(np.std(z)),
            "within_3se": float(np.mean(np.abs(z) < 3)), "mean_error": float(np.mean(errors)),
            "worst_error": float(errors[int(np.argmax(np.abs(errors)))]),
            "stated_mean": float(np.mean([s for s in stated if math.isfinite(s)] or [math.inf])),
            "unknown_stated": int(sum(not math.isfinite(s) for s in stated)),
            "mean_samples": float(np.nanmean(samples)) if np.isfinite(samples).any() else None,
            "median_seconds": float(np.median(seconds)),
            "met": bool(abs(mean_z) <= MEAN_Z_LIMIT and coverage >= COVERAGE_LIMIT and seeds >= 50)}


#: What this run changed and found (2026-12-06), said above the table.
RUN_NOTES = [
    "**Shipped configuration, every row 50 seeds.** The whole table was re-run as the product now samples: each "
    "texel's table rotated, and the fixed table's floor planned and stated for rare-path meters "
    "(`measure/render/adaptive.py`). The rows measured earlier without that floor (fin and spot at standard "
    "then took 4-813 s a reading and stopped at 16 and 4 seeds) are replaced: a reading now takes seconds.",
    "**The spot's reference was biased, not the meter.** Its patch render (`tests/bpy/reference.py`) used "
    "Cycles' default scrambling distance 1, with which every pixel draws one of the Sobol table's fixed "
    "patterns: the mean over pixels converges to those patterns' mean, not to the integral. It read "
    "657.9 lx +- 0.1 % for seed 7 and 657.8 lx +- 0.1 % for seed 11 (the bias does not move with the seed); "
    "with each pixel's table rotated by its own uniform shift (what the harness now does) 653.4 lx +- 0.1 % "
    "(seed 11) and 653.0 lx +- 0.1 % (seed 7, the reference below); with the BLUE_NOISE pattern, a different "
    "sampler (Sobol-Burley), 653.0 lx +- 0.1 %. Against the old reference the standard row read mean z "
    "-1.69 +- 0.12 (50 % coverage), and -1.82 +- 0.20 with the staged stopping rule: the same 0.8 % by both "
    "rules, which is what showed it was no stopping bias.",
    "The glossy highlight's reference (`tests/bpy/glass_fog_unseen_references.json`) was rendered with "
    "distance 1 too: re-rendered rotated it reads 0.33 % higher (E 7.0057 against 6.9829 W/m² per channel, "
    "both +- 0.1 %), and the glossy rows moved from +0.27 / +0.29 to +0.12 / -0.12 (preview / standard). The "
    "other stored patch references of that file and of glass_fog_references.json and reference_values.json "
    "are not re-rendered (those with no 'sampler' key).",
]


def markdown(data, scenes):
    lines = ["# Rare-hit acceptance table (issue 32)", "",
             "Generated by `bench/coverage_rare_hits.py run` with the product's sampler (Tabulated Sobol, each "
             "texel's table rotated by its own uniform shift: `measure/render/render_settings.py`) and stopping "
             "rule (sequential rounds, `radiometry/sampling/allocation.py`), the presets' targets (preview 5 %, "
             "standard 1 %) and absolute floors (none for the fin meter). Acceptance: |mean z| <= "
             f"{MEAN_Z_LIMIT} and coverage of the 95 % intervals >= {100 * COVERAGE_LIMIT:.0f} % over >= 50 seeds. "
             "z = (reading - reference) / hypot(stated s.e., reference s.e.); mean z ± its standard error "
             "(sd(z) / √seeds); seeds 1, 1001, 2001, ...; s per reading: median wall time on the shared, "
             "loaded 2-core machine.", ""]
    for key, obj in scenes.items():
        lines += [f"- **{obj.name}**: " + " ".join(obj.description)]
    ref = data["references"].get("spot metal")
    if ref:
        lines += [f"- spot reference: {ref['lux']:.2f} lx ± {100 * ref['rel_std_error']:.3f} % "
                  f"({ref['samples']} samples, {ref['seconds']} s)."]
    costs = json.loads(COST.read_text()) if COST.exists() else {}
    if costs:
        lines += ["", "What rotating the table costs (`coverage_rare_hits.py cost`: the fin scene's 97 %-hidden meter, "
                  "floor off, rotated and fixed table alternately on the same seeds in one process; CPU seconds of "
                  "the process, Cycles' threads included):", "",
                  "| quality | seeds | samples rotated / fixed | CPU s rotated / fixed | ratio samples | ratio CPU | "
                  "stated rotated / fixed |", "|---|---:|---:|---:|---:|---:|---:|"]
        for quality, c in costs.items():
            a, b = c["rotated"], c["tabulated"]
            lines.append(f"| {quality} | {c['seeds']} | {a['samples']:.0f} / {b['samples']:.0f} | {a['cpu_s']:.2f} / "
                         f"{b['cpu_s']:.2f} | {a['samples'] / b['samples']:.2f} | {a['cpu_s'] / b['cpu_s']:.2f} | "
                         f"{100 * a['rel']:.2f} % / {100 * b['rel']:.2f} % |")
    lines += [""] + [f"- {note}" for note in RUN_NOTES]
    lines += ["", "| scene | quality | rule | seeds | reference | mean z | coverage of 95 % | within 3 s.e. | sd(z) | "
              "mean error | worst error | stated (mean) | samples (mean) | s per reading | acceptance |",
              "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    order = list(scenes)
    for r in sorted(data["rows"], key=lambda r: (order.index(r["key"]) if r["key"] in order else 99, r["quality"],
                                                    r.get("rule", "sequential") != "sequential")):
        ref_txt = f"{r['reference']:.4g} {r['unit']}" + (f" ± {100 * r['reference_rel_se']:.2f} %"
                                                            if r["reference_rel_se"] else " (exact)")
        samples = "—" if r["mean_samples"] is None else f"{r['mean_samples']:.0f}"
        lines.append(f"| {r['scene']} | {r['quality']} | {r.get('rule', 'sequential')} | {r['seeds']} | {ref_txt} | {r['mean_z']:+.2f} ± "
                     f"{r['mean_z_se']:.2f} | {100 * r['coverage']:.0f} % | {100 * r['within_3se']:.0f} % | "
                     f"{r['sd_z']:.2f} | {100 * r['mean_error']:+.2f} % | {100 * r['worst_error']:+.2f} % | "
                     f"{100 * r['stated_mean']:.2f} % | {samples} | {r['median_seconds']:.2f} | "
                     f"{'met' if r['met'] else ('**NOT met**' if r['seeds'] >= 50 else 'unfinished')} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=["refs", "run", "table", "cost"])
    parser.add_argument("--scenes", nargs="+", default=["slit sky", "fin", "glossy highlight", "spot metal"])
    parser.add_argument("--quality", nargs="+", default=["preview", "standard"])
    parser.add_argument("--seeds", type=int, default=50)
    parser.add_argument("--rule", default="sequential", choices=["sequential", "staged"],
                        help="stopping rule: the product's (sequential) or staged (an experiment, issue 32)")
    parser.add_argument("--store", default=None, help="json to write the rows to (default bench/coverage_rare_hits.json; "
                        "its .md beside it); the spot reference is read from the default's")
    args = parser.parse_args(argv)
    global OUT
    spot_ref = _data()["references"].get("spot metal")
    if args.store:
        OUT = pathlib.Path(args.store)
    if args.what == "refs":
        return refs()
    import radiometer
    from radiometer import api
    from radiometer.outputs import write_text

    scenes = _scenes()
    data = _data()
    if spot_ref:
        scenes["spot metal"].stored = (spot_ref["lux"], spot_ref["rel_std_error"])
    if args.what == "cost":
        costs = json.loads(COST.read_text()) if COST.exists() else {}
        for quality in args.quality:
            costs[quality] = cost(api, quality, args.seeds)
            write_text(COST, json.dumps(costs, indent=1) + "\n")
    if args.what == "run":
        for key in args.scenes:
            obj = scenes[key]
            scene = obj.build()
            radiometer.register()
            sys.path.insert(0, str(ROOT / "bench"))
            from coverage_rare_paths_fin import _with_rule

            try:
                for label in obj.METERS:
                    for quality in args.quality:
                        def keep(row, key=key, label=label, quality=quality, rule=args.rule):
                            row = dict(row, key=key, rule=rule)
                            data["rows"] = [r for r in data["rows"] if (r["key"], r["meter"], r["quality"],
                                                                        r.get("rule", "sequential"))
                                            != (key, label, quality, rule)] + [row]
                            write_text(OUT, json.dumps(data, indent=1) + "\n")
                            write_text(OUT.with_suffix(".md"), markdown(data, scenes))

                        with _with_rule(None if args.rule == "sequential" else args.rule):
                            keep(run_row(api, obj, scene, label, quality, args.seeds, partial=keep))
            finally:
                radiometer.unregister()
    write_text(OUT.with_suffix(".md"), markdown(data, scenes))
    print(markdown(data, scenes))


if __name__ == "__main__":
    main(sys.argv[1:])

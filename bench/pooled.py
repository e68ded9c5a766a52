"""Issue 17's pooled estimator in the throughput room: 1000 meters at 1 %, pooled against per meter.

The interreflecting throughput room (bench/scenes.py ``room``) and its 1000 meters at 0.75 m (the
throughput section's points). Interleaved, each rep with its own seed: ``measure_illuminance`` with
``pooling=True`` (the default: radiometry/sampling/pooled_field.py) and with ``pooling=False`` (every meter
on its own samples), timed, with the samples and bakes each spent. Coverage: the independent numpy
tracer (bench/room_reference.py, transparent light as in Cycles) at ``checked`` meters drawn at
random; z = (reading - truth) / (stated 1-sigma (+) truth's s.e.), for pooled readings and for the
per-meter ones. The machine is shared: only the ratios within one run mean something.

Run alone: ``.venv/bin/python bench/pooled.py [--quick] [--reps N]`` writes bench/pooled.json and
prints the markdown section; ``bench/run.py --only pooled`` runs it in `make bench`.
"""

import json
import math
import os
import re
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import scenes  # noqa: E402


def _load():
    try:
        return [round(x, 1) for x in os.getloadavg()]
    except OSError:
        return None


def bench_pooled(quick=False, reps=None, truth_from=None):
    import room_reference
    from radiometer import api
    from radiometer.measure.render import sensors

    n = 400 if quick else 1000
    reps = reps or (2 if quick else 3)
    checked = 12 if quick else 32
    paths = 10_000 if quick else 40_000
    scene = scenes.room()
    pts, nrm = scenes.meter_points(n, half_width=1.8, z=0.75, seed=3)
    sub = np.random.default_rng(17).choice(n, checked, replace=False)
    t0 = time.perf_counter()
    if truth_from:  # the same points' truth from an earlier run's JSON (it is deterministic)
        with open(truth_from, encoding="utf-8") as f:
            truth = np.array(json.load(f)["truth"])
    else:
        truth = np.array([room_reference.irradiance(pts[k], paths=paths, seed=1000 + int(k)) for k in sub])
    truth_seconds = time.perf_counter() - t0
    total, total_se = truth[:, 0] + truth[:, 1], truth[:, 2]
    api.measure_illuminance(pts[:2], nrm[:2], target_rel_error=0.01)  # warm-up
    real = sensors.run_bake
    bakes = [0]

    def counted(*args, **kwargs):
        bakes[0] += 1
        return real(*args, **kwargs)

    sensors.run_bake = counted
    load_start = _load()
    rows = {True: [], False: []}
    z = {True: {"pooled": [], "held_out_or_refused": []}, False: {"per_meter": []}}
    try:
        for rep in range(reps):
            for pooling in (True, False):
                bakes[0] = 0
                t0 = time.perf_counter()
                rs = api.measure_illuminance(pts, nrm, target_rel_error=0.01, seed=100 + rep, pooling=pooling)
                seconds = time.perf_counter() - t0
                e = np.array([r.irradiance for r in rs])
                rel = np.array([r.rel_std_error for r in rs])
                pooled = np.array([r.method.endswith("+pooled") for r in rs])
                first = next((r for r in rs if r.method.endswith("+pooled")), None)  # its note states the misfit bound
                bound = [float(m.group(1)) for m in (re.search(r"upper bound ([0-9.e+-]+) W/m", t)
                                                     for t in (first.notes if first else [])) if m]
                rows[pooling].append({"seconds": seconds, "samples": float(sum(r.samples for r in rs)),
                                      "bakes": bakes[0], "worst_rel_error": float(rel.max()),
                                      "median_rel_error": float(np.median(rel)), "pooled": int(pooled.sum()),
                                      "pooled_rel_error_median": (float(np.median(rel[pooled])) if pooled.any()
                                                                  else None),
                                      "misfit_upper_w_m2": bound[0] if bound else None})
                zz = (e[sub] - total) / np.hypot(rel[sub] * np.abs(e[sub]), total_se)
                if pooling:
                    z[True]["pooled"] += zz[pooled[sub]].tolist()
                    z[True]["held_out_or_refused"] += zz[~pooled[sub]].tolist()
                else:
                    z[False]["per_meter"] += zz.tolist()
    finally:
        sensors.run_bake = real

    def summary(values):
        v = np.asarray(values, float)
        if not v.size:
            return {"count": 0}
        return {"count": int(v.size), "covered_95": float(np.mean(np.abs(v) < 1.96)), "z_mean": float(v.mean()),
                "z_rms": float(np.sqrt(np.mean(v ** 2))), "z_max": float(np.max(np.abs(v)))}

    def med(key, pooling):
        return float(np.median([r[key] for r in rows[pooling]]))

    return {"meters": n, "reps": reps, "checked": checked, "truth_paths": paths, "truth_seconds": truth_seconds,
            "load_start": load_start, "load_end": _load(),
            "truth_rel_se_max": float(np.max(total_se / total)), "truth": truth.tolist(),
            "pooled_runs": rows[True], "per_meter_runs": rows[False],
            "seconds_ratio": med("seconds", True) / med("seconds", False),
            "samples_ratio": med("samples", True) / med("samples", False),
            "coverage": {"pooled": summary(z[True]["pooled"]),
                         "held_out_or_refused": summary(z[True]["held_out_or_refused"]),
                         "per_meter": summary(z[False]["per_meter"])}}


def markdown(p):
    def med(rows, key):
        return float(np.median([r[key] for r in rows]))

    pr, mr = p["pooled_runs"], p["per_meter_runs"]
    out = [f"## Pooled estimator: {p['meters']:,} meters at 1 % (issue 17)", "",
           f"One run of bench/pooled.py, load average {p['load_start']} at the start and {p['load_end']} at the end "
           f"(2 cores shared). The throughput room's {p['meters']} meters at a 1 % target, {p['reps']} reps "
           "interleaved, each with its own seed: `pooling=True` (the default: groups of >= 300 meters on one plane "
           "read their rendered part from a fitted field, radiometry/sampling/pooled_field.py) against `pooling=False` "
           "(every meter on its own samples, the previous product). Medians over the reps.", "",
           "| way | seconds | samples | bakes | meters pooled | worst stated error | median stated error |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for label, rows in (("pooled (default)", pr), ("per meter (`pooling=False`)", mr)):
        out.append(f"| {label} | {med(rows, 'seconds'):.2f} | {med(rows, 'samples') / 1e6:.3f} M | "
                   f"{med(rows, 'bakes'):.0f} | {med(rows, 'pooled'):.0f} | {100 * med(rows, 'worst_rel_error'):.2f} % | "
                   f"{100 * med(rows, 'median_rel_error'):.2f} % |")
    out += ["", f"Pooled / per meter in this run: time **{p['seconds_ratio']:.2f}**, samples **{p['samples_ratio']:.2f}**. "
                "Each rep's seconds: pooled " + ", ".join(f"{r['seconds']:.2f}" for r in pr) + "; per meter "
            + ", ".join(f"{r['seconds']:.2f}" for r in mr) + ".", "",
            f"Coverage against the independent numpy tracer (bench/room_reference.py, {p['truth_paths']:,} paths per "
            f"point, worst s.e. {100 * p['truth_rel_se_max']:.3f} %) at {p['checked']} meters drawn at random, every rep; "
            "z = (reading - truth) / (stated 1-sigma (+) truth's s.e.):", "",
            "| readings | count | 95 % intervals covering | z mean | z rms | largest abs(z) |", "|---|---:|---:|---:|---:|---:|"]
    for label, key in (("pooled", "pooled"), ("held out or refused (read on their own), pooled runs", "held_out_or_refused"),
                       ("per meter runs", "per_meter")):
        c = p["coverage"][key]
        if c["count"]:
            out.append(f"| {label} | {c['count']} | {100 * c['covered_95']:.1f} % | {c['z_mean']:+.2f} | "
                       f"{c['z_rms']:.2f} | {c['z_max']:.2f} |")
        else:
            out.append(f"| {label} | 0 | | | | |")
    return out + [""]


def main(argv=None):
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--reps", type=int, default=None)
    parser.add_argument("--out", default=os.path.join(HERE, "pooled.json"))
    parser.add_argument("--truth-from", default=None, help="reuse the truth of an earlier run's JSON")
    args = parser.parse_args(argv)
    result = bench_pooled(args.quick, args.reps, args.truth_from)
    from radiometer.outputs import write_text

    write_text(args.out, json.dumps(result, indent=2, default=float) + "\n")
    print("\n".join(markdown(result)))
    return 0


if __name__ == "__main__":
    sys.exit(main())

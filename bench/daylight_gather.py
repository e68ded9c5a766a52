"""Bench for issue 31: the rest of many daylight meters gathered from bakes on the walls (``meter.surface_gather``,
from ``MIN_METERS`` meters) against each meter rendering its own rest (the pooled field at 300 meters and more), in
issue 31's room with its window open (bench/daylight_factor.py ``side_lit_scene(deep=True)``), a 30 x 30 and a
10 x 10 grid at 1 %, each pair timed alternately ``repeats`` times in one run (ratios within it). At 10 x 10 the
gather is forced (``MIN_METERS`` lowered) to show where the default's threshold comes from.

    PYTHONPATH=... python bench/daylight_gather.py [repeats]   # writes bench/daylight_gather.json and .md
"""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from daylight_factor import side_lit_scene  # noqa: E402 - the bench's sibling module


def bench_daylight_gather(repeats=2, sizes=(30, 10), target=0.01):
    import numpy as np

    from radiometer import api
    from radiometer.measure.meter import surface_gather

    t0 = time.perf_counter()
    scene, plane = side_lit_scene(deep=True)
    api.daylight_factor_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)  # warm-up
    rows = []
    default = surface_gather.MIN_METERS
    try:
        for n in sizes:
            row = {"points": n * n, "gather_s": [], "per_meter_s": []}
            for _ in range(repeats):
                for mode in ("gather", "per_meter"):
                    surface_gather.MIN_METERS = 1 if mode == "gather" else 10 ** 9
                    t = time.perf_counter()
                    g = api.daylight_factor_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target, seed=1)
                    row[f"{mode}_s"].append(time.perf_counter() - t)
                    row[f"{mode}_df"] = float(np.mean(g.daylight_factor))
                    row[f"{mode}_worst"] = float(np.max(g.rel_std_error))
            row["ratio"] = float(np.median(row["per_meter_s"]) / np.median(row["gather_s"]))
            rows.append(row)
    finally:
        surface_gather.MIN_METERS = default
    return {"rows": rows, "target_rel_error": target, "min_meters": default, "total_s": time.perf_counter() - t0,
            "load_average": os.getloadavg()}


def markdown(s):
    lines = ["## Daylight factor: the rest gathered from the walls (issue 31)", "",
             "Issue 31's room (4 x 6 x 3 m, a 2 x 1.2 m window, open), the work plane at 0.85 m, target "
             f"{100 * s['target_rel_error']:.2g} % (1 s.e.), one run of {s['total_s']:.0f} s on a 2-core machine (load "
             f"{', '.join(f'{v:.2f}' for v in s['load_average'])} at its end). `gather`: the light the walls reflect "
             "from one-sample bakes at a random point of each wall cell, 32 draws a round, weighed by each meter's "
             "cos cos / r^2 (radiometry/sampling/surface_gather.py); `per meter`: each meter renders its own rest "
             f"(pooled from 300 meters). The product gathers from {s['min_meters']} meters.", "",
             "| points | gather (s) | per meter (s) | per meter / gather (median) | DF average gather / per meter (%) | "
             "worst stated error gather / per meter |", "|---|---|---|---|---|---|"]
    for r in s["rows"]:
        lines.append(f"| {r['points']} | {', '.join(f'{v:.2f}' for v in r['gather_s'])} | "
                     f"{', '.join(f'{v:.2f}' for v in r['per_meter_s'])} | **{r['ratio']:.2f}** | "
                     f"{r['gather_df']:.4f} / {r['per_meter_df']:.4f} | {100 * r['gather_worst']:.2f} % / "
                     f"{100 * r['per_meter_worst']:.2f} % |")
    return lines + [""]


if __name__ == "__main__":
    from scenes import write_results

    result = bench_daylight_gather(int(sys.argv[1]) if len(sys.argv) > 1 else 2)
    write_results(HERE, "daylight_gather", result, "\n".join(markdown(result)))
    print("\n".join(markdown(result)))

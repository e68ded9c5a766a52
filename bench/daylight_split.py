"""Bench for issue 31: the daylight-factor grid's fast path (``method="auto"``: the openings as emitters, the
sky and ground seen straight in closed form, only the rest rendered) against the electric-light grid on the
same points, the whole render (``method="render"``) and Radiance path tracing per core, in the side-lit room
open AND behind a 6 mm pane, as ratios of times taken in one run.

The side-lit room of tests/bpy/daylight_room.py (4 x 3 x 2.7 m, a 2 x 1.2 m window), an n x n grid on an
imaginary work plane at 0.85 m (bench/daylight_factor.py's scene), then issue 31's own room (4 x 6 x 3 m, the same
window, ``side_lit_scene(deep=True)``) the same two ways; the pane room adds
``add_pane_blender`` (a solid 6 mm pane of Glass BSDF, IOR 1.52). Electric light: one 0.6 m square area
light under the ceiling, a black world. Per room a 2 x 2 warm-up of each Radiometer grid runs first.

Radiance: ``radiance_daylight_factor`` of tests/bpy/daylight_room.py (rtrace as a one-thread path tracer,
the same quads, the pane as a dielectric box) on the same points, ``rad_runs`` separate processes of
``rad_samples`` repeats per point. Its cost is the rtrace processes' CPU seconds (getrusage of the
children: Python's building of the input and parsing of the output not counted). Its per-sample relative
spread per point is rel_std_error x sqrt(samples) of each process (pooled); the one-thread seconds it needs
for the whole grid at the worst relative error Radiometer's auto grid stated are
CPU-per-sample x sum over points of (spread_i / err)^2, i.e. each point run just until IT reaches that
error (the cheapest equal-worst-error Radiance run). Radiometer per core: its wall time x 2 cores (Cycles
uses both; the machine's load is recorded), and its process CPU seconds beside it.

    PYTHONPATH=... python bench/daylight_split.py [n] [target]   # default 6 x 6 at 1 %; writes
    bench/daylight_split.json and bench/daylight_split.md
"""

import json
import os
import resource
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from daylight_factor import ISSUE_ROOM, side_lit_scene  # noqa: E402 - the bench's sibling module

CORES = 2  # this machine's; Cycles renders on all of them


def _cpu_self():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _timed(fn):
    """(result, wall s, this process's CPU s)."""
    c0, t0 = _cpu_self(), time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0, _cpu_self() - c0


def _agreement(a, sa, b, sb):
    """a - b in combined standard errors (absolute s.e. given): mean, worst |z|, share within 2, z."""
    import numpy as np

    a, sa, b, sb = (np.ravel(v) for v in (a, sa, b, sb))
    z = (a - b) / np.hypot(sa, sb)
    # the averages' difference, its s.e. taking the points as independent draws
    avg_se = float(np.sqrt(np.sum(sa ** 2) + np.sum(sb ** 2)) / a.size)
    return {"mean": float(np.mean(z)), "worst_abs": float(np.max(np.abs(z))),
            "share_within_2": float(np.mean(np.abs(z) <= 2.0)), "points": int(z.size),
            "average_difference": float(np.mean(a) - np.mean(b)), "average_difference_se": avg_se,
            "z": np.round(z, 2).tolist()}


def _spread_indices(count, k):
    """k indices spread evenly over 0..count-1 (all when k >= count)."""
    import numpy as np

    if k is None or k >= count:
        return np.arange(count)
    return np.unique(np.round(np.linspace(0, count - 1, k)).astype(int))


def bench_room(glass, n, target, whole_points=None, rad_points=None, rad_samples=10000, rad_runs=4, repeats=3,
               deep=False):
    import numpy as np

    from radiometer import api
    from scenes import load_test_module

    room = load_test_module("daylight_room")
    scene, plane = side_lit_scene(deep)
    if glass:
        room.add_pane_blender(scene)
    name = "side-lit room behind a 6 mm pane" if glass else "side-lit room, open window"
    if deep:
        name = name.replace("side-lit room", "issue 31's room (4 x 6 x 3 m)")
    out = {"room": name, "glass": glass, "deep": deep, "points": n * n, "target_rel_error": target, "load_average_before": os.getloadavg()}
    # warm-up: kernels, the emitters' linking check, captures
    api.illuminance_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)
    api.daylight_factor_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)
    api.daylight_factor(np.array([[2.0, 1.5, 0.85]]), (0, 0, 1), scene=scene, method="render",
                        target_rel_error=0.05)

    electric, out["electric_s"], out["electric_cpu_s"] = _timed(
        lambda: api.illuminance_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target))
    out["electric_max_rel_std_error"] = float(electric.max_rel_std_error)
    grid = lambda: api.daylight_factor_grid(plane, resolution=(n, n), scene=scene,  # noqa: E731
                                            target_rel_error=target, seed=1)

    auto, out["auto_s"], out["auto_cpu_s"] = _timed(grid)
    # the shared machine's load moves single timings: the pair repeated, alternated, for the ratio's spread
    pairs = []
    for _ in range(repeats):
        e_s = _timed(lambda: api.illuminance_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target))[1]
        pairs.append((e_s, _timed(grid)[1]))
    out["repeats_electric_auto_s"] = pairs
    df = np.asarray(auto.daylight_factor, float).ravel()
    rel = np.asarray(auto.rel_std_error, float).ravel()
    sc = np.asarray(auto.sky_component, float).ravel()
    pts = np.asarray(auto.points, float).reshape(-1, 3)
    normal = np.asarray(auto.normal, float)
    err = float(np.max(rel))
    out.update({"auto_method": auto.method, "auto_max_rel_std_error": err,
                "auto_sky_component_points": int(np.sum(np.isfinite(sc))),
                "auto_sky_component_share_mean": float(np.nanmean(sc / df)) if np.any(np.isfinite(sc)) else None,
                "auto_average_df": float(auto.stats["average"]),
                "auto_x_electric": out["auto_s"] / out["electric_s"],
                "auto_x_electric_repeats": [a_s / e_s for e_s, a_s in pairs],
                "auto_x_electric_median": float(np.median([out["auto_s"] / out["electric_s"]]
                                                          + [a_s / e_s for e_s, a_s in pairs])),
                "auto_df": np.round(df, 4).tolist(), "auto_rel_std_error": np.round(rel, 5).tolist(),
                "points_m": np.round(pts, 4).tolist()})

    # the whole render on the same points (all, or a spread subset when it would take minutes)
    idx = _spread_indices(n * n, whole_points)
    whole, out["whole_s"], out["whole_cpu_s"] = _timed(
        lambda: api.daylight_factor(pts[idx], normal, scene=scene, method="render", target_rel_error=target, seed=2))
    w_df = np.array([r.daylight_factor for r in whole], float)
    w_rel = np.array([r.rel_std_error for r in whole], float)
    out.update({"whole_points": int(idx.size), "whole_method": "/".join(sorted({r.method for r in whole})),
                "whole_max_rel_std_error": float(np.max(w_rel)),
                "whole_s_per_point": out["whole_s"] / idx.size,
                "whole_s_scaled_to_grid": out["whole_s"] / idx.size * n * n,
                "auto_s_per_point": out["auto_s"] / (n * n),
                "whole_x_electric_scaled": out["whole_s"] / idx.size * n * n / out["electric_s"],
                "auto_average_df_on_whole_points": float(np.mean(df[idx])),
                "whole_average_df": float(np.mean(w_df)),
                "auto_vs_whole": _agreement(df[idx], rel[idx] * df[idx], w_df, w_rel * w_df)})

    # Radiance path tracing, one thread, on the same points (or a spread subset)
    ridx = _spread_indices(n * n, rad_points)
    folder = tempfile.mkdtemp(prefix="radiometer-bench-rad-")
    means, rels = [], []
    c0, t0 = _cpu_children(), time.perf_counter()
    for _ in range(rad_runs):
        m, r = room.radiance_daylight_factor(folder, pts[ridx], normals=normal, samples=rad_samples, glass=glass,
                                             room_quads=room.quads(*ISSUE_ROOM) if deep else None)
        means.append(m)
        rels.append(r)
        # rtrace -u+ seeds its random numbers from the clock's second (measured: processes started in the same
        # second return the same numbers), so the next process starts in a later second than this one ended
        end = int(time.time())
        while int(time.time()) <= end:
            time.sleep(0.02)
    rad_cpu, rad_wall = _cpu_children() - c0, time.perf_counter() - t0
    means, rels = np.array(means), np.array(rels)  # (runs, points)
    rad_df = means.mean(axis=0)
    spread = np.sqrt(np.mean(rels ** 2 * rad_samples, axis=0))  # per-sample relative spread, each process's own
    rad_rel = spread / np.sqrt(rad_samples * rad_runs)
    # the processes' means against their own stated errors: 1 when the repeats are independent draws
    chi = (means - rad_df) ** 2 / (rels * means) ** 2
    between = float(np.sqrt(np.sum(chi) / (ridx.size * (rad_runs - 1)))) if rad_runs > 1 else None
    samples_done = rad_samples * rad_runs * ridx.size
    cpu_per_sample = rad_cpu / samples_done
    need = (spread / err) ** 2  # samples per point to reach the auto grid's worst stated error
    scale = (n * n) / ridx.size  # the subset stands for the grid
    rad_s = cpu_per_sample * float(np.sum(need)) * scale
    rad_s_uniform = cpu_per_sample * float(np.max(need)) * n * n
    radiometer_core_s = out["auto_s"] * CORES
    out.update({"radiance_points": int(ridx.size), "radiance_samples_per_point": rad_samples * rad_runs,
                "radiance_runs": rad_runs, "radiance_cpu_s": rad_cpu, "radiance_wall_s": rad_wall,
                "radiance_cpu_us_per_sample": 1e6 * cpu_per_sample,
                "radiance_spread_per_sample_min": float(np.min(spread)),
                "radiance_spread_per_sample_max": float(np.max(spread)),
                "radiance_samples_needed_max": float(np.max(need)),
                "radiance_samples_needed_mean": float(np.mean(need)),
                "radiance_between_process_over_stated": between,
                "radiance_one_thread_s_at_auto_error": rad_s,
                "radiance_one_thread_s_at_auto_error_uniform": rad_s_uniform,
                "radiometer_core_s": radiometer_core_s,
                "per_core_ratio": rad_s / radiometer_core_s,
                "per_core_ratio_cpu": rad_s / out["auto_cpu_s"],
                "per_core_ratio_uniform": rad_s_uniform / radiometer_core_s,
                "per_core_ratio_between": (rad_s * between ** 2 / radiometer_core_s) if between else None,
                "radiance_average_df": float(np.mean(rad_df)),
                "auto_average_df_on_radiance_points": float(np.mean(df[ridx])),
                "radiance_max_rel_std_error": float(np.max(rad_rel)),
                "radiance_df": np.round(rad_df, 4).tolist(), "radiance_rel_std_error": np.round(rad_rel, 5).tolist(),
                "auto_vs_radiance": _agreement(df[ridx], rel[ridx] * df[ridx], rad_df, rad_rel * rad_df),
                "load_average_after": os.getloadavg()})
    return out


def bench_daylight_split(n=6, target=0.01, whole_points=(None, 25), rad_points=None, rad_samples=10000, rad_runs=4,
                         repeats=3):
    """Both rooms, open and glazed, then issue 31's own deeper room the same two ways; ``whole_points``: (open,
    pane) how many of the grid's points the whole render measures (None: all); Radiance on ``rad_points`` (None:
    all) with ``rad_runs`` x ``rad_samples`` repeats each."""
    t0 = time.perf_counter()
    rooms = [bench_room(glass, n, target, whole_points=whole_points[glass], rad_points=rad_points,
                        rad_samples=rad_samples, rad_runs=rad_runs, repeats=repeats, deep=deep)
             for deep in (False, True) for glass in (False, True)]
    return {"points": n * n, "target_rel_error": target, "cores": CORES, "rooms": rooms,
            "total_s": time.perf_counter() - t0}


def markdown(s):
    lines = ["## Daylight factor: the openings as emitters (issue 31)", "",
             "Side-lit room (tests/bpy/daylight_room.py, 4 x 3 x 2.7 m, a 2 x 1.2 m window), and issue 31's own room "
             "(4 x 6 x 3 m, the same window; the electric light under the middle of its ceiling), "
             f"{s['points']} points on the work plane at 0.85 m, target "
             f"{100 * s['target_rel_error']:.2g} % (1 s.e.) each; each room's rows from one run of "
             f"{s['total_s']:.0f} s in all on a {s['cores']}-core machine shared with other work (ratios within the "
             "run; absolute seconds are not comparable across runs). Per core: Radiometer's wall time x "
             f"{s['cores']} cores (its process CPU seconds beside it) against Radiance's one-thread rtrace CPU "
             "seconds to reach, at every point, the worst relative error Radiometer's `auto` grid stated "
             "(samples per point = (per-sample relative spread / that error)^2, each point run just to it).", ""]
    for r in s["rooms"]:
        wp = r["whole_points"]
        lines += [f"### {r['room']}", "",
                  f"Load average (1, 5, 15 min) before {', '.join(f'{v:.2f}' for v in r['load_average_before'])}, "
                  f"after {', '.join(f'{v:.2f}' for v in r['load_average_after'])}.", "",
                  "| grid | time (s) | x electric | per core vs Radiance | worst stated error |",
                  "|---|---|---|---|---|",
                  f"| electric light (one area light, black world) | {r['electric_s']:.2f} | 1 | | "
                  f"{100 * r['electric_max_rel_std_error']:.2g} % |",
                  f"| daylight factor `auto` ({r['auto_method']}; SC in closed form at "
                  f"{r['auto_sky_component_points']} of {r['points']} points) | {r['auto_s']:.2f} "
                  f"(CPU {r['auto_cpu_s']:.2f}) | {r['auto_x_electric']:.2f} | **{r['per_core_ratio']:.0f} x** faster "
                  f"({r['per_core_ratio_cpu']:.0f} x by CPU s) | {100 * r['auto_max_rel_std_error']:.2g} % |",
                  f"| daylight factor `render` (whole; {wp} of {r['points']} points"
                  + ("" if wp == r["points"] else f", {r['whole_s']:.1f} s measured, scaled per point") + ") | "
                  f"{r['whole_s_scaled_to_grid']:.2f} | {r['whole_x_electric_scaled']:.2f} | | "
                  f"{100 * r['whole_max_rel_std_error']:.2g} % |",
                  f"| Radiance rtrace path tracing, one thread, to the `auto` grid's worst error | "
                  f"{r['radiance_one_thread_s_at_auto_error']:.0f} (1 thread) | "
                  "| 1 | "
                  f"{100 * r['auto_max_rel_std_error']:.2g} % (projected) |", ""]
        a, b = r["auto_vs_whole"], r["auto_vs_radiance"]
        lines += [f"`auto` x electric, the pair repeated {len(r['auto_x_electric_repeats'])} more times alternately "
                  "(the machine's load moves single timings): "
                  + ", ".join(f"{v:.2f}" for v in r["auto_x_electric_repeats"])
                  + f"; median of all {len(r['auto_x_electric_repeats']) + 1}: {r['auto_x_electric_median']:.2f}.", "",
                  f"`auto` vs whole render ({a['points']} points; auto minus render in combined s.e.): mean "
                  f"{a['mean']:+.2f}, worst {a['worst_abs']:.2f}, {100 * a['share_within_2']:.0f} % within 2; average "
                  f"DF {r['auto_average_df_on_whole_points']:.3f} % vs {r['whole_average_df']:.3f} % (difference "
                  f"{a['average_difference']:+.3f} +- {a['average_difference_se']:.3f} %, points taken as "
                  "independent). Whole render "
                  f"{r['whole_s_per_point']:.3f} s per point against `auto`'s {r['auto_s_per_point']:.4f} s "
                  f"({r['whole_s_per_point'] / r['auto_s_per_point']:.0f} x).", "",
                  f"Radiance ({r['radiance_points']} points, {r['radiance_runs']} rtrace processes x "
                  f"{r['radiance_samples_per_point'] // r['radiance_runs']} repeats each per point, each process "
                  "started in a later second than the last ended (rtrace -u+ seeds from the clock's second), "
                  f"{r['radiance_cpu_s']:.1f} s CPU, {r['radiance_cpu_us_per_sample']:.1f} us per sample): "
                  f"per-sample relative spread {r['radiance_spread_per_sample_min']:.2f}-"
                  f"{r['radiance_spread_per_sample_max']:.2f}, so {r['radiance_samples_needed_mean']:.0f} samples per "
                  f"point on average ({r['radiance_samples_needed_max']:.0f} at the worst) for "
                  f"{100 * r['auto_max_rel_std_error']:.2g} %: {r['radiance_one_thread_s_at_auto_error']:.0f} s on one "
                  f"thread against Radiometer's {r['radiometer_core_s']:.2f} core-seconds. Were every point run to the "
                  f"worst point's count: {r['radiance_one_thread_s_at_auto_error_uniform']:.0f} s "
                  f"({r['per_core_ratio_uniform']:.0f} x). The processes' means spread "
                  f"{r['radiance_between_process_over_stated']:.2f} x their repeats' stated error (1 for independent "
                  "draws; were Radiance's need scaled by its square, the per-core ratio would read "
                  f"{r['per_core_ratio_between']:.0f} x).", "",
                  f"`auto` vs Radiance (the independent reference; {b['points']} points, Radiance at worst "
                  f"{100 * r['radiance_max_rel_std_error']:.2g} %; in combined s.e.): mean {b['mean']:+.2f}, worst "
                  f"{b['worst_abs']:.2f}, {100 * b['share_within_2']:.0f} % within 2; average DF "
                  f"{r['auto_average_df_on_radiance_points']:.3f} % vs {r['radiance_average_df']:.3f} % (difference "
                  f"{b['average_difference']:+.3f} +- {b['average_difference_se']:.3f} %, points taken as "
                  "independent).", ""]
    return lines


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 6
    target = float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
    result = bench_daylight_split(n, target)
    with open(os.path.join(HERE, "daylight_split.json"), "w", encoding="utf-8") as fh:
        json.dump(result, fh, indent=2)
    with open(os.path.join(HERE, "daylight_split.md"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(markdown(result)) + "\n")
    print("\n".join(markdown(result)))

"""Issue 31's "annual at real sizes": 1000 points x 146 patches in the side-lit room of tests/bpy/annual_room.py
(4 x 8 m, a 2.4 x 1.0 m opening facing south, a synthetic London year), Radiometer against Radiance, per core.

* Radiance: ``annual_room.radiance_annual`` on the same points: two-phase ``rcontrib -ab 8 -ad 16384 -lw 1e-6``
  x ``gendaymtx`` for sDA, one Radiance sun per occupied hour for ASE. Its CPU seconds are its child processes'
  (user + system: rcontrib runs on one thread).
* Radiometer: ``annual.annual_daylight`` at preview quality (the dome: the patches' direct light through the
  open window in closed form where proven, the rest rendered); its CPU seconds are the process's (Cycles'
  threads included), its wall seconds beside them.

A 20 x 50 grid at 0.85 m from 0.1 m off the walls. Compared: sDA and ASE, and per point Radiance's share of
hours at 300 lx against Radiometer's 2-standard-error bounds (+- 0.02 for Radiance's own noise, as
tests/bpy/test_annual.py) and its direct-sun hours.

    PYTHONPATH=<dir holding radiometer> python bench/annual_large.py   # bench/annual_large.{json,md}
"""

import json
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def grid(nx=20, ny=50):
    xs, ys = np.linspace(0.1, 3.9, nx), np.linspace(0.1, 7.9, ny)
    return [(float(x), float(y), 0.85) for y in ys for x in xs]


def run(nx=20, ny=50, out_dir=HERE):
    import bpy

    import radiometer
    from radiometer.measure.analyses import annual
    from radiometer.measure.blender import request as request_of
    from scenes import load_test_module

    room = load_test_module("annual_room")
    points = grid(nx, ny)
    folder = tempfile.mkdtemp(prefix="radiometer-annual-large-")
    epw_path = room.write_epw(os.path.join(folder, "year.epw"))
    out = {"points": len(points), "grid": [nx, ny], "load_average_before": os.getloadavg()}
    t0, c0 = time.perf_counter(), os.times()
    ref = room.radiance_annual(folder, epw_path, points)
    c1 = os.times()
    out["radiance"] = {"wall_s": time.perf_counter() - t0,
                       "cpu_s": (c1.children_user - c0.children_user) + (c1.children_system - c0.children_system),
                       "sda": float(ref["sda"]), "ase": float(ref["ase"]),
                       "sda_point_fraction": [float(v) for v in ref["sda_point_fraction"]],
                       "ase_hours": [float(v) for v in ref["ase_hours"]]}
    print("radiance", {k: v for k, v in out["radiance"].items() if not isinstance(v, list)}, flush=True)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    room.room.build_blender(scene, room.quads())
    t0, c0 = time.perf_counter(), os.times()
    r = annual.annual_daylight(points, (0, 0, 1), epw_path, request=request_of.build(scene, quality="preview", seed=1))
    c1 = os.times()
    lo, hi = r.sda_point_fraction_bounds
    frac = np.asarray(ref["sda_point_fraction"])
    inside = (lo - 0.02 <= frac) & (frac <= hi + 0.02)
    hours = np.asarray(ref["ase_hours"])
    occ = r.occupied
    e, se = r.illuminance[occ], r.illuminance_std_error[occ]
    rel = se[e >= 100.0] / e[e >= 100.0]
    out["radiometer"] = {"wall_s": time.perf_counter() - t0, "cpu_s": (c1.user - c0.user) + (c1.system - c0.system),
                         "seconds_coefficients": float(r.seconds_coefficients), "sda": float(r.sda),
                         "sda_range": [float(v) for v in r.sda_range], "ase": float(r.ase),
                         "points_inside_bounds": int(inside.sum()),
                         "worst_outside": float(np.max(np.maximum(lo - 0.02 - frac, frac - hi - 0.02))),
                         "ase_hours_max_difference": float(np.max(np.abs(r.ase_hours - hours))),
                         "hourly_rel_error_median": float(np.median(rel)),
                         "hourly_rel_error_p95": float(np.percentile(rel, 95)),
                         "notes": [n for n in r.notes if "direct light" in n or "rays per meter" in n]}
    out["load_average_after"] = os.getloadavg()
    out["cpu_ratio_radiance_over_radiometer"] = out["radiance"]["cpu_s"] / out["radiometer"]["cpu_s"]
    print("radiometer", {k: v for k, v in out["radiometer"].items() if k != "notes"}, flush=True)
    with open(os.path.join(out_dir, "annual_large.json"), "w") as f:
        json.dump(out, f, indent=1)
    write_md(out_dir)
    return out


def bench_annual_large(quick=False):
    """``make bench`` section (bench/run.py): the 1000-point run; quick: 10 x 10 points into a temporary folder
    (quick runs never overwrite results)."""
    if quick:
        return run(10, 10, tempfile.mkdtemp(prefix="radiometer-bench-"))
    return run()


def write_md(out_dir=HERE):
    with open(os.path.join(out_dir, "annual_large.json")) as f:
        d = json.load(f)
    rad, rm = d["radiance"], d["radiometer"]
    n = d["points"]
    nx, ny = d.get("grid", (20, 50))
    lines = [f"## Annual daylight at {n} points x 146 patches, against Radiance (issue 31)", "",
             f"`bench/annual_large.py`: the side-lit room of tests/bpy/annual_room.py, {n} points ({nx} x {ny} at 0.85 m), a "
             "synthetic London year, one run on the 2-core machine (load average before "
             f"{', '.join(f'{v:.1f}' for v in d['load_average_before'])}, after "
             f"{', '.join(f'{v:.1f}' for v in d['load_average_after'])}).", "",
             "| | CPU s | wall s | sDA300/50 % | ASE1000/250 h |", "|---|---|---|---|---|",
             f"| Radiance (rcontrib -ab 8 -ad 16384 -lw 1e-6 x gendaymtx; hourly suns for ASE) | {rad['cpu_s']:.0f} | "
             f"{rad['wall_s']:.0f} | {100 * rad['sda']:.1f} % | {100 * rad['ase']:.1f} % |",
             f"| Radiometer, preview (dome, direct part in closed form) | {rm['cpu_s']:.0f} | {rm['wall_s']:.0f} | "
             f"{100 * rm['sda']:.1f} % ({100 * rm['sda_range'][0]:.1f}-{100 * rm['sda_range'][1]:.1f} %) | "
             f"{100 * rm['ase']:.1f} % |", "",
             f"Per core Radiance / Radiometer = {d['cpu_ratio_radiance_over_radiometer']:.2f} (acceptance: at least 10). "
             f"Per point, Radiance's share of hours at 300 lx lies within Radiometer's 2-s.e. bounds (+- 0.02) at "
             f"{rm['points_inside_bounds']} of {n} points (worst outside by {rm['worst_outside']:.3f}); direct-sun "
             f"hours within {rm['ase_hours_max_difference']:.0f} h. Radiometer's hourly error at 100 lx or more: "
             f"median {100 * rm['hourly_rel_error_median']:.1f} %, 95th percentile "
             f"{100 * rm['hourly_rel_error_p95']:.1f} %.", ""] + [f"- {note}" for note in rm["notes"]]
    with open(os.path.join(out_dir, "annual_large.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    if sys.argv[1:] == ["md"]:
        write_md()
    else:
        run()

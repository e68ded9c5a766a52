"""Bench / validation for issue 19: annual daylight (sDA, ASE) of the non-saturated side-lit room of
tests/bpy/annual_room.py (4 x 8 m, a 2.4 x 1.0 m opening facing south, 40 points, a synthetic London
year), Radiometer against Radiance, and the cost of the daylight coefficients before / after:

* Radiance: two-phase rcontrib x gendaymtx for sDA, one Radiance sun per occupied hour for the
  direct-sun ASE (annual_room.radiance_annual; timed here, run again).
* Radiometer, ``method="dome"`` (every patch in one render per round) at preview quality: timed.
* Radiometer, ``method="per_patch"`` (one meter measurement per patch, the previous way) on
  ``PER_PATCH_SAMPLE`` patches spread over the sky, timed and scaled to the 146 patches (its cost is
  per patch: a full run took 61 min in the previous round); the ratio per_patch / dome in one run.

``.venv/bin/python bench/annual.py`` writes bench/annual.json (a few minutes on two cores).
"""

import json
import os
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PER_PATCH_SAMPLE = [3, 40, 77, 120]  # low south-east, mid, high, near the zenith


def bench_annual(quick=False):
    """``make bench`` section: the same run (quick: two per-patch samples; the JSON is not rewritten)."""
    return main(write=not quick, per_patch_sample=PER_PATCH_SAMPLE[:2] if quick else PER_PATCH_SAMPLE)


def markdown(s):
    r, ref = s["radiometer"], s["radiance"]
    return ["## Annual daylight against Radiance, and its cost (issue 19)", "",
            f"{s['room']}, synthetic London year: sDA300/50 % {100 * r['sda_300_50']:.1f} % (2-s.e. range "
            f"{100 * r['sda_300_50_range'][0]:.1f}-{100 * r['sda_300_50_range'][1]:.1f} %) vs Radiance "
            f"{100 * ref['sda']:.1f} %; ASE1000/250h (direct sun) {100 * r['ase_1000_250h']:.1f} % vs "
            f"{100 * ref['ase']:.1f} %; per point: share of hours at 300 lx within "
            f"{s['sda_point_fraction_max_difference']:.3f}, ASE hours within {s['ase_hours_max_difference']} h. "
            f"Daylight coefficients of 146 patches for {len(r['locations'])} points: "
            f"{s['seconds_dome_coefficients']:.1f} s (one render per round for all patches) vs "
            f"{s['seconds_per_patch_method_146_patches']:.0f} s one render per patch ({s['per_patch_note']}): {s['speed_ratio_per_patch_over_dome']:.0f} x faster; Radiance "
            f"{s['seconds_radiance']:.0f} s (two-phase sDA and the hourly suns); load average "
            f"{s['load_average_1min']:.1f} on 2 cores.", ""]


def main(write=True, per_patch_sample=PER_PATCH_SAMPLE):
    import bpy

    import radiometer
    from radiometer.measure.analyses import annual
    from scenes import load_test_module

    room = load_test_module("annual_room")
    folder = tempfile.mkdtemp(prefix="radiometer-annual-")
    epw_path = room.write_epw(os.path.join(folder, "year.epw"))
    t0 = time.perf_counter()
    ref = room.radiance_annual(folder, epw_path)
    t_rad = time.perf_counter() - t0
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    room.room.build_blender(scene, room.quads())
    normals = np.tile([0.0, 0.0, 1.0], (len(room.POINTS), 1))
    t0 = time.perf_counter()
    from radiometer.measure.blender import request as request_of

    r = annual.annual_daylight(room.POINTS, normals, epw_path, request=request_of.build(scene, quality="preview"))
    t_all = time.perf_counter() - t0
    t0 = time.perf_counter()
    annual.patch_coefficients(scene, locations=room.POINTS, normals=normals, patch_indices=per_patch_sample,
                              quality="preview")
    t_patch = (time.perf_counter() - t0) / len(per_patch_sample)
    per_patch_total = 146 * t_patch
    result = {
        "room": "tests/bpy/annual_room.py: 4 x 8 x 2.7 m, opening 2.4 x 1.0 m facing south, 40 points at 0.85 m",
        "radiometer": r.to_dict(), "radiance": ref, "seconds_radiance": t_rad,
        "seconds_radiometer_total": t_all, "seconds_dome_coefficients": r.seconds_coefficients,
        "seconds_per_patch_method_per_patch": t_patch, "seconds_per_patch_method_146_patches": per_patch_total,
        "speed_ratio_per_patch_over_dome": per_patch_total / r.seconds_coefficients,
        "sda_difference_pp": 100 * (r.sda - ref["sda"]), "ase_difference_pp": 100 * (r.ase - ref["ase"]),
        "sda_point_fraction_max_difference": float(np.max(np.abs(r.sda_point_fraction - ref["sda_point_fraction"]))),
        "ase_hours_max_difference": int(np.max(np.abs(r.ase_hours - np.asarray(ref["ase_hours"])))),
        "load_average_1min": os.getloadavg()[0],
        "per_patch_note": f"timed on patches {per_patch_sample} and scaled to 146",
    }
    if write:
        with open(os.path.join(HERE, "annual.json"), "w", encoding="utf-8") as f:
            json.dump(result, f, indent=1, default=float)
    print(json.dumps({k: v for k, v in result.items() if k not in ("radiometer", "radiance")}, indent=1))
    return result


if __name__ == "__main__":
    main()

"""Coverage of the sun's first bounce as emitters (issue 31, measure/meter/sun_bounce.py) against the
Sun light rendered as it is, in the daylit demo room where that converges: the 9:00 equinox sun (22 deg)
through the pane onto the floor, 5 meters. The reference is Cycles' own Sun light to 0.3 % (one seed,
independent of the sunlit polygons); the emitters' readings at 2 % over ``seeds`` seeds; z = (emitters -
reference) / hypot(stated, reference s.e.); acceptance: at least 90 % of 95 % intervals hold.

    PYTHONPATH=... python bench/sun_bounce_coverage.py [--quick]   # writes bench/sun_bounce_coverage.{json,md}
"""

import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
METERS = [(-1.0, -1.0, 0.75), (0.5, 0.0, 0.75), (1.5, 1.5, 0.75), (0.0, 1.0, 1.8), (-1.5, 0.5, 0.75)]
NORMALS = [(0, 0, 1), (0, 0, 1), (0, 0, 1), (0, 1, 0), (0, 0, 1)]


def bench_sun_bounce_coverage(quick=False, seeds=50, target=0.02, reference_target=0.003):
    import bpy

    import radiometer
    from radiometer import api
    from radiometer.demo import daylight
    from radiometer.measure.analyses import sun_study
    from radiometer.measure.blender import request as request_of, scene_guard
    from radiometer.measure.meter import point_meter as meter

    seeds = 3 if quick else seeds
    reference_target = 0.01 if quick else reference_target  # a smoke run: minutes, not a result
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = daylight.build(bpy.context.scene)
    scene.world = None
    site = daylight.SITE
    info = api.set_sun(scene, site["latitude_deg"], site["longitude_deg"], daylight.local_time((2026, 3, 20, 9, 0)))
    sun = bpy.data.objects[info["object"]]
    points, normals = np.array(METERS, float), np.array(NORMALS, float)
    out = {"elevation_deg": info["elevation_deg"], "azimuth_deg": info["azimuth_deg"], "seeds": seeds,
           "target": target, "reference_target": reference_target, "load_average_before": os.getloadavg()}
    t0 = time.perf_counter()
    ref = meter.measure_illuminance(points, normals, request_of.build(scene, target_rel_error=reference_target,
                                                                      seed=999))
    out["reference_s"] = time.perf_counter() - t0
    out["reference_lux"] = [r.illuminance for r in ref]
    out["reference_rel"] = [r.rel_std_error for r in ref]
    rows, secs = [], []
    for k in range(seeds):
        request = request_of.build(scene, target_rel_error=target, seed=k)
        t0 = time.perf_counter()
        with scene_guard.preserved_scene(scene) as snapshot:
            model = meter.capture_model(scene, request.view_layer)
            readings, reason, _plan = sun_study.sun_bounce_readings(request, model, sun, info, points, normals,
                                                                    snapshot)
        secs.append(time.perf_counter() - t0)
        if readings is None:
            raise RuntimeError(reason)
        rows.append([(r.illuminance, r.rel_std_error) for r in readings])
    arr = np.array(rows)  # (seeds, meters, 2)
    ref_l, ref_se = np.array(out["reference_lux"]), np.array(out["reference_lux"]) * np.array(out["reference_rel"])
    z = (arr[:, :, 0] - ref_l) / np.hypot(arr[:, :, 0] * arr[:, :, 1], ref_se)
    out.update({"emitters_lux": arr[:, :, 0].tolist(), "emitters_rel": arr[:, :, 1].tolist(), "z": z.tolist(),
                "coverage": float(np.mean(np.abs(z) <= 1.96)), "z_mean": float(z.mean()), "z_sd": float(z.std()),
                "per_meter_coverage": np.mean(np.abs(z) <= 1.96, axis=0).tolist(),
                "per_meter_z_mean": z.mean(axis=0).tolist(), "seconds_per_call": float(np.median(secs)),
                "load_average_after": os.getloadavg()})
    return out


def markdown(s):
    lines = ["## The sun's first bounce as emitters: coverage against the Sun light (issue 31)", "",
             f"Daylit demo room (demo/daylight.py, 6 mm pane), the sun at {s['elevation_deg']:.1f} deg (azimuth "
             f"{s['azimuth_deg']:.1f} deg, 9:00 on the equinox in London) through the pane onto the floor, where the "
             "Sun light's own render converges. Reference: `measure_illuminance` with the Sun light at "
             f"{100 * s['reference_target']:.1f} % (one seed; {s['reference_s']:.0f} s); the emitters "
             f"(`sun_study.sun_bounce_readings`) at {100 * s['target']:.0f} % over {s['seeds']} seeds "
             f"({s['seconds_per_call']:.2f} s per call, median). z = (emitters - reference) / hypot(stated, "
             "reference s.e.). One run on a 2-core machine shared with other work.", "",
             f"Coverage of 95 % intervals: **{100 * s['coverage']:.1f} %** (acceptance >= 90 %), z mean "
             f"{s['z_mean']:+.2f}, s.d. {s['z_sd']:.2f}.", "",
             "| meter (m) | normal | reference (lx) | ref. s.e. | emitters mean (lx) | mean stated | coverage | z mean |",
             "|---|---|---|---|---|---|---|---|"]
    lux = np.array(s["emitters_lux"])
    rel = np.array(s["emitters_rel"])
    for j, (p, n) in enumerate(zip(METERS, NORMALS)):
        lines.append(f"| {p} | {n} | {s['reference_lux'][j]:.2f} | {100 * s['reference_rel'][j]:.2f} % | "
                     f"{lux[:, j].mean():.2f} | {100 * rel[:, j].mean():.2f} % | "
                     f"{100 * s['per_meter_coverage'][j]:.0f} % | {s['per_meter_z_mean'][j]:+.2f} |")
    return lines + [""]


def bench_section(quick=False):
    """``make bench`` section (bench/run.py): 50 seeds, written to bench/sun_bounce_coverage.{json,md}; quick: 3 seeds,
    written nowhere (quick runs never overwrite results)."""
    result = bench_sun_bounce_coverage(quick=quick)
    if not quick:
        with open(os.path.join(HERE, "sun_bounce_coverage.json"), "w", encoding="utf-8") as fh:
            json.dump(result, fh, indent=2)
        with open(os.path.join(HERE, "sun_bounce_coverage.md"), "w", encoding="utf-8") as fh:
            fh.write("\n".join(markdown(result)) + "\n")
    return result


if __name__ == "__main__":
    print("\n".join(markdown(bench_section(quick="--quick" in sys.argv))))

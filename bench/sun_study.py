"""Bench section for issue 19: an hourly sun study's cost per time step (called by bench/run.py).

The daylit demo room (demo/daylight.py: a south window with a 6 mm pane, the equinox in London) with a
4 x 4 grid of meters at desk height; one study step per hour over 24 hours. Reported as ratios of times
taken in the same run (the machine is shared): a sunlit step against one plain measurement of the same
meters under the same sun (what the step adds: the guard, switching lights off, a scene capture for
the sunlit ray test), and a night step (no sun: nothing rendered) against a sunlit one.
"""

import datetime as dt
import statistics
import time

import numpy as np


BUDGET_S = 60.0


def demo_room_meters():
    """A fresh daylit demo room (demo/daylight.py) and its 4 x 4 meters at desk height: (scene, points (16, 3))."""
    import bpy

    import radiometer
    from radiometer.demo import daylight

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    xs = np.linspace(-1.5, 1.5, 4)
    return daylight.build(bpy.context.scene), np.array([(x, y, 0.75) for y in xs for x in xs])


def bench_sun_study(quick=False):
    from radiometer import api
    from radiometer.demo import daylight

    scene, points = demo_room_meters()
    site = daylight.SITE
    hours = range(0, 24, 4) if quick else range(24)
    times = [daylight.local_time((2026, 3, 20, h, 0)) for h in hours]
    # Preview (5 %): at 1 % the low-sun steps of a daylit room take minutes each on the shared 2 cores, and
    # the ratios below do not depend on the target (both sides measure the same meters the same way).
    quality = "preview"
    started = time.perf_counter()
    # A low sun leaves readings of a few lux that the relative target makes costly (749 s for the 2 deg
    # step without a budget in one run): each step gets at most BUDGET_S, as a user would give it.
    r = api.sun_study(points, (0, 0, 1), times, latitude_deg=site["latitude_deg"], longitude_deg=site["longitude_deg"],
                      scene=scene, quality=quality, time_budget_s=BUDGET_S)
    wall = time.perf_counter() - started
    up = np.array([s["elevation_deg"] > 0 for s in r.sun])
    # One plain measurement of the same meters under the sun at noon, interleaved with noon steps.
    noon = daylight.local_time((2026, 3, 20, 12, 0))
    api.set_sun(scene, site["latitude_deg"], site["longitude_deg"], noon)
    plain, step = [], []
    for k in range(2 if quick else 3):
        t0 = time.perf_counter()
        api.measure_illuminance(points, (0, 0, 1), scene=scene, quality=quality, seed=k)
        plain.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        api.sun_study(points, (0, 0, 1), [noon], latitude_deg=site["latitude_deg"],
                      longitude_deg=site["longitude_deg"], scene=scene, quality=quality, seed=k)
        step.append(time.perf_counter() - t0)
    sunlit_steps = r.seconds[up]
    night_steps = r.seconds[~up]
    return {"points": len(points), "times": len(times), "quality": quality, "wall_s": wall, "budget_s": BUDGET_S,
            "median_sunlit_step_s": float(np.median(sunlit_steps)) if sunlit_steps.size else None,
            "median_night_step_s": float(np.median(night_steps)) if night_steps.size else None,
            "night_over_sunlit": (float(np.median(night_steps) / np.median(sunlit_steps))
                                  if sunlit_steps.size and night_steps.size else None),
            "noon_step_over_plain_measurement": statistics.median(step) / statistics.median(plain),
            "median_plain_measurement_s": statistics.median(plain), "median_noon_step_s": statistics.median(step),
            "max_rel_std_error": float(np.max(r.rel_std_error)), "sunlight_hours_mean": float(r.sunlight_hours.mean()),
            "step_seconds": [float(x) for x in r.seconds],
            "sun_elevation_deg": [float(s["elevation_deg"]) for s in r.sun]}


def markdown(s):
    return ["## Sun study cost per time step (issue 19)", "",
            f"Daylit demo room, {s['points']} meters at desk height, {s['times']} hourly steps on the equinox "
            f"(quality {s['quality']}" + (f", at most {s['budget_s']:g} s per step" if s.get("budget_s") else "")
            + f"): a sunlit step takes {s['noon_step_over_plain_measurement']:.2f} x one plain "
            f"measurement of the same meters under the same sun (the guard, lights off, one scene capture and the "
            f"sunlit ray test are the difference); a night step (nothing rendered) costs "
            + (f"{s['night_over_sunlit']:.3f}" if s["night_over_sunlit"] is not None else "n/a")
            + f" of a sunlit one. This run: {s['median_sunlit_step_s']:.2f} s per sunlit step (median), "
            f"{s['wall_s']:.1f} s for the whole day; worst stated error {100 * s['max_rel_std_error']:.2g} %."
            + (f" The slowest step took {max(s['step_seconds']):.0f} s (sun {s['sun_elevation_deg'][int(np.argmax(s['step_seconds']))]:.0f}"
               " deg high: readings of a few lux behind the wall, each sampled towards the relative target "
               "until the step's budget)." if "step_seconds" in s else ""), ""]

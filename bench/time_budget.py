"""How closely `time_budget_s` is kept (moved here from a test: wall time belongs in the bench).

    .venv/bin/python bench/time_budget.py      # prints a table; run on a quiet machine

The demo room (interreflecting, 6 meters), rendered: for each budget, the wall time of the call,
its ratio to the budget and the worst stated error. A round that overruns its estimate may take
the call past the budget by about one round; the old test allowed 2 x budget + 1 s.
"""

import time

import bpy


def main():
    from radiometer import api
    from radiometer.demo import scene as demo

    bpy.ops.wm.read_factory_settings(use_empty=True)
    demo.build(bpy.context.scene, with_meters=False)
    points = [(x, y, 0.75) for x in (-1.0, 0.0, 1.0) for y in (-0.5, 0.5)]
    api.measure_illuminance(points[0], (0, 0, 1), method="render", samples=8)  # Cycles' first use
    print(f"{'budget s':>9} {'wall s':>8} {'wall/budget':>11} {'worst rel. s.e.':>15}")
    for budget in (0.5, 1.5, 4.0):
        t0 = time.perf_counter()
        readings = api.measure_illuminance(points, (0, 0, 1), method="render", time_budget_s=budget)
        wall = time.perf_counter() - t0
        worst = max(r.rel_std_error for r in readings)
        print(f"{budget:>9.1f} {wall:>8.2f} {wall / budget:>11.2f} {100 * worst:>14.2f}%")


if __name__ == "__main__":
    main()

"""Issue 31's dark meters: a grid that runs past a lit room's walls. Issue 31's room (4 x 6 x 3 m, one open
2 x 1.2 m window in the wall y = 0, reflectances 0.2 / 0.5 / 0.7), one 0.6 m area light under the middle of its
ceiling, a black world; a 10 x 10 grid at 0.85 m from x = -5 to 9 m and y = 0.3 to 5.7 m, so 80 of the 100
meters stand outside the room, all behind the window's plane. Per variant, in one run (ratios within it):

* the electric grid at 1 % as shipped: the meters outside proven dark (``radiometry/scene/sealed.py``: a closed
  shell whose openings look out on nothing, every light inside, the world black);
* the same with those proofs switched off (as before 2026-12-07): the outside meters sample to ``DARK_FLOOR``;
* the room with a 6 mm pane standing 6 mm in front of the window's plane (as tests/bpy/daylight_room.py puts it):
  the proof holds while the pane, rendered as thin glass, sends nothing back (no face of it in front faces the
  room: ``sealed._keeps_going``);
* the same room built of nine separate boxes 0.2 m thick that touch (no single closed surface): the walls' outer
  faces cover the box round the scene but for the window (``sealed._behind_covered_faces``).

    PYTHONPATH=<dir holding radiometer> python bench/dark_meters.py   # writes bench/dark_meters.{json,md}
"""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def build(glass, boxes=False):
    import numpy as np

    from daylight_factor import ISSUE_ROOM, plane_and_panel
    from scenes import fresh, load_test_module

    room = load_test_module("daylight_room")
    scene = fresh()  # an empty factory scene, registered, a black world
    W, D, H = ISSUE_ROOM  # noqa: N806 - the room module's names
    if boxes:  # the same room of nine separate boxes 0.2 m thick that touch, as the demo room and most users build one
        room.build_boxes_blender(scene, room.boxes_room_boxes(W=W, D=D, H=H, window=(1.0, 3.0, 0.9, 2.1)))
    else:
        room.build_blender(scene, room.quads(W, D, H))
    if glass:
        room.add_pane_blender(scene)
    plane_and_panel(scene, (W - 0.25, D - 0.25), (W / 2, D / 2, H - 0.05))
    points = np.array([(x, y, 0.85) for y in np.linspace(0.3, 5.7, 10) for x in np.linspace(-5.0, 9.0, 10)])
    return scene, points, (points[:, 0] > 0.0) & (points[:, 0] < W)


def _grid(scene, points, target):
    from radiometer import api

    t0 = time.perf_counter()
    readings = api.measure_illuminance(points, (0.0, 0.0, 1.0), scene=scene, target_rel_error=target, seed=1)
    return readings, time.perf_counter() - t0


def variant(name, glass, proof, target, boxes=False):
    import math

    import numpy as np

    from radiometer.radiometry.scene import sealed

    scene, points, inside = build(glass, boxes)
    real = sealed._behind_open_shell, sealed._behind_covered_faces
    if not proof:
        sealed._behind_open_shell = lambda model, sealing, sources, pts, *_: np.zeros(len(pts), bool)
        sealed._behind_covered_faces = lambda model, sources, pts, *_: np.zeros(len(pts), bool)
    try:
        _grid(scene, points[:4], 0.05)  # warm-up: kernels, capture
        readings, seconds = _grid(scene, points, target)
    finally:
        sealed._behind_open_shell, sealed._behind_covered_faces = real
    out = [r for r, i in zip(readings, inside) if not i]
    return {"variant": name, "glass": glass, "proof": proof, "boxes": boxes, "seconds": seconds, "outside": len(out),
            "outside_exact_zero": sum(r.exact and r.illuminance == 0.0 for r in out),
            "outside_infinite_error": sum(math.isinf(r.rel_std_error) for r in out),
            "outside_samples_mean": float(np.mean([r.samples for r in out])),
            "outside_max_lux": float(max(r.illuminance for r in out)),
            "inside_mean_lux": float(np.mean([r.illuminance for r, i in zip(readings, inside) if i])),
            "load_average": os.getloadavg()}


def markdown(rows, target):
    lines = ["## Dark meters: a grid past a lit room's walls (issue 31)", "",
             "`bench/dark_meters.py`: issue 31's room (4 x 6 x 3 m, one 2 x 1.2 m window), one 0.6 m area light under "
             f"its ceiling, a black world; 100 meters at 0.85 m, 80 of them outside the room behind the window's "
             f"plane; the electric grid at {100 * target:.0f} %, one run on the 2-core machine shared with other work.",
             "", "| variant | seconds | outside meters exact 0 | outside meters stating an infinite error | samples "
             "per outside meter (mean) | inside mean (lx) |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['variant']} | {r['seconds']:.2f} | {r['outside_exact_zero']} of {r['outside']} | "
                     f"{r['outside_infinite_error']} | {r['outside_samples_mean']:.0f} | {r['inside_mean_lux']:.1f} |")
    first, before, glazed, boxes = rows
    lines += ["", f"As shipped against the proofs switched off: {before['seconds'] / first['seconds']:.0f}x faster. "
              f"With the 6 mm pane in front of the window's plane: {glazed['outside_exact_zero']} of "
              f"{glazed['outside']} outside meters proven dark; in the room of boxes {boxes['outside_exact_zero']} of "
              f"{boxes['outside']}.", ""]
    return "\n".join(lines)


def run(target=0.01, out_dir=HERE):
    from scenes import write_results

    rows = [variant("open window, as shipped", False, True, target),
            variant("open window, the proof switched off (as before 2026-12-07)", False, False, target),
            variant("6 mm pane in front of the window's plane", True, True, target),
            variant("the same room as nine separate boxes 0.2 m thick, open window", False, True, target, boxes=True)]
    text = markdown(rows, target)
    write_results(out_dir, "dark_meters", {"target_rel_error": target, "rows": rows}, text.rstrip("\n"))
    print(text)
    return rows


if __name__ == "__main__":
    run()

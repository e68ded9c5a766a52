"""Issue 31 on a room as users build one: walls, floor and roof as nine separate boxes that touch (no single
closed surface, so no room's openings to prove). The daylight factor's sky component is then the sky over every
direction that meets no surface (``obstructed_aperture.open_directions``), the rest rendered through the gate (since
the same day the window an emitter where no pane stands: ``sky_component.add_envelope_emitters``);
before 2026-12-07 such a room was rendered whole. The same boxes joined into one closed solid (a Boolean union, as a
solidified or imported room is: the window a tunnel through thick walls, the room's air outside the closed shell) take
the same path since 2026-12-07 (rendered whole before: each point was outside 'the room holding the openings').

The room of tests/bpy/daylight_room.py ``boxes_room_boxes`` (4 x 5 x 2.8 m inside, walls 0.2 m thick, a 2 x 1.3 m
window), open and with a solid 6 mm pane at the room side of its window (``boxes_pane``); a hidden work plane
3.5 x 4.5 m at 0.85 m; an n x n grid at ``target`` (1 s.e.). Per room, in one run (ratios within it):

* the electric grid on the same points (one 0.6 m area light under the roof, a black world) and the daylight
  factor grid (``method="auto"``), the pair repeated alternately (the machine is shared: the ratio's spread);
* the whole render (``method="render"``) on ``whole`` points spread over the grid, its seconds scaled per point,
  and auto minus render on those points in combined standard errors.

    PYTHONPATH=<dir holding radiometer> python bench/boxes_room_split.py [n] [target] [whole]
    # default 10 x 10 at 1 %, 12 points rendered whole; writes bench/boxes_room_split.{json,md}
"""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def build(glass, solid=False):
    import bpy

    import radiometer
    from daylight_factor import plane_and_panel
    from radiometer.compat import ensure_node_tree
    from scenes import load_test_module

    room = load_test_module("daylight_room")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = bpy.context.scene
    if solid:  # the boxes joined into one closed solid: the window a tunnel through thick walls
        room.build_solid_blender(scene, room.boxes_room_boxes())
    else:
        room.build_boxes_blender(scene, room.boxes_room_boxes())
    if glass:
        room.add_pane_blender(scene, room.boxes_pane()[0])
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene, plane_and_panel(scene, (3.75, 4.75), (2.0, 2.5, 2.75))


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def against_whole(scene, grid, target, whole):
    """The daylight-factor ``grid`` (``method="auto"``) against the whole render (``method="render"``, seed 2, the
    same ``target``) at ``whole`` points spread over it: its seconds and auto minus render in combined s.e."""
    import numpy as np

    from radiometer import api

    df = np.asarray(grid.daylight_factor, float).ravel()
    rel = np.asarray(grid.rel_std_error, float).ravel()
    pts = np.asarray(grid.points, float).reshape(-1, 3)
    idx = np.unique(np.linspace(0, df.size - 1, whole).round().astype(int))
    rendered, whole_s = _timed(lambda: api.daylight_factor(pts[idx], (0.0, 0.0, 1.0), scene=scene,
                                                           target_rel_error=target, seed=2, method="render"))
    w_df = np.array([r.daylight_factor for r in rendered])
    w_se = np.array([r.rel_std_error * r.daylight_factor for r in rendered])
    z = (df[idx] - w_df) / np.hypot(rel[idx] * df[idx], w_se)
    return {"whole_points": int(idx.size), "whole_s": whole_s, "whole_s_per_point": whole_s / idx.size,
            "z_auto_minus_whole": np.round(z, 3).tolist(), "z_mean": float(z.mean()),
            "z_worst": float(np.abs(z).max()), "z_within_2": float(np.mean(np.abs(z) <= 2.0))}


def bench_room(glass, n, target, whole, repeats=3, solid=False):
    import numpy as np

    from radiometer import api
    from scenes import grid_pair

    scene, plane = build(glass, solid)
    out = {"room": ("room as one solid, open window" if solid else "room of boxes, 6 mm pane" if glass
                    else "room of boxes, open window"), "glass": glass, "solid": solid,
           "points": n * n, "target_rel_error": target, "load_before": os.getloadavg()}
    electric, auto = grid_pair(api, scene, plane, n, target)  # warmed up

    pairs = []
    grid = None
    for _ in range(1 + repeats):
        e_s = _timed(electric)[1]
        grid, a_s = _timed(auto)
        pairs.append((e_s, a_s))
    sc = np.asarray(grid.sky_component, float).ravel()
    ratios = [a / e for e, a in pairs]
    out.update({"electric_s": [e for e, _a in pairs], "auto_s": [a for _e, a in pairs],
                "auto_x_electric": ratios, "auto_x_electric_median": float(np.median(ratios)),
                "sky_component_points": int(np.sum(np.isfinite(sc))),
                "auto_max_rel_std_error": float(np.max(grid.rel_std_error)),
                "auto_average_df": float(grid.stats["average"]),
                "auto_s_per_point": float(np.median([a for _e, a in pairs])) / (n * n),
                **against_whole(scene, grid, target, whole),
                "notes": [note for note in grid.notes if "sky component" in note][:1],
                "load_after": os.getloadavg()})
    out["whole_over_auto_per_point"] = out["whole_s_per_point"] / out["auto_s_per_point"]
    print(out["room"], {k: v for k, v in out.items() if k not in ("z_auto_minus_whole", "notes")}, flush=True)
    return out


def markdown(rooms):
    lines = ["## Daylight factor in a room of separate boxes (issue 31)", "",
             "`bench/boxes_room_split.py`: walls, floor and roof as nine boxes that touch (4 x 5 x 2.8 m inside, "
             "0.2 m thick, a 2 x 1.3 m window; no single closed surface), a work plane at 0.85 m; the last row the "
             "same boxes joined into one closed solid (a Boolean union: the window a tunnel through thick walls, as a "
             "solidified or imported room; rendered whole before 2026-12-07); one run on the "
             "2-core machine shared with other work (ratios within the run).", "",
             "| room | grid | auto (s, median) | x electric (median; each pair) | sky component proven | worst stated "
             "error | whole render per point / auto's | auto - whole (combined s.e.) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rooms:
        lines.append(f"| {r['room']} | {r['points']} points at {100 * r['target_rel_error']:.0f} % | "
                     f"{sorted(r['auto_s'])[len(r['auto_s']) // 2]:.2f} | **{r['auto_x_electric_median']:.2f}** "
                     f"({', '.join(f'{v:.2f}' for v in r['auto_x_electric'])}) | {r['sky_component_points']} of "
                     f"{r['points']} | {100 * r['auto_max_rel_std_error']:.2f} % | {r['whole_over_auto_per_point']:.0f} x "
                     f"({r['whole_s_per_point']:.2f} s a point on {r['whole_points']} points) | mean "
                     f"{r['z_mean']:+.2f}, worst {r['z_worst']:.2f}, {100 * r['z_within_2']:.0f} % within 2 |")
    lines += ["", "Load average before / after: " + "; ".join(
        f"{r['room']}: {', '.join(f'{v:.1f}' for v in r['load_before'])} / "
        f"{', '.join(f'{v:.1f}' for v in r['load_after'])}" for r in rooms), ""]
    lines += [f"- {r['room']}: {r['notes'][0]}" for r in rooms if r["notes"]]
    return "\n".join(lines) + "\n"


def run(n=10, target=0.01, whole=12, out_dir=HERE):
    rooms = [bench_room(glass, n, target, whole, solid=solid) for glass, solid in ((False, False), (True, False),
                                                                                 (False, True))]
    from scenes import write_results

    text = markdown(rooms)
    write_results(out_dir, "boxes_room_split", {"rooms": rooms}, text.rstrip("\n"))
    print(text)
    return rooms


if __name__ == "__main__":
    from scenes import grid_arguments

    run(*grid_arguments(sys.argv[1:]))

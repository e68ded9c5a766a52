"""Issue 31 on rooms as users place them: on a ground plane. The daylight-factor grid (100 points at 1 %) of the
bench's side-lit room (tests/bpy/daylight_room.py, one thin-walled mesh, a 2 x 1.2 m open window) and of the room of
boxes (``boxes_room_boxes``: 0.2 m walls, a 2 x 1.3 m window), each standing on a 64 x 63 m diffuse ground plane of
reflectance 0.2 just below its floor, against the electric grid on the same points (one 0.6 m area light, a black
world), in one run (ratios within it).

Since 2026-12-07 a ground plane in front of a closed room's openings, below them, no longer keeps them from being
emitters: they emit the sky alone, upwards, and let the other rays through to the ground plane, which the world
lights (``sky_component.openings_to_world``, ``Openings.sky_only``). The row "before" forces the path taken until then
(the world's Ray-Depth gate alone) on the same scene and seed. A spread of points is also rendered whole (another
seed): auto minus the whole render in combined standard errors.

    PYTHONPATH=<dir holding radiometer> python bench/ground_plane_split.py [n] [target] [whole]
    # default 10 x 10 at 1 %, 12 points rendered whole; writes bench/ground_plane_split.{json,md}
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

GROUND_REFLECTANCE = 0.2


def build(kind):
    """(scene, plane): the side-lit room ("thin") or the room of boxes ("boxes") on the ground plane."""
    import bpy

    from scenes import load_test_module

    room = load_test_module("daylight_room")
    if kind == "thin":
        from daylight_factor import side_lit_scene

        scene, plane = side_lit_scene()
        z = -0.01
    else:
        from boxes_room_split import build as boxes

        scene, plane = boxes(False)
        z = -0.21  # below the floor box
    me = bpy.data.meshes.new("ground")
    me.from_pydata([(-30.0, -30.0, z), (34.0, -30.0, z), (34.0, 33.0, z), (-30.0, 33.0, z)], [], [(0, 1, 2, 3)])
    me.materials.append(room.diffuse_material("ground", GROUND_REFLECTANCE))
    scene.collection.objects.link(bpy.data.objects.new("ground", me))
    return scene, plane


def _gate_only():
    """As before 2026-12-07: openings with anything in front of them (here the ground plane) not made emitters."""
    from radiometer.measure.analyses import sky_component

    real = sky_component.openings_to_world

    def refuse_sky_only(model):
        found = real(model)
        if found.sky_only:
            return sky_component.Openings([], [], [], "a surface of the scene lies in front of an opening (as before "
                                                      "2026-12-07)")
        return found

    return real, refuse_sky_only


def bench_room(kind, n, target, whole):
    import numpy as np

    from boxes_room_split import _timed, against_whole

    from radiometer import api
    from radiometer.measure.analyses import sky_component
    from scenes import grid_pair

    scene, plane = build(kind)
    out = {"room": {"thin": "side-lit room (thin walls, one mesh)", "boxes": "room of boxes"}[kind] + " on a ground plane",
           "kind": kind, "points": n * n, "target_rel_error": target, "ground_reflectance": GROUND_REFLECTANCE,
           "load_before": os.getloadavg()}
    electric, auto = grid_pair(api, scene, plane, n, target)  # warmed up

    real, before = _gate_only()
    e_s = [_timed(electric)[1]]
    grid, a_s = _timed(auto)
    sky_component.openings_to_world = before
    try:
        api.daylight_factor_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)  # its own checks
        old, b_s = _timed(auto)
    finally:
        sky_component.openings_to_world = real
    e_s.append(_timed(electric)[1])
    electric_s = float(np.mean(e_s))
    out.update({"electric_s": e_s, "auto_s": a_s, "before_s": b_s, "auto_x_electric": a_s / electric_s,
                "before_x_electric": b_s / electric_s, "auto_average_df": float(grid.stats["average"]),
                "before_average_df": float(old.stats["average"]),
                "auto_max_rel_std_error": float(np.max(grid.rel_std_error)),
                **against_whole(scene, grid, target, whole),
                "notes": [note for note in grid.notes if "emitted" in note or "gap(s)" in note][:1],
                "load_after": os.getloadavg()})
    print(out["room"], {k: v for k, v in out.items() if k not in ("z_auto_minus_whole", "notes")}, flush=True)
    return out


def markdown(rooms):
    lines = ["## Daylight factor on a ground plane (issue 31)", "",
             "`bench/ground_plane_split.py`: the bench's side-lit room and the room of boxes, each on a 64 x 63 m "
             f"diffuse ground plane of reflectance {GROUND_REFLECTANCE:g} just below its floor; 100 points at 1 % on "
             "the work plane at 0.85 m; one run on the 2-core machine shared with other work (ratios within the "
             "run). 'before': the path taken until 2026-12-07 (the world's Ray-Depth gate alone, the openings not "
             "made emitters), same scene and seed.", "",
             "| room | electric (s, mean of 2) | auto (s) | x electric | before (s) | x electric before | worst stated "
             "error | auto - whole render (combined s.e.) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rooms:
        lines.append(f"| {r['room']} | {sum(r['electric_s']) / len(r['electric_s']):.3f} | {r['auto_s']:.2f} | "
                     f"**{r['auto_x_electric']:.1f}** | {r['before_s']:.2f} | {r['before_x_electric']:.1f} | "
                     f"{100 * r['auto_max_rel_std_error']:.2f} % | mean {r['z_mean']:+.2f}, worst {r['z_worst']:.2f}, "
                     f"{100 * r['z_within_2']:.0f} % within 2 ({r['whole_points']} points) |")
    lines += ["", "Average daylight factor, auto / before: " + "; ".join(
        f"{r['room']}: {r['auto_average_df']:.3f} / {r['before_average_df']:.3f} %" for r in rooms),
        "", "Load average before / after: " + "; ".join(
        f"{r['room']}: {', '.join(f'{v:.1f}' for v in r['load_before'])} / "
        f"{', '.join(f'{v:.1f}' for v in r['load_after'])}" for r in rooms), ""]
    lines += [f"- {r['room']}: ...{r['notes'][0][-330:]}" for r in rooms if r["notes"]]
    return "\n".join(lines) + "\n"


def run(n=10, target=0.01, whole=12, out_dir=HERE):
    rooms = [bench_room(kind, n, target, whole) for kind in ("thin", "boxes")]
    from scenes import write_results

    text = markdown(rooms)
    write_results(out_dir, "ground_plane_split", {"rooms": rooms}, text.rstrip("\n"))
    print(text)
    return rooms


if __name__ == "__main__":
    from scenes import grid_arguments

    run(*grid_arguments(sys.argv[1:]))

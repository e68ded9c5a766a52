"""Bench section for issue 19: a 100-point daylight-factor grid at 1 % against a 100-point
electric-light grid at 1 % in the same room, as a ratio of times taken in the same run.

The side-lit room of tests/bpy/daylight_room.py (4 x 3 x 2.7 m, a 2 x 1.2 m open window), a 10 x 10
grid on an imaginary work plane at 0.85 m. Electric light: one 0.6 m square area light under the
ceiling, a black world. Daylight: the same grid under the CIE overcast sky (api.daylight_factor_grid:
lights off, temporary overcast world).
"""

import time


#: Issue 31's own room (its "side-lit room, 4 x 6 x 3 m inside, with one open 2 x 1.2 m window"): width, depth,
#: height (m), the same window as tests/bpy/daylight_room.py's (x 1-3 m, z 0.9-2.1 m in the wall y = 0).
ISSUE_ROOM = (4.0, 6.0, 3.0)


def side_lit_scene(deep=False):
    """The room, a hidden 3.5 x 2.5 m work plane at 0.85 m, one 0.6 m area light, a black world:
    (scene, plane). ``deep``: issue 31's own room (``ISSUE_ROOM``) instead, its work plane 3.5 x 5.5 m, the
    light under the middle of its ceiling."""
    import bpy

    import radiometer
    from scenes import load_test_module
    from radiometer.compat import ensure_node_tree

    room = load_test_module("daylight_room")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = bpy.context.scene
    W, D, H = ISSUE_ROOM  # noqa: N806 - the room module's names
    room.build_blender(scene, room.quads(W, D, H) if deep else None)
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    if deep:
        return scene, plane_and_panel(scene, (W - 0.25, D - 0.25), (W / 2, D / 2, H - 0.05))
    return scene, plane_and_panel(scene, (3.75, 2.75), (2.0, 1.5, 2.65))


def plane_and_panel(scene, corner, lamp_at):
    """A hidden work plane from (0.25, 0.25) to ``corner`` (x, y) m at 0.85 m and one 0.6 m area light of 200 W at
    ``lamp_at``; returns the plane."""
    import bpy

    me = bpy.data.meshes.new("work plane")
    x1, y1 = corner
    me.from_pydata([(0.25, 0.25, 0), (x1, 0.25, 0), (x1, y1, 0), (0.25, y1, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("work plane", me)
    plane.location = (0, 0, 0.85)
    plane.hide_render = True
    scene.collection.objects.link(plane)
    light = bpy.data.lights.new("panel", "AREA")
    light.size, light.energy = 0.6, 200.0
    lamp = bpy.data.objects.new("panel", light)
    lamp.location = lamp_at
    scene.collection.objects.link(lamp)
    return plane


def bench_daylight_factor(quick=False):
    import numpy as np

    from radiometer import api

    scene, plane = side_lit_scene()
    n = 4 if quick else 10
    target = 0.05 if quick else 0.01
    t0 = time.perf_counter()
    electric = api.illuminance_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target)
    t_electric = time.perf_counter() - t0
    t0 = time.perf_counter()
    daylight = api.daylight_factor_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target)
    t_daylight = time.perf_counter() - t0
    # The same grid through the meter camera (method="camera": a fixed number of rays per quality; the
    # time it would need for the target is scaled from its worst stated error, time ~ error^2).
    t0 = time.perf_counter()
    camera = api.daylight_factor_grid(plane, resolution=(n, n), scene=scene, method="camera",
                                      quality="preview" if quick else "standard")
    t_camera = time.perf_counter() - t0
    cam_err = float(np.max(camera.rel_std_error))
    cam_diff = float(np.max(np.abs(camera.daylight_factor - daylight.daylight_factor)
                            / np.hypot(camera.rel_std_error * camera.daylight_factor,
                                       daylight.rel_std_error * daylight.daylight_factor)))
    return {"camera_s": t_camera, "camera_max_rel_std_error": cam_err,
            "camera_s_scaled_to_target": t_camera * (cam_err / target) ** 2,
            "camera_max_difference_in_combined_se": cam_diff,
            "points": n * n, "target_rel_error": target, "electric_s": t_electric, "daylight_factor_s": t_daylight,
            "ratio_daylight_over_electric": t_daylight / t_electric,
            "electric_max_rel_std_error": float(electric.max_rel_std_error),
            "daylight_max_rel_std_error": float(np.max(daylight.rel_std_error)),
            "average_daylight_factor": daylight.stats["average"], "uniformity": daylight.stats["uniformity"]}


def markdown(s):
    return ["## Daylight factor grid against an electric-light grid (issue 19)", "",
            f"Side-lit room (tests/bpy/daylight_room.py), {s['points']} points on the work plane, target "
            f"{100 * s['target_rel_error']:.2g} % (1 s.e.) each: the daylight-factor grid (CIE overcast sky, "
            f"lights off) took {s['ratio_daylight_over_electric']:.2f} x the electric-light grid (one area light, "
            f"black world). This run: {s['daylight_factor_s']:.1f} s vs {s['electric_s']:.1f} s; average DF "
            f"{s['average_daylight_factor']:.2f} %, uniformity {s['uniformity']:.2f}; worst stated errors "
            f"{100 * s['daylight_max_rel_std_error']:.2g} % / {100 * s['electric_max_rel_std_error']:.2g} %."
            + (f" Through the meter camera (method='camera'): {s['camera_s']:.1f} s at a worst stated error of "
               f"{100 * s['camera_max_rel_std_error']:.2g} % ({s['camera_s_scaled_to_target']:.1f} s scaled to the "
               f"target), every point within {s['camera_max_difference_in_combined_se']:.1f} combined s.e. of the "
               "meter's." if "camera_s" in s else ""), ""]

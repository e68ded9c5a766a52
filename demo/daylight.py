"""A daylit room, built by code: a 4 x 4 x 3 m room with a window in its south wall and a 6 mm
glass pane in it, the sun where it stands at a chosen place and time (``measure.authoring.sun.set_sun``, what
``api.set_sun`` calls), and a few meters measured by a one-time sun study (``measure.analyses.sun_study``).

Run it with ``python -m radiometer demo --daylight [--out DIR] [--open]`` (``make demo`` does, after
the electric-light demo; about 2 s). The sun reaches the floor through the pane: the meter reads a
planar Glass BSDF slab as thin glass (issue 18; without that the sun behind it is a caustic Cycles
hardly finds, docs/FACTS.md). ``--open`` hides the pane in renders (an open window). Scene axes: +X east, +Y north, +Z up, metres; floor at z = 0, room centred on
the origin; the window (2.0 x 1.2 m, sill 0.9 m) faces south so the northern-hemisphere sun comes in.

The room is built of separate closed boxes (floor, roof, four walls, the south wall in four pieces
around the opening), the way an architect's model arrives; the pane is a closed 6 mm slab with a
Glass BSDF (IOR 1.5).

The saved room is ready for every daylight command (docs/daylight-sky.md, "Getting started"): a
"Work Plane" (3 x 3 m at 0.85 m, EN 17037's reference plane, 0.5 m in from the walls; hidden in renders)
that ``daylight-factor``, ``annual``, ``grid`` and ``report`` find by its name, a camera looking at the
window from the back of the room (``illuminance-image``, ``glare --luminance-image``), the meters above
as meter objects (``measure``), and beside the .blend a SYNTHETIC weather year for London,
``daylight_room_synthetic.epw`` (``radiometry/sun/synthetic_weather.py``: generated, not measured).
Its world is the sunny day's sky (``CLEAR_SKY``: a CIE clear sky around the sun), so the window seen by the
camera or a DGP view shows sky and ground; the meters printed by the demo read the sun alone.
"""

import os
import sys
import time

import bpy

from ..measure.blender.materials import shader_material
from .builders import black_world, closed_box, diffuse_material, metric_cycles_scene

ROOM = (4.0, 4.0, 3.0)
WALL = 0.1
WINDOW = {"width": 2.0, "sill": 0.9, "head": 2.1}
PANE_THICKNESS = 0.006
SITE = {"name": "London", "latitude_deg": 51.5074, "longitude_deg": -0.1278, "time_zone": "Europe/London"}
WHEN = (2026, 3, 20, 12, 0)  # local wall-clock time on the March equinox
#: EN 17037's reference plane: 0.85 m above the floor, 0.5 m in from the walls (a 3 x 3 m square here).
WORK_PLANE = {"height": 0.85, "margin": 0.5}
#: The camera: at the back of the room at a seated eye height, looking at the window (south, -Y).
CAMERA = {"location": (0.0, 1.6, 1.2), "look": (0.0, -1.0, 0.0), "lens_mm": 16.0, "resolution": (320, 240)}
#: The saved room's world on its sunny day: the CIE standard clear sky (ISO 15469 type 12) around the sun,
#: its unobstructed horizontal illuminance from the IES clear-day model E_kh = A + B sin(alpha)^C, A = 0.8 klx,
#: B = 15.5 klx, C = 0.5 (IES Lighting Handbook daylight chapter, IES RP-21; alpha the sun's elevation), over
#: a ground of reflectance 0.2. Without it the window of a sunny room shows a black sky (a camera or a DGP
#: view sees tens of cd/m² of reflections in the pane instead of kilo-candelas of sky and ground).
CLEAR_SKY = {"sky_type": "cie:12", "a_lux": 800.0, "b_lux": 15500.0, "c": 0.5, "ground_reflectance": 0.2}
#: The synthetic weather file written beside the .blend.
WEATHER_FILE = "daylight_room_synthetic.epw"

#: Meter name -> (location, normal): scene coordinates, m.
METERS = {
    "Roof (open sky)": ((0.0, 0.0, ROOM[2] + WALL + 0.05), (0.0, 0.0, 1.0)),
    "South facade": ((1.6, -ROOM[1] / 2 - WALL - 0.01, 1.5), (0.0, -1.0, 0.0)),
    "Floor in the sun patch": ((0.0, -0.4, 0.0), (0.0, 0.0, 1.0)),
    "Desk height near window": ((0.0, -1.0, 0.75), (0.0, 0.0, 1.0)),
    "Floor, back corner": ((-1.5, 1.5, 0.0), (0.0, 0.0, 1.0)),
}


def glass_material(name="Glass (IOR 1.5)", ior=1.5):
    return shader_material(name, "ShaderNodeBsdfGlass", {"IOR": ior, "Roughness": 0.0})[0]


def build(scene=None, *, glass=True, pane_renders=True):
    """Build the room into ``scene`` (default: the context scene) with a black world; returns it.

    ``glass``: put the pane in the window; ``pane_renders``: False hides it in renders (the window is
    then open for Cycles and the meter)."""
    scene = scene or bpy.context.scene
    metric_cycles_scene(scene)
    black_world(scene, "Black")
    room = bpy.data.collections.new("Daylit Room")
    scene.collection.children.link(room)
    hx, hy, h, t = ROOM[0] / 2, ROOM[1] / 2, ROOM[2], WALL
    walls = diffuse_material("Walls (albedo 0.6)", (0.6, 0.6, 0.6))
    floor = diffuse_material("Floor (albedo 0.3)", (0.3, 0.3, 0.3))
    box = lambda name, lo, hi, mat: closed_box(  # noqa: E731
        name, tuple((a + b) / 2 for a, b in zip(lo, hi)), tuple((b - a) / 2 for a, b in zip(lo, hi)), mat, room)
    box("Floor", (-hx - t, -hy - t, -t), (hx + t, hy + t, 0.0), floor)
    box("Roof", (-hx - t, -hy - t, h), (hx + t, hy + t, h + t), walls)
    box("North Wall", (-hx - t, hy, 0.0), (hx + t, hy + t, h), walls)
    box("East Wall", (hx, -hy, 0.0), (hx + t, hy, h), walls)
    box("West Wall", (-hx - t, -hy, 0.0), (-hx, hy, h), walls)
    w, sill, head = WINDOW["width"] / 2, WINDOW["sill"], WINDOW["head"]
    y0, y1 = -hy - t, -hy
    box("South Wall below", (-hx - t, y0, 0.0), (hx + t, y1, sill), walls)
    box("South Wall above", (-hx - t, y0, head), (hx + t, y1, h), walls)
    box("South Wall west", (-hx - t, y0, sill), (-w, y1, head), walls)
    box("South Wall east", (w, y0, sill), (hx + t, y1, head), walls)
    if glass:
        yc = -hy - t / 2
        pane = box("Window Pane", (-w, yc - PANE_THICKNESS / 2, sill), (w, yc + PANE_THICKNESS / 2, head),
                   glass_material())
        pane.hide_render = not pane_renders
    _work_plane(scene)
    _camera(scene)
    return scene


def _work_plane(scene):
    a = ROOM[0] / 2 - WORK_PLANE["margin"]
    mesh = bpy.data.meshes.new("Work Plane")
    mesh.from_pydata([(-a, -a, 0), (a, -a, 0), (a, a, 0), (-a, a, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("Work Plane", mesh)
    plane.location = (0.0, 0.0, WORK_PLANE["height"])
    plane.hide_render = True  # a reference surface: it must not block or reflect light
    plane.display_type = "WIRE"
    scene.collection.objects.link(plane)
    return plane


def _camera(scene):
    import mathutils

    data = bpy.data.cameras.new("Camera")
    data.lens = CAMERA["lens_mm"]
    cam = bpy.data.objects.new("Camera", data)
    cam.location = CAMERA["location"]
    # a camera looks along its local -Z with +Y up: point -Z along the view, keep the horizon level
    cam.rotation_euler = mathutils.Vector(CAMERA["look"]).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = CAMERA["resolution"]
    scene.render.resolution_percentage = 100
    return cam


def add_meters(scene):
    """The meters of ``METERS`` as meter objects (illuminance, facing their normals) in a "Meters" collection."""
    import mathutils

    from ..measure.meter.meter_objects import add_meter_object

    meters = bpy.data.collections.new("Meters")
    scene.collection.children.link(meters)
    out = []
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0], collection=meters):
        for name, (location, normal) in METERS.items():
            obj = add_meter_object(bpy.context, "ILLUMINANCE", location,
                                   rotation=tuple(mathutils.Vector((0.0, 0.0, 1.0)).rotation_difference(
                                       mathutils.Vector(normal)).to_euler()))
            settings = obj.radiometer_meter  # the demo builds the user's scene: its meters, as Add > Light Meter
            settings.is_meter, settings.kind = True, "ILLUMINANCE"
            obj.name = name
            out.append(obj)
    return out


def write_weather(out_dir, interrupt=None):
    """Write the SYNTHETIC London year (``radiometry.sun.synthetic_weather``) as ``out_dir``/WEATHER_FILE,
    whole or not at all. Returns its path."""
    import contextlib

    from ..errors import RadiometerError
    from ..outputs import write_text
    from ..radiometry.sun import synthetic_weather

    path = os.path.join(os.path.abspath(out_dir), WEATHER_FILE)
    with interrupt.critical() if interrupt is not None else contextlib.nullcontext():
        try:
            write_text(path, synthetic_weather.synthetic_epw_text())
        except OSError as exc:
            raise RadiometerError(f"cannot write {path}: {exc.strerror or exc}") from None
    return path


def clear_sky_horizontal_illuminance(elevation_deg):
    """The IES clear-day sky's unobstructed horizontal illuminance (lx) at a sun elevation (deg); 0 below
    the horizon (``CLEAR_SKY``)."""
    import math

    s = math.sin(math.radians(float(elevation_deg)))
    return CLEAR_SKY["a_lux"] + CLEAR_SKY["b_lux"] * s ** CLEAR_SKY["c"] if s > 0.0 else 0.0


def set_clear_sky(scene, sun):
    """Make ``scene``'s world the clear sky around ``sun`` (``set_sun``'s dict); returns ``set_cie_sky``'s dict,
    or None with the sun below the horizon (the world stays black)."""
    from ..measure.authoring import sky

    e_h = clear_sky_horizontal_illuminance(sun["elevation_deg"])
    if e_h <= 0.0:
        return None
    return sky.set_cie_sky(scene, CLEAR_SKY["sky_type"], horizontal_illuminance_lux=e_h,
                           sun_direction=tuple(sun["direction"]), ground_reflectance=CLEAR_SKY["ground_reflectance"])


def local_time(when=WHEN, time_zone=SITE["time_zone"]):
    from ..radiometry.sun import solar_position

    return solar_position.local_datetime(*when, time_zone)


def run(out_dir="out", *, quality="preview", when=WHEN, glass=True, stream=sys.stdout, interrupt=None):
    """Build the room, set the sun, measure the meters; print a summary; save ``out_dir``/daylight_room.blend.

    ``glass``: render the pane (a Glass BSDF slab); False hides it in renders (an open window; the
    pane is built either way); ``interrupt``: the CLI's Ctrl-C handler (the .blend is written inside its
    critical section) or None. Returns a dict (sun, readings per meter, seconds)."""
    from ..measure.authoring import sun as sun_light
    from ..measure.analyses import sun_study

    started = time.perf_counter()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        import radiometer

        radiometer.register()
    scene = build(bpy.context.scene, glass=True, pane_renders=glass)
    add_meters(scene)
    t = local_time(when)
    sun = sun_light.set_sun(scene, SITE["latitude_deg"], SITE["longitude_deg"], t)
    p = lambda *a: print(*a, file=stream)  # noqa: E731
    p(f"Radiometer daylit room: {SITE['name']} ({SITE['latitude_deg']:.4f} N, {SITE['longitude_deg']:.4f} E), "
      f"{t.isoformat()} ({SITE['time_zone']})")
    p(f"Sun (NREL SPA): azimuth {sun['azimuth_deg']:.3f} deg from north, elevation {sun['elevation_deg']:.3f} deg "
      f"(apparent); direction ({', '.join(f'{v:.4f}' for v in sun['direction'])})")
    p(f"Direct normal illuminance {sun['direct_normal_illuminance_lux']:.0f} lx ({sun['model']}); "
      f"Blender sun strength {sun['strength_w_m2']:.4g} W/m² at {scene.radiometer.efficacy:g} lm/W")
    p(f"Room 4 x 4 x 3 m, window {WINDOW['width']:.1f} x {WINDOW['head'] - WINDOW['sill']:.1f} m facing south"
      + (", 6 mm clear glass pane (Glass BSDF, IOR 1.5)" if glass else
         ", its 6 mm glass pane hidden in renders (an open window)"))
    names = list(METERS)
    from radiometer.measure.blender import request as request_of

    study = sun_study.sun_study([METERS[n][0] for n in names], [METERS[n][1] for n in names], [t],
                                latitude_deg=SITE["latitude_deg"], longitude_deg=SITE["longitude_deg"],
                                direct_normal_illuminance_lux=sun["direct_normal_illuminance_lux"],
                                request=request_of.build(scene, quality=quality))
    import numpy as np

    direction = np.asarray(sun["direction"])
    p(f"\n{'meter':<26} {'E lx':>10} {'± 1 s.e.':>9} {'sunlit':>7} {'E_dn max(0, n.s)':>17}")
    rows = {}
    for k, name in enumerate(names):
        e, se = float(study.illuminance[0, k]), float(study.rel_std_error[0, k])
        n = np.asarray(METERS[name][1], float)
        direct = sun["direct_normal_illuminance_lux"] * max(0.0, float(n @ direction))
        err = "exact" if study.exact[0, k] else f"{100 * se:.1f} %"
        lit = f"{100 * study.sunlit_fraction[0, k]:.0f} %"
        p(f"{name:<26} {e:10.0f} {err:>9} {lit:>7} {direct:17.0f}")
        rows[name] = {"illuminance_lx": e, "rel_std_error": se, "exact": bool(study.exact[0, k]),
                      "sunlit": bool(study.sunlit[0, k]), "sunlit_fraction": float(study.sunlit_fraction[0, k]),
                      "unobstructed_direct_lx": direct}
    p("(E_dn max(0, n.s): the sun's direct light on an unobstructed meter; sunlit: share of the sun's disc "
      "the meter sees, glass counted as clear)")
    p("(the meters read the sun alone: the sun study takes the world away)")
    clear = set_clear_sky(scene, sun)  # after the sun study: the saved room's sunny-day world
    p(f"Saved world: CIE clear sky (ISO 15469 type 12), {clear['horizontal_illuminance_lux']:.0f} lx on the "
      f"unobstructed horizontal from the sky (IES clear day), ground reflectance {CLEAR_SKY['ground_reflectance']:g}"
      if clear else "Saved world: black (the sun is below the horizon)")
    blend = weather = None
    if out_dir:
        from ..errors import RadiometerError
        from ..measure.blender.blend_file import save_copy

        try:
            os.makedirs(out_dir, exist_ok=True)  # `radiometer demo --daylight` checked it before the run
        except OSError as exc:
            raise RadiometerError(f"cannot create the output folder {out_dir}: {exc.strerror or exc}") from None
        blend = save_copy(os.path.join(os.path.abspath(out_dir), "daylight_room.blend"), interrupt)
        weather = write_weather(out_dir, interrupt)
        p(f"\nWrote {blend} (work plane 'Work Plane' at {WORK_PLANE['height']:g} m, camera 'Camera', "
          f"{len(METERS)} meters)")
        p(f"Wrote {weather} (a SYNTHETIC weather year for London: generated, not measured)")
    seconds = time.perf_counter() - started
    p(f"({seconds:.1f} s)")
    return {"sun": sun, "time": t.isoformat(), "meters": rows, "blend": blend,
            "weather": weather, "seconds": seconds}

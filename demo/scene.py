"""A closed 4 x 4 x 3 m room, built the way users build one: a cube scaled into a room (one closed
mesh, outward normals, which Cycles shades from both sides), a desk (a closed box) with a desk lamp,
a ceiling area light, a work plane at desk height and light meters, two of them placed exactly on
the desk top (snapped, as users place them). Coordinates in metres (unit scale 1), floor at z = 0,
room centred on the origin.
"""

import math

import bpy

from .builders import black_world, closed_box, diffuse_material, metric_cycles_scene

ROOM = (4.0, 4.0, 3.0)
DESK = {"centre": (0.4, -0.3), "size": (1.6, 0.8)}  # top at WORK_PLANE_HEIGHT
WORK_PLANE_HEIGHT = 0.75


def build(scene=None, *, with_meters=True):
    """Build the room into ``scene`` (default: a fresh scene named 'Radiometer Demo'). Returns it."""
    if scene is None:
        scene = bpy.data.scenes.new("Radiometer Demo")
    if bpy.context.window is not None:
        bpy.context.window.scene = scene
    metric_cycles_scene(scene)
    black_world(scene, "Radiometer Demo Sky")

    room = bpy.data.collections.new("Room")
    scene.collection.children.link(room)
    hx, hy, h = ROOM[0] / 2, ROOM[1] / 2, ROOM[2]
    wall, wood = diffuse_material("Wall (albedo 0.7)", (0.7, 0.7, 0.7)), diffuse_material("Desk (albedo 0.3)", (0.35, 0.25, 0.18))
    closed_box("Room", (0.0, 0.0, h / 2), (hx, hy, h / 2), wall, room)
    (dx, dy), (sx, sy) = DESK["centre"], DESK["size"]
    closed_box("Desk", (dx, dy, WORK_PLANE_HEIGHT / 2), (sx / 2, sy / 2, WORK_PLANE_HEIGHT / 2), wood, room)

    lights = bpy.data.collections.new("Lights")
    scene.collection.children.link(lights)
    ceiling = bpy.data.lights.new("Ceiling Panel", "AREA")
    ceiling.shape, ceiling.size, ceiling.energy = "SQUARE", 0.6, 6.0  # 6 W x 683 lm/W = 4100 lm, an office panel
    obj = bpy.data.objects.new("Ceiling Panel", ceiling)
    obj.location = (0.0, 0.0, h - 0.01)  # area lights emit along local -Z: downwards
    lights.objects.link(obj)
    lamp = bpy.data.lights.new("Table Lamp", "POINT")
    lamp.energy, lamp.shadow_soft_size = 1.0, 0.05  # 683 lm, like a 60 W incandescent bulb
    lamp.use_temperature, lamp.temperature = True, 2700.0
    obj = bpy.data.objects.new("Table Lamp", lamp)
    obj.location = (1.0, -0.5, 1.2)  # 45 cm above the desk's right end
    lights.objects.link(obj)

    plane_mesh = bpy.data.meshes.new("Work Plane")
    a = 1.8
    plane_mesh.from_pydata([(-a, -a, 0), (a, -a, 0), (a, a, 0), (-a, a, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("Work Plane", plane_mesh)
    plane.location = (0.0, 0.0, WORK_PLANE_HEIGHT)
    plane.hide_render = True  # an imaginary reference surface: it must not block or reflect light
    plane.display_type = "WIRE"
    scene.collection.objects.link(plane)

    if with_meters:
        from ..measure.meter.meter_objects import add_meter_object

        def add_meter(context, kind, location, acceptance_deg=1.0):
            obj = add_meter_object(context, kind, location)
            settings = obj.radiometer_meter  # the demo builds the user's scene: its meters, as Add > Light Meter
            settings.is_meter, settings.kind, settings.acceptance_deg = True, kind, acceptance_deg
            return obj

        meters = bpy.data.collections.new("Meters")
        scene.collection.children.link(meters)
        layer = scene.view_layers[0]
        with bpy.context.temp_override(scene=scene, view_layer=layer, collection=meters):
            # Two meters lie ON the desk top (z = its surface), two in free space at desk height.
            for name, loc in (("Desk Centre", (dx, dy, WORK_PLANE_HEIGHT)),
                              ("Desk Under Lamp", (1.0, -0.5, WORK_PLANE_HEIGHT)),
                              ("Room Centre", (-0.6, 1.0, WORK_PLANE_HEIGHT)),
                              ("Room Corner", (-1.5, -1.5, WORK_PLANE_HEIGHT))):
                obj = add_meter(bpy.context, "ILLUMINANCE", loc)
                obj.name = name
            obj = add_meter(bpy.context, "LUMINANCE", (0.0, -1.5, 1.6), acceptance_deg=2.0)
            obj.name = "Wall Luminance"
            obj.rotation_euler = (math.radians(90.0), 0.0, math.radians(90.0))  # looks at the x = -2 wall
    return scene

"""A 4 x 4 x 3 m room: diffuse walls, a ceiling area light, a table lamp, sunlight through a window,
a work plane at 0.75 m and a few light meters. Coordinates in metres (unit scale 1), floor at z = 0,
room centred on the origin, window in the +Y wall.
"""

import math

import bpy

from ..compat import ensure_node_tree

ROOM = (4.0, 4.0, 3.0)
WINDOW = {"x": (-0.8, 0.8), "z": (1.0, 2.2)}  # opening in the y = +2 wall
WORK_PLANE_HEIGHT = 0.75


def _diffuse(name, albedo):
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*albedo, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mat.diffuse_color = (*albedo, 1.0)
    return mat


def _box_mesh(name, quads, material, collection):
    verts, faces = [], []
    for quad in quads:
        base = len(verts)
        verts += quad
        faces.append(tuple(range(base, base + 4)))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    collection.objects.link(obj)
    return obj


def build(scene=None, *, with_meters=True):
    """Build the room into ``scene`` (default: a fresh scene named 'Radiometer Demo'). Returns it."""
    if scene is None:
        scene = bpy.data.scenes.new("Radiometer Demo")
    if bpy.context.window is not None:
        bpy.context.window.scene = scene
    scene.render.engine = "CYCLES"
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    world = bpy.data.worlds.new("Radiometer Demo Sky")
    background = ensure_node_tree(world).nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world

    room = bpy.data.collections.new("Room")
    scene.collection.children.link(room)
    hx, hy, h = ROOM[0] / 2, ROOM[1] / 2, ROOM[2]
    wall, floor = _diffuse("Wall (albedo 0.7)", (0.7, 0.7, 0.7)), _diffuse("Floor (albedo 0.3)", (0.3, 0.25, 0.2))
    # Quads wound so normals face into the room.
    _box_mesh("Floor", [[(-hx, -hy, 0), (hx, -hy, 0), (hx, hy, 0), (-hx, hy, 0)]], floor, room)
    _box_mesh("Ceiling", [[(-hx, -hy, h), (-hx, hy, h), (hx, hy, h), (hx, -hy, h)]], wall, room)
    wx0, wx1 = WINDOW["x"]
    wz0, wz1 = WINDOW["z"]
    walls = [
        [(-hx, -hy, 0), (-hx, -hy, h), (hx, -hy, h), (hx, -hy, 0)],      # y = -2
        [(-hx, -hy, 0), (-hx, hy, 0), (-hx, hy, h), (-hx, -hy, h)],      # x = -2
        [(hx, -hy, 0), (hx, -hy, h), (hx, hy, h), (hx, hy, 0)],          # x = +2
        # y = +2 wall around the window opening
        [(-hx, hy, 0), (hx, hy, 0), (hx, hy, wz0), (-hx, hy, wz0)],
        [(-hx, hy, wz1), (hx, hy, wz1), (hx, hy, h), (-hx, hy, h)],
        [(-hx, hy, wz0), (wx0, hy, wz0), (wx0, hy, wz1), (-hx, hy, wz1)],
        [(wx1, hy, wz0), (hx, hy, wz0), (hx, hy, wz1), (wx1, hy, wz1)],
    ]
    _box_mesh("Walls", walls, wall, room)

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
    obj.location = (1.2, -1.2, 1.2)
    lights.objects.link(obj)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy, sun.angle = 20.0, math.radians(0.526)  # W/m^2 facing the sun; the sun's disc is 0.526 deg
    obj = bpy.data.objects.new("Sun", sun)
    obj.rotation_euler = (math.radians(-50.0), 0.0, 0.0)  # shines in through the +Y window, downwards
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
        from ..operators.meter import add_meter

        meters = bpy.data.collections.new("Meters")
        scene.collection.children.link(meters)
        layer = scene.view_layers[0]
        with bpy.context.temp_override(scene=scene, view_layer=layer, collection=meters):
            for name, loc in (("Desk Centre", (0.0, 0.0, WORK_PLANE_HEIGHT)),
                              ("Desk Lamp Side", (1.0, -1.0, WORK_PLANE_HEIGHT)),
                              ("Desk Window Side", (0.0, 1.5, WORK_PLANE_HEIGHT)),
                              ("Desk Corner", (-1.5, -1.5, WORK_PLANE_HEIGHT))):
                obj = add_meter(bpy.context, "ILLUMINANCE", loc)
                obj.name = name
            obj = add_meter(bpy.context, "LUMINANCE", (0.0, -1.5, 1.6), acceptance_deg=2.0)
            obj.name = "Wall Luminance"
            obj.rotation_euler = (math.radians(90.0), 0.0, math.radians(90.0))  # looks at the x = -2 wall
    return scene

"""A small test office for glare and false-colour tests: a 6 x 4 x 3 m grey room (albedo 0.5, one closed
mesh) with four 0.6 m square ceiling panels (area lights facing down), and its Radiance twin.

Imports nothing from Radiometer's measuring code (the tests use it as an independent yardstick's scene).
"""

import math

import bpy

from radiometer.compat import ensure_node_tree

ROOM = ((-3.0, 3.0), (-2.0, 2.0), (0.0, 3.0))
ALBEDO = 0.5
PANEL = 0.6                                   # m, side of each square panel
PANEL_Z = 2.9                                 # m
PANELS = ((-1.2, 0.0), (1.2, 0.0), (-1.2, 1.4), (1.2, 1.4))
PANEL_POWER = 15.0                            # W (Blender, normalized): L = P / (pi A)
EYE = (0.0, -1.6, 1.2)
VIEW = (0.0, 1.0, 0.0)


def grey_material(name="grey", albedo=ALBEDO):
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def emission_material(name, strength):
    """A white Emission shader of ``strength``: radiance = strength W/(m² sr) per channel (Blender manual:
    strength 1 shows the colour as it is)."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    emission.inputs["Strength"].default_value = strength
    tree.links.new(emission.outputs["Emission"], tree.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    return mat


def room_faces():
    """The six faces of the room as corner lists (each seen counter-clockwise from inside the room)."""
    (x0, x1), (y0, y1), (z0, z1) = ROOM
    return [
        [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],  # floor, normal +z
        [(x0, y0, z1), (x0, y1, z1), (x1, y1, z1), (x1, y0, z1)],  # ceiling, normal -z
        [(x0, y0, z0), (x0, y0, z1), (x1, y0, z1), (x1, y0, z0)],  # y0 wall, normal +y
        [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],  # y1 wall, normal -y
        [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)],  # x0 wall, normal +x
        [(x1, y0, z0), (x1, y0, z1), (x1, y1, z1), (x1, y1, z0)],  # x1 wall, normal -x
    ]


def build(scene, *, panels=True):
    """Room mesh + panels in ``scene`` (black world). Returns the list of panel light objects."""
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    verts, faces = [], []
    for quad in room_faces():
        faces.append(tuple(range(len(verts), len(verts) + 4)))
        verts += quad
    mesh = bpy.data.meshes.new("Room")
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(grey_material())
    room = bpy.data.objects.new("Room", mesh)
    scene.collection.objects.link(room)
    lights = []
    if panels:
        for k, (x, y) in enumerate(PANELS):
            data = bpy.data.lights.new(f"Panel {k + 1}", "AREA")
            data.shape, data.size, data.energy = "SQUARE", PANEL, PANEL_POWER
            obj = bpy.data.objects.new(f"Panel {k + 1}", data)
            obj.location = (x, y, PANEL_Z)
            scene.collection.objects.link(obj)
            lights.append(obj)
    return lights


def panel_luminance(efficacy=683.0):
    """cd/m² of a white panel: K x P / (pi A) (Blender's normalized area light, FACTS.md)."""
    return efficacy * PANEL_POWER / (math.pi * PANEL * PANEL)


def radiance_scene(path, efficacy=683.0):
    """Write the office as a Radiance scene: grey plastic room, panels as 'light' polygons facing down
    whose luminance (179 lm/W x radiance, Radiance's convention) equals the Blender panels' in cd/m²."""
    r = panel_luminance(efficacy) / 179.0
    lines = [f"void plastic grey 0 0 5 {ALBEDO} {ALBEDO} {ALBEDO} 0 0",
             f"void light lum 0 0 3 {r:.9g} {r:.9g} {r:.9g}"]
    for k, quad in enumerate(room_faces()):
        lines.append(f"grey polygon wall{k} 0 0 12 " + " ".join(f"{c:g}" for p in quad for c in p))
    h = PANEL / 2
    for k, (x, y) in enumerate(PANELS):
        # clockwise seen from above: the normal (right-hand rule) points down
        quad = [(x - h, y - h), (x - h, y + h), (x + h, y + h), (x + h, y - h)]
        lines.append(f"lum polygon panel{k} 0 0 12 " + " ".join(f"{a:g} {b:g} {PANEL_Z:g}" for a, b in quad))
    with open(path, "w", encoding="ascii") as f:
        f.write("\n".join(lines) + "\n")
    return path

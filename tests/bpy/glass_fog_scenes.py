"""Scenes of the window and fog corpus (issue 18), shared by ``test_glass_fog.py`` and
``make_glass_fog_references.py``. Builders use bpy only (no Radiometer measurement code), so the
references rendered from them stay independent of the meter.

Every builder resets Blender to an empty factory scene and returns ``(scene, cases)`` with cases a
list of ``(label, point, normal)`` in scene coordinates.
"""

import math

import bpy
import numpy as np

from radiometer.compat import ensure_node_tree  # Blender 4.5: new worlds/materials have no tree yet


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def _world(scene, strength=0.0, colour=(1.0, 1.0, 1.0), fog_density=None):
    world = bpy.data.worlds.new("world")
    tree = ensure_node_tree(world)
    bg = tree.nodes["Background"]
    bg.inputs["Strength"].default_value = strength
    bg.inputs["Color"].default_value = tuple(colour) + (1.0,)
    if fog_density is not None:
        scatter = tree.nodes.new("ShaderNodeVolumeScatter")
        scatter.inputs["Density"].default_value = fog_density
        out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld")
        tree.links.new(scatter.outputs["Volume"], out.inputs["Volume"])
    scene.world = world
    return world


def _light(scene, kind, location, rotation=(0.0, 0.0, 0.0), **props):
    data = bpy.data.lights.new(kind.lower(), kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    obj.location, obj.rotation_euler = location, rotation
    scene.collection.objects.link(obj)
    return obj


#: Fog: a world volume (Volume Scatter, density 0.05 per m: sigma_s = 0.05 / m, no absorption).
FOG_LIGHTS = {
    "POINT": dict(kind="POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0),
    "SPOT": dict(kind="SPOT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0,
                 spot_size=math.radians(40.0), spot_blend=0.0),
    "AREA": dict(kind="AREA", location=(0.0, 0.0, 2.0), energy=100.0, size=1.0),
}


def fog(kind):
    scene = reset()
    _world(scene, strength=0.0, fog_density=0.05)
    spec = dict(FOG_LIGHTS[kind])
    _light(scene, spec.pop("kind"), spec.pop("location"), **spec)
    return scene, [(f"fog {kind.lower()}", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))]


def glass_material(name, kind="glass", ior=1.52, colour=(1.0, 1.0, 1.0), roughness=0.0):
    """A window material: "glass" (Glass BSDF), "principled" (Principled BSDF, transmission 1) or
    "trick" (Light Path > Is Shadow Ray mixing a white Transparent BSDF in for shadow rays)."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    if kind == "principled":
        bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled")
        bsdf.inputs["Transmission Weight"].default_value = 1.0
        bsdf.inputs["Roughness"].default_value = roughness
        bsdf.inputs["IOR"].default_value = ior
        bsdf.inputs["Base Color"].default_value = tuple(colour) + (1.0,)
    else:
        bsdf = tree.nodes.new("ShaderNodeBsdfGlass")
        bsdf.inputs["IOR"].default_value = ior
        bsdf.inputs["Roughness"].default_value = roughness
        bsdf.inputs["Color"].default_value = tuple(colour) + (1.0,)
    shader = bsdf.outputs[0]
    if kind == "trick":
        path = tree.nodes.new("ShaderNodeLightPath")
        transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
        mix = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(path.outputs["Is Shadow Ray"], mix.inputs[0])
        tree.links.new(shader, mix.inputs[1])
        tree.links.new(transparent.outputs[0], mix.inputs[2])
        shader = mix.outputs[0]
    tree.links.new(shader, out.inputs["Surface"])
    return mat


def add_pane(scene, name, material, centre=(0.0, 0.0, 1.0), size=(2.0, 2.0), thickness=0.006):
    """A horizontal pane: a flat box (a solidified slab) or, with thickness 0, a single face."""
    cx, cy, cz = centre
    hx, hy, hz = size[0] / 2, size[1] / 2, thickness / 2
    mesh = bpy.data.meshes.new(name)
    if thickness > 0.0:
        v = [(cx + x, cy + y, cz + z) for z in (-hz, hz) for y in (-hy, hy) for x in (-hx, hx)]
        faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    else:
        v = [(cx - hx, cy - hy, cz), (cx + hx, cy - hy, cz), (cx + hx, cy + hy, cz), (cx - hx, cy + hy, cz)]
        faces = [(0, 1, 2, 3)]
    mesh.from_pydata(v, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


#: Windows over a meter at the origin (facing up): name -> (material kind, IOR, colour, panes as
#: (height, thickness)).
WINDOWS = {
    "plain": ("glass", 1.52, (1.0, 1.0, 1.0), [(1.0, 0.006)]),
    "single_face": ("glass", 1.5, (1.0, 1.0, 1.0), [(1.0, 0.0)]),
    "trick": ("trick", 1.5, (1.0, 1.0, 1.0), [(1.0, 0.0)]),
    "principled": ("principled", 1.45, (1.0, 1.0, 1.0), [(1.0, 0.004)]),
    "tinted": ("glass", 1.52, (0.6, 0.8, 0.9), [(1.0, 0.006)]),
    "double_glazing": ("glass", 1.52, (1.0, 1.0, 1.0), [(1.0, 0.004), (1.02, 0.004)]),
}


def window(name, light="SUN", elevation_deg=60.0):
    """A meter at the origin under a 2 x 2 m horizontal window at 1 m, lit by a sun (0.53 degrees)
    or a point light (3 m up, 0.5 m aside) through it; black world."""
    scene = reset()
    _world(scene, strength=0.0)
    kind, ior, colour, panes = WINDOWS[name]
    mat = glass_material(f"{name} glass", kind, ior, colour)
    for k, (z, thickness) in enumerate(panes):
        add_pane(scene, f"Pane {k + 1}", mat, centre=(0.0, 0.0, z), thickness=thickness)
    if light == "SUN":
        _light(scene, "SUN", (0.0, 0.0, 5.0), rotation=(math.radians(90.0 - elevation_deg), 0.0, 0.0),
               energy=100.0, angle=math.radians(0.53))
    else:
        _light(scene, "POINT", (0.0, 0.5, 3.0), energy=1000.0, shadow_soft_size=0.0)
    return scene, [(f"{name} {light.lower()}", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))]


#: Frosted (rough) panes of the corpus: the "plain" window with a rough Glass BSDF, by roughness.
FROSTED_ROUGHNESS = (0.3, 0.2, 0.1)


def frosted_window(light="POINT", roughness=0.3):
    """``window("plain", light)`` with its 6 mm pane frosted: a Glass BSDF (IOR 1.52) of the given
    roughness, which Radiometer renders as it is (it is not a thin pane)."""
    scene, [(label, point, normal)] = window("plain", light=light)
    bpy.data.objects["Pane 1"].data.materials[0] = glass_material(f"frosted {roughness:g}", roughness=roughness)
    return scene, [(f"frosted {roughness:g} {light.lower()}", point, normal)]


def _diffuse(name, albedo):
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def _quads(scene, name, quads, material):
    verts, faces = [], []
    for quad in quads:
        faces.append(tuple(range(len(verts), len(verts) + 4)))
        verts.extend(quad)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def constant_pane_material(name, T, R):
    """Thin glass at ONE angle: Transparent BSDF of colour T plus a sharp Glossy BSDF of colour R
    (the reference for the sun's part, whose rays all cross the pane at the sun's angle). Put it on
    a single face: on both faces of a slab a ray would pass T twice."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
    transparent.inputs["Color"].default_value = tuple(T) + (1.0,)
    glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
    glossy.inputs["Roughness"].default_value = 0.0
    glossy.inputs["Color"].default_value = tuple(R) + (1.0,)
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(transparent.outputs[0], add.inputs[0])
    tree.links.new(glossy.outputs[0], add.inputs[1])
    tree.links.new(add.outputs[0], out.inputs["Surface"])
    return mat


#: Skylight room: 6 x 6 x 3 m, a 1.5 x 1.5 m opening in the ceiling glazed with a 6 mm Glass BSDF
#: pane (IOR 1.52), a sun of 100 W/m^2 at 60 degrees elevation (0.53 degree disc) and a uniform sky
#: of radiance 0.5 W/(m^2 sr). Meters on the floor: in the sun patch and in the shade.
ROOM_SUN_ELEVATION = 60.0


def window_room(part=None):
    """``part``: None (the scene), "sun" (black sky, the pane as constant thin glass at the sun's
    angle from the slab's closed form) or "sky" (the sun hidden, the real Glass BSDF pane)."""
    scene = reset()
    _world(scene, strength=0.0 if part == "sun" else 0.5)
    wall = _diffuse("walls", 0.5)
    h, top, g = 3.0, 3.0, 0.75
    floor = [[(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)]]
    walls = [[(-h, -h, 0), (-h, h, 0), (-h, h, top), (-h, -h, top)], [(h, -h, 0), (h, -h, top), (h, h, top), (h, h, 0)],
             [(-h, -h, 0), (-h, -h, top), (h, -h, top), (h, -h, 0)], [(-h, h, 0), (h, h, 0), (h, h, top), (-h, h, top)]]
    ceiling = [[(-h, -h, top), (-h, h, top), (-g, h, top), (-g, -h, top)], [(g, -h, top), (g, h, top), (h, h, top), (h, -h, top)],
               [(-g, -h, top), (-g, -g, top), (g, -g, top), (g, -h, top)], [(-g, g, top), (-g, h, top), (g, h, top), (g, g, top)]]
    _quads(scene, "Room", floor + walls + ceiling, wall)
    if part == "sun":
        from radiometer.radiometry.scene import thin_glass  # the slab's closed form (reference side)

        c = math.cos(math.radians(90.0 - ROOM_SUN_ELEVATION))
        T, R, _A = thin_glass.slab(c, float(np.float32(1.52)))
        pane_mat = constant_pane_material("pane at the sun's angle", T, R)
    else:
        pane_mat = glass_material("skylight glass", "glass", 1.52)
    # The sun's reference pane is one face (a ray crosses it once: T once, not at both slab faces).
    add_pane(scene, "Skylight", pane_mat, centre=(0.0, 0.0, top), size=(2 * g, 2 * g),
             thickness=0.0 if part == "sun" else 0.006)
    if part != "sky":
        _light(scene, "SUN", (0.0, 0.0, 5.0), rotation=(math.radians(90.0 - ROOM_SUN_ELEVATION), 0.0, 0.0),
               energy=100.0, angle=math.radians(0.53))
    return scene, [("floor in the sun", (0.0, 1.7, 0.0), (0.0, 0.0, 1.0)),
                   ("floor in the shade", (-2.0, -2.0, 0.0), (0.0, 0.0, 1.0))]


def glossy_floor(roughness=0.3):
    """A 6 x 6 m metal floor (Glossy BSDF, GGX, white) under a small sphere light (radius 5 cm,
    100 W at 2 m); meters facing down at 1 m: all their light arrives by the floor's glossy
    reflection (issue 18: z = -3.0 and -2.5 at `standard`)."""
    scene = reset()
    _world(scene, strength=0.0)
    mat = bpy.data.materials.new("metal floor")
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfGlossy")
    bsdf.distribution = "GGX"
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    _quads(scene, "Floor", [[(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)]], mat)
    _light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.05)
    return scene, [("over the highlight", (0.0, 0.0, 1.0), (0.0, 0.0, -1.0)),
                   ("beside the highlight", (1.0, 0.0, 1.0), (0.0, 0.0, -1.0))]


#: Absorbing pane: Volume Absorption inside a 6 mm Glass BSDF slab (Cycles: sigma_a = density (1 - Color)).
ABSORBER = {"density": 20.0, "colour": (0.5, 0.8, 0.9)}


def absorbing_pane_sky(sun=False):
    """The "plain" window of ``window`` with a Volume Absorption in the pane, under a uniform sky of
    radiance 1 W/(m^2 sr) (optionally the sun too)."""
    scene, cases = window("plain", light="SUN")
    if not sun:
        bpy.data.objects.remove(next(o for o in scene.objects if o.type == "LIGHT"))
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    tree = bpy.data.objects["Pane 1"].data.materials[0].node_tree
    absorb = tree.nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Density"].default_value = ABSORBER["density"]
    absorb.inputs["Color"].default_value = tuple(ABSORBER["colour"]) + (1.0,)
    out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(absorb.outputs[0], out.inputs["Volume"])
    return scene, [("under an absorbing pane, sky", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))]


SCENES = {f"fog_{k.lower()}": (lambda k=k: fog(k)) for k in FOG_LIGHTS}
SCENES["absorbing_pane_sky"] = absorbing_pane_sky
SCENES["glossy_floor"] = glossy_floor
SCENES.update({f"frosted_{light.lower()}_{r:g}": (lambda light=light, r=r: frosted_window(light, r))
               for light in ("POINT", "SUN") for r in FROSTED_ROUGHNESS})
SCENES.update({"window_room_sun": lambda: window_room("sun"), "window_room_sky": lambda: window_room("sky")})

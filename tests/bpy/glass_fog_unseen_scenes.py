"""Issue 18 acceptance on scenes the corpus does not hold (T8's QA, bench/qa_glass_fog.md).

Scenes of the same kinds as ``glass_fog_scenes.py`` but built differently: a tilted tinted skylight,
double glazing in a vertical wall with a low sun, trick glass on a Solidify modifier, a vertical
Principled pane with a tilted meter, a frosted Principled pane under an area light, a spot and an area
light in denser fog over a floor, a volume cube (not the world) between a lamp and a meter, a glossy
metal floor reflecting an area light onto a wall meter.

Builders use bpy only (no Radiometer measurement code). Each returns ``(scene, cases)`` with cases a
list of ``(label, point, normal)``. ``fresnel_slab`` is this file's own Fresnel slab (written from the
textbook, not from ``radiometry/scene/thin_glass.py``): the closed-form reference for the clear panes.
"""

import importlib.util
import math
import pathlib

import bpy
import numpy as np
from mathutils import Euler, Vector

HERE = pathlib.Path(__file__).resolve().parent


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_gfu_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


base = _load("glass_fog_scenes")  # bpy-only helpers (materials, panes, lights, worlds)

#: Rec.709 luminance weights from the primaries' and D65's chromaticities (ITU-R BT.709): Y row of the
#: RGB -> XYZ matrix, computed here (not the package's table).
def _rec709_y():
    xy = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
    white = np.array([0.3127, 0.3290])
    m = np.stack([xy[:, 0] / xy[:, 1], np.ones(3), (1 - xy[:, 0] - xy[:, 1]) / xy[:, 1]])
    w = np.array([white[0] / white[1], 1.0, (1 - white.sum()) / white[1]])
    return m[1] * np.linalg.solve(m, w)


REC709_Y = _rec709_y()
K_M = 683.0  # lm/W, the package's (and Radiance's) luminous efficacy


def f32(x):
    """Shader inputs are stored as float32 (IOR 1.45 is 1.4500000477)."""
    return float(np.float32(x))


def fresnel_slab(cos_i, ior, thickness=0.006, tint=(1.0, 1.0, 1.0), sigma_a=0.0):
    """Transmittance (RGB) of a plane-parallel slab in air for unpolarised light at incidence cosine
    ``cos_i``: exact Fresnel amplitudes (Hecht 4.42/4.43) per polarisation, the incoherent sum of
    internal reflections, absorption exp(-sigma_a d / cos_t) per pass, and a Glass BSDF's ``tint``
    weighting every interface event (two crossings, two internal reflections per round trip)."""
    cos_i = abs(cos_i)
    sin_t = math.sqrt(max(0.0, 1.0 - cos_i * cos_i)) / ior
    cos_t = math.sqrt(1.0 - sin_t * sin_t)
    rs = ((cos_i - ior * cos_t) / (cos_i + ior * cos_t)) ** 2
    rp = ((ior * cos_i - cos_t) / (ior * cos_i + cos_t)) ** 2
    a = math.exp(-sigma_a * thickness / cos_t)
    c = np.asarray(tint, float)
    return sum(0.5 * c * c * (1 - r) ** 2 * a / (1 - (c * r * a) ** 2) for r in (rs, rp))


def fresnel_slab_r(cos_i, ior, tint=(1.0, 1.0, 1.0)):
    """Reflectance (RGB) of the same non-absorbing slab (needed for two panes in a row)."""
    cos_i = abs(cos_i)
    sin_t = math.sqrt(max(0.0, 1.0 - cos_i * cos_i)) / ior
    cos_t = math.sqrt(1.0 - sin_t * sin_t)
    rs = ((cos_i - ior * cos_t) / (cos_i + ior * cos_t)) ** 2
    rp = ((ior * cos_i - cos_t) / (ior * cos_i + cos_t)) ** 2
    c = np.asarray(tint, float)
    return sum(0.5 * (c * r + c ** 3 * r * (1 - r) ** 2 / (1 - (c * r) ** 2)) for r in (rs, rp))


def lux(e_rgb):
    return K_M * float(np.dot(e_rgb, REC709_Y))


def sun_direction(rotation):
    """Unit vector towards a Blender sun of Euler ``rotation`` (it shines along its local -Z)."""
    return np.array(Euler(rotation).to_matrix() @ Vector((0.0, 0.0, 1.0)))


def _black(name):
    return base._diffuse(name, 0.0)


def _box(scene, name, lo, hi, material):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    return base._quads(scene, name, [
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],   # top (+z)
        [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],   # bottom
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],   # -y
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],   # +y
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],   # -x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)]], material)


# --- closed-form cases (thin glass, delta lights and a 0.53 degree sun) ---------------------------------

SKYLIGHT = {"ior": 1.5, "tint": (0.7, 0.85, 0.9), "thickness": 0.008, "tilt_deg": 30.0,
            "sun_rotation": (math.radians(-10.0), 0.0, math.radians(15.0)), "sun_w": 100.0,
            "point": (0.3, 0.2, 4.0), "point_w": 500.0}


def skylight_tilted(light="SUN"):
    """A tinted 8 mm Glass BSDF pane (IOR 1.5), 1.5 m square, centred 2 m above the meter and tilted
    30 degrees about x (a skylight); the sun (0.53 degree disc, 80 degrees up, crossing the pane at 40
    degrees) or a 500 W point light beyond it."""
    s = SKYLIGHT
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = base.glass_material("skylight tinted", "glass", s["ior"], s["tint"])
    pane = base.add_pane(scene, "Skylight", mat, centre=(0.0, 0.0, 0.0), size=(1.5, 1.5), thickness=s["thickness"])
    pane.location = (0.0, 0.0, 2.0)
    pane.rotation_euler = (math.radians(s["tilt_deg"]), 0.0, 0.0)
    if light == "SUN":
        base._light(scene, "SUN", (0.0, 0.0, 6.0), rotation=s["sun_rotation"], energy=s["sun_w"],
                    angle=math.radians(0.53))
    else:
        base._light(scene, "POINT", s["point"], energy=s["point_w"], shadow_soft_size=0.0)
    return scene, [(f"under a tilted tinted skylight, {light.lower()}", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))]


def skylight_tilted_expected(light):
    s = SKYLIGHT
    n_pane = np.array(Euler((math.radians(s["tilt_deg"]), 0.0, 0.0)).to_matrix() @ Vector((0.0, 0.0, 1.0)))
    tint = tuple(f32(c) for c in s["tint"])
    if light == "SUN":
        d = sun_direction(s["sun_rotation"])
        e_open = s["sun_w"] * d[2]
    else:
        v = np.array(s["point"])
        d = v / np.linalg.norm(v)
        e_open = s["point_w"] / (4 * math.pi) * d[2] / (v @ v)
    T = fresnel_slab(float(d @ n_pane), f32(s["ior"]), s["thickness"], tint)
    return lux(e_open * T)


WALL = {"ior": 1.52, "elevation_deg": 25.0, "sun_w": 100.0, "panes_y": (0.0, 0.02), "thickness": 0.004}


def wall_double_glazing(albedo=0.0, part=None):
    """A black room (floor, walls, ceiling and a desk of albedo 0) behind double glazing (two 4 mm
    Glass BSDF panes, IOR 1.52, 16 mm apart) filling a 2 x 1.2 m opening in the wall y = 0; the sun at
    25 degrees elevation shining straight in (+y). Meters: floor in the sun patch, floor in the shade,
    on the desk in the sun.

    ``albedo``: the room's (0.5: a grey room, rendered references). ``part="sun"``: the reference scene
    of a grey room: the two panes replaced by ONE face of constant thin glass at the sun's angle (T and R
    of the two panes by the adding formula from ``fresnel_slab``): exact for every sun ray; light from
    inside meets it with R(25 deg) instead of its own angle's R (a small part of a small part: the window
    is 1.7 % of the room's surface)."""
    w = WALL
    scene = base.reset()
    base._world(scene, strength=0.0)
    black = base._diffuse("grey room", albedo) if albedo else _black("black room")
    X, Y, H = 3.0, 6.0, 3.0
    x0, x1, z0, z1 = -1.0, 1.0, 0.8, 2.0
    wall = [[(-X, 0, 0), (-X, 0, H), (x0, 0, H), (x0, 0, 0)], [(x1, 0, 0), (x1, 0, H), (X, 0, H), (X, 0, 0)],
            [(x0, 0, 0), (x0, 0, z0), (x1, 0, z0), (x1, 0, 0)], [(x0, 0, z1), (x0, 0, H), (x1, 0, H), (x1, 0, z1)]]
    room = [[(-X, 0, 0), (X, 0, 0), (X, Y, 0), (-X, Y, 0)], [(-X, 0, H), (-X, Y, H), (X, Y, H), (X, 0, H)],
            [(-X, 0, 0), (-X, Y, 0), (-X, Y, H), (-X, 0, H)], [(X, 0, 0), (X, 0, H), (X, Y, H), (X, Y, 0)],
            [(-X, Y, 0), (X, Y, 0), (X, Y, H), (-X, Y, H)]]
    base._quads(scene, "Room", wall + room, black)
    _box(scene, "Desk", (-0.9, 0.8, 0.0), (-0.1, 1.6, 0.75), black)
    mat = base.glass_material("double glazing", "glass", w["ior"])
    if part == "sun":
        T, R = double_glazing_optics()
        pane = base.add_pane(scene, "Constant pane", base.constant_pane_material("double glazing at 25 deg", T, R),
                             centre=(0.0, 0.0, 0.0), size=(x1 - x0, z1 - z0), thickness=0.0)
        pane.location = (0.0, 0.0, 0.5 * (z0 + z1))
        pane.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    for k, y in enumerate(w["panes_y"] if part != "sun" else ()):
        pane = base.add_pane(scene, f"Pane {k + 1}", mat, centre=(0.0, 0.0, 0.0), size=(x1 - x0, z1 - z0),
                             thickness=w["thickness"])
        pane.location = (0.0, y, 0.5 * (z0 + z1))
        pane.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    base._light(scene, "SUN", (0.0, -3.0, 5.0), rotation=(math.radians(90.0 - w["elevation_deg"]), 0.0, 0.0),
                energy=w["sun_w"], angle=math.radians(0.53))
    return scene, [("floor in the sun patch", (0.5, 3.0, 0.0), (0.0, 0.0, 1.0)),
                   ("floor in the shade", (2.5, 3.0, 0.0), (0.0, 0.0, 1.0)),
                   ("desk in the sun", (-0.5, 1.2, 0.75), (0.0, 0.0, 1.0))]


def double_glazing_optics():
    """(T, R) RGB of the two panes at the sun's angle: the incoherent adding formula."""
    w = WALL
    cos_pane = math.cos(math.radians(w["elevation_deg"]))  # the panes' normal is horizontal, along the sun's azimuth
    ior = f32(w["ior"])
    T = fresnel_slab(cos_pane, ior, w["thickness"])
    R = fresnel_slab_r(cos_pane, ior)
    return T * T / (1 - R * R), R + T * T * R / (1 - R * R)


def wall_double_glazing_expected(label):
    if "shade" in label:
        return 0.0
    w = WALL
    return lux(w["sun_w"] * math.sin(math.radians(w["elevation_deg"])) * double_glazing_optics()[0])


TRICK = {"ior": 1.5, "thickness": 0.006, "sun_rotation": (math.radians(50.0), 0.0, math.radians(-30.0)), "sun_w": 80.0}


def trick_solidified():
    """The archviz trick (Light Path > Is Shadow Ray mixes a white Transparent BSDF in for shadow
    rays) on a single plane given its 6 mm by a Solidify modifier; sun at 40 degrees elevation; the
    meter off-centre, where the sun's ray crosses the pane."""
    t = TRICK
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = base.glass_material("trick on solidify", "trick", t["ior"])
    pane = base.add_pane(scene, "Solid pane", mat, centre=(0.0, 0.0, 1.2), size=(1.6, 1.6), thickness=0.0)
    mod = pane.modifiers.new("Solidify", "SOLIDIFY")
    mod.thickness = t["thickness"]
    mod.offset = 0.0
    base._light(scene, "SUN", (0.0, 0.0, 6.0), rotation=t["sun_rotation"], energy=t["sun_w"], angle=math.radians(0.53))
    return scene, [("under trick glass on a Solidify slab", (0.6, 1.0, 0.0), (0.0, 0.0, 1.0))]


def trick_solidified_expected():
    t = TRICK
    d = sun_direction(t["sun_rotation"])
    return lux(t["sun_w"] * d[2] * fresnel_slab(float(d[2]), f32(t["ior"]), t["thickness"]))


PRINCIPLED = {"ior": 1.45, "thickness": 0.005, "point": (2.5, 0.3, 1.4), "point_w": 300.0,
              "normal": (1.0, 0.0, 0.2)}


def principled_vertical():
    """A vertical 1.2 m square Principled BSDF pane (transmission 1, roughness 0, IOR 1.45, 5 mm) in the
    plane x = 1; a 300 W point light 1.5 m beyond it; the meter 1 m before it, tilted up 11 degrees."""
    p = PRINCIPLED
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = base.glass_material("principled pane", "principled", p["ior"])
    pane = base.add_pane(scene, "Principled pane", mat, centre=(0.0, 0.0, 0.0), size=(1.2, 1.2),
                         thickness=p["thickness"])
    pane.location = (1.0, 0.0, 1.0)
    pane.rotation_euler = (0.0, math.radians(90.0), 0.0)
    base._light(scene, "POINT", p["point"], energy=p["point_w"], shadow_soft_size=0.0)
    n = np.array(p["normal"]) / np.linalg.norm(p["normal"])
    return scene, [("facing a vertical Principled pane", (0.0, 0.0, 1.0), tuple(n))]


def principled_vertical_expected():
    p = PRINCIPLED
    v = np.array(p["point"]) - np.array([0.0, 0.0, 1.0])
    d = v / np.linalg.norm(v)
    n = np.array(p["normal"]) / np.linalg.norm(p["normal"])
    e_open = p["point_w"] / (4 * math.pi) * float(d @ n) / (v @ v)
    return lux(e_open * fresnel_slab(float(d[0]), f32(p["ior"]), p["thickness"]))


CLOSED_FORM = {
    "skylight_sun": (lambda: skylight_tilted("SUN"), lambda label: skylight_tilted_expected("SUN"), "tinted glass"),
    "skylight_point": (lambda: skylight_tilted("POINT"), lambda label: skylight_tilted_expected("POINT"),
                       "tinted glass"),
    "wall_double_glazing": (wall_double_glazing, wall_double_glazing_expected, "double glazing"),
    "trick_solidified": (trick_solidified, lambda label: trick_solidified_expected(), "trick glass"),
    "principled_vertical": (principled_vertical, lambda label: principled_vertical_expected(), "Principled glass"),
}


# --- rendered-reference cases (converged patch renders cached in glass_fog_unseen_references.json) ------

def frosted_principled_area():
    """A 2 m square, 6 mm Principled pane (transmission 1, IOR 1.45, roughness 0.4) 1 m above the meter;
    a 0.6 m square area light of 150 W 1.5 m above the pane, 0.3 m aside."""
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = base.glass_material("frosted principled", "principled", 1.45, roughness=0.4)
    base.add_pane(scene, "Frosted pane", mat, centre=(0.0, 0.0, 1.0), size=(2.0, 2.0), thickness=0.006)
    base._light(scene, "AREA", (0.3, 0.0, 2.5), energy=150.0, size=0.6)
    return scene, [("under a frosted Principled pane, area light", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))]


def fog_floor():
    """A world Volume Scatter of density 0.1/m (colour 0.8: sigma_s = 0.08/m) over an 8 m grey floor
    (albedo 0.5); a 200 W spot (35 degrees, blend 0.15) 3 m up and a 1 m square 100 W area light at
    (2.5, 0, 2.5) tilted towards the centre. Meters on the floor under each light and at desk height."""
    scene = base.reset()
    base._world(scene, strength=0.0, fog_density=0.1)
    base._quads(scene, "Floor", [[(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)]], base._diffuse("floor", 0.5))
    base._light(scene, "SPOT", (0.0, 0.0, 3.0), energy=200.0, shadow_soft_size=0.0, spot_size=math.radians(35.0),
                spot_blend=0.15)
    base._light(scene, "AREA", (2.5, 0.0, 2.5), rotation=(0.0, math.radians(-20.0), 0.0), energy=100.0, size=1.0)
    return scene, [("floor under the spot", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
                   ("floor under the area light", (2.5, 0.0, 0.0), (0.0, 0.0, 1.0)),
                   ("desk height between them", (1.2, 0.0, 0.8), (0.0, 0.0, 1.0))]


def _one_node_material(name, node_type, output, inputs, **props):
    """A material of one shader node (its ``inputs`` and ``props`` set) into the Material Output's
    ``output`` socket ("Surface" or "Volume")."""
    mat = bpy.data.materials.new(name)
    tree = base.ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    node = tree.nodes.new(node_type)
    for key, value in props.items():
        setattr(node, key, value)
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    tree.links.new(node.outputs[0], out.inputs[output])
    return mat


def fog_cube():
    """No world volume: a 1.2 m cube of Volume Scatter (density 0.8/m, white, anisotropy 0.3; no
    surface shader) centred 1.5 m above the meter, a 150 W point light 3.2 m up: every segment from the
    meter under the cube to the lamp crosses 1.2 m of it; a second meter 1.5 m aside sees past it."""
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = _one_node_material("fog cube", "ShaderNodeVolumeScatter", "Volume",
                             {"Density": 0.8, "Color": (1.0, 1.0, 1.0, 1.0), "Anisotropy": 0.3})
    _box(scene, "Fog cube", (-0.6, -0.6, 0.9), (0.6, 0.6, 2.1), mat)
    base._light(scene, "POINT", (0.0, 0.0, 3.2), energy=150.0, shadow_soft_size=0.0)
    return scene, [("under a fog cube", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
                   ("beside a fog cube", (1.5, 0.0, 0.0), (0.0, 0.0, 1.0))]


def glossy_wall():
    """A 6 m metal floor (Glossy BSDF GGX, roughness 0.15, colour 0.9), a 0.5 m square 200 W area light
    2.2 m up facing down, a grey wall (albedo 0.5) at x = 2: a meter on the wall 0.6 m up, facing the
    light (direct light plus the floor's glossy reflection of the light)."""
    scene = base.reset()
    base._world(scene, strength=0.0)
    mat = _one_node_material("metal floor 0.15", "ShaderNodeBsdfGlossy", "Surface",
                             {"Roughness": 0.15, "Color": (0.9, 0.9, 0.9, 1.0)}, distribution="GGX")
    base._quads(scene, "Floor", [[(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)]], mat)
    base._quads(scene, "Wall", [[(2, -3, 0), (2, -3, 3), (2, 3, 3), (2, 3, 0)]], base._diffuse("wall", 0.5))
    base._light(scene, "AREA", (0.0, 0.0, 2.2), energy=200.0, size=0.5)
    return scene, [("wall meter lit via a glossy floor", (2.0, 0.0, 0.6), (-1.0, 0.0, 0.0))]


def principled_floor(roughness, **inputs):
    """The glossy wall's floor ("metal floor 0.15") made a Principled BSDF (base colour 0.5, Metallic 0,
    IOR 1.5: a polished stone or lacquered floor) of ``roughness``, with other ``inputs`` set; returns
    the node."""
    mat = bpy.data.materials["metal floor 0.15"]
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    node = tree.nodes.new("ShaderNodeBsdfPrincipled")
    node.inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    node.inputs["Metallic"].default_value = 0.0
    node.inputs["IOR"].default_value = 1.5
    node.inputs["Roughness"].default_value = roughness
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    tree.links.new(node.outputs[0], out.inputs["Surface"])
    return node


def emitting_panel(scene, strength=250.0):
    """Replace the scene's one light by an emitting 0.5 m square mesh ("Panel", Emission ``strength``)
    at its place, facing down (the glossy wall's area light as an emissive mesh)."""
    light = next(ob for ob in scene.objects if ob.type == "LIGHT")
    z = light.location.z
    bpy.data.objects.remove(light)
    mesh = bpy.data.meshes.new("Panel")
    h = 0.25
    mesh.from_pydata([(-h, -h, z), (-h, h, z), (h, h, z), (h, -h, z)], [], [(0, 1, 2, 3)])  # normal -z
    mesh.materials.append(_one_node_material("panel emission", "ShaderNodeEmission", "Surface",
                                             {"Strength": strength}))
    obj = bpy.data.objects.new("Panel", mesh)
    scene.collection.objects.link(obj)
    return obj


RENDERED = {
    "grey_room_glazing": (lambda: wall_double_glazing(0.5), "double glazing"),
    "foggy_room": (lambda: foggy_room(), "fog area"),
    "frosted_principled_area": (frosted_principled_area, "frosted pane"),
    "fog_cube": (fog_cube, "fog point"),
    "glossy_wall": (glossy_wall, "glossy floor"),
    "fog_floor": (fog_floor, "fog spot"),
}
def foggy_room(part=None):
    """The grey room behind the wall's double glazing (``wall_double_glazing(0.5)``) filled with fog: a
    volume object (Volume Scatter, density 0.05/m, colour 0.8: sigma_s = 0.04/m) just inside the room
    (a world volume would swallow the sun: its rays would cross unbounded fog). Meters: the floor in the
    sun patch and in the shade. ``part="sun"``: the reference scene (panes as constant thin glass)."""
    scene, cases = wall_double_glazing(0.5, part=part)
    mat = _one_node_material("room fog", "ShaderNodeVolumeScatter", "Volume", {"Density": 0.05})
    _box(scene, "Room fog", (-2.99, 0.03, 0.001), (2.99, 5.99, 2.99), mat)
    return scene, cases[:2]


#: Rendered references made on another scene than the meter's (make_glass_fog_unseen_references.py).
REFERENCE_SCENES = {"grey_room_glazing": lambda: wall_double_glazing(0.5, part="sun"),
                    "foggy_room": lambda: foggy_room(part="sun")}

"""An HDRI world with a small bright sun disc (issue 18): a meter in the open and one in a black room lit
only through a square opening in its ceiling, with exact references (same interface as fin_scene.py).

World: an equirectangular float image of W x H = 256 x 128 pixels (1.41 deg each), Closest
interpolation, a uniform sky of ``SKY`` W/(m^2 sr) and a 3 x 3-pixel sun disc of ``SUN`` W/(m^2 sr)
(4.2 deg in elevation, 1.4 deg across) at elevations 68.9-73.1 deg (zenith angle <= 21.1 deg), white
(CIE Y 1).
Room: a closed black box (albedo 0), floor z = 0 ... ceiling z = 1 m, 4 x 4 m, with a 1 x 1 m opening
centred above the meter in the ceiling. Meters face +z:
- "open": at (0, 0, 3), above everything: the whole upper hemisphere of the image;
- "room": at (0, 0, 0) on the floor: the sky through the opening, and the sun disc wholly inside it
  (the opening's inscribed cone is 26.6 deg wide at any azimuth, the disc at most 21.1 deg off the
  zenith), so the reference does not depend on the image's azimuth convention.

References (independent of Radiometer's code): a piecewise-constant image's irradiance on a surface
facing the zenith is sum over pixel rows of L x dphi x (sin^2 el_top - sin^2 el_bottom) / 2 (the
integral of sin(el) cos(el) over the row, exact); through the opening, the uniform sky gives
SKY x the opening's projected solid angle (Lambert's contour formula), and the sun disc adds
(SUN - SKY) x its pixels' rows' integrals, the disc being wholly visible.
"""

import math

import numpy as np

W, H = 256, 128
SKY = 0.2           # W/(m^2 sr), white
SUN = 4000.0        # W/(m^2 sr) on 9 pixels
SUN_ROWS = (12, 13, 14)     # rows counted from the top (row 0 touches the zenith)
SUN_COLS = (40, 41, 42)
NORMAL = (0.0, 0.0, 1.0)
OPENING = 0.5      # half side of the ceiling opening (m), centred above the room meter
METERS = {"open": (0.0, 0.0, 3.0), "room": (0.0, 0.0, 0.0)}


def image():
    """(H, W, 3) radiance, top row first."""
    px = np.full((H, W, 3), SKY)
    for i in SUN_ROWS:
        for j in SUN_COLS:
            px[i, j] = SUN
    return px


def _row_factor(i):
    """Integral of sin(el) cos(el) d el over pixel row i (from the top) times the pixel's d phi."""
    top = math.pi / 2 - math.pi * i / H
    bottom = math.pi / 2 - math.pi * (i + 1) / H
    return (2 * math.pi / W) * (math.sin(top) ** 2 - math.sin(bottom) ** 2) / 2 if bottom >= 0 else 0.0


def _opening_psa():
    """Projected solid angle (sr) of the 2 OPENING square 1 m above the room meter, by Lambert's
    contour formula (fin_scene.projected_solid_angle)."""
    import importlib.util
    import pathlib

    spec = importlib.util.spec_from_file_location("fin_scene", pathlib.Path(__file__).with_name("fin_scene.py"))
    fin = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(fin)
    a = OPENING
    return fin.projected_solid_angle((0.0, 0.0, 0.0), NORMAL, [(-a, -a, 1.0), (a, -a, 1.0), (a, a, 1.0), (-a, a, 1.0)])


def reference_lux(label):
    """Exact illuminance (lx) at meter ``label`` and the share of it from the sun disc."""
    sun = (SUN - SKY) * len(SUN_COLS) * sum(_row_factor(i) for i in SUN_ROWS)
    if label == "open":
        sky = SKY * sum(_row_factor(i) for i in range(H // 2)) * W
    else:
        sky = SKY * _opening_psa()
    return 683.0 * (sky + sun), sun / (sky + sun)


def build(scene):
    """Build the scene into ``scene`` (an empty one); returns it."""
    import bpy

    from radiometer.compat import ensure_node_tree
    from radiometer.demo import builders

    builders.metric_cycles_scene(scene)
    rgba = np.concatenate([image(), np.ones((H, W, 1))], axis=-1)[::-1].astype(np.float32)  # bottom row first
    img = bpy.data.images.new("hdri_sun", W, H, float_buffer=True, alpha=False)
    img.pixels.foreach_set(rgba.ravel())
    world = bpy.data.worlds.new("hdri_sun")
    tree = ensure_node_tree(world)
    env = tree.nodes.new("ShaderNodeTexEnvironment")
    env.image, env.interpolation = img, "Closest"
    tree.links.new(env.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world

    a, s = OPENING, 2.0
    quads = [  # floor, four walls, the ceiling as four quads around the opening
        [(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0)],
        [(-s, -s, 0), (-s, -s, 1), (s, -s, 1), (s, -s, 0)], [(s, -s, 0), (s, -s, 1), (s, s, 1), (s, s, 0)],
        [(s, s, 0), (s, s, 1), (-s, s, 1), (-s, s, 0)], [(-s, s, 0), (-s, s, 1), (-s, -s, 1), (-s, -s, 0)],
        [(-s, -s, 1), (-s, s, 1), (-a, s, 1), (-a, -s, 1)], [(a, -s, 1), (a, s, 1), (s, s, 1), (s, -s, 1)],
        [(-a, -s, 1), (-a, -a, 1), (a, -a, 1), (a, -s, 1)], [(-a, a, 1), (-a, s, 1), (a, s, 1), (a, a, 1)],
    ]
    verts = [v for q in quads for v in q]
    mesh = bpy.data.meshes.new("room")
    mesh.from_pydata(verts, [], [tuple(range(4 * k, 4 * k + 4)) for k in range(len(quads))])
    mesh.materials.append(builders.diffuse_material("room", 0.0))
    obj = bpy.data.objects.new("room", mesh)
    scene.collection.objects.link(obj)
    return scene

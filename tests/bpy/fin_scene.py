"""The fin scene of issue 18 (case 5): a meter lit only by a sunlit Lambertian patch of which a black
fin hides most, so the light arrives by a rare path (a thin visible sliver), with its exact reference.

Geometry (metres, unit scale 1, black world):
- patch: a 2 x 2 m square in the plane x = 0, y in [-1, 1], z in [0, 2], facing +x, Diffuse BSDF of
  albedo ``ALBEDO``;
- sun: ``SUN_W`` W/m^2, white, arriving from azimuth 60 deg (direction to the sun (cos 60, sin 60, 0)):
  the patch receives SUN_W cos 60 deg; no meter faces it (each meter faces -x: cos = -0.5);
- fin: a black (albedo 0) quad in the plane x = ``FIN_X``, y in [-1.5, ``FIN_EDGE``], z in [-0.5, 2.5],
  two-sided as Cycles shades it; it hides from a meter at (2, y_m, 1) every patch point with
  y < 2 FIN_EDGE - y_m (its edge seen from the meter projects onto the patch with factor 2). The fin's
  sun shadow falls at y <= FIN_EDGE - 1.73 FIN_X = -1.28, off the patch (1 cm penumbra), so the patch
  is uniformly lit;
- meters at (2, y_m, 1) facing -x (``METERS``): 50 %, 97 % and 99 % of the patch's light hidden.

Reference (independent of Radiometer's code): the patch's exitance under the sun is exact,
M = ALBEDO x E_sun cos 60 deg (nothing else lights it: black world, black fin; the sun's 0.53 deg disc
changes the mean cosine by < 1e-5), so its radiance is L = M / pi; the illuminance at a meter is
L times the projected solid angle of the visible rectangle (Lambert's contour formula for a polygon,
checked here against a midpoint quadrature in ``tests/bpy/test_rare_paths_fin.py``).
"""

import math

import numpy as np

ALBEDO = 0.8
SUN_W = 10.0             # W/m^2 on a surface facing the sun, white (CIE Y = 1)
SUN_AZIMUTH = math.radians(60.0)
FIN_X = 1.0
FIN_EDGE = 0.45
PATCH = ((0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (0.0, 1.0, 2.0), (0.0, -1.0, 2.0))
NORMAL = (-1.0, 0.0, 0.0)
#: label -> meter position; every meter faces NORMAL
METERS = {
    "half hidden": (2.0, 0.68, 1.0),
    "97 % hidden": (2.0, -0.02, 1.0),
    "99 % hidden": (2.0, -0.07, 1.0),
}


def projected_solid_angle(point, normal, vertices):
    """Projected solid angle (sr) of a planar polygon seen from ``point`` on a surface of ``normal``,
    by Lambert's contour formula: 1/2 |sum_i angle(r_i, r_i+1) n . (r_i x r_i+1) / |r_i x r_i+1||
    (the polygon wholly above the surface's horizon)."""
    r = np.asarray(vertices, float) - np.asarray(point, float)
    n = np.asarray(normal, float)
    total = 0.0
    for a, b in zip(r, np.roll(r, -1, axis=0)):
        c = np.cross(a, b)
        total += math.atan2(np.linalg.norm(c), a @ b) * (n @ c) / np.linalg.norm(c)
    return abs(total) / 2.0


def visible_patch(point):
    """The patch's rectangle that the fin leaves visible from ``point`` (vertices), or None."""
    cut = 2.0 * FIN_EDGE - point[1]  # the fin edge's projection from the meter (x = 2) onto x = 0
    lo = max(cut, -1.0)
    if lo >= 1.0:
        return None
    return ((0.0, lo, 0.0), (0.0, 1.0, 0.0), (0.0, 1.0, 2.0), (0.0, lo, 2.0))


def patch_luminance():
    """cd/m^2 of the sunlit patch: ALBEDO x 683 lm/W x SUN_W cos(azimuth) / pi."""
    return ALBEDO * 683.0 * SUN_W * math.cos(SUN_AZIMUTH) / math.pi


def reference_lux(label):
    """Exact illuminance (lx) at meter ``label``, and the share of the patch's light the fin hides."""
    point = METERS[label]
    full = projected_solid_angle(point, NORMAL, PATCH)
    vis = visible_patch(point)
    seen = 0.0 if vis is None else projected_solid_angle(point, NORMAL, vis)
    return patch_luminance() * seen, 1.0 - seen / full


def build(scene):
    """Build the fin scene into ``scene`` (an empty one); returns it."""
    from radiometer.demo import builders

    import bpy

    builders.metric_cycles_scene(scene)
    builders.black_world(scene)
    # A sun light shines along its local -Z: aim it along -(cos az, sin az, 0).
    to_sun = np.array([math.cos(SUN_AZIMUTH), math.sin(SUN_AZIMUTH), 0.0])
    from mathutils import Vector

    rotation = Vector(tuple(-to_sun)).to_track_quat("-Z", "Y").to_euler()
    builders.add_light(scene, "SUN", rotation=tuple(rotation), energy=SUN_W, name="sun")

    def quad(name, verts, albedo):
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([tuple(v) for v in verts], [], [(0, 1, 2, 3)])
        mesh.materials.append(builders.diffuse_material(name, albedo))
        obj = bpy.data.objects.new(name, mesh)
        scene.collection.objects.link(obj)
        return obj

    quad("patch", PATCH, ALBEDO)  # wound so its normal is +x
    quad("fin", [(FIN_X, -1.5, -0.5), (FIN_X, FIN_EDGE, -0.5), (FIN_X, FIN_EDGE, 2.5), (FIN_X, -1.5, 2.5)], 0.0)
    return scene

"""Rare-hit scenes of issue 32's acceptance table (bench/coverage_rare_hits.py), beside the fin scene
(``fin_scene.py``), each with a reference that uses none of Radiometer's measurement code.

- ``SLIT_SKY``: a daylight-factor point that sees the CIE overcast sky through a slit (an urban canyon:
  the window head over the opposite roof line) in a black room, so the DF is the sky component alone.
  Reference: this file's own 2-D Gauss-Legendre integral of the CIE standard overcast luminance
  (CIE S 011 type 1, L = Lz (1 + 2 sin e) / 3, E_h = 7 pi Lz / 9) over the visible part of the window,
  which is a rectangle (``slit_sky_df``).
- ``GLOSSY``: a wall meter lit by a metal floor's glossy reflection (GGX 0.15) of an area light
  (``glass_fog_unseen_scenes.glossy_wall``). Reference: its stored patch render
  (tests/bpy/glass_fog_unseen_references.json, ``reference.reference_irradiance``, 0.1 % target).
- ``SPOT_METAL``: a wall meter outside a spot's cone that sees the spot's reflection in a rough metal
  floor (GGX 0.2). Reference: a patch render (``reference.reference_irradiance``, 0.1 % target, seed 7),
  made by ``python bench/coverage_rare_hits.py refs`` and stored in bench/coverage_rare_hits.json.

Every scene: ``build()`` -> bpy scene; ``METERS``: label -> (point, normal); ``measure(api, scene, point,
normal, quality, seed)`` -> (value, rel_std_error, samples, exact, seconds); ``UNIT`` of the value.
"""

import importlib.util
import math
import pathlib
import time

import bpy
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent


def _load(name):
    spec = importlib.util.spec_from_file_location(name, HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _black(name="black"):
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
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


def _box(x0, x1, y0, y1, z0, z1):
    """The 6 faces of an axis-aligned box (any winding: every surface here is black, two-sided)."""
    return [[(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0)],
            [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],
            [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],
            [(x0, y1, z0), (x1, y1, z0), (x1, y1, z1), (x0, y1, z1)],
            [(x0, y0, z0), (x0, y1, z0), (x0, y1, z1), (x0, y0, z1)],
            [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)]]


class SlitSky:
    """A black room x in [-4, 0], y in [-2, 2], z in [0, 3] m whose wall x = 0 has a window y in [-1, 1],
    z in [1, 2.5]; a black block x in [6, 26], y in [-30, 30], z in [0, ROOF] across the street. A DF
    meter at (-3, 0, 0.8) facing up sees the sky only above the block's roof line: through the window's
    top 0.3 m (z > 0.8 + (ROOF - 0.8) x 3 / 9 = 2.2). Ground reflectance 0 (black), so the DF is the sky
    component alone; the light comes by a rare path (about 0.4 % of cosine-weighted directions)."""

    name = "slit sky"
    UNIT = "% DF"
    ROOF = 5.0
    WINDOW = ((-1.0, 1.0), (1.0, 2.5))  # (y range, z range) in the plane x = 0
    METER = (-3.0, 0.0, 0.8)
    STREET = 6.0  # the block's face, x
    METERS = {"DF point under a slit of sky": ((-3.0, 0.0, 0.8), (0.0, 0.0, 1.0))}
    description = [
        "A black room (4 x 4 x 3 m) with a 2 x 1.5 m window; a black block across the street hides all of",
        "the CIE overcast sky but a 0.3 m slit under the window head (DF meter at desk height facing up,",
        "ground reflectance 0). Reference: the CIE standard overcast luminance L = Lz (1 + 2 sin e) / 3 over",
        "the visible window rectangle by a 400 x 400 Gauss-Legendre rule, / E_h = 7 pi Lz / 9 (written in",
        "tests/bpy/rare_hit_scenes.py, not Radiometer's sky code)."]

    def build(self):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        scene = bpy.context.scene
        black = _black()
        (y0, y1), (z0, z1) = self.WINDOW
        room = [q for k, q in enumerate(_box(-4.0, 0.0, -2.0, 2.0, 0.0, 3.0)) if k != 5]  # all but x = 0
        wall = [[(0.0, -2.0, 0.0), (0.0, 2.0, 0.0), (0.0, 2.0, z0), (0.0, -2.0, z0)],  # below the window
                [(0.0, -2.0, z1), (0.0, 2.0, z1), (0.0, 2.0, 3.0), (0.0, -2.0, 3.0)],  # above
                [(0.0, -2.0, z0), (0.0, y0, z0), (0.0, y0, z1), (0.0, -2.0, z1)],  # left
                [(0.0, y1, z0), (0.0, 2.0, z0), (0.0, 2.0, z1), (0.0, y1, z1)]]  # right
        _quads(scene, "room", room + wall, black)
        _quads(scene, "block", _box(self.STREET, 26.0, -30.0, 30.0, 0.0, self.ROOF), black)
        return scene

    def reference(self, label, n=400):
        """(DF %, relative s.e. 0, share of the hemisphere's cosine-weighted directions that see sky)."""
        return slit_sky_df(self.METER, self.WINDOW, self.STREET, self.ROOF, n)

    def measure(self, api, scene, point, normal, quality, seed):
        t0 = time.perf_counter()
        r = api.daylight_factor(point, normal, scene=scene, quality=quality, ground_reflectance=0.0, seed=seed)
        import re

        found = [int(m.group(1)) for n in r.notes for m in [re.search(r"samples per meter (\d+)", n)] if m]
        return r.daylight_factor, r.rel_std_error, (found[0] if found else None), r.exact, time.perf_counter() - t0


def cie_overcast(sin_e):
    """CIE standard overcast sky (CIE S 011 type 1) luminance / zenith luminance at elevation sin e, and
    the horizontal illuminance it gives / zenith luminance (7 pi / 9)."""
    return (1 + 2 * sin_e) / 3, 7.0 * math.pi / 9.0


def slit_sky_df(meter, window, street_x, roof, n=400, sky=cie_overcast):
    """DF (%) at ``meter`` (facing up, in front of a window in the plane x = 0 spanning ``window`` = (y
    range, z range)) lit by the CIE standard overcast sky seen over a block whose face is at x =
    ``street_x`` and whose roof is at z = ``roof``; also the share of cosine-weighted directions that
    reach the sky. A ray from the meter through (0, y, z) rises, so it clears the roof iff it is above it
    at x = street_x: the visible part of the window is the rectangle z > zc."""
    mx, my, mz = meter
    d = -mx  # horizontal distance from the meter to the window plane
    (y0, y1), (z0, z1) = window
    zc = max(z0, mz + (roof - mz) * d / (street_x - mx))
    if zc >= z1:
        return 0.0, 0.0, 0.0
    g, w = np.polynomial.legendre.leggauss(n)
    y = y0 + (g + 1) / 2 * (y1 - y0)
    z = zc + (g + 1) / 2 * (z1 - zc)
    Y, Z = np.meshgrid(y - my, z - mz, indexing="ij")
    W = np.outer(w, w) * (y1 - y0) * (z1 - zc) / 4
    r = np.sqrt(d * d + Y ** 2 + Z ** 2)
    sin_e = Z / r  # elevation of the direction = cosine at the up-facing meter
    domega = d / r ** 3  # solid angle per window area (cos at the window / r^2)
    relative, horizontal = sky(sin_e)
    e_over_lz = float(np.sum(W * relative * sin_e * domega))
    share = float(np.sum(W * sin_e * domega)) / math.pi
    return 100.0 * e_over_lz / horizontal, 0.0, share


class GlossyWall:
    """glass_fog_unseen_scenes.glossy_wall: the QA's glossy highlight (issue 18, F1)."""

    name = "glossy highlight"
    UNIT = "lx"
    KEY = "glossy_wall/wall meter lit via a glossy floor"
    description = [
        "A 6 m metal floor (Glossy GGX, roughness 0.15, colour 0.9) reflects a 0.5 m, 200 W area light",
        "2.2 m up onto a grey wall; the meter on the wall 0.6 m up faces the light (its direct part a closed",
        "form, the reflection rendered). Reference: the stored patch render",
        "(tests/bpy/glass_fog_unseen_references.json: a white Lambertian patch seen by an orthographic",
        "Cycles camera, 0.1 % target)."]

    def __init__(self):
        self.u = _load("glass_fog_unseen_scenes")
        self.METERS = {"wall meter over the highlight": ((2.0, 0.0, 0.6), (-1.0, 0.0, 0.0))}

    def build(self):
        scene, _cases = self.u.glossy_wall()
        return scene

    def reference(self, label):
        import json

        e = json.loads((HERE / "glass_fog_unseen_references.json").read_text())["values"][self.KEY]
        return self.u.lux(e["E_rgb"]), e["rel_std_error"], None

    def measure(self, api, scene, point, normal, quality, seed):
        t0 = time.perf_counter()
        r = api.measure_illuminance(point, normal, scene=scene, quality=quality, seed=seed)
        return r.illuminance, r.rel_std_error, r.samples, r.exact, time.perf_counter() - t0


class SpotMetal(GlossyWall):
    """A rough metal floor in a spot's beam, seen by a wall meter outside the beam."""

    name = "metal floor in a spot's beam"
    ROUGHNESS = 0.2
    description = [
        "A 6 m metal floor (Glossy GGX, roughness 0.2, colour 0.9), a 500 W spot (point source, 90 deg",
        "cone, blend 0.1) 2.2 m up pointing down, a grey wall (albedo 0.5) at x = 2; the meter on the wall",
        "1.5 m up faces -x: the spot's direct light misses it (71 deg off the axis), the spot's reflection",
        "in the floor (the mirror point 28 deg off the axis) reaches it. Reference: a patch render",
        "(tests/bpy/reference.py, 0.1 % target, seed 7), stored in bench/coverage_rare_hits.json."]

    def __init__(self):
        super().__init__()
        self.METERS = {"wall meter seeing the spot's reflection": ((2.0, 0.0, 1.5), (-1.0, 0.0, 0.0))}
        self.stored = None  # (lux, rel s.e.) set by the bench from its json

    def build(self):
        u = self.u
        scene = u.base.reset()
        u.base._world(scene, strength=0.0)
        mat = u._one_node_material("rough metal floor", "ShaderNodeBsdfGlossy", "Surface",
                                   {"Roughness": self.ROUGHNESS, "Color": (0.9, 0.9, 0.9, 1.0)}, distribution="GGX")
        u.base._quads(scene, "Floor", [[(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)]], mat)
        u.base._quads(scene, "Wall", [[(2, -3, 0), (2, -3, 3), (2, 3, 3), (2, 3, 0)]], u.base._diffuse("wall", 0.5))
        u.base._light(scene, "SPOT", (0.0, 0.0, 2.2), energy=500.0, spot_size=math.radians(90.0), spot_blend=0.1,
                      shadow_soft_size=0.0)
        return scene

    def reference(self, label):
        if self.stored is None:
            raise RuntimeError("make the spot reference first: bench/coverage_rare_hits.py refs")
        return self.stored[0], self.stored[1], None


SCENES = {"slit sky": SlitSky, "glossy highlight": GlossyWall, "spot metal": SpotMetal}

"""Sample floors for meters whose rendered light comes by paths a pilot can miss (issue 18).

A pilot of 512-768 samples that finds *some* light is trusted by the stopping rule unless it is dark
(``allocation.DARK_FLOOR``) or heavy-tailed (``allocation.HEAVY_TAIL``). A glossy highlight escapes both
and read low with a confident error (bench/qa_glass_fog.md F1); it gets a floor of samples that every
such meter takes before its error is trusted (``meter.world_floor`` is the world's):

* ``highlight_floor``: a glossy reflector above the meter's horizon in which a light's specular image
  falls: a metal (roughness at least ``glass.SHARP_ROUGHNESS``, at most ``GLOSSY_ROUGHNESS_MAX``) or a
  dielectric's specular or coat layer (at most ``DIELECTRIC_ROUGHNESS_MAX``); the light is a light
  object or an emitting mesh (its image taken from its area-weighted centre). Its
  highlight is a small bright region: a cosine-sampled path from the meter hits it with probability
  p = (Omega_image + Omega_lobe) cos / pi, Omega_image the light's solid angle seen in the mirror,
  Omega_lobe = pi (LOBE_WIDTH alpha)^2 the GGX reflected lobe (alpha = roughness^2). The floor is
  ``HIGHLIGHT_HITS`` / p samples (at most ``DARK_FLOOR``): about that many paths find the highlight.

A sample floor for meters under fog (F2) was measured and not kept: bench/volume_floor.py.

Host code (reads materials through bpy); the maths is numpy.
"""

import math

import bpy
import numpy as np

from ...radiometry.sampling import allocation
from ...radiometry.scene import visibility
from ...radiometry.emitters.base import RayVisibility
from ..capture import glass

#: Largest Cycles roughness r whose highlight gets a floor. Above it the lobe (alpha = r^2 >= 0.25,
#: about 19 degrees wide) is broad and the formula's floor falls below the pilot itself; measured on the
#: glossy wall scene (bench/glossy_highlight_floor.py): see bench/qa_glass_fog.md.
GLOSSY_ROUGHNESS_MAX = 0.5

#: Expected number of pilot paths that find the highlight (Poisson: fewer than half of them with
#: probability below 1e-6, and a batch-means variance that sees the highlight's spread).
HIGHLIGHT_HITS = 100

#: Half width of the GGX reflected lobe in units of alpha: D falls to half at tan(theta_h) =
#: alpha sqrt(sqrt(2) - 1) = 0.64 alpha, doubled by reflection.
LOBE_WIDTH = 1.3

_METAL_NODES = ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfMetallic")


#: Largest roughness of a dielectric highlight (a Principled BSDF's specular or coat layer) that gets a
#: floor: its Fresnel reflection is a few % at normal incidence, so a wider lobe's highlight is too weak
#: to hide from a pilot. Measured on the glossy wall scene with a Principled floor (base colour 0.5,
#: IOR 1.5; bench/glossy_highlight_floor.json, docs/errors.md): roughness 0.15 covered 70 % of 50 seeds
#: without a floor.
DIELECTRIC_ROUGHNESS_MAX = 0.3


def _roughness_of(node, name):
    """The node's ``name`` roughness (SHARP_ROUGHNESS when linked: a texture may be that smooth somewhere)."""
    socket = node.inputs.get(name)
    if socket is None:
        return None
    return glass.SHARP_ROUGHNESS if socket.is_linked else float(socket.default_value)


def _specular_principled(material, gate):
    """Principled BSDFs of ``material`` whose ``gate`` input is linked or not 0 and that reflect (an IOR
    other than 1, or linked)."""
    nodes = glass.closure_nodes(material, (), gate)[0]
    ior = {"Specular IOR Level": "IOR", "Coat Weight": "Coat IOR"}[gate]
    return [nd for nd in nodes if nd.inputs.get(ior) is None or nd.inputs[ior].is_linked
            or float(nd.inputs[ior].default_value) != 1.0]


def glossy_roughness(material):
    """Smallest roughness of a glossy reflector in ``material`` whose highlight gets a floor, or None:
    a metal-like closure (Glossy, Anisotropic, Metallic BSDF, a Principled BSDF with Metallic > 0 or
    linked) of roughness in [SHARP_ROUGHNESS, GLOSSY_ROUGHNESS_MAX], or a dielectric one (a Principled
    BSDF's specular layer, or its coat) in [SHARP_ROUGHNESS, DIELECTRIC_ROUGHNESS_MAX]."""
    candidates = [(_roughness_of(nd, "Roughness"), GLOSSY_ROUGHNESS_MAX)
                  for nd in glass.closure_nodes(material, _METAL_NODES, "Metallic")[0]]
    candidates += [(_roughness_of(nd, "Roughness"), DIELECTRIC_ROUGHNESS_MAX)
                   for nd in _specular_principled(material, "Specular IOR Level")]
    candidates += [(_roughness_of(nd, "Coat Roughness"), DIELECTRIC_ROUGHNESS_MAX)
                   for nd in _specular_principled(material, "Coat Weight")]
    # (1e-6: Blender stores roughness in float32, 0.3 reads 0.30000001)
    rough = [r for r, top in candidates if r is not None and glass.SHARP_ROUGHNESS - 1e-6 <= r <= top + 1e-6]
    return min(rough) if rough else None


def glossy_triangles(model):
    """((T, 3, 3) triangles in m, (T,) object names, (T,) roughness) of the render-visible objects,
    visible to glossy rays, whose material is a glossy reflector (``glossy_roughness``)."""
    from ..blender.identity import geometry_objects

    g = model.geometry
    rough = np.full(len(g.object_names), np.nan)
    for k, obj in enumerate(geometry_objects(g)):
        if obj is None or not obj.visible_glossy:
            continue
        values = [r for r in (glossy_roughness(slot.material) for slot in obj.material_slots) if r is not None]
        if values:
            rough[k] = min(values)
    keep = ~np.isnan(rough)
    if not keep.any():
        return np.zeros((0, 3, 3)), np.zeros(0, dtype=object), np.zeros(0)
    index = np.asarray(g.object_index, int)
    chosen = keep[index]
    return (np.asarray(g.triangles, float)[chosen], np.asarray(g.object_names, dtype=object)[index[chosen]],
            rough[index[chosen]])


def _mesh_image_solid_angle(mesh, centre, at, path_length):
    """Solid angle (sr) of an emitting mesh's mirror image seen over a path of ``path_length`` m from the
    mirror point ``at``: its triangles' area projected towards ``at`` from its centre, over path^2."""
    towards = np.asarray(at, float) - centre
    towards = towards / max(float(np.linalg.norm(towards)), 1e-300)
    return float(np.sum(mesh.areas_m2 * np.abs(mesh.normals @ towards))) / path_length ** 2


def _highlight_sources(model):
    """(name, position m or None, unit vector to a light at infinity or None, solid_angle(at, path)) of
    every light and emitting mesh that a glossy reflector can show as a highlight. An emitting mesh is
    seen from its area-weighted centre (a compact emitter's image is where the floor matters; a long
    strip's other parts only add to it)."""
    out = []
    for light in model.lights:
        spec = light.spec
        if spec is None or light.portal or not light.reaches_diffuse:
            continue
        sun = not spec.has_position
        out.append((light.name, None if sun else np.asarray(spec.position, float),
                    -np.asarray(spec.emission_direction, float) if sun else None,
                    spec.mirror_image_solid_angle))
    for mesh in getattr(model, "emissive_meshes", None) or ():
        area = float(np.sum(mesh.areas_m2))
        if not mesh.visibility & RayVisibility.GLOSSY or area <= 0.0:
            continue
        centre = np.einsum("t,tk->k", mesh.areas_m2, mesh.triangles.mean(axis=1)) / area
        out.append((mesh.name, centre, None,
                    lambda at, path, mesh=mesh, centre=centre: _mesh_image_solid_angle(mesh, centre, at, path)))
    return out


def highlight_floor(model, points_m, normals):
    """((N,) samples each meter takes at least, or None; names "'light' in 'reflector'") for meters
    that see a light's or an emitting mesh's specular image in a glossy reflector above their horizon
    (module doc)."""
    n = len(points_m)
    sources = _highlight_sources(model)
    if not sources or not model.geometry.count:
        return None, []
    tris, owners, rough = glossy_triangles(model)
    if not len(tris):
        return None, []
    lobe = math.pi * (LOBE_WIDTH * rough ** 2) ** 2
    floor = np.zeros(n, int)
    names = set()
    for name, position, to_sun, solid_angle in sources:
        for k in range(n):
            hit, _image, at = visibility.mirror_images(points_m[k], tris, position, to_sun)
            for j in np.flatnonzero(hit):
                d = at[j] - points_m[k]
                r = float(np.linalg.norm(d))
                cos = float(normals[k] @ d) / r if r > 0 else 0.0
                if cos <= 0.0:  # the mirror point is below the meter's horizon
                    continue
                path = r + (0.0 if position is None else float(np.linalg.norm(position - at[j])))
                p = (solid_angle(at[j], path) + lobe[j]) * cos / math.pi
                need = allocation.DARK_FLOOR if p <= 0 else min(allocation.DARK_FLOOR, math.ceil(HIGHLIGHT_HITS / p))
                if need > allocation.PILOT_MIN_SAMPLES:
                    floor[k] = max(floor[k], need)
                    names.add(f"{name!r} in {owners[j]!r}")
    return (floor if floor.any() else None), sorted(names)

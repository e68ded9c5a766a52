"""Meters sealed off from every source (issue 31, dark meters): a reading that is exactly 0 by proof.

A closed surface (every edge shared by exactly two triangles, ``sky_aperture.closed_components``) parts
space in two: a path from a point of odd crossing parity to one of even parity crosses it. When its
triangles are opaque and stop every kind of ray (``SceneGeometry.sealing_triangles``: diffuse, glossy,
transmission, shadow and volume rays see them, no holdout), no light path crosses it: light is absorbed
or reflected back to the side it came from. So a meter on one side of such a shell receives nothing
from a source wholly on the other side. A meter for which every source of the scene is cut off by some
shell reads exactly 0 with no sample spent (a box outside a closed room whose lights are all inside, a
meter in a closed cupboard of a daylit room).

What is proven, and what is refused (then nothing is proven and the meter is measured as before):
* the sources: every light's emitter answers ``extent()`` (points and reach), the emissive meshes by
  their triangles; the sun and the world lie at infinity, outside every shell; a light that casts no
  shadow (its light goes through surfaces), one without a known extent, an object with shadow linking
  (blockers), or a participating medium (its shader may emit) proves nothing;
* a source's whole extent is on one side of a shell: the box around it, grown by its reach and the
  tolerance, meets none of the shell's triangles (separating axes, every doubt read as "meets"), and
  the box's centre's side is decided by the crossing parity;
* the meter's side is decided by the crossing parity (a meter within the tolerance of the shell: not
  decided, so not proven);
* materials: only shader nodes through which no light passes (``shader_kinds.SEALING_SHADERS``, a
  whitelist: a Principled BSDF without alpha, transmission or subsurface, diffuse, glossy, metallic, sheen,
  toon, emission and their mixes), inside node groups too; geometry that is not triangulated (curves,
  point clouds, particle hair) proves nothing;
* tolerances: vertices welded within two float32 steps of the shell's largest coordinate
  (``WELD_FLOAT32_STEPS``); a crack narrower than that between two objects' edges counts as closed.
"""

import numpy as np

from . import visibility
from ..skies import sky_aperture

__all__ = ["source_extents", "sealed_off"]

_CUBE = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])


#: How far apart (in float32 steps of the largest coordinate) two vertices may be and still be one vertex of a
#: shell: a slit narrower than this reads as closed (2 steps: 0.5 mm at 2 km from the origin, 0.24 um at 1 m).
WELD_FLOAT32_STEPS = 2.0


def source_extents(model):
    """Every source of the model that emits: a list of (points (K, 3) m, reach m) or "infinity" (the sun,
    the world), or None when some source's extent is unknown or its light ignores surfaces."""
    if model.volumes or model.world_volume:
        return None  # a volume's shader may emit: its light's extent is not read
    if model.needs.get("blocker_linking", False):
        return None  # an object's shadow linking may let its light through the shell
    if model.geometry.unmodelled or model.needs.get("hair_particles", False):
        return None  # geometry not triangulated (curves, point clouds, particle hair) may emit or leak
    out = []
    for light in model.lights:
        if light.portal:
            continue  # guides world sampling, emits nothing
        if light.spec is None or not light.casts_shadow:
            return None
        if not light.spec.has_position:
            out.append("infinity")
            continue
        extent = light.spec.extent()
        if extent is None:
            return None
        out.append(extent)
    for mesh in model.emissive_meshes:
        extent = mesh.extent()
        if extent is None:
            return None
        out.append(extent)
    if model.needs.get("emissive_surfaces", False) and not model.emissive_meshes:
        return None  # surfaces emit, but were not read as emitters
    if model.world_emits:
        out.append("infinity")
    return out


def _box(points, grow):
    lo, hi = points.min(axis=0) - grow, points.max(axis=0) + grow
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    return centre, (centre + _CUBE * half, np.eye(3), np.eye(3))


def sealed_off(model, points_m):
    """(N,) bool: meters at ``points_m`` (N, 3) m that no source of ``model`` can reach (every source is
    cut off from them by a closed shell of sealing triangles); and a note (str) saying how, or ""."""
    points_m = np.atleast_2d(np.asarray(points_m, float))
    none = np.zeros(len(points_m), bool)
    g = model.geometry
    sources = source_extents(model)
    if not sources or not g.count:
        return none, ""
    sealing = g.triangles[g.sealing_triangles()]
    if not len(sealing):
        return none, ""
    # Vertices are welded within two float32 steps of the shell's own coordinates (its mesh and transform
    # were float32): a gap wider than that is a gap.
    shell_tol = WELD_FLOAT32_STEPS * np.finfo(np.float32).eps * max(1.0, float(np.max(np.abs(sealing))))
    shells = sky_aperture.closed_components(sealing, shell_tol)
    if not shells:
        return none, ""
    # cut[s] (N,) bool: source s is cut off from each meter by some shell
    cut = np.zeros((len(sources), len(points_m)), bool)
    for idx in shells:
        tris = sealing[idx]
        meter_side = np.array([{True: 1, False: 0, None: -1}[v]
                               for v in sky_aperture.inside_enclosures(points_m, tris, [], shell_tol)])
        for s, source in enumerate(sources):
            if isinstance(source, str):
                side = 0  # at infinity: outside every shell
            else:
                points, reach = np.asarray(source[0], float).reshape(-1, 3), float(source[1])
                centre, box = _box(points, reach + shell_tol)
                if np.any(visibility.triangles_meet_polytope(tris, box, shell_tol)):
                    continue  # the source may touch or cross this shell: it cuts nothing off
                inside = sky_aperture.inside_enclosure(centre, tris, [], shell_tol)
                if inside is None:
                    continue
                side = int(inside)
            cut[s] |= (meter_side >= 0) & (meter_side != side)
    dark = np.all(cut, axis=0)
    if not dark.any():
        return dark, ""
    return dark, ("sealed off: a closed opaque shell of surfaces that stop every ray lies between the meter and "
                  "every light source: exactly 0, nothing rendered (radiometry/scene/sealed.py)")

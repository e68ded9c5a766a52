"""The sun's first bounce as emitters (issue 31, the low sun): the Blender side of
``radiometry.scene.sun_patches``, in the meter's room: the analyses (``sun_study``) call it.

Where every sunlit surface is Lambertian (``shader_kinds.lambertian_albedo``) and everything the sun meets
is modelled (opaque triangles, recognised thin panes; no refractor, medium or see-through caster),
the sun's light after its first bounce is exactly the light of one-sided Lambertian emitters of radiance
rho E / pi over the sunlit polygons. ``sun_study_step`` then hides the sun, adds those emitters (one mesh
object, removed by the scene guard) and lets the meter read the sun's direct light in closed form and render
only what the emitters give, which Cycles samples by next-event estimation: a 2 deg sun's strip on a reveal
is an area light like any other, instead of a target that a meter's diffuse rays hit by chance.

The emitters: one n-gon per sunlit piece, one layer per cubature direction (cutting them into disjoint
pieces with summed irradiances was tried: the cuts cost more time than the layers), direction k's layer
(k + 1) x 0.1 mm in front of its surface so that Cycles' float32 geometry never puts it behind. The material
adds a Transparent BSDF (rays pass as if it were not there) to an Emission whose colour is the piece's
radiance (a face attribute) on the front side only (Geometry > Backfacing; light sampling of the front
only). It casts no shadow.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

#: Seconds the sunlit polygons of one step may take (all cubature directions) before the step renders the sun as
#: before: the demo room's take about 0.25 s; a scene of 10^5 triangles would take minutes.
GEOMETRY_SECONDS = 10.0
#: Offset of the emitters in front of their surfaces (m) per cubature direction (k + 1 times this).
EMITTER_OFFSET_M = 1e-4
ATTRIBUTE = "radiometer_sun_radiance"
NAME = "Radiometer sun's first bounce"


@dataclasses.dataclass
class SunBounce:
    """The sunlit pieces per cubature direction (``pieces``: [``SunPieces``]), the albedo (T, 3) per
    triangle (NaN where not Lambertian), ``proven`` and ``reason``, ``seconds``, ``notes``."""

    pieces: list
    albedo: np.ndarray
    proven: bool
    reason: str = ""
    seconds: float = 0.0
    notes: list = dataclasses.field(default_factory=list)

    def piece_count(self):
        return sum(len(p.polygons) for p in self.pieces)


def receiver_albedo(model):
    """(T, 3) the Lambertian albedo of each captured triangle (NaN where its material is not Lambertian or
    its object does not stop every ray), and {object index: why not}."""
    from ..blender import identity
    from ..capture import shader_kinds

    g = model.geometry
    albedo = np.full((g.count, 3), np.nan)
    objects = identity.geometry_objects(g)
    slots = g.material_slot if g.material_slot is not None else np.zeros(g.count, int)
    why, cache = {}, {}
    for k, ob in enumerate(objects):
        rows = np.flatnonzero(g.object_index == k)
        if not len(rows):
            continue
        if ob is None:
            why[k] = f"object {g.object_names[k]!r} not found"
            continue
        if len(g.seals) > k and not g.seals[k]:
            why[k] = f"object {g.object_names[k]!r} lets some rays through (its ray visibility)"
            continue
        materials = [s.material for s in ob.material_slots] if len(ob.material_slots) else []
        for j in np.unique(slots[rows]):
            material = materials[j] if 0 <= j < len(materials) else None
            key = material.as_pointer() if material is not None else 0
            if key not in cache:
                cache[key] = shader_kinds.lambertian_albedo(material)
            rgb, reason = cache[key]
            if rgb is None:
                why.setdefault(k, reason)
                continue
            albedo[rows[slots[rows] == j]] = rgb
    return albedo, why


#: The disc's cubature for a relative target: degree 2 (3 directions) while its error, of order (a l / w)^3
#: (about 1.5e-3 for the demo's 8 cm strip lit past an edge 2 m away), stays below a fifth of the target;
#: Stroud's degree 5 (7 directions) for tighter targets (the reference preset's 0.2 %).
DEGREE_2_FROM_TARGET = 0.0075


def plan(model, direction, radius_rad, target_rel_error=None):
    """The sun's first bounce for the sun in ``direction`` (unit, towards it; scene axes) with a disc of
    angular radius ``radius_rad``: a :class:`SunBounce`, ``proven`` False with the reason where a condition
    fails (the caller then renders the sun as before). ``target_rel_error`` picks the disc's cubature
    (``DEGREE_2_FROM_TARGET``; None: degree 5)."""
    from ...radiometry.scene import scene_model, sun_patches, thin_glass

    started = time.perf_counter()
    g = model.geometry

    def refuse(reason):
        return SunBounce([], np.zeros((g.count, 3)), False, reason, time.perf_counter() - started)

    if model.refractors:
        return refuse("a refracting object (not a thin pane) may bend the sun's light")
    if model.volumes or model.world_volume:
        return refuse("a medium scatters the sun's light")
    if g.unmodelled:
        return refuse("render-visible geometry is not triangulated (" + ", ".join(map(str, g.unmodelled[:3])) + ")")
    # a sunlit mirror or glossy surface is refused below (not Lambertian)
    panes = list(model.panes.values())
    if thin_glass.parallel_stacks(model.panes):
        return refuse("multiple glazing (the light between its panes is not cast)")
    pane_tri = g.pane_of >= 0
    opaque = np.asarray(g.opaque, bool)
    casts = g.shadow_triangles()
    if np.any(casts & ~opaque & ~pane_tri):
        return refuse("a see-through surface that is not a thin pane casts shadows")
    occluders = casts & opaque & ~pane_tri
    receivers = opaque & ~pane_tri
    if not g.count:
        return refuse("the scene has no surfaces")
    albedo, why = receiver_albedo(model)
    tol = 4.0 * scene_model.length_tolerance(g.triangles.reshape(-1, 3))
    degree = 2 if target_rel_error is not None and target_rel_error >= DEGREE_2_FROM_TARGET else 5
    dirs, weights = sun_patches.disc_cubature(direction, radius_rad, degree=degree)
    slots = g.material_slot if g.material_slot is not None else np.zeros(g.count, int)
    # receivers merge only within one object's material slot (one albedo)
    groups = np.unique(np.stack([g.object_index, slots], axis=1), axis=0, return_inverse=True)[1].ravel()
    surfaces = sun_patches.surfaces(g.triangles, receivers, occluders, groups=groups, tol=tol)
    pieces = []
    for d, w in zip(dirs, weights):
        p = sun_patches.sunlit_pieces(surfaces, None, None, d, panes=panes, tol=tol, weight=w,
                                      deadline=started + GEOMETRY_SECONDS)
        if not p.proven:
            return refuse(p.reason)
        lit = np.unique(p.triangle)
        bad = lit[~np.all(np.isfinite(albedo[lit]), axis=1)]
        if len(bad):
            k = int(g.object_index[bad[0]])
            return refuse(f"the sun lights a surface that is not Lambertian: {why.get(k, g.object_names[k])}")
        pieces.append(p)
    out = SunBounce(pieces, albedo, True, "", time.perf_counter() - started)
    mirrored = sum(k == "mirror" for p in pieces for k in p.kind)
    out.notes.append(
        f"the sun's first bounce as emitters (radiometry/scene/sun_patches.py): {out.piece_count()} sunlit "
        f"pieces of Lambertian surfaces ({mirrored} lit by the sun's image in a pane) over a {len(dirs)}-point "
        f"cubature of the sun's disc (exact to degree {degree}), each emitting rho E / pi; the sun itself was "
        f"hidden and its direct light read in closed form ({out.seconds:.2f} s of geometry)")
    return out


def emitter_material(name):
    """A new material: the face attribute ``ATTRIBUTE`` as emitted radiance on the front side, plus a
    Transparent BSDF (rays pass through)."""
    import bpy

    from ...compat import ensure_node_tree

    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    attr = tree.nodes.new("ShaderNodeAttribute")
    attr.attribute_type = "GEOMETRY"
    attr.attribute_name = ATTRIBUTE
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    tree.links.new(attr.outputs["Vector"], emission.inputs["Color"])
    clear_front = tree.nodes.new("ShaderNodeBsdfTransparent")
    clear_back = tree.nodes.new("ShaderNodeBsdfTransparent")
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(clear_front.outputs[0], add.inputs[0])
    tree.links.new(emission.outputs[0], add.inputs[1])
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
    tree.links.new(add.outputs[0], mix.inputs[1])
    tree.links.new(clear_back.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    mat.cycles.emission_sampling = "FRONT"
    return mat


def add_emitters(request, bounce, sun_rgb):
    """Inside the caller's guard: the emitters of ``bounce`` as one mesh object linked to the scene;
    ``sun_rgb`` (3,): the sun's normal irradiance per channel in the render's units (the Sun light's
    strength x colour). Returns the object."""
    import bpy

    from ..capture.scene_capture import EMITTER_PROP

    scale = request.scale_length
    verts, faces, radiance = [], [], []
    for k, pieces in enumerate(bounce.pieces):
        lift = (k + 1) * EMITTER_OFFSET_M
        for poly, tri, n, e in zip(pieces.polygons, pieces.triangle, pieces.normal, pieces.irradiance):
            start = len(verts)
            verts.extend(((poly + lift * n) / scale).tolist())
            faces.append(tuple(range(start, start + len(poly))))
            radiance.append(bounce.albedo[tri] * e * np.asarray(sun_rgb, float) / math.pi)
    mesh = bpy.data.meshes.new(NAME)
    mesh.from_pydata(verts, [], faces)
    attr = mesh.attributes.new(ATTRIBUTE, "FLOAT_VECTOR", "FACE")
    if radiance:
        attr.data.foreach_set("vector", np.asarray(radiance, np.float32).ravel())
    mesh.materials.append(emitter_material(NAME))
    mesh.update()
    obj = bpy.data.objects.new(NAME, mesh)
    obj[EMITTER_PROP] = "the sun's first bounce"  # the capture reads it as an emitter, not a refractor
    obj.visible_shadow = False
    request.scene.collection.objects.link(obj)
    return obj

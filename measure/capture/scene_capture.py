"""Capture the scene exactly as Cycles renders it, into a pure ``radiometry.scene.scene_model.SceneModel``.

The viewport depsgraph is not what Cycles renders: it drops objects disabled in viewports, keeps
collections disabled in renders, evaluates modifiers and geometry nodes at viewport settings and
instances particles at the viewport display percentage. The only faithful source is the RENDER
depsgraph, and Blender hands it to a render engine. So a capture registers a tiny render engine
for the duration of the call and renders one 4 x 4 frame with it inside
``scene_guard.preserved_scene``: its ``render(depsgraph)`` reads every light and every triangle that
Cycles would receive (instances, render visibility, ray-visibility and shadow flags, evaluated
transforms incl. shear), then the scene is restored. The engine is unregistered again at once, so
it never shows in the Render Engine menu.

Three walks share that probe: ``capture`` reads everything; ``capture_lights`` reads the lights only
(the geometry kept); ``capture_partial`` reads everything but the triangles of instances no edit
reached, which it keeps from an earlier capture (``capture_cache`` decides which; issue 17). After
edits of lights alone (data, node trees, a light object moved), ``relight`` replays the light instances
a probe recorded (``LightRecord``) with their data-blocks and matrices read again, and renders nothing.
"""

import dataclasses
import hashlib
import math

import bpy
import numpy as np

from ...errors import RadiometerError
from ...radiometry.scene import scene_model
from ...compat import active_node_tree
from ..blender import scene_guard
from . import scene_lights, shader_kinds
from ..blender.identity import object_identity, source_objects  # noqa: F401 (callers use scene_capture.source_objects)

_GEOMETRY_TYPES = shader_kinds.GEOMETRY_TYPES
_MESHABLE = {"MESH", "CURVE", "SURFACE", "META", "FONT"}

#: Beyond this many triangles the proofs are skipped (memory, time): the scene is rendered.
MAX_TRIANGLES = 4_000_000
#: Custom property on Radiometer's own temporary emitters (``measure.meter.sun_bounce``).
EMITTER_PROP = "radiometer_emitter"


class _Capture:
    """State shared with the render callback (one capture at a time)."""

    exclude = frozenset()
    scale = 1.0  # metres per scene unit: triangles are stored in metres
    result = None
    error = None
    lights_only = False  # capture_lights: walk the lights only, the geometry is kept from a capture
    previous = None  # capture_partial: the instances of an earlier capture whose triangles may be kept
    reread = None  # capture_partial: reread(original, data, parent) -> True when they must be read again
    instances = None  # a dict to fill with this capture's instances (capture_cache keeps it for the next)
    light_records = None  # a list to fill with one LightRecord per light instance (``relight`` replays them)
    view_layer = None  # the name of the view layer to read (the probe renders no other)


def _material_traits(material):
    """(opaque, emissive, glossy, transmission, volume, null surface, seals, black) of a material as Cycles
    shades it. A null surface: the active output has a Volume and no Surface (a fog box): Cycles renders the
    boundary as a null interface that neither blocks nor reflects light; the medium is in ``volumes``.
    ``seals``: only shader nodes through which no light passes (``shader_kinds.seals``: sealed shells).
    ``black``: provably sends no light at all (``_black_surface``)."""
    if material is None:  # Cycles' default surface: grey diffuse
        return True, False, False, False, False, False, True, False
    from ...compat import active_node_tree

    tree = active_node_tree(material)
    types = shader_kinds.node_types(tree)  # a Principled BSDF's alpha/transmission read as Transparent (groups too)
    transmissive = bool(types & shader_kinds.TRANSMISSIVE_NODES)
    volume = shader_kinds.uses_volume(tree)
    return (not transmissive and not volume, bool(types & shader_kinds.EMISSIVE_NODES),
            bool(types & shader_kinds.GLOSSY_NODES), transmissive, volume, volume and _volume_only(tree),
            not volume and shader_kinds.seals(types), _black_surface(tree))


def _active_output(tree):
    """The Material Output node Cycles renders (targeting Cycles or all engines: ``get_output_node("CYCLES")``, not an
    EEVEE-only one), unmuted, or None."""
    node = tree.get_output_node("CYCLES")
    return node if node is not None and not node.mute else None


def _live_links(socket):
    """The valid, unmuted links into ``socket`` (none for a missing socket)."""
    return [link for link in socket.links if link.is_valid and not link.is_muted] if socket is not None else []


def _black_surface(tree):
    """True when the material provably reflects, transmits and emits nothing: the output Cycles renders takes a
    Surface from one Diffuse BSDF whose Color is unlinked and (0, 0, 0), and no Volume (a black room's walls,
    a black card). Cycles drops a closure of zero weight, so such a surface only stops rays. Anything else
    (a Principled BSDF keeps its specular layer at base colour 0) may reflect."""
    output = _active_output(tree) if tree is not None else None
    if output is None:
        return False
    surface, volume = _live_links(output.inputs.get("Surface")), _live_links(output.inputs.get("Volume"))
    if len(surface) != 1 or volume:
        return False
    node = surface[0].from_node
    colour = node.inputs.get("Color") if node.bl_idname == "ShaderNodeBsdfDiffuse" and not node.mute else None
    return colour is not None and not colour.is_linked and all(float(c) == 0.0 for c in colour.default_value[:3])


def _volume_only(tree):
    """True when the material's output Cycles renders takes a Volume and no Surface (issue 18, F5)."""
    output = _active_output(tree)
    if output is None:
        return False
    return bool(_live_links(output.inputs.get("Volume"))) and not _live_links(output.inputs.get("Surface"))


def _emission_radiance(material):
    """(3,) radiance per channel (render units: W/(scene unit^2 sr)) of a material that is one plain
    emitter (Material Output <- Emission, or <- Principled BSDF with only emission), else None.
    Cycles' Emission strength is radiance ("1.0 gives the Color input in the image")."""
    from ...compat import active_node_tree

    tree = active_node_tree(material) if material is not None else None
    output = _active_output(tree) if tree is not None else None
    if output is None:
        return None
    links = _live_links(output.inputs.get("Surface"))
    if len(links) != 1:
        return None
    node = links[0].from_node
    names = {"ShaderNodeEmission": ("Color", "Strength"),
             "ShaderNodeBsdfPrincipled": ("Emission Color", "Emission Strength")}.get(node.bl_idname)
    if names is None or node.mute:
        return None
    colour, strength = (node.inputs.get(k) for k in names)
    if colour is None or strength is None or colour.is_linked or strength.is_linked:
        return None
    return np.array(colour.default_value[:3], float) * float(strength.default_value)


def _source_id(inst, original, part=-1):
    """The emitter's stable identity (``radiometry.emitters.SourceId``): object session uid, library,
    the instance's persistent id, and a part index (material slot)."""
    from ...radiometry.emitters import SourceId

    uid, library = object_identity(original)
    instance = tuple(int(k) for k in inst.persistent_id) if inst.is_instance else ()
    return SourceId(uid, library, instance, int(part))


def _ray_visibility(obj, shadow):
    """``radiometry.emitters.RayVisibility`` of an evaluated object (``shadow``: casts shadows)."""
    from ...radiometry.emitters import RayVisibility as V

    flags = V.NONE
    for attr, flag in (("visible_camera", V.CAMERA), ("visible_diffuse", V.DIFFUSE), ("visible_glossy", V.GLOSSY),
                       ("visible_transmission", V.TRANSMISSION), ("visible_volume_scatter", V.VOLUME_SCATTER)):
        if getattr(obj, attr, True):
            flags |= flag
    return flags | (V.SHADOW if shadow else V.NONE)


def _mesh_triangles(obj):
    """Local-space vertices (V, 3) float64, triangles as vertex indices (T, 3) and per-triangle material slot
    index of an evaluated object (the vertices are transformed before the triangles gather them: V < 3T)."""
    mesh = obj.to_mesh()
    try:
        if mesh is None:
            return np.zeros((0, 3)), np.zeros((0, 3), int), np.zeros(0, int)
        mesh.calc_loop_triangles()
        n_tri, n_vert = len(mesh.loop_triangles), len(mesh.vertices)
        co = np.empty(3 * n_vert, np.float32)
        mesh.vertices.foreach_get("co", co)
        tri = np.empty(3 * n_tri, np.int32)
        mesh.loop_triangles.foreach_get("vertices", tri)
        mat = np.empty(n_tri, np.int32)
        mesh.loop_triangles.foreach_get("material_index", mat)
        return co.reshape(-1, 3).astype(np.float64), tri.reshape(-1, 3), mat.astype(int)
    finally:
        obj.to_mesh_clear()


def _collect(depsgraph):
    """Walk the render depsgraph; returns a SceneModel (positions still in scene units)."""
    lights, names, shadow, reflects, unmodelled, volumes = [], [], [], [], [], []
    mirrored = []  # per geometry object: its transform's determinant is negative (SceneGeometry.mirrored)
    seals, seal_chunks = [], []
    ids = []  # per geometry object: its original's identity (measure.blender.identity.object_identity)
    panes, refractors, pane_chunks, meshes = {}, [], [], []
    rough = set()  # refractors rough enough that light sampling finds small lights through them (issue 18)
    tri_chunks, obj_chunks, opaque_chunks, emissive_chunks, slot_chunks = [], [], [], [], []
    bound_chunks = []  # per geometry object: its triangles' (min, max) corners (scene_model.triangle_bounds)
    needs = {"geometry": False, "glossy": False, "transmission": False, "volume": False, "emissive_surfaces": False}
    material_cache, local_cache, instance_count = {}, {}, {}
    total = 0
    digest = hashlib.blake2b(digest_size=16)  # what geometry the render holds, where (capture_lights compares it)
    for inst in depsgraph.object_instances:
        obj = inst.object
        original = obj.original if obj.original is not None else obj
        name = original.name
        if inst.is_instance:
            # Stable, readable names: the order of instances in the depsgraph is deterministic.
            k = instance_count[name] = instance_count.get(name, 0) + 1
            parent = inst.parent.original.name if inst.parent is not None and inst.parent.original else "?"
            name = f"{name} (instance {k} of {parent!r})"
        if obj.type == "LIGHT":
            source_id = _source_id(inst, original)
            visibility = _ray_visibility(obj, bool(getattr(obj.data, "use_shadow", True)))
            lights.append(dict(_light_entry(obj, name, inst.matrix_world, source_id, visibility),
                               source=original.name, source_id=source_id))
            if _Capture.light_records is not None:
                _Capture.light_records.append(_light_record(obj, original, name, inst.matrix_world, source_id))
            continue
        if obj.type in _GEOMETRY_TYPES and (obj.visible_diffuse or obj.visible_glossy or obj.visible_transmission
                                            or obj.visible_shadow):  # no rays: the capture skips it too
            digest.update(repr(_instance_signature(inst, obj, original)).encode("utf-8", "replace"))
        if _Capture.lights_only:
            continue
        if obj.type not in _GEOMETRY_TYPES or original.name in _Capture.exclude:
            continue
        rays = (obj.visible_diffuse, obj.visible_glossy, obj.visible_transmission, obj.visible_shadow)
        if not any(rays):
            continue
        needs["geometry"] = True
        linking = getattr(obj, "light_linking", None)
        if linking is not None and linking.blocker_collection is not None:
            needs["blocker_linking"] = True  # an emitting object's shadows may ignore surfaces (scene.sealed)
        if any(getattr(ps.settings, "type", "") == "HAIR" for ps in getattr(obj, "particle_systems", ())):
            needs["hair_particles"] = True  # rendered strands the capture does not triangulate (scene.sealed)
        if obj.type == "VOLUME":
            needs["volume"] = True
            volumes.append((name,) + _bound_box_m(obj, inst.matrix_world))
        if obj.type not in _MESHABLE:
            unmodelled.append(name)
            continue
        ident, data_state, m = _instance_key(inst, obj, original), _data_state(obj, original), _matrix(inst)
        local, world, bounds = _kept_triangles(ident, data_state, m, inst, original)
        key = (obj.data.as_pointer() if inst.is_instance and obj.data is not None else None, original.name)
        if local is None:
            local = local_cache.get(key) if key[0] is not None else None
        if local is None:
            local = _mesh_triangles(obj)
            local = (*local, np.unique(local[2]))  # the material indices used, once per mesh
            if key[0] is not None:
                local_cache[key] = local
        verts_local, tri_index, mat_index, mat_used = local
        if not len(tri_index):
            continue
        total += len(tri_index)
        if total > MAX_TRIANGLES:
            unmodelled.append(f"{name} (more than {MAX_TRIANGLES} triangles in the scene)")
            continue
        slots = [slot.material for slot in obj.material_slots] or [None]
        traits = []
        for material in slots:
            k = material.as_pointer() if material is not None else 0
            if k not in material_cache:
                material_cache[k] = _material_traits(material)
            traits.append(material_cache[k])
            _o, emits, glossy, transmission, volume, _null, _seals, _black = material_cache[k]
            needs["glossy"] |= glossy
            needs["transmission"] |= transmission
            needs["volume"] |= volume
            needs["emissive_surfaces"] |= emits
        traits = np.array(traits, dtype=bool)
        slot = np.clip(mat_index, 0, len(traits) - 1)
        used = np.unique(np.clip(mat_used, 0, len(traits) - 1))
        if world is None:
            world = ((verts_local @ m[:3, :3].T + m[:3, 3]) * _Capture.scale)[tri_index]  # metres
            bounds = scene_model.triangle_bounds(world)
        if _Capture.instances is not None:
            _Capture.instances[ident] = (data_state, local, m, _Capture.scale, world, bounds)
        bound_chunks.append(bounds)
        pane_mask = None
        # transmits: a thin pane, or a refractor to render (issue 18); Radiometer's own emitters (the sun's
        # first bounce, issue 31) let rays through unchanged and are neither
        if traits[used, 3].any() and not original.get(EMITTER_PROP):
            # The mesh's own float32 coordinates, in metres through the transform's largest stretch (issue 32).
            local_extent = float(np.abs(verts_local).max()) * float(np.linalg.norm(m[:3, :3], 2)) * _Capture.scale
            pane_mask = _glass_object(panes, refractors, len(names), name, original.name, world, slot, slots,
                                      traits, material_cache, source_id=_source_id(inst, original), rough=rough,
                                      local_extent=local_extent)
        pane_chunks.append(np.where(pane_mask, len(names), -1) if pane_mask is not None else np.full(len(world), -1))
        if traits[used, 4].any() and len(names) not in panes:  # a medium fills this mesh (issue 18)
            flat = world.reshape(-1, 3)
            volumes.append((name, flat.min(axis=0), flat.max(axis=0)))
        if traits[used, 1].any():  # emits: one EmissiveMesh emitter per emitting slot
            _emissive_meshes(meshes, inst, original, name, world, slot, slots, traits, material_cache)
        index = len(names)
        names.append(name)
        mirrored.append(bool(np.linalg.det(np.asarray(m, float)[:3, :3]) < 0.0))
        ids.append(object_identity(original))
        # Faces of a volume-only object are null interfaces (issue 18, F5): no shadow, no reflection;
        # its medium (in ``volumes``) is what attenuates and scatters, and the planner renders it.
        null = bool(traits[used, 5].all())
        black = bool(traits[used, 7].all())  # every face provably sends nothing: it only blocks (issue 31)
        shadow.append(bool(obj.visible_shadow) and not null)
        reflects.append(bool(obj.visible_diffuse or obj.visible_glossy or obj.visible_transmission) and not null
                        and not black)
        # every kind of ray stops at it (no holdout, no ray type switched off): what may close a sealed shell
        seals.append(bool(obj.visible_diffuse and obj.visible_glossy and obj.visible_transmission and obj.visible_shadow
                          and obj.visible_volume_scatter) and not bool(getattr(obj, "is_holdout", False)) and not null)
        tri_chunks.append(world)
        obj_chunks.append(np.full(len(world), index))
        opaque_chunks.append(traits[slot, 0])
        seal_chunks.append(traits[slot, 6])
        emissive_chunks.append(traits[slot, 1])
        slot_chunks.append(slot)
    cat = (lambda chunks, shape: np.concatenate(chunks) if chunks else np.zeros(shape))
    geometry = scene_model.SceneGeometry(
        triangles=cat(tri_chunks, (0, 3, 3)), object_index=cat(obj_chunks, (0,)).astype(int), object_names=names,
        object_ids=ids,
        casts_shadow=np.array(shadow, bool), opaque=cat(opaque_chunks, (0,)).astype(bool),
        reflects=np.array(reflects, bool), seals=np.array(seals, bool), mirrored=np.array(mirrored, bool),
        sealing_material=cat(seal_chunks, (0,)).astype(bool), emissive=cat(emissive_chunks, (0,)).astype(bool), unmodelled=unmodelled,
        pane_of=cat(pane_chunks, (0,)).astype(int), material_slot=cat(slot_chunks, (0,)).astype(int),
        tri_bounds=(cat([b[0] for b in bound_chunks], (0, 3)), cat([b[1] for b in bound_chunks], (0, 3))))
    needs["volumes"] = volumes
    needs["panes"], needs["refractors"] = panes, refractors
    needs["rough_refractors"] = rough  # names: no caustic bound for them (measure.capture.glass.rough_refraction)
    needs["emissive_meshes"] = meshes
    needs["render_instances"] = digest.hexdigest()
    return lights, geometry, needs


def _instance_key(inst, obj, original):
    """A render instance's identity across captures: its object's identity and its persistent id."""
    return object_identity(original), tuple(inst.persistent_id) if inst.is_instance else ()


def _data_state(obj, original):
    """What an evaluated object's triangles are read from, short of their coordinates: its original's
    data-block and (meshes) the evaluated element counts (a render-only subdivision level or simplify
    setting changes these)."""
    data = obj.data
    counts = ((len(data.vertices), len(data.edges), len(data.polygons), len(data.loops))
              if obj.type == "MESH" and data is not None else ())
    source = getattr(original, "data", None)
    return obj.type, source.as_pointer() if source is not None else 0, counts


def _matrix(inst):
    return np.array(inst.matrix_world, dtype=np.float64)


def _kept_triangles(ident, data_state, m, inst, original):
    """(local arrays, world triangles, their bounds) kept from the capture ``capture_partial`` builds on;
    (local arrays, None, None) for an instance that moved (transformed again, as a full capture would);
    (None, None, None) when its triangles must be read: it is new, its data-block or element counts
    differ, or ``_Capture.reread`` says an edit may have reached it."""
    if _Capture.previous is None:
        return None, None, None
    old = _Capture.previous.get(ident)
    if old is None or old[0] != data_state or old[3] != _Capture.scale:
        return None, None, None
    parent = inst.parent.original if inst.is_instance and inst.parent is not None else None
    if _Capture.reread(original, getattr(original, "data", None), parent):
        return None, None, None
    _state, local, old_m, _scale, world, bounds = old
    return (local, world, bounds) if np.array_equal(old_m, m) else (local, None, None)


def _instance_signature(inst, obj, original):
    """What a capture's geometry depends on for one render instance, short of its triangles: identity,
    transform, ray visibility, data-block, materials and (meshes) element counts. Two captures whose
    signatures all agree and between which no mesh, material or modifier was edited (``capture_cache``
    watches those) hold the same triangles."""
    data = obj.data
    counts = (len(data.vertices), len(data.polygons)) if obj.type == "MESH" and data is not None else ()
    return (obj.type, object_identity(original), tuple(inst.persistent_id) if inst.is_instance else (),
            tuple(v for row in inst.matrix_world for v in row),
            tuple(bool(getattr(obj, a, True)) for a in ("visible_diffuse", "visible_glossy", "visible_transmission",
                                                        "visible_shadow", "visible_volume_scatter", "is_holdout")),
            getattr(getattr(data, "original", data), "name", ""), counts,
            tuple((slot.link, slot.material.original.name if slot.material is not None else "")
                  for slot in obj.material_slots),
            _object_state(obj)[1])  # its light linking (receivers, blockers): read for sealed shells


def _emissive_meshes(meshes, inst, original, name, world_tris, slot, slots, traits, cache):
    """Append a ``radiometry.emitters.EmissiveMesh`` (metres, SI radiance or None when the emission is
    not a plain value) for every emitting material slot of one object instance."""
    from ...radiometry.emitters import EmissiveMesh

    visibility = _ray_visibility(inst.object, bool(inst.object.visible_shadow))
    for j, material, radiance in _used_slots(slot, slots, traits, 1, cache, "emission", _emission_radiance):
        # Cycles renders in scene units: radiance per scene unit^2 is radiance / scale^2 per m^2.
        si = None if radiance is None else radiance / _Capture.scale**2
        meshes.append(EmissiveMesh(world_tris[slot == j], si, name=f"{name} [{getattr(material, 'name', 'default')}]",
                                   source_id=_source_id(inst, original, j), visibility=visibility))


def _used_slots(slot, slots, traits, trait, cache, tag, read):
    """(slot index, material, read(material)) for every material slot the triangles use whose
    ``traits[:, trait]`` holds; ``read`` runs once per material (``cache`` by (tag, pointer))."""
    for j in np.unique(slot):
        if not traits[j, trait]:
            continue
        material = slots[j]
        key = (tag, material.as_pointer() if material is not None else 0)
        if key not in cache:
            cache[key] = read(material)
        yield int(j), material, cache[key]


def _glass_object(panes, refractors, index, name, source, world_tris, slot, slots, traits, cache, source_id=None,
                  rough=None, local_extent=0.0):
    """Record the transmissive part of an object as a thin pane (``radiometry.scene.thin_glass.Pane`` in
    ``panes`` by object index) when every transmissive material it uses is a pane with the same
    optics and those triangles form a planar pane (other slots, e.g. an opaque window frame in the
    same mesh, stay ordinary geometry); returns the (T,) mask of the pane's triangles. Otherwise the
    object is recorded as a refractor (name, reason) that Cycles renders as it is, and None returned;
    its name goes to ``rough`` too when every transmissive material is ``glass.rough_refraction``.
    ``local_extent``: the largest |coordinate| of the mesh in its own frame, in metres through the
    transform's largest stretch: float32 rounding there, not only in world coordinates, sets the
    tolerance of the pane test (a CAD import's mesh far from its origin, moved back by its transform)."""
    from ...radiometry.scene import thin_glass
    from . import glass

    optics, glass_slots = [], []
    for j, _material, value in _used_slots(slot, slots, traits, 3, cache, "pane", glass.pane_optics):
        optics.append(value)
        glass_slots.append(j)
    if any(o is None for o, _why in optics) or any(o != optics[0][0] for o, _why in optics):
        why = next((w for o, w in optics if o is None and w), "not a recognised glass shader")
        refractors.append((name, why))
        _rough_refractor(rough, name, slot, slots, traits, cache)
        return None
    mask = np.isin(slot, glass_slots)
    pane_tris = world_tris[mask]
    flat = world_tris.reshape(-1, 3)
    tol = thin_glass.coordinate_tolerance(float(np.abs(flat).max()), local_extent)  # float32 vertices, transform
    geom, why = thin_glass.pane_geometry(pane_tris, tol)
    if geom is None:
        refractors.append((name, f"curved or thick refractor ({why})"))
        _rough_refractor(rough, name, slot, slots, traits, cache)
        return None
    o = optics[0][0]
    shape = f"a slab {1000 * geom.thickness:.3g} mm thick" if len(geom.heights) == 2 else "a single face"
    # Volume Absorption density is per scene unit: per metre it is density / scale.
    absorption = tuple(float(a) / _Capture.scale for a in o.get("absorption", (0.0, 0.0, 0.0)))
    panes[index] = thin_glass.Pane(name=name, ior=o["ior"], thickness=geom.thickness, tint_t=o["tint_t"],
                                   absorption=absorption,
                                   tint_r=o["tint_r"], geometry=geom, trick=bool(o.get("trick")),
                                   model=f"{o['model']}, IOR {o['ior']:g}, {shape}", source=source,
                                   source_id=source_id, slots=tuple(glass_slots))
    return mask


def _rough_refractor(rough, name, slot, slots, traits, cache):
    """Add ``name`` to ``rough`` when every transmissive material it uses refracts roughly."""
    from . import glass

    if rough is not None and all(value for _j, _m, value in _used_slots(slot, slots, traits, 3, cache, "rough",
                                                                         glass.rough_refraction)):
        rough.add(name)


def _bound_box_m(obj, matrix_world):
    """(min (3,), max (3,)) in metres of an evaluated object's bounding box in world space."""
    corners = np.array([tuple(c) for c in obj.bound_box], float)
    m = np.array(matrix_world, dtype=np.float64)
    world = (corners @ m[:3, :3].T + m[:3, 3]) * _Capture.scale
    return world.min(axis=0), world.max(axis=0)


def _light_entry(obj, name, matrix_world, source_id, visibility):
    """One light instance as the capture keeps it: its emitter, built here from the evaluated light
    (``scene_lights.emitter_of``, SI), or None with the reason no closed form covers it; and what the
    planner needs beside it."""
    data = obj.data
    for attr in ("energy", "exposure"):
        if not math.isfinite(float(getattr(data, attr, 0.0))):
            raise RadiometerError(f"light {name!r} has a non-finite {attr} ({getattr(data, attr)}): "
                                  "give it a real value")
    for attr in ("color", "temperature_color"):
        if hasattr(data, attr) and not all(math.isfinite(float(c)) for c in getattr(data, attr)):
            raise RadiometerError(f"light {name!r} has a non-finite {attr} {tuple(getattr(data, attr))}: "
                                  "give it a real colour")
    cycles = getattr(data, "cycles", None)
    portal = bool(getattr(cycles, "is_portal", False)) and data.type == "AREA"
    notes = []
    if float(getattr(data, "energy", 0.0)) < 0.0:
        notes.append(f"light {name!r} has negative power ({data.energy:g} W): Blender subtracts its light")
    spec, uncovered = None, scene_lights.uncovered_reason(data, obj)
    if uncovered is None:
        try:
            spec = scene_lights.emitter_of(data, matrix_world, _Capture.scale, name=name, source_id=source_id,
                                           visibility=visibility)
        except ValueError as exc:
            uncovered = f"has no closed form here ({exc})"
    return {"name": name, "spec": spec, "uncovered": uncovered,
            "casts_shadow": bool(getattr(data, "use_shadow", True)), "reaches_diffuse": bool(obj.visible_diffuse),
            "portal": portal, "notes": tuple(notes)}


#: What ``_light_entry`` and ``uncovered_reason`` read from a light's OBJECT (the rest is its data-block).
_LIGHT_OBJECT_FLAGS = ("visible_camera", "visible_diffuse", "visible_glossy", "visible_transmission",
                       "visible_volume_scatter", "hide_render")


@dataclasses.dataclass(frozen=True)
class LightRecord:
    """One light instance of a probe render, as ``relight`` replays it: the instance's name, identity and
    world matrix (scene units, rows), and its object's state (``_object_state``) and data-block then."""

    name: str
    source: str
    session_uid: int
    data_pointer: int
    matrix_world: tuple
    source_id: object
    object_state: tuple
    basis: tuple  # the object's own transform, for an instance (``_basis``)


def _object_state(obj):
    """The light object's values that the capture reads (ray flags, light linking) or that decide whether
    it renders (``hide_render``): equal values, equal light entries."""
    linking = getattr(obj, "light_linking", None)
    links = (None, None) if linking is None else (
        linking.receiver_collection is not None, linking.blocker_collection is not None)
    return tuple(bool(getattr(obj, attr, True)) for attr in _LIGHT_OBJECT_FLAGS), links


def _basis(original):
    """An instanced light's own transform where it alone places the light in its collection (no parent, no
    constraint: then its instances move only with their instancer, whose edits are not lights-only), else
    None (``relight`` then leaves such an instance to the probe)."""
    if original.parent is not None or len(original.constraints):
        return None
    return tuple(tuple(row) for row in original.matrix_basis)


def _light_record(obj, original, name, matrix_world, source_id):
    return LightRecord(name=name, source=original.name, session_uid=int(original.session_uid),
                       data_pointer=original.data.as_pointer(), matrix_world=tuple(tuple(row) for row in matrix_world),
                       source_id=source_id, object_state=_object_state(original), basis=_basis(original))


class _LightInstance:
    """What ``_light_entry`` reads of an evaluated light instance, rebuilt from a record and the light's
    data-block (``relight``)."""

    def __init__(self, data, state):
        self.data = data
        for attr, value in zip(_LIGHT_OBJECT_FLAGS, state[0]):
            setattr(self, attr, value)
        receiver, blocker = state[1]
        self.light_linking = None if receiver is None else type("LightLinking", (), {
            "receiver_collection": True if receiver else None, "blocker_collection": True if blocker else None})()


def _unanimated(light):
    """True when nothing evaluates a light's values differently from its data-block's stored ones."""
    tree = getattr(light, "node_tree", None)
    return light.animation_data is None and (tree is None or tree.animation_data is None)


class _ProbeEngine(bpy.types.RenderEngine):
    bl_idname = "RADIOMETER_SCENE_PROBE"
    bl_label = "Radiometer scene probe"

    def render(self, depsgraph):
        if _Capture.view_layer is not None and depsgraph.view_layer.name != _Capture.view_layer:
            return  # another view layer of the frame (``_render_probe`` turns them off; never read them)
        try:
            _Capture.result = _collect(depsgraph)
        except BaseException as exc:  # noqa: BLE001 - handed back to the caller, never swallowed
            _Capture.error = exc


def _render_probe(scene, view_layer):
    registered = False
    if not hasattr(bpy.types, _ProbeEngine.__name__):
        bpy.utils.register_class(_ProbeEngine)
        registered = True
    try:
        with scene_guard.preserved_scene(scene):
            render = scene.render
            render.engine = _ProbeEngine.bl_idname
            render.resolution_x = render.resolution_y = 4
            render.resolution_percentage = 100
            render.use_compositing = False
            render.use_sequencer = False
            render.use_border = False
            # Only the view layer asked for: Blender renders every enabled view layer of the frame, one
            # render(depsgraph) call each (measured, bpy 5.0.1, also with ``layer=``), and the last one's
            # capture was kept: a capture for the first of two layers read the second's lights.
            for layer in scene.view_layers:
                if layer.use != (layer.name == view_layer.name):  # no write (and no update) when it is so
                    layer.use = layer.name == view_layer.name
            if scene.camera is None:  # Blender refuses to render without one; removed on exit
                cam = bpy.data.objects.new("radiometer_probe_camera", bpy.data.cameras.new("radiometer_probe_camera"))
                scene.collection.objects.link(cam)
                scene.camera = cam
            with bpy.context.temp_override(scene=scene, view_layer=view_layer):
                result = bpy.ops.render.render(scene=scene.name, layer=view_layer.name)
            if result != {"FINISHED"}:
                raise RadiometerError(f"could not read the scene as rendered ({', '.join(sorted(result))})")
    finally:
        if registered:
            bpy.utils.unregister_class(_ProbeEngine)


def _probe(scene, view_layer, exclude, lights_only, instances=None, previous=None, reread=None, light_records=None):
    """(raw lights, geometry, needs) of the render depsgraph, read by one probe render (``instances``,
    ``previous``, ``reread``: see ``capture_partial``; ``light_records``: a list to fill, see ``relight``)."""
    _Capture.exclude, _Capture.result, _Capture.error = frozenset(exclude), None, None
    _Capture.scale, _Capture.lights_only = scene.unit_settings.scale_length, lights_only
    _Capture.instances, _Capture.previous, _Capture.reread = instances, previous, reread
    _Capture.light_records, _Capture.view_layer = light_records, view_layer.name
    try:
        _render_probe(scene, view_layer)
        if _Capture.error is not None:
            if isinstance(_Capture.error, RadiometerError):
                raise _Capture.error
            raise RadiometerError(f"could not read the scene: {_Capture.error}") from _Capture.error
        if _Capture.result is None:
            raise RadiometerError("could not read the scene as rendered (the probe render did not run)")
        return _Capture.result
    finally:
        _Capture.result = _Capture.error = None
        _Capture.lights_only = False
        _Capture.instances = _Capture.previous = _Capture.reread = _Capture.light_records = None
        _Capture.view_layer = None


def _model_lights(raw_lights):
    return [scene_model.ModelLight(
        name=item["name"], spec=item["spec"], uncovered=item["uncovered"], casts_shadow=item["casts_shadow"],
        reaches_diffuse=item["reaches_diffuse"], portal=item["portal"], notes=item["notes"],
        source=item["source"], source_id=item["source_id"]) for item in raw_lights]


def _world_state(scene):
    """(world emits, world has a volume) of the scene's world."""
    world_volume = shader_kinds.uses_volume(active_node_tree(scene.world) if scene.world else None)
    return shader_kinds.world_emits(scene.world), bool(world_volume)


def capture(scene, view_layer=None, exclude=(), instances=None, light_records=None):
    """The scene as Cycles renders it: a ``SceneModel`` in metres: emitters (``radiometry.emitters``,
    built here once per capture, with their source identity and ray visibility) and triangles.
    ``instances``: a dict to fill with what ``capture_partial`` needs to build on this capture;
    ``light_records``: a list to fill with what ``relight`` needs to read its lights again without a render."""
    return _capture(scene, view_layer, exclude, instances, light_records=light_records)


def capture_partial(scene, previous, reread, view_layer=None, exclude=(), instances=None, light_records=None):
    """``capture(scene, view_layer, exclude)`` after a geometry edit, reading again only the triangles
    an edit may have reached (issue 17). ``previous``: the ``instances`` a capture of this scene filled;
    ``reread(original object, original data-block, original instancer or None)``: True when an edit
    since may have changed that instance's triangles (``capture_cache`` decides from the depsgraph's
    updates). Every other instance keeps its local arrays (transformed again if it moved) and, if it did
    not move, its triangles; everything else (lights, materials, flags, panes, emitters) is read as in a
    full capture, by the same walk, so the model equals a full capture's."""
    return _capture(scene, view_layer, exclude, instances, previous, reread, light_records)


def _capture(scene, view_layer, exclude, instances, previous=None, reread=None, light_records=None):
    view_layer = view_layer or scene.view_layers[0]
    raw_lights, geometry, needs = _probe(scene, view_layer, exclude, False, instances, previous, reread,
                                         light_records)
    needs["world_emits"], world_volume = _world_state(scene)
    needs["surface_volume"] = needs["volume"]  # without the world's: capture_lights reads the world again
    needs["volume"] |= world_volume
    volumes = needs.pop("volumes", [])
    panes, refractors = needs.pop("panes", {}), needs.pop("refractors", [])
    emissive_meshes = needs.pop("emissive_meshes", [])
    needs["thin_panes"] = panes  # every render path swaps these for thin glass (measure.capture.glass.swap_panes)
    return scene_model.SceneModel(lights=_model_lights(raw_lights), geometry=geometry,
                                  world_emits=needs["world_emits"], needs=needs, scale_length=_Capture.scale,
                                  world=_world(scene, needs["world_emits"]), volumes=volumes,
                                  world_volume=world_volume, panes=panes, refractors=refractors,
                                  emissive_meshes=emissive_meshes)


def capture_lights(scene, model, view_layer=None, light_records=None):
    """``model`` (a capture of this scene) with its lights and world read again and everything else kept
    (the geometry object itself, with its spatial index): for edits that changed only lights or the
    world (``capture_cache`` decides which). One probe render that walks the render depsgraph's lights
    only: a few ms where a full capture turns 130k triangles into arrays (issue 17). The returned model's
    ``needs["render_instances"]`` is the render's geometry signature now: the caller compares it with the
    model's when an update may have changed visibility (see ``_instance_signature``)."""
    view_layer = view_layer or scene.view_layers[0]
    raw_lights, _geometry, probe_needs = _probe(scene, view_layer, (), lights_only=True, light_records=light_records)
    return _relit(scene, model, raw_lights, probe_needs["render_instances"])


def _relit(scene, model, raw_lights, render_instances):
    """``model`` with ``raw_lights`` for its lights and the world read again (``capture_lights``, ``relight``)."""
    world_emits, world_volume = _world_state(scene)
    needs = dict(model.needs, world_emits=world_emits, render_instances=render_instances,
                 volume=bool(model.needs.get("surface_volume", model.needs["volume"])) or world_volume)
    return dataclasses.replace(model, lights=_model_lights(raw_lights), world_emits=world_emits, needs=needs,
                               world=_world(scene, world_emits), world_volume=world_volume,
                               volumes=list(model.volumes), panes=dict(model.panes),
                               refractors=list(model.refractors), emissive_meshes=list(model.emissive_meshes),
                               notes=list(model.notes))


def relight(scene, model, records, view_layer=None):
    """``capture_lights(scene, model)`` without a probe render, after edits of lights alone (their data,
    their node trees, their objects moved: ``capture_cache`` decides, from the depsgraph's updates).
    Every light instance of ``records`` (the list the probe of ``model`` filled) is read again from its
    object's data-block by the probe's own ``_light_entry``, with the instance's kept name and identity,
    and its kept world matrix, or, for a light object of its own (not an instance) that moved, the
    object's matrix as ``view_layer``'s depsgraph evaluated it, which is the render's instance matrix.
    Returns ``(model, records)``, or None (the caller renders the probe) when a record's object is gone,
    renamed or holds another data-block, when it is not evaluated in ``view_layer``'s depsgraph (disabled
    in viewports), when its ray flags, light linking or ``hide_render`` differ from the probe's, when an
    instanced light moved, or when a light or its node tree is animated (the render would evaluate it)."""
    view_layer = view_layer or scene.view_layers[0]
    raw_lights, fresh = [], []
    _Capture.scale = scene.unit_settings.scale_length
    for record in records:
        original = bpy.data.objects.get(record.source)
        if (original is None or int(original.session_uid) != record.session_uid or original.type != "LIGHT"
                or original.data is None or original.data.as_pointer() != record.data_pointer
                or not _unanimated(original.data)):
            return None
        if _object_state(original) != record.object_state:
            return None
        if record.source_id.instance:  # kept only while its own transform is (its instancer did not move)
            if record.basis is None or _basis(original) != record.basis:
                return None
        else:
            # The object as the view layer's depsgraph evaluated it (capture_cache evaluated it just before):
            # its matrix is the render's instance matrix, up to date also for a view layer that is not the
            # active one (whose evaluation is not copied back to the original). Not evaluated there
            # (disabled in viewports): the probe reads it.
            evaluated = view_layer.depsgraph.id_eval_get(original)
            if not evaluated.is_evaluated:
                return None
            matrix = tuple(tuple(row) for row in evaluated.matrix_world)
            if matrix != record.matrix_world:  # the light moved
                record = dataclasses.replace(record, matrix_world=matrix)
        instance = _LightInstance(original.data, record.object_state)
        visibility = _ray_visibility(instance, bool(getattr(original.data, "use_shadow", True)))
        raw_lights.append(dict(_light_entry(instance, record.name, record.matrix_world, record.source_id, visibility),
                               source=record.source, source_id=record.source_id))
        fresh.append(record)
    return _relit(scene, model, raw_lights, model.needs.get("render_instances")), tuple(fresh)


def _world(scene, emits):
    """The world as pure data (``measure.capture.world_capture.read_world``) when it emits, else None (issue 14)."""
    if not emits:
        return None
    from . import world_capture

    return world_capture.read_world(scene)

"""The scene capture, cached per depsgraph update (issue 17: capture once).

``scene_capture.capture`` renders a probe frame through the render depsgraph (a full scene sync, 43 %
of a one-meter measurement in a 130k-triangle room). An analysis used to repeat it 4-5 times on an
unchanged scene. This module keeps the last few captures and hands one back only when nothing that
can change the result has changed since it was taken:

* **Blender's own edits.** A ``depsgraph_update_post`` handler counts updates; before every look-up
  the view layer's depsgraph is evaluated (``view_layer.update()``), so a pending edit fires the
  handler first. Measured (bpy 5.0.1): editing a light, an object in a collection disabled in the
  viewport, a mesh (also ``foreach_set`` of vertices), a material node, the unit scale, the
  simplify settings, a world node or a collection's render visibility all fire it. Loading a file,
  undo and redo bump the count too.
* **What does not fire it** (measured): properties defined in Python by Cycles (``light.cycles.is_portal``),
  the text of an IES data-block and an IES file on disk, an image's pixels, and settings that only the
  render sees (a Subdivision modifier's render levels, a particle system's rendered children). These are
  part of the key (``_untracked_state``: every light's ``is_portal``, the IES texts' hash, the IES files'
  size and mtime; ``_render_only_state``: a hash of every modifier's, particle system's, curve's and
  metaball's settings); the world, which reads image pixels, is read again on every hit.
* The key also holds the scene (pointer and name), the view layer, the frame and subframe, the unit
  scale and the excluded objects.
* **Animated scenes are never served from the cache**: a driver may read a custom property, whose edit
  fires nothing (measured: a light's power driven by ``obj["power"]`` kept its old value), and
  keyframes edited from Python need not be announced. Any data-block with animation data turns the
  cache off; the analyses still pass their one capture down explicitly.

**Edits to lights only** (issue 17). The handler also sorts what each update touched
(``depsgraph.updates``, :func:`update_kind`): a light (its object or data, incl. a move), the world,
their node trees, or an object that adds nothing to the capture (an empty or a camera that instances
nothing: a meter writing its reading; children they move are reported as their own updates) KEEP the
geometry; the scene, a collection, or an object's shading or visibility flags MAYBE change it (Blender
reports a hidden object, and also a measurement's own restore, that way); anything else (a mesh, a
material, a moved or reshaped object, a modifier), a file load, undo or redo CHANGES it. With no change
since a capture, the cached geometry (the same object, with its spatial index) is kept and only the
lights and the world are read again (``scene_capture.capture_lights``: one probe render that walks the
lights, ~2.5 ms in the 130k-triangle room where a full capture takes ~0.1 s on a quiet machine); after a
MAYBE, only if that probe finds the same render instances (identity, transform, ray visibility, data,
materials, element counts: ``scene_capture._instance_signature``), else everything is captured again.
When every update since the capture edited lights alone (a light's data-block, its node tree, its
object: ``_lights_only``; the handler counts the other batches in ``other_updates``), not even that
probe runs: ``scene_capture.relight`` replays the light instances the last probe recorded with their
data and (for lights of their own that moved) matrices read again (0.6-0.9 ms instead of 8-9 ms in the
small bench room, loaded), and declines (the probe runs) where it cannot vouch for the render's values.

**Edits to geometry** (issue 17). The handler also notes what each geometry update touched (``_touched``:
the objects Blender reports with new geometry, their data-blocks; a material, its node tree or a camera
touches no triangle; anything else, e.g. a geometry node tree, whose edit Blender reports alone, counts
as everything), and a modifier's render-only setting marks its object through the per-object hashes of
``_render_only_state``. After such edits the capture is partial (``scene_capture.capture_partial``): the
same walk of the render depsgraph as a full capture, reading the triangles again only for instances
whose object, data or instancer was touched, that are new, whose data-block or element counts differ,
or whose object or instancer is not in the viewport's depsgraph (disabled in viewports: Blender reports
no edit of it, measured); a moved instance is transformed again from its kept local arrays. The model
equals a full capture's (``tests/bpy/test_capture_partial.py`` compares every array). Undo, redo, a file
load, or more than 256 geometry updates since the capture mean a full capture.

A hit costs one depsgraph evaluation (nothing to evaluate when nothing changed) and one pass over the
lights and modifiers; a miss is one capture. Our own measurements change the scene inside
``scene_guard.preserved_scene`` and restore it, which fires the handler; :class:`Watch` keeps the
capture a measurement used valid across that, and only that (see its docstring).

Hits return a shallow copy of the cached ``SceneModel`` (its own lists and dicts; the geometry,
whose triangle grid is built lazily, is shared, so the proofs' spatial index is built once too).
"""

import collections
import dataclasses
import functools
import hashlib
import os

import bpy
import numpy as np

from . import scene_capture

#: Captures kept (one 130k-triangle model is ~10 MB).
CAPACITY = 4

_state = {"updates": 0, "geometry_updates": 0, "maybe_updates": 0, "hits": 0, "misses": 0, "restamps": 0,
          "light_recaptures": 0, "partial_captures": 0, "other_updates": 0, "light_rereads": 0}
_entries = collections.OrderedDict()
#: (geometry update count, what it touched: frozenset of ('object', session uid) / ('data', pointer), or
#: None for "anything"), one per geometry update, the latest last: what a partial capture must read again.
_edits = collections.deque(maxlen=256)
#: (cache key, scene_capture instances) of the latest capture: what a partial capture builds on.
_instances = [None, None]


def _geometry_edit(touched):
    _state["geometry_updates"] += 1
    _edits.append((_state["geometry_updates"], touched))


@bpy.app.handlers.persistent
def _count_update(*_args):
    """load_post, undo_post, redo_post: anything may have changed."""
    _state["updates"] += 1
    _state["other_updates"] += 1
    _geometry_edit(None)


def _stamp():
    return _state["updates"], _state["geometry_updates"], _state["maybe_updates"]


def _embedded_tree_pointers():
    """Pointers of the lights' and worlds' own node trees (their edits leave the geometry as it was)."""
    return {tree.as_pointer() for block in (*bpy.data.lights, *bpy.data.worlds)
            if (tree := getattr(block, "node_tree", None)) is not None}


KEEPS, MAYBE, CHANGES = "keeps", "maybe", "changes"


def update_kind(update, trees=None):
    """What a depsgraph update may do to a capture's geometry: KEEPS (a light, the world, their node
    trees, an empty or camera that instances nothing), MAYBE (the scene, a collection, an object's
    shading or visibility flags: the render's instances are compared before the geometry is kept) or
    CHANGES (a mesh, a material, a moved or reshaped object, anything else)."""
    block = update.id
    original = getattr(block, "original", None) or block
    if isinstance(block, (bpy.types.Light, bpy.types.World)):
        return KEEPS
    if isinstance(block, bpy.types.Object):
        if original.type == "LIGHT":
            return KEEPS  # a light moved or edited (children it moves are reported as their own updates)
        if original.type in {"EMPTY", "CAMERA"} and original.instance_type == "NONE":
            return KEEPS  # a meter's reading written, the camera moved: nothing the capture reads itself
        if not (update.is_updated_geometry or update.is_updated_transform):
            return MAYBE  # visibility or shading flags: the instance signature tells
        return CHANGES
    if isinstance(block, (bpy.types.Scene, bpy.types.Collection)):
        return MAYBE
    if isinstance(block, bpy.types.ShaderNodeTree):
        return KEEPS if original.as_pointer() in (_embedded_tree_pointers() if trees is None else trees) else CHANGES
    return CHANGES


#: Data-blocks whose edits reach the triangles only through the objects that use them, which Blender
#: reports as updated too (measured, bpy 5.0.1: a mesh's vertices, a modifier, a boolean's cutter moved,
#: an instanced collection's object): ('data', pointer) is recorded besides. Materials, their node trees,
#: cameras and images that no texture or geometry node reads (a bake's target) change no triangle (traits
#: are read on every capture). Anything else, e.g. a geometry
#: node tree (measured: its edit reports the tree alone, not the objects it deforms), counts as anything.
_GEOMETRY_DATA = ("Mesh", "Curve", "SurfaceCurve", "TextCurve", "MetaBall", "Curves", "PointCloud", "Volume")


def _touched(update, trees):
    """What a CHANGES update may have changed in the triangles: a set of markers, or None for anything."""
    block = update.id
    original = getattr(block, "original", None) or block
    if isinstance(block, bpy.types.Object):
        return {("object", int(original.session_uid))} if update.is_updated_geometry else set()
    if isinstance(block, (bpy.types.Material, bpy.types.ShaderNodeTree, bpy.types.Camera)):
        return set()  # shading (read on every capture), or a camera (the probe adds one when none is set)
    if type(block).__name__ in _GEOMETRY_DATA:
        return {("data", original.as_pointer())}
    if isinstance(block, bpy.types.Image) and not _image_feeds_geometry(original):
        return set()  # a bake's own image (ours, or the user's), shown or shaded only
    return None


def _image_feeds_geometry(image):
    """True if ``image`` may move vertices: a texture (Displace and other modifiers) or a geometry node
    tree or geometry-nodes modifier input uses it."""
    if any(getattr(texture, "image", None) == image for texture in bpy.data.textures):
        return True
    for tree in bpy.data.node_groups:
        if tree.bl_idname != "GeometryNodeTree":
            continue
        for node in tree.nodes:
            if getattr(node, "image", None) == image:
                return True
            if any(sock.type == "IMAGE" and getattr(sock, "default_value", None) == image for sock in node.inputs):
                return True
    for obj in bpy.data.objects:
        for modifier in obj.modifiers:
            if modifier.type == "NODES" and any(value == image for value in modifier.values()):
                return True
    return False


@bpy.app.handlers.persistent
def _count_edit(_scene=None, depsgraph=None, *_args):
    """depsgraph_update_post: counts updates, those that may change the geometry and those that change it,
    and notes what the latter touched (``_touched``)."""
    _state["updates"] += 1
    if depsgraph is None:
        _state["other_updates"] += 1
        _geometry_edit(None)
        return
    updates = list(depsgraph.updates)  # each pass over the RNA collection builds its items again
    trees, kinds, touched = None, set(), set()
    for update in updates:
        if isinstance(update.id, bpy.types.ShaderNodeTree) and trees is None:
            trees = _embedded_tree_pointers()
        kind = update_kind(update, trees)
        kinds.add(kind)
        if kind == CHANGES and touched is not None:
            more = _touched(update, trees)
            touched = None if more is None else touched | more
    if kinds != {KEEPS} or not _lights_only(updates):  # only lights edited: see scene_capture.relight
        _state["other_updates"] += 1
    if CHANGES in kinds:
        _geometry_edit(None if touched is None else frozenset(touched))
    elif MAYBE in kinds:
        _state["maybe_updates"] += 1


def _lights_only(updates):
    """True when a batch of updates edited lights and nothing else: each is a light's data-block, its node
    tree or a light object (measured, bpy 5.0.1: a light's power, colour or shadow flag reports its object,
    geometry and shading, beside its data; a ray-visibility flag or ``hide_render`` the object alone, a move
    the object with its transform; children a light moves are reported as their own updates). The lights
    can then be read again without a probe render: ``scene_capture.relight`` compares every value it reads
    of the objects with the probe's and declines where it cannot vouch for the render's (an object's flags
    changed, an instanced light moved)."""
    trees = None
    for update in updates:
        block = update.id
        original = getattr(block, "original", None) or block
        if isinstance(block, bpy.types.Light):
            continue
        if isinstance(block, bpy.types.Object) and original.type == "LIGHT":
            continue
        if not isinstance(block, bpy.types.ShaderNodeTree):
            return False
        if trees is None:
            trees = {light.node_tree.as_pointer() for light in bpy.data.lights if light.node_tree is not None}
        if original.as_pointer() not in trees:
            return False
    return bool(updates)


def _touched_since(geometry_updates):
    """Union of what every geometry edit after count ``geometry_updates`` touched, or None (anything, or
    edits no longer on record)."""
    newer = [touched for count, touched in _edits if count > geometry_updates]
    if len(newer) != _state["geometry_updates"] - geometry_updates or any(t is None for t in newer):
        return None
    return frozenset().union(*newer)


def _rereader(touched, view_layer):
    """``scene_capture.capture_partial``'s ``reread``: an instance is read again when its object, its
    data or its instancer was touched, or when its object or instancer is not in the viewport's depsgraph
    (disabled in viewports but rendered: Blender reports no edit of such an object, measured)."""
    depsgraph, seen = view_layer.depsgraph, {}
    objects = {uid for kind, uid in touched if kind == "object"}
    data = {ptr for kind, ptr in touched if kind == "data"}

    def unseen(ob):
        key = ob.as_pointer()
        if key not in seen:
            seen[key] = not depsgraph.id_eval_get(ob).is_evaluated
        return seen[key]

    def reread(original, data_block, parent):
        if int(original.session_uid) in objects or unseen(original):
            return True
        if data_block is not None and data_block.as_pointer() in data:
            return True
        return parent is not None and (int(parent.session_uid) in objects or unseen(parent))

    return reread


_HANDLERS = (("depsgraph_update_post", _count_edit), ("load_post", _count_update), ("undo_post", _count_update),
             ("redo_post", _count_update))


def _ensure_handlers():
    """Install the counting handlers where they are missing; True if one had to be (re)installed."""
    installed = False
    for name, handler in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler not in handlers:
            handlers.append(handler)
            installed = True
    return installed


def remove_handlers():
    """Take the counting handlers out again (unregister) and forget every capture."""
    for name, handler in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        while handler in handlers:
            handlers.remove(handler)
    clear()


def clear():
    _entries.clear()
    _instances[:] = [None, None]


def stats():
    """{'hits', 'misses', 'updates', 'geometry_updates', 'maybe_updates', 'restamps', 'light_recaptures',
    'partial_captures'} since the module was loaded (the tests and the bench read it); a light recapture and
    a partial capture are also counted as misses."""
    return dict(_state)


def _untracked_state(scene):
    """What the model depends on that does not fire a depsgraph update (see the module docstring)."""
    state = []
    for light in bpy.data.lights:
        cycles = getattr(light, "cycles", None)
        ies_state = ()
        tree = getattr(light, "node_tree", None) if getattr(light, "use_nodes", False) else None
        if tree is not None:
            for node in tree.nodes:
                if node.bl_idname != "ShaderNodeTexIES":
                    continue
                if node.mode == "INTERNAL":
                    text = node.ies.as_string() if node.ies is not None else ""
                    ies_state += (hashlib.blake2b(text.encode("utf-8", "surrogatepass"), digest_size=16).digest(),)
                else:
                    path = bpy.path.abspath(node.filepath) if node.filepath else ""
                    try:
                        st = os.stat(path)
                        ies_state += ((path, st.st_size, st.st_mtime_ns),)
                    except OSError:
                        ies_state += ((path, None),)
        state.append((light.name, bool(getattr(cycles, "is_portal", False)), ies_state))
    return tuple(state)


#: ``bpy.data`` collections whose data-blocks can carry animation data (keyframes, drivers, NLA).
_ANIMATABLE = ("objects", "meshes", "lights", "materials", "worlds", "node_groups", "scenes", "shape_keys",
               "curves", "cameras", "metaballs", "volumes", "pointclouds", "hair_curves", "lattices", "armatures",
               "grease_pencils", "textures", "particles", "collections")


def _animated():
    """True if any data-block has animation data. A driver may read a value whose edit Blender does not
    announce (a custom property: measured, the cache served the old power), and keyframes edited from
    Python need not be announced either; such scenes are captured every time."""
    import bpy

    for name in _ANIMATABLE:
        for block in getattr(bpy.data, name, ()):
            if getattr(block, "animation_data", None) is not None:
                return True
    return False


_SIMPLE = {"BOOLEAN", "INT", "FLOAT", "ENUM", "STRING"}


def _settings(struct):
    """Every simple RNA value of ``struct`` (pointers by the name of the data-block), and its ID properties."""
    import bpy

    values = []
    for prop in struct.bl_rna.properties:
        if prop.type not in _SIMPLE and prop.type != "POINTER":
            continue
        try:
            value = getattr(struct, prop.identifier)
        except (AttributeError, RuntimeError, TypeError):
            continue
        if prop.type == "POINTER":
            value = value.name if isinstance(value, bpy.types.ID) else None
        elif isinstance(value, (set, frozenset)):
            value = tuple(sorted(value))
        elif not isinstance(value, (str, bool, int, float)):
            try:
                value = tuple(value)
            except TypeError:
                value = repr(value)
        values.append((prop.identifier, value))
    try:
        values += [(key, repr(struct[key])) for key in struct.keys()]  # geometry-nodes inputs live here
    except (AttributeError, TypeError):
        pass
    return tuple(values)


def _render_only_state(scene, view_layer):
    """What changes the render but fires no update: ({session uid: hash}, hash of the rest).

    * Settings only the render sees (measured: a Subdivision modifier's render levels, a particle system's
      rendered children): per object, its modifiers' settings; the rest: particle settings, curve and
      metaball data (render resolution).
    * Objects disabled in viewports (not in the viewport's depsgraph) but rendered: Blender reports no edit
      of them at all (measured: a move, a vertex edit): per object, its own transform, parent and
      constraints, data-block and (meshes) its vertices and faces.

    Per object, so that such an edit reads only that object again (``_render_changes``)."""
    import bpy

    objects = {}
    for obj in bpy.data.objects:
        if len(obj.modifiers):
            digest = hashlib.blake2b(digest_size=16)
            for modifier in obj.modifiers:
                digest.update(repr((modifier.name, _settings(modifier))).encode("utf-8", "replace"))
            objects[int(obj.session_uid)] = digest.digest()
    depsgraph = view_layer.depsgraph
    for obj in scene.objects:
        if obj.type == "LIGHT" or depsgraph.id_eval_get(obj).is_evaluated:
            continue
        digest = hashlib.blake2b(objects.get(int(obj.session_uid), b""), digest_size=16)
        # Its own transform (matrix_world is only brought up to date by an evaluation, which it has not).
        for matrix in (obj.matrix_basis, obj.matrix_parent_inverse):
            digest.update(np.array(matrix, np.float64).tobytes())
        digest.update(repr((obj.type, obj.data.as_pointer() if obj.data is not None else 0,
                            obj.parent.as_pointer() if obj.parent is not None else 0, obj.parent_type,
                            obj.parent_bone, [_settings(c) for c in obj.constraints])).encode("utf-8", "replace"))
        if obj.type == "MESH" and obj.data is not None:
            mesh = obj.data
            co = np.empty(3 * len(mesh.vertices), np.float32)
            mesh.vertices.foreach_get("co", co)
            loops = np.empty(len(mesh.loops), np.int32)
            mesh.loops.foreach_get("vertex_index", loops)
            digest.update(co.tobytes())
            digest.update(loops.tobytes())
            digest.update(repr(len(mesh.polygons)).encode())
        objects[int(obj.session_uid)] = digest.digest()
    digest = hashlib.blake2b(digest_size=16)
    for name in ("particles", "curves", "metaballs"):
        for block in getattr(bpy.data, name, ()):
            digest.update(repr((name, block.name, _settings(block))).encode("utf-8", "replace"))
    return objects, digest.digest()


def _render_changes(old, new):
    """The objects whose modifiers differ between two ``_render_only_state()``s, as ('object', uid)
    markers, or None when particle, curve or metaball data differ (anything may have changed)."""
    if old[1] != new[1]:
        return None
    return frozenset(("object", uid) for uid in set(old[0]) | set(new[0]) if old[0].get(uid) != new[0].get(uid))


def _key(scene, view_layer, exclude):
    # The view layer's material override changes every surface's traits without changing the instances.
    # The render-only settings are kept beside the key (entries' last item), compared on every look-up.
    override = getattr(view_layer, "material_override", None)
    return (scene.as_pointer(), scene.name, view_layer.name, scene.frame_current, float(scene.frame_subframe),
            float(scene.unit_settings.scale_length), frozenset(exclude), _untracked_state(scene),
            override.name if override is not None else "")


def _copy(model, scene):
    # Own containers for the caller; arrays and the geometry (with its lazily built grid) are shared.
    fresh = dataclasses.replace(model, **{f.name: type(value)(value) for f in dataclasses.fields(model)
                                         if isinstance(value := getattr(model, f.name), (list, dict))})
    if model.world is not None:  # the world reads image pixels, which fire no update: read it again
        from . import world_capture

        fresh.world = world_capture.read_world(scene)
    return fresh


def capture(scene, view_layer=None, exclude=()):
    """``scene_capture.capture(scene, view_layer, exclude)``, served from the cache when the scene has
    not changed since (see the module docstring). Returns a ``radiometry.scene.scene_model.SceneModel``."""
    view_layer = view_layer or scene.view_layers[0]
    if _ensure_handlers():
        clear()  # updates may have gone uncounted while the handler was missing
    if _animated():
        _state["misses"] += 1
        return scene_capture.capture(scene, view_layer, exclude=exclude)
    view_layer.update()  # a pending edit fires the handler now, before the look-up
    key, render_state = _key(scene, view_layer, exclude), _render_only_state(scene, view_layer)
    entry = _entries.get(key)
    same_render = entry is not None and entry[4] == render_state
    if entry is not None and entry[0] == _state["updates"] and same_render:
        _entries.move_to_end(key)
        _state["hits"] += 1
        return _copy(entry[3], scene)
    _state["misses"] += 1
    model, records = None, []
    if (entry is not None and entry[1] == _state["geometry_updates"] and entry[2] == _state["maybe_updates"]
            and entry[5] == _state["other_updates"] and entry[6] is not None and same_render):
        # Only lights were edited since: the same light instances, read again from their data and objects
        # without a probe render (None when relight cannot vouch for them: then the probe below).
        relit = scene_capture.relight(scene, entry[3], entry[6], view_layer)
        if relit is not None:
            model, records = relit
            _state["light_recaptures"] += 1
            _state["light_rereads"] += 1
    if model is None and entry is not None and entry[1] == _state["geometry_updates"] and same_render:
        # No mesh, material or object shape changed since: read the lights and the world again, and keep
        # the geometry when the render holds the same instances (checked if visibility may have changed).
        cached, maybe_changed = entry[3], entry[2] != _state["maybe_updates"]  # before the probe's own updates
        records = []
        model = scene_capture.capture_lights(scene, cached, view_layer, light_records=records)
        if maybe_changed and (model.needs.get("render_instances") is None
                              or model.needs["render_instances"] != cached.needs.get("render_instances")):
            model = None  # an object was hidden, shown, added or removed: capture everything
        else:
            _state["light_recaptures"] += 1
    if model is None and entry is not None and _instances[0] == key:
        # A geometry edit: read again only the instances it may have reached (issue 17).
        touched, render = _touched_since(entry[1]), _render_changes(entry[4], render_state)
        if touched is not None and render is not None:
            touched |= render  # a render-only modifier setting: that object is read again
            fresh, records = {}, []
            model = scene_capture.capture_partial(scene, _instances[1], _rereader(touched, view_layer), view_layer,
                                                  exclude=exclude, instances=fresh, light_records=records)
            _instances[:] = [key, fresh]
            _state["partial_captures"] += 1
    if model is None:
        fresh, records = {}, []
        model = scene_capture.capture(scene, view_layer, exclude=exclude, instances=fresh, light_records=records)
        _instances[:] = [key, fresh]
    view_layer.update()  # absorb the probe render's own restore, so the next look-up can hit
    # (update counts, model, render-only state, other-than-light-data updates, the probe's light records)
    _entries[key] = (*_stamp(), model, render_state, _state["other_updates"], tuple(records))
    _entries.move_to_end(key)
    while len(_entries) > CAPACITY:
        _entries.popitem(last=False)
    return _copy(model, scene)


class Watch:
    """Keeps the capture a measurement used valid across the measurement's own scene changes.

    A measurement changes the scene (sensors, render settings, light linking) inside
    ``scene_guard.preserved_scene`` and restores it; Blender reports that as updates, so the next call
    would capture again. Built right after the capture (``meter.measure_illuminance``), a Watch notes
    the entry; the measurement's ``progress`` and ``cancelled`` callbacks go through :meth:`wrap`, which
    evaluates the depsgraph before and after each call, so an edit made by a callback is seen and
    spoils the Watch; :meth:`done`, called only when the measurement succeeded (after the guard
    restored the scene), stamps the entry with the present update count. Nothing else runs inside a
    measurement (it is synchronous), and whatever fires no update is part of the key, recomputed then.
    """

    def __init__(self, scene, view_layer=None, exclude=()):
        self.scene, self.view_layer = scene, view_layer or scene.view_layers[0]
        self.key = None
        self.spoiled = False
        if _animated():
            return
        self.view_layer.update()
        key = _key(scene, self.view_layer, exclude)
        entry = _entries.get(key)
        if (entry is not None and entry[0] == _state["updates"]
                and entry[4] == _render_only_state(scene, self.view_layer)):
            self.key = key  # the measurement uses this entry's model, and nothing changed since

    def wrap(self, callback):
        """``callback`` with the depsgraph evaluated before and after it (None stays None)."""
        if callback is None or self.key is None:
            return callback

        def watched(*args, **kwargs):
            self.view_layer.update()  # the measurement's own pending changes: counted before the call
            before = _state["updates"]
            try:
                return callback(*args, **kwargs)
            finally:
                self.view_layer.update()
                if _state["updates"] != before:
                    self.spoiled = True  # the callback changed the scene

        # The callback's signature stays visible (progress.reporter decides its form from it).
        return functools.update_wrapper(watched, callback, assigned=(), updated=())

    def done(self):
        """The measurement succeeded and its guard restored the scene: keep the entry valid."""
        if self.key is None or self.spoiled:
            return
        self.view_layer.update()
        entry = _entries.get(self.key)
        if (entry is None or _animated() or _key(self.scene, self.view_layer, self.key[6]) != self.key
                or _render_only_state(self.scene, self.view_layer) != entry[4]):
            return
        _entries[self.key] = (*_stamp(), entry[3], entry[4], _state["other_updates"], entry[6])
        _state["restamps"] += 1


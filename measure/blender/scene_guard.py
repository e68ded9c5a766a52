"""Leave the user's scene exactly as it was, whatever happens during a measurement.

``preserved_scene`` snapshots every RNA property of the render-related structs (render, cycles,
bake, image settings, colour management, view layers' passes), the camera, frame, active object,
selection and world, plus the set of data-blocks in every ``bpy.data`` collection. On exit (normal,
exception, KeyboardInterrupt) it restores the properties and removes every data-block created
inside, so a measurement, even a failed or cancelled one, leaves no trace.
"""

import contextlib

import bpy

# bpy.data collections whose new members are removed on exit. Order matters a little: objects
# before the meshes/lights/cameras they use, materials before images/node groups/texts.
_DATA_COLLECTIONS = (
    "objects", "meshes", "lights", "cameras", "materials", "node_groups", "images", "textures",
    "worlds", "collections", "texts", "curves", "scenes",
)

# Properties computed from others: writing them back would round-trip through the others
# (white balance whitepoint <-> temperature/tint), so only their sources are restored.
_DERIVED = {"white_balance_whitepoint"}

# Properties whose values must not be written back (read-only at runtime or derived).
_SKIP = {"rna_type", "is_evaluated", "original", "users", "session_uid", "is_missing",
         "use_nodes"}  # Scene.use_nodes is deprecated in 5.0 (reading it warns)


_WRITABLE = {}  # RNA struct identifier -> identifiers of its writable plain properties
_NESTED = {}  # RNA struct identifier -> identifiers of its nested (non-ID) struct pointers

#: How deep nested setting structs are followed (render > image_settings > view_settings >
#: curve_mapping is 3). Every level is snapshotted and restored, parents first (setting a parent's
#: enum, e.g. file_format, resets its children, e.g. linear_colorspace_settings: issue 21).
MAX_DEPTH = 4


def _writable_identifiers(struct):
    # Walking bl_rna.properties is the slow part of a snapshot; the list depends only on the type.
    key = struct.bl_rna.identifier
    idents = _WRITABLE.get(key)
    if idents is None:
        idents = tuple(prop.identifier for prop in struct.bl_rna.properties
                       if prop.identifier not in _SKIP and not prop.is_readonly
                       and prop.type not in {"POINTER", "COLLECTION"})
        _WRITABLE[key] = idents
    return idents


# Nested structs that only hold a value when their parent says so (reading them otherwise logs
# "current value '-1' matches no enum" on every snapshot: a PNG output has no linear colour space).
_ONLY_WHEN = {"linear_colorspace_settings": "has_linear_colorspace"}


def _is_id(rna):
    while rna is not None:
        if rna.identifier == "ID":
            return True
        rna = rna.base
    return False


def _nested_identifiers(struct):
    """Pointer properties of ``struct`` to nested setting structs (not to data-blocks, which are
    restored by identity: camera, world)."""
    key = struct.bl_rna.identifier
    idents = _NESTED.get(key)
    if idents is None:
        idents = tuple(prop.identifier for prop in struct.bl_rna.properties
                       if prop.type == "POINTER" and prop.identifier not in _SKIP
                       and prop.fixed_type is not None and not _is_id(prop.fixed_type))
        _NESTED[key] = idents
    return idents


def _tree_values(struct, depth=MAX_DEPTH, seen=None):
    """``{"values": plain values, "nested": {ident: tree}}`` of ``struct`` and its nested structs."""
    seen = set() if seen is None else seen
    # A struct embedded first in its parent has the parent's address: the type tells them apart.
    seen.add((struct.bl_rna.identifier, struct.as_pointer()))
    nested = {}
    if depth > 0:
        for ident in _nested_identifiers(struct):
            flag = _ONLY_WHEN.get(ident)
            if flag is not None and not getattr(struct, flag, True):
                continue
            try:
                child = getattr(struct, ident)
            except (AttributeError, RuntimeError):
                continue
            if child is None or not hasattr(child, "bl_rna") \
                    or (child.bl_rna.identifier, child.as_pointer()) in seen:
                continue
            nested[ident] = _tree_values(child, depth - 1, seen)
    return {"values": _rna_values(struct), "nested": nested}


def _restore_tree(struct, tree):
    _restore_values(struct, tree["values"])  # parents first: their enums may reset the children
    for ident, child_tree in tree["nested"].items():
        try:
            child = getattr(struct, ident)
        except (AttributeError, RuntimeError):
            continue
        if child is not None:
            _restore_tree(child, child_tree)


def _rna_values(struct):
    """Plain values of the writable, non-pointer RNA properties of ``struct``."""
    values = {}
    for ident in _writable_identifiers(struct):
        try:
            value = getattr(struct, ident)
        except (AttributeError, RuntimeError):
            continue
        if isinstance(value, set):
            values[ident] = set(value)
        elif hasattr(value, "__len__") and not isinstance(value, str):
            values[ident] = tuple(value)
        else:
            values[ident] = value
    return values


def _same(current, value):
    if hasattr(current, "__len__") and not isinstance(current, (str, set)):
        return tuple(current) == tuple(value)
    return current == value


def _restore_values(struct, values):
    for ident, value in values.items():
        if ident in _DERIVED:
            continue
        try:
            if not _same(getattr(struct, ident), value):
                setattr(struct, ident, value)
        except (AttributeError, TypeError, RuntimeError, ValueError):
            # Properties that refuse a write (context-dependent enums) are left; they were not
            # changed by us either, since we only write properties we can write.
            pass


def _render_structs(scene):
    structs = {
        "render": scene.render,
        "image_settings": scene.render.image_settings,
        "bake": scene.render.bake,
        "view_settings": scene.view_settings,
        "display_settings": scene.display_settings,
        "scene": scene,
    }
    # The scene's own nested structs are walked through the entries above (render, view/display
    # settings, cycles), so the scene itself is taken flat (depth 0 in _snapshot_structs).
    if hasattr(scene, "cycles"):
        structs["cycles"] = scene.cycles
    for i, layer in enumerate(scene.view_layers):
        structs[f"view_layer{i}"] = layer
        if hasattr(layer, "cycles"):
            structs[f"view_layer{i}.cycles"] = layer.cycles
    return structs


def _snapshot_structs(scene):
    """Every writable property of the render-related structs, nested setting structs included
    (image settings' colour management, view settings and their curve mapping, bake settings and
    their image settings, ...): what a measurement may change and must give back."""
    return {key: _tree_values(s, 0 if key == "scene" else MAX_DEPTH) for key, s in _render_structs(scene).items()}


def _data_pointers():
    return {name: {id_.as_pointer() for id_ in getattr(bpy.data, name)} for name in _DATA_COLLECTIONS}


def _selection(view_layer):
    return {ob.name for ob in view_layer.objects if ob.select_get(view_layer=view_layer)}


class SceneSnapshot:
    def __init__(self, scene):
        self.scene = scene
        self.values = _snapshot_structs(scene)
        self.camera = scene.camera
        self.world = scene.world
        self.frame = (scene.frame_current, scene.frame_subframe)
        self.layers = []
        for layer in scene.view_layers:
            self.layers.append((layer, layer.objects.active, _selection(layer)))
        self.data = _data_pointers()
        self._remembered = []

    def remember(self, struct, attr):
        """Also restore ``struct.attr`` on exit (for data a measurement must change temporarily)."""
        self._remembered.append((struct, attr, getattr(struct, attr)))

    def restore(self):
        scene = self.scene
        for struct, attr, value in reversed(self._remembered):
            if getattr(struct, attr) != value:
                setattr(struct, attr, value)
        self._remove_new_data()
        for key, struct in _render_structs(scene).items():
            if key in self.values:
                _restore_tree(struct, self.values[key])
        if scene.camera != self.camera:
            scene.camera = self.camera
        if scene.world != self.world:
            scene.world = self.world
        if (scene.frame_current, scene.frame_subframe) != self.frame:
            scene.frame_set(self.frame[0], subframe=self.frame[1])
        for layer, active, selected in self.layers:
            layer.update()  # drop bases of objects removed above
            for ob in layer.objects:
                if ob is None:
                    continue
                want = ob.name in selected
                if ob.select_get(view_layer=layer) != want:
                    ob.select_set(want, view_layer=layer)
            if layer.objects.active != active:
                layer.objects.active = active

    def _remove_new_data(self):
        for name in _DATA_COLLECTIONS:
            collection = getattr(bpy.data, name)
            before = self.data[name]
            for id_ in [i for i in collection if i.as_pointer() not in before]:
                collection.remove(id_, do_unlink=True) if name != "scenes" else collection.remove(id_)


@contextlib.contextmanager
def preserved_scene(scene=None):
    """Context manager: everything a measurement changes is undone on exit, even on error."""
    scene = scene or bpy.context.scene
    snapshot = SceneSnapshot(scene)
    try:
        yield snapshot
    finally:
        snapshot.restore()


def scene_fingerprint(scene=None):
    """A comparable summary of everything a measurement must leave untouched (used by tests)."""
    scene = scene or bpy.context.scene
    layer = bpy.context.view_layer
    return {
        "values": _snapshot_structs(scene),
        "camera": scene.camera.name if scene.camera else None,
        "world": scene.world.name if scene.world else None,
        "frame": (scene.frame_current, scene.frame_subframe),
        "active": layer.objects.active.name if layer.objects.active else None,
        "selection": sorted(_selection(layer)),
        "counts": {name: len(getattr(bpy.data, name)) for name in _DATA_COLLECTIONS},
        "objects": sorted(
            (ob.name, tuple(ob.location), tuple(ob.rotation_euler), tuple(ob.scale),
             ob.parent.name if ob.parent else None, ob.hide_render, ob.hide_viewport, ob.visible_camera)
            for ob in scene.objects
        ),
        "lights": sorted((l.name, l.energy) for l in bpy.data.lights),
    }

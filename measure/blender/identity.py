"""Blender objects by identity, never by name (issue 17/18): the object part of a capture's
``radiometry.emitters.SourceId`` (session uid and library) and the objects behind such ids. A home
of its own so that both the capture (``scene_capture``) and the code that changes objects for a
measurement (``glass.swap_panes``) can use it without an import circle."""

import bpy


def object_identity(obj):
    """(session uid, library path or '') of an original object: the object part of a ``SourceId``."""
    library = obj.library.filepath if getattr(obj, "library", None) is not None else ""
    return int(getattr(obj, "session_uid", 0)), library


def source_objects(source_ids):
    """{(session uid, library): original object} for the objects behind ``SourceId``s (a capture's lights
    or meshes; a (session uid, library) pair works too), found by identity, never by name: a renamed
    object or a shared data-block is its own."""
    wanted = {tuple(sid[:2]) for sid in source_ids if sid is not None}
    found = {}
    for ob in bpy.data.objects:
        key = object_identity(ob)
        if key in wanted:
            found[key] = ob
    return found


def geometry_objects(geometry):
    """Per object of a captured ``SceneGeometry`` (its index k): the original Blender object, or None.
    By the capture's identity (``object_ids``: a renamed object is still found); by name only for
    hand-built geometry without ids (an instance's label "name (instance ...)" names its object)."""
    if len(geometry.object_ids) == len(geometry.object_names):
        found = source_objects(geometry.object_ids)
        return [found.get(tuple(sid)) for sid in geometry.object_ids]
    return [bpy.data.objects.get(name.split(" (instance ")[0]) for name in geometry.object_names]

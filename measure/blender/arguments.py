"""Checks of the Blender arguments of the public API (a scene; an object or its name): one line each,
like the plain checks in ``validation.py``, which stays free of bpy. Host code: bpy is imported inside
the functions, so ``import radiometer.api`` needs no Blender until a scene or an object is passed."""

from ...errors import RadiometerError
from ...validation import fail, shown_value


def scene(value, name="scene"):
    """None (the context scene) or a ``bpy.types.Scene`` that still exists."""
    if value is None:
        return None
    import bpy

    if not isinstance(value, bpy.types.Scene):
        fail(name, "a bpy.types.Scene or None", value)
    try:
        value.name  # noqa: B018 - a removed scene raises ReferenceError here
    except ReferenceError:
        raise RadiometerError(f"{name} was removed from the file") from None
    return value


def blender_object(value, name="object", *, scene_=None, types=None):
    """A ``bpy.types.Object`` or the name of one (in ``scene_`` when given); returns the object."""
    import bpy

    if isinstance(value, str):
        pool = scene_.objects if scene_ is not None else bpy.data.objects
        obj = pool.get(value)
        if obj is None:
            raise RadiometerError(f"no object named {shown_value(value)}"
                                  + (f" in scene {scene_.name!r}" if scene_ else ""))
        value = obj
    if not isinstance(value, bpy.types.Object):
        fail(name, "an object or an object's name", value)
    try:
        value.name  # noqa: B018
    except ReferenceError:
        raise RadiometerError(f"{name} was removed from the file") from None
    if types is not None and value.type not in types:
        raise RadiometerError(f"{name} {value.name!r} is not a " + " or ".join(t.lower() for t in types)
                              + f" (it is a {value.type.lower()})")
    return value

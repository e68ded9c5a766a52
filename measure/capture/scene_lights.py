"""A Blender light's emitter, and why a closed form may not cover it. ``measure.capture.scene_capture`` calls these
on every light of the RENDER depsgraph (so instanced and evaluated lights count exactly as Cycles renders
them); the photometric-power dialog (``measure.authoring.light_power``) calls ``emitter_of`` too.

``emitter_of`` is the one home from a ``bpy.types.Light`` to its emitter: it reads the light's values
here (host side) and hands them to the pure core's ``radiometry.emitters.from_blender_values``, which
never reads bpy (so the dict of values is only the hand-over between the two layers, and the pure
tier tests the conversion without Blender).
"""

from ...radiometry import emitters


_LIGHT_ATTRS = (
    "type", "energy", "color", "use_temperature", "temperature", "temperature_color", "exposure", "normalize",
    "use_soft_falloff", "shadow_soft_size", "spot_size", "spot_blend", "shape", "size", "size_y", "spread", "angle",
)


def emitter_of(light_data, matrix_world, scale_length, *, name=None, source_id=None,
               visibility=emitters.RayVisibility.ALL, energy=None):
    """The emitter (``radiometry.emitters``, SI) of a Blender light as Cycles renders it.

    Parameters
    ----------
    light_data : bpy.types.Light
        The (evaluated) light data-block.
    matrix_world : 4x4 matrix
        The instance's world matrix, scene units.
    scale_length : float
        Metres per scene unit.
    name, source_id, visibility
        Its label, stable identity (``emitters.SourceId``) and ray visibility, from the capture.
    energy : float or None
        Replaces the light's ``energy`` (W; sun W/m^2) when given: the power dialog reads per unit.

    Raises
    ------
    ValueError
        When the values have no closed form (``from_blender_values``).
    """
    values = light_values(light_data, matrix_world)
    if name is not None:
        values["name"] = name
    if energy is not None:
        values["energy"] = float(energy)
    return emitters.from_blender_values(values, scale_length, source_id=source_id, visibility=visibility)


def light_values(light_data, matrix_world):
    """Plain values of a light (named as Blender's Light RNA) and its ``matrix_world`` (nested lists,
    rows): what ``emitters.from_blender_values`` reads."""
    values = {}
    for attr in _LIGHT_ATTRS:
        if hasattr(light_data, attr):
            value = getattr(light_data, attr)
            values[attr] = tuple(value) if hasattr(value, "__len__") and not isinstance(value, str) else value
    values["matrix_world"] = [list(row) for row in matrix_world]
    table = _photometric_table(light_data)
    if table is not None:
        values["intensity_table"] = table
    return values


def _photometric_table(light_data):
    """The ``emitters.Photometry`` table (``light_table``) of a recognised IES light (``measure/capture/luminaires.py``), else None."""
    if not (getattr(light_data, "use_nodes", False) and getattr(light_data, "node_tree", None) is not None):
        return None
    from . import luminaires

    return luminaires.photometric_table(light_data)[0]


def uncovered_reason(light_data, obj):
    """Why a closed form cannot describe this light (None when it can)."""
    if getattr(light_data, "use_nodes", False) and light_data.node_tree is not None:
        from . import luminaires

        table, reason = luminaires.photometric_table(light_data)
        if table is None:
            return reason
    linking = getattr(obj, "light_linking", None)
    if linking is not None and (linking.receiver_collection is not None or linking.blocker_collection is not None):
        return "uses light linking"
    if not (obj.visible_diffuse or obj.visible_glossy):
        return "is invisible to diffuse rays"
    return None

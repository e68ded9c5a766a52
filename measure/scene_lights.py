"""A Blender light as plain values for its emitter (``radiometry.emitters.from_blender_values``), and why
a closed form may not cover it. ``measure.scene_capture`` calls these on every light of the RENDER depsgraph
(so instanced and evaluated lights count exactly as Cycles renders them).
"""


_LIGHT_ATTRS = (
    "type", "energy", "color", "use_temperature", "temperature", "temperature_color", "exposure", "normalize",
    "use_soft_falloff", "shadow_soft_size", "spot_size", "spot_blend", "shape", "size", "size_y", "spread", "angle",
)


def light_values(light_data, matrix_world):
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
    """``emitters.IntensityTable`` of a recognised IES light (``measure/luminaires.py``), else None."""
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

"""Read the scene's lights as plain values for the analytic models (``radiometry.lights``).

Everything is read from the EVALUATED depsgraph, so a script that moves a light and measures at once
gets the new position, and instanced lights count. Lights the closed forms do not cover are listed
with the reason (they are left to rendering).
"""

import bpy
import numpy as np

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
    """IntensityTable of a recognised IES light (``measure/luminaires.py``), else None."""
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


def scene_lights(scene=None, depsgraph=None):
    """List of dicts: name, values (for ``light_spec_from_values``), uncovered (reason or None)."""
    scene = scene or bpy.context.scene
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    lights = []
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        name = obj.original.name if obj.original else obj.name
        if inst.is_instance:
            name += f" (instance {inst.random_id})"
        lights.append({
            "name": name,
            "values": light_values(obj.data, inst.matrix_world),
            "uncovered": uncovered_reason(obj.data, obj),
        })
    return lights


def light_specs(scene=None, depsgraph=None):
    """(specs, uncovered) where specs are ``radiometry.lights.LightSpec`` in SI units."""
    from ..radiometry import lights as light_models

    scene = scene or bpy.context.scene
    scale = scene.unit_settings.scale_length
    specs, uncovered = [], []
    for item in scene_lights(scene, depsgraph):
        if item["uncovered"]:
            uncovered.append((item["name"], item["uncovered"]))
            continue
        values = dict(item["values"], name=item["name"])
        specs.append(light_models.light_spec_from_values(values, scale))
    return specs, uncovered

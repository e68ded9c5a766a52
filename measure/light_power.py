"""Read or set a Blender light's power in photometric units (lm, cd, lux, cd/m^2).

Uses the same convention as every reading: luminous = K x CIE Y of the light's RGB power in the
file's working colour space (K from the scene's Radiometer settings, default 683 lm/W). Colour,
temperature colour, exposure and normalize are honoured, because the conversion goes through the
same ``LightSpec`` the analytic meter uses; every quantity is linear in ``energy``.
"""

import math

import bpy
import numpy as np

from ..errors import RadiometerError
from . import meter, scene_lights

# unit -> (light types it applies to, label)
UNITS = {
    "LUMEN": ({"POINT", "SPOT", "AREA"}, "lm"),
    "CANDELA": ({"POINT", "SPOT"}, "cd"),
    "LUX": ({"SUN"}, "lx"),
    "NIT": ({"AREA"}, "cd/m²"),
}


def _per_unit_energy(obj, unit, scene):
    """Photometric value of ``obj`` per unit of ``energy`` (light data's own units)."""
    from ..radiometry import lights as light_models

    light = obj.data
    types, _label = UNITS[unit]
    if light.type not in types:
        allowed = ", ".join(u.lower() for u, (t, _l) in UNITS.items() if light.type in t)
        raise RadiometerError(f"{unit.lower()} does not apply to a {light.type.lower()} light; use {allowed}")
    values = scene_lights.light_values(light, obj.matrix_world)
    values["energy"] = 1.0
    spec = light_models.light_spec_from_values(values, scene.unit_settings.scale_length)
    _space, weights, efficacy = meter.scene_photometry(scene)
    if spec.intensity_table is not None:
        # A photometric (IES) light: its flux is its intensity integrated over the sphere (a
        # Fibonacci sphere of 200k directions: 1e-4 relative for a smooth table).
        if unit != "LUMEN":
            raise RadiometerError("a photometric (IES) light's intensities come from its file: set its lumens")
        count = 200_000
        k = np.arange(count) + 0.5
        z = 1.0 - 2.0 * k / count
        phi = np.pi * (1.0 + 5 ** 0.5) * k
        r = np.sqrt(1.0 - z * z)
        dirs = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
        intensity = light_models.radiant_intensity(spec, dirs) @ weights
        return efficacy * float(4 * math.pi * intensity.mean())
    flux = efficacy * float(np.asarray(spec.rgb_power) @ weights)
    if unit == "CANDELA":
        # Blender's point and spot lights: I = P / (4 pi) inside the cone, whatever its size.
        return flux / (4 * math.pi)
    if unit == "NIT":
        # Lambertian emitter: L = P / (pi A) with A the light's area in m^2 (object scale included).
        side_y = spec.size_y if spec.shape in ("RECTANGLE", "ELLIPSE") else spec.size
        area = spec.size * spec.scale[0] * side_y * spec.scale[1]
        area *= math.pi / 4 if spec.shape in ("DISK", "ELLIPSE") else 1.0
        return flux / (math.pi * area)
    return flux  # lumens (point, spot: flux of the equivalent point; area: total flux), lux (sun)


def photometric_power(obj, unit, scene=None):
    scene = scene or bpy.context.scene
    return obj.data.energy * _per_unit_energy(obj, unit, scene)


def set_photometric_power(obj, unit, value, scene=None):
    """Set ``obj.data.energy`` so that the light emits ``value`` in ``unit``; returns the energy."""
    scene = scene or bpy.context.scene
    value = float(value)
    if not math.isfinite(value) or value < 0:
        raise RadiometerError(f"photometric power must be a finite non-negative number, got {value}")
    per_unit = _per_unit_energy(obj, unit, scene)
    if per_unit <= 0:
        raise RadiometerError("the light's colour has no luminance: it cannot emit lumens")
    obj.data.energy = value / per_unit
    return obj.data.energy

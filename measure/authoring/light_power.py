"""Read or set a Blender light's power in photometric units (lm, cd, lux, cd/m^2).

Uses the same convention as every reading: luminous = K x CIE Y of the light's RGB power in the
file's working colour space (K from the scene's Radiometer settings, default 683 lm/W). Colour,
temperature colour, exposure and normalize are honoured, because the conversion goes through the
same emitter (``radiometry.emitters``) the analytic meter uses; every quantity is linear in ``energy``.
"""

import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry import emitters
from ..blender import request as request_of
from ..capture import scene_lights

# unit -> (light types it applies to, label)
UNITS = {
    "LUMEN": ({"POINT", "SPOT", "AREA"}, "lm"),
    "CANDELA": ({"POINT", "SPOT"}, "cd"),
    "LUX": ({"SUN"}, "lx"),
    "NIT": ({"AREA"}, "cd/m²"),
}


def _per_unit_energy(obj, unit, request):
    """Photometric value of ``obj`` per unit of ``energy`` (light data's own units), read from the
    light's emitter (``radiometry.emitters``): its flux, intensity and area have no other home."""
    light = obj.data
    types, _label = UNITS[unit]
    if light.type not in types:
        allowed = ", ".join(u.lower() for u, (t, _l) in UNITS.items() if light.type in t)
        raise RadiometerError(f"{unit.lower()} does not apply to a {light.type.lower()} light; use {allowed}")
    emitter = scene_lights.emitter_of(light, obj.matrix_world, request.scale_length, energy=1.0)
    _space, weights, efficacy = request.photometry
    if isinstance(emitter, emitters.PhotometricLight):
        # A photometric (IES) light: its flux is its table integrated over the sphere (the emitter's
        # one integration, emitters.photometric.table_flux).
        if unit != "LUMEN":
            raise RadiometerError("a photometric (IES) light's intensities come from its file: set its lumens")
        return emitter.luminous_flux_lm(weights, efficacy)
    # Blender's convention for point and spot lights: lumens are those of the equivalent point
    # (P, whatever the cone), and their intensity P / (4 pi) inside the cone.
    flux = efficacy * float(np.asarray(emitter.rgb_power) @ weights)
    if unit == "CANDELA":
        return efficacy * float(emitter.intensity_towards(emitter.emission_direction) @ weights)
    if unit == "NIT":
        # Lambertian emitter: L = P / (pi A) with A the light's area in m^2 (object scale included).
        return flux / (math.pi * emitter.area_m2)
    return flux  # lumens (point, spot: flux of the equivalent point; area: total flux), lux (sun)


def photometric_power(obj, unit, scene=None):
    """The light's emission in ``unit``; ``scene``: a request (``measure.blender.request``), a scene or None
    (the context's): its efficacy and unit scale."""
    return obj.data.energy * _per_unit_energy(obj, unit, request_of.of(scene))


def set_photometric_power(obj, unit, value, scene=None):
    """Set ``obj.data.energy`` so that the light emits ``value`` in ``unit``; returns the energy.
    ``scene`` as in :func:`photometric_power`."""
    value = float(value)
    if not math.isfinite(value) or value < 0:
        raise RadiometerError(f"photometric power must be a finite non-negative number, got {value}")
    per_unit = _per_unit_energy(obj, unit, request_of.of(scene))
    if per_unit <= 0:
        raise RadiometerError("the light's colour has no luminance: it cannot emit lumens")
    obj.data.energy = value / per_unit
    return obj.data.energy

"""The sun where it stands at a place and time: a Sun light pointed and scaled for the meter.

Host side (bpy) of ``api.sun_position`` / ``api.set_sun``. The position is
``radiometry.sun.solar_position`` (NREL SPA, pure numpy); this module turns it into a Blender Sun light:

* **Direction**: the light's local -Z (the way a Blender sun shines) points away from the sun, so
  its local +Z is :func:`radiometry.sun.solar_position.sun_direction` (+X east, +Y north, +Z up,
  rotated by the north offset: the angle from scene +Y to true north, counter-clockwise seen from
  above). Angular diameter 0.53 deg (the sun's mean apparent diameter).
* **Strength** (W/m^2 per scene unit^2, what Blender's *Strength* means for a sun): chosen so that
  Radiometer's meter reads the direct normal illuminance E_dn in lux: strength = E_dn x
  scale_length^2 / (K x Y(colour)), with K the scene's luminous efficacy (Radiometer's setting,
  683 lm/W by default) and Y the CIE Y of the light's colour in the working space. The colour is set
  to white (1, 1, 1: Y = 1), temperature off, exposure 0, so the strength is simply E_dn / K.
* **Spectrum** (for the melanopic readings): the light's ``radiometer_spectrum`` is set to CIE D55 when
  neither the object nor its light data has one (:data:`SUN_SPECTRUM`; a user's setting is kept).
* **E_dn**: given (``direct_normal_illuminance_lux``), or the IES clear-day model
  (``solar_position.clear_day_direct_normal_illuminance``: E_dn = 127.5 klx / R^2 x exp(-0.21 m),
  Kasten-Young air mass).
* **Below the horizon** (apparent elevation <= 0): the light stays, pointing from below, with
  strength 0 (and E_dn 0): it adds nothing, and moving the time brings it back.

The light is found again by its custom property ``radiometer_sun`` (created once, then updated);
the place and time are stored on it (``radiometer_sun_*`` properties) for the panel and reports.
"""

import datetime as _dt
import math

import bpy
import numpy as np

from ...errors import RadiometerError
from ...radiometry.sun import solar_position as sp
from ..meter.spectra import PROP_SPECTRUM

SUN_ANGLE_DEG = 0.53
#: The spectrum a new Radiometer sun is given for spectral readings (measure/meter/spectra.py reads the custom
#: property): CIE D55, the D-series phase photography takes for direct sunlight (~5500 K). A stated default:
#: the beam's spectrum depends on air mass and turbidity (warmer at low sun, where no D-series phase applies).
SUN_SPECTRUM = "D55"
PROP_SUN = "radiometer_sun"
DEFAULT_NAME = "Radiometer Sun"


def find_sun(scene):
    """The scene's Radiometer sun object (custom property ``radiometer_sun``), or None."""
    for ob in scene.objects:
        if ob.type == "LIGHT" and ob.get(PROP_SUN) and ob.data.type == "SUN":
            return ob
    return None


def sun_strength_w_m2(illuminance_lux, request, colour=(1.0, 1.0, 1.0)):
    """Blender sun strength (W/m^2 per scene unit^2) that the meter reads as ``illuminance_lux``
    (``request``: ``measure.blender.request``, its efficacy and unit scale)."""
    _space, weights, efficacy = request.photometry
    y = float(np.asarray(colour, float) @ weights)
    if not y > 0:
        raise RadiometerError(f"the sun's colour {tuple(colour)} has no luminance")
    return float(illuminance_lux) * request.unit_area / (efficacy * y)


def sun_position(latitude_deg, longitude_deg, when, **kwargs):
    """``radiometry.sun.solar_position.solar_position`` at the timezone-aware ``when`` (a datetime or a
    sequence of them; keyword arguments as there), with bad input as a one-line RadiometerError: what
    ``api.sun_position`` returns, for host code (which never imports the api)."""
    try:
        return sp.solar_position(sp.unix_seconds(when), latitude_deg, longitude_deg, **kwargs)
    except (TypeError, ValueError) as exc:
        raise RadiometerError(str(exc).splitlines()[0]) from None


def _when_text(when):
    return when.isoformat() if isinstance(when, _dt.datetime) else str(when)


def set_sun(scene, latitude_deg, longitude_deg, when, *, direct_normal_illuminance_lux=None, north_offset_deg=0.0,
            elevation_m=0.0, pressure_hpa=1013.25, temperature_c=12.0, sun=None):
    """Create or update the scene's Radiometer sun for this place and time; returns a dict.

    ``sun``: a Sun light object to update instead of the scene's Radiometer sun. Returns
    ``object`` (the light object's name), ``azimuth_deg``, ``elevation_deg``, ``zenith_deg``,
    ``direction`` (towards the sun, scene axes), ``direct_normal_illuminance_lux`` (0 below the
    horizon), ``strength_w_m2`` (the light's strength), ``model`` (where E_dn came from),
    ``above_horizon``, ``created`` and ``notes``. ``scene``: a request (``measure.blender.request``), a
    scene or None (the context's).
    """
    from ..blender import request as request_of

    request = request_of.of(scene)
    scene = request.scene
    if not isinstance(when, _dt.datetime):
        raise RadiometerError(f"set_sun takes one timezone-aware datetime, got {type(when).__name__}")
    if direct_normal_illuminance_lux is not None:
        e = float(direct_normal_illuminance_lux)
        if not (math.isfinite(e) and e >= 0.0):
            raise RadiometerError(f"direct normal illuminance must be a finite number >= 0 lux, got {e}")
    pos = sun_position(latitude_deg, longitude_deg, when, elevation_m=elevation_m, pressure_hpa=pressure_hpa,
                       temperature_c=temperature_c, north_offset_deg=north_offset_deg)
    above = bool(pos.elevation_deg > 0.0)
    if direct_normal_illuminance_lux is not None:
        e_dn = float(direct_normal_illuminance_lux) if above else 0.0
        model = "given"
    else:
        e_dn = float(sp.clear_day_direct_normal_illuminance(pos.zenith_deg, pos.earth_sun_distance_au))
        model = "IES clear-day model: E_dn = 127.5 klx / R^2 x exp(-0.21 m), Kasten-Young air mass"
    if sun is not None and (getattr(sun, "type", None) != "LIGHT" or sun.data.type != "SUN"):
        raise RadiometerError(f"{getattr(sun, 'name', sun)!r} is not a Sun light")
    obj = sun or find_sun(scene)
    created = obj is None
    if created:
        data = bpy.data.lights.new(DEFAULT_NAME, "SUN")
        obj = bpy.data.objects.new(DEFAULT_NAME, data)
        scene.collection.objects.link(obj)
        obj[PROP_SUN] = True
    light = obj.data
    from mathutils import Vector

    direction = np.asarray(pos.direction, float)
    obj.rotation_mode = "XYZ"
    obj.rotation_euler = Vector(direction.tolist()).to_track_quat("Z", "Y").to_euler("XYZ")
    light.angle = math.radians(SUN_ANGLE_DEG)
    light.color = (1.0, 1.0, 1.0)
    if hasattr(light, "use_temperature"):
        light.use_temperature = False
    if hasattr(light, "exposure"):
        light.exposure = 0.0
    strength = sun_strength_w_m2(e_dn, request)
    light.energy = strength
    obj["radiometer_sun_latitude_deg"] = float(latitude_deg)
    obj["radiometer_sun_longitude_deg"] = float(longitude_deg)
    obj["radiometer_sun_time"] = _when_text(when)
    obj["radiometer_sun_north_offset_deg"] = float(north_offset_deg)
    obj["radiometer_sun_direct_normal_lux"] = e_dn
    notes = [f"sun at azimuth {pos.azimuth_deg:.3f} deg, elevation {pos.elevation_deg:.3f} deg (apparent, NREL SPA)"]
    if PROP_SPECTRUM not in obj.keys() and PROP_SPECTRUM not in light.keys():
        # the spectral readings (CIE S 026) need the sun's spectrum; a user's own setting is kept
        light[PROP_SPECTRUM] = SUN_SPECTRUM
        notes.append(f"spectrum CIE {SUN_SPECTRUM} (a stated default for direct sunlight, ~5500 K; set the light's "
                     f"'{PROP_SPECTRUM}' to change it, e.g. 'D5000' or a spectral file)")
    if not above:
        notes.append("the sun is below the horizon: strength 0 (the light is kept, pointing from below)")
    return {"object": obj.name, "azimuth_deg": float(pos.azimuth_deg), "elevation_deg": float(pos.elevation_deg),
            "zenith_deg": float(pos.zenith_deg), "direction": direction.tolist(),
            "direct_normal_illuminance_lux": e_dn, "strength_w_m2": strength, "model": model,
            "above_horizon": above, "created": created, "notes": notes}

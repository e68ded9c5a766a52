"""Daylight operators: *Set Sun* points and scales the scene's sun for the panel's place and time."""

import bpy

from ..errors import RadiometerError
from .polls import needs

#: Last sun set per scene name (shown by panels/daylight.py; plain data, no maths).
LAST = {}


def settings_datetime(settings):
    """The timezone-aware datetime of the Daylight settings (RadiometerError with one line if invalid)."""
    from ..radiometry.sun import solar_position

    try:
        return solar_position.local_datetime(settings.year, settings.month, settings.day, settings.hour,
                                             settings.minute, settings.time_zone)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None


class RADIOMETER_OT_set_sun(bpy.types.Operator):
    """Create or update the scene's sun for the Daylight panel's place, date, time and north (undoable)"""

    bl_idname = "radiometer.set_sun"
    bl_label = "Set Sun"
    bl_options = {"REGISTER", "UNDO"}  # UNDO: Blender pushes an undo step after execute

    @classmethod
    def poll(cls, context):
        return needs(cls, context.scene is not None and hasattr(context.scene, "radiometer_daylight"), "no scene")

    def execute(self, context):
        import math

        from .. import api

        s = context.scene.radiometer_daylight
        try:
            when = settings_datetime(s)
            lux = s.direct_normal_illuminance if s.direct_normal_illuminance > 0 else None
            out = api.set_sun(context.scene, s.latitude, s.longitude, when, direct_normal_illuminance_lux=lux,
                              north_offset_deg=math.degrees(s.north_offset), elevation_m=s.site_elevation)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        LAST[context.scene.name] = dict(out, when=when.isoformat())
        state = (f"{out['direct_normal_illuminance_lux']:.0f} lx direct normal" if out["above_horizon"]
                 else "below the horizon: off")
        self.report({"INFO"}, f"Sun at azimuth {out['azimuth_deg']:.2f}°, elevation {out['elevation_deg']:.2f}°, "
                              f"{state}")
        return {"FINISHED"}


classes = (RADIOMETER_OT_set_sun,)

"""Daylight settings on the scene (``Scene.radiometer_daylight``): place, date, time, time zone, north.

The *Daylight* panel (panels/daylight.py) shows them; *Set Sun* (operators/daylight.py) turns them
into the scene's sun through ``api.set_sun``. No maths here.
"""

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

#: City presets: (identifier, label, latitude deg N, longitude deg E, IANA time zone).
CITIES = (
    ("LONDON", "London", 51.5074, -0.1278, "Europe/London"),
    ("PARIS", "Paris", 48.8566, 2.3522, "Europe/Paris"),
    ("BERLIN", "Berlin", 52.5200, 13.4050, "Europe/Berlin"),
    ("NEW_YORK", "New York", 40.7128, -74.0060, "America/New_York"),
    ("LOS_ANGELES", "Los Angeles", 34.0522, -118.2437, "America/Los_Angeles"),
    ("SAO_PAULO", "São Paulo", -23.5505, -46.6333, "America/Sao_Paulo"),
    ("CAPE_TOWN", "Cape Town", -33.9249, 18.4241, "Africa/Johannesburg"),
    ("DUBAI", "Dubai", 25.2048, 55.2708, "Asia/Dubai"),
    ("SINGAPORE", "Singapore", 1.3521, 103.8198, "Asia/Singapore"),
    ("TOKYO", "Tokyo", 35.6762, 139.6503, "Asia/Tokyo"),
    ("SYDNEY", "Sydney", -33.8688, 151.2093, "Australia/Sydney"),
    ("REYKJAVIK", "Reykjavík", 64.1466, -21.9426, "Atlantic/Reykjavik"),
)


def _apply_city(self, _context):
    for ident, _label, lat, lon, tz in CITIES:
        if ident == self.city:
            self.latitude, self.longitude, self.time_zone = lat, lon, tz
            return


class RadiometerDaylightSettings(bpy.types.PropertyGroup):
    city: EnumProperty(name="City", description="Fill in latitude, longitude and time zone from a city",
                       items=[("CUSTOM", "Custom", "Latitude, longitude and time zone as typed")]
                       + [(c[0], c[1], f"{c[1]}: {c[2]:.4f} N, {c[3]:.4f} E, {c[4]}") for c in CITIES],
                       default="CUSTOM", update=_apply_city)
    latitude: FloatProperty(name="Latitude", description="Geodetic latitude of the site, degrees (north positive)",
                            default=51.5074, min=-90.0, max=90.0, precision=4)
    longitude: FloatProperty(name="Longitude", description="Longitude of the site, degrees (east positive)",
                             default=-0.1278, min=-180.0, max=180.0, precision=4)
    site_elevation: FloatProperty(name="Site Elevation", description="Height of the site above sea level, m "
                                  "(parallax only)", default=0.0, min=-500.0, max=9000.0, unit="LENGTH")
    year: IntProperty(name="Year", description="Calendar year of the local date", default=2026, min=1, max=9999)
    month: IntProperty(name="Month", description="Month of the local date (1-12)", default=6, min=1, max=12)
    day: IntProperty(name="Day", description="Day of the month of the local date", default=21, min=1, max=31)
    hour: IntProperty(name="Hour", description="Local wall-clock hour (0-23) in the time zone below", default=12,
                      min=0, max=23)
    minute: IntProperty(name="Minute", description="Local wall-clock minute (0-59)", default=0, min=0, max=59)
    time_zone: StringProperty(name="Time Zone", description="IANA time zone name (Europe/London: daylight saving "
                              "applied) or a fixed UTC offset such as +02:00", default="Europe/London")
    north_offset: FloatProperty(name="North Offset", description="Angle from the scene's +Y axis to true north, "
                                "counter-clockwise seen from above", default=0.0, min=-360.0, max=360.0,
                                subtype="ANGLE", unit="ROTATION")
    direct_normal_illuminance: FloatProperty(
        name="Direct Normal (lx)", description="Illuminance of the sun on a surface facing it, lux; 0 uses the IES "
        "clear-day model (127.5 klx / R² · exp(-0.21 m))", default=0.0, min=0.0, soft_max=150000.0)


classes = (RadiometerDaylightSettings,)


def register_extra():
    bpy.types.Scene.radiometer_daylight = PointerProperty(type=RadiometerDaylightSettings)


def unregister_extra():
    del bpy.types.Scene.radiometer_daylight

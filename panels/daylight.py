"""Daylight panel (Properties > World): site, date, time, time zone and north for the scene's sun."""

import bpy

from . import SceneSettingsPanel, WorldPanel


class RADIOMETER_PT_daylight(SceneSettingsPanel, WorldPanel, bpy.types.Panel):
    bl_label = "Daylight"
    bl_idname = "RADIOMETER_PT_daylight"
    settings = "radiometer_daylight"

    def draw(self, context):
        from ..operators.daylight import LAST

        s = context.scene.radiometer_daylight
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "city")
        col = layout.column(align=True)
        col.prop(s, "latitude")
        col.prop(s, "longitude")
        col.prop(s, "site_elevation")
        col = layout.column(align=True)
        col.prop(s, "year")
        col.prop(s, "month")
        col.prop(s, "day")
        col = layout.column(align=True)
        col.prop(s, "hour")
        col.prop(s, "minute")
        layout.prop(s, "time_zone")
        layout.prop(s, "north_offset")
        layout.prop(s, "direct_normal_illuminance")
        layout.operator("radiometer.set_sun", icon="LIGHT_SUN")
        info = LAST.get(context.scene.name)
        if info is not None:
            col = layout.column(align=True)
            col.label(text=f"{info['when']}")
            col.label(text=f"Azimuth {info['azimuth_deg']:.2f}°  Elevation {info['elevation_deg']:.2f}°")
            if info["above_horizon"]:
                col.label(text=f"{info['direct_normal_illuminance_lux']:.0f} lx direct normal "
                               f"({'given' if info['model'] == 'given' else 'IES clear day'})")
            else:
                col.label(text="Below the horizon: sun off", icon="INFO")


classes = (RADIOMETER_PT_daylight,)

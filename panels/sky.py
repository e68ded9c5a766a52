"""CIE Sky panel (Properties > World): shows the scene's Radiometer CIE sky and the Set CIE Sky button."""

import bpy

from . import WorldPanel


class RADIOMETER_PT_cie_sky(WorldPanel, bpy.types.Panel):
    bl_label = "CIE Sky"
    bl_idname = "RADIOMETER_PT_cie_sky"

    @classmethod
    def poll(cls, context):
        return context.scene is not None

    def draw(self, context):
        import json

        from .. import api
        from ..errors import RadiometerError

        layout = self.layout
        world = context.scene.world
        tag = world.get("radiometer_cie_sky") if world is not None else None
        if tag:
            try:
                info = json.loads(tag)
                name = api.sky_model(info["sky_type"]).label
                col = layout.column(align=True)
                col.label(text=f"{name}: {info['horizontal_illuminance_lux']:.0f} lx horizontal", icon="WORLD")
                col.label(text=f"Zenith {info['zenith_luminance']:.0f} cd/m², ground {info['ground_luminance']:.0f} cd/m²")
            except (ValueError, KeyError, TypeError, RadiometerError):
                layout.label(text="CIE sky tag unreadable", icon="ERROR")
        layout.operator("radiometer.set_cie_sky", icon="LIGHT_SUN")


classes = (RADIOMETER_PT_cie_sky,)

"""World panel (Properties > World): the world's illuminance, its brightest direction, calibration."""

import bpy

from . import WorldPanel


class RADIOMETER_PT_world(WorldPanel, bpy.types.Panel):
    bl_label = "Radiometer"
    bl_idname = "RADIOMETER_PT_world"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.scene.world is not None

    def draw(self, context):
        from ..operators.world import LAST

        layout = self.layout
        info = LAST.get(context.scene.name)
        col = layout.column(align=True)
        if info is None:
            col.label(text="Not measured", icon="INFO")
        else:
            exact = ", exact" if info["exact"] else ""
            col.label(text=f"{info['illuminance']:.5g} lx on +Z ({info['method']}{exact})", icon="LIGHT_SUN")
            if info.get("brightest_luminance") is not None:
                d = info["brightest_direction"]
                col.label(text=f"Brightest {info['brightest_luminance']:.4g} cd/m² at ({d[0]:.2f}, {d[1]:.2f}, {d[2]:.2f})")
            for note in info["notes"][1:3]:
                col.label(text=note[:90])
        row = layout.row(align=True)
        row.operator("radiometer.world_illuminance", icon="PLAY")
        row.operator("radiometer.calibrate_world", icon="MODIFIER")
        layout.operator("radiometer.world_irradiance_map", icon="IMAGE_DATA")


classes = (RADIOMETER_PT_world,)

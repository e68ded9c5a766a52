"""Set a light's power in lumens, candela, lux (sun) or nits (area)."""

import bpy
from bpy.props import EnumProperty, FloatProperty

from ..errors import RadiometerError
from .polls import needs

_UNIT_ITEMS = [
    ("LUMEN", "Lumens (lm)", "Luminous flux (point, spot: of the equivalent point light; area: total)"),
    ("CANDELA", "Candela (cd)", "Luminous intensity of a point or spot light"),
    ("LUX", "Lux (lx)", "Illuminance on a surface facing the sun"),
    ("NIT", "Nits (cd/m²)", "Luminance of an area light's surface"),
]


class RADIOMETER_OT_set_light_power(bpy.types.Operator):
    """Set the active light's power from a photometric quantity (scene's luminous efficacy)"""

    bl_idname = "radiometer.set_light_power"
    bl_label = "Set Photometric Power"
    bl_options = {"REGISTER", "UNDO"}

    unit: EnumProperty(name="Unit", items=_UNIT_ITEMS, default="LUMEN",
                       description="The photometric quantity to set the light's power from")
    value: FloatProperty(name="Value", default=800.0, min=0.0, soft_max=1e6,
                         description="Amount in the chosen unit (lm, cd, lx or cd/m²); the dialog starts from "
                                     "the light's present value")

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return needs(cls, ob is not None and ob.type == "LIGHT", "select a light")

    def invoke(self, context, event):
        from .. import api

        ob = context.active_object
        units = [u for u, _label in api.photometric_units(ob.data.type)]
        if units and self.unit not in units:
            self.unit = units[0]
        try:
            self.value = api.photometric_power(ob, self.unit, scene=context.scene)
        except RadiometerError:
            pass  # keep the last value: the dialog still lets the user type one
        return context.window_manager.invoke_props_dialog(self, title=f"Set Photometric Power of {ob.name}")

    def execute(self, context):
        from .. import api

        try:
            energy = api.set_photometric_power(context.active_object, self.unit, self.value, scene=context.scene)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        # Blender's unit of Light.energy: W, except a sun's strength (irradiance, W/m²)
        unit = "W/m²" if getattr(context.active_object.data, "type", "") == "SUN" else "W"
        self.report({"INFO"}, f"{context.active_object.name}: energy set to {energy:.6g} {unit}")
        return {"FINISHED"}


class RADIOMETER_PT_light_power(bpy.types.Panel):
    bl_label = "Radiometer Photometry"
    bl_idname = "RADIOMETER_PT_light_power"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.light is not None and context.active_object is not None

    def draw(self, context):
        from .. import api

        layout = self.layout
        ob = context.active_object
        for unit, label in api.photometric_units(ob.data.type):
            try:
                value = api.photometric_power(ob, unit, scene=context.scene)
                layout.label(text=f"{value:.6g} {label}")
            except RadiometerError as exc:
                layout.label(text=str(exc), icon="ERROR")
        layout.label(text=f"K = {context.scene.radiometer.efficacy:g} lm/W")
        layout.operator("radiometer.set_light_power")


classes = (RADIOMETER_OT_set_light_power, RADIOMETER_PT_light_power)

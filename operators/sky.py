"""*Set CIE Sky*: make the scene's world a CIE standard sky (``api.set_cie_sky``), undoable."""

import bpy
from bpy.props import EnumProperty, FloatProperty

from ..errors import RadiometerError
from .polls import needs

def _sky_items(_self, _context):
    """One item per ``api.SKY_MODELS`` entry. The identifiers predate the mapping ("overcast", "12": its
    name less the "cie:" prefix) so that remembered operator settings still work; ``api.sky_model``
    reads both spellings."""
    from .. import api

    return [(name.removeprefix("cie:"), model.label, model.description) for name, model in api.SKY_MODELS.items()]


def scene_sun_direction(scene):
    """Unit vector towards the sun from the scene's first render-visible Sun light (its +Z axis), or None."""
    for ob in scene.objects:
        if ob.type == "LIGHT" and ob.data.type == "SUN" and not ob.hide_render:
            z = ob.matrix_world.to_3x3().col[2].normalized()
            return tuple(z)
    return None


class RADIOMETER_OT_set_cie_sky(bpy.types.Operator):
    """Make the scene's world a CIE standard sky scaled to a horizontal illuminance (the old world is kept in the file)"""

    bl_idname = "radiometer.set_cie_sky"
    bl_label = "Set CIE Sky"
    bl_options = {"REGISTER", "UNDO"}

    sky_type: EnumProperty(name="Sky", description="The sky model (api.SKY_MODELS): CIE overcast sky or ISO 15469 general sky type 1-15",
                           items=_sky_items)
    horizontal_illuminance: FloatProperty(
        name="Horizontal Illuminance (lx)", description="Unobstructed horizontal illuminance from the sky alone, lux",
        default=10_000.0, min=1.0, soft_max=120_000.0)
    ground_reflectance: FloatProperty(
        name="Ground Reflectance", description="Reflectance of the uniform ground below the sharp horizon "
        "(its luminance is this x E_h / pi)", default=0.2, min=0.0, max=1.0)

    @classmethod
    def poll(cls, context):
        return needs(cls, context.scene is not None, "no scene")

    def invoke(self, context, _event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        from .. import api

        model = api.sky_model(self.sky_type)
        sun = scene_sun_direction(context.scene)
        if model.needs_sun and sun is None:
            self.report({"ERROR"}, f"{model.label} depends on the sun: add a Sun light (Daylight panel: Set Sun)")
            return {"CANCELLED"}
        try:
            out = api.set_cie_sky(context.scene, model.name, horizontal_illuminance_lux=self.horizontal_illuminance,
                                  sun_direction=sun if model.needs_sun else None,
                                  ground_reflectance=self.ground_reflectance)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, out["notes"][0])
        return {"FINISHED"}


classes = (RADIOMETER_OT_set_cie_sky,)

"""World operators: the world's illuminance, calibration to a measured illuminance, irradiance map."""

import bpy
from bpy.props import FloatProperty, FloatVectorProperty

from ..errors import RadiometerError
from .polls import needs

#: Last world reading per scene name (shown by panels/world.py; plain data, no maths).
LAST = {}


def _needs_world(cls, context):
    return needs(cls, context.scene is not None and context.scene.world is not None, "the scene has no world")


class RADIOMETER_OT_world_illuminance(bpy.types.Operator):
    """Illuminance from the world alone on a surface facing the given normal"""

    bl_idname = "radiometer.world_illuminance"
    bl_label = "World Illuminance"
    bl_options = {"REGISTER"}

    normal: FloatVectorProperty(description="Surface normal the illuminance is measured on (world axes, normalised)",
                                name="Normal", default=(0.0, 0.0, 1.0), size=3)

    @classmethod
    def poll(cls, context):
        return _needs_world(cls, context)

    def execute(self, context):
        from .. import api

        try:
            info = api.world_illuminance(context.scene, tuple(self.normal))
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        LAST[context.scene.name] = info
        self.report({"INFO"}, f"World: {info['illuminance']:.5g} lx ({info['method']})")
        return {"FINISHED"}


class RADIOMETER_OT_calibrate_world(bpy.types.Operator):
    """Set the world's Background strength so the world alone gives this illuminance (undoable)"""

    bl_idname = "radiometer.calibrate_world"
    bl_label = "Calibrate World"
    bl_options = {"REGISTER", "UNDO"}  # UNDO: Blender pushes an undo step after execute

    illuminance: FloatProperty(description="Illuminance the world should produce on a surface with this normal, lx",
                               name="Illuminance (lx)", default=10000.0, min=1e-6, soft_max=150000.0)
    normal: FloatVectorProperty(description="Surface normal the illuminance is measured on (world axes, normalised)",
                                name="Normal", default=(0.0, 0.0, 1.0), size=3)

    @classmethod
    def poll(cls, context):
        return _needs_world(cls, context)

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        from .. import api

        try:
            out = api.calibrate_world(context.scene, self.illuminance, tuple(self.normal))
            LAST[context.scene.name] = api.world_illuminance(context.scene, tuple(self.normal))
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, out["notes"][0])
        return {"FINISHED"}


class RADIOMETER_OT_world_irradiance_map(bpy.types.Operator):
    """Compute the world's irradiance environment map and show it in an Image Editor"""

    bl_idname = "radiometer.world_irradiance_map"
    bl_label = "Irradiance Map"
    bl_options = {"REGISTER", "UNDO"}  # loads the map as an image data-block

    @classmethod
    def poll(cls, context):
        return _needs_world(cls, context)

    def execute(self, context):
        import os

        from .. import api

        path = api.default_map_path(f"{context.scene.name}_irradiance")
        try:
            out = api.irradiance_environment_map("world", path, scene=context.scene)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        image = bpy.data.images.load(out["path"], check_existing=True)
        image.reload()
        for area in getattr(context.screen, "areas", []) if context.screen else []:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                break
        self.report({"INFO"}, f"Irradiance map {os.path.basename(out['path'])} loaded as image {image.name!r}")
        return {"FINISHED"}


classes = (RADIOMETER_OT_world_illuminance, RADIOMETER_OT_calibrate_world, RADIOMETER_OT_world_irradiance_map)

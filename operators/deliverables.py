"""Deliverable pictures in Blender: the camera view's false-colour luminance image, shown in the image
editor (thin: one ``api.luminance_image`` call, the PNG loaded as an image data-block)."""

import bpy
from bpy.props import EnumProperty

from ..errors import RadiometerError
from .polls import needs


class RADIOMETER_OT_luminance_image(bpy.types.Operator):
    """Render the scene camera's view as a false-colour luminance (cd/m²) or illuminance (lx) image with a
    legend and show it in an Image Editor"""

    bl_idname = "radiometer.luminance_image"
    bl_label = "False-Colour Image"
    bl_options = {"REGISTER", "UNDO"}  # loads the picture as an image data-block: one undo step removes it

    quantity: EnumProperty(name="Quantity", description="What the false colours show",
                           items=(("LUMINANCE", "Luminance (cd/m²)", "What the camera sees, in cd/m²"),
                                  ("ILLUMINANCE", "Illuminance (lx)", "Light arriving on the visible surfaces, in lx "
                                   "(exact on Lambertian surfaces; 0 on metal, glass and emitters)")),
                           default="LUMINANCE")

    scale: EnumProperty(name="Scale", description="Colour scale of the false-colour legend",
                        items=(("log", "Logarithmic", "Decades of luminance, as Radiance's falsecolor -log"),
                               ("linear", "Linear", "0 to the brightest pixels (99.5th percentile)")),
                        default="log")

    @classmethod
    def poll(cls, context):
        return needs(cls, context.scene is not None and context.scene.camera is not None, "the scene has no camera")

    def execute(self, context):
        import os

        from .. import api, outputs

        scene = context.scene
        what = self.quantity.lower()
        path = os.path.join(outputs.user_folder("images"), f"{outputs.file_stem(scene.camera.name)}_{what}.exr")
        make = api.luminance_image if self.quantity == "LUMINANCE" else api.illuminance_image
        try:
            img = make(path, scene=scene, quality=scene.radiometer.quality, scale=self.scale)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        shown = img.paths.get("png", img.paths["exr"])
        image = bpy.data.images.load(shown, check_existing=True)
        image.reload()
        for area in getattr(context.screen, "areas", []) if context.screen else []:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                break
        self.report({"INFO"}, f"{self.quantity.capitalize()} image {os.path.basename(shown)} loaded as image {image.name!r} "
                              f"({img.resolution[0]} x {img.resolution[1]} px)")
        return {"FINISHED"}


classes = (RADIOMETER_OT_luminance_image,)

"""BRDF operators: assign the material's Radiometer BRDF, and plot a BRDF summary image."""

import os
import tempfile

import bpy

from ..errors import RadiometerError


def _active_material(context):
    mat = getattr(context, "material", None)
    if mat is None and context.object is not None:
        mat = context.object.active_material
    return mat


def _poll_material(cls, context):
    if _active_material(context) is None:
        cls.poll_message_set("needs an active object with an active material")
        return False
    if not hasattr(bpy.types.Material, "radiometer_brdf"):
        cls.poll_message_set("Radiometer is not registered")
        return False
    return True


class RADIOMETER_OT_assign_brdf(bpy.types.Operator):
    """Realise the chosen BRDF on the active material (node group or OSL script)"""

    bl_idname = "radiometer.assign_brdf"
    bl_label = "Apply BRDF"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _poll_material(cls, context)

    def execute(self, context):
        from ..props.brdf import _params_dict
        from ..shading.assign import assign_brdf

        mat = _active_material(context)
        s = mat.radiometer_brdf
        if len(s.params) == 0:
            from ..props.brdf import sync_params

            sync_params(s, s.model)
        try:
            fid = assign_brdf(mat, s.model, s.method, **_params_dict(s))
        except RadiometerError as exc:
            s.error = str(exc)
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"{mat.name}: {s.model} via {fid.closure} ({fid.summary()})")
        if s.method == "osl" and "renders black" in fid.notes:
            self.report({"WARNING"}, "OSL is not active in this scene: use Enable OSL in the panel")
        if fid.notes:
            self.report({"INFO"}, fid.notes)
        return {"FINISHED"}


def plot_directory():
    """Where plots go: the extension's user directory, or a temporary one outside an extension."""
    root = __package__.rsplit(".", 1)[0]
    try:
        return bpy.utils.extension_path_user(root, path="plots", create=True)
    except (ValueError, KeyError, RuntimeError):
        path = os.path.join(tempfile.gettempdir(), "radiometer_plots")
        os.makedirs(path, exist_ok=True)
        return path


class RADIOMETER_OT_brdf_plot(bpy.types.Operator):
    """Plot the material's BRDF (library summary plot) and show it in an Image Editor"""

    bl_idname = "radiometer.brdf_plot"
    bl_label = "Plot BRDF"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return _poll_material(cls, context)

    def execute(self, context):
        from ..props.brdf import _params_dict
        from ..shading.plot import write_plot

        mat = _active_material(context)
        s = mat.radiometer_brdf
        path = os.path.join(plot_directory(), f"brdf_{s.model}.png")
        try:
            write_plot(s.model, path, **_params_dict(s))
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        image = bpy.data.images.get(os.path.basename(path))
        if image is not None and image.filepath == path:
            image.reload()
        else:
            image = bpy.data.images.load(path, check_existing=True)
        shown = False
        for area in (context.screen.areas if context.screen else []):
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                shown = True
                break
        self.report({"INFO"}, f"BRDF plot written to {path}" + ("" if shown else " (open an Image Editor to see it)"))
        return {"FINISHED"}


class RADIOMETER_OT_enable_osl(bpy.types.Operator):
    """Render this scene with Open Shading Language (Cycles, CPU): needed by OSL BRDF materials"""

    bl_idname = "radiometer.enable_osl"
    bl_label = "Enable OSL"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if context.scene is None or not hasattr(context.scene, "cycles"):
            cls.poll_message_set("needs a scene with Cycles available")
            return False
        return True

    def execute(self, context):
        scene = context.scene
        changed = []
        if scene.render.engine != "CYCLES":
            scene.render.engine = "CYCLES"
            changed.append("render engine -> Cycles")
        if not scene.cycles.shading_system:
            scene.cycles.shading_system = True
            changed.append("Open Shading Language on")
        if scene.cycles.device != "CPU":
            scene.cycles.device = "CPU"
            changed.append("device -> CPU (OSL does not run on GPUs)")
        self.report({"INFO"}, f"{scene.name}: " + (", ".join(changed) if changed else "OSL was already on"))
        return {"FINISHED"}


classes = (RADIOMETER_OT_assign_brdf, RADIOMETER_OT_brdf_plot, RADIOMETER_OT_enable_osl)

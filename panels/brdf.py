"""Material Properties > Radiometer BRDF: model, method, parameters, Apply, fidelity."""

import bpy


def format_fidelity(settings):
    """'exact' or 'approximate: RMS 3.2 %, albedo Δ 0.004' (or '' when not applied)."""
    if not settings.applied:
        return ""
    return settings.fidelity_summary or settings.fidelity_kind


class RADIOMETER_PT_brdf(bpy.types.Panel):
    bl_label = "Radiometer BRDF"
    bl_idname = "RADIOMETER_PT_brdf"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return getattr(context, "material", None) is not None and hasattr(context.material, "radiometer_brdf")

    def draw(self, context):
        layout = self.layout
        mat = context.material
        s = mat.radiometer_brdf
        if mat.library is not None:
            layout.label(text=f"Linked from {mat.library.filepath}: make the material local to edit it",
                         icon="LIBRARY_DATA_DIRECT")
            return
        col = layout.column()
        col.prop(s, "model")
        col.prop(s, "method")
        box = layout.box()
        if len(s.params) == 0:
            box.label(text="Parameters appear after Apply (defaults from the library)")
        for item in s.params:
            label = f"{item.name} [{item.unit}]" if item.unit else item.name
            row = box.row()
            if item.optional:
                row.prop(item, "use", text="")
                row = row.row()
                row.enabled = item.use
            if item.kind == "color":
                row.prop(item, "color", text=label)
            elif item.kind == "float":
                row.prop(item, "value", text=label)
            else:
                row.prop(item, "text", text=label)
        row = layout.row(align=True)
        row.operator("radiometer.assign_brdf", icon="MATERIAL")
        row.operator("radiometer.brdf_plot", icon="IMAGE_DATA")
        layout.prop(s, "live_update")
        if s.error:
            layout.label(text=s.error, icon="ERROR")
        if s.applied:
            col = layout.column(align=True)
            col.label(text=f"Fidelity: {format_fidelity(s)}",
                      icon="CHECKMARK" if s.fidelity_kind == "exact" else "INFO")
            col.label(text=f"Cycles: {s.fidelity_closure}")
            if s.method == "osl":
                from ..shading.osl import osl_problems

                problems = osl_problems(context.scene)
                for p in problems:
                    col.label(text=p, icon="ERROR")
                if problems:
                    col.operator("radiometer.enable_osl", icon="SCRIPT")
            elif s.fidelity_kind == "approximate" and s.model == "phong":
                col.label(text="OSL realises Phong exactly (method OSL Script)", icon="INFO")


classes = (RADIOMETER_PT_brdf,)

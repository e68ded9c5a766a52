"""Sidebar panel (tab "Radiometer"): analysis buttons and tables of the last results."""

import bpy

from . import SceneSettingsPanel, SidebarPanel


def _yes(ok, expected=False):
    """'ok', 'near field' (the light departs exactly as its shape's closed form predicts: physics) or 'departs'."""
    return "ok" if ok else "near field" if expected else "departs"


class RADIOMETER_PT_analysis(SceneSettingsPanel, SidebarPanel, bpy.types.Panel):
    bl_label = "Analysis"
    bl_idname = "RADIOMETER_PT_analysis"
    bl_options = {"DEFAULT_CLOSED"}
    settings = "radiometer_analysis"

    def draw(self, context):
        from .meter import draw_progress

        s = context.scene.radiometer_analysis
        layout = self.layout
        if hasattr(context.scene, "radiometer"):
            draw_progress(layout, context.scene.radiometer)
        layout.prop(s, "output_dir")
        row = layout.row(align=True)
        row.operator_menu_enum("radiometer.check_inverse_square", "light", text="Inverse Square")
        row.operator_menu_enum("radiometer.check_cosine_law", "light", text="Cosine Law")
        if len(s.laws):
            table = layout.box().column(align=True)
            head = table.row()
            for text in ("Light", "1/d² exp.", "Near (m)", "", "cos dev", ""):
                head.label(text=text)
            for item in s.laws:
                r = table.row()
                r.label(text=item.name)
                if item.inverse_checked:
                    r.label(text=f"{item.exponent:.3f}")
                    r.label(text="never" if item.near_field_limit < 0 else f"{item.near_field_limit:.3g}")
                    r.label(text=_yes(item.inverse_passed, item.inverse_expected))
                else:
                    r.label(text="n/a")
                    r.label(text="")
                    r.label(text="")
                if item.cosine_checked:
                    r.label(text=f"{100 * item.cosine_max_dev:.3g} %")
                    r.label(text=_yes(item.cosine_passed, item.cosine_expected))
                else:
                    r.label(text="")
                    r.label(text="")
                for label, causes in (("1/d²", item.inverse_causes), ("cos", item.cosine_causes)):
                    for cause in causes.split(" | ") if causes else ():
                        table.label(text=f"   {label}: {cause[:110]}", icon="INFO")


class _AnalysisSubpanel(SidebarPanel):
    """Mixin: a subpanel of the Analysis panel."""

    bl_parent_id = "RADIOMETER_PT_analysis"


class RADIOMETER_PT_grid(_AnalysisSubpanel, bpy.types.Panel):
    bl_label = "Work-Plane Grid"
    bl_idname = "RADIOMETER_PT_grid"

    def draw(self, context):
        s = context.scene.radiometer_analysis
        layout = self.layout
        col = layout.column(align=True)
        col.prop(s, "work_plane")
        if s.work_plane is None:
            col.prop(s, "plane_height")
        col.prop(s, "use_resolution")
        if s.use_resolution:
            row = col.row(align=True)
            row.prop(s, "resolution_x")
            row.prop(s, "resolution_y")
        else:
            col.prop(s, "spacing")
        col.prop(s, "colour_plane")
        op = layout.operator("radiometer.illuminance_grid", icon="MESH_GRID")
        op.create_plane = s.work_plane is None
        if s.grid_target:
            box = layout.box().column(align=True)
            box.label(text=f"{s.grid_target}: {s.grid_nx} x {s.grid_ny} points [{s.grid_method}]")
            box.label(text=f"E_avg {s.grid_avg:.4g} lx   E_min {s.grid_min:.4g} lx")
            box.label(text=f"E_max {s.grid_max:.4g} lx   U0 {s.grid_u0:.3f}")
            if s.grid_image:
                box.label(text=bpy.path.basename(s.grid_image), icon="IMAGE_DATA")
            from ..operators.false_colour import is_shown

            shown = is_shown()
            layout.operator("radiometer.toggle_false_colour", icon="HIDE_ON" if shown else "COLOR",
                            text="Hide False Colour" if shown else "Show False Colour")


class RADIOMETER_PT_convergence(_AnalysisSubpanel, bpy.types.Panel):
    bl_label = "Convergence and Report"
    bl_idname = "RADIOMETER_PT_convergence"

    def draw(self, context):
        s = context.scene.radiometer_analysis
        layout = self.layout
        layout.prop(s, "target_error")
        layout.operator("radiometer.convergence_study", icon="GRAPH")
        if s.conv_target:
            box = layout.box().column(align=True)
            box.label(text=f"{s.conv_target}: error ~ N^{s.conv_slope:.2f} ± {s.conv_slope_se:.2f}")
            box.label(text=f"{100 * s.target_error:g} %: ~{s.conv_samples:.3g} samples, ~{s.conv_seconds:.3g} s")
        layout.operator("radiometer.export_report", icon="EXPORT")
        if s.report_path:
            layout.label(text=s.report_path, icon="FILE_TEXT")


classes = (RADIOMETER_PT_analysis, RADIOMETER_PT_grid, RADIOMETER_PT_convergence)

"""Sidebar panel (tab "Radiometer") and viewport text showing each meter's reading."""

import math

import bpy

from . import SidebarPanel

from ..readings import format_error, format_value  # the one digits rule, shared with the CLI and the reports

_draw_handle = None


def format_reading(meter):
    """One line with units, e.g. '512 lx ±1.1 %' (used by the panel and the viewport overlay)."""
    if not meter.has_reading:
        return "not measured"
    unit = "cd/m²" if meter.kind == "LUMINANCE" else "lx"
    return f"{format_value(meter.photometric, meter.rel_std_error, meter.exact)} {unit} " \
           f"{format_error(meter.rel_std_error, meter.exact)}"


# Every Radiometer operator, so F3 (menu search) finds each one; operators registered by other
# modules later are listed after these.
MENU_OPERATORS = ("measure", "add_meter", "add_meter_on_surface", "set_light_power", "check_inverse_square", "check_cosine_law",
                  "illuminance_grid", "convergence_study", "export_report", "assign_brdf", "brdf_plot")


class RADIOMETER_MT_main(bpy.types.Menu):
    """Radiometer: light meters, law checks, grids, reports and BRDFs"""

    bl_label = "Radiometer"
    bl_idname = "RADIOMETER_MT_main"

    def draw(self, context):
        layout = self.layout
        layout.operator_context = "INVOKE_DEFAULT"
        layout.operator("radiometer.measure", icon="PLAY")
        layout.operator_menu_enum("radiometer.add_meter", "kind", text="Add Light Meter", icon="LIGHT_SUN")
        layout.operator("radiometer.add_meter_on_surface", text="Add Light Meter on Surface", icon="SNAP_FACE")
        layout.operator("radiometer.set_light_power", icon="LIGHT")
        layout.separator()
        layout.operator("radiometer.check_inverse_square")
        layout.operator("radiometer.check_cosine_law")
        layout.operator("radiometer.illuminance_grid")
        layout.operator("radiometer.convergence_study")
        layout.operator("radiometer.export_report", icon="TEXT")
        layout.separator()
        layout.operator("radiometer.assign_brdf", icon="MATERIAL")
        layout.operator("radiometer.brdf_plot")
        others = sorted(set(dir(bpy.ops.radiometer)) - set(MENU_OPERATORS))
        if others:
            layout.separator()
            for name in others:
                layout.operator(f"radiometer.{name}")


def _draw_menu_entry(self, _context):
    self.layout.menu(RADIOMETER_MT_main.bl_idname)


def draw_progress(layout, settings):
    """The running Radiometer operation's progress bar (written by operators/modal.py), if any."""
    if settings.progress_text:
        layout.progress(factor=settings.progress, type="BAR", text=settings.progress_text.split("   ")[0])
        layout.label(text="Esc cancels", icon="CANCEL")


class RADIOMETER_PT_meters(SidebarPanel, bpy.types.Panel):
    bl_label = "Light Meters"
    bl_idname = "RADIOMETER_PT_meters"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.radiometer
        draw_progress(layout, settings)
        col = layout.column(align=True)
        col.prop(settings, "method")
        col.prop(settings, "quality")
        col.prop(settings, "target_rel_error")
        col.prop(settings, "efficacy_convention")
        sub = col.row()
        sub.enabled = settings.efficacy_convention == "CUSTOM"
        sub.prop(settings, "efficacy")
        col.prop(settings, "show_overlay")
        col.prop(settings, "live", icon="REC")
        if settings.live:
            from ..props import live_state

            col.label(text=live_state.status(context.scene) or "Live: waiting for a change", icon="TIME")
        row = layout.row(align=True)
        row.operator_menu_enum("radiometer.add_meter", "kind", text="Add Meter", icon="ADD")
        row.operator("radiometer.measure", icon="PLAY")
        meters = [ob for ob in context.scene.objects if ob.radiometer_meter.is_meter]
        if not meters:
            layout.label(text="No meters: Add > Light Meter", icon="INFO")
        for ob in meters:
            layout.label(text=f"{ob.name}: {format_reading(ob.radiometer_meter)}", icon="LIGHT_SUN")
        if settings.last_summary:
            layout.label(text="Last: " + settings.last_summary[:120])


class RADIOMETER_PT_active_meter(SidebarPanel, bpy.types.Panel):
    bl_label = "Active Meter"
    bl_idname = "RADIOMETER_PT_active_meter"
    bl_parent_id = "RADIOMETER_PT_meters"

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return ob is not None and ob.radiometer_meter.is_meter

    def draw(self, context):
        m = context.active_object.radiometer_meter
        layout = self.layout
        layout.prop(m, "kind")
        if m.kind == "LUMINANCE":
            layout.prop(m, "acceptance_deg")
        if m.kind == "RADIANCE_MAP":
            layout.prop(m, "map_resolution")
            if m.map_path:
                layout.label(text=m.map_path)
        if not m.has_reading:
            layout.label(text="Not measured yet")
            return
        radiometric = "W/(m² sr)" if m.kind == "LUMINANCE" else "W/m²"
        photometric = "cd/m²" if m.kind == "LUMINANCE" else "lx"
        col = layout.column(align=True)
        col.label(text=f"{format_value(m.photometric, m.rel_std_error, m.exact)} {photometric}")
        col.label(text=f"{m.value:.6g} {radiometric}  (RGB {m.value_rgb[0]:.4g}, {m.value_rgb[1]:.4g}, "
                       f"{m.value_rgb[2]:.4g})")
        col.label(text="exact" if m.exact else
                  f"relative standard error {100 * m.rel_std_error:.3g} %" if math.isfinite(m.rel_std_error) else
                  "relative standard error unknown: no light found yet (see the notes)")
        col.label(text=f"{m.method}, {m.samples} samples, {m.seconds:.3g} s, K = {m.efficacy:g} lm/W")
        from ..compat import working_colour_space
        from ..readings import photographic_text

        space = working_colour_space()
        photo = photographic_text("luminance" if m.kind == "LUMINANCE" else "illuminance", m.photometric,
                                  tuple(m.value_rgb), space)
        if photo and m.kind != "RADIANCE_MAP":
            col.label(text=photo, icon="CAMERA_DATA")
        if m.kind == "ILLUMINANCE":
            row = layout.row(align=True)
            row.operator("radiometer.melanopic_reading", icon="LIGHT").reflected = False
            row.operator("radiometer.melanopic_reading", text="With Reflections", icon="LIGHT_AREA").reflected = True
            if m.spectral_status:
                col = layout.column(align=True)
                whole = m.spectral_status.startswith("direct + reflected")
                col.label(text=f"mel-EDI {m.mel_edi:.4g} lx ({'direct + reflected' if whole else 'direct light'}), "
                               f"mel-DER {m.mel_der:.3g}" + ("" if whole else f", S/P {m.sp_ratio:.3g}"))
                col.label(text=m.spectral_status[:140])
        box = layout.box()
        for note in m.notes.split(" | "):
            box.label(text=note[:140])


def _draw_overlay():
    import blf
    from bpy_extras.view3d_utils import location_3d_to_region_2d

    context = bpy.context
    scene = context.scene
    if scene is None or not hasattr(scene, "radiometer") or not scene.radiometer.show_overlay:
        return
    space = context.space_data
    if space is None or not getattr(space.overlay, "show_overlays", True):
        return  # the viewport's Overlays toggle hides our text too
    region, rv3d = context.region, space.region_3d
    if region is None or rv3d is None:
        return
    font = 0
    scale = context.preferences.system.ui_scale if context.preferences else 1.0
    blf.size(font, 12 * scale)
    if scene.radiometer.live:
        from ..props import live_state

        blf.position(font, 20 * scale, 20 * scale, 0)
        blf.draw(font, "Radiometer " + (live_state.status(scene) or "Live"))
    for ob in scene.objects:
        m = ob.radiometer_meter
        if not m.is_meter or not ob.visible_get():
            continue
        pos = location_3d_to_region_2d(region, rv3d, ob.matrix_world.translation)
        if pos is None:
            continue
        blf.position(font, pos.x + 8 * scale, pos.y + 8 * scale, 0)
        blf.draw(font, format_reading(m))


classes = (RADIOMETER_PT_meters, RADIOMETER_PT_active_meter, RADIOMETER_MT_main)


def register_extra():
    global _draw_handle
    _draw_handle = bpy.types.SpaceView3D.draw_handler_add(_draw_overlay, (), "WINDOW", "POST_PIXEL")
    bpy.types.VIEW3D_MT_object.append(_draw_menu_entry)


def unregister_extra():
    global _draw_handle
    bpy.types.VIEW3D_MT_object.remove(_draw_menu_entry)
    if _draw_handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle, "WINDOW")
        _draw_handle = None

"""Sidebar panel (tab "Radiometer") and viewport text showing each meter's reading."""

import bpy

_draw_handle = None


def format_reading(meter):
    """One line with units, e.g. '512.3 lx ±0.4 %' (used by the panel and the viewport overlay)."""
    if not meter.has_reading:
        return "not measured"
    unit = "cd/m²" if meter.kind == "LUMINANCE" else "lx"
    err = "exact" if meter.exact else f"±{100 * meter.rel_std_error:.2g} %"
    return f"{meter.photometric:.4g} {unit} {err}"


def draw_progress(layout, settings):
    """The running Radiometer operation's progress bar (written by operators/modal.py), if any."""
    if settings.progress_text:
        layout.progress(factor=settings.progress, type="BAR", text=settings.progress_text.split("   ")[0])
        layout.label(text="Esc cancels", icon="CANCEL")


class RADIOMETER_PT_meters(bpy.types.Panel):
    bl_label = "Light Meters"
    bl_idname = "RADIOMETER_PT_meters"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Radiometer"

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


class RADIOMETER_PT_active_meter(bpy.types.Panel):
    bl_label = "Active Meter"
    bl_idname = "RADIOMETER_PT_active_meter"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Radiometer"
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
        col.label(text=f"{m.photometric:.6g} {photometric}")
        col.label(text=f"{m.value:.6g} {radiometric}  (RGB {m.value_rgb[0]:.4g}, {m.value_rgb[1]:.4g}, "
                       f"{m.value_rgb[2]:.4g})")
        col.label(text="exact" if m.exact else f"relative standard error {100 * m.rel_std_error:.3g} %")
        col.label(text=f"{m.method}, {m.samples} samples, {m.seconds:.3g} s, K = {m.efficacy:g} lm/W")
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
    region, rv3d = context.region, context.space_data.region_3d if context.space_data else None
    if region is None or rv3d is None:
        return
    font = 0
    blf.size(font, 12)
    for ob in scene.objects:
        m = ob.radiometer_meter
        if not m.is_meter or not ob.visible_get():
            continue
        pos = location_3d_to_region_2d(region, rv3d, ob.matrix_world.translation)
        if pos is None:
            continue
        blf.position(font, pos.x + 8, pos.y + 8, 0)
        blf.draw(font, format_reading(m))


classes = (RADIOMETER_PT_meters, RADIOMETER_PT_active_meter)


def register_extra():
    global _draw_handle
    _draw_handle = bpy.types.SpaceView3D.draw_handler_add(_draw_overlay, (), "WINDOW", "POST_PIXEL")


def unregister_extra():
    global _draw_handle
    if _draw_handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle, "WINDOW")
        _draw_handle = None

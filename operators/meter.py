"""Light meter operators: add a meter, measure meters (modal with progress and Esc in the UI)."""

import bpy
from bpy.props import EnumProperty, FloatProperty

from ..errors import MeasurementCancelled, RadiometerError
from ..props.meter import METER_KINDS

_DISPLAY = {"ILLUMINANCE": ("SINGLE_ARROW", 0.3), "LUMINANCE": ("CONE", 0.1), "RADIANCE_MAP": ("SPHERE", 0.1)}


def add_meter(context, kind, location, acceptance_deg=1.0):
    """Create a meter empty at ``location`` (linked to the active collection) and make it active."""
    name = {"ILLUMINANCE": "Illuminance Meter", "LUMINANCE": "Luminance Meter", "RADIANCE_MAP": "Radiance Map"}[kind]
    obj = bpy.data.objects.new(name, None)
    obj.empty_display_type, obj.empty_display_size = _DISPLAY[kind]
    if kind == "LUMINANCE":
        obj.rotation_euler = (3.14159265358979 / 2, 0.0, 0.0)  # look along +Y (horizontal) by default
    obj.location = location
    meter = obj.radiometer_meter
    meter.is_meter, meter.kind, meter.acceptance_deg = True, kind, acceptance_deg
    context.collection.objects.link(obj)
    for other in context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    return obj


class RADIOMETER_OT_add_meter(bpy.types.Operator):
    """Add a light meter at the 3D cursor"""

    bl_idname = "radiometer.add_meter"
    bl_label = "Light Meter"
    bl_options = {"REGISTER", "UNDO"}

    kind: EnumProperty(name="Kind", items=METER_KINDS, default="ILLUMINANCE")
    acceptance_deg: FloatProperty(name="Acceptance (deg)", default=1.0, min=0.01, max=60.0)

    @classmethod
    def poll(cls, context):
        if context.scene is None or context.collection is None:
            cls.poll_message_set("needs a scene and an active collection")
            return False
        return True

    def execute(self, context):
        obj = add_meter(context, self.kind, context.scene.cursor.location.copy(), self.acceptance_deg)
        self.report({"INFO"}, f"Added {obj.name}")
        return {"FINISHED"}


def _summary(results):
    parts = []
    for obj, r in results:
        if r.quantity == "luminance":
            parts.append(f"{obj.name}: {r.luminance:.4g} cd/m²")
        else:
            parts.append(f"{obj.name}: {r.illuminance:.4g} lx")
    return "; ".join(parts)


class RADIOMETER_OT_measure(bpy.types.Operator):
    """Measure the selected light meters (all meters when none is selected). Esc cancels"""

    bl_idname = "radiometer.measure"
    bl_label = "Measure"
    bl_options = {"REGISTER", "UNDO"}

    only_selected: bpy.props.BoolProperty(name="Only Selected", default=True)

    _timer = None

    @classmethod
    def poll(cls, context):
        if context.scene is None or not hasattr(context.scene, "radiometer"):
            cls.poll_message_set("Radiometer is not registered for this scene")
            return False
        if not any(ob.radiometer_meter.is_meter for ob in context.scene.objects):
            cls.poll_message_set("no light meters in the scene: add one with Add > Light Meter")
            return False
        return True

    def _targets(self, context):
        from ..measure import meters

        selected = [ob for ob in context.selected_objects if ob.radiometer_meter.is_meter]
        return meters.meter_objects(context.scene, selected if (self.only_selected and selected) else None)

    def execute(self, context):
        # Blocking path (background mode, scripts, F3 with no window).
        from ..measure import meters

        try:
            results = meters.measure_meters(self._targets(context), scene=context.scene)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        context.scene.radiometer.last_summary = _summary(results)
        self.report({"INFO"}, context.scene.radiometer.last_summary)
        return {"FINISHED"}

    def invoke(self, context, event):
        from ..measure import meters

        if context.window_manager is None or context.window is None:
            return self.execute(context)
        try:
            objects = self._targets(context)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self._scene = context.scene
        self._settings = meters.scene_settings(context.scene)
        self._steps = meters.plan_steps(context.scene, objects)
        self._results = []
        self._cancel = False
        wm = context.window_manager
        wm.progress_begin(0, len(self._steps))
        self._timer = wm.event_timer_add(0.05, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        from ..measure import meters

        if event.type == "ESC":
            return self._finish(context, cancelled=True)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        index = getattr(self, "_index", 0)
        if index >= len(self._steps):
            return self._finish(context)
        try:
            self._results += meters.run_step(self._scene, self._steps[index], self._settings)
        except MeasurementCancelled:
            return self._finish(context, cancelled=True)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return self._finish(context, cancelled=True, quiet=True)
        self._index = index + 1
        context.window_manager.progress_update(self._index)
        return {"RUNNING_MODAL"}

    def _finish(self, context, cancelled=False, quiet=False):
        from ..measure import meters

        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        if cancelled:
            # Readings are written only when every step succeeded: nothing to undo.
            if not quiet:
                self.report({"WARNING"}, "Measurement cancelled; readings unchanged")
            return {"CANCELLED"}
        for obj, reading in self._results:
            meters.write_reading(obj, reading)
        context.scene.radiometer.last_summary = _summary(self._results)
        self.report({"INFO"}, context.scene.radiometer.last_summary)
        return {"FINISHED"}


def _menu_add(self, _context):
    self.layout.operator_menu_enum("radiometer.add_meter", "kind", text="Light Meter", icon="LIGHT_SUN")


classes = (RADIOMETER_OT_add_meter, RADIOMETER_OT_measure)


def register_extra():
    bpy.types.VIEW3D_MT_add.append(_menu_add)


def unregister_extra():
    bpy.types.VIEW3D_MT_add.remove(_menu_add)

"""Light meter operators: add a meter, measure meters (modal with progress and Esc in the UI), read the
active meter's direct light in melanopic EDI."""

import bpy
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty

from ..props.meter import METER_KINDS
from .. import api
from .modal import Step, Task, TaskOperator
from .polls import needs, registered


def add_meter(context, kind, location, acceptance_deg=1.0, rotation=None):
    """Create a meter at ``location`` in the active collection, selected and active (``api.add_meter``)."""
    return api.add_meter(kind, location, acceptance_deg=acceptance_deg, rotation=rotation, context=context)

ALIGN_ITEMS = [
    ("WORLD", "World", "Align the new meter to the world (an illuminance meter faces up, a spot meter along +Y)"),
    ("VIEW", "View", "Align the new meter to the view: an illuminance meter faces the viewer, a spot meter "
                     "looks into the scene"),
    ("CURSOR", "3D Cursor", "Use the 3D cursor's rotation"),
]


def _poll_scene_collection(cls, context):
    """Adding objects needs a scene and an active collection (else say so in the tooltip)."""
    return needs(cls, context.scene is not None and context.collection is not None,
                 "needs a scene and an active collection")


class _AddsObjects:
    """Mixin: an operator that adds objects to the active collection."""

    @classmethod
    def poll(cls, context):
        return _poll_scene_collection(cls, context)


class RADIOMETER_OT_add_meter(_AddsObjects, bpy.types.Operator):
    """Add a light meter at the 3D cursor"""

    bl_idname = "radiometer.add_meter"
    bl_label = "Light Meter"
    bl_options = {"REGISTER", "UNDO"}

    kind: EnumProperty(name="Kind", items=METER_KINDS, default="ILLUMINANCE", description="What the meter measures")
    acceptance_deg: FloatProperty(name="Acceptance (deg)", default=1.0, min=0.01, max=60.0,
                                  description="Full acceptance angle of a spot (luminance) meter, deg")
    align: EnumProperty(name="Align", items=ALIGN_ITEMS, default="WORLD",
                        description="The orientation of the new meter")
    location: FloatVectorProperty(name="Location", size=3, subtype="TRANSLATION",
                                  description="Where the meter goes (default: the 3D cursor)")
    rotation: FloatVectorProperty(name="Rotation", size=3, subtype="EULER",
                                  description="The meter's rotation (with Align World; set from the view or the "
                                              "cursor otherwise)")

    def invoke(self, context, event):
        if not self.properties.is_property_set("location"):
            self.location = context.scene.cursor.location
        return self.execute(context)

    def _rotation(self, context):
        if self.align == "CURSOR":
            return tuple(context.scene.cursor.matrix.to_euler())
        if self.align == "VIEW":
            rv3d = getattr(context, "region_data", None)
            if rv3d is not None and hasattr(rv3d, "view_rotation"):
                # The view's +Z points at the viewer: an illuminance meter (+Z) faces the viewer, a spot
                # meter (looking along -Z) looks where the viewer looks.
                return tuple(rv3d.view_rotation.to_euler())
            self.report({"WARNING"}, "no 3D view to align to: aligned to the world")
        if self.properties.is_property_set("rotation"):
            return tuple(self.rotation)
        return api.meter_default_rotation(self.kind)

    def execute(self, context):
        location = self.location if self.properties.is_property_set("location") else context.scene.cursor.location
        rotation = self._rotation(context)
        obj = add_meter(context, self.kind, tuple(location), self.acceptance_deg, rotation=rotation)
        self.location, self.rotation = tuple(obj.location), tuple(obj.rotation_euler)  # shown in the redo panel
        self.report({"INFO"}, f"Added {obj.name}")
        return {"FINISHED"}


# --- Add meter on surface --------------------------------------------------------------------------

def meter_pose_on_surface(scene, origin, direction, depsgraph=None):
    """Where a meter placed on the face hit by the ray ``origin + t direction`` goes, or None (no hit).

    Returns ``(location, normal, rotation_euler, hit_object)``: the hit point itself (the meter code
    raises its sensor off the surface internally), the face normal (world space, turned towards the
    ray's origin when the ray hits a face's back, so the meter reads the side the user looks at) and
    the rotation putting the meter's +Z along that normal.
    """
    from mathutils import Vector

    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    origin, direction = Vector(origin), Vector(direction)
    if direction.length == 0:
        return None
    hit, location, normal, _index, obj, _matrix = scene.ray_cast(depsgraph, origin, direction.normalized())
    if not hit or normal.length == 0:
        return None
    normal = normal.normalized()
    if normal.dot(direction) > 0:  # back face: face the viewer
        normal = -normal
    rotation = normal.to_track_quat("Z", "Y").to_euler()
    return Vector(location), normal, rotation, (obj.original if obj is not None else None)


def view_ray(context, event):
    """(origin, direction) of the ray under the mouse in the 3D view's WINDOW region it is over, or None."""
    from bpy_extras import view3d_utils

    area = context.area
    if area is None or area.type != "VIEW_3D":
        return None
    for region in area.regions:
        if region.type != "WINDOW" or region.data is None:
            continue
        x, y = event.mouse_x - region.x, event.mouse_y - region.y
        if 0 <= x < region.width and 0 <= y < region.height:
            coord = (x, y)
            return (view3d_utils.region_2d_to_origin_3d(region, region.data, coord),
                    view3d_utils.region_2d_to_vector_3d(region, region.data, coord))
    return None


class RADIOMETER_OT_add_meter_on_surface(_AddsObjects, bpy.types.Operator):
    """Add an illuminance meter on the surface under the mouse, facing out of it (click a face; Esc cancels)"""

    bl_idname = "radiometer.add_meter_on_surface"
    bl_label = "Light Meter on Surface"
    bl_options = {"REGISTER", "UNDO"}

    ray_origin: FloatVectorProperty(name="Ray Origin", size=3, subtype="TRANSLATION",
                                    description="Start of the ray that picks the surface (set from the mouse)")
    ray_direction: FloatVectorProperty(name="Ray Direction", size=3, default=(0.0, 0.0, -1.0),
                                       subtype="DIRECTION",
                                       description="Direction of the ray that picks the surface (set from the "
                                                   "mouse)")

    def _status(self, context, text):
        if context.workspace is not None:
            context.workspace.status_text_set(text)
        if context.area is not None:
            context.area.header_text_set(text)

    def invoke(self, context, event):
        if context.area is None or context.area.type != "VIEW_3D":
            self.report({"WARNING"}, "Add Meter on Surface works in a 3D viewport")
            return {"CANCELLED"}
        context.window_manager.modal_handler_add(self)
        self._status(context, "Click a surface to place a light meter on it   Esc/Right click: cancel")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            self._status(context, None)
            return {"CANCELLED"}
        if event.type == "LEFTMOUSE" and event.value == "PRESS":
            ray = view_ray(context, event)
            if ray is None:
                return {"RUNNING_MODAL"}
            self.ray_origin, self.ray_direction = tuple(ray[0]), tuple(ray[1])
            if meter_pose_on_surface(context.scene, *ray, context.evaluated_depsgraph_get()) is None:
                self.report({"WARNING"}, "no surface under the mouse: click a face (Esc cancels)")
                return {"RUNNING_MODAL"}
            self._status(context, None)
            return self.execute(context)
        return {"PASS_THROUGH"}  # navigate the view while choosing

    def execute(self, context):
        pose = meter_pose_on_surface(context.scene, self.ray_origin, self.ray_direction,
                                     context.evaluated_depsgraph_get())
        if pose is None:
            self.report({"WARNING"}, "the ray hits no surface: nothing added")
            return {"CANCELLED"}
        location, _normal, rotation, hit = pose
        obj = add_meter(context, "ILLUMINANCE", tuple(location), rotation=tuple(rotation))
        self.report({"INFO"}, f"Added {obj.name} on {hit.name if hit else 'the surface'}")
        return {"FINISHED"}


def _summary(results):
    parts = []
    for obj, r in results:
        if r.quantity == "luminance":
            parts.append(f"{obj.name}: {r.luminance:.4g} cd/m²")
        else:
            parts.append(f"{obj.name}: {r.illuminance:.4g} lx")
    return "; ".join(parts)


def measured_line(done, total, summary):
    """The status-bar line after *Measure*: how many of the scene's meters were measured, and why.

    A selection that holds meters limits the run to them (a stale selection would otherwise measure
    one meter of five without a word); none selected measures them all.
    """
    if done == total:
        head = f"Measured all {total} meter{'s' if total != 1 else ''}"
    else:
        head = (f"Measured {done} of {total} meters (the selected ones; deselect all to measure every "
                "meter)")
    return f"{head}: {summary}" if summary else head


UI_BATCH = 8  # illuminance meters per modal step: short steps, so Esc and the progress bar respond


class RADIOMETER_OT_measure(TaskOperator, bpy.types.Operator):
    """Measure the selected light meters (all meters when none is selected). Esc cancels"""

    bl_idname = "radiometer.measure"
    bl_label = "Measure"
    bl_options = {"REGISTER", "UNDO"}

    only_selected: bpy.props.BoolProperty(name="Only Selected", default=True,
                                          description="Measure only the selected meters (all when none is selected)")

    @classmethod
    def poll(cls, context):
        return registered(cls, context) and needs(
            cls, any(ob.radiometer_meter.is_meter for ob in context.scene.objects),
            "no light meters in the scene: add one with Add > Light Meter") and cls.task_poll(context)

    def _targets(self, context):
        selected = [ob for ob in context.selected_objects if ob.radiometer_meter.is_meter]
        return api.meter_objects(selected if (self.only_selected and selected) else None, scene=context.scene)

    def build_task(self, context):
        return measure_task(context.scene, self._targets(context), batch=None if bpy.app.background else UI_BATCH)

    def finish(self, context, task):
        for obj, reading in task.results:
            api.store_reading(obj, reading)
        context.scene.radiometer.last_summary = _summary(task.results)
        total = sum(1 for ob in context.scene.objects if ob.radiometer_meter.is_meter)
        return measured_line(len(task.results), total, context.scene.radiometer.last_summary)


def measure_task(scene, objects, batch=UI_BATCH):
    """A Task measuring ``objects``; ``task.results`` collects (object, reading) (written by finish)."""
    task_steps = []
    results = []

    def runner(run):
        def fn(progress, cancelled):
            results.extend(run(progress=progress, cancelled=cancelled))
        return fn

    for label, w, run in api.meter_steps(objects, scene=scene, batch=batch):
        task_steps.append(Step(label, runner(run), w))
    task = Task("Measure", task_steps)
    task.results = results
    return task


class RADIOMETER_OT_melanopic_reading(bpy.types.Operator):
    """Read the active illuminance meter's direct light in melanopic EDI (CIE S 026): mel-EDI, mel-DER and
    S/P from each light's spectrum, exact where every light has one and a closed form"""

    bl_idname = "radiometer.melanopic_reading"
    bl_label = "Melanopic Reading"
    bl_options = {"REGISTER", "UNDO"}

    reflected: bpy.props.BoolProperty(
        name="Include Reflected Light", default=False,
        description="Add the light reflected by the room's surfaces and the world's light (daylight), by spectral "
                    "band renders at preview quality, with a 95 % interval (a few seconds)")

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return registered(cls, context) and needs(
            cls, ob is not None and ob.radiometer_meter.is_meter and ob.radiometer_meter.kind == "ILLUMINANCE",
            "needs an active illuminance meter")

    def execute(self, context):
        from ..errors import RadiometerError

        try:
            r = api.meter_melanopic_reading(context.active_object, scene=context.scene, reflected=self.reflected)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        if r.get("part") == "direct+reflected":
            iv = r["interval_95"]["mel_edi_lx"]
            self.report({"INFO"}, f"mel-EDI {r['mel_edi_lx']:.4g} lx, direct + reflected (95 % {iv['low_95']:.4g}-"
                                  f"{iv['high_95']:.4g} lx)")
        else:
            why = next((n for n in r["notes"] if n.startswith("reflected part not added")), None)
            self.report({"WARNING"} if self.reflected else {"INFO"},
                        f"mel-EDI {r['mel_edi_lx']:.4g} lx of the direct light"
                        + ("" if r["exact"] else " (a lower bound)") + (f"; {why}" if self.reflected and why else ""))
        return {"FINISHED"}


def _menu_add(self, _context):
    self.layout.operator_menu_enum("radiometer.add_meter", "kind", text="Light Meter", icon="LIGHT_SUN")
    self.layout.operator_context = "INVOKE_DEFAULT"
    self.layout.operator("radiometer.add_meter_on_surface", icon="SNAP_FACE")


classes = (RADIOMETER_OT_add_meter, RADIOMETER_OT_add_meter_on_surface, RADIOMETER_OT_measure,
           RADIOMETER_OT_melanopic_reading)


def register_extra():
    bpy.types.VIEW3D_MT_add.append(_menu_add)


def unregister_extra():
    bpy.types.VIEW3D_MT_add.remove(_menu_add)

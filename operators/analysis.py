"""Analysis operators: law checks (one light or all), work-plane grid, convergence study, report.

Thin: gather inputs, call ``radiometer.api``, store the results in ``scene.radiometer_analysis``
(shown by the sidebar), load the PNG plots into Blender's images and report one line.
"""

import math
import os

import bpy
from bpy.props import BoolProperty, EnumProperty

from .. import api
from .. import plots
from ..errors import RadiometerError
from .modal import Step, Task, TaskOperator, one_call_task
from .polls import needs, registered

_ALL = "__ALL__"
_light_items_cache = []  # Blender needs the enum strings kept alive


def _light_items(_self, context):
    items = [(_ALL, "All Lights", "Check every light that renders")]
    scene = context.scene if context else None
    if scene is not None:
        items += [(ob.name, ob.name, f"{ob.data.type.title()} light") for ob in scene.objects
                  if ob.type == "LIGHT" and not ob.hide_render]
    _light_items_cache[:] = items
    return _light_items_cache


def output_dir(context):
    """The settings' output folder as an absolute path (a temp folder for unsaved files), created."""
    from .. import outputs

    raw = context.scene.radiometer_analysis.output_dir or "//radiometer/"
    if raw.startswith("//") and not bpy.data.filepath:
        # Unsaved file: a private folder of this session (mkdtemp, 0700), never a fixed /tmp path.
        path = os.path.join(outputs.private_temp_root(), "analysis")
        os.makedirs(path, mode=0o700, exist_ok=True)
        return path
    path = bpy.path.abspath(raw)
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as exc:
        raise RadiometerError(f"cannot create the output folder {path}: {exc.strerror or exc}") from None
    return path


def load_image(context, path):
    """Load (or reload) a PNG into bpy.data.images and show it in any open Image Editor (None: no PNG)."""
    if not path:  # no plot was written (matplotlib missing): the numbers stand on their own
        return None
    image = bpy.data.images.load(path, check_existing=True)
    image.reload()
    screen = context.screen if hasattr(context, "screen") else None
    for area in (screen.areas if screen else ()):
        if area.type == "IMAGE_EDITOR":
            area.spaces.active.image = image
    return image


def warn_without_plots(operator):
    """Tell the user once per run that images are skipped where matplotlib is missing."""
    if not plots.matplotlib_available():
        operator.report({"WARNING"}, plots.missing_message())


def _plot_path(path):
    """``path`` where matplotlib can draw it, else None: the operators' pictures are extras (the
    warning above says why they are missing); the API raises when a plot path is given without it."""
    return path if plots.matplotlib_available() else None


def _has_lights(cls, context):
    return registered(cls, context, "radiometer_analysis") and needs(
        cls, any(ob.type == "LIGHT" and not ob.hide_render for ob in context.scene.objects),
        "the scene has no lights that render: add a light")


def _law_item(settings, light):
    item = settings.laws.get(light.name)
    if item is None:
        item = settings.laws.add()
        item.name = light.name
    item.kind = light.data.type
    return item


def _targets(self, context):
    scene = context.scene
    if self.light == _ALL:
        return [ob for ob in scene.objects if ob.type == "LIGHT" and not ob.hide_render]
    return [scene.objects[self.light]]


def _with_progress(context, items):
    """Yield ``items`` while driving the window manager's progress bar (a no-op without a window)."""
    wm = context.window_manager
    items = list(items)
    if wm is None or context.window is None:
        yield from items
        return
    wm.progress_begin(0, max(len(items), 1))
    try:
        for i, item in enumerate(items):
            wm.progress_update(i)
            yield item
    finally:
        wm.progress_end()


def _measure_settings(context):
    """The scene's Radiometer method, quality and target error (fraction; None: the preset's)."""
    s = context.scene.radiometer
    return {"method": s.method, "quality": s.quality,
            "target_rel_error": s.target_rel_error if s.target_rel_error > 0 else None}


def _slug(name):
    """The report's file-name stem for an object: readable, unique among the scene's objects."""
    from .. import api

    return api.report_file_stem(name, among=[ob.name for ob in bpy.context.scene.objects])


def _law_task(self, context, kind):
    """A Task with one step per light: ``task.results`` maps light name -> result object."""
    from .. import api

    out = output_dir(context)
    lights = _targets(self, context)
    results = {}
    location = tuple(context.scene.cursor.location) if getattr(self, "at_cursor", False) else None
    steps = []
    for light in lights:
        if kind == "inverse_square" and light.data.type == "SUN":
            if self.light != _ALL:
                raise RadiometerError(f"{light.name}: a sun has no position, the inverse-square law does not "
                                      "apply; check its cosine law")
            results[light.name] = None
            continue

        def fn(progress, cancelled, light=light):
            plot = _plot_path(os.path.join(out, f"{kind}_{_slug(light.name)}.png"))
            if kind == "inverse_square":
                results[light.name] = api.check_inverse_square(
                    light, scene=context.scene, plot=plot, progress=progress, cancelled=cancelled,
                    **_measure_settings(context))
            else:
                results[light.name] = api.check_cosine_law(
                    light, scene=context.scene, location=location, plot=plot, progress=progress,
                    cancelled=cancelled, **_measure_settings(context))

        steps.append(Step(light.name, fn))
    task = Task("Inverse Square" if kind == "inverse_square" else "Cosine Law", steps)
    task.results, task.lights = results, lights
    return task


class RADIOMETER_OT_check_inverse_square(TaskOperator, bpy.types.Operator):
    """Sweep a meter facing the light along its axis and compare with I/d² (near-field limit, exponent)"""

    bl_idname = "radiometer.check_inverse_square"
    bl_label = "Check Inverse Square"
    bl_options = {"REGISTER", "UNDO"}

    light: EnumProperty(name="Light", items=_light_items, description="The light to check, or every light")

    @classmethod
    def poll(cls, context):
        return _has_lights(cls, context) and cls.task_poll(context)

    def build_task(self, context):
        warn_without_plots(self)
        return _law_task(self, context, "inverse_square")

    def finish(self, context, task):
        settings = context.scene.radiometer_analysis
        lines = []
        for light in task.lights:
            item = _law_item(settings, light)
            r = task.results.get(light.name)
            if r is None:
                item.inverse_checked, item.inverse_note = False, "sun: no position, inverse square does not apply"
                continue
            item.inverse_checked, item.inverse_note = True, ""
            item.exponent = r.exponent if math.isfinite(r.exponent) else 0.0
            item.exponent_se = r.exponent_se if math.isfinite(r.exponent_se) else 0.0
            item.near_field_limit = r.near_field_limit if math.isfinite(r.near_field_limit) else -1.0
            item.inverse_passed = r.passed
            item.inverse_expected = r.expected_departure
            item.inverse_causes = " | ".join(r.causes)
            item.inverse_plot = r.plot
            load_image(context, r.plot)
            verdict = "ok" if r.passed else "near field, as its shape predicts" if r.expected_departure else "departs"
            lines.append(f"{light.name}: {verdict}, exponent {r.exponent:.4f}, near field "
                         f"{r.near_field_limit:.3g} m; the room adds up to {100 * r.max_scene_share:.3g} %")
        return "; ".join(lines) or "no point, spot or area light to check"


class RADIOMETER_OT_check_cosine_law(TaskOperator, bpy.types.Operator):
    """Tilt a meter from facing the light to 89 degrees and compare E(θ)/E(0) with cos θ"""

    bl_idname = "radiometer.check_cosine_law"
    bl_label = "Check Cosine Law"
    bl_options = {"REGISTER", "UNDO"}

    light: EnumProperty(name="Light", items=_light_items, description="The light to check, or every light")
    at_cursor: BoolProperty(name="At 3D Cursor", default=False,
                            description="Measure at the 3D cursor instead of in front of the light")

    @classmethod
    def poll(cls, context):
        return _has_lights(cls, context) and cls.task_poll(context)

    def build_task(self, context):
        warn_without_plots(self)
        return _law_task(self, context, "cosine")

    def finish(self, context, task):
        settings = context.scene.radiometer_analysis
        lines = []
        for light in task.lights:
            r = task.results[light.name]
            item = _law_item(settings, light)
            item.cosine_checked = True
            item.cosine_max_dev = min(r.max_rel_deviation, 1e9)
            item.cosine_onset = r.onset_deg if math.isfinite(r.onset_deg) else -1.0
            item.cosine_passed = r.passed
            item.cosine_expected = r.expected_departure
            item.cosine_causes = " | ".join(r.causes)
            item.cosine_plot = r.plot
            load_image(context, r.plot)
            verdict = "ok" if r.passed else "near field, as its shape predicts" if r.expected_departure else "departs"
            lines.append(f"{light.name}: {verdict}, max deviation "
                         f"{100 * r.max_rel_deviation:.3g} % at {r.max_at_deg:g} deg; the room adds up to "
                         f"{100 * r.max_scene_share:.3g} %")
        return "; ".join(lines)


def create_work_plane(context, height, size=(4.0, 4.0)):
    """A render-hidden plane at ``height`` (scene units) covering the scene's meshes (or 4 x 4)."""
    import numpy as np

    corners = [np.array(ob.matrix_world) @ np.r_[list(c), 1.0] for ob in context.scene.objects
               if ob.type == "MESH" and not ob.hide_render for c in ob.bound_box]
    if corners:
        pts = np.array(corners)[:, :2]
        (x0, y0), (x1, y1) = pts.min(axis=0), pts.max(axis=0)
    else:
        x0, y0, x1, y1 = -size[0] / 2, -size[1] / 2, size[0] / 2, size[1] / 2
    if x1 - x0 <= 0 or y1 - y0 <= 0:
        x0, y0, x1, y1 = -size[0] / 2, -size[1] / 2, size[0] / 2, size[1] / 2
    mesh = bpy.data.meshes.new("Work Plane")
    mesh.from_pydata([(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)], [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new("Work Plane", mesh)
    obj.location = (0.0, 0.0, height)
    obj.hide_render = True  # an imaginary reference surface: it must not block or reflect light
    obj.display_type = "WIRE"
    context.scene.collection.objects.link(obj)
    return obj


class RADIOMETER_OT_illuminance_grid(TaskOperator, bpy.types.Operator):
    """Measure illuminance on a grid over the work plane: E_avg, E_min, E_max, U0, isolux image and CSV"""

    bl_idname = "radiometer.illuminance_grid"
    bl_label = "Illuminance Grid"
    bl_options = {"REGISTER", "UNDO"}

    create_plane: BoolProperty(name="Create Work Plane", default=False,
                               description="Create a render-hidden plane at the set height when none is picked")

    @classmethod
    def poll(cls, context):
        return registered(cls, context, "radiometer_analysis") and cls.task_poll(context)

    def build_task(self, context):
        from .. import api

        settings = context.scene.radiometer_analysis
        plane = settings.work_plane
        if plane is None or plane.name not in context.scene.objects:
            if not self.create_plane:
                raise RadiometerError("pick a work plane in the sidebar, or create one (Create Work Plane)")
            plane = create_work_plane(context, settings.plane_height)
            settings.work_plane = plane
        out = output_dir(context)
        warn_without_plots(self)
        slug = _slug(plane.name)
        kwargs = {"resolution": (settings.resolution_x, settings.resolution_y)} if settings.use_resolution else \
            {"spacing": settings.spacing or None}
        def call(progress, cancelled):
            return api.illuminance_grid(
                plane, scene=context.scene, png=_plot_path(os.path.join(out, f"isolux_{slug}.png")),
                csv=os.path.join(out, f"grid_{slug}.csv"), progress=progress, cancelled=cancelled, **kwargs,
                **_measure_settings(context))

        return one_call_task("Illuminance Grid", plane.name, "grid", call)

    def finish(self, context, task):
        settings = context.scene.radiometer_analysis
        g = task.results["grid"]
        s = g.stats
        settings.grid_target, settings.grid_nx, settings.grid_ny = g.target, g.nx, g.ny
        settings.grid_avg, settings.grid_min, settings.grid_max = s["avg"], s["min"], s["max"]
        settings.grid_u0 = s["u0"] if math.isfinite(s["u0"]) else 0.0
        settings.grid_method, settings.grid_image, settings.grid_csv = g.method, g.image, g.csv
        load_image(context, g.image)
        if settings.colour_plane:
            from .. import api

            try:
                api.colour_plane(g, scene=context.scene)
            except RadiometerError as exc:  # matplotlib missing: the grid numbers are still valid
                self.report({"WARNING"}, str(exc))
        return (f"{g.target}: E_avg {s['avg']:.4g} lx, E_min {s['min']:.4g} lx, U0 {s['u0']:.3f} "
                f"({g.nx} x {g.ny} points)")


class RADIOMETER_OT_convergence_study(TaskOperator, bpy.types.Operator):
    """Render the active meter (or plane) at increasing samples; fit error vs time; samples for the target"""

    bl_idname = "radiometer.convergence_study"
    bl_label = "Convergence Study"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return registered(cls, context, "radiometer_analysis") and needs(
            cls, ob is not None and ((ob.radiometer_meter.is_meter and ob.radiometer_meter.kind == "ILLUMINANCE")
                                     or ob.type == "MESH"),
            "make an illuminance meter or a plane the active object") and cls.task_poll(context)

    def build_task(self, context):
        from .. import api

        settings = context.scene.radiometer_analysis
        out = output_dir(context)
        warn_without_plots(self)
        target = context.active_object
        def call(_progress, cancelled):  # the study reports no progress of its own (one step)
            return api.convergence_study(
                target, scene=context.scene, target_error=settings.target_error,
                quality=context.scene.radiometer.quality, plot=_plot_path(os.path.join(out, "convergence.png")),
                cancelled=cancelled)

        return one_call_task("Convergence Study", target.name, "study", call)

    def finish(self, context, task):
        settings = context.scene.radiometer_analysis
        c = task.results["study"]
        settings.conv_target = c.target
        settings.conv_slope, settings.conv_slope_se = c.fit["slope"], c.fit["slope_se"]
        settings.conv_samples = min(c.samples_for_target, 1e12)
        settings.conv_seconds = min(c.seconds_for_target, 1e12)
        settings.conv_plot = c.plot
        load_image(context, c.plot)
        return (f"{c.target}: error ~ N^{c.fit['slope']:.2f} ~ t^{c.fit['time_slope']:.2f}; "
                f"{100 * c.target_error:g} % needs ~{c.samples_for_target:.3g} samples, "
                f"~{c.seconds_for_target:.3g} s")


class RADIOMETER_OT_export_report(TaskOperator, bpy.types.Operator):
    """Write report.json, report.md and plots: meters, law checks for every light, grids, convergence"""

    bl_idname = "radiometer.export_report"
    bl_label = "Export Report"
    bl_options = {"REGISTER", "UNDO"}

    convergence: BoolProperty(name="Convergence Study", default=True,
                              description="Also run a short convergence study on the first illuminance meter")

    @classmethod
    def poll(cls, context):
        return _has_lights(cls, context) and cls.task_poll(context)

    def build_task(self, context):
        warn_without_plots(self)
        return report_task(context, self.convergence)

    def finish(self, context, task):
        result = task.results["report"]
        context.scene.radiometer_analysis.report_path = result["paths"]["markdown"]
        return f"Report written to {result['paths']['markdown']}"


def report_task(context, convergence=True):
    """A Task with one step per part of the report (meters, each light's laws, each grid, convergence)."""
    from .. import api

    box = {}
    holder = {}
    parts = api.iter_report(output_dir(context), scene=context.scene, convergence=convergence,
                               progress=lambda done, total, *_: "task" in holder and holder["task"]._set(done / total),
                               cancelled=lambda: "task" in holder and holder["task"].cancel_requested)
    try:
        plan = next(parts)
    except StopIteration as done:  # nothing to measure: the files are written already
        plan, box["report"] = [], done.value

    def fn(progress, cancelled):
        try:
            next(parts)
        except StopIteration as done:
            box["report"] = done.value

    task = Task("Report", [Step(label, fn, weight) for label, weight in plan])
    task.results = box
    task.on_end = parts.close  # Esc between parts: the report's staging folder is removed now, not at GC
    holder["task"] = task
    return task


classes = (RADIOMETER_OT_check_inverse_square, RADIOMETER_OT_check_cosine_law, RADIOMETER_OT_illuminance_grid,
           RADIOMETER_OT_convergence_study, RADIOMETER_OT_export_report)

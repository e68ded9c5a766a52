"""False colour in the viewport: the last illuminance grid as coloured quads over its plane, and a legend.

* :func:`show` makes the coloured copy (``measure.analyses.grid.colour_plane``: colour attribute 'lux_colour',
  hidden in renders) with an emission material reading that attribute (so Material Preview shows it), and
  adds one ``SpaceView3D`` POST_PIXEL draw handler that draws a colour bar with lux labels.
* :func:`hide` removes both. ``unregister_extra`` and a persistent ``load_pre`` handler call it, and
  ``load_post`` removes coloured copies saved into a file (they carry ``OBJECT_MARK``).
* :func:`legend_layout` is the pure part of the legend (rectangles, colours, ticks and labels).
"""

import math

import bpy
from bpy.app.handlers import persistent

from ..errors import RadiometerError

OBJECT_MARK = "radiometer_false_colour"
MATERIAL_NAME = "Radiometer False Colour"

#: What is shown now: {"handler": draw handle or None, "objects": [names], "lo": lux, "hi": lux, "target": str}
_state = {"handler": None, "objects": [], "lo": 0.0, "hi": 0.0, "target": ""}


def is_shown():
    return _state["handler"] is not None or bool(_state["objects"])


def _format_lux(v):
    if not math.isfinite(v):
        return "n/a"
    if v == 0:
        return "0 lx"
    return f"{v:.3g} lx" if abs(v) < 1e4 else f"{v:.3e} lx"


def legend_layout(lo, hi, region_width, region_height, *, ui_scale=1.0, steps=32, ticks=5):
    """The legend's geometry in region pixels: a vertical bar at the right edge, bottom = lo, top = hi.

    Returns {"bar": (x0, y0, x1, y1), "segments": [(y0, y1, rgba)], "ticks": [(y, value, label)],
    "title": (x, y, text)}. Pure: no GPU, usable in tests.
    """
    from ..api import false_colour

    s = max(0.5, float(ui_scale))
    width, margin = 18 * s, 20 * s
    height = max(40 * s, min(260 * s, region_height - 4 * margin))
    x1 = region_width - margin - 60 * s  # room for the labels on the right of the bar
    x0 = x1 - width
    y0 = (region_height - height) / 2
    y1 = y0 + height
    segments = []
    for k in range(steps):
        a, b = y0 + height * k / steps, y0 + height * (k + 1) / steps
        segments.append((a, b, false_colour((k + 0.5) / steps)))
    tick_list = []
    span = hi - lo
    for k in range(ticks):
        t = k / (ticks - 1) if ticks > 1 else 0.5
        value = lo + t * span if span > 0 else lo
        tick_list.append((y0 + t * height, value, _format_lux(value)))
    return {"bar": (x0, y0, x1, y1), "segments": segments, "ticks": tick_list,
            "title": (x0, y1 + 8 * s, "Illuminance")}


def draw_legend():
    """POST_PIXEL callback: the colour bar of what is shown (skipped headless or without a GPU context)."""
    if bpy.app.background or _state["handler"] is None:
        return
    try:
        import blf
        import gpu
        from gpu_extras.batch import batch_for_shader
    except ImportError:
        return
    region = bpy.context.region
    if region is None:
        return
    overlay = getattr(bpy.context.space_data, "overlay", None)
    if overlay is not None and not overlay.show_overlays:
        return
    scale = bpy.context.preferences.system.ui_scale
    lay = legend_layout(_state["lo"], _state["hi"], region.width, region.height, ui_scale=scale)
    try:
        shader = gpu.shader.from_builtin("SMOOTH_COLOR")
    except Exception:  # no GPU context
        return
    x0, _, x1, _ = lay["bar"]
    pos, col, idx = [], [], []
    for a, b, c in lay["segments"]:
        n = len(pos)
        pos += [(x0, a), (x1, a), (x1, b), (x0, b)]
        col += [c] * 4
        idx += [(n, n + 1, n + 2), (n, n + 2, n + 3)]
    gpu.state.blend_set("ALPHA")
    batch_for_shader(shader, "TRIS", {"pos": pos, "color": col}, indices=idx).draw(shader)
    gpu.state.blend_set("NONE")
    font = 0
    blf.size(font, 11 * scale)
    blf.color(font, 1.0, 1.0, 1.0, 1.0)
    for y, _value, label in lay["ticks"]:
        blf.position(font, x1 + 6 * scale, y - 4 * scale, 0)
        blf.draw(font, label)
    tx, ty, text = lay["title"]
    blf.position(font, tx, ty, 0)
    blf.draw(font, f"{text}: {_state['target']}")


def _material():
    mat = bpy.data.materials.get(MATERIAL_NAME)
    if mat is not None:
        return mat
    from ..compat import ensure_node_tree

    mat = bpy.data.materials.new(MATERIAL_NAME)
    tree = ensure_node_tree(mat)
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    attr = nodes.new("ShaderNodeAttribute")
    attr.attribute_type, attr.attribute_name = "GEOMETRY", "lux_colour"
    emit = nodes.new("ShaderNodeEmission")
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(attr.outputs["Color"], emit.inputs["Color"])
    links.new(emit.outputs["Emission"], out.inputs["Surface"])
    mat.diffuse_color = (0.9, 0.4, 0.2, 1.0)  # Solid view without Attribute colouring
    return mat


def show(result, scene=None):
    """Show ``result`` (a GridResult, or anything with ``target`` and ``lux``) in false colour. Returns the object."""
    from ..api import colour_plane

    scene = scene or bpy.context.scene
    if scene.objects.get(result.target) is None:
        raise RadiometerError(f"work plane {result.target!r} is not in the scene")
    hide()
    obj = colour_plane(result, scene=scene, name=f"False Colour {result.target}")
    obj[OBJECT_MARK] = True
    obj.data.materials.append(_material())
    obj.hide_select = True
    _state["objects"].append(obj.name)
    finite = [float(v) for v in result.lux.ravel() if math.isfinite(v)]
    _state["lo"], _state["hi"] = (min(finite), max(finite)) if finite else (0.0, 0.0)
    _state["target"] = result.target
    _state["handler"] = bpy.types.SpaceView3D.draw_handler_add(draw_legend, (), "WINDOW", "POST_PIXEL")
    _redraw()
    return obj


def _remove_object(obj):
    mesh = obj.data
    bpy.data.objects.remove(obj, do_unlink=True)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def hide():
    """Remove the coloured object(s) and the legend's draw handler (safe to call when nothing is shown)."""
    if _state["handler"] is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_state["handler"], "WINDOW")
        _state["handler"] = None
    names, _state["objects"] = _state["objects"], []
    try:
        objects = bpy.data.objects
        for name in names:
            obj = objects.get(name)
            if obj is not None:
                _remove_object(obj)
        mat = bpy.data.materials.get(MATERIAL_NAME)
        if mat is not None and mat.users == 0:
            bpy.data.materials.remove(mat)
    except AttributeError:  # restricted bpy.data while Blender quits
        pass
    _redraw()


def _redraw():
    wm = getattr(bpy.context, "window_manager", None)
    for window in getattr(wm, "windows", ()):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


class _LastGrid:
    def __init__(self, target, lux):
        self.target, self.lux = target, lux


def last_grid(scene):
    """The scene's last grid (target and lux read back from its CSV), or RadiometerError."""
    import os

    from ..api import grid_lux_from_csv as lux_from_csv

    s = scene.radiometer_analysis
    path = bpy.path.abspath(s.grid_csv) if s.grid_csv else ""
    if not s.grid_target or not path or not os.path.isfile(path):
        raise RadiometerError("run Illuminance Grid first (its CSV file is needed)")
    return _LastGrid(s.grid_target, lux_from_csv(path))


class RADIOMETER_OT_toggle_false_colour(bpy.types.Operator):
    """Show or hide the last illuminance grid in false colour over its plane, with a lux legend"""

    bl_idname = "radiometer.toggle_false_colour"
    bl_label = "Toggle False Colour"
    bl_options = {"REGISTER", "UNDO"}  # adds/removes an object: one undo step (the legend follows, _on_undo_redo)

    @classmethod
    def poll(cls, context):
        if is_shown():
            return True
        scene = context.scene
        if scene is None or not hasattr(scene, "radiometer_analysis") or not scene.radiometer_analysis.grid_target:
            cls.poll_message_set("Run Illuminance Grid first")
            return False
        return True

    def execute(self, context):
        if is_shown():
            hide()
            self.report({"INFO"}, "False colour hidden")
            return {"FINISHED"}
        try:
            obj = show(last_grid(context.scene), scene=context.scene)
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"False colour on {_state['target']}: {_format_lux(_state['lo'])} to "
                    f"{_format_lux(_state['hi'])} ({obj.name}; Material Preview or Solid > Attribute)")
        return {"FINISHED"}


@persistent
def _on_load_pre(*_args):
    hide()


@persistent
def _on_load_post(*_args):
    for obj in [ob for ob in bpy.data.objects if ob.get(OBJECT_MARK)]:
        _remove_object(obj)


@persistent
def _on_undo_redo(*_args):
    """Undo and redo bring the coloured copy back or take it away; the legend follows what exists."""
    present = [ob.name for ob in bpy.data.objects if ob.get(OBJECT_MARK)]
    _state["objects"] = present
    if not present and _state["handler"] is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_state["handler"], "WINDOW")
        _state["handler"] = None
    elif present and _state["handler"] is None:
        _state["handler"] = bpy.types.SpaceView3D.draw_handler_add(draw_legend, (), "WINDOW", "POST_PIXEL")
    _redraw()


_HANDLERS = (("load_pre", _on_load_pre), ("load_post", _on_load_post), ("undo_post", _on_undo_redo),
             ("redo_post", _on_undo_redo))


def register_extra():
    for name, fn in _HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister_extra():
    hide()
    for name, fn in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        while fn in handlers:
            handlers.remove(fn)


classes = (RADIOMETER_OT_toggle_false_colour,)

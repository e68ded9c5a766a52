"""BRDF operators: assign the material's Radiometer BRDF, and plot a BRDF summary image."""

import os

import bpy

from ..errors import RadiometerError
from .polls import needs


def _active_material(context):
    mat = getattr(context, "material", None)
    if mat is None and context.object is not None:
        mat = context.object.active_material
    return mat


def _poll_material(cls, context):
    return (needs(cls, _active_material(context) is not None, "needs an active object with an active material")
            and needs(cls, hasattr(bpy.types.Material, "radiometer_brdf"), "Radiometer is not registered"))


class _OnActiveMaterial:
    """Mixin: an operator on the active material's Radiometer BRDF (greyed out, saying why, without one)."""

    @classmethod
    def poll(cls, context):
        return _poll_material(cls, context)


class RADIOMETER_OT_assign_brdf(_OnActiveMaterial, bpy.types.Operator):
    """Realise the chosen BRDF on the active material (node group or OSL script)"""

    bl_idname = "radiometer.assign_brdf"
    bl_label = "Apply BRDF"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        from ..props.brdf import input_links, params_dict, pull_from_node, restore_links
        from ..shading.assign import assign_brdf

        mat = _active_material(context)
        s = mat.radiometer_brdf
        if len(s.params) == 0:
            from ..props.brdf import sync_params

            sync_params(s, s.model)
        pull_from_node(mat)  # the group node's inputs (edited by hand) win over stored values
        links = input_links(mat)  # textures / bump linked into the group node
        try:
            fid = assign_brdf(mat, s.model, s.method, tangent_source=s.tangent_source, uv_map=s.uv_map,
                              **params_dict(s))
            restore_links(mat, links)
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
    """Where plots go: the extension's user directory, else a private (0700) temporary folder."""
    from .. import outputs

    return outputs.user_folder("plots")


def lobe_data(material, thetas_i=(0.0, 30.0, 60.0), n=91):
    """In-plane lobes of the model and of what Cycles renders for ``material``: a list of
    (theta_i deg, theta_o deg array (-90..90, negative = back side), f_model (n, 3), f_closure (n, 3)).

    The closure is evaluated from the group node's current inputs when the BRDF is applied
    (``shading.assign.current_fidelity``), else from the stored parameters."""
    import numpy as np

    from .. import brdf
    from ..props.brdf import group_node, params_dict
    from ..shading import closures as C
    from ..shading.assign import current_fidelity, node_params
    from ..shading.realise import realise

    s = material.radiometer_brdf
    node = group_node(material, s)
    if node is not None:
        model, _, _, _, params = node_params(node)
        fid = current_fidelity(material)
    else:
        model, params = s.model, params_dict(s)
        fid = realise(model, s.method, **params)[1]
    theta_o = np.linspace(-89.0, 89.0, n)
    out = []
    for ti in thetas_i:
        t = np.radians(ti)
        wi = np.tile([np.sin(t), 0.0, np.cos(t)], (n, 1))
        to = np.radians(theta_o)
        wo = np.stack([-np.sin(to), np.zeros(n), np.cos(to)], axis=-1)  # + = mirror side
        fm = np.broadcast_to(np.asarray(brdf.evaluate(model, wi, wo, **params), dtype=float), (n, 3))
        fc = np.broadcast_to(np.asarray(C.evaluate_terms(fid.terms, wi, wo), dtype=float), (n, 3))
        out.append((ti, theta_o, np.array(fm), np.array(fc)))
    return model, fid, out


def write_lobe_plot(material, path):
    """PNG of the model's in-plane lobes (solid) against the Cycles closure (dashed), luminance-weighted
    in the file's working space, as the meter weighs them (``plots.brdf.write_lobes``)."""
    from ..compat import working_colour_space
    from ..plots.brdf import write_lobes
    from ..radiometry.photometry import efficacy as photometry

    model, fid, lobes = lobe_data(material)
    return write_lobes(path, model, fid.closure, fid.summary(), lobes,
                       photometry.luminance_weights(working_colour_space()))


class RADIOMETER_OT_brdf_plot(_OnActiveMaterial, bpy.types.Operator):
    """Plot the material's BRDF (model vs Cycles closure lobes, or the library summary) in an Image Editor"""

    bl_idname = "radiometer.brdf_plot"
    bl_label = "Plot BRDF"
    bl_options = {"REGISTER", "UNDO"}  # loads the plot as an image data-block

    kind: bpy.props.EnumProperty(
        name="Plot", default="LOBE",
        items=[("LOBE", "Model vs Cycles", "In-plane lobes of the model and of the Cycles closure it renders as"),
               ("SUMMARY", "Library Summary", "The BRDF library's summary plot of the model")],
        description="What to plot")

    def execute(self, context):
        from ..plots.brdf import write_summary
        from ..props.brdf import params_dict
        from ..shading.realise import check_params

        mat = _active_material(context)
        s = mat.radiometer_brdf
        suffix = "_lobe" if self.kind == "LOBE" else ""
        path = os.path.join(plot_directory(), f"brdf_{s.model}{suffix}.png")
        try:
            if self.kind == "LOBE":
                write_lobe_plot(mat, path)
            else:
                write_summary(s.model, path, **check_params(s.model, params_dict(s)))
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
        return needs(cls, context.scene is not None and hasattr(context.scene, "cycles"),
                     "needs a scene with Cycles available")

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


def _preset_items(self, context):
    from ..brdf.fresnel import PRESETS

    items = []
    for key, p in PRESETS.items():
        extra = f", n = {p['ior']}" if "ior" in p else ""
        items.append((key.upper(), key.title(), f"{key.title()}: F0 = {p['f0']}{extra} (CS348B Fresnel slide)"))
    return items


_preset_cache = []


def _preset_items_cached(self, context):
    if not _preset_cache:
        _preset_cache.extend(_preset_items(self, context))
    return _preset_cache


class RADIOMETER_OT_brdf_preset(_OnActiveMaterial, bpy.types.Operator):
    """Set the normal-incidence reflectance F0 of the material's BRDF to a physical preset"""

    bl_idname = "radiometer.brdf_preset"
    bl_label = "Fresnel Preset"
    bl_options = {"REGISTER", "UNDO"}

    preset: bpy.props.EnumProperty(name="Preset", items=_preset_items_cached,
                                   description="Physical material: gold, silver, glass or diamond")

    def execute(self, context):
        from ..brdf.fresnel import PRESETS
        from ..props.brdf import apply_settings, callbacks_muted, group_node, sync_params

        mat = _active_material(context)
        s = mat.radiometer_brdf
        if mat.library is not None:
            self.report({"ERROR"}, f"{mat.name} is linked from a library: make it local to edit it")
            return {"CANCELLED"}
        if len(s.params) == 0:
            sync_params(s, s.model)
        item = s.params.get("f0")
        if item is None:
            self.report({"ERROR"}, f"{s.model} has no f0 parameter (choose GGX, Beckmann or Torrance-Sparrow)")
            return {"CANCELLED"}
        f0 = float(PRESETS[self.preset.lower()]["f0"])
        node = group_node(mat, s)
        sock = node.inputs.get("f0") if node is not None else None
        if sock is not None and not sock.is_linked:  # the node is what renders: edit it in place
            sock.default_value = (f0, f0, f0, 1.0) if sock.type == "RGBA" else f0
        structural = False
        with callbacks_muted():
            if item.kind == "color":
                item.color = (f0, f0, f0)
            else:
                item.value = f0
            for other in ("ior", "eta", "k"):  # they would override f0
                o = s.params.get(other)
                if o is not None and o.use:
                    o.use = False
                    structural = True
        if structural and s.applied:
            apply_settings(mat)
        self.report({"INFO"}, f"{mat.name}: F0 = {f0} ({self.preset.title()})")
        return {"FINISHED"}


class RADIOMETER_OT_brdf_param_info(bpy.types.Operator):
    """What a BRDF parameter means (from radiometer.brdf)"""

    bl_idname = "radiometer.brdf_param_info"
    bl_label = "Parameter Info"
    bl_options = {"INTERNAL"}

    param: bpy.props.StringProperty(name="Parameter", description="Name of the BRDF parameter")

    @classmethod
    def description(cls, context, properties):
        mat = _active_material(context)
        item = mat.radiometer_brdf.params.get(properties.param) if mat is not None else None
        if item is None:
            return "BRDF parameter"
        unit = {"1": "dimensionless", "rad": "radians"}.get(item.unit, item.unit)
        return f"{item.name}: {item.description}" + (f" ({unit})" if unit else "")

    def execute(self, context):
        self.report({"INFO"}, self.description(context, self.properties))
        return {"FINISHED"}


classes = (RADIOMETER_OT_assign_brdf, RADIOMETER_OT_brdf_plot, RADIOMETER_OT_enable_osl, RADIOMETER_OT_brdf_preset,
           RADIOMETER_OT_brdf_param_info)

"""Material Properties > Radiometer BRDF: model, method, presets, parameters, tangent frame, Apply,
fidelity (RMS, median, 95th percentile, max), OSL hint, lobe plot.

Like Blender's own material panels, once the BRDF is applied the parameter rows ARE the group node's
inputs (``layout.prop(socket, "default_value")``): editing them changes the node in place, a linked
input (a texture) shows where it comes from, and nothing the user added around the group is touched.
Before Apply the rows edit the stored parameters (``Material.radiometer_brdf.params``), so the
library's defaults are visible and editable from the start.
"""

import bpy

from . import PropertiesPanel

#: readable labels of the library's parameter names (unknown names are title-cased)
LABELS = {
    "albedo": "Albedo \u03c1",
    "sigma": "Roughness \u03c3",
    "alpha": "Roughness \u03b1",
    "alpha_x": "Roughness \u03b1 Tangent",
    "alpha_y": "Roughness \u03b1 Bitangent",
    "f0": "Reflectance F0",
    "ior": "IOR n",
    "eta": "Conductor IOR \u03b7",
    "k": "Extinction \u03ba",
    "n": "Exponent n",
    "n_u": "Exponent Tangent n_u",
    "n_v": "Exponent Bitangent n_v",
    "kd": "Diffuse kd",
    "ks": "Specular ks",
    "Rs": "Specular Rs",
    "Rd": "Diffuse Rd",
    "variant": "Variant",
}
UNITS = {"1": "", "rad": "", "": ""}  # dimensionless: no suffix; radians: the angle field shows degrees


def param_label(item):
    """'Roughness α', 'Reflectance F0', or 'Name (unit)' for units other than 1 and rad."""
    label = LABELS.get(item.name, item.name.replace("_", " ").title())
    unit = UNITS.get(item.unit, item.unit)
    return f"{label} ({unit})" if unit else label


def format_fidelity(settings):
    """'exact' or 'approximate: RMS 3.2 %, albedo Δ 0.004' (or '' when not applied)."""
    if not settings.applied:
        return ""
    return settings.fidelity_summary or settings.fidelity_kind


def fidelity_lines(settings):
    """The fidelity numbers as panel lines: RMS, median ratio, 95th percentile, max."""
    if not settings.applied:
        return []
    if settings.fidelity_kind == "exact":
        return [f"RMS {100 * settings.fidelity_rms:.2f} %  (exact mapping)"]
    lines = [f"RMS {100 * settings.fidelity_rms:.1f} %,  albedo \u0394 {settings.fidelity_albedo:.3f}"]
    if settings.fidelity_has_pointwise:
        lines.append(f"Ratio median {settings.fidelity_median:.2f},  95 % within "
                     f"{settings.fidelity_p95:.2f}\u00d7,  max {settings.fidelity_max:.2f}\u00d7")
    return lines


def needs_osl_hint(settings):
    """True when the node mapping is poor (RMS or 95th-percentile factor above the thresholds)."""
    from ..props.brdf import OSL_HINT_P95, OSL_HINT_RMS

    if not settings.applied or settings.method != "nodes" or settings.fidelity_kind == "exact":
        return False
    return settings.fidelity_rms > OSL_HINT_RMS or (settings.fidelity_has_pointwise
                                                     and settings.fidelity_p95 > OSL_HINT_P95)


def is_anisotropic(settings, node):
    if node is not None and node.inputs.get("Tangent") is not None:
        return True
    return settings.model in ("ward", "ashikhmin_shirley") or any(
        i.name in ("alpha_x", "alpha_y", "n_u", "n_v") for i in settings.params)


def draw_params(layout, context, mat, settings, node):
    from ..props.brdf import node_input

    box = layout.box()
    head = box.row()
    head.label(text="Group Node Inputs" if node is not None else "Parameters (applied with Apply)",
               icon="NODETREE" if node is not None else "PROPERTIES")
    if any(i.name == "f0" for i in settings.params) or not settings.params:
        head.operator_menu_enum("radiometer.brdf_preset", "preset", text="Preset", icon="PRESET")
    if len(settings.params) == 0:
        box.label(text="Pick a model to see its parameters")
        return
    col = box.column()
    col.use_property_split = True
    col.use_property_decorate = False
    for item in settings.params:
        label = param_label(item)
        row = col.row(align=True)
        if item.optional:
            row.prop(item, "use", text="")
        sub = row.row(align=True)
        sub.enabled = (not item.optional) or item.use
        sock = node_input(node, item)
        if item.kind == "option":
            sub.prop(item, "option", text=label)
        elif sock is not None and sock.is_linked:
            src = sock.links[0].from_node
            sub.label(text=f"{label}: from {src.label or src.name}", icon="LINKED")
        elif sock is not None:
            sub.prop(sock, "default_value", text=label)
        elif item.kind == "color":
            sub.prop(item, "color", text=label)
        elif item.kind == "float":
            sub.prop(item, "angle" if item.unit == "rad" else "value", text=label)
        else:
            sub.prop(item, "text", text=label)
        row.operator("radiometer.brdf_param_info", text="", icon="QUESTION", emboss=False).param = item.name
    if node is not None:
        for extra in ("Normal", "Tangent"):
            sock = node.inputs.get(extra)
            if sock is not None and sock.is_linked:
                src = sock.links[0].from_node
                col.label(text=f"{extra}: from {src.label or src.name}", icon="LINKED")
    if is_anisotropic(settings, node):
        col.prop(settings, "tangent_source")
        if settings.tangent_source == "UV":
            ob = context.object
            if ob is not None and ob.type == "MESH":
                col.prop_search(settings, "uv_map", ob.data, "uv_layers", icon="GROUP_UVS")
            else:
                col.prop(settings, "uv_map")


class RADIOMETER_PT_brdf(PropertiesPanel, bpy.types.Panel):
    bl_label = "Radiometer BRDF"
    bl_idname = "RADIOMETER_PT_brdf"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return getattr(context, "material", None) is not None and hasattr(context.material, "radiometer_brdf")

    def draw(self, context):
        from ..props.brdf import group_node

        layout = self.layout
        mat = context.material
        s = mat.radiometer_brdf
        if mat.library is not None:
            layout.label(text=f"Linked from {mat.library.filepath}: make the material local to edit it",
                         icon="LIBRARY_DATA_DIRECT")
            return
        col = layout.column()
        col.use_property_split = True
        col.use_property_decorate = False
        col.prop(s, "model")
        col.prop(s, "method")
        node = group_node(mat, s) if mat.node_tree is not None else None
        draw_params(layout, context, mat, s, node)
        row = layout.row(align=True)
        row.operator("radiometer.assign_brdf", text="Update BRDF" if node is not None else "Apply BRDF",
                     icon="MATERIAL")
        row.operator("radiometer.brdf_plot", text="Plot Lobes", icon="IMAGE_DATA").kind = "LOBE"
        layout.prop(s, "live_update")
        if s.error:
            layout.label(text=s.error, icon="ERROR")
        if s.applied:
            box = layout.box()
            col = box.column(align=True)
            col.label(text=f"Fidelity: {s.fidelity_kind or 'unknown'}",
                      icon="CHECKMARK" if s.fidelity_kind == "exact" else "INFO")
            for line in fidelity_lines(s):
                col.label(text=line)
            col.label(text=f"Cycles: {s.fidelity_closure}")
            if s.method == "osl":
                from ..shading.osl import osl_problems

                problems = osl_problems(context.scene)
                for p in problems:
                    col.label(text=p, icon="ERROR")
                if problems:
                    col.operator("radiometer.enable_osl", icon="SCRIPT")
            elif needs_osl_hint(s):
                col.label(text="The node mapping is poor here: OSL renders this model more closely",
                          icon="INFO")
                col.prop_enum(s, "method", "osl", text="Use OSL Script")


classes = (RADIOMETER_PT_brdf,)

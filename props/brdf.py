"""Material.radiometer_brdf: the BRDF model, its parameters and the fidelity of its Cycles mapping.

Parameters live in a collection built from ``radiometer.brdf.describe(model)``, so adding a model to
the library needs no change here. Editing a parameter (or the model or method) re-applies the BRDF
to the material when ``live_update`` is on and the BRDF has been applied once; a bad value leaves
the material unchanged and shows the error in the panel.
"""

import contextlib

import bpy
import numpy as np
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       PointerProperty, StringProperty)

_guard = {"busy": False}
_enum_cache = []  # Blender needs the strings of dynamic enum items kept alive


def _model_items(self, context):
    if not _enum_cache:
        try:
            from ..brdf import describe, names

            for name in names():
                d = describe(name)
                title = d.get("title", name.replace("_", " ").title()) if isinstance(d, dict) else name
                doc = d.get("description", "") if isinstance(d, dict) else ""
                _enum_cache.append((name, title, doc))
        except Exception:  # library missing or broken: offer nothing rather than break the UI
            return [("lambert", "Lambert", "")]
    return _enum_cache


@contextlib.contextmanager
def callbacks_muted():
    """Inside, writing parameters fires no re-apply: the update callbacks return at once (an operator
    that sets several values and applies once, or none)."""
    previous = _guard["busy"]
    _guard["busy"] = True
    try:
        yield
    finally:
        _guard["busy"] = previous


def _material(owner):
    mat = owner.id_data
    return mat if isinstance(mat, bpy.types.Material) else None


def params_dict(settings):
    """The parameters to pass: optional ones only when switched on, others only when not default
    (so that, e.g., the Schlick f0 default does not clash with an explicit ior)."""
    out = {}
    for item in settings.params:
        if item.optional and not item.use:
            continue
        if item.kind == "color":
            value = [float(c) for c in item.color]
            if not item.optional and item.has_default and all(abs(c - item.default_value) < 1e-9 for c in value):
                continue
        elif item.kind == "float":
            value = float(item.value)
            if not item.optional and item.has_default and abs(value - item.default_value) < 1e-9 * max(1.0, abs(value)):
                continue
        else:
            value = item.text
            if not item.optional and value == item.default_text:
                continue
        out[item.name] = value
    return out


#: above these (node mapping, uniform direction set) the panel suggests the OSL method
OSL_HINT_RMS = 0.10
OSL_HINT_P95 = 1.5


def group_node(material, settings=None):
    """The material's Radiometer group node when it realises ``settings``' model and method, else None."""
    import json

    from ..shading.assign import GROUP_NODE_NAME

    tree = material.node_tree
    node = tree.nodes.get(GROUP_NODE_NAME) if tree is not None else None
    if node is None or node.node_tree is None or "radiometer_signature" not in node.node_tree:
        return None
    if settings is not None:
        try:
            sig = json.loads(node.node_tree["radiometer_signature"])
        except (TypeError, ValueError):
            return None
        if sig.get("model") != settings.model or sig.get("method") != settings.method:
            return None
    return node


def node_input(node, item):
    """The group node's input socket that holds parameter ``item`` now (None: not an input)."""
    if node is None or item.kind == "option" or (item.optional and not item.use):
        return None
    return node.inputs.get(item.name)


def pull_from_node(material, skip=()):
    """Copy the group node's input values into the stored parameters (the node is the truth once
    applied: an artist may have edited it in the node editor or in the panel). No callbacks fire."""
    settings = material.radiometer_brdf
    node = group_node(material, settings)
    if node is None:
        return False
    _guard["busy"] = True
    try:
        for item in settings.params:
            sock = node_input(node, item)
            if sock is None or item.name in skip:
                continue
            v = sock.default_value
            if item.kind == "color":
                item.color = tuple(float(c) for c in v[:3]) if sock.type == "RGBA" else (float(v),) * 3
            elif item.kind == "float":
                item.value = float(v) if sock.type != "RGBA" else float(np.mean(v[:3]))
    finally:
        _guard["busy"] = False
    return True


def input_links(material):
    """[(input name, from_socket)] of links into the group node's inputs (textures, bump)."""
    from ..shading.assign import GROUP_NODE_NAME

    tree = material.node_tree
    node = tree.nodes.get(GROUP_NODE_NAME) if tree is not None else None
    if node is None:
        return []
    return [(sock.name, link.from_socket) for sock in node.inputs if sock.is_linked for link in sock.links]


def restore_links(material, links):
    """Re-link user links that a rebuild of the group's interface dropped (same input names only)."""
    from ..shading.assign import GROUP_NODE_NAME

    tree = material.node_tree
    node = tree.nodes.get(GROUP_NODE_NAME) if tree is not None else None
    if node is None:
        return
    for name, from_socket in links:
        sock = node.inputs.get(name)
        if sock is not None and not sock.is_linked:
            try:
                tree.links.new(from_socket, sock)
            except (ReferenceError, RuntimeError):  # the source node was removed meanwhile
                pass


def apply_settings(material, changed=()):
    """Apply the material's stored model/method/params; store the error message on failure.

    The group node's current input values are kept (pulled into the stored parameters first), except
    for the parameters named in ``changed`` (just edited through the stored parameters)."""
    from ..errors import RadiometerError
    from ..shading.assign import assign_brdf

    settings = material.radiometer_brdf
    pull_from_node(material, skip=changed)
    links = input_links(material)
    try:
        fid = assign_brdf(material, settings.model, settings.method, tangent_source=settings.tangent_source,
                          uv_map=settings.uv_map, **params_dict(settings))
        restore_links(material, links)
    except RadiometerError as exc:
        _guard["busy"] = True
        try:
            settings.error = str(exc)
        finally:
            _guard["busy"] = False
        return None
    return fid


def _on_param_change(self, context):
    if _guard["busy"]:
        return
    mat = _material(self)
    if mat is not None and mat.radiometer_brdf.applied and mat.radiometer_brdf.live_update:
        apply_settings(mat, changed=(self.name,) if isinstance(self, RADIOMETER_PG_brdf_param) else ())


def sync_params(settings, model, values=None):
    """Rebuild the parameter collection for ``model`` from describe(); ``values`` override defaults."""
    from ..shading.realise import param_specs

    values = values or {}
    _guard["busy"] = True
    try:
        settings.params.clear()
        for name, s in param_specs(model).items():
            item = settings.params.add()
            item.name = name
            item.kind = s.get("kind", "float")
            item.optional = bool(s.get("optional"))
            item.use = name in values and values[name] is not None
            item.unit = s.get("unit", "") or ""
            item.description = s.get("description", "") or ""
            default = s.get("default")
            item.has_default = default is not None
            shown = values.get(name, default if default is not None else s.get("ui_default"))
            if item.kind == "color":
                if default is not None:
                    item.default_value = float(np.mean(default)) if hasattr(default, "__len__") else float(default)
                if shown is not None:
                    item.color = tuple(shown) if hasattr(shown, "__len__") else (shown,) * 3
            elif item.kind == "float":
                if default is not None:
                    item.default_value = float(default)
                if shown is not None:
                    item.value = float(shown)
                if s.get("min") is not None:
                    item.soft_min = float(s["min"])
                if s.get("max") is not None:
                    item.soft_max = float(s["max"])
            else:
                item.values = ",".join(str(v) for v in s.get("values", []))
                item.default_text = "" if default is None else str(default)
                item.text = "" if shown is None else str(shown)
    finally:
        _guard["busy"] = False


def _on_model_change(self, context):
    if _guard["busy"]:
        return
    sync_params(self, self.model)
    _on_param_change(self, context)


def store_assignment(material, model, method, params, fidelity):
    """Record what ``shading.assign.assign_brdf`` realised (no update callbacks fire)."""
    settings = material.radiometer_brdf
    _guard["busy"] = True
    try:
        settings.model = model
        settings.method = method
        if params_dict(settings) != params or len(settings.params) == 0:
            sync_params(settings, model, params)
            _guard["busy"] = True
        settings.applied = True
        settings.error = ""
        settings.fidelity_kind = fidelity.kind
        settings.fidelity_rms = fidelity.rms_rel_diff
        settings.fidelity_albedo = fidelity.albedo_diff
        settings.fidelity_closure = fidelity.closure
        settings.fidelity_notes = fidelity.notes
        settings.fidelity_summary = fidelity.summary()
        pw = getattr(fidelity, "pointwise", None)
        has_pw = pw is not None and getattr(pw, "n", 0) > 0
        settings.fidelity_has_pointwise = has_pw
        settings.fidelity_median = float(pw.median) if has_pw else 1.0
        settings.fidelity_p95 = float(pw.p95) if has_pw else 1.0
        settings.fidelity_max = float(pw.max) if has_pw else 1.0
    finally:
        _guard["busy"] = False


_option_cache = {}  # values string -> enum items (kept alive for Blender)


def _option_items(self, context):
    key = self.values or self.text or "-"
    if key not in _option_cache:
        values = [v for v in key.split(",") if v] or ["-"]
        _option_cache[key] = [(v, v.replace("_", " ").title(), f"{self.name} = '{v}'") for v in values]
    return _option_cache[key]


def _get_option(self):
    values = [v for v in (self.values or self.text).split(",") if v]
    return values.index(self.text) if self.text in values else 0


def _set_option(self, index):
    values = [v for v in (self.values or self.text).split(",") if v]
    if 0 <= index < len(values) and values[index] != self.text:
        self.text = values[index]  # fires text's update (re-apply)


def _get_angle(self):
    return self.value


def _set_angle(self, v):
    self.value = v  # fires value's update (re-apply)


class RADIOMETER_PG_brdf_param(bpy.types.PropertyGroup):
    """One BRDF parameter (name = the library's parameter name, e.g. alpha, f0, sigma)."""

    # name (StringProperty) comes from PropertyGroup
    kind: StringProperty(name="Kind", default="float", description="Parameter kind: 'float', 'color' (RGB) or 'option'")
    optional: BoolProperty(name="Optional", default=False,
                           description="The parameter is optional (passed only when Use is on)")
    use: BoolProperty(name="Use", default=False, update=_on_param_change,
                      description="Pass this optional parameter (e.g. ior instead of f0)")
    has_default: BoolProperty(name="Has Default", default=True,
                              description="The library gives this parameter a default value")
    default_value: FloatProperty(name="Default Value", default=0.0,
                                 description="The library's default value (mean for RGB)")
    default_text: StringProperty(name="Default Choice", default="",
                                 description="The library's default choice of an option")
    values: StringProperty(name="Choices", default="", description="Allowed choices of an option, comma-separated")
    unit: StringProperty(name="Unit", default="",
                         description="Unit of the parameter ('1' = dimensionless, 'rad' = radians)")
    description: StringProperty(name="Description", default="",
                                description="What the parameter means (from radiometer.brdf)")
    soft_min: FloatProperty(name="Minimum", default=0.0, description="Smallest allowed value")
    soft_max: FloatProperty(name="Maximum", default=1.0, description="Largest allowed value")
    value: FloatProperty(name="Value", update=_on_param_change, precision=4,
                         description="Value of the parameter (library units: dimensionless or radians)")
    angle: FloatProperty(name="Angle", subtype="ANGLE", get=_get_angle, set=_set_angle,
                         description="Value of an angle parameter (shown in degrees, stored in radians)")
    color: FloatVectorProperty(name="Colour", subtype="COLOR", size=3, min=0.0, soft_max=1.0,
                               default=(0.8, 0.8, 0.8), update=_on_param_change,
                               description="RGB value of the parameter (reflectances are linear, 0-1)")
    text: StringProperty(name="Value", update=_on_param_change, description="Chosen option (e.g. variant)")
    option: EnumProperty(name="Option", items=_option_items, get=_get_option, set=_set_option,
                         description="Variant of the model (changes the formula; re-applies the BRDF)")


class RADIOMETER_PG_brdf(bpy.types.PropertyGroup):
    """Material.radiometer_brdf: the model, its parameters and the fidelity of its Cycles mapping."""

    model: EnumProperty(name="Model", items=_model_items, update=_on_model_change,
                        description="Parametric BRDF from radiometer.brdf")
    method: EnumProperty(
        name="Method",
        items=[("nodes", "Node Group", "Cycles closures in a node group: Cycles (any device) and EEVEE"),
               ("osl", "OSL Script", "Open Shading Language script: Cycles on the CPU with OSL enabled")],
        default="nodes", update=_on_param_change,
        description="How the BRDF is realised: Cycles closure nodes, or an OSL script (exact for more models)")
    params: CollectionProperty(name="Parameters", type=RADIOMETER_PG_brdf_param,
                               description="The model's parameters (before Apply; afterwards the group node's inputs)")
    tangent_source: EnumProperty(
        name="Tangent",
        items=[("OBJECT", "Object Axis", "Anisotropy along the object's +X axis (+Y where +X is along the normal)"),
               ("UV", "UV Map", "Anisotropy along the tangent of a UV map (Blender's Tangent node)")],
        default="OBJECT", update=_on_param_change,
        description="Frame of anisotropic models: the object's +X axis or a UV map's tangent")
    uv_map: StringProperty(name="UV Map", default="", update=_on_param_change,
                           description="UV map whose tangent orients the anisotropy (empty: the active one)")
    live_update: BoolProperty(name="Live Update", default=True,
                              description="Re-apply the BRDF whenever a parameter changes")
    applied: BoolProperty(name="Applied", default=False, description="The BRDF has been applied to this material")
    error: StringProperty(name="Last Error", default="", description="Why the last Apply failed (empty: it succeeded)")
    fidelity_kind: StringProperty(name="Fidelity", default="",
                                  description="'exact' or 'approximate' (Cycles vs the library)")
    fidelity_rms: FloatProperty(name="Fidelity RMS Difference", default=0.0,
                                description="RMS relative difference of f (dimensionless)")
    fidelity_albedo: FloatProperty(name="Fidelity Albedo Difference", default=0.0,
                                   description="Max directional-albedo difference")
    fidelity_has_pointwise: BoolProperty(name="Has Pointwise Ratios", default=False,
                                         description="Pointwise ratio statistics are available")
    fidelity_median: FloatProperty(name="Median Ratio", default=1.0,
                                   description="Median ratio f_Cycles / f_model on the uniform "
                                   "direction set (1 = right on average)")
    fidelity_p95: FloatProperty(name="95th Percentile Ratio", default=1.0,
                                description="95 % of direction pairs lie within this factor "
                                "of the model (max(q, 1/q))")
    fidelity_max: FloatProperty(name="Largest Ratio", default=1.0,
                                description="Largest factor max(q, 1/q) between Cycles and "
                                "the model on the uniform direction set")
    fidelity_closure: StringProperty(name="Cycles Closure", default="",
                                     description="What Cycles renders (closures and nodes)")
    fidelity_notes: StringProperty(name="Fidelity Notes", default="",
                                   description="Notes on the mapping (fits, limits, OSL state)")
    fidelity_summary: StringProperty(name="Fidelity Summary", default="", description="One-line fidelity summary")


classes = (RADIOMETER_PG_brdf_param, RADIOMETER_PG_brdf)


def _hook(material, model, method, params, fidelity):
    if getattr(material, "radiometer_brdf", None) is not None:
        store_assignment(material, model, method, params, fidelity)


def register_extra():
    from ..shading import assign

    bpy.types.Material.radiometer_brdf = PointerProperty(type=RADIOMETER_PG_brdf)
    if _hook not in assign.ASSIGNED_HOOKS:
        assign.ASSIGNED_HOOKS.append(_hook)


def unregister_extra():
    from ..shading import assign

    if _hook in assign.ASSIGNED_HOOKS:
        assign.ASSIGNED_HOOKS.remove(_hook)
    del bpy.types.Material.radiometer_brdf

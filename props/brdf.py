"""Material.radiometer_brdf: the BRDF model, its parameters and the fidelity of its Cycles mapping.

Parameters live in a collection built from ``radiometer.brdf.describe(model)``, so adding a model to
the library needs no change here. Editing a parameter (or the model or method) re-applies the BRDF
to the material when ``live_update`` is on and the BRDF has been applied once; a bad value leaves
the material unchanged and shows the error in the panel.
"""

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


def _material(owner):
    mat = owner.id_data
    return mat if isinstance(mat, bpy.types.Material) else None


def _params_dict(settings):
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


def apply_settings(material):
    """Apply the material's stored model/method/params; store the error message on failure."""
    from ..errors import RadiometerError
    from ..shading.assign import assign_brdf

    settings = material.radiometer_brdf
    try:
        fid = assign_brdf(material, settings.model, settings.method, **_params_dict(settings))
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
        apply_settings(mat)


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
        if _params_dict(settings) != params or len(settings.params) == 0:
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
    finally:
        _guard["busy"] = False


class RADIOMETER_PG_brdf_param(bpy.types.PropertyGroup):
    # name (StringProperty) comes from PropertyGroup
    kind: StringProperty(default="float")  # 'float' | 'color' | 'option'
    optional: BoolProperty(default=False)
    use: BoolProperty(name="Use", default=False, update=_on_param_change,
                      description="Pass this optional parameter (e.g. ior instead of f0)")
    has_default: BoolProperty(default=True)
    default_value: FloatProperty(default=0.0)
    default_text: StringProperty(default="")
    unit: StringProperty(default="")
    description: StringProperty(default="")
    soft_min: FloatProperty(default=0.0)
    soft_max: FloatProperty(default=1.0)
    value: FloatProperty(name="Value", update=_on_param_change, precision=4)
    color: FloatVectorProperty(name="Colour", subtype="COLOR", size=3, min=0.0, soft_max=1.0,
                               default=(0.8, 0.8, 0.8), update=_on_param_change)
    text: StringProperty(name="Value", update=_on_param_change)


class RADIOMETER_PG_brdf(bpy.types.PropertyGroup):
    model: EnumProperty(name="Model", items=_model_items, update=_on_model_change,
                        description="Parametric BRDF from radiometer.brdf")
    method: EnumProperty(
        name="Method",
        items=[("nodes", "Node Group", "Cycles closures in a node group: Cycles (any device) and EEVEE"),
               ("osl", "OSL Script", "Open Shading Language script: Cycles on the CPU with OSL enabled")],
        default="nodes", update=_on_param_change)
    params: CollectionProperty(type=RADIOMETER_PG_brdf_param)
    live_update: BoolProperty(name="Live Update", default=True,
                              description="Re-apply the BRDF whenever a parameter changes")
    applied: BoolProperty(default=False)
    error: StringProperty(default="")
    fidelity_kind: StringProperty(default="")
    fidelity_rms: FloatProperty(default=0.0, description="RMS relative difference of f (dimensionless)")
    fidelity_albedo: FloatProperty(default=0.0, description="Max directional-albedo difference")
    fidelity_closure: StringProperty(default="")
    fidelity_notes: StringProperty(default="")
    fidelity_summary: StringProperty(default="")


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

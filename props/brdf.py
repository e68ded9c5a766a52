"""Material.radiometer_brdf: the BRDF model, its parameters and the fidelity of its Cycles mapping.

Parameters live in a collection built from ``radiometer.brdf.describe(model)``, so adding a model to
the library needs no change here. Editing a parameter (or the model or method) re-applies the BRDF
to the material when ``live_update`` is on and the BRDF has been applied once; a bad value leaves
the material unchanged and shows the error in the panel.
"""

import bpy
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
    out = {}
    for item in settings.params:
        if item.kind == "color":
            out[item.name] = list(item.color)
        elif item.kind == "float":
            out[item.name] = item.value
        else:
            out[item.name] = item.text
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
    from ..brdf import describe

    values = values or {}
    d = describe(model)
    specs = d["params"] if isinstance(d, dict) else d
    _guard["busy"] = True
    try:
        settings.params.clear()
        for s in specs:
            item = settings.params.add()
            item.name = s["name"]
            item.kind = s.get("kind", "float")
            item.unit = s.get("unit", "") or ""
            item.description = s.get("description", "") or ""
            v = values.get(s["name"], s.get("default"))
            if item.kind == "color":
                if v is not None:
                    item.color = tuple(v) if hasattr(v, "__len__") else (v, v, v)
            elif item.kind == "float":
                if v is not None:
                    item.value = float(v)
                if s.get("min") is not None:
                    item.soft_min = float(s["min"])
                if s.get("max") is not None:
                    item.soft_max = float(s["max"])
            else:
                item.text = "" if v is None else str(v)
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
        if settings.model != model or len(settings.params) == 0:
            settings.model = model
            _guard["busy"] = False
            sync_params(settings, model, params)
            _guard["busy"] = True
        else:
            current = {p.name for p in settings.params}
            if params:
                for item in settings.params:
                    if item.name in params:
                        v = params[item.name]
                        if item.kind == "color":
                            item.color = tuple(v) if hasattr(v, "__len__") else (v, v, v)
                        elif item.kind == "float":
                            item.value = float(v)
                        else:
                            item.text = str(v)
            del current
        settings.method = method
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
    kind: StringProperty(default="float")
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


def register_extra():
    bpy.types.Material.radiometer_brdf = PointerProperty(type=RADIOMETER_PG_brdf)


def unregister_extra():
    del bpy.types.Material.radiometer_brdf

"""Panels and viewport overlays: they show settings and readings and contain no maths."""

from ..registration import ModuleGroup


class SidebarPanel:
    """Mixin (before ``bpy.types.Panel``): a panel of the 3D viewport sidebar's "Radiometer" tab."""

    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Radiometer"


class PropertiesPanel:
    """Mixin (before ``bpy.types.Panel``): a panel of the Properties editor (its tab: ``bl_context``)."""

    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"


class WorldPanel(PropertiesPanel):
    """Mixin (before ``bpy.types.Panel``): a panel of Properties > World."""

    bl_context = "world"


class SceneSettingsPanel:
    """Mixin: a panel shown while the scene has the property group named ``settings`` (registered)."""

    settings = ""

    @classmethod
    def poll(cls, context):
        return context.scene is not None and hasattr(context.scene, cls.settings)

# Submodules in registration order; each owns a ``classes`` tuple.
_group = ModuleGroup(__name__, ("meter", "brdf", "analysis", "luminaires", "world", "daylight", "cluster", "sky"))
register = _group.register
unregister = _group.unregister

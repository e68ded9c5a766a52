"""Import a photometric file (IES LM-63, EULUMDAT) as a light: operator and File > Import entry."""

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper

from ..errors import RadiometerError


class RADIOMETER_OT_import_luminaire(bpy.types.Operator, ImportHelper):
    """Add a luminaire from an IES LM-63 or EULUMDAT file as a point light at the 3D cursor (renders the
    file's candela at the scene's luminous efficacy; read exactly by the light meter)"""

    bl_idname = "radiometer.import_luminaire"
    bl_label = "Import Luminaire (IES, EULUMDAT)"
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: StringProperty(description="File types shown in the browser (IES LM-63, EULUMDAT)",
                                default="*.ies;*.IES;*.ldt;*.LDT", options={"HIDDEN"})

    def execute(self, context):
        from .. import api

        try:
            obj = api.import_luminaire(self.filepath, scene=context.scene, location=tuple(context.scene.cursor.location))
        except RadiometerError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        self.report({"INFO"}, f"{obj.name}: {obj.data.get('radiometer_lumens', 0.0):.6g} lm")
        return {"FINISHED"}


def _menu(self, _context):
    self.layout.operator(RADIOMETER_OT_import_luminaire.bl_idname, text="Luminaire (.ies, .ldt)")


def register_extra():
    bpy.types.TOPBAR_MT_file_import.append(_menu)


def unregister_extra():
    bpy.types.TOPBAR_MT_file_import.remove(_menu)


classes = (RADIOMETER_OT_import_luminaire,)

"""Sidebar panel (tab "Radiometer"): the active light's photometry when it is a luminaire."""

import bpy

from . import SidebarPanel


class RADIOMETER_PT_luminaire(SidebarPanel, bpy.types.Panel):
    bl_label = "Luminaire"
    bl_idname = "RADIOMETER_PT_luminaire"

    @classmethod
    def poll(cls, context):
        ob = context.active_object
        return ob is not None and ob.type == "LIGHT"

    def draw(self, context):
        from ..errors import RadiometerError
        from .. import api

        layout = self.layout
        ob = context.active_object
        table, reason = api.photometric_table(ob.data)
        if table is None:
            layout.label(text="Not a photometric light" if reason == "has no node tree" else f"Light {reason}")
            layout.operator("radiometer.import_luminaire", icon="IMPORT")
            return
        try:
            s = api.luminaire_summary(ob)  # cached: not re-read on every redraw
        except RadiometerError as exc:
            layout.label(text=str(exc), icon="ERROR")
            return
        col = layout.column(align=True)
        for label, value in (("Luminaire", s.get("luminaire") or s.get("catalogue_number")),
                             ("Manufacturer", s.get("manufacturer"))):
            if value:
                col.label(text=f"{label}: {value.splitlines()[0]}")
        col.label(text=f"Flux: {s['lumens']:.5g} lm")
        col.label(text=f"Max intensity: {s['max_candela']:.5g} cd")
        if s.get("beam_angle_deg") is not None:
            col.label(text=f"Beam / field: {s['beam_angle_deg']:.3g}° / {s['field_angle_deg']:.3g}°")
        col.label(text=f"Symmetry: {s['symmetry']}")
        col.label(text="Meter: exact (photometric point)", icon="CHECKMARK")


classes = (RADIOMETER_PT_luminaire,)

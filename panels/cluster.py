"""Scale-out panel (3D viewport sidebar > Radiometer): whether Dask is there, how to get it, how to use it."""

import bpy

from . import SidebarPanel


class RADIOMETER_PT_cluster(SidebarPanel, bpy.types.Panel):
    bl_label = "Scale-out (Dask)"
    bl_idname = "RADIOMETER_PT_cluster"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        from ..cluster import available
        from ..operators.cluster import LAST

        layout = self.layout
        col = layout.column(align=True)
        if not available():
            col.label(text="Dask is not installed in Blender's Python:", icon="INFO")
            for line in ("pip install dask==2026.8.0 distributed==2026.8.0", "(the versions in requirements.txt);",
                         "then sun studies, daylight and batches", "can run on a cluster"):
                col.label(text=line)
            return
        col.label(text="Dask is installed", icon="CHECKMARK")
        col.label(text="Run on a cluster: python -m radiometer")
        col.label(text="sun-study|batch ... --scheduler ADDRESS")
        col.label(text="or --workers N (docs/cluster.md)")
        layout.operator("radiometer.cluster_check", icon="NETWORK_DRIVE")
        if LAST.get("error"):
            layout.label(text=LAST["error"][:120], icon="ERROR")
        elif LAST.get("info"):
            info = LAST["info"]
            layout.label(text=f"{info['workers']} workers, {info['threads']} threads, {info['hosts']} host(s)")


classes = (RADIOMETER_PT_cluster,)

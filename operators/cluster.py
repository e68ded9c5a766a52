"""*Check Dask Cluster*: connect to a scheduler and report its workers (the scale-out's UI entry)."""

import bpy

#: The last check per window session: plain data shown by panels/cluster.py.
LAST = {}


class RADIOMETER_OT_cluster_check(bpy.types.Operator):
    """Connect to a Dask scheduler and report its workers and threads (for sun studies, daylight and batches on a cluster)"""

    bl_idname = "radiometer.cluster_check"
    bl_label = "Check Dask Cluster"
    bl_options = {"REGISTER", "UNDO"}  # changes nothing in the scene; UNDO kept for the house rule

    scheduler: bpy.props.StringProperty(
        name="Scheduler", default="tcp://127.0.0.1:8786",
        description="Address of the Dask scheduler (started with `dask scheduler`), e.g. tcp://10.0.0.5:8786")

    @classmethod
    def poll(cls, context):
        from ..cluster import available

        if not available():
            cls.poll_message_set("Dask is not installed (see the Scale-out panel)")
            return False
        return True

    def invoke(self, context, event):
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        from .. import api
        from ..errors import RadiometerError

        try:
            info = api.cluster_info(self.scheduler)
        except RadiometerError as exc:
            LAST["error"], LAST["info"] = str(exc), None
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        LAST["error"], LAST["info"] = None, info
        self.report({"INFO"}, f"{info['workers']} workers, {info['threads']} threads on {info['hosts']} host(s)")
        return {"FINISHED"}


classes = (RADIOMETER_OT_cluster_check,)

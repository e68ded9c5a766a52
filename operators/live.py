"""Registers the live meter mode's depsgraph handler and timer; the mode itself (its state, the
handler and the timer) is host code in ``measure/meter/live.py``, which the properties and panels read."""

from ..measure.meter.live import register_extra, unregister_extra  # noqa: F401 - ModuleGroup calls them

classes = ()

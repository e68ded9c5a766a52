"""Registers the live meter mode's depsgraph handler and timer; the mode itself (its state, the
handler and the timer) is host code in ``measure/meter/live.py``, which the properties and panels read."""

from .. import api

classes = ()


def register_extra():  # ModuleGroup calls it with the other operators
    api.live_register()


def unregister_extra():
    api.live_unregister()

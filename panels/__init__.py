"""Panels and viewport overlays: they show settings and readings and contain no maths."""

from ..registration import ModuleGroup

# Submodules in registration order; each owns a ``classes`` tuple.
_group = ModuleGroup(__name__, ("meter", "brdf", "analysis", "luminaires", "world", "daylight", "cluster", "sky"))
register = _group.register
unregister = _group.unregister

"""Operators: thin wrappers that gather inputs, call one function of ``radiometer.api`` and report."""

from ..registration import ModuleGroup

# Submodules in registration order; each owns a ``classes`` tuple.
_group = ModuleGroup(__name__, ("meter", "lights", "brdf", "analysis", "luminaires", "world", "live", "false_colour", "daylight", "cluster", "sky", "deliverables"))
register = _group.register
unregister = _group.unregister

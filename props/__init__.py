"""PropertyGroups: settings and results stored in the .blend (they survive save and reload)."""

from ..registration import ModuleGroup

# Submodules in registration order; each owns a ``classes`` tuple and attaches its pointers in
# ``register_extra`` (and deletes them in ``unregister_extra``).
_group = ModuleGroup(__name__, ("meter", "brdf", "analysis", "daylight"))
register = _group.register
unregister = _group.unregister

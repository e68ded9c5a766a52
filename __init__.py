"""Radiometer: physically based shading and radiometric analysis for Blender.

The repository root is the extension package. Importing it must stay cheap and must not import
``bpy``: the math packages (``radiometer.brdf``, ``radiometer.radiometry``) are used from plain
Python too. Everything that touches Blender is imported inside ``register()``.
"""

__all__ = ["register", "unregister"]

_registered_modules = []


def _host_modules():
    # Order matters: properties first (operators and panels refer to them), UI last.
    from . import props, operators, panels, cli

    return [props, operators, panels, cli]


def register():
    """Register everything; calling it again while registered does nothing (idempotent).

    A failure part-way unregisters what was registered and re-raises, so a later call starts clean.
    """
    import bpy

    from .shading import closures

    if _registered_modules:
        return
    # Fidelity of BRDF mappings is computed against the Fresnel this Blender's Cycles renders.
    closures.use_cycles_version(bpy.app.version)
    modules = _host_modules()
    try:
        for module in modules:
            module.register()
            _registered_modules.append(module)
    except Exception:
        unregister()
        raise


def unregister():
    # Exact mirror of register(): reverse order, only what was registered.
    while _registered_modules:
        _registered_modules.pop().unregister()

"""Registers groups of Blender classes as exact mirror images (register in order, unregister in reverse).

A host submodule owns a ``classes`` tuple and may define ``register_extra()``/``unregister_extra()``
(menus, handlers, draw callbacks). ``ModuleGroup`` keeps what it registered so that ``unregister``
removes exactly that, even after a partially failed ``register``.
"""

import importlib


class ModuleGroup:
    def __init__(self, package, names):
        self.package = package
        self.names = tuple(names)
        self._done = []

    def register(self):
        import bpy

        for name in self.names:
            module = importlib.import_module(f".{name}", self.package)
            registered = []
            try:
                for cls in module.classes:
                    bpy.utils.register_class(cls)
                    registered.append(cls)
                if hasattr(module, "register_extra"):
                    module.register_extra()
            except Exception:
                for cls in reversed(registered):
                    bpy.utils.unregister_class(cls)
                raise
            self._done.append(module)

    def unregister(self):
        import bpy

        while self._done:
            module = self._done.pop()
            if hasattr(module, "unregister_extra"):
                module.unregister_extra()
            for cls in reversed(module.classes):
                bpy.utils.unregister_class(cls)

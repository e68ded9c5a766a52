"""Blender-side shading: realise Radiometer BRDFs as Cycles closure networks and check them.

``fit``, ``optim`` and ``closures`` import no bpy (pure numpy); ``nodes``, ``osl``, ``assign`` and ``validate``
need Blender and import bpy lazily inside their functions.
"""

"""Blender-side measurement (imports bpy): everything that renders or reads the scene lives here.

The maths it relies on lives in ``radiometer.radiometry`` (no bpy)."""

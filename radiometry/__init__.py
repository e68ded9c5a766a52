"""Pure-numpy radiometry core: units, photometry, analytic light irradiance, statistics (no bpy)."""

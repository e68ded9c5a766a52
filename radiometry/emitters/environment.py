"""The world as an emitter: constant, equirect image and CIE sky, at infinity.

The maths stays where it was written: :class:`..environment.WorldLight` (constant and image worlds,
pixel-exact or bilinear quadrature) and :class:`..cie_sky.CIESkyWorld` (the 15 CIE standard skies)
both derive from :class:`EnvironmentEmitter`, which gives them the :class:`.base.Emitter` interface
over their own ``irradiance(normals)``. A world is the same at every point (unoccluded), so
``irradiance_at`` ignores the points but for their shape. Units: the world's radiance is per scene
unit^2 like every world (W/(m^2 sr) when the scene's unit is the metre); no position, so no intensity
(ValueError) and infinite power.
"""

import numpy as np

from .base import Emitter, EmitterFlags, RayVisibility

__all__ = ["EnvironmentEmitter"]


class EnvironmentEmitter(Emitter):
    """Mixin: the Emitter interface of a world. Subclasses provide ``modelled`` (bool), ``kind``,
    ``reason`` and ``irradiance(normals) -> (E (..., 3), absolute error (..., 3))``."""

    source_id = None
    visibility = RayVisibility.ALL

    @property
    def flags(self):
        flags = EmitterFlags.INFINITE
        return flags if self.modelled else flags | EmitterFlags.RENDERED_ONLY

    def power_w(self):
        return np.full(3, np.inf)

    def intensity_towards(self, directions):
        raise ValueError("the world is at infinity: it has no position, intensity does not apply")

    def irradiance_at(self, points, normals):
        """(E (..., 3) W/m^2 per channel, absolute error (..., 3)) of the unoccluded world on receivers
        facing ``normals``; ValueError when the world is not modelled (only a render measures it)."""
        p = np.asarray(points, float)
        n = np.asarray(normals, float)
        p, n = np.broadcast_arrays(p, n)
        if not self.modelled:
            raise ValueError(f"the world is not modelled: {self.reason}")
        e, err = self.irradiance(n)
        return np.asarray(e, float), np.asarray(err, float)

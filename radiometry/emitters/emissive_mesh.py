"""Surfaces with an Emission shader: emitters that only a render measures.

An :class:`EmissiveMesh` is the emitting triangles of one object (one material slot, ``source_id.part``)
in metres with the radiance they emit, W/(m^2 sr) per RGB channel, on both sides (Cycles' Emission
closure emits from the front and the back). Cycles' Emission strength is that radiance: "a value of
1.0 will ensure that the object in the image has the exact same color as the Color input" (Blender
manual, Emission shader), so L = strength x colour (read by the capture layer where both are plain
values; None otherwise: a texture or a node chain).

Power: sum over the triangles of pi L A x 2 (both sides), W per channel. Irradiance: the sum of
Lambert's polygon formula over the triangles, each seen from the side the receiver is on. That is a
closed form only of the triangles *as if nothing shaded them*: a mesh shades itself, and its
emission may vary over the surface, so the bound is None and the flags say RENDERED_ONLY: the planner
renders every point such a surface can reach (``scene_model.indirect_possible``). Intensity (far field):
sum of L A_t |cos| per side.
"""

import numpy as np

from ..scene.geometry import polygon_projected_solid_angle
from ..units import as_finite_array
from .base import Emitter, EmitterFlags, RayVisibility, SourceId, prepare_receivers

__all__ = ["EmissiveMesh"]


class EmissiveMesh(Emitter):
    """Emitting triangles (T, 3, 3) m with radiance (3,) or (T, 3) W/(m^2 sr) per channel, or None
    when the capture could not read it (power and irradiance are then NaN)."""

    def __init__(self, triangles, radiance=None, *, name="", source_id=None, visibility=RayVisibility.ALL):
        self.triangles = as_finite_array(triangles, "triangles").reshape(-1, 3, 3)
        self.name = str(name)
        self.source_id = SourceId(*source_id) if source_id is not None and not isinstance(source_id, SourceId) \
            else source_id
        self.visibility = RayVisibility(visibility)
        if radiance is None:
            self.radiance = None
        else:
            rad = as_finite_array(radiance, "radiance")
            self.radiance = np.broadcast_to(rad, (len(self.triangles), 3)).astype(float)
        cross = np.cross(self.triangles[:, 1] - self.triangles[:, 0], self.triangles[:, 2] - self.triangles[:, 0])
        length = np.linalg.norm(cross, axis=1)
        self.areas_m2 = 0.5 * length
        self.normals = np.divide(cross, length[:, None], out=np.zeros_like(cross), where=length[:, None] > 0)

    @property
    def flags(self):
        return EmitterFlags.AREA | EmitterFlags.RENDERED_ONLY

    def extent(self):
        return self.triangles.reshape(-1, 3), 0.0

    @property
    def area_m2(self):
        """Total area of the emitting triangles, m^2 (one side)."""
        return float(self.areas_m2.sum())

    def _radiance(self):
        return self.radiance if self.radiance is not None else np.full((len(self.triangles), 3), np.nan)

    def power_w(self):
        return 2.0 * np.pi * (self.areas_m2 @ self._radiance())

    def intensity_towards(self, directions):
        d = np.asarray(as_finite_array(directions, "direction"), float)
        d = d / np.linalg.norm(d, axis=-1, keepdims=True)
        cos = np.abs(d @ self.normals.T)                                   # (..., T): both sides emit
        return (cos * self.areas_m2) @ self._radiance()

    def irradiance_at(self, points, normals):
        p, n, lead = prepare_receivers(points, normals)
        e = np.zeros((len(p), 3))
        radiance = self._radiance()
        for t, tri in enumerate(self.triangles):
            if self.areas_m2[t] == 0.0:
                continue
            # Both sides emit the same radiance: whichever the receiver sees (either winding works).
            e += polygon_projected_solid_angle(tri, p, n)[:, None] * radiance[t]
        return e.reshape(lead + (3,)), None

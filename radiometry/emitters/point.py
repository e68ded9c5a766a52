"""Point light (Cycles ``kernel/light/point.h``): radius 0, or a sphere / receiver-facing disk.

* radius 0: radiant intensity I = P/(4 pi) (``eval_fac = 1/(pi * 4)``), E = I cos / r^2; a delta
  position (infinite at its own position: ValueError there).
* radius R, soft falloff OFF: Lambertian sphere of radiance P/(4 pi^2 R^2) (a receiver inside it
  sees E = pi L).
* radius R, soft falloff ON: a disk of radius R always facing the receiver, same radiance, so
  E = P cos / (4 pi (R^2 + r^2)) above the horizon (Snyder's cap under the horizon).

Power: P per channel in every case (I = P/(4 pi) in every direction). Spots (:mod:`.spot`) share
these models and multiply by their cone.
"""

import math
from dataclasses import dataclass

import numpy as np

from ..scene.geometry import cap_projected_solid_angle, norm, unit
from ..scene.visibility import circumscribed_polygon
from .base import EmitterFlags
from .cycles_light import CyclesLight

__all__ = ["PointLight", "delta_irradiance"]


def delta_irradiance(position, p, n, what="a point/spot of radius 0"):
    """(g (N,), unit vectors receiver -> light (N, 3), r (N,)): cos / r^2 from a delta position, m^-2.
    ValueError at zero distance."""
    to_light = position - p
    r = norm(to_light)
    if np.any(r == 0.0):
        raise ValueError(f"zero distance to light: {what} has infinite irradiance at its position")
    w = to_light / r[:, None]
    cos_r = np.maximum(np.sum(w * n, axis=1), 0.0)
    return cos_r / r / r, w, r


@dataclass(frozen=True)
class PointLight(CyclesLight, kind_key=("POINT", False)):
    """A point light (see the module docstring); a spot is a point light with a cone."""

    @property
    def flags(self):
        return EmitterFlags.DELTA_POSITION if self.radius == 0.0 else EmitterFlags.AREA

    def power_w(self):
        return np.array(self.rgb_power, dtype=np.float64)

    def _cone(self, directions):
        """Cone factor for world directions leaving the light (1 for a point light)."""
        return np.ones(np.shape(directions)[:-1])

    def _unit_intensity(self, d):
        return np.full(d.shape[:-1], 1.0 / (4.0 * np.pi)) * self._cone(d)

    def _cap(self, w, sin_sq, n):
        """(int over the cap of half-angle asin(sqrt(sin_sq)) about w of cone(-omega) max(n.omega, 0)
        d omega, relative bound): Snyder's closed form for a point light."""
        return cap_projected_solid_angle(np.sum(w * n, axis=1), sin_sq), np.zeros(len(w))

    def _unit_irradiance(self, p, n):
        if self.radius == 0.0:
            g, w, _r = delta_irradiance(self.position, p, n)
            g = g / (4.0 * np.pi) * self._cone(-w)
            return g, np.zeros_like(g)
        to_light = self.position - p
        d = norm(to_light)
        if np.any(d == 0.0) and self.soft_falloff:
            raise ValueError("zero distance to light: receiver at the centre of a soft-falloff light")
        w = unit(to_light)
        big_r = self.radius
        radiance = 1.0 / (4.0 * np.pi**2 * big_r**2)
        if self.soft_falloff:
            sin_sq = big_r**2 / (big_r**2 + d**2)
            inside = np.zeros(d.shape, dtype=bool)
        else:
            inside = d <= big_r
            sin_sq = np.where(inside, 1.0, (big_r / np.maximum(d, big_r)) ** 2)
        g = np.zeros(d.shape)
        bound = np.zeros(d.shape)
        todo = ~inside
        if np.any(todo):
            q, b = self._cap(w[todo], sin_sq[todo], n[todo])
            g[todo], bound[todo] = radiance * q, b
        # Inside a sphere (soft falloff off) Cycles samples the receiver's hemisphere and applies no
        # spot attenuation (kernel/light/spot.h: attenuation only when d^2 > r^2): E = pi L.
        return np.where(inside, radiance * np.pi, g), bound

    # What callers ask (see CyclesLight) ----------------------------------------------------------
    @property
    def size_m(self):
        return 2.0 * self.radius

    def describe(self):
        if self.radius > 0:
            return (f"{self.kind.lower()} light, radius {self.radius:.2g} m"
                    + (", soft falloff" if self.soft_falloff else ""))
        return CyclesLight.describe(self)

    @property
    def interior_radius_m(self):
        return 0.0 if self.soft_falloff else self.radius

    @property
    def _reach(self):
        return self.radius

    def angular_radius(self, point_m, facing):
        if self.radius > 0:
            dist = float(np.linalg.norm(np.asarray(self.position) - point_m))
            # soft falloff: a disk of radius R facing the receiver; otherwise a sphere of radius R
            return float(math.atan2(self.radius, dist) if self.soft_falloff else math.asin(min(1.0, self.radius / dist)))
        return 0.0

    def occlusion_bases(self, points, scene_reach, sides):
        if self.radius == 0.0:
            return super().occlusion_bases(points, scene_reach, sides)
        n = len(points)
        axis = self.position - points
        d = np.linalg.norm(axis, axis=1)
        r = self.radius
        inside = d <= r * (1 + 1e-9)
        bases = np.zeros((n, sides, 3))
        for k in np.flatnonzero(~inside):
            # The cone from p tangent to the sphere, cut by the plane touching the sphere's far side,
            # holds the sphere and so every segment from p to it.
            tan_a = r / np.sqrt(d[k] ** 2 - r * r)
            bases[k] = circumscribed_polygon(points[k] + axis[k] / d[k] * (d[k] + r), axis[k], (d[k] + r) * tan_a,
                                             sides)
        return "polytope", bases, inside

    def mirror_cone(self, p, normal, plane_point, tol):
        radius = float(self.radius)
        hl = float(normal @ (np.asarray(self.position, float) - plane_point))
        if hl < -(radius + tol):
            return "far"
        if hl <= radius + tol:
            return None  # the light straddles its plane
        d = np.asarray(self.position, float) - 2.0 * hl * normal - p
        dist = float(np.linalg.norm(d))
        r, half = d / dist, float(np.arcsin(min(1.0, radius / dist)))
        return r, half, float(-(r @ normal))

    def mirror_image_solid_angle(self, at, path_length):
        if self.radius > 0.0:
            return math.pi * float(self.radius) ** 2 / path_length ** 2
        return 0.0

    def near_field_words(self):
        if self.soft_falloff:
            return "Blender's soft falloff on a sphere light"
        return CyclesLight.near_field_words(self)

    def inverse_square_causes(self, d):
        if not (self.radius > 0 and self.soft_falloff):
            return []
        r = self.radius
        return [f"light: Blender's soft falloff on a {self.kind.lower()} light with radius {r:.3g} m: Cycles "
                f"renders E = I/(R² + d²), a deviation of -R²/(R² + d²) (-{100 * r * r / (r * r + d[0] ** 2):.3g} "
                f"% at {d[0]:.3g} m; under 1 % beyond {math.sqrt(99) * r:.3g} m); turn Soft Falloff off for an "
                "inverse-square sphere"]

    def exactness(self):
        if self.radius == 0.0:
            return True, "point", "inverse square law, exact" + self._sign_note()
        model = "disk facing receiver" if self.soft_falloff else "Lambertian sphere"
        return True, model, "closed-form cap projected solid angle, exact" + self._sign_note()

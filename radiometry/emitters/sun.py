"""Sun light (Cycles ``kernel/light/distant.h``): a uniform cone of directions at infinity.

``rgb_power`` is the irradiance (W/m^2 per channel) on a surface facing the sun; ``angle`` is the
full angular diameter of the disc. Angle 0: E = E_n max(cos theta, 0) (a delta direction); angle > 0:
a uniform cap of half-angle angle/2, E = E_n x (projected solid angle of the cap, Snyder 1996 under the
horizon) / (pi sin^2(angle/2)). No position: no intensity, no finite power (``inf``).
"""

import math
from dataclasses import dataclass

import numpy as np

from ..scene.geometry import cap_projected_solid_angle
from ..scene.visibility import circumscribed_polygon
from .base import EmitterFlags
from .cycles_light import CyclesLight

__all__ = ["SunLight"]


@dataclass(frozen=True)
class SunLight(CyclesLight, kind_key=("SUN", False)):
    """A sun (see the module docstring)."""

    @property
    def flags(self):
        return EmitterFlags.INFINITE | (EmitterFlags.DELTA_DIRECTION if self.angle == 0.0 else EmitterFlags.NONE)

    def power_w(self):
        return np.full(3, np.inf)

    @property
    def normal_irradiance(self):
        """(3,) W/m^2 per channel on a surface facing the sun."""
        return np.array(self.rgb_power, dtype=np.float64)

    def _unit_irradiance(self, p, n):
        to_sun = -self.emission_direction
        cos_t = n @ to_sun
        half = 0.5 * self.angle
        if half == 0.0:
            g = np.maximum(cos_t, 0.0)
        else:
            sin_sq = np.sin(half) ** 2
            g = cap_projected_solid_angle(cos_t, np.full_like(cos_t, sin_sq)) / (np.pi * sin_sq)
        return g, np.zeros_like(g)

    def _unit_intensity(self, d):
        raise ValueError("a sun has no position: inverse-square does not apply")

    # What callers ask (see CyclesLight) ----------------------------------------------------------
    def towards_centre(self, p):
        return self.axes[:, 2]

    def angular_radius(self, point_m, facing):
        return 0.5 * self.angle

    def occlusion_bases(self, points, scene_reach, sides):
        inside = np.zeros(len(points), bool)
        to_sun = self.axes[:, 2]
        far = points + to_sun * scene_reach
        half = 0.5 * self.angle
        if half == 0.0:
            return "segment", far, inside
        ring = circumscribed_polygon(np.zeros(3), to_sun, scene_reach * np.tan(min(half, 1.5)), sides)
        return "polytope", far[:, None, :] + ring[None, :, :], inside

    def beyond_plane(self, normal, height, side, tol):
        towards = -self.emission_direction
        return bool(side * (normal @ towards) < -np.sin(0.5 * self.angle) - 1e-12)

    def mirror_cone(self, p, normal, plane_point, tol):
        s = np.asarray(self.axes[:, 2], float)
        half = 0.5 * float(self.angle)
        c = float(s @ normal)
        if c < -np.sin(half) - 1e-12:
            return "far"  # the sun lights only its far side
        return s - 2.0 * c * normal, half, c

    def mirror_image_solid_angle(self, at, path_length):
        return math.pi * (0.5 * float(self.angle)) ** 2

    def _seen_from(self, d, dist, eye, efficacy, weights, sides):
        return None, "a sun: daylight glare is not rated by UGR (CIE 117 is for luminaires)"

    def exactness(self):
        if self.angle == 0.0:
            return True, "directional", "E = energy cos(theta), exact" + self._sign_note()
        return True, "uniform cap", "Snyder 1996 cap under the horizon, exact" + self._sign_note()

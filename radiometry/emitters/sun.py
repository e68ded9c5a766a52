"""Sun light (Cycles ``kernel/light/distant.h``): a uniform cone of directions at infinity.

``rgb_power`` is the irradiance (W/m^2 per channel) on a surface facing the sun; ``angle`` is the
full angular diameter of the disc. Angle 0: E = E_n max(cos theta, 0) (a delta direction); angle > 0:
a uniform cap of half-angle angle/2, E = E_n x (projected solid angle of the cap, Snyder 1996 under the
horizon) / (pi sin^2(angle/2)). No position: no intensity, no finite power (``inf``).
"""

from dataclasses import dataclass

import numpy as np

from ..scene.geometry import cap_projected_solid_angle
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

    def exactness(self):
        if self.angle == 0.0:
            return True, "directional", "E = energy cos(theta), exact" + self._sign_note()
        return True, "uniform cap", "Snyder 1996 cap under the horizon, exact" + self._sign_note()

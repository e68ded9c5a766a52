"""Homogeneous participating media: what a medium takes from the direct light (issue 18). Pure numpy.

A homogeneous medium of extinction coefficient sigma_t (1/m, per RGB channel) passes the fraction
T = exp(-sigma_t d) of the light along a straight segment of length d (Beer-Lambert). For a delta
light (a point or spot of radius 0) the direct light reaching a receiver is its closed form times
T(d), d the receiver-light distance, and nothing else: the light the medium scatters towards the
receiver (in-scattering) is a separate contribution that the meter renders. The reading is then
not exact (it holds a rendered part), but its direct part is a closed form.

Cycles' volume closures (kernel ``svm/closure.h``, ``svm_node_closure_volume``): Volume Scatter has
sigma_t = sigma_s = density x colour; Volume Absorption has sigma_t = sigma_a = density x (1 - colour).
Densities are per scene unit of length (Cycles ignores the unit scale): sigma_t (1/m) = density / scale.
"""

from dataclasses import dataclass

import numpy as np

#: Volume nodes whose extinction this module models, and how colour enters sigma_t.
KINDS = ("scatter", "absorption")


@dataclass(frozen=True)
class HomogeneousMedium:
    """A medium filling all space (a world volume) with constant extinction.

    Attributes
    ----------
    name : str
        What it is, for notes ("the world's volume (Volume Scatter)").
    sigma_t : tuple of 3 float
        Extinction coefficient per RGB channel, 1/m.
    """

    name: str
    sigma_t: tuple

    def transmittance(self, distance_m):
        """exp(-sigma_t d), shape (..., 3), for distances (...,) in m (dimensionless)."""
        d = np.asarray(distance_m, dtype=float)
        if np.any(d < 0) or not np.all(np.isfinite(d)):
            raise ValueError("distances through a medium must be finite and >= 0")
        return np.exp(-d[..., None] * np.asarray(self.sigma_t, float))


def extinction(kind, density, colour, scale_length=1.0):
    """sigma_t (3,) in 1/m of a Cycles volume node: ``kind`` in KINDS, ``density`` per scene unit,
    ``colour`` (3,) linear RGB, ``scale_length`` metres per scene unit."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
    c = np.clip(np.asarray(colour, float)[:3], 0.0, None)
    weight = c if kind == "scatter" else 1.0 - c
    sigma = max(float(density), 0.0) * weight / float(scale_length)
    return tuple(float(v) for v in sigma)

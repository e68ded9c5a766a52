"""Homogeneous media (issue 18): Beer-Lambert attenuation and Cycles' volume extinction (no bpy).
References: T = exp(-sigma_t d) (Beer-Lambert); sigma_t of Cycles' Volume Scatter = density x colour and of
Volume Absorption = density x (1 - colour) (kernel svm/closure.h, svm_node_closure_volume)."""

import math

import numpy as np
import pytest

from radiometer.radiometry.scene import media


def test_extinction_of_cycles_volume_nodes():
    assert media.extinction("scatter", 0.05, (0.8, 0.8, 0.8)) == pytest.approx((0.04,) * 3)
    assert media.extinction("absorption", 0.5, (1.0, 0.5, 0.0)) == pytest.approx((0.0, 0.25, 0.5))
    # densities are per scene unit: a scene in centimetres (0.01 m per unit) has 100x the 1/m
    assert media.extinction("scatter", 0.05, (1, 1, 1), scale_length=0.01) == pytest.approx((5.0,) * 3)
    assert media.extinction("scatter", -1.0, (1, 1, 1)) == (0.0, 0.0, 0.0)  # Cycles clamps density at 0
    with pytest.raises(ValueError):
        media.extinction("emission", 1.0, (1, 1, 1))


def test_beer_lambert_transmittance():
    fog = media.HomogeneousMedium("fog", (0.04, 0.1, 0.0))
    t = fog.transmittance(np.array([0.0, 2.0, 10.0]))
    assert t.shape == (3, 3)
    assert np.allclose(t[0], 1.0)
    assert t[1] == pytest.approx([math.exp(-0.08), math.exp(-0.2), 1.0], rel=1e-12)
    # two segments in a row pass the product of their fractions
    assert np.allclose(fog.transmittance(np.array([4.0]))[0] * fog.transmittance(np.array([6.0]))[0], t[2])
    with pytest.raises(ValueError):
        fog.transmittance(np.array([-1.0]))

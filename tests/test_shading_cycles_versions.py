"""Blender 4.x Cycles renders the Metallic BSDF's physical-conductor Fresnel with PBRT-v2's
approximation: a mapping that is exact on 5.x must be reported as approximate there."""

import numpy as np
import pytest

from radiometer.shading import closures, realise


@pytest.fixture
def cycles_4_5():
    closures.use_cycles_version((4, 5, 15))
    try:
        yield
    finally:
        closures.use_cycles_version((5, 0, 1))


def test_approximation_is_exact_at_normal_incidence_only():
    eta, k = np.array([1.5, 0.2, 2.0]), np.array([0.0, 3.0, 1.0])
    exact = closures.fresnel_conductor(1.0, eta, k)
    approx = closures.fresnel_conductor_approximate(1.0, eta, k)
    # Normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2) for both (Born & Wolf).
    assert np.allclose(approx, ((eta - 1) ** 2 + k ** 2) / ((eta + 1) ** 2 + k ** 2), rtol=1e-12)
    assert np.allclose(exact, approx, rtol=1e-12)
    # Away from normal incidence it is not exact: for a dielectric (k = 0) it misses the Brewster
    # dip of the parallel polarisation, 52 % off near cos = 0.47.
    c = np.linspace(1e-3, 1.0, 2000)
    ratio = closures.fresnel_conductor_approximate(c, 1.5, 0.0)[:, 0] / closures.fresnel_conductor(c, 1.5, 0.0)[:, 0]
    assert np.max(np.abs(ratio - 1)) > 0.4


def test_dielectric_ior_mapping_is_exact_on_5_and_approximate_on_4(cycles_4_5):
    _terms, fid4 = realise.realise("ggx", "nodes", alpha=0.3, ior=1.5)
    assert fid4.kind == "approximate" and fid4.rms_rel_diff > 1e-3
    closures.use_cycles_version((5, 0, 1))
    _terms, fid5 = realise.realise("ggx", "nodes", alpha=0.3, ior=1.5)
    assert fid5.kind == "exact"

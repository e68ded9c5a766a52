"""radiometer.brdf.special.erfc (numpy only) against the C library's erfc and scipy.special.erfc.

Reference values: ``math.erfc`` (the C library: glibc's erfc is accurate to < 1 ulp) and
``scipy.special.erfc`` (Cephes ndtr.c, whose documentation states a peak relative error of 5.7e-14
on [0, 26.6] in IEEE double: the bound used below for the comparison with scipy).
"""

import math

import numpy as np
import pytest

from radiometer.brdf import microfacet
from radiometer.brdf.special import erfc

scipy_special = pytest.importorskip("scipy.special")

_TINY = np.finfo(float).tiny  # below this, results are subnormal: only absolute errors make sense
_X = np.linspace(-10.0, 30.0, 80001)


def test_erfc_matches_c_library_to_about_one_ulp():
    ours = erfc(_X)
    libm = np.array([math.erfc(v) for v in _X])
    normal = libm >= _TINY
    rel = np.abs(ours[normal] - libm[normal]) / libm[normal]
    assert np.max(rel[_X[normal] <= 10.0]) < 8e-16, np.max(rel[_X[normal] <= 10.0])
    assert np.max(rel) < 1.5e-15, np.max(rel)
    # subnormal results (x > 26.55) and the underflow to 0 (x > 27.23): a few units of 5e-324
    assert np.max(np.abs(ours[~normal] - libm[~normal])) <= 1e-322


def test_erfc_matches_scipy_within_scipys_stated_error():
    ours = erfc(_X)
    ref = scipy_special.erfc(_X)
    normal = ref >= _TINY
    rel = np.abs(ours[normal] - ref[normal]) / ref[normal]
    assert np.max(rel) < 5.8e-14, np.max(rel)  # Cephes: peak 5.7e-14 (its own error dominates)
    assert np.max(rel[_X[normal] <= 3.0]) < 2e-15
    assert np.max(np.abs(ours[~normal] - ref[~normal])) < _TINY


def test_erfc_special_values_and_shapes():
    out = erfc(np.array([np.nan, np.inf, -np.inf, 0.0, -0.0, 27.3, 1e300, -1e300]))
    assert np.isnan(out[0])
    assert out[1:].tolist() == [0.0, 2.0, 1.0, 1.0, 0.0, 0.0, 2.0]
    x = np.random.default_rng(3).normal(scale=4.0, size=(2, 3, 4, 5))
    y = erfc(x)
    assert y.shape == x.shape
    np.testing.assert_allclose(y, scipy_special.erfc(x), rtol=6e-14, atol=0)
    assert np.ndim(erfc(0.5)) == 0 and float(erfc(0.5)) == pytest.approx(math.erfc(0.5), rel=1e-16)
    # symmetry erfc(-x) = 2 - erfc(x) holds to rounding of the sum
    np.testing.assert_allclose(erfc(-np.abs(x)), 2.0 - erfc(np.abs(x)), rtol=2e-16, atol=0)


def test_beckmann_lambda_matches_the_scipy_erfc_version():
    # Smith Lambda for Beckmann (Walter et al. 2007 eq. 27) = (exp(-a^2)/(a sqrt(pi)) - erfc(a)) / 2,
    # recomputed with scipy's erfc. Lambda is a difference of two nearly equal terms for large a, so
    # the bound is relative to the larger term (scipy's 5.7e-14 erfc error, amplified by nothing else).
    theta = np.linspace(1e-3, np.pi / 2 - 1e-3, 400)
    w = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
    ours = microfacet.beckmann_lambda(w, 0.3, 0.3)
    a = 1.0 / (0.3 * np.tan(theta))
    first = np.exp(-a * a) / (a * math.sqrt(math.pi))
    ref = np.maximum(0.5 * (first - scipy_special.erfc(a)), 0.0)
    # (+ the smallest normal double: for a > 26.5 both terms are subnormal, Lambda < 1e-308)
    assert np.all(np.abs(ours - ref) <= 6e-14 * first + _TINY)
    assert ours[0] == 0.0 and ours[-1] > 1.0  # normal: no masking; grazing: strong masking

"""Numpy models of Cycles closures (radiometer.shading.closures) and node parameter conversions.

Reference values: closed forms named in each test. The models themselves are checked against
Cycles renders in tests/bpy/test_shading_validate.py.
"""

import math

import numpy as np
import pytest

from radiometer.shading import closures as C
from radiometer.shading import fit as F
from radiometer.shading import nodes as N


def _dir(theta, phi):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


def _albedo(fn, theta_i):
    return F.directional_albedo(fn, (math.degrees(theta_i),))[0]


def test_lambert_albedo_is_one():
    # closed form: integral of (1/pi) cos over the hemisphere = 1
    assert np.allclose(_albedo(C.lambert, 0.3), 1.0, atol=1e-6)


@pytest.mark.parametrize("n", [1.0, 10.0, 50.0])
def test_phong_ramp_is_normalised_at_normal_incidence(n):
    # closed form: (n + 2)/(2 pi) * integral cos^n(theta) cos(theta) d omega = 1 for wi = normal
    a = _albedo(lambda wi, wo: C.phong_ramp(wi, wo, n), 0.0)
    assert np.allclose(a, 1.0, atol=2e-3)


@pytest.mark.parametrize("dist", ["ggx", "beckmann"])
@pytest.mark.parametrize("alpha", [(0.3, 0.3), (0.2, 0.5)])
def test_ndf_projected_area_is_one(dist, alpha):
    # closed form: integral D(h) cos(theta_h) d omega_h = 1 (Walter et al. 2007, eq. 4)
    wo, weight = F._quadrature(256, 256)  # weight includes cos(theta) d omega
    d = C._ndf(dist, alpha[0], alpha[1], wo)
    assert abs(np.sum(d * weight) - 1.0) < 2e-3


@pytest.mark.parametrize("dist", ["ggx", "beckmann"])
def test_microfacet_reciprocity_and_energy(dist):
    rng = np.random.default_rng(1)
    th = rng.uniform(0.05, 1.4, size=(50, 2))
    ph = rng.uniform(0, 2 * np.pi, size=(50, 2))
    wi = np.array([_dir(t, p) for t, p in zip(th[:, 0], ph[:, 0])])
    wo = np.array([_dir(t, p) for t, p in zip(th[:, 1], ph[:, 1])])
    f1 = C.microfacet(wi, wo, 0.2, 0.4, dist, "schlick", (0.9, 0.5, 0.1))
    f2 = C.microfacet(wo, wi, 0.2, 0.4, dist, "schlick", (0.9, 0.5, 0.1))
    assert np.allclose(f1, f2, rtol=1e-10)
    # F = 1 single scattering conserves energy (albedo < 1) and loses more as alpha grows
    a1 = _albedo(lambda x, y: C.microfacet(x, y, 0.1, 0.1, dist), 0.5)
    a3 = _albedo(lambda x, y: C.microfacet(x, y, 0.3, 0.3, dist), 0.5)
    assert np.all(a3 < a1) and np.all(a1 < 1.0 + 1e-9) and np.all(a3 > 0.8)


def test_fresnel_closed_forms():
    # Schlick: F(1) = f0, F(0) = 1; conductor with k = 0: ((n-1)/(n+1))^2 at normal incidence (Hecht)
    assert np.allclose(C.fresnel_schlick(1.0, (0.04, 0.5, 0.9)), (0.04, 0.5, 0.9))
    assert np.allclose(C.fresnel_schlick(0.0, 0.04), 1.0)
    assert np.allclose(C.fresnel_conductor(1.0, 1.5, 0.0), 0.04)
    # gold-like conductor at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2)
    n, k = 0.2, 3.0
    assert np.allclose(C.fresnel_conductor(1.0, n, k), ((n - 1) ** 2 + k * k) / ((n + 1) ** 2 + k * k))


def test_oren_nayar_zero_roughness_is_lambert_and_albedo_bounded():
    wi, wo = _dir(0.5, 0.0), _dir(0.7, 2.0)
    assert np.allclose(C.oren_nayar(wi, wo, 0.0, 0.5), 0.5 / np.pi)
    # the EON model is energy preserving: white albedo stays within 1 (Portsmouth et al. 2024)
    a = _albedo(lambda x, y: C.oren_nayar(x, y, 1.0, 1.0), 0.6)
    assert np.all(a < 1.0 + 1e-3) and np.all(a > 0.9)


def test_ashikhmin_shirley_isotropic_matches_formula():
    # Ashikhmin & Shirley (2000) eq. 4 with F = 1, n = 2/alpha^2 - 2
    alpha = 0.3
    n = 2 / alpha ** 2 - 2
    wi, wo = _dir(0.4, 0.0), _dir(0.6, 2.5)
    h = (wi + wo) / np.linalg.norm(wi + wo)
    expected = (n + 1) / (8 * np.pi) * h[2] ** n / (np.dot(h, wi) * max(wi[2], wo[2]))
    assert np.allclose(C.ashikhmin_shirley(wi, wo, alpha, alpha), expected, rtol=1e-10)


def test_shapes_and_nonfinite_inputs():
    for shape in [(3,), (6, 3), (2, 3, 3)]:
        wi = np.broadcast_to(_dir(0.3, 0.0), shape)
        wo = np.broadcast_to(_dir(0.5, 3.0), shape)
        f = C.evaluate_terms([C.Term("diffuse", color=(0.5, 0.5, 0.5)),
                              C.Term("microfacet", alpha_x=0.2, alpha_y=0.2, fresnel="schlick", f0=0.04)], wi, wo)
        assert f.shape == shape
        assert np.allclose(f.reshape(-1, 3), f.reshape(-1, 3)[0])
    bad = np.array([[np.nan, 0, 1], [0, 0, np.inf], [0, 0, -1], [0, 0, 1]])
    with np.errstate(invalid="ignore"):
        f = C.microfacet(bad, np.array([0, 0, 1.0]), 0.3, 0.3)
    assert f.shape == (4, 3)
    assert np.all(f[2] == 0)  # below the surface: zero


@pytest.mark.parametrize("ax,ay", [(0.1, 0.4), (0.4, 0.1), (0.2, 0.2), (0.05, 0.9)])
def test_node_anisotropy_conversions_round_trip(ax, ay):
    # Cycles svm/closure.h formulas, inverted in shading.nodes
    r, a = N.glossy_roughness_anisotropy(ax, ay)
    alpha = r * r
    bx, by = (alpha * (1 - a), alpha / (1 - a)) if a > 0 else (alpha / (1 + a), alpha * (1 + a))
    assert np.allclose((bx, by), (ax, ay), rtol=1e-9)
    if max(ax, ay) / min(ax, ay) <= 10:
        r, a, rot = N.metallic_roughness_anisotropy_rotation(ax, ay)
        aspect = math.sqrt(1 - 0.9 * a)
        hi, lo = r * r / aspect, r * r * aspect
        assert np.allclose((hi, lo) if rot == 0 else (lo, hi), (ax, ay), rtol=1e-9)


@pytest.mark.parametrize("ax,ay", [(0.1, 0.4), (0.4, 0.1), (0.2, 0.2), (0.05, 0.3)])
def test_law_node_controls_round_trip(ax, ay):
    # the group's Math nodes (shading.laws, NumpyOps replica) invert Cycles' svm/closure.h formulas
    from radiometer.shading import laws as L

    r, a = (float(v) for v in L.glossy_controls(L.NumpyOps, ax, ay))
    assert np.allclose(L.cycles_alphas_glossy(r, a), (ax, ay), rtol=1e-9)
    r, a, rot = (float(v) for v in L.metallic_controls(L.NumpyOps, ax, ay))
    assert np.allclose(L.cycles_alphas_metallic(r, a, rot), (ax, ay), rtol=1e-9)

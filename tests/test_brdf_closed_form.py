"""BRDF values against closed forms and independent published numbers."""

import math

import numpy as np
import pytest
from scipy import integrate

import radiometer.brdf as brdf
from radiometer.brdf import fresnel, microfacet as mf
from radiometer.brdf.models import blinn_phong_normalization


def test_lambert_value():
    # Closed form (Hanrahan CS348B lecture 10): f = ρ/π.
    f = brdf.evaluate("lambert", [0.2, 0.3, 0.9], [-0.5, 0.1, 0.4], albedo=(0.5, 0.25, 1.0))
    np.testing.assert_allclose(f, np.array([0.5, 0.25, 1.0]) / math.pi, rtol=1e-14)


@pytest.mark.parametrize("n", [1.33, 1.5, 2.4])
def test_fresnel_dielectric_normal_incidence(n):
    # Born & Wolf: R(0) = ((n-1)/(n+1))²; Schlick is exact at θ = 0 by construction.
    r0 = ((n - 1) / (n + 1)) ** 2
    assert fresnel.dielectric(1.0, n) == pytest.approx(r0, rel=1e-12)
    assert fresnel.schlick(r0, 1.0) == pytest.approx(fresnel.dielectric(1.0, n), rel=1e-12)


def test_fresnel_brewster_and_grazing():
    # At Brewster's angle tan θB = n, R_p = 0 and R_s = sin²(θi - θt) (Born & Wolf §1.5.3).
    n = 1.5
    ti = math.atan(n)
    tt = math.asin(math.sin(ti) / n)
    assert fresnel.dielectric(math.cos(ti), n) == pytest.approx(0.5 * math.sin(ti - tt) ** 2, rel=1e-12)
    assert fresnel.dielectric(0.0, n) == 1.0
    # Total internal reflection from inside glass beyond the critical angle.
    assert fresnel.dielectric(math.cos(math.radians(45)), 1 / 1.5) == 1.0


def test_fresnel_conductor():
    eta, k = np.array([0.2, 1.1, 1.5]), np.array([3.9, 2.4, 0.0])
    # Normal incidence closed form ((n-1)² + k²)/((n+1)² + k²) (Born & Wolf §14.2).
    np.testing.assert_allclose(fresnel.conductor(1.0, eta, k), ((eta - 1) ** 2 + k ** 2) / ((eta + 1) ** 2 + k ** 2), rtol=1e-12)
    # k = 0 reduces to the exact dielectric formula at every angle.
    c = np.linspace(0, 1, 11)
    np.testing.assert_allclose(fresnel.conductor(c, 1.5, 0.0), fresnel.dielectric(c, 1.5), rtol=1e-12, atol=1e-15)


def test_fresnel_presets_match_lecture():
    assert fresnel.PRESETS["gold"]["f0"] == 0.82 and fresnel.PRESETS["silver"]["f0"] == 0.95
    assert fresnel.f0_from_ior(fresnel.PRESETS["glass"]["ior"]) == pytest.approx(fresnel.PRESETS["glass"]["f0"], abs=1e-12)
    # The slide's diamond value 0.15 is a rounding of the exact 0.1696 for n = 2.4.
    assert fresnel.f0_from_ior(2.4) == pytest.approx(0.1696, abs=1e-4)


@pytest.mark.parametrize("dist", ["ggx", "beckmann"])
@pytest.mark.parametrize("ax,ay", [(0.05, 0.05), (0.3, 0.3), (1.0, 1.0), (0.1, 0.6)])
def test_D_projected_area_is_one(dist, ax, ay):
    # ∫ D(m) cos θm dωm = 1 (Walter 2007 eq. 4), by adaptive quadrature in (φ, θ).
    def integrand(theta, phi):
        m = np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])
        return float(mf.D(dist, m, ax, ay)) * math.cos(theta) * math.sin(theta)
    a = min(ax, ay)
    # Split θ at a few lobe widths so quad sees the peak.
    total = 0.0
    edges = [0.0, math.atan(a), math.atan(4 * a), math.atan(20 * a), math.pi / 2]
    for lo, hi in zip(edges[:-1], edges[1:]):
        total += integrate.dblquad(integrand, 0, 2 * math.pi, lo, hi, epsabs=1e-10, epsrel=1e-9)[0]
    assert total == pytest.approx(1.0, abs=2e-6)


@pytest.mark.parametrize("dist", ["ggx", "beckmann"])
@pytest.mark.parametrize("theta_o", [0.3, 1.0, 1.45])
def test_smith_lambda_matches_projected_area(dist, theta_o):
    # Smith's Λ is defined by ∫ max(0, wo·m) D(m) dωm = cos θo (1 + Λ(wo)) (Heitz 2014 eq. 17);
    # this checks the closed-form Λ of both distributions against direct integration of D.
    alpha = 0.4
    wo = np.array([math.sin(theta_o), 0.0, math.cos(theta_o)])

    def integrand(theta, phi):
        m = np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])
        return max(0.0, float(wo @ m)) * float(mf.D(dist, m, alpha, alpha)) * math.sin(theta)
    total = integrate.dblquad(integrand, 0, 2 * math.pi, 0, math.pi / 2, epsabs=1e-10, epsrel=1e-9)[0]
    lam = float(mf.smith_lambda(dist, wo, alpha, alpha))
    assert total == pytest.approx(math.cos(theta_o) * (1 + lam), rel=1e-6)


def _mirror_pair_45():
    t = math.pi / 4
    return np.array([math.sin(t), 0, math.cos(t)]), np.array([-math.sin(t), 0, math.cos(t)])


def test_ggx_mitsuba_separable_reference():
    # Mitsuba 3 roughconductor (GGX, alpha 0.3, separable Smith G, F = 1) at θi = θo = 45° in the
    # mirror configuration gives f·cos θi = 1.19715 [1/sr] (number supplied with the brief). The
    # same quantity from our building blocks with the SEPARABLE G must reproduce it; this pins the
    # quantity as f·cos θi, not f.
    wi, wo = _mirror_pair_45()
    h = np.array([0.0, 0.0, 1.0])
    f = mf.ggx_D(h, 0.3, 0.3) * mf.G_separable("ggx", wi, wo, 0.3, 0.3) / (4 * wi[2] * wo[2])
    assert float(f * wi[2]) == pytest.approx(1.19715, abs=5e-6)


def test_ggx_height_correlated_closed_form():
    # Same configuration with the height-correlated G (what `ggx` uses, as Cycles): h = n, so
    # D = 1/(π α²), Λ(45°) = (sqrt(1 + α²) - 1)/2, f = D / (1 + 2Λ) / (4 cos² 45°) = 1.693809 1/sr,
    # f·cos θi = 1.197704. (The project's Cycles number 4.7655 is reproduced by neither f nor f·cos:
    # it is 3.98 f·cos, see the brdf report.)
    a = 0.3
    lam = (math.sqrt(1 + a * a) - 1) / 2
    expected = 1 / (math.pi * a * a) / (1 + 2 * lam) / 2.0
    wi, wo = _mirror_pair_45()
    f = brdf.evaluate("ggx", wi, wo, alpha=a)
    np.testing.assert_allclose(f, expected, rtol=1e-12)
    assert expected * math.cos(math.pi / 4) == pytest.approx(1.197704, abs=1e-6)


def test_phong_albedo_normal_incidence():
    # Lafortune & Willems 1994: at normal incidence the lobe integrates to exactly ks, so ρ = kd + ks.
    for n in (0.0, 5.0, 100.0, 1e4):
        a = brdf.albedo("phong", 0.0, kd=0.25, ks=(0.7, 0.5, 0.1), n=n)
        np.testing.assert_allclose(a, [0.95, 0.75, 0.35], atol=2e-4)


def test_blinn_phong_exact_normalization():
    # Giesen 2009: c(n) = (n+2)(n+4)/(8π(2^(-n/2)+n)) makes the lobe albedo at normal incidence 1.
    for n in (0.0, 1.0, 10.0, 1000.0):
        a = brdf.albedo("blinn_phong", 0.0, kd=0.0, ks=1.0, n=n)
        np.testing.assert_allclose(a, 1.0, atol=2e-4)
    assert blinn_phong_normalization(0.0) == pytest.approx(1 / math.pi)  # n = 0 is Lambert


def test_oren_nayar_classic_closed_forms():
    # Oren & Nayar 1994 eq. 30: at normal incidence the B term vanishes, ρ_dir = ρ A;
    # in the retro-reflection direction θi = θo = θ, Δφ = 0: f = ρ/π (A + B sin θ tan θ).
    s2 = 0.5 ** 2
    A, B = 1 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)
    np.testing.assert_allclose(brdf.albedo("oren_nayar", 0.0, albedo=0.8, sigma=0.5), 0.8 * A, rtol=1e-6)
    t = math.radians(60)
    w = np.array([math.sin(t), 0, math.cos(t)])
    f = brdf.evaluate("oren_nayar", w, w, albedo=0.8, sigma=0.5)
    np.testing.assert_allclose(f, 0.8 / math.pi * (A + B * math.sin(t) * math.tan(t)), rtol=1e-12)


def test_oren_nayar_cycles_zero_roughness_is_lambert():
    w1, w2 = np.array([0.3, 0.2, 0.9]), np.array([-0.6, 0.1, 0.5])
    np.testing.assert_allclose(brdf.evaluate("oren_nayar", w1, w2, albedo=0.6, sigma=0.0, variant="cycles"),
                               brdf.evaluate("lambert", w1, w2, albedo=0.6), rtol=1e-14)


def test_mirror_albedo_is_fresnel():
    theta = np.radians([0.0, 45.0, 80.0])
    a = brdf.albedo("mirror", theta, ior=1.5)
    np.testing.assert_allclose(a[:, 0], fresnel.dielectric(np.cos(theta), 1.5), rtol=1e-12)
    assert a[0, 0] == pytest.approx(0.04, rel=1e-12)
    np.testing.assert_allclose(brdf.reflectance(1.0, f0=0.82), 0.82)
    assert np.all(brdf.evaluate("mirror", [0.3, 0, 0.9], [-0.3, 0, 0.9]) == 0)


def test_microfacet_sharp_limit_is_mirror():
    # As alpha -> 0 with F = 1 the directional albedo of ggx/beckmann -> 1 (G -> 1): independent of the lobe shape.
    for name in ("ggx", "beckmann", "torrance_sparrow"):
        a = brdf.albedo(name, np.radians([0, 40, 70]), alpha=1e-4)
        np.testing.assert_allclose(a, 1.0, atol=5e-4)

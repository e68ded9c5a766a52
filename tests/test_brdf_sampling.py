"""Importance sampling matches pdf (chi-square), pdf integrates to 1, sample/pdf consistency."""

import importlib.util
import math
import pathlib

import numpy as np
import pytest
from scipy import stats

import radiometer.brdf as brdf

_spec = importlib.util.spec_from_file_location("brdf_cases", pathlib.Path(__file__).with_name("brdf_cases.py"))
cases = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cases)

# Moderately sharp lobes so the bin integrals of the pdf are accurate on a 32x32 sub-grid per bin.
CHI2_CASES = [
    ("lambert", {}), ("oren_nayar", {"sigma": 0.5}),
    ("phong", {"kd": 0.3, "ks": 0.6, "n": 15.0}), ("blinn_phong", {"kd": 0.2, "ks": 0.7, "n": 20.0}),
    ("torrance_sparrow", {"alpha": 0.4}), ("ggx", {"alpha": 0.4}), ("ggx", {"alpha_x": 0.2, "alpha_y": 0.6}),
    ("beckmann", {"alpha": 0.4}), ("ward", {"kd": 0.2, "ks": 0.6, "alpha_x": 0.2, "alpha_y": 0.5}),
    ("ashikhmin_shirley", {"n_u": 30.0, "n_v": 5.0, "Rs": 0.4, "Rd": 0.5}),
]
N_COS, N_PHI, SUB = 16, 24, 32
N_SAMPLES = 200_000
SIGNIFICANCE = 0.01  # family-wise; Bonferroni-corrected per test below


def _bin_integrals(name, params, wo):
    """∫ pdf over each (cos θ, φ) bin of the full sphere, midpoint rule on a SUB x SUB grid per bin."""
    nc, nphi = N_COS * SUB, N_PHI * SUB
    c = -1 + (np.arange(nc) + 0.5) * 2 / nc
    phi = (np.arange(nphi) + 0.5) * 2 * math.pi / nphi
    C, P = np.meshgrid(c, phi, indexing="ij")
    s = np.sqrt(1 - C * C)
    w = np.stack([s * np.cos(P), s * np.sin(P), C], -1)
    p = brdf.pdf(name, w, wo, **params) * (2 / nc) * (2 * math.pi / nphi)  # dω = d(cos θ) dφ
    return p.reshape(N_COS, SUB, N_PHI, SUB).sum(axis=(1, 3))


@pytest.mark.parametrize("name,params", CHI2_CASES, ids=[f"{n}-{i}" for i, (n, _) in enumerate(CHI2_CASES)])
def test_chi_square_sampling_matches_pdf(name, params):
    rng = np.random.default_rng(10)
    t, ph = math.radians(40), 0.3
    wo = np.array([math.sin(t) * math.cos(ph), math.sin(t) * math.sin(ph), math.cos(t)])
    wi, pdf_s = brdf.sample(name, wo, rng.random((N_SAMPLES, 2)), **params)
    # The pdf reported by sample() is the pdf() of the returned direction.
    np.testing.assert_allclose(pdf_s, brdf.pdf(name, wi, wo, **params), rtol=1e-9)
    ci = np.clip(((wi[:, 2] + 1) / 2 * N_COS).astype(int), 0, N_COS - 1)
    pi = np.clip(((np.arctan2(wi[:, 1], wi[:, 0]) % (2 * math.pi)) / (2 * math.pi) * N_PHI).astype(int), 0, N_PHI - 1)
    observed = np.bincount(ci * N_PHI + pi, minlength=N_COS * N_PHI).astype(float)
    prob = _bin_integrals(name, params, wo).reshape(-1)
    # pdf integrates to 1 over the sphere (to the bin-quadrature accuracy).
    assert prob.sum() == pytest.approx(1.0, abs=2e-3)
    expected = prob / prob.sum() * N_SAMPLES
    # Pool bins with expected count < 5 into one (standard chi-square validity condition).
    small = expected < 5
    obs = np.append(observed[~small], observed[small].sum())
    exp = np.append(expected[~small], expected[small].sum())
    if exp[-1] == 0:
        assert obs[-1] == 0
        obs, exp = obs[:-1], exp[:-1]
    chi2 = np.sum((obs - exp) ** 2 / exp)
    p_value = stats.chi2.sf(chi2, len(obs) - 1)
    assert p_value > SIGNIFICANCE / len(CHI2_CASES), f"chi2={chi2:.1f}, dof={len(obs) - 1}, p={p_value:.2e}"


@pytest.mark.parametrize("name,params", cases.SAMPLED, ids=[f"{n}-{i}" for i, (n, _) in enumerate(cases.SAMPLED)])
def test_weights_are_bounded_estimates_of_albedo(name, params):
    # Monte Carlo with the model's own sampler must agree with the deterministic albedo() quadrature.
    rng = np.random.default_rng(11)
    t = math.radians(35)
    wo = np.array([math.sin(t), 0.0, math.cos(t)])
    wi, p = brdf.sample(name, wo, rng.random((200_000, 2)), **params)
    f = brdf.evaluate(name, wi, wo, **params)
    ok = p > 0
    w = np.zeros_like(f)
    w[ok] = f[ok] * np.maximum(0, wi[ok, 2])[:, None] / p[ok, None]
    est = w.mean(axis=0)
    err = 4 * w.std(axis=0) / math.sqrt(len(w)) + 1e-3
    np.testing.assert_allclose(est, brdf.albedo(name, t, **params), atol=float(np.max(err)))


def test_mirror_is_not_sampled():
    with pytest.raises(ValueError):
        brdf.sample("mirror", [0, 0, 1], [0.5, 0.5])

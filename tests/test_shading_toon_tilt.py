"""The closures the Phong-family node mappings use (issue 18): Cycles' glossy Toon BSDF and a normal
tilted towards the viewer, against independent closed forms (no bpy)."""

import numpy as np
import pytest

from radiometer.shading import closures as C


def _cap(mu_lo, n_mu=200, n_phi=64):
    """Midpoint quadrature over the cap cos(theta) >= mu_lo: directions (N, 3), solid angles (sr)."""
    mu = mu_lo + (1 - mu_lo) * (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m * m)
    d = np.stack([s * np.cos(p), s * np.sin(p), m], -1).reshape(-1, 3)
    return d, np.full(len(d), ((1 - mu_lo) / n_mu) * (2 * np.pi / n_phi))


@pytest.mark.parametrize("size", [0.1, 0.3])
def test_toon_cone_integrates_to_one(size):
    # smooth 0: eval = 1 / (2 pi (1 - cos a)) over a cone of half-angle a = size pi/2 around the mirror
    # direction, so integral of f cos_i d omega_i = 1 (the cone's solid angle is 2 pi (1 - cos a))
    a = size * np.pi / 2
    wo = np.array([0.0, 0.0, 1.0])
    inside, dw = _cap(np.cos(a) + 1e-12)
    f = C.toon_glossy(inside, wo, size, 0.0)[:, 0]
    assert np.sum(f * inside[:, 2] * dw) == pytest.approx(1.0, rel=1e-9)
    outside = np.array([[np.sin(a + 1e-6), 0.0, np.cos(a + 1e-6)]])
    assert C.toon_glossy(outside, wo, size, 0.0)[0, 0] == 0.0


def test_toon_ramp_is_linear_in_the_angle_to_the_mirror_direction():
    wo = np.array([np.sin(0.5), 0.0, np.cos(0.5)])
    mirror = np.array([-np.sin(0.5), 0.0, np.cos(0.5)])
    size, smooth = 0.1, 0.2  # full to 0.157 rad, zero at 0.471 rad
    a = np.array([0.05, 0.2, 0.3, 0.4, 0.5])
    wi = np.stack([-np.sin(0.5 - a), np.zeros_like(a), np.cos(0.5 - a)], -1)  # towards the normal
    assert np.allclose(np.arccos(wi @ mirror), a)
    eval_ = C.toon_glossy(wi, wo, size, smooth)[:, 0] * wi[:, 2]
    peak = 1.0 / (2 * np.pi * (1 - np.cos(0.15 * np.pi)))  # sample angle (size + smooth) pi/2
    expected = peak * np.clip(1 - (a - 0.05 * np.pi) / (0.1 * np.pi), 0, 1)
    assert np.allclose(eval_, np.where(a < 0.05 * np.pi, peak, expected), rtol=1e-9)


def test_tilted_normal_leans_towards_the_viewer():
    wo = np.array([[np.sin(1.0), 0.0, np.cos(1.0)], [0.0, 0.0, 1.0]])
    n = C.tilted_normal(wo, 0.1)
    lean = 0.1 * np.sin(1.0) / max(np.cos(1.0), C.TILT_MIN_COS)
    assert np.allclose(n[0], np.array([lean, 0.0, 1.0]) / np.hypot(lean, 1.0))
    assert np.allclose(n[1], [0.0, 0.0, 1.0])  # seen from above nothing leans


def test_tilted_microfacet_term_is_the_plain_lobe_about_the_tilted_normal():
    rng = np.random.default_rng(3)
    wi = rng.normal(size=(200, 3))
    wi[:, 2] = np.abs(wi[:, 2])
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    wo = np.array([np.sin(0.7), 0.0, np.cos(0.7)])
    term = C.Term("microfacet", distribution="beckmann", alpha_x=0.2, alpha_y=0.2, tilt=0.05)
    f = C.evaluate_terms([term], wi, wo)[:, 0]
    # independent: rotate the scene so that N' is +Z (a rotation about Y), evaluate, and convert the
    # eval (f' cos(wi, N')) back to f about the true normal
    n = C.tilted_normal(wo[None, :], 0.05)[0]
    ang = np.arctan2(n[0], n[2])
    rot = np.array([[np.cos(ang), 0, -np.sin(ang)], [0, 1, 0], [np.sin(ang), 0, np.cos(ang)]])
    assert np.allclose(rot @ n, [0, 0, 1])
    f_rot = C.microfacet(wi @ rot.T, wo @ rot.T, 0.2, 0.2, "beckmann")[:, 0]
    ci_t = wi @ n
    expected = np.where((ci_t > 0) & (wi[:, 2] > 0), f_rot * ci_t / wi[:, 2], 0.0)
    assert np.allclose(f, expected, rtol=1e-9, atol=1e-12)

"""Fresnel reflectance: Schlick's approximation, exact dielectric, exact conductor.

All functions broadcast with plain numpy rules, so RGB works by passing ``cos[..., None]`` together
with an RGB parameter of shape (3,). Cosines are of the angle between the incident direction and
the (micro)surface normal; only |cos| is used (reflection is symmetric). Indices are relative
(transmitted side / incident side), dimensionless.

References
----------
C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer Graphics Forum
13(3), 1994 (eq. 24).
M. Born, E. Wolf, *Principles of Optics*, 7th ed., §1.5.2 (Fresnel equations).
M. Pharr, W. Jakob, G. Humphreys, *PBRT* 4th ed., §9.3 ("FrDielectric", "FrComplex").
P. Hanrahan, CS348B lecture 10 (2002/2009), "Fresnel Reflectance" slide: the PRESETS below.
"""

import numpy as np

__all__ = ["schlick", "dielectric", "conductor", "f0_from_ior", "PRESETS"]

#: Normal-incidence reflectances F(0) from the CS348B lecture slide (gold, silver: measured metals;
#: glass n = 1.5, diamond n = 2.4). Note ((2.4-1)/(2.4+1))² = 0.170, the slide rounds it to 0.15;
#: we keep the slide's value for ``f0`` and give the index so the exact value is available.
PRESETS = {
    "gold": {"f0": 0.82},
    "silver": {"f0": 0.95},
    "glass": {"f0": 0.04, "ior": 1.5},
    "diamond": {"f0": 0.15, "ior": 2.4},
}


def f0_from_ior(ior):
    """Normal-incidence reflectance of a dielectric: ((n-1)/(n+1))² (Born & Wolf)."""
    ior = np.asarray(ior, dtype=float)
    return ((ior - 1.0) / (ior + 1.0)) ** 2


def schlick(f0, cos):
    """Schlick's approximation F = F0 + (1 - F0)(1 - cos)^5 (dimensionless, in [0, 1])."""
    c = np.clip(np.abs(np.asarray(cos, dtype=float)), 0.0, 1.0)
    f0 = np.asarray(f0, dtype=float)
    return f0 + (1.0 - f0) * (1.0 - c) ** 5


def dielectric(cos_i, ior):
    """Exact unpolarised Fresnel reflectance of a smooth dielectric interface.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle (sign ignored).
    ior : array_like
        Relative index n_t / n_i (> 0). ``ior < 1`` gives total internal reflection (F = 1)
        beyond the critical angle.

    Returns
    -------
    ndarray
        (R_s + R_p) / 2, dimensionless in [0, 1]. At exactly grazing incidence F = 1.
    """
    c = np.clip(np.abs(np.asarray(cos_i, dtype=float)), 0.0, 1.0)
    eta = np.asarray(ior, dtype=float)
    with np.errstate(all="ignore"):
        sin2_t = (1.0 - c * c) / (eta * eta)
        tir = sin2_t >= 1.0
        cos_t = np.sqrt(np.maximum(0.0, 1.0 - sin2_t))
        den_s = c + eta * cos_t
        den_p = eta * c + cos_t
        r_s = (c - eta * cos_t) / den_s
        r_p = (eta * c - cos_t) / den_p
        f = 0.5 * (r_s * r_s + r_p * r_p)
    # Both denominators vanish only at cos_i = 0 with ior = 1; the grazing limit is F = 1.
    return np.where(tir | (den_s <= 0) | (den_p <= 0), 1.0, f)


def conductor(cos_i, eta, k):
    """Exact unpolarised Fresnel reflectance of a conductor with complex index eta + i k.

    Parameters
    ----------
    cos_i : array_like
        Cosine of the incidence angle (sign ignored).
    eta, k : array_like
        Real and imaginary parts of the relative complex index (dimensionless, eta > 0, k >= 0),
        typically RGB of shape (3,).

    Returns
    -------
    ndarray
        (|r_s|² + |r_p|²) / 2 in [0, 1]; k = 0 reduces to :func:`dielectric`.
    """
    c = np.clip(np.abs(np.asarray(cos_i, dtype=float)), 0.0, 1.0)
    n = np.asarray(eta, dtype=float) + 1j * np.asarray(k, dtype=float)
    with np.errstate(all="ignore"):
        sin2_t = (1.0 - c * c) / (n * n)
        cos_t = np.sqrt(1.0 - sin2_t)  # principal complex root, as in pbrt-v4 FrComplex
        den_p = n * c + cos_t
        den_s = c + n * cos_t
        r_p = (n * c - cos_t) / den_p
        r_s = (c - n * cos_t) / den_s
        f = 0.5 * (np.abs(r_p) ** 2 + np.abs(r_s) ** 2)
    # Zero denominators only at grazing incidence with n = 1 exactly; limit F = 1.
    return np.where((np.abs(den_p) == 0) | (np.abs(den_s) == 0), 1.0, np.real(f))

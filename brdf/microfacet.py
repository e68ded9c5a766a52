"""Microfacet distributions, Smith masking-shadowing and sampling (local frame, z = normal).

Conventions
-----------
* ``alpha_x``, ``alpha_y`` are the microfacet SLOPE parameters (dimensionless, > 0) along the local
  x (tangent) and y (bitangent) axes; isotropic means alpha_x = alpha_y = alpha. Blender/Cycles'
  "Roughness" r maps to alpha = r² (Cycles svm_closure.h: ``roughness = sqr(param1)``).
* Directions and the microfacet normal ``m`` are unit vectors of shape (..., 3). D is a density
  over microfacet normals per unit solid angle [1/sr], normalised so that the projected area
  ∫ D(m) cos θm dωm = 1.
* Smith: G1 = 1/(1+Λ); separable G2 = G1(wi) G1(wo); height-correlated G2 = 1/(1+Λ(wi)+Λ(wo))
  (the form Cycles uses, bsdf_microfacet.h ``bsdf_G``).

References
----------
B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction through Rough
Surfaces", EGSR 2007 (GGX D, Beckmann D, Λ, G1).
E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2), 2014
(anisotropic Λ, height-correlated G2, V-cavity G as a valid masking function).
E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018 (VNDF sampling).
K. Torrance, E. Sparrow, "Theory for Off-Specular Reflection From Roughened Surfaces", JOSA 57(9),
1967; R. Cook, K. Torrance, ACM TOG 1(1), 1982 (V-cavity G = min(1, 2(n·h)(n·v)/(v·h), ...)).
"""

import math

import numpy as np

from .frame import dot, normalize
from .special import erfc as _erfc  # numpy only: Blender's Python has no scipy

__all__ = [
    "ggx_D", "beckmann_D", "D", "ggx_lambda", "beckmann_lambda", "smith_lambda", "G1",
    "G_separable", "G_height_correlated", "G_vcavity", "sample_ggx_vndf", "pdf_ggx_vndf",
    "sample_slope_D", "pdf_D_cos",
]

_SQRT_PI = math.sqrt(math.pi)


def _xyz(w):
    w = np.asarray(w, dtype=float)
    return w[..., 0], w[..., 1], w[..., 2]


def ggx_D(m, alpha_x, alpha_y):
    """Anisotropic GGX / Trowbridge-Reitz D(m) = 1/(π αx αy (x²/αx² + y²/αy² + z²)²) [1/sr]; 0 for z <= 0."""
    x, y, z = _xyz(m)
    with np.errstate(all="ignore"):
        q = (x / alpha_x) ** 2 + (y / alpha_y) ** 2 + z * z
        d = 1.0 / (math.pi * alpha_x * alpha_y * q * q)
    return np.where(z > 0, d, 0.0)


def beckmann_D(m, alpha_x, alpha_y):
    """Anisotropic Beckmann D(m) = exp(-tan²θ(cos²φ/αx² + sin²φ/αy²)) / (π αx αy cos⁴θ) [1/sr]."""
    x, y, z = _xyz(m)
    with np.errstate(all="ignore"):
        z2 = z * z
        e = ((x / alpha_x) ** 2 + (y / alpha_y) ** 2) / z2
        num = np.exp(-e) / (math.pi * alpha_x * alpha_y)
        # exp(-e) underflows to 0 long before z⁴ does; only divide where the numerator is > 0.
        d = np.where(num > 0, num / (z2 * z2), 0.0)
    return np.where((z > 0) & np.isfinite(d), d, 0.0)


def D(distribution, m, alpha_x, alpha_y):
    """Dispatch: ``distribution`` is 'ggx' or 'beckmann'."""
    return (ggx_D if distribution == "ggx" else beckmann_D)(m, alpha_x, alpha_y)


def _alpha2_tan2(w, alpha_x, alpha_y):
    # α(φ)² tan²θ = (x² αx² + y² αy²) / z²: inf at the horizon, 0 along the normal.
    x, y, z = _xyz(w)
    with np.errstate(all="ignore"):
        num = (x * alpha_x) ** 2 + (y * alpha_y) ** 2
        return np.where(z > 0, np.where(num > 0, num / (z * z), 0.0), np.inf)


def ggx_lambda(w, alpha_x, alpha_y):
    """Smith Λ for GGX: (sqrt(1 + α² tan²θ) - 1)/2; inf for z <= 0."""
    a2t2 = _alpha2_tan2(w, alpha_x, alpha_y)
    with np.errstate(all="ignore"):
        # x/(1+sqrt(1+x)) == sqrt(1+x)-1 without cancellation for tiny x (sharp lobes).
        lam = 0.5 * a2t2 / (1.0 + np.sqrt(1.0 + a2t2))
    return np.where(np.isinf(a2t2), np.inf, lam)


def beckmann_lambda(w, alpha_x, alpha_y):
    """Smith Λ for Beckmann, exact: (exp(-a²)/(a√π) - erfc(a))/2 with a = 1/(α tanθ)."""
    a2t2 = _alpha2_tan2(w, alpha_x, alpha_y)
    with np.errstate(all="ignore"):
        a = 1.0 / np.sqrt(a2t2)  # inf along the normal (Λ = 0), 0 at the horizon (Λ = inf)
        lam = 0.5 * (np.exp(-a * a) / (a * _SQRT_PI) - _erfc(a))
        lam = np.where(a > 30.0, 0.0, lam)  # both terms underflow: exp(-900) ~ 1e-391
        lam = np.maximum(lam, 0.0)  # rounding in the difference can give -1e-17
    return np.where(a2t2 == 0, 0.0, np.where(np.isinf(a2t2), np.inf, lam))


def smith_lambda(distribution, w, alpha_x, alpha_y):
    return (ggx_lambda if distribution == "ggx" else beckmann_lambda)(w, alpha_x, alpha_y)


def G1(distribution, w, alpha_x, alpha_y):
    """Smith masking G1(w) = 1/(1 + Λ(w)), in [0, 1]."""
    return 1.0 / (1.0 + smith_lambda(distribution, w, alpha_x, alpha_y))


def G_separable(distribution, wi, wo, alpha_x, alpha_y):
    """Separable Smith G2 = G1(wi) G1(wo) (Walter 2007; Mitsuba 3 default)."""
    return G1(distribution, wi, alpha_x, alpha_y) * G1(distribution, wo, alpha_x, alpha_y)


def G_height_correlated(distribution, wi, wo, alpha_x, alpha_y):
    """Height-correlated Smith G2 = 1/(1 + Λ(wi) + Λ(wo)) (Heitz 2014 eq. 99; Cycles)."""
    return 1.0 / (1.0 + smith_lambda(distribution, wi, alpha_x, alpha_y)
                  + smith_lambda(distribution, wo, alpha_x, alpha_y))


def G_vcavity(wi, wo, m):
    """Torrance-Sparrow / Cook-Torrance V-cavity G = min(1, 2 mz wo_z/(wo·m), 2 mz wi_z/(wi·m))."""
    mz = np.asarray(m)[..., 2]
    with np.errstate(all="ignore"):
        g_o = 2.0 * mz * np.asarray(wo)[..., 2] / dot(wo, m)
        g_i = 2.0 * mz * np.asarray(wi)[..., 2] / dot(wi, m)
        g = np.minimum(1.0, np.minimum(g_o, g_i))
    # Back-facing microfacet (w·m <= 0) or NaN from 0/0: no visible contribution.
    return np.where((dot(wo, m) > 0) & (dot(wi, m) > 0) & np.isfinite(g), np.maximum(g, 0.0), 0.0)


def sample_ggx_vndf(wo, alpha_x, alpha_y, u1, u2):
    """Sample a microfacet normal from the GGX distribution of visible normals D_wo(m) (Heitz 2018).

    ``wo`` must be unit with z > 0 (callers mask the rest). Returns unit m with z >= 0.
    """
    wo = np.asarray(wo, dtype=float)
    u1 = np.asarray(u1, dtype=float)
    u2 = np.asarray(u2, dtype=float)
    # Stretch the view vector to the hemisphere configuration (α = 1).
    vh = normalize(np.stack([alpha_x * wo[..., 0], alpha_y * wo[..., 1], wo[..., 2]], axis=-1))
    lensq = vh[..., 0] ** 2 + vh[..., 1] ** 2
    # Tangent T1 ⟂ vh in the xy plane; undefined (0/0) for vh = z, where any T1 works.
    inv = 1.0 / np.sqrt(np.where(lensq > 0, lensq, 1.0))
    t1 = np.where(lensq[..., None] > 0,
                  np.stack([-vh[..., 1] * inv, vh[..., 0] * inv, np.zeros_like(lensq)], axis=-1),
                  np.array([1.0, 0.0, 0.0]))
    t2 = np.cross(vh, t1)
    r = np.sqrt(u1)
    phi = 2.0 * math.pi * u2
    p1 = r * np.cos(phi)
    p2 = r * np.sin(phi)
    s = 0.5 * (1.0 + vh[..., 2])
    p2 = (1.0 - s) * np.sqrt(np.maximum(0.0, 1.0 - p1 * p1)) + s * p2
    p3 = np.sqrt(np.maximum(0.0, 1.0 - p1 * p1 - p2 * p2))
    nh = p1[..., None] * t1 + p2[..., None] * t2 + p3[..., None] * vh
    # Unstretch back to the ellipsoid configuration.
    m = np.stack([alpha_x * nh[..., 0], alpha_y * nh[..., 1], np.maximum(0.0, nh[..., 2])], axis=-1)
    return normalize(m)


def pdf_ggx_vndf(wo, m, alpha_x, alpha_y):
    """Density of :func:`sample_ggx_vndf` over m [1/sr]: G1(wo) max(0, wo·m) D(m) / wo_z."""
    wo = np.asarray(wo, dtype=float)
    with np.errstate(all="ignore"):
        p = G1("ggx", wo, alpha_x, alpha_y) * np.maximum(0.0, dot(wo, m)) \
            * ggx_D(m, alpha_x, alpha_y) / wo[..., 2]
    return np.where((wo[..., 2] > 0) & np.isfinite(p), p, 0.0)


def sample_slope_D(distribution, alpha_x, alpha_y, u1, u2):
    """Sample m with density D(m) cos θm (exact for both distributions, any anisotropy).

    The slope distribution P22 is an affine image of the isotropic α = 1 one, so the slope is
    r (αx cos 2πu2, αy sin 2πu2) with r² = -ln(1-u1) (Beckmann: Gaussian slopes) or
    r² = u1/(1-u1) (GGX), and m = normalize(-slope_x, -slope_y, 1) (Walter 2007 §5.2/5.3).
    """
    u1 = np.clip(np.asarray(u1, dtype=float), 0.0, 1.0 - 2.0 ** -53)  # keeps r finite
    u2 = np.asarray(u2, dtype=float)
    if distribution == "beckmann":
        r = np.sqrt(-np.log1p(-u1))
    else:
        r = np.sqrt(u1 / (1.0 - u1))
    phi = 2.0 * math.pi * u2
    sx = r * alpha_x * np.cos(phi)
    sy = r * alpha_y * np.sin(phi)
    return normalize(np.stack(np.broadcast_arrays(-sx, -sy, np.ones_like(sx)), axis=-1))


def pdf_D_cos(distribution, m, alpha_x, alpha_y):
    """Density of :func:`sample_slope_D` over m [1/sr]: D(m) cos θm."""
    return D(distribution, m, alpha_x, alpha_y) * np.maximum(0.0, np.asarray(m)[..., 2])

"""Numpy models of the Cycles closures that Radiometer realises BRDFs with (no bpy).

Each function returns the BRDF value f in 1/sr (RGB, shape (..., 3)) WITHOUT the cosine factor, in
the local frame z = normal, x = tangent. They are transcriptions of the Cycles 5.0 kernel code that
ships inside the bpy wheel (``scripts/addons_core/cycles/source/kernel/closure/*.h``); the file
and function each one follows is named in its docstring, so a Blender update can be re-checked.
A rendered comparison (``shading.validate``) confirms them against Cycles itself.

A closure network is a list of ``Term`` objects; ``evaluate_terms`` sums them.

References
----------
Walter, Marschner, Li, Torrance (2007), "Microfacet models for refraction through rough surfaces",
EGSR: GGX and Beckmann D, Smith Lambda, the rational Beckmann Lambda approximation.
Heitz (2014), "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2):
height-correlated Smith G = 1 / (1 + Lambda_i + Lambda_o).
Schlick (1994), "An inexpensive BRDF model for physically-based rendering", CGF 13(3).
Ashikhmin, Shirley (2000), "An anisotropic Phong BRDF model", JGT 5(2).
Lafortune, Willems (1994), "Using the modified Phong reflectance model for physically based rendering".
Fujii (2012) / Portsmouth et al. (2024, OpenPBR) "energy-preserving Oren-Nayar": Cycles' Oren-Nayar.
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "Term",
    "evaluate_terms",
    "microfacet",
    "ashikhmin_shirley",
    "phong_ramp",
    "toon_glossy",
    "tilted_normal",
    "oren_nayar",
    "lambert",
    "fresnel_schlick",
    "fresnel_conductor",
]

_EPS = 1e-12


@dataclass
class Term:
    """One Cycles closure with its weight.

    Attributes
    ----------
    closure : str
        'diffuse' | 'oren_nayar' | 'microfacet' | 'ashikhmin_shirley' | 'phong_ramp' | 'toon' | 'mirror'.
    color : tuple of 3 float
        Weight per RGB channel (dimensionless).
    distribution : str
        'ggx' or 'beckmann' for 'microfacet'.
    alpha_x, alpha_y : float
        Microfacet width along tangent / bitangent (alpha = Blender roughness squared).
    fresnel : str
        'none' (F = 1), 'schlick' (uses ``f0``) or 'conductor' (uses ``ior`` and ``k``).
    f0, ior, k : tuple of 3 float
        Fresnel parameters (dimensionless).
    roughness : float
        Cycles Oren-Nayar roughness in [0, 1].
    exponent : float
        Phong exponent for 'phong_ramp'.
    size, smooth : float
        Toon BSDF (glossy) controls in [0, 1], fractions of pi/2 rad: full intensity within
        ``size`` of the mirror direction, falling linearly to 0 over ``smooth`` beyond it.
    tilt : float
        Shading normal tilted towards the viewer (``tilted_normal``): N' = normalize(N + tilt (wo -
        cos_o N) / max(cos_o, TILT_MIN_COS)); 0 leaves the normal as it is (dimensionless).
    """

    closure: str
    color: tuple = (1.0, 1.0, 1.0)
    distribution: str = "ggx"
    alpha_x: float = 0.0
    alpha_y: float = 0.0
    fresnel: str = "none"
    f0: tuple = (1.0, 1.0, 1.0)
    ior: tuple = (1.5, 1.5, 1.5)
    k: tuple = (0.0, 0.0, 0.0)
    roughness: float = 0.0
    exponent: float = 1.0
    size: float = 0.0
    smooth: float = 0.0
    tilt: float = 0.0
    view: tuple = ()  # view-dependent weight factors: ("pow", k) -> cos_o^k, ("as_diffuse",) -> 1-(1-cos_o/2)^5
    extra: dict = field(default_factory=dict)

    def to_dict(self):
        d = {"closure": self.closure, "color": [float(c) for c in self.color]}
        if self.closure in ("microfacet", "ashikhmin_shirley", "mirror"):
            d.update(distribution=self.distribution, alpha_x=float(self.alpha_x), alpha_y=float(self.alpha_y),
                     fresnel=self.fresnel)
            if self.fresnel == "schlick":
                d["f0"] = [float(c) for c in self.f0]
            if self.fresnel == "conductor":
                d["ior"] = [float(c) for c in self.ior]
                d["k"] = [float(c) for c in self.k]
        if self.closure == "oren_nayar":
            d["roughness"] = float(self.roughness)
        if self.closure == "phong_ramp":
            d["exponent"] = float(self.exponent)
        if self.closure == "toon":
            d.update(size=float(self.size), smooth=float(self.smooth))
        if self.tilt:
            d["tilt"] = float(self.tilt)
        return d


def _rgb(value):
    return np.broadcast_to(np.asarray(value, dtype=float), (3,))


def fresnel_schlick(cos_theta, f0):
    """Schlick Fresnel F = f0 + (1 - f0)(1 - cos)^5, RGB (..., 3).

    Cycles' F82-tint model with a white edge tint is exactly this (``fresnel_f82`` with B = 0 in
    ``closure/bsdf_util.h``; ``bsdf_microfacet_setup_fresnel_f82_tint`` sets B = 0 for tint 1).

    References
    ----------
    Schlick (1994), eq. 15.
    """
    c = np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)[..., None]
    s5 = (1.0 - c) ** 5
    f0 = _rgb(f0)
    return np.clip(f0 + (1.0 - f0) * s5, 0.0, 1.0)


# Cycles before Blender 5.0 evaluated the Metallic BSDF's "physical conductor" Fresnel with the
# PBRT-v2 approximation (``fresnel_conductor(cosi, eta, k)`` in 4.x ``closure/bsdf_util.h``), up to
# 46 % off the exact value at grazing incidence for k = 0. The host calls
# ``use_cycles_version(bpy.app.version)`` so fidelity is computed against what Cycles renders.
_APPROXIMATE_CONDUCTOR = False


def use_cycles_version(version):
    """Select the conductor Fresnel Cycles uses in this Blender version (tuple like (5, 0, 1))."""
    global _APPROXIMATE_CONDUCTOR
    _APPROXIMATE_CONDUCTOR = tuple(version)[:2] < (5, 0)


def fresnel_conductor_approximate(cos_theta, eta, k):
    """PBRT-v2's approximate conductor Fresnel (Cycles <= 4.5): exact at normal incidence only.

    References
    ----------
    Pharr & Humphreys, "Physically Based Rendering" 2nd ed. (2010), sec. 8.2.1, FrCond.
    """
    c = np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)[..., None]
    eta = np.broadcast_to(np.asarray(eta, dtype=float), (3,))
    k = np.broadcast_to(np.asarray(k, dtype=float), (3,))
    c2 = c * c
    tmp_f = eta * eta + k * k
    tmp = tmp_f * c2
    r_parl2 = (tmp - 2.0 * eta * c + 1.0) / (tmp + 2.0 * eta * c + 1.0)
    r_perp2 = (tmp_f - 2.0 * eta * c + c2) / (tmp_f + 2.0 * eta * c + c2)
    return 0.5 * (r_parl2 + r_perp2)


def fresnel_conductor(cos_theta, eta, k):
    """Unpolarised Fresnel reflectance of a conductor with complex IOR eta + i k, RGB (..., 3).

    With k = 0 this is the exact dielectric Fresnel reflectance (no total internal reflection for
    light arriving from outside). Cycles: ``fresnel_conductor_polarized`` in ``closure/bsdf_util.h``.

    References
    ----------
    Pharr, Jakob, Humphreys, "Physically Based Rendering" 4th ed., sec. 9.5 (FrComplex).
    """
    if _APPROXIMATE_CONDUCTOR:
        return fresnel_conductor_approximate(cos_theta, eta, k)
    c = np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)[..., None]
    n = np.asarray(eta, dtype=complex) + 1j * np.asarray(k, dtype=complex)
    n = np.broadcast_to(n, (3,))
    sin2 = 1.0 - c * c
    sin2_t = sin2 / (n * n)
    cos_t = np.sqrt(1.0 - sin2_t)
    r_parl = (n * c - cos_t) / (n * c + cos_t)
    r_perp = (c - n * cos_t) / (c + n * cos_t)
    return 0.5 * (np.abs(r_parl) ** 2 + np.abs(r_perp) ** 2)


def _lambda(distribution, ax, ay, v):
    """Smith Lambda; Cycles ``bsdf_lambda_from_sqr_alpha_tan_n`` (closure/bsdf_microfacet.h)."""
    vz2 = np.maximum(v[..., 2] ** 2, _EPS)
    s = (ax * ax * v[..., 0] ** 2 + ay * ay * v[..., 1] ** 2) / vz2
    if distribution == "ggx":
        return 0.5 * (np.sqrt(1.0 + s) - 1.0)
    # Beckmann: Cycles uses Walter et al.'s rational approximation (below their eq. 69), not erf.
    with np.errstate(divide="ignore", invalid="ignore"):
        a = 1.0 / np.sqrt(np.maximum(s, _EPS))
        lam = ((0.396 * a - 1.259) * a + 1.0) / ((2.181 * a + 3.535) * a)
    return np.where(s < 0.39, 0.0, lam)


def _ndf(distribution, ax, ay, h):
    hx, hy, hz = h[..., 0], h[..., 1], np.maximum(h[..., 2], _EPS)
    if distribution == "ggx":
        t = hx * hx / (ax * ax) + hy * hy / (ay * ay) + hz * hz
        return 1.0 / (np.pi * ax * ay * t * t)
    e = (hx * hx / (ax * ax) + hy * hy / (ay * ay)) / (hz * hz)
    return np.exp(-e) / (np.pi * ax * ay * hz ** 4)


def _frame(wi, wo):
    wi = np.asarray(wi, dtype=float)
    wo = np.asarray(wo, dtype=float)
    wi, wo = np.broadcast_arrays(wi, wo)
    ci, co = wi[..., 2], wo[..., 2]
    h = wi + wo
    h = h / np.maximum(np.linalg.norm(h, axis=-1, keepdims=True), _EPS)
    return wi, wo, ci, co, h


def microfacet(wi, wo, alpha_x, alpha_y, distribution="ggx", fresnel="none", f0=1.0, ior=1.5, k=0.0):
    """Cycles microfacet reflection (Glossy / Metallic BSDF, OSL microfacet closures), 1/sr.

    f = F(wi.h) D(h) G2(wi, wo) / (4 cos_i cos_o), with the height-correlated Smith
    G2 = 1 / (1 + Lambda(wi) + Lambda(wo)) (``bsdf_microfacet_eval``, closure/bsdf_microfacet.h).

    Parameters
    ----------
    wi, wo : array_like (..., 3)
        Unit directions towards the light and the viewer, local frame.
    alpha_x, alpha_y : float
        Microfacet widths (alpha = Blender roughness ** 2).
    distribution : {'ggx', 'beckmann'}
    fresnel : {'none', 'schlick', 'conductor'}

    References
    ----------
    Walter et al. (2007), eqs. 20, 33, 72; Heitz (2014), eq. 99.
    """
    wi, wo, ci, co, h = _frame(wi, wo)
    ax = max(float(alpha_x), 1e-4)
    ay = max(float(alpha_y), 1e-4)
    valid = (ci > 0) & (co > 0)
    D = _ndf(distribution, ax, ay, h)
    G = 1.0 / (1.0 + _lambda(distribution, ax, ay, wi) + _lambda(distribution, ax, ay, wo))
    cos_hi = np.sum(wi * h, axis=-1)
    if fresnel == "schlick":
        F = fresnel_schlick(cos_hi, f0)
    elif fresnel == "conductor":
        F = fresnel_conductor(cos_hi, ior, k)
    else:
        F = np.ones(cos_hi.shape + (3,))
    with np.errstate(divide="ignore", invalid="ignore"):
        f = (D * G / (4.0 * np.maximum(ci, _EPS) * np.maximum(co, _EPS)))[..., None] * F
    return np.where(valid[..., None], f, 0.0)


def ashikhmin_shirley(wi, wo, alpha_x, alpha_y):
    """Cycles' Glossy BSDF 'Ashikhmin-Shirley' distribution, F = 1, 1/sr.

    f = sqrt((n_x + 1)(n_y + 1)) / (8 pi) (n.h)^e / ((h.k) max(cos_i, cos_o)),
    n = 2 / alpha^2 - 2 (``bsdf_ashikhmin_shirley_eval``, closure/bsdf_ashikhmin_shirley.h).

    References
    ----------
    Ashikhmin, Shirley (2000), eq. 4 with F = 1.
    """
    wi, wo, ci, co, h = _frame(wi, wo)
    ax = np.clip(float(alpha_x), 1e-4, 1.0)
    ay = np.clip(float(alpha_y), 1e-4, 1.0)
    nx, ny = 2.0 / ax ** 2 - 2.0, 2.0 / ay ** 2 - 2.0
    hz = np.maximum(h[..., 2], 1e-6)
    sin2 = np.maximum(1.0 - hz * hz, _EPS)
    e = (nx * h[..., 0] ** 2 + ny * h[..., 1] ** 2) / sin2
    hk = np.maximum(np.abs(np.sum(h * wi, axis=-1)), 1e-6)
    norm = np.sqrt((nx + 1.0) * (ny + 1.0)) / (8.0 * np.pi)
    f = norm * hz ** e / (hk * np.maximum(np.maximum(ci, co), 1e-6))
    valid = (ci > 0) & (co > 0)
    return np.where(valid[..., None], f[..., None] * np.ones(3), 0.0)


def phong_ramp(wi, wo, exponent):
    """Cycles OSL ``phong_ramp`` with one colour: f = (n + 2) / (2 pi) cos^n(R(wi).wo), 1/sr.

    This is the normalised modified Phong lobe (``bsdf_phong_ramp_eval``, closure/bsdf_phong_ramp.h).

    References
    ----------
    Lafortune, Willems (1994), eq. for the normalised modified Phong specular term.
    """
    wi, wo, ci, co, _ = _frame(wi, wo)
    r = 2.0 * ci[..., None] * np.array([0.0, 0.0, 1.0]) - wi
    cos_ro = np.sum(r * wo, axis=-1)
    valid = (ci > 0) & (co > 0) & (cos_ro > 0)
    f = (exponent + 2.0) / (2.0 * np.pi) * np.maximum(cos_ro, 0.0) ** exponent
    return np.where(valid[..., None], f[..., None] * np.ones(3), 0.0)


def toon_glossy(wi, wo, size, smooth):
    """Cycles' Toon BSDF, component Glossy, 1/sr (``bsdf_glossy_toon_eval``, closure/bsdf_toon.h).

    With the angle a between wi and the mirror direction of wo, max_angle = clamp(size, 1e-5, 1) pi/2,
    s = clamp(smooth, 0, 1) pi/2 and the sample angle a_s = min(max_angle + s, pi/2), Cycles returns
    eval = I(a) / (2 pi (1 - cos a_s)) with I = 1 below max_angle, 1 - (a - max_angle)/s up to
    max_angle + s, 0 beyond. Its eval carries no cos_i, so f = eval / cos_i.
    """
    wi, wo, ci, co, _ = _frame(wi, wo)
    return _toon_f(_toon_angle(wi, wo), ci, co, size, smooth)


def _toon_angle(wi, wo):
    """Angle (rad) between wi and the mirror direction of wo about +Z, clipped to [0, pi/2]."""
    r = 2.0 * wo[..., 2:3] * np.array([0.0, 0.0, 1.0]) - wo
    return np.arccos(np.clip(np.sum(r * wi, axis=-1), 0.0, 1.0))


def _toon_f(angle, ci, co, size, smooth):
    max_angle = float(np.clip(size, 1e-5, 1.0)) * np.pi / 2
    s = float(np.clip(smooth, 0.0, 1.0)) * np.pi / 2
    sample_angle = min(max_angle + s, np.pi / 2)
    if s > 0:
        intensity = np.where(angle < max_angle, 1.0, np.clip(1.0 - (angle - max_angle) / s, 0.0, 1.0))
    else:
        intensity = np.where(angle < max_angle, 1.0, 0.0)
    intensity = np.where(angle < sample_angle, intensity, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = intensity / (2.0 * np.pi * (1.0 - np.cos(sample_angle))) / np.maximum(ci, _EPS)
    valid = (ci > 0) & (co > 0)
    return np.where(valid[..., None], f[..., None] * np.ones(3), 0.0)


#: Smallest cos_o the normal tilt divides by (grazing views): ``tilted_normal``.
TILT_MIN_COS = 0.5


def tilted_normal(wo, tilt):
    """(..., 3) unit shading normal N' = normalize(N + tilt t / max(cos_o, TILT_MIN_COS)), N = +Z, t the
    view direction's part in the surface plane: the normal leans towards the viewer by about
    tilt tan(theta_o), which moves a lobe around the mirror direction towards the normal (a stand-in
    for the cos_i factor a Phong-type lobe has and a closure's eval lacks). The node group builds the
    same from Geometry > Incoming and the normal."""
    wo = np.asarray(wo, dtype=float)
    co = wo[..., 2]
    t = wo - co[..., None] * np.array([0.0, 0.0, 1.0])
    n = np.array([0.0, 0.0, 1.0]) + (tilt / np.maximum(co, TILT_MIN_COS))[..., None] * t
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def _in_frame(v, n):
    """Components of v in an orthonormal frame with z = n (x: any perpendicular; isotropic closures)."""
    a = np.where(np.abs(n[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    x = np.cross(a, n)
    x = x / np.linalg.norm(x, axis=-1, keepdims=True)
    y = np.cross(n, x)
    return np.stack([np.sum(v * x, -1), np.sum(v * y, -1), np.sum(v * n, -1)], axis=-1)


def oren_nayar(wi, wo, roughness, albedo=1.0):
    """Cycles' Oren-Nayar (Diffuse BSDF with roughness > 0) INCLUDING its albedo, 1/sr, RGB.

    Transcribed from ``bsdf_oren_nayar_get_intensity`` / ``bsdf_oren_nayar_setup``
    (closure/bsdf_oren_nayar.h): Fujii's single scattering A + B t with
    A = 1 / (pi + sigma (pi/2 - 2/3)), B = sigma A, t = (l.v - cos_i cos_o) / max(cos_i, cos_o) when
    positive, plus the OpenPBR energy-compensation term, which is NOT linear in the albedo rho:
    f = rho [A + B t + E_ms(rho) (1 - E(cos_i)) (1 - E(cos_o))],
    E_ms(rho) = rho^2 E_avg / (pi (1 - E_avg) (1 - rho (1 - E_avg))).

    References
    ----------
    Fujii, "A tiny improvement of Oren-Nayar reflectance model" (mimosa-pudica.net, 2012).
    Portsmouth, Kutz, Hill (2024), "EON: A practical energy-preserving rough diffuse BRDF", JCGT 14(1).
    """
    wi, wo, ci, co, _ = _frame(wi, wo)
    rho = np.clip(_rgb(albedo), 0.0, 1.0)
    sigma = float(np.clip(roughness, 0.0, 1.0))
    valid = (ci > 0) & (co > 0)
    if sigma < 1e-5:
        return np.where(valid[..., None], np.ones(ci.shape + (3,)) * rho / np.pi, 0.0)
    a = 1.0 / (np.pi + sigma * (np.pi / 2 - 2.0 / 3.0))
    b = sigma * a
    t = np.sum(wi * wo, axis=-1) - ci * co
    t = np.where(t > 0, t / np.maximum(np.maximum(ci, co), _EPS), t)
    single = a + b * t
    e_avg = a * np.pi + ((2 * np.pi - 5.6) / 3.0) * b
    e_ms = rho * rho * (e_avg / (1.0 - e_avg)) / (np.pi * (1.0 - rho * (1.0 - e_avg)))
    e_l = a * np.pi + b * _g_on(ci)
    e_v = a * np.pi + b * _g_on(co)
    # Cycles multiplies the whole closure, E_ms included, by the colour weight (bsdf_alloc weight).
    f = rho * (single[..., None] + ((1.0 - e_l) * (1.0 - e_v))[..., None] * e_ms)
    return np.where(valid[..., None], f, 0.0)


def _g_on(c):
    """G(cos) of the EON model (``bsdf_oren_nayar_G``)."""
    c = np.clip(c, 0.0, 1.0)
    s = np.sqrt(np.maximum(1.0 - c * c, 0.0))
    t = np.arccos(c)
    near = c < 1e-6  # Cycles: Taylor fallback at grazing, where tan(theta) misbehaves
    with np.errstate(divide="ignore", invalid="ignore"):
        g = s * (t - 2.0 / 3.0 - s * c) + (2.0 / 3.0) * (s / np.maximum(c, _EPS)) * (1.0 - s ** 3)
    return np.where(near, (np.pi / 2 - 2.0 / 3.0) - c, g)


def lambert(wi, wo):
    """Lambertian 1/pi (Cycles Diffuse BSDF with roughness 0), 1/sr."""
    wi, wo, ci, co, _ = _frame(wi, wo)
    valid = (ci > 0) & (co > 0)
    return np.where(valid[..., None], np.full(ci.shape + (3,), 1.0 / np.pi), 0.0)


def view_weight(view, wo):
    """Product of the view-dependent weight factors of a term at view directions wo, shape (...,).

    ("pow", k): cos_o^k, a stand-in for the cos_i cos_o factor that Phong-type lobes lack relative to a
    microfacet lobe; ("as_diffuse",): 1 - (1 - cos_o/2)^5 (Ashikhmin-Shirley's diffuse view factor). The
    node group computes the same from the shading normal and Geometry > Incoming.
    """
    co = np.clip(np.asarray(wo, dtype=float)[..., 2], 0.0, 1.0)
    w = np.ones_like(co)
    for factor in view:
        if factor[0] == "pow":
            w = w * co ** float(factor[1])
        elif factor[0] == "as_diffuse":
            w = w * (1.0 - (1.0 - 0.5 * co) ** 5)
        else:
            raise ValueError(f"unknown view factor {factor!r}")
    return w


def evaluate_terms(terms, wi, wo):
    """Sum of the closures in ``terms`` (list of ``Term``), f in 1/sr, RGB (..., 3).

    A term with a ``tilt`` is evaluated in the frame of its tilted normal N' (``tilted_normal``), as
    Cycles does with a linked Normal: its eval is f' cos(wi, N'), so f = f' (wi.N') / (wi.N), and it
    is 0 where wi lies on different sides of N and N' (``bump_shadowing_term``, closure/bsdf.h).
    """
    total = None
    frames = {}  # tilt -> (wi, wo in the tilted frame, cos ratio): terms of one law share their tilt
    for term in terms:
        if float(term.tilt) != 0.0:
            f = _tilted_term(term, wi, wo, frames)
            total = f if total is None else total + f
            continue
        c = term.closure
        if c == "diffuse":
            f = lambert(wi, wo)
        elif c == "oren_nayar":
            # the albedo enters non-linearly (energy compensation): the term colour is the albedo.
            f = oren_nayar(wi, wo, term.roughness, term.color)
        elif c == "microfacet":
            f = microfacet(wi, wo, term.alpha_x, term.alpha_y, term.distribution, term.fresnel,
                           term.f0, term.ior, term.k)
        elif c == "ashikhmin_shirley":
            f = ashikhmin_shirley(wi, wo, term.alpha_x, term.alpha_y)
        elif c == "phong_ramp":
            f = phong_ramp(wi, wo, term.exponent)
        elif c == "toon":
            f = toon_glossy(wi, wo, term.size, term.smooth)
        elif c == "mirror":
            # A delta lobe has no finite value off the mirror direction.
            f = np.zeros(np.broadcast_shapes(np.shape(wi), np.shape(wo)))
        else:
            raise ValueError(f"unknown closure {c!r}")
        if c != "oren_nayar":
            f = f * _rgb(term.color)
        if term.view:
            f = f * view_weight(term.view, np.broadcast_to(wo, np.shape(f)))[..., None]
        total = f if total is None else total + f
    if total is None:
        total = np.zeros(np.broadcast_shapes(np.shape(wi), np.shape(wo)))
    return total


def _tilted_term(term, wi, wo, frames):
    """One isotropic term with a tilted normal (see ``evaluate_terms``), f in 1/sr, RGB (..., 3)."""
    from dataclasses import replace

    if term.closure not in ("microfacet", "toon") or abs(float(term.alpha_x) - float(term.alpha_y)) > 1e-12:
        raise ValueError(f"a tilted normal is modelled for isotropic microfacet and toon terms, not {term.closure!r}")
    key = float(term.tilt)
    if key not in frames:
        wi_, wo_ = np.broadcast_arrays(np.asarray(wi, dtype=float), np.asarray(wo, dtype=float))
        n = tilted_normal(wo_, key)
        wi_t, wo_t = _in_frame(wi_, n), _in_frame(wo_, n)
        ci, ci_t = wi_[..., 2], wi_t[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where((ci > 0) & (ci_t > 0) & (wo_[..., 2] > 0), ci_t / np.maximum(ci, _EPS), 0.0)
        frames[key] = (wi_t, wo_t, scale)
    wi_t, wo_t, scale = frames[key]
    if term.closure == "toon":  # the angle is shared by every ramp of the law
        if (key, "angle") not in frames:
            frames[key, "angle"] = _toon_angle(wi_t, wo_t)
        f = _toon_f(frames[key, "angle"], wi_t[..., 2], wo_t[..., 2], term.size, term.smooth) * _rgb(term.color)
    else:
        f = evaluate_terms([replace(term, tilt=0.0, view=())], wi_t, wo_t)
    f = f * scale[..., None]
    if term.view:
        f = f * view_weight(term.view, wo)[..., None]
    return f

"""Fit Cycles closure networks to Radiometer's numpy BRDFs and measure how close they are (no bpy).

The comparison is between two numpy functions: the library model ``radiometer.brdf.evaluate`` and
the closure network ``shading.closures.evaluate_terms`` (a transcription of the Cycles kernel,
checked against Cycles renders). Two numbers describe the fidelity:

* ``rms_rel_diff``: the weighted RMS relative difference over a fixed set S of direction pairs,

      sqrt( sum_S w |f_c - f_m|^2 ) / sqrt( sum_S w |f_m|^2 ),   w = cos(theta_i) cos(theta_o),

  summed over the three colour channels. S is a grid of 8 x 8 polar angles (uniform in cos theta,
  3 to 80 deg: extreme grazing, where every model is unreliable, is left out) times 4 x 16 azimuths, plus points around the mirror direction of each theta_i at
  0, 0.5, 1, 2 and 4 lobe widths (so that narrow lobes are not missed).
* ``albedo_diff``: max over theta_i in {0, 30, 60, 75} deg and channels of |rho_c - rho_m|, with
  rho(theta_i) = integral of f cos(theta_o) d omega_o, both by the same Gauss-Legendre (cos theta) x
  uniform (phi) quadrature, 96 x 192 points (dimensionless).

Fitting minimises ``rms_rel_diff`` over the closure's shape parameters (Nelder-Mead on their
logarithms, from the analytic guess) with the colour weights (in [0, 1]) of each candidate solved
by bounded least squares at every step; the candidate with the smallest difference wins. Both
optimisers are numpy-only (``shading.optim``: Stark-Parker BVLS, Nelder-Mead), as Blender has no scipy.

References
----------
Ngan, Durand, Matusik (2005), "Experimental analysis of BRDF models", EGSR: fitting analytic BRDFs by
minimising a cosine-weighted difference over directions.
Walter et al. (2007), sec. 5.2: Blinn-Phong exponent n ~ 2 / alpha_beckmann^2 - 2.
"""

from dataclasses import dataclass, field, replace

import numpy as np

from . import closures as C
from .optim import bvls, nelder_mead

_DEG = np.pi / 180.0
ALBEDO_ANGLES_DEG = (0.0, 30.0, 60.0, 75.0)


def _dir(theta, phi):
    st = np.sin(theta)
    return np.stack([st * np.cos(phi), st * np.sin(phi), np.cos(theta)], axis=-1)


def direction_set(lobe_width=0.2):
    """(wi, wo) arrays (N, 3) of the comparison set S described in the module docstring.

    Parameters
    ----------
    lobe_width : float
        Angular width of the narrowest lobe in rad (e.g. alpha, or 1/sqrt(n) for Phong exponents).
    """
    mu = np.linspace(np.cos(80 * _DEG), np.cos(3 * _DEG), 8)
    th = np.arccos(mu)
    phi_i = np.array([0.0, 45.0, 90.0, 135.0]) * _DEG
    phi_o = np.arange(16) * (360.0 / 16) * _DEG
    ti, pi_, to, po = np.meshgrid(th, phi_i, th, phi_o, indexing="ij")
    wi = _dir(ti.ravel(), pi_.ravel())
    wo = _dir(to.ravel(), (pi_ + po).ravel())
    # near the mirror direction (theta_o = theta_i, phi_o = phi_i + pi), offsets in theta and phi
    w = float(np.clip(lobe_width, 1e-3, 1.0))
    offsets = np.array([0.0, 0.5, 1.0, 2.0, 4.0]) * w
    near_i, near_o = [], []
    for t in th:
        for p in phi_i:
            for d in offsets:
                steps = ((0.0, 0.0),) if d == 0 else ((d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d))
                for dt, dp in steps:
                    to_ = t + dt
                    if 0.0 < to_ <= 80 * _DEG:
                        near_i.append(_dir(t, p))
                        near_o.append(_dir(to_, p + np.pi + dp / max(np.sin(to_), 0.05)))
    wi = np.concatenate([wi, np.array(near_i)])
    wo = np.concatenate([wo, np.array(near_o)])
    return wi, wo


def rms_rel_diff(f_closure, f_model, wi, wo):
    """Weighted RMS relative difference (dimensionless), see module docstring."""
    w = (wi[..., 2] * wo[..., 2])[..., None]
    num = np.sum(w * (f_closure - f_model) ** 2)
    den = np.sum(w * f_model ** 2)
    return float(np.sqrt(num / den)) if den > 0 else float(np.sqrt(num))


_QUAD = {}


def _quadrature(n_mu=96, n_phi=192):
    key = (n_mu, n_phi)
    if key not in _QUAD:
        x, wx = np.polynomial.legendre.leggauss(n_mu)
        mu = 0.5 * (x + 1.0)
        wmu = 0.5 * wx
        phi = (np.arange(n_phi) + 0.5) * (2 * np.pi / n_phi)
        M, P = np.meshgrid(mu, phi, indexing="ij")
        wo = _dir(np.arccos(M.ravel()), P.ravel())
        # d omega = d mu d phi; the cos(theta_o) factor of the albedo is mu
        weight = (wmu[:, None] * (2 * np.pi / n_phi) * mu[:, None] * np.ones((1, n_phi))).ravel()
        _QUAD[key] = (wo, weight)
    return _QUAD[key]


def directional_albedo(f, theta_i_deg=ALBEDO_ANGLES_DEG):
    """rho(theta_i) = integral f(wi, wo) cos(theta_o) d omega_o for f(wi, wo) -> (..., 3); (n, 3)."""
    wo, weight = _quadrature()
    out = []
    for t in theta_i_deg:
        wi = np.broadcast_to(_dir(t * _DEG, 0.0), wo.shape)
        out.append(np.sum(f(wi, wo) * weight[:, None], axis=0))
    return np.array(out)


@dataclass
class Candidate:
    """A closure network with free shape parameters.

    ``build(x) -> list of Term`` (colour 1 where ``linear`` is True: its weight is then solved);
    ``x0`` the starting shape (in the log domain when ``log`` is True); ``bounds`` (lo, hi) per x.
    """

    name: str
    build: object
    x0: tuple = ()
    linear: tuple = ()  # per term: 'rgb' (per-channel weight), 'scalar' (one weight) or None (fixed)
    bounds: tuple = ()
    description: str = ""
    fitted_names: tuple = ()


@dataclass
class FitResult:
    terms: list
    rms_rel_diff: float
    albedo_diff: float
    candidate: str
    fitted: dict = field(default_factory=dict)


def _solve_weights(terms, linear, wi, wo, f_model):
    """Non-negative weights for the linear terms (least squares with weight cos_i cos_o)."""
    sw = np.sqrt(wi[..., 2] * wo[..., 2])
    fixed = np.zeros_like(f_model)
    cols = []
    for t, lin in zip(terms, linear):
        if lin is None:
            fixed = fixed + C.evaluate_terms([t], wi, wo)
        else:
            cols.append((t, lin, C.evaluate_terms([replace(t, color=(1.0, 1.0, 1.0))], wi, wo)))
    resid = f_model - fixed
    out = [t for t, lin in zip(terms, linear) if lin is None]
    if not cols:
        return out
    # scalar terms share one weight over the three channels; rgb terms one weight per channel
    n_scalar = [c for c in cols if c[1] == "scalar"]
    n_rgb = [c for c in cols if c[1] == "rgb"]
    rows_A, rows_b = [], []
    ncol = len(n_scalar) + 3 * len(n_rgb)
    for ch in range(3):
        A = np.zeros((len(sw), ncol))
        for j, (_, _, e) in enumerate(n_scalar):
            A[:, j] = e[..., ch] * sw
        for j, (_, _, e) in enumerate(n_rgb):
            A[:, len(n_scalar) + 3 * j + ch] = e[..., ch] * sw
        rows_A.append(A)
        rows_b.append(resid[..., ch] * sw)
    A = np.concatenate(rows_A)
    b = np.concatenate(rows_b)
    # weights in [0, 1]: a closure with weight <= 1 never reflects more than it receives
    x = bvls(A, b, 0.0, 1.0).x
    for j, (t, _, _) in enumerate(n_scalar):
        out.append(replace(t, color=(float(x[j]),) * 3))
    for j, (t, _, _) in enumerate(n_rgb):
        k = len(n_scalar) + 3 * j
        out.append(replace(t, color=tuple(float(v) for v in x[k:k + 3])))
    return [t for t in out if max(t.color) > 0 or t.closure == "oren_nayar"]


def fit_candidate(candidate, f_model, wi, wo):
    """Fit one candidate; return (terms, rms_rel_diff, x)."""
    fm = f_model(wi, wo)
    lo = np.array([b[0] for b in candidate.bounds], dtype=float)
    hi = np.array([b[1] for b in candidate.bounds], dtype=float)

    def terms_at(x):
        x = np.clip(x, lo, hi)
        return _solve_weights(candidate.build(np.exp(x)), candidate.linear, wi, wo, fm), x

    def cost(x):
        terms, _ = terms_at(x)
        return rms_rel_diff(C.evaluate_terms(terms, wi, wo), fm, wi, wo)

    x0 = np.clip(np.log(np.asarray(candidate.x0, dtype=float)), lo, hi)
    if len(x0):
        res = nelder_mead(cost, x0, xatol=1e-3, fatol=1e-5, maxiter=120 * len(x0))
        x = res.x if res.fun <= cost(x0) else x0
    else:
        x = x0
    terms, x = terms_at(x)
    return terms, cost(x), np.exp(x)


def fit(candidates, f_model, lobe_width=0.2):
    """Fit every candidate, keep the best; measure rms and albedo difference on the full set.

    The optimisation runs on every 3rd pair of the set (speed: re-fits happen on every UI edit);
    the reported numbers use the whole set.
    """
    wi, wo = direction_set(lobe_width)
    sub = slice(None, None, 3)
    best = None
    for cand in candidates:
        terms, err, x = fit_candidate(cand, f_model, wi[sub], wo[sub])
        err = rms_rel_diff(C.evaluate_terms(terms, wi, wo), f_model(wi, wo), wi, wo)
        if best is None or err < best[1]:
            best = (cand, err, x, terms)
    cand, err, x, terms = best
    fitted = {n: float(v) for n, v in zip(cand.fitted_names, x)}
    return FitResult(terms, err, albedo_difference(terms, f_model), cand.name, fitted)


def measure(terms, f_model, lobe_width=0.2):
    """rms_rel_diff and albedo_diff of a fixed network (used for the 'exact' mappings too)."""
    wi, wo = direction_set(lobe_width)
    err = rms_rel_diff(C.evaluate_terms(terms, wi, wo), f_model(wi, wo), wi, wo)
    return err, albedo_difference(terms, f_model)


def albedo_difference(terms, f_model):
    rc = directional_albedo(lambda a, b: C.evaluate_terms(terms, a, b))
    rm = directional_albedo(f_model)
    return float(np.max(np.abs(rc - rm)))


# -- pointwise metrics on a fixed uniform direction set -----------------------------------------

UNIFORM_MAX_THETA_DEG = 85.0
_UNIFORM = {}


def uniform_direction_set(n=160):
    """(wi, wo) of all pairs of a fixed set of ``n`` directions, uniform in solid angle.

    The directions are a spherical Fibonacci set on the cap theta <= 85 deg (cos theta uniform, golden-angle
    azimuths), so every part of the hemisphere counts by its solid angle, not by where a lobe is: n = 160
    gives 25 600 pairs (cost ~10 ms per model evaluation).
    """
    if n not in _UNIFORM:
        i = np.arange(n) + 0.5
        mu = 1.0 - (1.0 - np.cos(UNIFORM_MAX_THETA_DEG * _DEG)) * i / n
        phi = i * np.pi * (3.0 - np.sqrt(5.0))
        d = _dir(np.arccos(mu), phi)
        wi = np.repeat(d, n, axis=0)
        wo = np.tile(d, (n, 1))
        _UNIFORM[n] = (wi, wo)
    return _UNIFORM[n]


#: A pair counts in the pointwise statistics when its reflected radiance f cos_i (per unit incident
#: radiance from that direction, seen along wo) is at least this fraction of the largest over the set.
SIGNIFICANT = 1e-3


@dataclass
class Pointwise:
    """Ratio statistics q = f_closure / f_model over significant pairs of the uniform set.

    ``rms``: cos-weighted RMS relative difference (``rms_rel_diff``) on the uniform set; ``median``:
    median of q; ``p95``: 95th percentile of max(q, 1/q) (95 % of pairs lie within this factor);
    ``max``: the largest max(q, 1/q); ``q_lo``, ``q_hi``: the smallest and largest q (render checks);
    ``n``: number of (pair, channel) values.
    """

    rms: float
    median: float
    p95: float
    max: float
    q_lo: float
    q_hi: float
    n: int

    def to_dict(self):
        return {k: getattr(self, k) for k in ("rms", "median", "p95", "max", "q_lo", "q_hi", "n")}


def pointwise(f_closure, f_model, wi, wo):
    """:class:`Pointwise` of two (N, 3) arrays of f on the pairs (wi, wo)."""
    w = (wi[..., 2])[..., None]
    sig = f_model * w
    mask = sig >= SIGNIFICANT * np.max(sig) if np.max(sig) > 0 else np.zeros_like(sig, dtype=bool)
    mask &= f_model > 0
    rms = rms_rel_diff(f_closure, f_model, wi, wo)
    if not mask.any():
        return Pointwise(rms, 1.0, 1.0, 1.0, 1.0, 1.0, 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = f_closure[mask] / f_model[mask]
        sym = np.where(q > 0, np.maximum(q, 1.0 / q), np.inf)
    return Pointwise(rms, float(np.median(q)), float(np.percentile(sym, 95)), float(np.max(sym)),
                     float(np.min(q)), float(np.max(q)), int(mask.sum()))


def measure_pointwise(f_closure, f_model):
    """:func:`pointwise` of two functions f(wi, wo) -> (N, 3) on :func:`uniform_direction_set`."""
    wi, wo = uniform_direction_set()
    return pointwise(np.asarray(f_closure(wi, wo), dtype=float), np.asarray(f_model(wi, wo), dtype=float), wi, wo)


#: Weight of the RMS log ratio in the cost of :func:`fit_coefficients`.
LOG_WEIGHT = 0.2


def fit_coefficients(build, specs, f_model, lobe_width=0.2):
    """Fit a law's coefficients: Nelder-Mead on their logarithms within bounds, from the starts.

    ``build(c) -> terms``; ``specs`` is a list of (name, start, (lo, hi)). The cost is the cos-weighted RMS
    relative difference on :func:`direction_set` (every 3rd pair, plus every 7th pair of the uniform set,
    so that the lobe and the rest of the hemisphere both count). Returns (coefficients dict, cost).
    """
    wi_a, wo_a = direction_set(lobe_width)
    wi_u, wo_u = uniform_direction_set()
    wi = np.concatenate([wi_a[::3], wi_u[::7]])
    wo = np.concatenate([wo_a[::3], wo_u[::7]])
    fm = f_model(wi, wo)
    names = [s[0] for s in specs]
    lo = np.log([s[2][0] for s in specs])
    hi = np.log([s[2][1] for s in specs])

    def coef(x):
        # exponents may be 0: fit log(1 + k) for them
        return {n: float(np.exp(v)) for n, v in zip(names, np.clip(x, lo, hi))}

    sig = fm * wi[..., 2:3]
    mask = (sig >= SIGNIFICANT * sig.max()) & (fm > 0) if sig.max() > 0 else np.zeros_like(fm, dtype=bool)

    def cost(x):
        fc = C.evaluate_terms(build(coef(x)), wi, wo)
        with np.errstate(divide="ignore", invalid="ignore"):
            lq = np.log(np.maximum(fc[mask], 1e-30) / fm[mask])
        # RMS relative difference (the lobe) plus a share of the RMS log ratio (every significant pair)
        return rms_rel_diff(fc, fm, wi, wo) + LOG_WEIGHT * float(np.sqrt(np.mean(lq * lq))) if mask.any() else 0.0

    x0 = np.clip(np.log([max(s[1], 1e-6) for s in specs]), lo, hi)
    res = nelder_mead(cost, x0, xatol=1e-3, fatol=1e-5, maxiter=150 * len(x0))
    x = res.x if res.fun <= cost(x0) else x0
    return coef(x), cost(x)

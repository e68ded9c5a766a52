"""Public, name-based access to the BRDF models (see the package docstring for conventions)."""

import math

import numpy as np

from .frame import normalize
from .models import MODELS

__all__ = ["names", "get_model", "evaluate", "pdf", "sample", "albedo", "describe", "reflectance",
           "hammersley", "ALBEDO_SAMPLES"]

_Z = np.array([0.0, 0.0, 1.0])

#: Points per strategy of the deterministic albedo quadrature (two strategies, MIS).
ALBEDO_SAMPLES = 4096


def names():
    """Registry names of all models, in a stable order."""
    return list(MODELS)


def get_model(model):
    try:
        return MODELS[model]
    except (KeyError, TypeError):
        raise ValueError(f"unknown BRDF model {model!r}; valid names: {names()}") from None


def _prepare(*dirs):
    """Broadcast and normalise directions; return (unit dirs, nan mask)."""
    arrs = np.broadcast_arrays(*[np.asarray(d, dtype=float) for d in dirs])
    if arrs[0].shape[-1:] != (3,):
        raise ValueError(f"directions must have shape (..., 3), got {arrs[0].shape}")
    units = [normalize(a) for a in arrs]
    nan = np.zeros(units[0].shape[:-1], dtype=bool)
    for u in units:
        nan |= np.isnan(u).any(axis=-1)
    return units, nan


def _eval_unit(m, p, wi, wo):
    """f on unit directions: 0 below either horizon. NaN-free input assumed (already masked)."""
    valid = (wi[..., 2] > 0) & (wo[..., 2] > 0)
    # Substitute the normal for masked directions so the model never sees invalid input.
    wi_s = np.where(valid[..., None], wi, _Z)
    wo_s = np.where(valid[..., None], wo, _Z)
    f = m.f(wi_s, wo_s, p)
    return np.where(valid[..., None], f, 0.0)


def evaluate(model, wi, wo, **params):
    """BRDF value f(wi, wo) [1/sr], WITHOUT the cosine factor, as RGB.

    Parameters
    ----------
    model : str
        One of :func:`names`.
    wi, wo : array_like, shape (..., 3)
        Light and view directions in the LOCAL shading frame (z = normal), pointing away from the
        surface; broadcast against each other; need not be unit length.
    **params
        Model parameters (see :func:`describe`); scalars broadcast to RGB.

    Returns
    -------
    ndarray, shape (..., 3)
        f in 1/sr, always RGB. 0 where cos θi <= 0 or cos θo <= 0; NaN exactly for elements whose
        wi or wo contains NaN. Infinite components are taken as limit directions. Delta models
        (``mirror``) return 0 (see :func:`reflectance`).
    """
    m = get_model(model)
    p = m.resolve(**params)
    (wi, wo), nan = _prepare(wi, wo)
    wi = np.where(nan[..., None], _Z, wi)
    wo = np.where(nan[..., None], _Z, wo)
    f = _eval_unit(m, p, wi, wo)
    return np.where(nan[..., None], np.nan, f)


def _require_sampling(m):
    if not m.samplable:
        raise ValueError(f"model {m.name!r} has no importance sampling"
                         + (" (it is a delta BRDF: use models.MODELS['mirror'].sample_delta)" if m.delta else ""))


def pdf(model, wi, wo, **params):
    """Density [1/sr] with which :func:`sample` (given ``wo``) produces ``wi``, over the sphere.

    Returns shape (...,). 0 where wo is below the horizon; NaN where an input contains NaN.
    """
    m = get_model(model)
    _require_sampling(m)
    p = m.resolve(**params)
    (wi, wo), nan = _prepare(wi, wo)
    ok = (~nan) & (wo[..., 2] > 0) & (np.abs(wi).sum(axis=-1) > 0)
    val = m.pdf(np.where(ok[..., None], wi, _Z), np.where(ok[..., None], wo, _Z), p)
    return np.where(nan, np.nan, np.where(ok, val, 0.0))


def sample(model, wo, u, **params):
    """Importance-sample a light direction wi given the view direction wo.

    Parameters
    ----------
    wo : array_like, shape (..., 3)
        View direction (local frame); need not be unit.
    u : array_like, shape (..., 2)
        Uniform numbers in [0, 1).

    Returns
    -------
    (wi, pdf) : ndarray (..., 3) unit, ndarray (...) [1/sr]
        ``pdf`` equals :func:`pdf` at (wi, wo). wi may lie below the horizon (then f = 0). For wo
        below the horizon no sample exists: wi = 0 vector, pdf = 0. NaN in wo -> NaN out.
    """
    m = get_model(model)
    _require_sampling(m)
    p = m.resolve(**params)
    u = np.asarray(u, dtype=float)
    if u.shape[-1:] != (2,):
        raise ValueError(f"u must have shape (..., 2), got {u.shape}")
    (wo,), nan = _prepare(wo)
    shape = np.broadcast_shapes(wo.shape[:-1], u.shape[:-1])
    wo = np.broadcast_to(wo, shape + (3,))
    nan = np.broadcast_to(nan, shape) | np.isnan(np.broadcast_to(u, shape + (2,))).any(axis=-1)
    ok = (~nan) & (wo[..., 2] > 0)
    u_s = np.clip(np.where(ok[..., None], u, 0.5), 0.0, 1.0 - 2.0 ** -53)
    wi, pd = m.sample(np.where(ok[..., None], wo, _Z), u_s[..., 0], u_s[..., 1], p)
    wi = normalize(wi)
    wi = np.where(nan[..., None], np.nan, np.where(ok[..., None], wi, 0.0))
    pd = np.where(nan, np.nan, np.where(ok, pd, 0.0))
    return wi, pd


def hammersley(n):
    """Deterministic 2D Hammersley point set ((i + 1/2)/n, radical inverse base 2 of i)."""
    i = np.arange(n, dtype=np.uint64)
    bits = i.copy()
    rev = np.zeros(n, dtype=np.uint64)
    for _ in range(32):
        rev = (rev << np.uint64(1)) | (bits & np.uint64(1))
        bits >>= np.uint64(1)
    return (np.arange(n) + 0.5) / n, rev.astype(float) / 2.0 ** 32


def reflectance(cos_theta, **fresnel_params):
    """Reflectance F(cos θ) of the ideal ``mirror`` (its delta weight and directional albedo), RGB (..., 3)."""
    m = MODELS["mirror"]
    p = m.resolve(**fresnel_params)
    c = np.asarray(cos_theta, dtype=float)
    with np.errstate(invalid="ignore"):
        out = m.reflectance(np.clip(c, 0.0, 1.0), p)
    return np.where(np.isnan(c)[..., None], np.nan, np.where((c > 0)[..., None], out, 0.0))


def albedo(model, theta_i, n_samples=ALBEDO_SAMPLES, **params):
    """Directional albedo ρ(θi) = ∫ f(wi, wo) cos θo dωo over the upper hemisphere (dimensionless).

    Deterministic: a Hammersley point set of ``n_samples`` points feeds three strategies, cosine
    and uniform hemisphere sampling and the model's own importance sampling (by reciprocity, sampling wo
    "given wi"), combined with the power heuristic (multiple importance sampling, Veach 1997). The model
    sampler follows the lobe, so sharp lobes (alpha 1e-4, exponents 1e6) are as accurate as broad
    ones. Measured accuracy with the default 4096 points (against 65536-point runs and a 4000x4000
    (cos θ, φ) grid): |error| <= 2.6e-4 absolute for every model and parameter range in the tests
    (alpha 1e-4..1, exponents 0..1e6, θi up to 89.9°); white Lambert to 3e-8. Cost ~10 ms per angle.

    Parameters
    ----------
    theta_i : array_like
        Incidence polar angle(s) [rad], any shape. θi >= π/2 gives 0; NaN gives NaN.

    Returns
    -------
    ndarray, shape theta_i.shape + (3,)
    """
    m = get_model(model)
    p = m.resolve(**params)
    theta = np.asarray(theta_i, dtype=float)
    flat = theta.reshape(-1)
    out = np.zeros(flat.shape + (3,))
    nan = np.isnan(flat)
    cos_i = np.cos(np.where(nan, 0.0, flat))
    ok = (~nan) & (cos_i > 0) & (np.abs(flat) < math.pi / 2)
    wi_all = np.stack([np.sin(np.abs(flat)), np.zeros_like(flat), cos_i], axis=-1)

    if m.delta:
        out = reflectance(np.where(ok, cos_i, 0.0), **params)
    else:
        u1, u2 = hammersley(int(n_samples))
        idx = np.nonzero(ok)[0]
        chunk = max(1, 100_000 // int(n_samples))
        for start in range(0, idx.size, chunk):
            sel = idx[start:start + chunk]
            wi = wi_all[sel][:, None, :]  # (C, 1, 3)
            total = np.zeros((sel.size, 3))
            strategies = [np.broadcast_to(_cosine_dirs(u1, u2), (sel.size, u1.size, 3)),
                          np.broadcast_to(_uniform_dirs(u1, u2), (sel.size, u1.size, 3))]
            if m.samplable:
                x, _ = m.sample(np.broadcast_to(wi, (sel.size, u1.size, 3)), u1[None, :], u2[None, :], p)
                strategies.append(normalize(x))
            for k, x in enumerate(strategies):
                wi_b = np.broadcast_to(wi, x.shape)
                pdfs = [np.maximum(0.0, x[..., 2]) / math.pi, np.full(x.shape[:-1], 0.5 / math.pi)]
                if m.samplable:
                    pdfs.append(m.pdf(x, wi_b, p))
                f = _eval_unit(m, p, wi_b, x)
                # Power heuristic (β = 2): a cosine sample that lands in a needle-like lobe gets
                # weight ~ (p_cos/p_lobe)², not the ~1/N spike the balance heuristic leaves.
                with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                    contrib = f * (np.maximum(0.0, x[..., 2]) * pdfs[k]
                                   / sum(q * q for q in pdfs))[..., None]
                # The denominator is 0 only where this strategy's own pdf is 0 (f cos = 0 there).
                contrib = np.where(np.isfinite(contrib), contrib, 0.0)
                total += contrib.sum(axis=1) / u1.size
            out[sel] = total
    out = np.where(nan[:, None], np.nan, out)
    return out.reshape(theta.shape + (3,))


def _uniform_dirs(u1, u2):
    # Uniform hemisphere (density 1/(2π)): covers grazing outgoing directions, where the cosine
    # density vanishes but f can be large (Oren-Nayar's tan β term at grazing incidence).
    z = u1
    r = np.sqrt(np.maximum(0.0, 1 - z * z))
    phi = 2 * math.pi * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def _cosine_dirs(u1, u2):
    r = np.sqrt(u1)
    phi = 2 * math.pi * u2
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - u1)], axis=-1)


def describe(model):
    """Stable description of a model for UIs and docs.

    Returns a dict with keys ``name``, ``doc``, ``references`` (list of str), ``parameters``
    (list of dicts with ``name, default, min, max, kind ('float'|'color'), unit, description,
    optional, group, ui_default``), ``options`` (non-numeric choices: name -> {values, default}),
    ``samplable``, ``delta``, ``reciprocal``, ``isotropic`` and ``units``.
    """
    return get_model(model).describe()

"""The reflected light's spectrum by band renders, with a proven band bound (pure numpy; issue 35).

An RGB renderer is a three-band spectral renderer whose bands are whatever its channels hold. Render the
light with every material's colour set, per channel, to its reflectance in one wavelength band and every
light's colour to its radiant power in that band, and a channel reads that band's light.

**Bands.** 380-780 nm at 1 nm is cut into contiguous bands (sets of the 1 nm samples CIE S 026 sums over)
so that within each band every material's reflectance varies by at most ``tol`` (:func:`plan_bands`).

**The bound.** Every rendered path's contribution at wavelength lambda is the light's power at lambda
times a product of the reflectances it met at lambda (Lambertian and Principled diffuse colours:
multiplicative and non-negative). So the rendered irradiance per unit light power G(lambda) is
non-decreasing in every material's reflectance, and for every lambda in band b

    G(rho_min,b) <= G(lambda) <= G(rho_max,b),

rho_min,b / rho_max,b every material's lowest / highest reflectance over the band's samples. Two channels
per band render G at both ends. For a weighting w (V for E_v, s_alpha for alpha-opic irradiance) the
band's part, sum over lambda in b of P(lambda) w(lambda) G(lambda), lies in
[A_b G(rho_min,b), A_b G(rho_max,b)], A_b = sum over b of P w >= 0: **proven**, whatever the spectra do
inside the band. The estimate interpolates between the two ends by where the materials' reflectances lie
in their band range (``t``, weighted by P w); its deterministic error is the larger distance to an end.

**Several lights.** A channel holds sum over lights of P_l,b G_l; with light l's ratio
r_l,b = A_l,b / P_l,b the band's part lies in [min_l r_l,b x R_min, max_l r_l,b x R_max] (one light:
the ratio is exact).

**Stochastic error.** Channels of one render share its paths (correlated: their standard errors add
linearly within a render, a conservative choice); renders use different seeds (independent: add in
quadrature).

Not covered (said by the caller): light the bounce limit cuts off (Cycles' own truncation, as for any
rendered reading), materials that are not diffuse or Principled with a plain colour, emitting surfaces
and the world.
"""

import numpy as np

from .spectral import WAVELENGTHS_NM

__all__ = ["plan_bands", "band_table", "channel_layout", "combine"]

#: Default largest number of bands; each takes two channels (its low and high end), 3 channels a render.
MAX_BANDS = 24


def _bands_at(refl, tol):
    edges = [0]
    lo, hi = refl[:, 0].copy(), refl[:, 0].copy()
    for i in range(1, refl.shape[1]):
        lo2, hi2 = np.minimum(lo, refl[:, i]), np.maximum(hi, refl[:, i])
        if np.max(hi2 - lo2) > tol:
            edges.append(i)
            lo, hi = refl[:, i].copy(), refl[:, i].copy()
        else:
            lo, hi = lo2, hi2
    edges.append(refl.shape[1])
    return edges


def plan_bands(reflectances, max_bands=MAX_BANDS):
    """Band edges (sample indices into the 1 nm grid, first 0, last 401) for ``reflectances`` (M, 401):
    the smallest tolerance on every material's within-band range (to 1e-3) that needs at most ``max_bands``."""
    refl = np.atleast_2d(np.asarray(reflectances, float))
    lo, hi = 0.0, float(np.ptp(refl, axis=1).max()) + 1e-9
    if len(_bands_at(refl, lo)) - 1 <= max_bands:
        return _bands_at(refl, lo)
    while hi - lo > 1e-3:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if len(_bands_at(refl, mid)) - 1 <= max_bands else (mid, hi)
    return _bands_at(refl, hi)


def band_table(reflectances, edges):
    """Per band and material: lowest, highest and the 1 nm samples' t in [0, 1] (where each sample lies in
    its band's range; 0.5 where the range is 0). Shapes (B, M), (B, M), and t (M, 401)."""
    refl = np.atleast_2d(np.asarray(reflectances, float))
    b = len(edges) - 1
    rmin = np.stack([refl[:, edges[k]:edges[k + 1]].min(axis=1) for k in range(b)])
    rmax = np.stack([refl[:, edges[k]:edges[k + 1]].max(axis=1) for k in range(b)])
    t = np.full(refl.shape, 0.5)
    for k in range(b):
        span = (rmax[k] - rmin[k])[:, None]
        seg = refl[:, edges[k]:edges[k + 1]]
        t[:, edges[k]:edges[k + 1]] = np.where(span > 0, (seg - rmin[k][:, None]) / np.where(span > 0, span, 1.0),
                                               0.5)
    return rmin, rmax, t


def channel_layout(n_bands):
    """Renders as lists of up to 3 (band, end) channels, end 0 (lowest reflectances) or 1 (highest)."""
    channels = [(b, end) for b in range(n_bands) for end in (0, 1)]
    return [channels[i:i + 3] for i in range(0, len(channels), 3)]


def band_sums(values, edges):
    """Sum of ``values`` (..., 401) over each band: (..., B)."""
    values = np.asarray(values, float)
    return np.stack([values[..., edges[k]:edges[k + 1]].sum(axis=-1) for k in range(len(edges) - 1)], axis=-1)


def combine(edges, light_power, weights, t, channel_values, channel_se, layout, channel_bound=None, source_gain=None):
    """Band renders -> a weighted quantity with its bounds.

    ``light_power`` (L, 401): each light's radiant power per 1 nm sample, in the units the renders used
    for light colour x strength (its band sums are what the light's colour channels held);
    ``weights`` (Q, 401): the weightings (V, s_alpha ...); ``t`` (401,): where the materials' reflectances
    lie in their band range (mean over materials); ``channel_values`` / ``channel_se`` {(band, end): R, s.e.}
    of the rendered band irradiance; ``channel_bound`` {(band, end): b}: a deterministic bound on a channel's
    value (the meter's own, e.g. a caustic's), widening the range. ``source_gain`` (L,): how much of each
    source's band power reaches the meter (its light at the meter per unit of the power the renders gave it,
    from a render of that source alone): the estimate inside a band weights the sources' spectra by what
    reaches the meter, not by the powers alone (which need not share a unit: a lamp's watts, a world's power
    per unit luminance). None, or no source reaching the meter: by the powers. The bounds never use it.
    Returns dict of arrays (Q,): ``estimate``, ``lower``, ``upper`` (the band range, before noise),
    ``std_error`` (stochastic, 1 sigma).
    """
    p = np.asarray(light_power, float)
    w = np.atleast_2d(np.asarray(weights, float))
    pb = band_sums(p, edges)  # (L, B)
    ab = band_sums(p[:, None, :] * w[None, :, :], edges)  # (L, Q, B)
    gain = None if source_gain is None else np.asarray(source_gain, float).reshape(-1)
    if gain is not None and not (gain.shape == (len(p),) and np.all(np.isfinite(gain)) and np.all(gain >= 0.0)
                                 and gain.sum() > 0.0):
        gain = None
    received = p if gain is None else p * gain[:, None]  # (L, 401): what reaches the meter, per source
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(pb[:, None, :] > 0, ab / np.where(pb[:, None, :] > 0, pb[:, None, :], 1.0), 0.0)
        # where the band's P w is centred between its ends (the estimate's interpolation weight)
        pw = received.sum(axis=0)[None, :] * w  # (Q, 401)
        tw = band_sums(pw * t[None, :], edges) / np.where(band_sums(pw, edges) > 0, band_sums(pw, edges), 1.0)
    rmin_ratio, rmax_ratio = ratio.min(axis=0), ratio.max(axis=0)  # (Q, B)
    rb = band_sums(received, edges).sum(axis=0)  # (B,)
    r_mean = band_sums(pw, edges) / np.where(rb > 0, rb, 1.0)[None, :]  # (Q, B)
    nb = len(edges) - 1
    lo_v = np.array([channel_values[(b, 0)] for b in range(nb)])
    hi_v = np.array([channel_values[(b, 1)] for b in range(nb)])
    est = np.sum(r_mean * (lo_v + tw * (hi_v - lo_v)), axis=1)
    lower = np.sum(rmin_ratio * lo_v, axis=1)
    upper = np.sum(rmax_ratio * hi_v, axis=1)
    if channel_bound:
        lower -= np.sum(rmin_ratio * np.array([channel_bound.get((b, 0), 0.0) for b in range(nb)]), axis=1)
        upper += np.sum(rmax_ratio * np.array([channel_bound.get((b, 1), 0.0) for b in range(nb)]), axis=1)
    var = np.zeros(w.shape[0])
    for render in layout:
        s = np.zeros(w.shape[0])
        for b, end in render:
            coef = r_mean[:, b] * (tw[:, b] if end else (1.0 - tw[:, b]))
            s += np.abs(coef) * channel_se[(b, end)]
        var += s**2
    return {"estimate": est, "lower": lower, "upper": upper, "std_error": np.sqrt(var)}


def box_reflectance(rgb):
    """The stated upsampling of an RGB colour (no spectrum given): the base colour's R on 590-780 nm, G on
    490-589 nm, B on 380-489 nm (white (1, 1, 1) -> 1 everywhere, grey g -> g), clipped to [0, 1]."""
    r, g, b = (min(max(float(c), 0.0), 1.0) for c in rgb[:3])
    wl = WAVELENGTHS_NM
    return np.where(wl >= 590.0, r, np.where(wl >= 490.0, g, b))


def _mallett_basis():
    from . import _spectral_tables as tables

    basis = np.stack([np.interp(WAVELENGTHS_NM, tables.TABLE_WAVELENGTHS, getattr(tables, f"MALLETT2019_{k}"))
                      for k in "RGB"])
    return basis / basis.sum(axis=0)  # sums to 1 within 1e-5 as published: exactly, so white is 1 and grey flat


#: Mallett & Yuksel's sRGB reflectance basis (R, G, B) at 1 nm, renormalised to sum to 1 (:func:`mallett_reflectance`).
MALLETT2019_BASIS = _mallett_basis()


def mallett_reflectance(rgb):
    """A reflectance spectrum for a linear Rec.709 (sRGB primaries) colour with no spectrum given: the spectral
    primary decomposition of Mallett & Yuksel, "Spectral Primary Decomposition for Rendering with sRGB
    Reflectance", EGSR 2019: r B_R + g B_G + b B_B, the published basis at 1 nm (linear interpolation of its 5 nm
    table) renormalised to sum to 1; ``rgb`` clipped to [0, 1] (the basis reproduces reflectances of sRGB
    colours in that cube, and the spectrum then lies in [0, 1]). White is 1, a grey g is g at every wavelength,
    and the spectrum's Rec.709 colour under D65 is ``rgb`` again (the decomposition's round trip)."""
    c = np.clip(np.asarray(rgb, float)[..., :3], 0.0, 1.0)
    out = c @ MALLETT2019_BASIS
    # a grey is flat to the last bit (the basis sums to 1 only to ~2e-16 after renormalising)
    grey = (c[..., 0] == c[..., 1]) & (c[..., 1] == c[..., 2])
    return np.where(grey[..., None], c[..., :1], out)


#: The upsampling's relative error bound (fraction of the rendered part) for E_v and each alpha-opic quantity: the largest error of
#: taking every material's spectrum as :func:`mallett_reflectance` of its Rec.709 colour, against its true spectrum,
#: over the family of coloured rooms of :data:`RGB_ONLY_REL_BOUND` (both solved by the same spectral radiosity at 5
#: nm; bench/spectral_room_family.md). Measured, not proven: the band range is proven for the assumed spectrum, and
#: a real material is one of its metamers.
UPSAMPLING_REL_BOUND = {"illuminance_lx": 0.061, "s_cone": 0.051, "m_cone": 0.038, "l_cone": 0.089, "rhodopic": 0.103,
                        "melanopic": 0.126}  # measured 6.05, 5.06, 3.71, 8.81, 10.24, 12.55 %, rounded up

#: The box upsampling's bands as 1 nm sample masks, in R, G, B order (:func:`box_reflectance`).
BOX_MASKS = np.stack([WAVELENGTHS_NM >= 590.0, (WAVELENGTHS_NM >= 490.0) & (WAVELENGTHS_NM < 590.0),
                      WAVELENGTHS_NM < 490.0])

#: The RGB-only estimate's relative error bound (fraction of its value) for the reflected part's E_v and
#: mel-EDI: the largest relative error of :func:`rgb_only_estimate` on an RGB radiosity against a
#: spectral radiosity over a family of coloured rooms (23 ColorChecker wall colours x 4 light spectra x 2
#: meters; the saturated red room of issue 35's acceptance left out): bench/spectral_room_family.md. Measured,
#: not proven: a room outside that family (other colours, a coloured floor, several coloured surfaces) can
#: exceed it.
RGB_ONLY_REL_BOUND = {"illuminance_lx": 0.130, "mel_edi_lx": 0.172}  # measured 12.98 % and 17.14 %, rounded up


def rgb_only_estimate(rendered_rgb, light_rgb, light_power, weights):
    """The rendered part's weighted sums from its RGB alone (no reflectance spectra), with a stated assumption:
    the room's gain in each box band (B 380-489, G 490-589, R 590-780 nm) is the RGB render's gain in that
    channel, G_c = rendered_c / light_rgb_c, so the part is sum_c G_c sum over band c of P w.

    ``rendered_rgb`` (3,): the meter's rendered irradiance; ``light_rgb`` (3,): the lights' power x colour
    summed; ``light_power`` (401,): their radiant power per 1 nm sample (its V-sum their Y-weighted power);
    ``weights`` (Q, 401). Returns (Q,)."""
    rgb, lrgb = np.asarray(rendered_rgb, float), np.asarray(light_rgb, float)
    gain = np.where(lrgb > 0, rgb / np.where(lrgb > 0, lrgb, 1.0), 0.0)
    band = (np.asarray(light_power, float)[None, None, :] * BOX_MASKS[None, :, :]
            * np.atleast_2d(np.asarray(weights, float))[:, None, :]).sum(axis=-1)  # (Q, 3)
    return band @ gain

"""Photometry: RGB luminance weights, luminous efficacy, and photometric <-> Blender power conversions.

Blender light "watts" are radiometric per RGB channel: a light of power P and colour c emits P*c_i
in channel i. Photometric quantities follow from the luminance of the RGB triple times a luminous
efficacy K: Phi_v = K * (w . P c) lm, with w the Y row of the working space's RGB->XYZ matrix.
The default convention is K = 683 lm/W, as Blender's glTF importer/exporter uses (a white 1 W light
is 683 lm). Radiance's convention is 179 lm/W (equal-energy white).

References
----------
- SMPTE RP 177-1993, *Derivation of Basic Television Color Equations*; C. Poynton, *Digital Video
  and HD* (2012), ch. 26: RGB->XYZ matrix from primaries and white point.
- ITU-R BT.709-6, ITU-R BT.2020-2, SMPTE ST 2065-1 / Academy S-2014-004 (ACEScg, AP1 primaries).
- CIE 018:2019 (V(lambda)), CIE 015:2018 (colour-matching functions); BIPM SI Brochure (683 lm/W).
- M. Planck (1901) blackbody spectral radiance; G. Wyszecki, W. S. Stiles, *Color Science* (1982).
"""

import numpy as np

from . import _cie_tables as cie
from ..constants import C2_M_K, K_M_LM_PER_W, K_RADIANCE_WHITE_LM_PER_W, VISIBLE_RANGE_NM
from ..units import as_finite_array, check_nonnegative, check_positive

__all__ = [
    "COLOUR_SPACES", "EFFICACY", "rgb_to_xyz_matrix", "luminance_weights", "luminance_factor",
    "luminous", "efficacy_of_spectrum", "blackbody_spd", "blackbody_efficacy", "blackbody_rgb",
    "photopic_v", "lumens_to_watts", "watts_to_lumens", "candela_to_watts", "watts_to_candela",
    "lux_to_sun_strength", "sun_strength_to_lux", "nits_to_area_watts", "area_watts_to_nits",
]

_D65_XY = (0.3127, 0.3290)
_REC709 = ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06))

#: Working colour spaces of Blender 5: (primaries xy (3,2), white point xy (2,)).
COLOUR_SPACES = {
    "Rec.709": (_REC709, _D65_XY),
    "Linear Rec.709": (_REC709, _D65_XY),
    "sRGB": (_REC709, _D65_XY),
    "Rec.2020": (((0.708, 0.292), (0.170, 0.797), (0.131, 0.046)), _D65_XY),
    "Linear Rec.2020": (((0.708, 0.292), (0.170, 0.797), (0.131, 0.046)), _D65_XY),
    # AP1 primaries with the ACES white point (~D60), SMPTE ST 2065-1.
    "ACEScg": (((0.713, 0.293), (0.165, 0.830), (0.128, 0.044)), (0.32168, 0.33767)),
}

#: Luminous efficacy conventions, lm/W: Blender/glTF 683, Radiance 179.
EFFICACY = {"blender_683": K_M_LM_PER_W, "radiance_179": K_RADIANCE_WHITE_LM_PER_W}


def _xy_to_xyz(xy):
    xy = np.asarray(xy, dtype=np.float64)
    x, y = xy[..., 0], xy[..., 1]
    return np.stack([x / y, np.ones_like(x), (1.0 - x - y) / y], axis=-1)


def rgb_to_xyz_matrix(primaries_xy, whitepoint_xy):
    """Normalised primary matrix (RGB -> XYZ, white maps to Y = 1).

    Parameters
    ----------
    primaries_xy : array_like, shape (3, 2)
        CIE xy chromaticities of the R, G, B primaries.
    whitepoint_xy : array_like, shape (2,)
        CIE xy chromaticity of the white point.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        M with XYZ = M @ RGB; row 1 holds the luminance weights.

    References
    ----------
    SMPTE RP 177-1993 section 3.3; Poynton, *Digital Video and HD* (2012), eq. 26.x: columns are the
    primaries' XYZ (Y = 1) scaled by S = P^-1 W so that RGB = (1,1,1) maps to the white point.
    """
    primaries = as_finite_array(primaries_xy, "primaries_xy", (3, 2))
    white = as_finite_array(whitepoint_xy, "whitepoint_xy", (2,))
    if np.any(primaries[:, 1] <= 0.0) or white[1] <= 0.0:
        raise ValueError("chromaticity y must be > 0")
    p = _xy_to_xyz(primaries).T  # columns = primaries
    w = _xy_to_xyz(white)
    scale = np.linalg.solve(p, w)
    return p * scale[np.newaxis, :]


def luminance_weights(colour_space="Rec.709"):
    """Relative luminance weights (Y row of the RGB->XYZ matrix), shape (3,), summing to 1.

    ``colour_space`` is one of :data:`COLOUR_SPACES` ('Rec.709' = 'Linear Rec.709' = sRGB primaries
    with D65, 'Rec.2020', 'ACEScg').
    """
    try:
        primaries, white = COLOUR_SPACES[colour_space]
    except KeyError:
        raise ValueError(f"unknown colour space {colour_space!r}; known: {sorted(COLOUR_SPACES)}") from None
    return rgb_to_xyz_matrix(primaries, white)[1].copy()


def luminance_factor(rgb, colour_space="Rec.709"):
    """Relative luminance w . rgb of a light colour, dimensionless, (..., 3) -> (...)."""
    rgb = as_finite_array(rgb, "rgb")
    if rgb.shape[-1:] != (3,):
        raise ValueError(f"rgb must have a last axis of 3, got shape {rgb.shape}")
    return rgb @ luminance_weights(colour_space)


def luminous(rgb, colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Photometric value K * (w . rgb) from radiometric RGB, vectorised (..., 3) -> (...).

    W -> lm, W/m^2 -> lux, W/sr -> cd, W/(m^2 sr) -> cd/m^2, with K = ``efficacy`` in lm/W.
    """
    k = float(check_positive(efficacy, "efficacy"))
    return k * luminance_factor(rgb, colour_space)


def photopic_v(wavelengths_nm):
    """CIE 1924 V(lambda), linearly interpolated from the 5 nm table, 0 outside 360-830 nm."""
    wl = as_finite_array(wavelengths_nm, "wavelengths_nm")
    return np.interp(wl, cie.WAVELENGTHS_NM, cie.PHOTOPIC_V, left=0.0, right=0.0)


def efficacy_of_spectrum(wavelengths_nm, spd):
    """Luminous efficacy 683 * int V S dl / int S dl over 360-830 nm, lm/W (trapezoid rule).

    Parameters
    ----------
    wavelengths_nm : array_like, shape (M,)
        Increasing wavelengths, nm.
    spd : array_like, shape (..., M)
        Spectral power distribution (any unit per nm), non-negative, not all zero in range.

    Notes
    -----
    The denominator is the power inside 360-830 nm only (the "visible" efficacy that matches
    Blender's RGB watts), not the total radiant power.
    """
    wl = as_finite_array(wavelengths_nm, "wavelengths_nm")
    s = check_nonnegative(spd, "spd")
    if wl.ndim != 1 or s.shape[-1] != wl.shape[0] or wl.shape[0] < 2 or np.any(np.diff(wl) <= 0):
        raise ValueError("wavelengths_nm must be 1-D, strictly increasing, matching spd's last axis")
    lo, hi = VISIBLE_RANGE_NM
    inside = (wl >= lo) & (wl <= hi)
    wl_in, s_in = wl[inside], s[..., inside]
    denom = np.trapz(s_in, wl_in, axis=-1)
    if np.any(denom <= 0.0):
        raise ValueError("spd has no power inside 360-830 nm")
    return K_M_LM_PER_W * np.trapz(s_in * photopic_v(wl_in), wl_in, axis=-1) / denom


def blackbody_spd(wavelengths_nm, temperature_k, c2_m_k=C2_M_K):
    """Planck spectral radiance, W/(m^2 sr m), shape broadcast of (..., 1) temperature and (M,) wl.

    L(l, T) = 2 h c^2 / l^5 / (exp(c2 / (l T)) - 1), computed with expm1 for accuracy. ``c2_m_k``
    defaults to the exact SI value h c / k = 1.438777e-2 m K; CIE 015 (and colour-science) use
    1.4388e-2 m K (ITS-90), which shifts efficacies by ~2e-5 relative.
    """
    wl_m = as_finite_array(wavelengths_nm, "wavelengths_nm") * 1e-9
    t = np.asarray(check_positive(temperature_k, "temperature_k"), dtype=np.float64)[..., np.newaxis]
    c1 = 2.0 * 6.626_070_15e-34 * 299_792_458.0**2
    with np.errstate(over="ignore"):  # exp overflow -> inf -> radiance 0 (deep Wien tail), intended
        return c1 / wl_m**5 / np.expm1(float(c2_m_k) / (wl_m * t))


def blackbody_efficacy(temperature_k, c2_m_k=C2_M_K):
    """Visible luminous efficacy of a blackbody, lm/W (:func:`efficacy_of_spectrum` of Planck).

    About 114 lm/W at 2700 K: the named "blackbody at a temperature" efficacy convention.
    """
    wl = cie.WAVELENGTHS_NM
    return efficacy_of_spectrum(wl, blackbody_spd(wl, temperature_k, c2_m_k))


def blackbody_rgb(temperature_k, colour_space="Rec.709"):
    """Linear RGB of a blackbody normalised to luminance Y = 1, shape (..., 3).

    CIE 1931 2 degree XYZ of Planck's law (5 nm sums), converted with the inverse of
    :func:`rgb_to_xyz_matrix`. Blender's ``Light.temperature_color`` is the same quantity from a
    fitted table: a test records the difference.
    """
    wl = cie.WAVELENGTHS_NM
    spd = blackbody_spd(wl, temperature_k)
    xyz = np.stack([spd @ cie.CMF_XBAR, spd @ cie.CMF_YBAR, spd @ cie.CMF_ZBAR], axis=-1)
    xyz = xyz / xyz[..., 1:2]
    primaries, white = COLOUR_SPACES[colour_space] if colour_space in COLOUR_SPACES else (None, None)
    if primaries is None:
        raise ValueError(f"unknown colour space {colour_space!r}")
    return xyz @ np.linalg.inv(rgb_to_xyz_matrix(primaries, white)).T


def _k_y(colour, colour_space, efficacy):
    y = luminance_factor(colour, colour_space)
    if np.any(y <= 0.0):
        raise ValueError("light colour has zero or negative luminance: no photometric conversion")
    return float(check_positive(efficacy, "efficacy")) * y


def watts_to_lumens(watts, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Luminous flux of a point/spot/area light of Blender power ``watts``: Phi = K Y_c P, lm.

    Y_c = w . colour is the colour's luminance factor. A spot keeps I = P/(4 pi) whatever its cone,
    so its lumens leaving through the cone are fewer; this is the flux of the equivalent point.
    """
    return np.asarray(watts, dtype=np.float64) * _k_y(colour, colour_space, efficacy)


def lumens_to_watts(lumens, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Blender power for a luminous flux: P = Phi / (K Y_c), W (inverse of :func:`watts_to_lumens`)."""
    return np.asarray(lumens, dtype=np.float64) / _k_y(colour, colour_space, efficacy)


def watts_to_candela(watts, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Luminous intensity of a point/spot (inside the cone): I_v = K Y_c P / (4 pi), cd."""
    return watts_to_lumens(watts, colour, colour_space, efficacy) / (4.0 * np.pi)


def candela_to_watts(candela, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Blender point/spot power for an intensity: P = 4 pi I_v / (K Y_c), W."""
    return lumens_to_watts(4.0 * np.pi * np.asarray(candela, dtype=np.float64), colour, colour_space, efficacy)


def sun_strength_to_lux(strength, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Illuminance on a surface facing a sun of strength E (W/m^2): E_v = K Y_c E, lux."""
    return watts_to_lumens(strength, colour, colour_space, efficacy)


def lux_to_sun_strength(lux, colour=(1.0, 1.0, 1.0), colour_space="Rec.709", efficacy=K_M_LM_PER_W):
    """Sun strength for an illuminance: E = E_v / (K Y_c), W/m^2."""
    return lumens_to_watts(lux, colour, colour_space, efficacy)


def area_watts_to_nits(watts, area_m2, colour=(1.0, 1.0, 1.0), colour_space="Rec.709",
                       efficacy=K_M_LM_PER_W):
    """Luminance of a normalised area light: L_v = K Y_c P / (pi A), cd/m^2 (Lambertian emitter)."""
    area = check_positive(area_m2, "area_m2")
    return watts_to_lumens(watts, colour, colour_space, efficacy) / (np.pi * area)


def nits_to_area_watts(nits, area_m2, colour=(1.0, 1.0, 1.0), colour_space="Rec.709",
                       efficacy=K_M_LM_PER_W):
    """Area-light power for a luminance: P = pi A L_v / (K Y_c), W (normalize on)."""
    area = check_positive(area_m2, "area_m2")
    return lumens_to_watts(np.pi * area * np.asarray(nits, dtype=np.float64), colour, colour_space, efficacy)


# Named blackbody conventions (visible efficacy of Planck's law, exact SI c2), lm/W.
EFFICACY["blackbody_2700K"] = float(blackbody_efficacy(2700.0))
EFFICACY["blackbody_6500K"] = float(blackbody_efficacy(6500.0))

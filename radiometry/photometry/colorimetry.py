"""A photographer's readout (pure numpy): exposure values and the colour temperature of light.

Exposure value at ISO 100 (EV100)
---------------------------------
ISO 2720:1974 calibration of exposure meters, with the usual constants:

- incident light (illuminance E in lx on the meter's diffuser): EV = log2(E S / C), S = 100 (ISO),
  C = 250 for a **flat** receptor (the meter's flat sensor, which is what Radiometer's illuminance meter is;
  a hemispherical dome takes C = 340, :data:`C_DOME`);
- reflected light (luminance L in cd/m², a spot meter): EV = log2(L S / K), K = 12.5 (cd s)/(m² ISO),
  the calibration constant of Canon, Nikon and Sekonic meters.

Correlated colour temperature and Duv
-------------------------------------
The light's chromaticity is that of its linear RGB in the scene's working colour space (RGB -> XYZ by
the space's normalised primary matrix, :func:`radiometry.photometry.efficacy.rgb_to_xyz_matrix`): a render has no
spectrum, so the CCT is that of any light metameric to the RGB. CIE 1960 UCS: u = 4X / (X + 15Y + 3Z),
v = 6Y / (X + 15Y + 3Z). CCT is the temperature of the nearest point of the Planckian locus in (u, v)
and Duv the signed distance to it (positive above the locus, towards green), by Ohno's method
(Y. Ohno, "Practical use and calculation of CCT and Duv", LEUKOS 10(1), 2014, 47-55): a cascade of
ever finer tables of the locus around the nearest entry, then his triangular solution on the last
three. The locus is Planck's law (c2 = 1.4388e-2 m K, CIE 015:2018) weighted by the CIE 1931 2° colour
matching functions (5 nm, 360-830 nm). Valid from 1000 K to 100 000 K and |Duv| <= 0.05 (Ohno's range);
outside it :func:`cct_duv` returns nan.
"""

import functools
import math

import numpy as np

from . import _cie_tables as cie
from .efficacy import COLOUR_SPACES, rgb_to_xyz_matrix

__all__ = ["ISO_S", "C_FLAT", "C_DOME", "K_REFLECTED", "ev100_incident", "ev100_reflected", "rgb_to_uv",
           "xyz_to_uv", "planck_uv", "cct_duv", "cct_duv_of_rgb"]

ISO_S = 100.0          #: ISO speed of EV100
C_FLAT = 250.0         #: incident-light calibration constant, flat receptor, lx s / ISO (ISO 2720)
C_DOME = 340.0         #: incident-light calibration constant, hemispherical receptor
K_REFLECTED = 12.5     #: reflected-light calibration constant, cd s / (m^2 ISO)
C2_CIE_M_K = 1.4388e-2  #: second radiation constant as CIE 015 uses it for the Planckian locus, m K

CCT_RANGE_K = (1000.0, 100000.0)
DUV_LIMIT = 0.05


def ev100_incident(illuminance_lx, receptor="flat"):
    """EV100 of incident light: log2(E S / C), S = 100, C = 250 (``receptor`` 'flat') or 340 ('dome').

    ``illuminance_lx`` (lx, array-like); E <= 0 gives -inf (no light, no exposure), nan stays nan.
    """
    c = {"flat": C_FLAT, "dome": C_DOME}.get(receptor)
    if c is None:
        raise ValueError(f"receptor must be 'flat' or 'dome', got {receptor!r}")
    e = np.asarray(illuminance_lx, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(e > 0, np.log2(np.where(e > 0, e, 1.0) * ISO_S / c), np.where(np.isnan(e), np.nan, -np.inf))


def ev100_reflected(luminance_cd_m2):
    """EV100 of reflected light (a spot meter): log2(L S / K), S = 100, K = 12.5; L in cd/m²."""
    lum = np.asarray(luminance_cd_m2, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(lum > 0, np.log2(np.where(lum > 0, lum, 1.0) * ISO_S / K_REFLECTED),
                        np.where(np.isnan(lum), np.nan, -np.inf))


def xyz_to_uv(xyz):
    """CIE 1960 UCS (u, v) of CIE XYZ, shape (..., 3) -> (..., 2); nan where X + 15Y + 3Z = 0."""
    xyz = np.asarray(xyz, float)
    x, y, z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    d = x + 15.0 * y + 3.0 * z
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.stack([np.where(d != 0, 4.0 * x / d, np.nan), np.where(d != 0, 6.0 * y / d, np.nan)], axis=-1)


def rgb_to_uv(rgb, colour_space="Rec.709"):
    """CIE 1960 (u, v) of linear RGB in ``colour_space`` (one of photometry.COLOUR_SPACES), (..., 3) -> (..., 2)."""
    try:
        primaries, white = COLOUR_SPACES[colour_space]
    except KeyError:
        raise ValueError(f"unknown colour space {colour_space!r}; known: {sorted(COLOUR_SPACES)}") from None
    m = rgb_to_xyz_matrix(primaries, white)
    return xyz_to_uv(np.asarray(rgb, float) @ m.T)


def planck_uv(temperature_k):
    """(u, v) of the Planckian locus at ``temperature_k`` (K, array-like) -> (..., 2)."""
    t = np.asarray(temperature_k, float)[..., None]
    wl_m = cie.WAVELENGTHS_NM * 1e-9
    with np.errstate(over="ignore"):
        spd = 1.0 / wl_m**5 / np.expm1(C2_CIE_M_K / (wl_m * t))  # c1 cancels in the chromaticity
    xyz = np.stack([spd @ cie.CMF_XBAR, spd @ cie.CMF_YBAR, spd @ cie.CMF_ZBAR], axis=-1)
    return xyz_to_uv(xyz)


@functools.lru_cache(maxsize=1)
def _coarse_table():
    t = np.geomspace(CCT_RANGE_K[0], CCT_RANGE_K[1], 200)
    return t, planck_uv(t)


def _cct_duv_scalar(u, v):
    if not (math.isfinite(u) and math.isfinite(v)):
        return math.nan, math.nan
    t, uv = _coarse_table()
    for _ in range(4):  # Ohno's cascade: each table 15 entries between the neighbours of the last minimum
        d = np.hypot(uv[:, 0] - u, uv[:, 1] - v)
        i = int(np.argmin(d))
        if i == 0 or i == len(t) - 1:
            return math.nan, math.nan  # nearest point at the end of the range: outside 1000-100000 K
        t = np.geomspace(t[i - 1], t[i + 1], 15)
        uv = planck_uv(t)
    d = np.hypot(uv[:, 0] - u, uv[:, 1] - v)
    i = int(np.clip(np.argmin(d), 1, len(t) - 2))
    # Ohno's triangular solution on the entries around the minimum
    (t0, t2), (p0, p2), (d0, d2) = (t[i - 1], t[i + 1]), (uv[i - 1], uv[i + 1]), (d[i - 1], d[i + 1])
    length = float(np.hypot(*(p2 - p0)))
    x = (d0**2 - d2**2 + length**2) / (2.0 * length)
    cct = t0 + (t2 - t0) * x / length
    v_on_line = p0[1] + (p2[1] - p0[1]) * x / length
    duv = math.copysign(math.sqrt(max(d0**2 - x**2, 0.0)), v - v_on_line)
    if abs(duv) > DUV_LIMIT:
        return math.nan, math.nan
    return float(cct), float(duv)


def cct_duv(uv):
    """(CCT in K, Duv) of CIE 1960 chromaticities ``uv`` (..., 2), Ohno 2014 (see module docstring).

    Returns two arrays of shape ``uv.shape[:-1]`` (floats for one point); nan outside 1000-100 000 K
    or |Duv| > 0.05 (not near enough to white for a colour temperature to mean anything).
    """
    uv = np.asarray(uv, float)
    flat = uv.reshape(-1, 2)
    out = np.array([_cct_duv_scalar(float(a), float(b)) for a, b in flat]).reshape(uv.shape[:-1] + (2,))
    if out.ndim == 1:
        return float(out[0]), float(out[1])
    return out[..., 0], out[..., 1]


def cct_duv_of_rgb(rgb, colour_space="Rec.709"):
    """(CCT in K, Duv) of linear RGB in the working ``colour_space``; nan for black or non-white light."""
    rgb = np.asarray(rgb, float)
    with np.errstate(invalid="ignore"):
        dark = ~(np.sum(rgb, axis=-1) > 0)
    uv = rgb_to_uv(rgb, colour_space)
    uv = np.where(dark[..., None], np.nan, uv)
    return cct_duv(uv)

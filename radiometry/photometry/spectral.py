"""Emitter spectra (pure numpy): Planck, the CIE illuminants and a luminaire's spectral file.

Every spectrum is a relative spectral power distribution on a wavelength grid, by default
:data:`WAVELENGTHS_NM`, 380-780 nm at 1 nm: the grid CIE S 026/E:2018 sums its alpha-opic
quantities on (see :mod:`.action_spectra`). Only the shape matters for the ratios built on it
(DER, ELR, S/P); absolute levels come from the meter's photopic reading.

- **Planck** (:func:`planck`): spectral radiance W/(m² sr nm), c1L = 2hc² and c2 = 1.4388e-2 m K, the
  value CIE 015:2018 uses for Planckian radiators and the one :mod:`.colorimetry`'s locus uses, so a
  blackbody at T has a CCT of T there.
- **CIE illuminant A** (:func:`cie_illuminant_a`): CIE 015:2018 eq. 3.1, closed form,
  S_A(λ) = 100 (560/λ)^5 (exp(1.435e7/(2848 x 560)) - 1) / (exp(1.435e7/(2848 λ)) - 1), λ in nm.
- **CIE daylight D-series** (:func:`cie_daylight`): CIE 015:2018 §3.1.3: chromaticity x_D of the CCT
  (4000-25000 K), y_D = -3 x_D² + 2.87 x_D - 0.275, M1 and M2 rounded to 3 decimals, S = S0 + M1 S1 + M2 S2
  from the 5 nm basis, linearly interpolated. D65 itself is CIE's 1 nm table (CIE S 014-2), not the formula.
- **Tabulated illuminants**: F-series FL1-FL12 and the LED series (LED-B1..B5, LED-BH1, LED-RGB1, LED-V1,
  LED-V2), CIE 015:2018 Tables 10-11 at 5 nm, linearly interpolated (zero outside 380-780 nm).
- **A spectral file** (:func:`read_spectrum_csv`): two columns, wavelength (nm) and relative power, as
  luminaire makers ship them; comma, semicolon, tab or space separated; one header line allowed.

Data: :mod:`._spectral_tables` (generated from colour-science 0.4.6 and CIE's own tables; sources there).
"""

import math
import os
import re

import numpy as np

from ...errors import RadiometerError
from . import _spectral_tables as tables
from ..constants import PLANCK_J_S, SPEED_OF_LIGHT_M_PER_S
from .. import input_files

__all__ = ["WAVELENGTHS_NM", "C2_CIE_M_K", "DAYLIGHT_CCT_RANGE_K", "D65_CCT_K", "ILLUMINANT_NAMES",
           "SpectralFileError", "planck", "cie_illuminant_a", "daylight_xy", "cie_daylight", "cie_illuminant",
           "resample", "read_spectrum_csv", "spectrum_from_spec"]

#: The spectral grid of every emitter spectrum here, nm (CIE S 026's: 380-780 nm at 1 nm).
WAVELENGTHS_NM = tables.WAVELENGTHS_1NM

#: Second radiation constant for Planckian radiators in colorimetry, m K (CIE 015:2018).
C2_CIE_M_K = 1.4388e-2

#: Range of CCT over which CIE 015 defines the daylight D-series, K.
DAYLIGHT_CCT_RANGE_K = (4000.0, 25000.0)

#: CCT of D65, K: 6500 K x 1.4388 / 1.4380 (the change of c2 in 1968).
D65_CCT_K = 6500.0 * 1.4388 / 1.4380

#: Named illuminants :func:`cie_illuminant` knows (besides "D<cct>" daylight and "blackbody:<K>").
ILLUMINANT_NAMES = ("A", "E", "D50", "D55", "D65", "D75") + tuple(tables.TABLE_ILLUMINANTS)

#: A spectral file larger than this is refused (a two-column table at 0.1 nm is under 100 kB).
MAX_FILE_BYTES = 4 * 1024 * 1024


class SpectralFileError(RadiometerError, ValueError):
    """A spectral file that cannot be read; the message is one line naming the file and the place."""


def _grid(wavelength_nm):
    return WAVELENGTHS_NM if wavelength_nm is None else np.asarray(wavelength_nm, float)


def planck(temperature_k, wavelength_nm=None):
    """Spectral radiance of a blackbody, W/(m² sr nm), shape ``temperature.shape + wavelength.shape``.

    c2 = 1.4388e-2 m K (:data:`C2_CIE_M_K`); ``temperature_k`` <= 0 or non-finite gives nan.
    """
    t = np.asarray(temperature_k, float)[..., None]
    wl_m = _grid(wavelength_nm) * 1e-9
    c1l = 2.0 * PLANCK_J_S * SPEED_OF_LIGHT_M_PER_S**2  # W m^2 / sr
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        value = c1l / wl_m**5 / np.expm1(C2_CIE_M_K / (wl_m * t)) * 1e-9
    return np.where((t > 0) & np.isfinite(t), value, np.nan)


def cie_illuminant_a(wavelength_nm=None):
    """Relative spectral power of CIE standard illuminant A (CIE 015:2018 eq. 3.1), 100 at 560 nm."""
    wl = _grid(wavelength_nm)
    c = 1.435e7 / 2848.0
    with np.errstate(over="ignore", divide="ignore"):
        return 100.0 * (560.0 / wl) ** 5 * math.expm1(c / 560.0) / np.expm1(c / wl)


def daylight_xy(cct_k):
    """CIE 1931 (x, y) of the daylight locus at ``cct_k`` (K, 4000-25000; nan outside), shape (..., 2)."""
    t = np.asarray(cct_k, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(t <= 7000.0,
                     -4.6070e9 / t**3 + 2.9678e6 / t**2 + 0.09911e3 / t + 0.244063,
                     -2.0064e9 / t**3 + 1.9018e6 / t**2 + 0.24748e3 / t + 0.237040)
    ok = (t >= DAYLIGHT_CCT_RANGE_K[0]) & (t <= DAYLIGHT_CCT_RANGE_K[1])
    x = np.where(ok, x, np.nan)
    y = -3.000 * x**2 + 2.870 * x - 0.275
    return np.stack([x, y], axis=-1)


def cie_daylight(cct_k, wavelength_nm=None):
    """Relative spectral power of the CIE daylight illuminant of CCT ``cct_k`` (K), CIE 015:2018 §3.1.3.

    Shape ``cct.shape + wavelength.shape``; nan outside 4000-25000 K (the D-series is not defined there).
    """
    xy = daylight_xy(cct_k)
    x, y = xy[..., 0], xy[..., 1]
    m = 0.0241 + 0.2562 * x - 0.7341 * y
    m1 = np.round((-1.3515 - 1.7703 * x + 5.9114 * y) / m, 3)
    m2 = np.round((0.0300 - 31.4424 * x + 30.0717 * y) / m, 3)
    wl = _grid(wavelength_nm)
    s0, s1, s2 = (np.interp(wl, tables.D_BASIS_WAVELENGTHS, b, left=0.0, right=0.0)
                  for b in (tables.D_BASIS_S0, tables.D_BASIS_S1, tables.D_BASIS_S2))
    return s0 + m1[..., None] * s1 + m2[..., None] * s2


def resample(wavelength_nm, values, wavelength_new_nm=None):
    """Linear interpolation of a spectrum onto ``wavelength_new_nm`` (default the 1 nm grid); 0 outside."""
    return np.interp(_grid(wavelength_new_nm), np.asarray(wavelength_nm, float), np.asarray(values, float),
                     left=0.0, right=0.0)


def cie_illuminant(name, wavelength_nm=None):
    """Relative spectral power of a named CIE illuminant (one of :data:`ILLUMINANT_NAMES`).

    "A": closed form; "E": equal energy; "D65": CIE's 1 nm table; "D50", "D55", "D75": the D-series at
    their CCTs (5000, 5500, 7500 K x 1.4388/1.4380); FL1-FL12 and the LED series: CIE 015:2018's tables.
    """
    wl = _grid(wavelength_nm)
    if name == "A":
        return cie_illuminant_a(wl)
    if name == "E":
        return np.ones_like(wl)
    if name == "D65":
        return resample(WAVELENGTHS_NM, tables.D65_1NM, wl)
    if name in ("D50", "D55", "D75"):
        return cie_daylight(float(name[1:]) * 100.0 * 1.4388 / 1.4380, wl)
    if name in tables.TABLE_ILLUMINANTS:
        return resample(tables.TABLE_WAVELENGTHS, tables.TABLE_ILLUMINANTS[name], wl)
    raise RadiometerError(f"unknown illuminant {name!r}; known: {', '.join(ILLUMINANT_NAMES)}, "
                          "D<CCT in K> (4000-25000) or blackbody:<K>")


def read_spectrum_csv(path):
    """(wavelengths nm, relative power) of a spectral file: two numeric columns, one row per wavelength.

    Wavelengths must rise strictly, lie within 200-2000 nm and cover 380-780 nm with steps of at most
    10 nm; powers must be finite, non-negative and not all zero. A first line that is not numeric is a
    header. Anything else is a :class:`SpectralFileError` (one line: the file, the line, what was wrong).
    """
    path = os.fspath(path)
    text = input_files.read_text(path, "spectral", MAX_FILE_BYTES, SpectralFileError).lstrip("\ufeff")
    wl, power = [], []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in re.split(r"[,;\t ]+", line) if f]
        try:
            values = [float(f) for f in fields[:2]]
        except ValueError:
            if not wl and number == 1:
                continue  # a header line
            raise SpectralFileError(f"{path}: line {number}: expected two numbers (nm, relative power), "
                                    f"got {line[:60]!r}") from None
        if len(values) != 2:
            raise SpectralFileError(f"{path}: line {number}: expected two numbers (nm, relative power), "
                                    f"got {line[:60]!r}")
        if not (math.isfinite(values[0]) and 200.0 <= values[0] <= 2000.0):
            raise SpectralFileError(f"{path}: line {number}: wavelength {fields[0]} nm is outside 200-2000 nm")
        if not (math.isfinite(values[1]) and values[1] >= 0.0):
            raise SpectralFileError(f"{path}: line {number}: relative power must be finite and >= 0, "
                                    f"got {fields[1]}")
        if wl and values[0] <= wl[-1]:
            raise SpectralFileError(f"{path}: line {number}: wavelengths must rise, {values[0]:g} nm "
                                    f"follows {wl[-1]:g} nm")
        wl.append(values[0])
        power.append(values[1])
    if len(wl) < 2:
        raise SpectralFileError(f"{path}: no spectrum: expected rows of wavelength (nm) and relative power")
    wl, power = np.array(wl), np.array(power)
    if wl[0] > 380.0 or wl[-1] < 780.0:
        raise SpectralFileError(f"{path}: covers {wl[0]:g}-{wl[-1]:g} nm; a spectrum must cover 380-780 nm")
    inside = (wl >= 380.0) & (wl <= 780.0)
    span = wl[max(np.argmax(inside) - 1, 0):len(wl) - np.argmax(inside[::-1]) + 1]
    if np.max(np.diff(span)) > 10.0:
        raise SpectralFileError(f"{path}: steps of up to {np.max(np.diff(span)):g} nm; at most 10 nm within "
                                "380-780 nm")
    if not np.any(power[inside] > 0):
        raise SpectralFileError(f"{path}: the relative power is zero everywhere in 380-780 nm")
    return wl, power


_DAYLIGHT = re.compile(r"^D\s*[:=]?\s*([0-9.eE+]+)\s*K?$", re.IGNORECASE)
_BLACKBODY = re.compile(r"^(?:blackbody|planck|bb)\s*[:=]?\s*([0-9.eE+]+)\s*K?$", re.IGNORECASE)


def spectrum_from_spec(spec, base_dir=None):
    """(label, relative spectrum on :data:`WAVELENGTHS_NM`) from a user's spectrum setting.

    ``spec``: a named illuminant ("A", "D65", "FL2", "LED-B3", "E"), daylight at a CCT ("D5000", "D:5000K"),
    a blackbody ("blackbody:2700", "blackbody 2700K") or a path to a spectral file (``.csv``, ``.txt``,
    ``.spd``; relative to ``base_dir`` when not absolute). Anything else: :class:`RadiometerError`.
    """
    if not isinstance(spec, str) or not spec.strip():
        raise RadiometerError(f"a spectrum must be a name, D<CCT>, blackbody:<K> or a file path, got {spec!r}")
    s = spec.strip()
    if s in ILLUMINANT_NAMES:
        return f"CIE {s}", cie_illuminant(s)
    m = _BLACKBODY.match(s)
    if m:
        t = float(m.group(1))
        if not (math.isfinite(t) and 500.0 <= t <= 100000.0):
            raise RadiometerError(f"blackbody temperature must be 500-100000 K, got {m.group(1)}")
        return f"blackbody {t:g} K", planck(t)
    m = _DAYLIGHT.match(s)
    if m:
        t = float(m.group(1))
        if not DAYLIGHT_CCT_RANGE_K[0] <= t <= DAYLIGHT_CCT_RANGE_K[1]:
            raise RadiometerError(f"CIE daylight is defined from 4000 K to 25000 K, got {m.group(1)} K")
        return f"CIE daylight {t:g} K", cie_daylight(t)
    if os.path.splitext(s)[1].lower() in (".csv", ".txt", ".spd", ".tsv") or os.sep in s or "/" in s:
        path = s if os.path.isabs(s) or base_dir is None else os.path.join(base_dir, s)
        wl, power = read_spectrum_csv(path)
        return f"file {os.path.basename(path)}", resample(wl, power)
    raise RadiometerError(f"unknown spectrum {spec!r}; use one of {', '.join(ILLUMINANT_NAMES)}, "
                          "D<CCT in K>, blackbody:<K> or a spectral file (.csv)")

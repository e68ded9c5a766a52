"""Plain-data results of measurements (no bpy): what a reading carries and how it prints."""

import dataclasses
import math
from typing import Optional


class AsDict:
    """Gives a result dataclass ``to_dict()``: its fields as plain data (``dataclasses.asdict``)."""

    def to_dict(self):
        return dataclasses.asdict(self)


def format_value(value, rel_std_error=0.0, exact=False):
    """``value`` with as many significant digits as its standard error supports (2 to 6).

    402.283 at 1.1 % -> '402'; at 0.12 % -> '402.3'; an exact (closed-form) value gets 5 digits.
    Plain decimals between 0.001 and 10^6, else scientific notation; "n/a" for None or non-finite.
    (The sidebar, the CLI and the reports all use this one.)
    """
    if value is None or not math.isfinite(value):
        return "n/a"
    if value == 0:
        return "0"
    magnitude = math.floor(math.log10(abs(value)))
    if exact or not rel_std_error or not math.isfinite(rel_std_error) or rel_std_error <= 0:
        digits = 5
    else:
        digits = magnitude - math.floor(math.log10(abs(value) * rel_std_error)) + 1
    digits = min(max(digits, 2), 6)
    if 1e-3 <= abs(value) < 1e6:
        decimals = digits - 1 - magnitude
        return f"{round(value, decimals):.{max(decimals, 0)}f}"
    return f"{value:.{digits - 1}e}"


def format_error(rel_std_error, exact=False):
    """'exact', '±1.1 %' (two significant digits, 1 s.e.) or 'n/a'."""
    if exact:
        return "exact"
    if rel_std_error is None or not math.isfinite(rel_std_error):
        return "n/a"
    return f"±{100 * rel_std_error:.2g} %"


def format_abs_error(value, rel_std_error, unit, exact=False):
    """The 1-s.e. error in the quantity's own unit, two significant digits: '±0.024 DF points', '±4.4 lx',
    'exact' or 'n/a' (issue 34: tables print absolute errors with the digits the error supports)."""
    if exact:
        return "exact"
    if value is None or rel_std_error is None or not (math.isfinite(value) and math.isfinite(rel_std_error)):
        return "n/a"
    return f"±{abs(value) * rel_std_error:.2g} {unit}"


def format_quantity(value, unit, rel_std_error=0.0, exact=False):
    """'402 lx ±1.1 %': the value with the digits its error supports, its unit and its error."""
    return f"{format_value(value, rel_std_error, exact)} {unit} {format_error(rel_std_error, exact)}"


def batch_method(readings):
    """The method of a batch of readings: one name when all agree, else each with its count, e.g.
    "mixed: analytic 12, hybrid 4" (a batch reads each meter as cheaply as its own proof allows)."""
    counts = {}
    for r in readings:
        counts[r.method] = counts.get(r.method, 0) + 1
    if len(counts) == 1:
        return next(iter(counts))
    return "mixed: " + ", ".join(f"{m} {n}" for m, n in counts.items())


def format_reading(reading):
    """One reading as a user reads it: '402 lx ±1.1 %' or '1230 cd/m² ±0.5 %'."""
    if getattr(reading, "quantity", "") == "luminance":
        return format_quantity(reading.luminance, "cd/m²", reading.rel_std_error, reading.exact)
    return format_quantity(reading.illuminance, "lx", reading.rel_std_error, reading.exact)


def _ev(value, kind):
    from .radiometry.photometry import colorimetry

    try:
        v = float(value)
    except (TypeError, ValueError):
        return math.nan
    f = colorimetry.ev100_incident if kind == "incident" else colorimetry.ev100_reflected
    return float(f(v))


def _cct(rgb, colour_space):
    from .radiometry.photometry import colorimetry, efficacy as photometry

    space = colour_space if colour_space in photometry.COLOUR_SPACES else None
    try:
        rgb = tuple(float(c) for c in rgb)
    except (TypeError, ValueError):
        return math.nan, math.nan
    if space is None or len(rgb) != 3 or not all(math.isfinite(c) for c in rgb):
        return math.nan, math.nan
    return colorimetry.cct_duv_of_rgb(rgb, space)


def _with_photographic(reading, d):
    """The reading's dict plus ev100, cct_k and duv (None where not defined: JSON has no inf/nan)."""
    for key in ("ev100", "cct_k", "duv"):
        v = getattr(reading, key)
        d[key] = v if math.isfinite(v) else None
    return d


def photographic_text(quantity, value, rgb, colour_space):
    """'EV100 8.7 (incident, flat sensor) · 3000 K, Duv +0.001' from plain values ("" where undefined).

    ``quantity``: 'illuminance' (``value`` in lx, ``rgb`` the irradiance RGB) or 'luminance' (cd/m²,
    radiance RGB); ``colour_space``: the working space of ``rgb``.
    """
    parts = []
    ev = _ev(value, "incident" if quantity == "illuminance" else "reflected")
    if math.isfinite(ev):
        kind = "incident, flat sensor" if quantity == "illuminance" else "reflected"
        parts.append(f"EV100 {ev:.1f} ({kind})")
    cct, duv = _cct(rgb, colour_space)
    if math.isfinite(cct):
        duv = 0.0 if abs(duv) < 0.0005 else duv  # never '-0.000'
        parts.append(f"{round(cct, -1):.0f} K, Duv {duv:+.3f}")
    return " · ".join(parts)


def photographic_summary(reading):
    """:func:`photographic_text` of a reading."""
    if getattr(reading, "quantity", "") == "luminance":
        return photographic_text("luminance", reading.luminance, reading.radiance_rgb, reading.colour_space)
    return photographic_text("illuminance", reading.illuminance, reading.irradiance_rgb, reading.colour_space)


@dataclasses.dataclass
class IlluminanceReading:
    """Irradiance on a surface element and its photometric twin, in SI units.

    ``irradiance`` (W/m^2) is the CIE-Y-weighted scalar of ``irradiance_rgb`` in the scene's
    working colour space, so ``illuminance = efficacy * irradiance`` (lux).
    """

    irradiance_rgb: tuple
    irradiance: float
    illuminance: float
    rel_std_error: float
    method: str
    samples: int
    seconds: float
    efficacy: float
    colour_space: str
    location: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, 1.0)
    exact: bool = False
    std_error_rgb: tuple = (0.0, 0.0, 0.0)
    notes: list = dataclasses.field(default_factory=list)
    render_settings: Optional[dict] = None
    quantity: str = "illuminance"
    #: Deterministic part of the error, relative (quadrature, possible partial occlusion); it is
    #: already included in ``rel_std_error`` (counted as one sigma).
    rel_error_bound: float = 0.0
    #: The 1-sigma relative standard error asked for (None: fixed samples or best in a time budget).
    target_rel_error: Optional[float] = None
    #: Which light came from closed forms and what Cycles rendered: {"analytic": [...], "rendered": [...]}.
    parts: dict = dataclasses.field(default_factory=dict)
    #: Issue 31: a meter whose pilot found no rendered light stops there and states a one-sided upper
    #: bound of its illuminance (lux; the absolute floor, see its notes) instead of an unknown error; a
    #: zero reading with a finite absolute error (e.g. a caustic's bound) states it here too.
    upper_bound_lux: Optional[float] = None

    def to_dict(self):
        return _with_photographic(self, dataclasses.asdict(self))

    @property
    def ev100(self):
        """Incident-light exposure value at ISO 100, flat receptor: log2(E * 100 / 250) (ISO 2720);
        -inf in the dark. The meter is a flat (cosine) sensor, so C = 250, not the dome's 340."""
        return _ev(self.illuminance, "incident")

    @property
    def cct_k(self):
        """Correlated colour temperature (K) of the light arriving, from ``irradiance_rgb`` in the
        working colour space (Ohno 2014, CIE 1960 uv); nan when dark or not near white (|Duv| > 0.05)."""
        return _cct(self.irradiance_rgb, self.colour_space)[0]

    @property
    def duv(self):
        """Distance from the Planckian locus in CIE 1960 uv (+ above, towards green); nan as :attr:`cct_k`."""
        return _cct(self.irradiance_rgb, self.colour_space)[1]

    def summary(self):
        err = "exact" if self.exact else f"±{100 * self.rel_std_error:.2g} % (1 s.e.)"
        if self.upper_bound_lux is not None:
            err = f"at most {self.upper_bound_lux:.3g} lx (one-sided bound: no rendered light found, see notes)"
        return f"{self.illuminance:.6g} lx  ({self.irradiance:.6g} W/m²)  {err}  [{self.method}]"


@dataclasses.dataclass
class LuminanceReading:
    """Average radiance in a spot meter's acceptance cone and its photometric twin (cd/m^2)."""

    radiance_rgb: tuple
    radiance: float
    luminance: float
    rel_std_error: float
    method: str
    samples: int
    seconds: float
    efficacy: float
    colour_space: str
    acceptance_deg: float
    location: tuple = (0.0, 0.0, 0.0)
    direction: tuple = (0.0, 0.0, -1.0)
    exact: bool = False
    notes: list = dataclasses.field(default_factory=list)
    render_settings: Optional[dict] = None
    #: The 1-sigma relative standard error asked for.
    target_rel_error: Optional[float] = None
    quantity: str = "luminance"
    #: Per channel (R, G, B) 1-sigma standard error of ``radiance_rgb``, W/(m^2 sr) (batch means).
    std_error_rgb: Optional[tuple] = None

    def to_dict(self):
        return _with_photographic(self, dataclasses.asdict(self))

    @property
    def ev100(self):
        """Reflected-light exposure value at ISO 100: log2(L * 100 / 12.5) (K = 12.5); -inf when dark."""
        return _ev(self.luminance, "reflected")

    @property
    def cct_k(self):
        """Correlated colour temperature (K) of the light seen, from ``radiance_rgb`` (see IlluminanceReading)."""
        return _cct(self.radiance_rgb, self.colour_space)[0]

    @property
    def duv(self):
        """Duv of the light seen (see IlluminanceReading.duv)."""
        return _cct(self.radiance_rgb, self.colour_space)[1]

    def summary(self):
        return (f"{self.luminance:.6g} cd/m²  ({self.radiance:.6g} W/(m² sr))  "
                f"±{100 * self.rel_std_error:.2g} % (1 s.e.)  [{self.method}]")


def format_melanopic(melanopic):
    """A meter's mel-EDI of the direct light (the report's ``melanopic`` dict) for the tables: '859.5 lx',
    '>= 859.5 lx' (a light without a spectrum or closed form left out: a lower bound) or '-' (none: a
    luminance meter, or a refused spectrum)."""
    m = melanopic or {}
    if "mel_edi_lx" not in m:
        return "-"
    v = f"{format_value(m['mel_edi_lx'], exact=True)} lx"   # closed forms: 5 digits, no exponent below 1e6
    return v if m["complete"] else f">= {v}"

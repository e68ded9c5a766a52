"""Photometric files (IES LM-63, EULUMDAT) read into a :class:`Photometry`; pure numpy, no bpy.

:class:`Photometry` is the one intensity-table class (``radiometry.emitters.photometric``): a file's
table here, a Blender IES light's table there (issue 17: it was two classes).

Formats
-------
* IES LM-63-1986 (no format line), LM-63-1991 (``IESNA91``), LM-63-1995 (``IESNA:LM-63-1995``),
  LM-63-2002 (``IESNA:LM-63-2002``) and LM-63-2019 (``IES:LM-63-2019``): keyword lines
  ``[KEY] value`` with ``[MORE]`` continuations, ``TILT=NONE``, ``TILT=INCLUDE`` or
  ``TILT=<file>`` (resolved next to the photometric file), candela multiplier, ballast factor,
  ballast-lamp photometric factor (1986-1995 only: 2002 calls it "future use", 2019 "file
  generation type", neither multiplies), absolute photometry (lumens per lamp = -1), photometric
  types C, B and A.
* EULUMDAT (``.ldt``): symmetry indicator 0-4, C-planes, gamma angles, intensities in cd/klm
  scaled by the lamp flux of the standard lamp sets (line 26c) times the conversion factor
  (line 24). A negative number of lamps (DIALux's absolute photometry) gives
  ``rated_lumens = None``.

Angles and symmetry (type C)
----------------------------
Vertical angle 0 deg is the nadir (straight down, the luminaire's local -Z), 180 deg the zenith.
C-plane 0 is the luminaire's local +X, 90 its local +Y (counter-clockwise seen from above).
Stored C ranges and what they mean: a single plane (axial symmetry); 0-90 (quadrilateral:
I(C) = I(-C) = I(180 - C)); 0-180 (bilateral about the C0-C180 plane: I(C) = I(360 - C));
90-270 (bilateral about the C90-C270 plane: I(C) = I(180 - C)); 0-360 (none). A full table
missing its 360 deg plane gets it (a copy of 0 deg) when the spacing says so, as Cycles does.

Interpolation (stated, and the one Cycles uses)
-----------------------------------------------
:meth:`Photometry.candela_at` interpolates the type-C table expanded to 0-360 deg with Cycles'
IES kernel (``intern/cycles/kernel/util/ies.h``): Catmull-Rom cubic on table indices (not
angles), first along the vertical angle then along C; the vertical stencil mirrors across the
nadir (and the zenith when the table reaches 180 deg) and otherwise repeats the end value; C
wraps around 360 deg; negative results are clamped to 0; directions outside the tabulated
vertical range give 0 (so a 0-90 deg table is dark from the horizon up, horizon included).
At tabulated angles it returns the table value exactly. :attr:`Photometry.lumens` integrates
that same interpolated distribution (Gauss-Legendre, 8 x 8 nodes per table cell), so it is the
flux Cycles emits for the light, which for a smooth distribution differs from a
trapezoidal zonal-lumen sum by the interpolation error only.

Errors: :class:`PhotometricFileError` (a ``ValueError``) with one line naming the file line and
what was expected.
"""

import math
import os
from dataclasses import dataclass

import numpy as np

from ..emitters.photometric import ANGLE_TOL as _ANGLE_TOL, Photometry, catmull_rom_table

__all__ = ["Photometry", "PhotometricFileError", "Tilt", "read_photometry", "parse_ies", "parse_ldt",
           "catmull_rom_table", "cycles_ies_table", "to_ies_text", "CYCLES_CANDELA_TO_WATT"]

#: Cycles' conversion of IES candela to its texture value (``intern/cycles/util/ies.cpp``):
#: 4 pi / 177.83, i.e. a D65 luminous efficacy of 177.83 lm/W and the 4 pi of point-light strength.
CYCLES_CANDELA_TO_WATT = 0.0706650768394
#: Luminous efficacy Cycles assumes for IES files (lm/W): with light energy E W and Emission
#: strength 1, the light's radiant intensity is E * cd / CYCLES_IES_EFFICACY W/sr (measured).
CYCLES_IES_EFFICACY = 4.0 * math.pi / CYCLES_CANDELA_TO_WATT

IES_FORMATS = {
    "IESNA91": "LM-63-1991",
    "IESNA:LM-63-1991": "LM-63-1991",
    "IESNA:LM-63-1995": "LM-63-1995",
    "IESNA:LM-63-2002": "LM-63-2002",
    "IES:LM-63-2019": "LM-63-2019",
    "IESNA:LM-63-2019": "LM-63-2019",
}
_PHOTOMETRIC_TYPES = {1: "C", 2: "B", 3: "A"}
#: No luminaire comes near this (searchlights reach ~1e9 cd); above it a table is a broken file, and
#: its flux would overflow (1e308 cd gives lumens = inf).
MAX_CANDELA = 1e12
#: Multipliers and ballast factors outside (0, MAX_FACTOR] are refused (a factor of -1 makes a
#: negative table, 0 a black one).
MAX_FACTOR = 1e6
#: Photometric files are text tables of a few kB to a few MB.
MAX_FILE_BYTES = 64 * 1024 * 1024


class PhotometricFileError(ValueError):
    """A photometric file that cannot be read; the message is one line naming the place."""


@dataclass(frozen=True)
class Tilt:
    """LM-63 TILT data: lamp-to-luminaire geometry (1, 2 or 3), tilt angles (deg) and factors."""

    geometry: int
    angles_deg: tuple
    factors: tuple
    source: str = "INCLUDE"

    def factor(self, tilt_deg):
        """Multiplying factor at a luminaire tilt (deg), linear between tabulated angles."""
        return float(np.interp(float(tilt_deg), self.angles_deg, self.factors))


# --- tokenising with line numbers -------------------------------------------------------------

class _Tokens:
    """Whitespace/comma separated numbers with their 1-based line numbers."""

    def __init__(self, lines, first_line, path):
        self.items = []
        for k, line in enumerate(lines):
            for tok in line.replace(",", " ").split():
                self.items.append((tok, first_line + k))
        self.pos = 0
        self.path = path
        self.last_line = first_line + max(len(lines) - 1, 0)

    def _fail(self, what, got=None, line=None, found=", found nothing"):
        where = f"line {line}" if line is not None else f"line {self.last_line} (end of file)"
        tail = f", got {got!r}" if got is not None else found
        raise PhotometricFileError(f"{self.path}: {where}: expected {what}{tail}")

    def number(self, what, integer=False):
        if self.pos >= len(self.items):
            self._fail(what)
        tok, line = self.items[self.pos]
        self.pos += 1
        try:
            value = float(tok)
        except ValueError:
            self._fail(what, tok, line)
        if not math.isfinite(value):
            self._fail(what + " (finite)", tok, line)
        if integer:
            if value != int(value):
                self._fail(what + " (an integer)", tok, line)
            return int(value), line
        return value, line

    def numbers(self, n, what):
        out = np.empty(n)
        lines = []
        for i in range(n):
            if self.pos >= len(self.items):
                self._fail(f"{n} {what}", found=f", found {i}")
            out[i], line = self.number(what)
            lines.append(line)
        return out, lines


def _check_ascending(values, lines, what, path):
    for i in range(1, len(values)):
        if not values[i] > values[i - 1]:
            raise PhotometricFileError(f"{path}: line {lines[i]}: expected {what} in increasing order, "
                                       f"got {values[i]:g} after {values[i - 1]:g}")


def _check_candela(values, lines, path, unit="candela", scale=1.0):
    for i, value in enumerate(values.ravel()):
        if value < 0.0:
            raise PhotometricFileError(f"{path}: line {lines[i]}: expected a non-negative {unit} value, got {value:g}")
        if not value * scale <= MAX_CANDELA:
            raise PhotometricFileError(f"{path}: line {lines[i]}: expected a {unit} value giving at most "
                                       f"{MAX_CANDELA:g} cd, got {value:g}" + (f" (x {scale:g})" if scale != 1 else ""))


def _check_factor(value, line, what, path):
    if not 0.0 < value <= MAX_FACTOR:
        raise PhotometricFileError(f"{path}: line {line}: expected {what} in (0, {MAX_FACTOR:g}], got {value:g}")


def _check_range(values, lines, low, high, what, path):
    for value, line in zip(values, lines):
        if not low - _ANGLE_TOL <= value <= high + _ANGLE_TOL:
            raise PhotometricFileError(f"{path}: line {line}: expected {what} within {low:g}..{high:g} deg, "
                                       f"got {value:g}")


def _classify_c(h, path, line):
    """Symmetry of a type-C horizontal angle list (deg), as LM-63 defines it."""
    first, last = h[0], h[-1]
    close = lambda a, b: abs(a - b) < _ANGLE_TOL  # noqa: E731
    if h.size == 1:
        return "axial"
    if close(first, 0.0) and close(last, 90.0):
        return "quadrilateral"
    if close(first, 0.0) and close(last, 180.0):
        return "bilateral"
    if close(first, 90.0) and close(last, 270.0):
        return "bilateral-90-270"
    if close(first, 0.0) and close(last, 360.0):
        return "none"
    if close(first, 0.0) and h.size >= 2:
        gap = 360.0 - last
        if close(h[-1] - h[-2], gap) or close(h[1] - h[0], gap):
            return "none"  # full table without its 360 deg plane (Cycles adds it too)
    raise PhotometricFileError(
        f"{path}: line {line}: expected type-C horizontal angles 0 (one plane), 0-90, 0-180, 90-270 or 0-360 deg, "
        f"got {first:g}-{last:g}")


# --- LM-63 --------------------------------------------------------------------------------------

def parse_ies(text, path="<text>", tilt_loader=None):
    """Parse LM-63 text into a :class:`Photometry` (see the module docstring).

    ``tilt_loader(name)`` returns the text of a ``TILT=<file>`` file (default: read it next to
    ``path``); a missing file raises :class:`PhotometricFileError`.
    """
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if not any(line.strip() for line in lines):
        raise PhotometricFileError(f"{path}: line 1: expected an IES LM-63 file, got an empty file")
    first = lines[0].strip().lstrip("\ufeff")
    fmt = IES_FORMATS.get(first.upper())
    start = 1 if fmt is not None else 0
    if fmt is None:
        if first.upper().startswith(("IESNA", "IES:")):
            raise PhotometricFileError(f"{path}: line 1: expected a known LM-63 format line "
                                       f"({', '.join(sorted(IES_FORMATS))}), got {first!r}")
        fmt = "LM-63-1986"
    metadata, labels, last_key = {}, [], None
    tilt_index = None
    for k in range(start, len(lines)):
        line = lines[k].strip()
        if line.upper().startswith("TILT"):
            tilt_index = k
            break
        if line.startswith("["):
            close = line.find("]")
            if close < 0:
                raise PhotometricFileError(f"{path}: line {k + 1}: expected a keyword like [MANUFAC], got {line!r}")
            key, value = line[1:close].strip().upper(), line[close + 1:].strip()
            if key == "MORE" and last_key is not None:
                metadata[last_key] = (metadata[last_key] + "\n" + value).strip()
                continue
            metadata[key] = (metadata[key] + "\n" + value) if key in metadata else value
            last_key = key
        elif line:
            labels.append(line)
    if tilt_index is None:
        raise PhotometricFileError(f"{path}: line {len(lines)} (end of file): expected a TILT= line, found none")
    if labels:
        metadata.setdefault("LABEL", "\n".join(labels))
    tilt_line = lines[tilt_index].strip()
    if "=" not in tilt_line:
        raise PhotometricFileError(f"{path}: line {tilt_index + 1}: expected TILT=NONE, TILT=INCLUDE or TILT=<file>, "
                                   f"got {tilt_line!r}")
    tilt_value = tilt_line.split("=", 1)[1].strip()
    tokens = _Tokens(lines[tilt_index + 1:], tilt_index + 2, path)
    tilt = None
    if tilt_value.upper() == "INCLUDE":
        tilt = _read_tilt(tokens, "INCLUDE", path)
    elif tilt_value.upper() != "NONE":
        if not tilt_value:
            raise PhotometricFileError(f"{path}: line {tilt_index + 1}: expected TILT=NONE, TILT=INCLUDE or "
                                       "TILT=<file>, got an empty TILT")
        tilt = _load_tilt_file(tilt_value, path, tilt_index + 1, tilt_loader)

    n_lamps, _ = tokens.number("the number of lamps (an integer)", integer=True)
    lumens_per_lamp, _ = tokens.number("the lumens per lamp (or -1 for absolute photometry)")
    multiplier, line_mult = tokens.number("the candela multiplier")
    n_v, line_nv = tokens.number("the number of vertical angles (an integer)", integer=True)
    n_h, line_nh = tokens.number("the number of horizontal angles (an integer)", integer=True)
    ptype, line_pt = tokens.number("the photometric type (1 = C, 2 = B, 3 = A)", integer=True)
    if n_v < 2:
        raise PhotometricFileError(f"{path}: line {line_nv}: expected at least 2 vertical angles, got {n_v}")
    if n_h < 1:
        raise PhotometricFileError(f"{path}: line {line_nh}: expected at least 1 horizontal angle, got {n_h}")
    if ptype not in _PHOTOMETRIC_TYPES:
        raise PhotometricFileError(f"{path}: line {line_pt}: expected the photometric type 1 (C), 2 (B) or 3 (A), "
                                   f"got {ptype}")
    units, _ = tokens.number("the units type (1 = feet, 2 = metres)", integer=True)
    width, _ = tokens.number("the luminous width")
    length, _ = tokens.number("the luminous length")
    height, _ = tokens.number("the luminous height")
    ballast, line_ballast = tokens.number("the ballast factor")
    third, line_third = tokens.number("the ballast-lamp photometric factor / future use / file generation type")
    watts, _ = tokens.number("the input watts")
    left = len(tokens.items) - tokens.pos
    if n_v + n_h + n_v * n_h > max(left, 1_000_000):  # before allocating: counts of 1e9 would need gigabytes
        raise PhotometricFileError(f"{path}: line {line_nv}: expected {n_v} vertical and {n_h} horizontal angles "
                                   f"and {n_v} x {n_h} candela values, the file has only {left} numbers left")
    _check_factor(multiplier, line_mult, "the candela multiplier", path)
    _check_factor(ballast, line_ballast, "the ballast factor", path)
    v, v_lines = tokens.numbers(n_v, "vertical angles")
    h, h_lines = tokens.numbers(n_h, "horizontal angles")
    cd_raw, cd_lines = tokens.numbers(n_v * n_h, "candela values")
    if tokens.pos < len(tokens.items):
        tok, line = tokens.items[tokens.pos]
        raise PhotometricFileError(f"{path}: line {line}: expected the end of the file after {n_h} x {n_v} candela "
                                   f"values, got {tok!r} (wrong angle counts?)")
    _check_ascending(v, v_lines, "vertical angles", path)
    _check_ascending(h, h_lines, "horizontal angles", path)
    factor = multiplier * ballast
    if fmt in ("LM-63-1986", "LM-63-1991", "LM-63-1995"):
        _check_factor(third, line_third, "the ballast-lamp photometric factor", path)
        factor *= third  # ballast-lamp photometric factor; later versions repurposed the field
    _check_candela(cd_raw, cd_lines, path, scale=factor)
    metadata.update({"units_type": units, "luminous_width": width, "luminous_length": length,
                     "luminous_height": height, "ballast_factor": ballast, "candela_multiplier": multiplier,
                     "number_of_lamps": n_lamps, "lumens_per_lamp": lumens_per_lamp})
    if fmt == "LM-63-2019":
        metadata["file_generation_type"] = third
    else:
        metadata["ballast_lamp_factor"] = third
    kind = _PHOTOMETRIC_TYPES[ptype]
    if kind == "C":
        _check_range(h, h_lines, 0.0, 360.0, "type-C horizontal angles", path)
        if v[0] < -_ANGLE_TOL or v[-1] > 180.0 + _ANGLE_TOL:
            raise PhotometricFileError(f"{path}: line {v_lines[0]}: expected type-C vertical angles within 0-180 deg, "
                                       f"got {v[0]:g}-{v[-1]:g}")
        symmetry = _classify_c(h, path, h_lines[0])
    else:
        if v[0] < -90.0 - _ANGLE_TOL or v[-1] > 90.0 + _ANGLE_TOL:
            raise PhotometricFileError(f"{path}: line {v_lines[0]}: expected type-{kind} vertical angles within "
                                       f"-90..90 deg, got {v[0]:g}-{v[-1]:g}")
        _check_range(h, h_lines, -180.0, 180.0, f"type-{kind} horizontal angles", path)
        symmetry = ("bilateral" if abs(h[0]) < _ANGLE_TOL else "none") if h.size > 1 else "axial"
    rated = None if lumens_per_lamp < 0 else n_lamps * lumens_per_lamp
    return Photometry(vertical_angles_deg=v, horizontal_angles_deg=h, candela=cd_raw.reshape(n_h, n_v) * factor,
                      symmetry=symmetry, photometric_type=kind, rated_lumens=rated, file_format=fmt,
                      metadata=metadata, tilt=tilt, input_watts=watts, source=path)


def _read_tilt(tokens, source, path):
    geometry, _ = tokens.number("the lamp-to-luminaire geometry (1, 2 or 3)", integer=True)
    n, line = tokens.number("the number of tilt angles (an integer)", integer=True)
    if n < 1:
        raise PhotometricFileError(f"{path}: line {line}: expected at least 1 tilt angle, got {n}")
    angles, a_lines = tokens.numbers(n, "tilt angles")
    factors, _ = tokens.numbers(n, "tilt multiplying factors")
    _check_ascending(angles, a_lines, "tilt angles", path)
    return Tilt(geometry=geometry, angles_deg=tuple(angles), factors=tuple(factors), source=source)


def _load_tilt_file(name, path, line, loader):
    if loader is None:
        base = os.path.dirname(path) if path != "<text>" else os.getcwd()
        full = name if os.path.isabs(name) else os.path.join(base, name)

        def loader(_name):
            with open(full, encoding="latin-1") as fh:
                return fh.read()
    try:
        text = loader(name)
    except OSError:
        raise PhotometricFileError(f"{path}: line {line}: expected the TILT file {name!r} next to the "
                                   "photometric file, it does not exist") from None
    tilt_lines = text.replace("\r\n", "\n").split("\n")
    return _read_tilt(_Tokens(tilt_lines, 1, f"{path} (TILT file {name})"), name, path)


# --- EULUMDAT ------------------------------------------------------------------------------------

_LDT_SYMMETRY = {0: "none", 1: "axial", 2: "bilateral", 3: "bilateral-90-270", 4: "quadrilateral"}


def parse_ldt(text, path="<text>"):
    """Parse EULUMDAT text into a :class:`Photometry` (candela = cd/klm x lamp flux / 1000 x line 24)."""
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    pos = [0]

    def raw(what):
        if pos[0] >= len(lines):
            raise PhotometricFileError(f"{path}: line {len(lines)} (end of file): expected {what}, found nothing")
        pos[0] += 1
        return lines[pos[0] - 1].strip(), pos[0]

    def num(what, integer=False):
        s, ln = raw(what)
        try:
            value = float(s.replace(",", ".")) if s else float("nan")
        except ValueError:
            raise PhotometricFileError(f"{path}: line {ln}: expected {what}, got {s!r}") from None
        if not math.isfinite(value) or (integer and value != int(value)):
            raise PhotometricFileError(f"{path}: line {ln}: expected {what}, got {s!r}")
        return (int(value) if integer else value), ln

    md = {}
    md["company"], _ = raw("the company identification (line 1)")
    ityp, _ = num("the type indicator Ityp (0-3)", integer=True)
    isym, ln_sym = num("the symmetry indicator Isym (0-4)", integer=True)
    if isym not in _LDT_SYMMETRY:
        raise PhotometricFileError(f"{path}: line {ln_sym}: expected the symmetry indicator Isym 0-4, got {isym}")
    mc, ln_mc = num("the number of C-planes Mc (an integer)", integer=True)
    dc, _ = num("the distance between C-planes Dc (deg)")
    ng, ln_ng = num("the number of intensities per C-plane Ng (an integer)", integer=True)
    dg, _ = num("the distance between gamma angles Dg (deg)")
    if mc < 1 and isym != 1:
        raise PhotometricFileError(f"{path}: line {ln_mc}: expected at least 1 C-plane, got {mc}")
    if isym in (2, 3) and mc % 2 or isym == 4 and mc % 4:
        raise PhotometricFileError(f"{path}: line {ln_mc}: expected Mc divisible by {2 if isym in (2, 3) else 4} for "
                                   f"symmetry {isym}, got {mc}")
    if ng < 2:
        raise PhotometricFileError(f"{path}: line {ln_ng}: expected at least 2 gamma angles Ng, got {ng}")
    for key in ("measurement_report", "luminaire_name", "luminaire_number", "file_name", "date_user"):
        md[key], _ = raw(key.replace("_", " "))
    for key in ("length_mm", "width_mm", "height_mm", "luminous_length_mm", "luminous_width_mm",
                "luminous_height_c0_mm", "luminous_height_c90_mm", "luminous_height_c180_mm", "luminous_height_c270_mm",
                "downward_flux_fraction_pct", "light_output_ratio_pct", "conversion_factor", "tilt_deg"):
        md[key], _ = num(key.replace("_", " "))
    n_sets, ln_sets = num("the number of standard sets of lamps (an integer)", integer=True)
    if n_sets < 1:
        raise PhotometricFileError(f"{path}: line {ln_sets}: expected at least 1 standard set of lamps, got {n_sets}")
    sets = []
    for _i in range(n_sets):
        sets.append({})
    for key, is_num in (("number_of_lamps", True), ("lamp_type", False), ("lamp_flux_lm", True),
                        ("colour", False), ("cri", False), ("watts", True)):
        for s in sets:
            s[key] = num(key.replace("_", " "))[0] if is_num else raw(key.replace("_", " "))[0]
    md["lamp_sets"] = sets
    md["direct_ratios"] = [num("a direct ratio (line 27)")[0] for _ in range(10)]
    c, c_lines = [], []
    for _ in range(mc):
        value, ln = num("a C-plane angle (deg)")
        c.append(value)
        c_lines.append(ln)
    g, g_lines = [], []
    for _ in range(ng):
        value, ln = num("a gamma angle (deg)")
        g.append(value)
        g_lines.append(ln)
    c, g = np.array(c), np.array(g)
    _check_ascending(c, c_lines, "C-plane angles", path)
    _check_range(c, c_lines, 0.0, 360.0, "C-plane angles", path)
    _check_ascending(g, g_lines, "gamma angles", path)
    if g[0] < -_ANGLE_TOL or g[-1] > 180.0 + _ANGLE_TOL:
        raise PhotometricFileError(f"{path}: line {g_lines[0]}: expected gamma angles within 0-180 deg, "
                                   f"got {g[0]:g}-{g[-1]:g}")
    if isym == 0:
        planes = np.arange(mc)
    elif isym == 1:
        planes = np.array([0])
    elif isym == 2:
        planes = np.arange(mc // 2 + 1)
    elif isym == 3:
        start = int(np.argmin(np.abs(c - 90.0)))
        planes = start + np.arange(mc // 2 + 1)
    else:
        planes = np.arange(mc // 4 + 1)
    if isym != 1 and planes[-1] >= mc:
        raise PhotometricFileError(f"{path}: line {c_lines[-1]}: expected C-planes reaching "
                                   f"{ {2: 180, 3: 270, 4: 90}.get(isym, 360)} deg for symmetry {isym}")
    values, v_lines = [], []
    for _ in range(planes.size * ng):
        value, ln = num(f"{planes.size} x {ng} luminous intensities (cd/klm) for symmetry {isym}")
        values.append(value)
        v_lines.append(ln)
    values = np.array(values)
    flux = sum(abs(s["lamp_flux_lm"]) for s in sets)
    if not 0.0 < md["conversion_factor"] <= MAX_FACTOR:
        raise PhotometricFileError(f"{path}: line 24: expected the conversion factor in (0, {MAX_FACTOR:g}], "
                                   f"got {md['conversion_factor']:g}")
    _check_candela(values, v_lines, path, "luminous intensity", scale=flux / 1000.0 * md["conversion_factor"])
    h = c[planes] if isym != 1 else np.array([0.0])
    symmetry = _LDT_SYMMETRY[isym]
    if isym == 0:
        symmetry = _classify_c(h, path, c_lines[0])
    flux = sum(abs(s["lamp_flux_lm"]) for s in sets)
    absolute = any(s["number_of_lamps"] < 0 for s in sets)
    candela = values.reshape(planes.size, ng) * (flux / 1000.0) * md["conversion_factor"]
    md["type_indicator"] = ityp
    md["symmetry_indicator"] = isym
    md["c_plane_spacing_deg"], md["gamma_spacing_deg"] = dc, dg
    watts = sum(s["watts"] for s in sets)
    return Photometry(vertical_angles_deg=g, horizontal_angles_deg=h, candela=candela, symmetry=symmetry,
                      photometric_type="C", rated_lumens=None if absolute else flux, file_format="EULUMDAT",
                      metadata=md, tilt=None, input_watts=watts, source=path)


# --- front end ---------------------------------------------------------------------------------

def read_photometry(path):
    """Read an IES LM-63 (``.ies``) or EULUMDAT (``.ldt``) file; the format is decided by the
    extension, else by content (a first line of ``IESNA``/``IES:``/``TILT=`` means LM-63)."""
    import stat

    path = os.fspath(path)
    try:
        # A FIFO blocks forever and /dev/zero never ends: only regular files of a sane size are read.
        st = os.stat(path)
        if stat.S_ISDIR(st.st_mode):
            raise PhotometricFileError(f"{path}: is a folder, not a photometric file")
        if not stat.S_ISREG(st.st_mode):
            raise PhotometricFileError(f"{path}: not a regular file (a pipe or a device): refusing to read it")
        if st.st_size > MAX_FILE_BYTES:
            raise PhotometricFileError(f"{path}: {st.st_size} bytes is too large for a photometric file "
                                       f"(at most {MAX_FILE_BYTES})")
        with open(path, "rb") as fh:
            data = fh.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise PhotometricFileError(f"{path}: no such file") from None
    except OSError as exc:
        raise PhotometricFileError(f"{path}: cannot read it ({exc.strerror or exc})") from None
    if b"\0" in data[:4096]:
        raise PhotometricFileError(f"{path}: line 1: expected a text photometric file, got binary data")
    text = data.decode("utf-8") if _is_utf8(data) else data.decode("latin-1")
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ldt":
        return parse_ldt(text, path)
    if ext == ".ies":
        return parse_ies(text, path)
    head = text.lstrip("\ufeff").lstrip().upper()
    if head.startswith(("IESNA", "IES:")) or "\nTILT=" in text.upper():
        return parse_ies(text, path)
    return parse_ldt(text, path)


def _is_utf8(data):
    try:
        data.decode("utf-8")
        return True
    except UnicodeDecodeError:
        return False


# --- Cycles' own reading of an IES text, and a canonical text Cycles reads as we do --------------

def cycles_ies_table(text):
    """The table Cycles' IES loader builds from LM-63 text, or None where Cycles would reject it.

    Returns (h_deg, v_deg, values) with values in Cycles' texture units (cd x multiplier x
    ballast factor x the second factor on that line x :data:`CYCLES_CANDELA_TO_WATT`). Follows
    ``intern/cycles/util/ies.cpp`` for type C: TILT data skipped (never applied), 90-270 tables
    ROTATED to 0-180 (not mirrored as LM-63 says), a single plane becomes 0 and 360, quadrant and
    half tables mirrored, a missing 360 plane added when the spacing says so. Types A and B:
    None here (the meter renders them).
    """
    t = text.replace(",", " ")
    at = t.find("\nTILT=")
    if at < 0:
        return None
    rest = t[at + 1:]
    if rest.startswith("TILT=INCLUDE"):
        toks = rest[len("TILT=INCLUDE"):].split()
        try:
            n_tilt = int(float(toks[1]))
        except (IndexError, ValueError):
            return None
        toks = toks[2 + 2 * n_tilt:]
    else:
        nl = rest.find("\n")
        if nl < 0:
            return None
        toks = rest[nl + 1:].split()
    try:
        nums = [float(x) for x in toks]
    except ValueError:
        return None
    if len(nums) < 13:
        return None
    factor = nums[2] * nums[10] * nums[11] * CYCLES_CANDELA_TO_WATT
    n_v, n_h, ptype = int(nums[3]), int(nums[4]), int(nums[5])
    body = nums[13:]
    if ptype != 1 or n_v < 2 or n_h < 1 or len(body) < n_v + n_h + n_v * n_h:
        return None
    v = np.float32(body[:n_v]).astype(np.float64)
    h = list(np.float32(body[n_v:n_v + n_h]).astype(np.float64))
    rows = [list(r) for r in (np.float32(np.array(body[n_v + n_h:n_v + n_h + n_v * n_h]).reshape(n_h, n_v)
                                         * factor).astype(np.float64))]
    close = lambda a, b: abs(a - b) < 1e-4  # noqa: E731
    if close(h[0], 90.0):
        h = [x - 90.0 for x in h]
    if len(h) == 1:
        h = [0.0, 360.0]
        rows = [rows[0], rows[0]]
    if close(h[-1], 90.0):
        n = len(h)
        for i in range(n - 2, -1, -1):
            h.append(180.0 - h[i])
            rows.append(rows[i])
    if close(h[-1], 180.0):
        n = len(h)
        for i in range(n - 2, -1, -1):
            h.append(360.0 - h[i])
            rows.append(rows[i])
    if close(h[0], 0.0) and not close(h[-1], 360.0) and len(h) > 1:
        gap = 360.0 - h[-1]
        if close(h[-1] - h[-2], gap) or close(h[1] - h[0], gap):
            h.append(360.0)
            rows.append(rows[0])
    h = np.array(h)
    if np.any(np.diff(h) <= 0.0) or np.any(np.diff(v) <= 0.0):
        return None
    return h, v, np.array(rows)


def to_ies_text(photometry, factor=1.0, label="Radiometer"):
    """LM-63-2002 text of the full (0-360 deg) type-C table times ``factor``, which Cycles reads
    exactly as :meth:`Photometry.candela_at` interprets the original: no TILT, no symmetry left
    for Cycles to interpret, multipliers folded in (written with 9 significant digits)."""
    h, v, cd = photometry.full_table()
    if h.size == 2 and np.array_equal(cd[0], cd[1]):
        # Axially symmetric: written as 37 identical C planes (every 10 deg). Blender 4.5 reads a
        # one- or two-plane table 7-12 % high, and near the nadir it depends on the plane spacing
        # (measured against 5.0's exact render: 90 deg 2.3 %, 30 deg 0.6 %, 10 deg 0.2 %).
        h = np.linspace(0.0, 360.0, 37)
        cd = np.repeat(cd[:1], h.size, axis=0)
    cd = cd * float(factor)
    out = ["IESNA:LM-63-2002", f"[TEST] {label}"]
    for key in ("MANUFAC", "LUMCAT", "LUMINAIRE", "LAMP"):
        value = photometry.metadata.get(key)
        if value:
            out.append(f"[{key}] {value.splitlines()[0]}")
    out.append(f"[_RADIOMETER_SOURCE] {os.path.basename(photometry.source)}")
    out.append("TILT=NONE")
    out.append(f"1 -1 1 {v.size} {h.size} 1 2 0 0 0")
    out.append("1 1 0")
    fmt = lambda a: " ".join(f"{x:.9g}" for x in a)  # noqa: E731
    out.append(fmt(v))
    out.append(fmt(h))
    out.extend(fmt(row) for row in cd)
    return "\n".join(out) + "\n"

"""EnergyPlus weather files (EPW), pure Python/numpy: the site and the hourly solar fields, checked.

Format (EnergyPlus "Auxiliary Programs", Weather Converter, EPW CSV format): 8 header lines, the
first ``LOCATION,city,state,country,source,WMO,latitude (deg N),longitude (deg E),time zone (h from
UTC),elevation (m)``; then one comma-separated record per hour with, among 35 fields (0-based):
0 year, 1 month, 2 day, 3 hour (1-24: the hour ENDING at that local standard time), 4 minute,
5 data source and uncertainty flags (not read), 6 dry-bulb and 7 dew-point temperature (deg C),
9 station pressure (Pa), 13 global horizontal, 14 direct normal, 15 diffuse horizontal radiation
(Wh/m^2 over the hour = mean W/m^2), 16 global horizontal, 17 direct normal, 18 diffuse horizontal
illuminance (lux), 19 zenith luminance (cd/m^2). Missing values (the EnergyPlus data dictionary):
9999 for radiation and zenith luminance, 999999 for illuminance and pressure, 99.9 for temperatures;
returned as NaN.

Checks (docs/daylight-sky.md, "Weather files"): only a regular file of at most ``MAX_FILE_BYTES`` is
opened (a FIFO, a device such as /dev/zero or a folder is refused before reading), lines of at most
``MAX_LINE_BYTES``; records are streamed into arrays of at most ``MAX_RECORDS`` rows, so memory is
bounded whatever the file (about 2 MB for a leap year). The header is the 8 keyword lines EnergyPlus
reads (LOCATION first); hourly data only (``DATA PERIODS`` with 1 record per hour). Every record: a
real date (30 February is refused), hour 1-24, minute 0-60 (EnergyPlus writes 0 or 60 for hourly
data), finite numbers; each record one hour after the one before (31 December 24:00 -> 1 January
1:00 may wrap once, 29 February may be skipped); a duplicated, missing or reversed hour, or the year
starting again, is refused naming the line. ``EPW.is_full_year``: 8760 records, or 8784 with
29 February; ``EPW.period`` says what a shorter file holds.

Irradiance is compared with the sun at the site (``solar_position``, NREL SPA at the start, middle
and end of each hour): missing (9999), negative or super-solar (direct normal above the
extraterrestrial E0 = 1367 W/m^2 / R^2, at most 1414 W/m^2 at perihelion; global or diffuse
horizontal above E0 times the hour's largest sin(elevation)) values of an hour when the sun is up
make the hour unusable: listed in ``EPW.notes`` (counts and lines) and left out of ``EPW.usable``,
or refused naming the first line when more than ``MAX_BAD_SHARE`` of the sun-up hours are
unusable. With the sun below the horizon the whole hour a missing or negative value is taken as 0
(noted). Sunshine (direct normal > 0 or global horizontal > ``NIGHT_GLOBAL_W_M2``) while the sun is
down for more than ``NIGHT_SUNSHINE_HOURS`` hours gives a warning note: the time zone or the site is
probably wrong.

``read_epw`` returns an ``EPW`` with the site and arrays of length n_hours; ``midpoint_hours``
gives the local standard time of each record's midpoint (hour - 0.5), the time used for the sun.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
import os

import numpy as np

from .. import input_files
from . import solar_position
from ..skies.perez import SOLAR_CONSTANT

__all__ = ["EPW", "EPWError", "read_epw", "parse_epw", "FIELDS", "MAX_FILE_BYTES", "MAX_LINE_BYTES",
           "MAX_RECORDS", "MAX_BAD_SHARE", "NIGHT_SUNSHINE_HOURS", "NIGHT_GLOBAL_W_M2", "HEADER_KEYWORDS"]

#: Field index -> (name, missing-value marker) for the fields read here.
FIELDS = {
    1: ("month", None), 2: ("day", None), 3: ("hour", None), 4: ("minute", None),
    6: ("dry_bulb_c", 99.9), 7: ("dew_point_c", 99.9), 9: ("pressure_pa", 999999.0),
    13: ("global_horizontal_w_m2", 9999.0), 14: ("direct_normal_w_m2", 9999.0),
    15: ("diffuse_horizontal_w_m2", 9999.0), 16: ("global_horizontal_lux", 999999.0),
    17: ("direct_normal_lux", 999999.0), 18: ("diffuse_horizontal_lux", 999999.0),
    19: ("zenith_luminance_cd_m2", 9999.0),
}
#: A year of hourly EPW records is 1.5-3 MB; a larger file is not a weather file of one year.
MAX_FILE_BYTES = 32 * 1024 * 1024
#: EPW lines are under 1 kB (the design-conditions header line is the longest, about 600 bytes).
MAX_LINE_BYTES = 64 * 1024
#: One leap year of hourly records.
MAX_RECORDS = 8784
#: More than this share of the sun-up hours unusable in one irradiance field: the file is refused.
MAX_BAD_SHARE = 0.05
#: More hours than this of sunshine while the sun is down at the site: a time-zone/site warning.
NIGHT_SUNSHINE_HOURS = 10
#: Global horizontal irradiance above this with the sun below the horizon the whole hour counts as
#: sunshine (twilight gives a few W/m^2).
NIGHT_GLOBAL_W_M2 = 20.0
#: The header lines EnergyPlus reads, each once (LOCATION first; "DATA PERIODS" last by convention).
HEADER_KEYWORDS = ("LOCATION", "DESIGN CONDITIONS", "TYPICAL/EXTREME PERIODS", "GROUND TEMPERATURES",
                   "HOLIDAYS/DAYLIGHT SAVINGS", "COMMENTS 1", "COMMENTS 2", "DATA PERIODS")

_MONTHS = ("January", "February", "March", "April", "May", "June", "July", "August", "September", "October",
           "November", "December")
_DAYS = (31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)
_FIRST_DAY = np.concatenate([[0], np.cumsum(_DAYS)[:-1]])  # day offset of each month, leap calendar
_HOURS_LEAP = 24 * 366
_LABELS = {6: "dry-bulb temperature", 7: "dew-point temperature", 9: "station pressure",
           13: "global horizontal radiation", 14: "direct normal radiation", 15: "diffuse horizontal radiation",
           16: "global horizontal illuminance", 17: "direct normal illuminance",
           18: "diffuse horizontal illuminance", 19: "zenith luminance"}
#: Irradiance fields checked against the sun: index in FIELDS order -> (label, horizontal?).
_SOLAR = {"global_horizontal_w_m2": ("global horizontal radiation", True),
          "direct_normal_w_m2": ("direct normal radiation", False),
          "diffuse_horizontal_w_m2": ("diffuse horizontal radiation", True)}
#: The fields the sky is built from (perez.sky_vector): an hour without them is not usable.
_SKY_FIELDS = ("direct_normal_w_m2", "diffuse_horizontal_w_m2")


class EPWError(ValueError):
    """A weather file that cannot be used; the message is one line naming the file and the line."""


@dataclasses.dataclass
class EPW:
    """The site (``city``, ``country``, ``latitude_deg`` N, ``longitude_deg`` E, ``time_zone_h``,
    ``elevation_m``) and hourly arrays named as in ``FIELDS`` (NaN where the file says missing).
    ``notes``: what the checks found (module docstring), one line each; ``usable`` (T,): hours whose
    direct normal and diffuse horizontal irradiance can be used; ``line_numbers`` (T,): each record's
    line in the file; ``period``: the records' span in words; ``is_full_year``."""

    city: str
    country: str
    latitude_deg: float
    longitude_deg: float
    time_zone_h: float
    elevation_m: float
    data: dict
    notes: list = dataclasses.field(default_factory=list)
    usable: np.ndarray = None
    line_numbers: np.ndarray = None
    period: str = ""
    is_full_year: bool = False

    def __getattr__(self, name):
        data = self.__dict__.get("data", {})
        if name in data:
            return data[name]
        raise AttributeError(name)

    @property
    def count(self):
        return len(self.data["hour"])

    def midpoint_hours(self):
        """Local standard time of each record's midpoint, hours of the day (hour - 0.5)."""
        return self.data["hour"] - 0.5

    def midpoint_datetimes(self, year=None):
        """Timezone-aware datetimes (fixed offset ``time_zone_h``) of the records' midpoints. ``year``:
        the calendar year to use (typical years mix years; default: the first record's year, or 2026)."""
        tz = _dt.timezone(_dt.timedelta(hours=float(self.time_zone_h)))
        y = int(year if year is not None else (self.data["year"][0] if "year" in self.data else 2026))
        out = []
        for m, d, h in zip(self.data["month"], self.data["day"], self.data["hour"]):
            try:
                base = _dt.datetime(y, int(m), int(d), tzinfo=tz)
            except ValueError:  # 29 February in a non-leap year: keep the record on 28 February
                base = _dt.datetime(y, int(m), int(d) - 1, tzinfo=tz)
            out.append(base + _dt.timedelta(hours=float(h) - 0.5))
        return out


# --- reading: lines with their numbers, bounded --------------------------------------------------

def read_epw(path):
    """Read and check an EPW file (see the module docstring); ``EPWError`` (a ValueError) with one
    line naming the file and the line for anything that cannot be used."""
    source = os.fspath(path)
    with input_files.open_regular(source, "weather", MAX_FILE_BYTES, EPWError) as fh:
        try:
            return _parse(_file_lines(fh, source), source)
        except OSError as exc:
            raise EPWError(f"{source}: cannot read it ({exc.strerror or exc})") from None


def parse_epw(text, source="EPW"):
    """An ``EPW`` from the file's text; ``EPWError`` (a ValueError) naming the line for malformed input."""
    def lines():
        for number, line in enumerate(text.splitlines(), start=1):
            if "\0" in line:
                raise EPWError(f"{source} line {number}: binary data (a NUL byte): not an EPW text file")
            yield number, line

    return _parse(lines(), source)


def _file_lines(fh, source):
    number = 0
    while True:
        raw = fh.readline(MAX_LINE_BYTES + 1)
        if not raw:
            return
        number += 1
        if b"\0" in raw:
            raise EPWError(f"{source} line {number}: binary data (a NUL byte): not an EPW text file")
        if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
            raise EPWError(f"{source} line {number}: longer than {MAX_LINE_BYTES} bytes: not an EPW line")
        try:
            line = raw.decode("utf-8")
        except UnicodeDecodeError:
            line = raw.decode("latin-1")
        yield number, line.rstrip("\r\n")


def _float(text, what, line, source="EPW"):
    try:
        value = float(text)
    except ValueError:
        raise EPWError(f"{source} line {line}: {what} is not a number ({text.strip()[:40]!r})") from None
    if not math.isfinite(value):
        raise EPWError(f"{source} line {line}: {what} is {text.strip()!r}, not a finite number (EPW writes a "
                       "missing value as its field's code, e.g. 9999 for radiation)")
    return value


def _keyword(line):
    return line.split(",", 1)[0].strip().upper()


def _header(lines, source):
    """The LOCATION fields, after checking the 8 header lines."""
    seen = {}
    loc = None
    for number, line in lines:
        if not line.strip():
            continue
        k = len(seen) + 1
        line = line.lstrip("\ufeff") if k == 1 else line  # a byte-order mark before LOCATION
        key = _keyword(line)
        if k == 1:
            if not key.startswith("LOCATION"):
                raise EPWError(f"{source}: not an EPW file (the first line must start with LOCATION)")
            key = "LOCATION"
            loc = [c.strip() for c in line.split(",")]
        elif key.startswith("HOLIDAYS/DAYLIGHT SAVING"):
            key = "HOLIDAYS/DAYLIGHT SAVINGS"
        if key not in HEADER_KEYWORDS:
            what = "an hourly record" if key[:1].isdigit() or key[:1] == "-" else repr(line.strip()[:40])
            raise EPWError(f"{source} line {number}: {what} where header line {k} of 8 is expected: the header "
                           f"has {k - 1} lines, an EPW has 8 ({', '.join(HEADER_KEYWORDS)})")
        if key in seen:
            raise EPWError(f"{source} line {number}: a second {key} header line (line {seen[key]} was one)")
        seen[key] = number
        if key == "DATA PERIODS":
            _data_periods(line, number, source)
        if k == 8:
            return loc
    if loc is None:
        raise EPWError(f"{source}: not an EPW file (the first line must start with LOCATION)")
    raise EPWError(f"{source}: the file ends after {len(seen)} header lines: an EPW has 8, then the hourly records")


def _data_periods(line, number, source):
    cells = [c.strip() for c in line.split(",")]
    try:
        per_hour = float(cells[2])
    except (IndexError, ValueError):
        raise EPWError(f"{source} line {number}: DATA PERIODS needs the number of periods and of records per "
                       f"hour (e.g. 'DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31')") from None
    if per_hour != 1:
        raise EPWError(f"{source} line {number}: DATA PERIODS gives {cells[2]} records per hour: only hourly EPW "
                       "files (1 record per hour) are read")


def _when(month, day, hour):
    return f"{int(day)} {_MONTHS[int(month) - 1]} hour {int(hour)}"


def _index(month, day, hour):
    """Hour of the leap calendar year, 0 = 1 January hour 1."""
    return (int(_FIRST_DAY[month - 1]) + day - 1) * 24 + hour - 1


_FEB28_LAST = _index(2, 28, 24)


def _whole(text, what, low, high, number, source):
    value = _float(text, what, number, source)
    if not (value == int(value) and low <= value <= high):
        raise EPWError(f"{source} line {number}: {what} must be a whole number {low}-{high}, got {text.strip()!r}")
    return int(value)


def _parse(lines, source):
    lines = iter(lines)
    loc = _header(lines, source)
    if len(loc) < 10:
        raise EPWError(f"{source} line 1: LOCATION needs 10 fields, got {len(loc)}")
    lat, lon = _float(loc[6], "latitude", 1, source), _float(loc[7], "longitude", 1, source)
    tz, elev = _float(loc[8], "time zone", 1, source), _float(loc[9], "elevation", 1, source)
    if not (-90 <= lat <= 90 and -180 <= lon <= 180 and -12 <= tz <= 14 and -500 <= elev <= 9000):
        raise EPWError(f"{source} line 1: latitude/longitude/time zone/elevation out of range "
                       f"({lat}, {lon}, {tz}, {elev})")
    names = ["year"] + [FIELDS[i][0] for i in FIELDS]
    values = np.empty((MAX_RECORDS, len(names)))
    numbers = np.empty(MAX_RECORDS, np.int64)
    n = 0
    first = previous = None
    for number, line in lines:
        if not line.strip():
            continue
        cells = line.split(",")
        if n == 0 and not _keyword(line)[:1].isdigit():
            raise EPWError(f"{source} line {number}: expected the first hourly record, got "
                           f"{line.strip()[:40]!r}: an EPW header has 8 lines")
        if len(cells) < 20:
            raise EPWError(f"{source} line {number}: a data record needs at least 20 fields, got {len(cells)}")
        year = _whole(cells[0], "year", 0, 9999, number, source)
        month = _whole(cells[1], "month", 1, 12, number, source)
        day = _whole(cells[2], "day", 1, 31, number, source)
        hour = _whole(cells[3], "hour", 1, 24, number, source)
        _whole(cells[4], "minute", 0, 60, number, source)
        if day > _DAYS[month - 1]:
            raise EPWError(f"{source} line {number}: {day} {_MONTHS[month - 1]} is not a date")
        at = _index(month, day, hour)
        if previous is not None:
            _check_step(previous, (at, month, day, hour, number), first, n, source)
        if n == MAX_RECORDS:
            raise EPWError(f"{source} line {number}: more than {MAX_RECORDS} hourly records: one year per file")
        numbers[n] = number
        values[n, 0] = year
        for k, i in enumerate(FIELDS, start=1):
            if i > 4:
                values[n, k] = _float(cells[i], _LABELS[i], number, source)
        values[n, 1:5] = month, day, hour, float(cells[4])
        previous = (at, month, day, hour, number)
        first = first or previous
        n += 1
    if n == 0:
        raise EPWError(f"{source}: no hourly records after the 8 header lines")
    values, numbers = values[:n].copy(), numbers[:n].copy()
    data = {"year": values[:, 0].astype(int)}
    for k, (_i, (name, missing)) in enumerate(FIELDS.items(), start=1):
        col = values[:, k]
        if missing is not None:
            col = np.where(col >= missing, np.nan, col)
        data[name] = col
    for name in ("month", "day", "hour", "minute"):
        data[name] = data[name].astype(int)
    raw = {name: values[:, 1 + list(FIELDS.values()).index((name, 9999.0))] for name in _SOLAR}
    leap = bool(np.any((data["month"] == 2) & (data["day"] == 29)))
    period = (f"{n} hourly records from {_when(*first[1:4])} (line {first[4]}) to "
              f"{_when(*previous[1:4])} (line {previous[4]})")
    weather = EPW(loc[1], loc[3], lat, lon, tz, elev, data, line_numbers=numbers, period=period,
                  is_full_year=n == (8784 if leap else 8760))
    _check_sun(weather, raw, leap, source)
    return weather


def _check_step(previous, record, first, count, source):
    """One hour after the previous record (29 February may be skipped, 31 December wraps once)."""
    at, month, day, hour, number = record
    before, line_before = previous[0], previous[4]
    step = (at - before) % _HOURS_LEAP
    if step == 1 or (step == 25 and before == _FEB28_LAST):
        if at == first[0]:
            raise EPWError(f"{source} line {number}: the year starts again ({_when(month, day, hour)} as on line "
                           f"{first[4]}) after {count} records: one year per file (a two-year file is refused)")
        return
    here, there = _when(month, day, hour), _when(*previous[1:4])
    if step == 0:
        raise EPWError(f"{source} line {number}: {here} repeats line {line_before} (a duplicated hour)")
    if step < _HOURS_LEAP // 2:
        missing = step - 1 - (24 if before <= _FEB28_LAST < _index(3, 1, 1) <= at else 0)
        raise EPWError(f"{source} line {number}: {here} follows {there} (line {line_before}): {missing} hour(s) "
                       "missing; the records must be consecutive hours")
    raise EPWError(f"{source} line {number}: {here} goes back in time after {there} (line {line_before}): the "
                   "records must be in time order")


# --- irradiance against the sun at the site ------------------------------------------------------

def _sun(weather, leap, chunk=256):
    """(sin of the sun's largest apparent elevation over each hour, the sun down the whole hour,
    extraterrestrial normal irradiance E0 W/m^2), NREL SPA at each hour's start, middle and end, in
    chunks so that memory stays bounded."""
    year = 2024 if leap else 2026
    d = weather.data
    month_start = np.array([(_dt.date(year, m, 1) - _dt.date(1970, 1, 1)).days for m in range(1, 13)])
    end = (month_start[d["month"] - 1] + d["day"] - 1) * 86400.0 + (d["hour"] - weather.time_zone_h) * 3600.0
    sin_max = np.empty(len(end))
    down = np.empty(len(end), bool)
    e0 = np.empty(len(end))
    for a in range(0, len(end), chunk):
        t = end[a:a + chunk]
        times = np.concatenate([t - 3600.0, t - 1800.0, t])
        pos = solar_position.solar_position(times, weather.latitude_deg, weather.longitude_deg,
                                            elevation_m=weather.elevation_m)
        elev = np.asarray(pos.elevation_deg, float).reshape(3, -1)
        sin_max[a:a + chunk] = np.sin(np.radians(elev.max(axis=0)))
        down[a:a + chunk] = np.all(elev < 0.0, axis=0)
        e0[a:a + chunk] = SOLAR_CONSTANT / np.asarray(pos.earth_sun_distance_au, float).reshape(3, -1)[1] ** 2
    return sin_max, down, e0


def _lines_text(numbers, limit=3):
    """'lines 12-15, 40, 77-80 and 9 more hours' from sorted line numbers (consecutive ones as ranges)."""
    numbers = [int(v) for v in numbers]
    runs = []
    for v in numbers:
        if runs and v == runs[-1][1] + 1:
            runs[-1][1] = v
        else:
            runs.append([v, v])
    shown = ", ".join(f"{a}-{b}" if b > a else f"{a}" for a, b in runs[:limit])
    rest = sum(b - a + 1 for a, b in runs[limit:])
    return f"line{'s' if len(numbers) > 1 else ''} {shown}" + (f" and {rest} more" if rest else "")


def _check_sun(weather, raw, leap, source):
    sin_max, down, e0 = _sun(weather, leap)
    up = ~down
    n_up = int(up.sum())
    lines = weather.line_numbers
    usable = np.ones(weather.count, bool)
    night_zero = np.zeros(weather.count, bool)
    dni, ghi = raw["direct_normal_w_m2"], raw["global_horizontal_w_m2"]
    sunny = down & (((dni > 0) & (dni < 9999.0)) | ((ghi > NIGHT_GLOBAL_W_M2) & (ghi < 9999.0)))
    # Sunshine at night: the hours are misplaced against the sun, so horizontal values cannot be
    # compared with the sun's height (direct normal is still compared with E0).
    misplaced = int(sunny.sum()) > NIGHT_SUNSHINE_HOURS
    if misplaced:
        weather.notes.append(
            f"warning: sunshine (direct normal > 0 or global horizontal > {NIGHT_GLOBAL_W_M2:g} W/m^2) in "
            f"{int(sunny.sum())} hours while the sun is below the horizon at {weather.latitude_deg:g} N "
            f"{weather.longitude_deg:g} E ({_lines_text(lines[sunny])}; more than {NIGHT_SUNSHINE_HOURS} h): the "
            f"time zone (UTC{weather.time_zone_h:+g} h) or the site in the LOCATION line is probably wrong; "
            "global and diffuse horizontal radiation were not compared with the sun's height")
    for name, (label, horizontal) in _SOLAR.items():
        v = raw[name]
        missing, negative = v == 9999.0, v < 0.0
        # + 0.5 W/m^2: the file's rounding to whole numbers. Above E0 is impossible at any hour (1e9
        # too: only 9999 itself means missing); horizontal values also above E0 sin(elevation).
        above = ~missing & (v > e0 + 0.5)
        if horizontal and not misplaced:
            above |= ~missing & up & (v > e0 * np.maximum(sin_max, 0.0) + 0.5)
        kinds = ((missing & up, "missing (9999)"), (negative & up, "negative"),
                 (above, "above the extraterrestrial irradiance" if horizontal else
                  f"above the extraterrestrial {SOLAR_CONSTANT:g} W/m^2 / R^2 (at most 1414 W/m^2)"))
        bad = kinds[0][0] | kinds[1][0] | kinds[2][0]
        count = int(bad.sum())
        if name in _SKY_FIELDS:
            night_zero |= (missing | negative) & down
        if not count:
            continue
        what = ", ".join(f"{text} {int(m.sum())} h" for m, text in kinds if m.any())
        if count > MAX_BAD_SHARE * max(n_up, 1):
            k = int(np.argmax(bad))
            value = "9999 (missing)" if missing[k] else f"{v[k]:g} W/m^2"
            raise EPWError(f"{source} line {lines[k]}: {label} {value} ({_when(*_mdh(weather, k))}); {count} of "
                           f"{n_up} sun-up hours unusable ({what}), more than {100 * MAX_BAD_SHARE:g} %: repair the "
                           "file (e.g. EnergyPlus's Weather Converter fills gaps) or use another")
        use = "left out of the metrics" if name in _SKY_FIELDS else \
            "not used (the sky is built from direct normal and diffuse horizontal radiation)"
        weather.notes.append(f"{label}: {what} of {n_up} sun-up hours ({_lines_text(lines[bad])}): {use}")
        if name in _SKY_FIELDS:
            usable &= ~bad
    night_zero &= usable
    if night_zero.any():
        weather.notes.append(f"{int(night_zero.sum())} hours with the sun below the horizon hold a missing (9999) "
                             f"or negative direct normal or diffuse radiation ({_lines_text(lines[night_zero])}): "
                             "taken as 0 (the sun is down)")
    weather.usable = usable


def _mdh(weather, k):
    return weather.data["month"][k], weather.data["day"][k], weather.data["hour"][k]

"""EnergyPlus weather files (EPW), pure Python/numpy: the site and the hourly solar fields.

Format (EnergyPlus "Auxiliary Programs", Weather Converter, EPW CSV format): 8 header lines, the
first ``LOCATION,city,state,country,source,WMO,latitude (deg N),longitude (deg E),time zone (h from
UTC),elevation (m)``; then one comma-separated record per hour with, among 35 fields (0-based):
0 year, 1 month, 2 day, 3 hour (1-24: the hour ENDING at that local standard time), 4 minute,
6 dry-bulb and 7 dew-point temperature (deg C), 9 station pressure (Pa), 13 global horizontal,
14 direct normal, 15 diffuse horizontal radiation (Wh/m^2 over the hour = mean W/m^2),
16 global horizontal, 17 direct normal, 18 diffuse horizontal illuminance (lux), 19 zenith luminance
(cd/m^2). Missing values are 9999 (radiation) and 999999 (illuminance, luminance): returned as NaN.

``read_epw`` returns an ``EPW`` with the site and arrays of length n_hours; ``midpoint_hours``
gives the local standard time of each record's midpoint (hour - 0.5), the time used for the sun.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt

import numpy as np

__all__ = ["EPW", "read_epw", "parse_epw", "FIELDS"]

#: Field index -> (name, missing-value marker) for the fields read here.
FIELDS = {
    1: ("month", None), 2: ("day", None), 3: ("hour", None), 4: ("minute", None),
    6: ("dry_bulb_c", 99.9), 7: ("dew_point_c", 99.9), 9: ("pressure_pa", 999999.0),
    13: ("global_horizontal_w_m2", 9999.0), 14: ("direct_normal_w_m2", 9999.0),
    15: ("diffuse_horizontal_w_m2", 9999.0), 16: ("global_horizontal_lux", 999999.0),
    17: ("direct_normal_lux", 999999.0), 18: ("diffuse_horizontal_lux", 999999.0),
    19: ("zenith_luminance_cd_m2", 9999.0),
}


@dataclasses.dataclass
class EPW:
    """The site (``city``, ``country``, ``latitude_deg`` N, ``longitude_deg`` E, ``time_zone_h``,
    ``elevation_m``) and hourly arrays named as in ``FIELDS`` (NaN where the file says missing)."""

    city: str
    country: str
    latitude_deg: float
    longitude_deg: float
    time_zone_h: float
    elevation_m: float
    data: dict

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


def _float(text, what, line):
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"EPW line {line}: {what} is not a number ({text!r})") from None


def parse_epw(text, source="EPW"):
    """An ``EPW`` from the file's text; ValueError naming the line for malformed input."""
    lines = text.splitlines()
    if not lines or not lines[0].upper().startswith("LOCATION"):
        raise ValueError(f"{source}: not an EPW file (the first line must start with LOCATION)")
    loc = [c.strip() for c in lines[0].split(",")]
    if len(loc) < 10:
        raise ValueError(f"{source} line 1: LOCATION needs 10 fields, got {len(loc)}")
    lat, lon = _float(loc[6], "latitude", 1), _float(loc[7], "longitude", 1)
    tz, elev = _float(loc[8], "time zone", 1), _float(loc[9], "elevation", 1)
    if not (-90 <= lat <= 90 and -180 <= lon <= 180 and -12 <= tz <= 14):
        raise ValueError(f"{source} line 1: latitude/longitude/time zone out of range ({lat}, {lon}, {tz})")
    rows = []
    for number, line in enumerate(lines[8:], start=9):
        if not line.strip():
            continue
        cells = line.split(",")
        if len(cells) < 20:
            raise ValueError(f"{source} line {number}: a data record needs at least 20 fields, got {len(cells)}")
        rows.append([_float(cells[0], "year", number)] + [_float(cells[i], FIELDS[i][0], number) for i in FIELDS])
    if not rows:
        raise ValueError(f"{source}: no hourly records after the 8 header lines")
    a = np.array(rows, float)
    data = {"year": a[:, 0].astype(int)}
    for k, (i, (name, missing)) in enumerate(FIELDS.items(), start=1):
        col = a[:, k]
        if missing is not None:
            col = np.where(col >= missing, np.nan, col)
        data[name] = col
    for name in ("month", "day", "hour"):
        data[name] = data[name].astype(int)
    bad = (data["month"] < 1) | (data["month"] > 12) | (data["day"] < 1) | (data["day"] > 31) | \
          (data["hour"] < 1) | (data["hour"] > 24)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise ValueError(f"{source} line {9 + k}: month/day/hour out of range "
                         f"({data['month'][k]}, {data['day'][k]}, {data['hour'][k]})")
    return EPW(loc[1], loc[3], lat, lon, tz, elev, data)


def read_epw(path):
    """Read an EPW file (see the module docstring)."""
    try:
        with open(path, encoding="latin-1") as f:
            text = f.read()
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None
    return parse_epw(text, source=str(path))

"""Where the sun is: the NREL Solar Position Algorithm, vectorised over times (pure numpy, no bpy).

Written from Reda, I. and Andreas, A. (2008), *Solar Position Algorithm for Solar Radiation
Applications*, NREL/TP-560-34302 (the "SPA": ±0.0003 deg from -2000 to 6000), sections 3.1-3.14;
its periodic-term tables live in :mod:`._spa_tables`. pvlib's ``spa_python`` is the test's
independent reference (tests/test_solar_position.py), never imported here.

Conventions (stated once, used everywhere in Radiometer)
-------------------------------------------------------
* **Azimuth**: degrees clockwise from true north, seen from above (0 north, 90 east, 180 south,
  270 west), in [0, 360): SPA's "topocentric azimuth angle" (eq. 45).
* **Elevation**: apparent topocentric elevation, i.e. with atmospheric refraction (SPA eq. 42-43:
  Bennett's formula scaled by pressure/1010 hPa and 283 K/(273 + T)), applied only while the
  geometric centre is above -(0.26667 + 0.5667) deg (the sun's radius plus the refraction at the
  horizon, as SPA and pvlib do); below that the apparent and true elevation are equal.
  ``zenith_deg`` = 90 - elevation.
* **Delta T** (TT - UT, s): Espenak & Meeus (2006) polynomials (NASA "Polynomial expressions for
  Delta T", the same model as pvlib's ``spa.calculate_deltat``) unless given. Only the sun's
  ecliptic longitude depends on it (about 0.04 arcsec per second of Delta T), so the model's few
  seconds of error near the present do not matter at the 0.0003 deg level.
* **Scene direction** (:func:`sun_direction`): a unit vector *towards* the sun with +X east, +Y
  north, +Z up when ``north_offset_deg`` is 0. ``north_offset_deg`` is the angle from the scene's
  +Y axis to true north, counter-clockwise seen from above (positive turns north towards -X): true
  north is (-sin o, cos o, 0) and east (cos o, sin o, 0).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt

import numpy as np

from . import _spa_tables as T

#: Unix time (s) of the Julian day epoch J2000.0 offset: JD = unix / 86400 + 2440587.5.
_UNIX_EPOCH_JD = 2440587.5
#: Semi-diameter of the sun plus refraction at the horizon (deg): SPA's refraction switch.
_SUN_RADIUS_DEG = 0.26667
ATMOSPHERIC_REFRACTION_AT_HORIZON_DEG = 0.5667
#: Equatorial radius of the Earth used by SPA (m) and the flattening ratio b/a.
_EARTH_RADIUS_M = 6378140.0
_EARTH_B_OVER_A = 0.99664719


def delta_t_espenak_meeus(year, month):
    """Delta T = TT - UT in seconds (Espenak & Meeus 2006 polynomials, valid -1999..3000).

    Parameters
    ----------
    year, month : array_like
        Gregorian year and month (1-12) of UT.
    """
    year = np.asarray(year, float)
    y = year + (np.asarray(month, float) - 0.5) / 12.0
    u = (y - 1820.0) / 100.0
    long_term = -20.0 + 32.0 * u * u
    pieces = [
        (year < -500, long_term),
        ((-500 <= year) & (year < 500), np.polyval([0.0090316521, 0.022174192, -0.1798452, -5.952053, 33.78311,
                                                    -1014.41, 10583.6], y / 100.0)),
        ((500 <= year) & (year < 1600), np.polyval([0.0083572073, -0.005050998, -0.8503463, 0.319781, 71.23472,
                                                    -556.01, 1574.2], (y - 1000.0) / 100.0)),
        ((1600 <= year) & (year < 1700), np.polyval([1.0 / 7129, -0.01532, -0.9808, 120.0], y - 1600.0)),
        ((1700 <= year) & (year < 1800), np.polyval([-1.0 / 1174000, 0.00013336, -0.0059285, 0.1603, 8.83],
                                                    y - 1700.0)),
        ((1800 <= year) & (year < 1860), np.polyval([0.000000000875, -0.0000001699, 0.0000121272, -0.00037436,
                                                     0.0041116, 0.0068612, -0.332447, 13.72], y - 1800.0)),
        ((1860 <= year) & (year < 1900), np.polyval([1.0 / 233174, -0.0004473624, 0.01680668, -0.251754, 0.5737,
                                                     7.62], y - 1860.0)),
        ((1900 <= year) & (year < 1920), np.polyval([-0.000197, 0.0061966, -0.0598939, 1.494119, -2.79],
                                                    y - 1900.0)),
        ((1920 <= year) & (year < 1941), np.polyval([0.0020936, -0.076100, 0.84493, 21.20], y - 1920.0)),
        ((1941 <= year) & (year < 1961), np.polyval([1.0 / 2547, -1.0 / 233, 0.407, 29.07], y - 1950.0)),
        ((1961 <= year) & (year < 1986), np.polyval([-1.0 / 718, -1.0 / 260, 1.067, 45.45], y - 1975.0)),
        ((1986 <= year) & (year < 2005), np.polyval([0.00002373599, 0.000651814, 0.0017275, -0.060374, 0.3345,
                                                     63.86], y - 2000.0)),
        ((2005 <= year) & (year < 2050), np.polyval([0.005589, 0.32217, 62.92], y - 2000.0)),
        ((2050 <= year) & (year < 2150), long_term - 0.5628 * (2150.0 - y)),
        (year >= 2150, long_term),
    ]
    return np.select([c for c, _ in pieces], [v for _, v in pieces])


# --- time input ---------------------------------------------------------------------------------

def unix_seconds(when):
    """Seconds since 1970-01-01 UTC (float64 array, shape of ``when``) of timezone-aware datetimes.

    ``when``: a ``datetime`` with a ``tzinfo`` (any: ``zoneinfo.ZoneInfo``, ``timezone.utc``,
    a fixed offset) or a sequence / array of them. Raises ``ValueError`` with one line for a naive
    datetime (its time zone would be a guess) or anything that is not a datetime.
    """
    scalar = isinstance(when, _dt.datetime)
    items = [when] if scalar else list(np.asarray(when, dtype=object).ravel())
    if not items:
        raise ValueError("no times given: pass a timezone-aware datetime or a sequence of them")
    out = np.empty(len(items))
    for i, t in enumerate(items):
        if not isinstance(t, _dt.datetime):
            raise ValueError(f"time {i}: expected a timezone-aware datetime, got {type(t).__name__} {t!r}")
        if t.tzinfo is None or t.tzinfo.utcoffset(t) is None:
            raise ValueError(f"time {t.isoformat()} has no time zone: give tzinfo (e.g. "
                             "zoneinfo.ZoneInfo('Europe/London') or datetime.timezone.utc)")
        out[i] = t.timestamp()
    return out[0] if scalar else out.reshape(np.shape(np.asarray(when, dtype=object)))


def _utc_year_month(unix):
    dt = np.asarray(unix, float).astype("datetime64[s]")
    years = dt.astype("datetime64[Y]").astype(int) + 1970
    months = dt.astype("datetime64[M]").astype(int) % 12 + 1
    return years, months


# --- the algorithm ------------------------------------------------------------------------------

def _periodic(table, jme):
    # sum_i A_i cos(B_i + C_i JME) over the rows, broadcast over the times
    return np.sum(table[:, 0] * np.cos(table[:, 1] + table[:, 2] * jme[..., None]), axis=-1)


def _series(tables, jme):
    return sum(_periodic(t, jme) * jme ** k for k, t in enumerate(tables)) / 1e8


@dataclasses.dataclass(frozen=True)
class SolarPosition:
    """The sun seen from one place at N times (arrays of shape (N,) or scalars for one time).

    Attributes
    ----------
    unix_s : seconds since 1970-01-01 UTC.
    azimuth_deg : clockwise from true north, [0, 360).
    elevation_deg : apparent (with refraction) topocentric elevation, deg.
    zenith_deg : 90 - elevation_deg.
    true_elevation_deg : elevation without refraction, deg.
    declination_deg : topocentric declination, deg.
    equation_of_time_min : apparent minus mean solar time, minutes.
    earth_sun_distance_au : heliocentric radius vector R, AU.
    delta_t_s : TT - UT used, s.
    """

    unix_s: np.ndarray
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    zenith_deg: np.ndarray
    true_elevation_deg: np.ndarray
    declination_deg: np.ndarray
    equation_of_time_min: np.ndarray
    earth_sun_distance_au: np.ndarray
    delta_t_s: np.ndarray
    latitude_deg: float
    longitude_deg: float
    elevation_m: float
    north_offset_deg: float = 0.0

    @property
    def direction(self):
        """Unit vector(s) towards the sun in scene axes (module convention, this north offset), (..., 3)."""
        return sun_direction(self.azimuth_deg, self.elevation_deg, self.north_offset_deg)

    @property
    def above_horizon(self):
        """True where the sun's apparent centre is above the horizon (elevation > 0)."""
        return np.asarray(self.elevation_deg) > 0.0

    def to_dict(self):
        """JSON-ready: lists for N times, numbers for one."""
        out = {f.name: np.asarray(getattr(self, f.name)).tolist() for f in dataclasses.fields(self)}
        out["direction"] = np.asarray(self.direction).tolist()
        return out


def solar_position(unix_s, latitude_deg, longitude_deg, *, elevation_m=0.0, pressure_hpa=1013.25,
                   temperature_c=12.0, delta_t_s=None, north_offset_deg=0.0,
                   atmos_refract_deg=ATMOSPHERIC_REFRACTION_AT_HORIZON_DEG):
    """NREL SPA topocentric sun position for one place at the times ``unix_s``.

    Parameters
    ----------
    unix_s : array_like
        UTC times as seconds since 1970-01-01 (see :func:`unix_seconds`).
    latitude_deg : float
        Geodetic latitude, deg, north positive, [-90, 90].
    longitude_deg : float
        Longitude, deg, east positive, [-180, 180].
    elevation_m : float
        Observer's height above mean sea level, m (parallax only).
    pressure_hpa, temperature_c : float
        Annual mean local pressure (hPa = mbar) and temperature (deg C) for the refraction.
    delta_t_s : float or array_like, optional
        TT - UT in s; default :func:`delta_t_espenak_meeus` of each time's year and month.
    north_offset_deg : float
        Scene north offset for ``direction`` (angle from +Y to true north, counter-clockwise).

    Returns
    -------
    SolarPosition
    """
    lat, lon = float(latitude_deg), float(longitude_deg)
    values = (lat, lon, float(elevation_m), float(pressure_hpa), float(temperature_c))
    if not all(np.isfinite(values)):
        raise ValueError(f"latitude, longitude, elevation, pressure and temperature must be finite, got {values}")
    if not -90.0 <= lat <= 90.0:
        raise ValueError(f"latitude must be within [-90, 90] deg, got {lat}")
    if not -180.0 <= lon <= 180.0:
        raise ValueError(f"longitude must be within [-180, 180] deg (east positive), got {lon}")
    if not pressure_hpa > 0:
        raise ValueError(f"pressure must be > 0 hPa, got {pressure_hpa}")
    if not np.isfinite(north_offset_deg):
        raise ValueError(f"north offset must be finite, got {north_offset_deg}")
    if not temperature_c > -273.15:
        raise ValueError(f"temperature must be above -273.15 deg C, got {temperature_c}")
    scalar = np.ndim(unix_s) == 0
    unix = np.atleast_1d(np.asarray(unix_s, float))
    if not np.all(np.isfinite(unix)):
        raise ValueError("times must be finite")
    if delta_t_s is None:
        delta_t = delta_t_espenak_meeus(*_utc_year_month(unix))
    else:
        delta_t = np.broadcast_to(np.asarray(delta_t_s, float), unix.shape).astype(float)

    # 3.1 time scales
    jd = unix / 86400.0 + _UNIX_EPOCH_JD
    jde = jd + delta_t / 86400.0
    jc = (jd - 2451545.0) / 36525.0
    jce = (jde - 2451545.0) / 36525.0
    jme = jce / 10.0
    # 3.2 heliocentric longitude, latitude (deg), radius (AU)
    L = np.degrees(_series((T.L0, T.L1, T.L2, T.L3, T.L4, T.L5), jme)) % 360.0
    B = np.degrees(_series((T.B0, T.B1), jme))
    R = _series((T.R0, T.R1, T.R2, T.R3, T.R4), jme)
    # 3.3 geocentric
    theta = (L + 180.0) % 360.0
    beta = -B
    # 3.4 nutation in longitude and obliquity (deg)
    x = np.stack([
        297.85036 + 445267.111480 * jce - 0.0019142 * jce ** 2 + jce ** 3 / 189474.0,
        357.52772 + 35999.050340 * jce - 0.0001603 * jce ** 2 - jce ** 3 / 300000.0,
        134.96298 + 477198.867398 * jce + 0.0086972 * jce ** 2 + jce ** 3 / 56250.0,
        93.27191 + 483202.017538 * jce - 0.0036825 * jce ** 2 + jce ** 3 / 327270.0,
        125.04452 - 1934.136261 * jce + 0.0020708 * jce ** 2 + jce ** 3 / 450000.0,
    ], axis=-1)
    arg = np.radians(x @ T.NUTATION_Y.T)  # (N, 63)
    a, b, c, d = T.NUTATION_ABCD.T
    delta_psi = np.sum((a + b * jce[:, None]) * np.sin(arg), axis=-1) / 36e6
    delta_eps = np.sum((c + d * jce[:, None]) * np.cos(arg), axis=-1) / 36e6
    # 3.5 true obliquity of the ecliptic (deg)
    U = jme / 10.0
    eps0 = np.polyval([2.45, 5.79, 27.87, 7.12, -39.05, -249.67, -51.38, 1999.25, -1.55, -4680.93, 84381.448], U)
    eps = eps0 / 3600.0 + delta_eps
    # 3.6-3.7 aberration, apparent sun longitude
    lam = theta + delta_psi - 20.4898 / (3600.0 * R)
    # 3.8 apparent sidereal time at Greenwich (deg)
    nu0 = (280.46061837 + 360.98564736629 * (jd - 2451545.0) + 0.000387933 * jc ** 2 - jc ** 3 / 38710000.0) % 360.0
    nu = nu0 + delta_psi * np.cos(np.radians(eps))
    # 3.9-3.10 geocentric right ascension and declination (deg)
    lam_r, eps_r, beta_r = np.radians(lam), np.radians(eps), np.radians(beta)
    alpha = np.degrees(np.arctan2(np.sin(lam_r) * np.cos(eps_r) - np.tan(beta_r) * np.sin(eps_r),
                                  np.cos(lam_r))) % 360.0
    delta = np.degrees(np.arcsin(np.sin(beta_r) * np.cos(eps_r) + np.cos(beta_r) * np.sin(eps_r) * np.sin(lam_r)))
    # 3.11 observer local hour angle (deg, westward from south)
    H = (nu + lon - alpha) % 360.0
    # 3.12 topocentric right ascension and declination (parallax)
    xi = np.radians(8.794 / (3600.0 * R))
    u = np.arctan(_EARTH_B_OVER_A * np.tan(np.radians(lat)))
    xt = np.cos(u) + elevation_m / _EARTH_RADIUS_M * np.cos(np.radians(lat))
    yt = _EARTH_B_OVER_A * np.sin(u) + elevation_m / _EARTH_RADIUS_M * np.sin(np.radians(lat))
    H_r, delta_r = np.radians(H), np.radians(delta)
    d_alpha = np.arctan2(-xt * np.sin(xi) * np.sin(H_r), np.cos(delta_r) - xt * np.sin(xi) * np.cos(H_r))
    delta_p = np.arctan2((np.sin(delta_r) - yt * np.sin(xi)) * np.cos(d_alpha),
                         np.cos(delta_r) - xt * np.sin(xi) * np.cos(H_r))
    # 3.13 topocentric local hour angle
    H_p = H_r - d_alpha
    # 3.14 topocentric zenith and azimuth
    lat_r = np.radians(lat)
    e0 = np.degrees(np.arcsin(np.sin(lat_r) * np.sin(delta_p) + np.cos(lat_r) * np.cos(delta_p) * np.cos(H_p)))
    with np.errstate(divide="ignore", invalid="ignore"):
        refraction = (pressure_hpa / 1010.0) * (283.0 / (273.0 + temperature_c)) * 1.02 / (
            60.0 * np.tan(np.radians(e0 + 10.3 / (e0 + 5.11))))
    refraction = np.where(e0 >= -(_SUN_RADIUS_DEG + atmos_refract_deg), refraction, 0.0)
    e = e0 + refraction
    gamma = np.degrees(np.arctan2(np.sin(H_p), np.cos(H_p) * np.sin(lat_r) - np.tan(delta_p) * np.cos(lat_r)))
    azimuth = (gamma + 180.0) % 360.0
    # A.1 equation of time (minutes), wrapped into (-20, 20]
    M = np.polyval([-1.0 / 2e6, -1.0 / 15300.0, 1.0 / 49931.0, 0.03032028, 360007.6982779, 280.4664567], jme)
    E = 4.0 * ((M - 0.0057183 - alpha + delta_psi * np.cos(eps_r)) % 360.0)
    E = np.where(E > 20.0, E - 1440.0, E)

    one = (lambda v: v[0]) if scalar else (lambda v: v)
    return SolarPosition(unix_s=one(unix), azimuth_deg=one(azimuth), elevation_deg=one(e), zenith_deg=one(90.0 - e),
                         true_elevation_deg=one(e0), declination_deg=one(np.degrees(delta_p)),
                         equation_of_time_min=one(E), earth_sun_distance_au=one(R), delta_t_s=one(delta_t),
                         latitude_deg=lat, longitude_deg=lon, elevation_m=float(elevation_m),
                         north_offset_deg=float(north_offset_deg))


def sun_direction(azimuth_deg, elevation_deg, north_offset_deg=0.0):
    """Unit vector(s) towards the sun in scene axes, shape (..., 3).

    +X east, +Y north, +Z up when ``north_offset_deg`` = 0; ``north_offset_deg`` is the angle from
    the scene's +Y to true north, counter-clockwise seen from above.
    """
    az = np.radians(np.asarray(azimuth_deg, float))
    el = np.radians(np.asarray(elevation_deg, float))
    o = np.radians(float(north_offset_deg))
    north = np.array([-np.sin(o), np.cos(o), 0.0])
    east = np.array([np.cos(o), np.sin(o), 0.0])
    horizontal = np.cos(el)[..., None]
    return (horizontal * (np.sin(az)[..., None] * east + np.cos(az)[..., None] * north)
            + np.sin(el)[..., None] * np.array([0.0, 0.0, 1.0]))


# --- clear-day direct normal illuminance ---------------------------------------------------------

#: Solar illuminance constant, lx: the extraterrestrial direct normal illuminance at 1 AU
#: (IES Lighting Handbook, 10th ed. (2011), daylighting chapter; Darula, Kittler & Gueymard (2005),
#: "Reference luminous solar constant and solar luminance for illuminance calculations",
#: Solar Energy 79, 559-565: 133.8 klx; the IES value 127.5 klx is used here, as the handbook's
#: extinction coefficients were fitted with it).
SOLAR_ILLUMINANCE_CONSTANT_LX = 127_500.0

#: IES atmospheric extinction coefficients c of E_dn = E_xn exp(-c m) by sky condition.
IES_EXTINCTION = {"clear": 0.21, "partly cloudy": 0.80, "overcast": None}


def relative_air_mass_kasten_young(zenith_deg):
    """Relative optical air mass m (Kasten & Young 1989, Applied Optics 28, 4735), nan at/below the horizon.

    m = 1 / (cos z + 0.50572 (96.07995 - z)^-1.6364), z the apparent zenith angle in deg.
    """
    z = np.asarray(zenith_deg, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        m = 1.0 / (np.cos(np.radians(z)) + 0.50572 * (96.07995 - z) ** -1.6364)
    return np.where(z < 90.0, m, np.nan)


def clear_day_direct_normal_illuminance(zenith_deg, earth_sun_distance_au=1.0, *, sky="clear"):
    """IES clear-day direct normal illuminance E_dn = (E_sc / R^2) exp(-c m), lux; 0 below the horizon.

    The IES Lighting Handbook daylight model (10th ed., 2011; the same form as IES RP-21 and CIBSE's
    "daylighting" guides): E_sc = 127.5 klx the solar illuminance constant, R the Earth-sun distance
    in AU (from SPA, the exact form of the handbook's 1 + 0.034 cos(2 pi (J - 2) / 365)), c the
    extinction coefficient (0.21 for a clear sky, 0.80 partly cloudy; overcast: no direct sun) and
    m the relative air mass (:func:`relative_air_mass_kasten_young`).
    """
    if sky not in IES_EXTINCTION:
        raise ValueError(f"unknown sky {sky!r}: one of {', '.join(IES_EXTINCTION)}")
    c = IES_EXTINCTION[sky]
    z = np.asarray(zenith_deg, float)
    if c is None:
        return np.zeros_like(z)
    m = relative_air_mass_kasten_young(z)
    e = SOLAR_ILLUMINANCE_CONSTANT_LX / np.asarray(earth_sun_distance_au, float) ** 2 * np.exp(-c * m)
    return np.where(z < 90.0, e, 0.0)


# --- time zones -----------------------------------------------------------------------------------

def parse_time_zone(text):
    """A ``tzinfo`` from an IANA name ("Europe/London", via ``zoneinfo``), "UTC", or a fixed UTC offset
    ("+02:00", "-0530", "UTC+1", "+5.5" hours). ValueError with one line otherwise."""
    import re
    import zoneinfo

    name = str(text).strip()
    if not name:
        raise ValueError("empty time zone: give an IANA name such as Europe/London or an offset such as +02:00")
    if name.upper() in ("UTC", "GMT", "Z"):
        return _dt.timezone.utc
    m = re.fullmatch(r"(?:UTC|GMT)?\s*([+-])(\d{1,2})(?::?(\d{2}))?|(?:UTC|GMT)?\s*([+-]\d{1,2}\.\d+)", name,
                     flags=re.IGNORECASE)
    if m:
        if m.group(4):
            minutes = round(float(m.group(4)) * 60.0)
        else:
            minutes = int(m.group(2)) * 60 + int(m.group(3) or 0)
            minutes = -minutes if m.group(1) == "-" else minutes
        if abs(minutes) > 14 * 60:
            raise ValueError(f"UTC offset {name!r} is beyond +-14 h")
        return _dt.timezone(_dt.timedelta(minutes=minutes))
    try:
        return zoneinfo.ZoneInfo(name)
    except (zoneinfo.ZoneInfoNotFoundError, ValueError):
        raise ValueError(f"unknown time zone {name!r}: give an IANA name such as Europe/London or an offset "
                         "such as +02:00") from None


def local_datetime(year, month, day, hour, minute, time_zone, second=0):
    """A timezone-aware datetime for a wall-clock time in ``time_zone`` (see :func:`parse_time_zone`).

    A wall time that does not exist (the hour skipped when clocks go forward) raises ValueError; an
    ambiguous one (the hour repeated when clocks go back) is its first occurrence (``fold=0``).
    """
    tz = parse_time_zone(time_zone) if isinstance(time_zone, str) else time_zone
    t = _dt.datetime(int(year), int(month), int(day), int(hour), int(minute), int(second), tzinfo=tz)
    # A skipped wall time does not survive the round trip through UTC.
    back = t.astimezone(_dt.timezone.utc).astimezone(tz)
    if back.replace(tzinfo=None) != t.replace(tzinfo=None):
        raise ValueError(f"{t.replace(tzinfo=None).isoformat()} does not exist in {time_zone} (clocks go forward)")
    return t

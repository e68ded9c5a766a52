"""A SYNTHETIC year of hourly weather as an EnergyPlus weather file (EPW), pure numpy: for the demo and
for tests, never for a real project (it is generated, not measured).

Model (every part published; the choices are stated in the file's header):

* The sun at each record's midpoint (local standard time, hour - 0.5): NREL SPA
  (:func:`solar_position.solar_position`).
* Clear-sky global horizontal irradiance G_0 = 910 sin(h) - 30 W/m^2 (h the sun's elevation; 0 when
  negative), and its reduction by a cloud cover N (oktas, 0-8): G = G_0 (1 - 0.75 (N/8)^3.4), with the
  diffuse share D/G = 0.3 + 0.7 (N/8)^2 (Kasten & Czeplak 1980, "Solar and terrestrial radiation
  dependent on the amount and type of cloud", Solar Energy 24, 177-189, eqs. for Hamburg). The beam
  part G - D gives the direct normal irradiance (G - D) / sin(h); overcast (N = 8) has D = G, no sun.
* The cloud cover: one value per block of ``block_hours`` hours, drawn from a seeded generator so that
  its mean over the year is ``mean_cloud_cover`` (a stated fraction of the sky, default 0.65, about
  5.2 oktas: an assumption near the long-term mean cloud amount of southern England, not a measured
  series); N is drawn as 8 x Beta(a, b) with a + b = 1 (a U-shaped spread: most blocks nearly clear or
  nearly overcast, as cloud climatologies show), rounded to whole oktas.
* Illuminance fields from the irradiances by Perez et al. 1990's luminous efficacy
  (:func:`perez.efficacy`, the model ``annual`` uses); zenith luminance missing (9999).
* Temperatures: an annual cosine (mean ``mean_temperature_c``, amplitude ``temperature_amplitude_c``,
  warmest on 25 July) with the dew point 4 K below; pressure from the elevation (standard atmosphere).

``synthetic_epw_text`` returns the whole file (8 header lines, LOCATION first, the word SYNTHETIC in
its source field and in COMMENTS 1, then 8760 records of 35 fields); ``epw.parse_epw`` reads it back.
"""

import datetime as _dt

import numpy as np

from . import solar_position
from ..skies import perez

__all__ = ["synthetic_year", "synthetic_epw_text", "LONDON"]

#: The demo's site (Heathrow's coordinates are close; the time zone is GMT, the file's standard time).
LONDON = {"city": "London (SYNTHETIC)", "region": "ENG", "country": "GBR", "latitude_deg": 51.5074,
          "longitude_deg": -0.1278, "time_zone_h": 0.0, "elevation_m": 11.0}


def _kasten_czeplak(sin_h, cloud_oktas):
    """(global horizontal, diffuse horizontal) W/m^2 for the sun's sin(elevation) and N oktas."""
    g0 = np.maximum(910.0 * np.asarray(sin_h, float) - 30.0, 0.0)
    n = np.asarray(cloud_oktas, float) / 8.0
    g = g0 * (1.0 - 0.75 * n ** 3.4)
    return g, g * (0.3 + 0.7 * n ** 2)


def synthetic_year(site=LONDON, *, year=2026, mean_cloud_cover=0.65, block_hours=3, seed=2026,
                   mean_temperature_c=11.5, temperature_amplitude_c=7.0):
    """The hourly arrays of a synthetic (non-leap) ``year`` at ``site`` (a dict as ``LONDON``).

    Returns a dict of (8760,) arrays: month, day, hour (1-24, the hour ending), cloud_oktas,
    global_horizontal_w_m2, direct_normal_w_m2, diffuse_horizontal_w_m2 (W/m^2, rounded to whole
    W/m^2 as EPW files hold them), the three illuminances (lx), dry_bulb_c, dew_point_c, pressure_pa."""
    if not 0.0 < mean_cloud_cover < 1.0:
        raise ValueError(f"mean_cloud_cover must be in (0, 1), got {mean_cloud_cover}")
    if _dt.date(year, 12, 31).timetuple().tm_yday != 365:
        raise ValueError(f"{year} is a leap year: give a common year (8760 hours)")
    tz = _dt.timezone(_dt.timedelta(hours=float(site["time_zone_h"])))
    start = _dt.datetime(year, 1, 1, tzinfo=tz)
    ends = [start + _dt.timedelta(hours=k + 1) for k in range(8760)]  # each record's hour ends here
    mids = [t - _dt.timedelta(minutes=30) for t in ends]
    pos = solar_position.solar_position(solar_position.unix_seconds(mids), site["latitude_deg"],
                                        site["longitude_deg"], elevation_m=site["elevation_m"])
    elevation = np.asarray(pos.elevation_deg, float)
    sin_h = np.sin(np.radians(elevation))
    rng = np.random.default_rng(seed)
    blocks = -(-8760 // block_hours)
    # 8 x Beta(a, b), a + b = 1: mean a = mean_cloud_cover, U-shaped (mostly near clear or near overcast)
    cover = rng.beta(mean_cloud_cover, 1.0 - mean_cloud_cover, blocks)
    oktas = np.repeat(np.rint(8.0 * cover), block_hours)[:8760]
    ghi, dhi = _kasten_czeplak(sin_h, oktas)
    up = sin_h > 0.0
    ghi, dhi = np.where(up, np.rint(ghi), 0.0), np.where(up, np.rint(dhi), 0.0)
    beam = ghi - dhi
    dni = np.where(up & (beam > 0), np.rint(beam / np.where(up, sin_h, 1.0)), 0.0)
    ghi = np.where(up, dhi + np.rint(dni * sin_h), 0.0)  # the three agree to the rounding
    day = np.array([t.timetuple().tm_yday for t in mids], float)
    temperature = mean_temperature_c + temperature_amplitude_c * np.cos(2 * np.pi * (day - 206.0) / 365.0)
    dew = temperature - 4.0
    zenith = np.radians(np.clip(90.0 - elevation, 0.0, 90.0))
    lit = up & (dhi > 0)
    eps = np.where(lit, perez.clearness(dni, np.where(lit, dhi, 1.0), perez.clamp_zenith(zenith)), 1.0)
    delta = np.where(lit, perez.brightness(np.where(lit, dhi, 1.0), perez.clamp_zenith(zenith), day), 0.01)
    k_dif, k_dir = perez.efficacy(np.clip(eps, 1.0, 11.9), delta, perez.clamp_zenith(zenith), dew)
    e_dh = np.where(lit, np.rint(dhi * k_dif), 0.0)
    e_dn = np.where(lit, np.rint(dni * k_dir), 0.0)
    pressure = np.rint(101325.0 * (1.0 - 2.25577e-5 * site["elevation_m"]) ** 5.25588)
    return {"month": np.array([t.month for t in mids]), "day": np.array([t.day for t in mids]),
            "hour": np.array([(t - _dt.timedelta(minutes=1)).hour + 1 for t in ends]), "cloud_oktas": oktas,
            "global_horizontal_w_m2": ghi, "direct_normal_w_m2": dni, "diffuse_horizontal_w_m2": dhi,
            "global_horizontal_lux": e_dh + np.rint(e_dn * np.where(up, sin_h, 0.0)), "direct_normal_lux": e_dn,
            "diffuse_horizontal_lux": e_dh, "dry_bulb_c": np.round(temperature, 1), "dew_point_c": np.round(dew, 1),
            "pressure_pa": np.full(8760, pressure)}


def synthetic_epw_text(site=LONDON, *, year=2026, mean_cloud_cover=0.65, block_hours=3, seed=2026):
    """The whole EPW file (str) of :func:`synthetic_year`, its header saying SYNTHETIC and how it was made."""
    y = synthetic_year(site, year=year, mean_cloud_cover=mean_cloud_cover, block_hours=block_hours, seed=seed)
    weekday = _dt.date(year, 1, 1).strftime("%A")
    how = (f"SYNTHETIC weather - generated not measured - do not use for design: clear-sky and cloud model of "
           f"Kasten & Czeplak 1980 (Solar Energy 24 177-189); cloud cover per {block_hours} h from a seeded "
           f"Beta draw with mean {mean_cloud_cover:g} of the sky (seed {seed}); illuminance by Perez et al. 1990 "
           f"efficacy; radiometer/radiometry/sun/synthetic_weather.py")
    head = [f"LOCATION,{site['city']},{site['region']},{site['country']},SYNTHETIC (radiometer),000000,"
            f"{site['latitude_deg']:.4f},{site['longitude_deg']:.4f},{site['time_zone_h']:.1f},{site['elevation_m']:.1f}",
            "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
            "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0", f"COMMENTS 1,{how}",
            f"COMMENTS 2,SYNTHETIC year {year}: 8760 hourly records; mean cloud cover of the drawn year "
            f"{float(np.mean(y['cloud_oktas'])) / 8:.3f}",
            f"DATA PERIODS,1,1,Data,{weekday}, 1/ 1,12/31"]
    rows = []
    for k in range(8760):
        f = [year, int(y["month"][k]), int(y["day"][k]), int(y["hour"][k]), 60, "*9*9*9*9*9*9*9*9*9*9*9*9*9*9*9*9*9*9",
             f"{y['dry_bulb_c'][k]:.1f}", f"{y['dew_point_c'][k]:.1f}", 76, int(y["pressure_pa"][k]), 9999, 9999,
             300, int(y["global_horizontal_w_m2"][k]), int(y["direct_normal_w_m2"][k]),
             int(y["diffuse_horizontal_w_m2"][k]), int(y["global_horizontal_lux"][k]),
             int(y["direct_normal_lux"][k]), int(y["diffuse_horizontal_lux"][k]), 9999, 180, 3.0,
             int(y["cloud_oktas"][k] * 10 / 8 + 0.5), int(y["cloud_oktas"][k] * 10 / 8 + 0.5), 10.0, 77777, 9,
             999999999, 10, 0.1, 0, 88, 0.2, 0, 1]
        rows.append(",".join(str(v) for v in f))
    return "\n".join(head + rows) + "\n"

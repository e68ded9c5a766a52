"""EPW reader (radiometry/sun/epw.py) against pvlib's read_epw (independent) on a small file the test writes."""

import math

import numpy as np
import pytest

from radiometer.radiometry.sun import epw

HEADER = ["LOCATION,Testville,TS,XYZ,synthetic,000000,51.50,-0.12,0.0,20.0",
          "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
          "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0", "COMMENTS 1,written by tests/test_epw.py",
          "COMMENTS 2,", "DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31"]


def write_epw(path, days=2):
    rng = np.random.default_rng(7)
    rows = []
    for day in range(1, days + 1):
        for hour in range(1, 25):
            sun = max(0.0, math.sin(math.pi * (hour - 6.5) / 12))
            dni, dhi = 600 * sun * rng.uniform(0, 1), 150 * sun
            ghi = dhi + dni * sun
            f = [1999, 6, day, hour, 60, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9*9*9", 15.0, 8.0, 60, 101325,
                 1000, 1300, 300, round(ghi), round(dni), round(dhi), round(110 * ghi), round(100 * dni),
                 round(120 * dhi), 9999 if hour == 3 else 5000, 180, 3.0, 5, 3, 10.0, 77777, 9, 999999999, 10, 0.1,
                 0, 88, 0.2, 0, 1]
            rows.append(",".join(str(v) for v in f))
    path.write_text("\n".join(HEADER + rows) + "\n", encoding="latin-1")
    return path


def test_epw_against_pvlib(tmp_path):
    from pvlib.iotools import read_epw as pvlib_read_epw

    path = write_epw(tmp_path / "t.epw")
    w = epw.read_epw(path)
    ref, meta = pvlib_read_epw(str(path))
    assert w.count == len(ref) == 48
    assert (w.latitude_deg, w.longitude_deg, w.time_zone_h, w.elevation_m) == (
        meta["latitude"], meta["longitude"], meta["TZ"], meta["altitude"])
    assert w.city == meta["city"]
    for mine, theirs in (("direct_normal_w_m2", "dni"), ("diffuse_horizontal_w_m2", "dhi"),
                         ("global_horizontal_w_m2", "ghi"), ("direct_normal_lux", "direct_normal_illum"),
                         ("diffuse_horizontal_lux", "diffuse_horizontal_illum"), ("dew_point_c", "temp_dew")):
        np.testing.assert_array_equal(w.data[mine], ref[theirs].to_numpy(float))
    assert np.isnan(w.zenith_luminance_cd_m2[2]) and w.zenith_luminance_cd_m2[3] == 5000
    # midpoints: the record of hour h covers (h-1, h]
    t = w.midpoint_datetimes(2026)
    assert t[0].hour == 0 and t[0].minute == 30 and t[23].hour == 23 and t[23].minute == 30
    assert list(w.midpoint_hours()[:2]) == [0.5, 1.5]


def test_epw_bad_input(tmp_path):
    with pytest.raises(ValueError, match="not an EPW"):
        epw.parse_epw("hello\n")
    path = write_epw(tmp_path / "t.epw", days=1)
    lines = path.read_text(encoding="latin-1").splitlines()
    lines[12] = lines[12].replace(",6,1,", ",13,1,", 1)
    with pytest.raises(ValueError, match="line 13"):
        epw.parse_epw("\n".join(lines))
    lines = path.read_text(encoding="latin-1").splitlines()
    lines[9] = "1999,6,1"
    with pytest.raises(ValueError, match="line 10"):
        epw.parse_epw("\n".join(lines))
    with pytest.raises(ValueError, match="cannot read"):
        epw.read_epw(tmp_path / "missing.epw")

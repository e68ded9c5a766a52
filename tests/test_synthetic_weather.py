"""The demo's SYNTHETIC weather year (radiometry/sun/synthetic_weather.py): a whole EPW year our reader
and pvlib's (independent) read alike, labelled SYNTHETIC, whose hours follow the stated model
(Kasten & Czeplak 1980) at the sun pvlib places independently."""

import numpy as np
import pytest

from radiometer.radiometry.sun import epw, synthetic_weather as sw


@pytest.fixture(scope="module")
def text():
    return sw.synthetic_epw_text()


def test_a_whole_year_our_reader_takes_without_a_note(text):
    w = epw.parse_epw(text, "synthetic.epw")
    assert w.count == 8760 and w.is_full_year and w.notes == [] and bool(np.all(w.usable))
    assert w.city == "London (SYNTHETIC)" and w.latitude_deg == pytest.approx(51.5074)
    head = text.splitlines()[:8]
    assert "SYNTHETIC" in head[0] and "SYNTHETIC" in head[5] and "Kasten & Czeplak 1980" in head[5]


def test_pvlib_reads_the_same_numbers(text, tmp_path):
    pvlib_iotools = pytest.importorskip("pvlib.iotools")
    path = tmp_path / "synthetic.epw"
    path.write_text(text, encoding="latin-1")
    ref, meta = pvlib_iotools.read_epw(str(path))
    w = epw.read_epw(path)
    assert len(ref) == 8760 and meta["latitude"] == pytest.approx(51.5074)
    for ours, theirs in (("global_horizontal_w_m2", "ghi"), ("direct_normal_w_m2", "dni"),
                         ("diffuse_horizontal_w_m2", "dhi"), ("diffuse_horizontal_lux", "diffuse_horizontal_illum"),
                         ("dry_bulb_c", "temp_air")):
        assert np.array_equal(np.asarray(w.data[ours]), ref[theirs].to_numpy(float)), ours


def test_hours_follow_kasten_czeplak_at_the_sun_pvlib_gives(text):
    """G = D + I_n sin h to the file's whole W/m^2; clear blocks (N = 0): G = 910 sin h - 30, D/G = 0.3;
    overcast (N = 8): no direct sun, D = G = 0.25 (910 sin h - 30). The sun from pvlib's SPA, not ours."""
    pvlib = pytest.importorskip("pvlib")
    import pandas as pd

    y = sw.synthetic_year()
    times = pd.date_range("2026-01-01 00:30", periods=8760, freq="h", tz="UTC")  # GMT = the file's standard time
    pos = pvlib.solarposition.spa_python(times, sw.LONDON["latitude_deg"], sw.LONDON["longitude_deg"],
                                         altitude=sw.LONDON["elevation_m"])
    sin_h = np.sin(np.radians(pos["apparent_elevation"].to_numpy()))
    g, d, n = y["global_horizontal_w_m2"], y["diffuse_horizontal_w_m2"], y["direct_normal_w_m2"]
    up = sin_h > 0.05
    assert np.all(np.abs(g - d - n * sin_h)[up] <= 1.0)  # rounding to whole W/m^2
    g0 = 910 * sin_h - 30
    clear, overcast = up & (y["cloud_oktas"] == 0), up & (y["cloud_oktas"] == 8)
    assert clear.sum() > 200 and overcast.sum() > 200
    assert np.abs(g - g0)[clear].max() <= 2.0
    assert np.abs(d - 0.3 * g0)[clear].max() <= 1.0
    assert np.all(n[overcast] == 0) and np.abs(g - 0.25 * g0)[overcast].max() <= 1.0
    assert np.all(g[sin_h < -0.01] == 0)


def test_cloud_cover_has_the_stated_mean():
    """Mean cloud cover of 2920 three-hour blocks of 8 x Beta(0.65, 0.35) rounded to oktas: 0.65 within
    4 standard errors (Beta s.d. sqrt(ab / ((a + b)^2 (a + b + 1))) = 0.337; / sqrt(2920) = 0.0062) plus the
    rounding's bias (at most 1/16)."""
    for seed in (1, 2026):
        mean = float(np.mean(sw.synthetic_year(seed=seed)["cloud_oktas"])) / 8
        assert abs(mean - 0.65) < 4 * 0.0062 + 1 / 16


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="mean_cloud_cover"):
        sw.synthetic_year(mean_cloud_cover=1.0)
    with pytest.raises(ValueError, match="leap year"):
        sw.synthetic_year(year=2028)

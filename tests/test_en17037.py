"""EN 17037 table (pure): levels reproduced by hand on cases whose illuminance is known in closed form."""

import math

import numpy as np
import pytest

from radiometer.radiometry.metrics import en17037


def _year(lux_when_lit, points=20):
    """Hourly illuminance (8760, points) of a horizontal point outdoors under a uniform sky of luminance
    L = E / pi from 06:00 to 18:00 (closed form: E = pi L), 0 lx at night; the daylight-hour mask."""
    hour = np.arange(8760) % 24
    lit = (hour >= 6) & (hour < 18)
    sky_luminance = lux_when_lit / math.pi                    # cd/m²
    e = np.where(lit, math.pi * sky_luminance, 0.0)[:, None] * np.ones(points)
    return e, lit


def test_outdoors_under_constant_diffuse_light():
    e, lit = _year(20000.0)
    row = en17037.daylight_provision_illuminance(e, lit)
    assert row.level == "high" and row.values["daylight_hours"] == 4380
    e, lit = _year(400.0)        # 300 lx met everywhere, 500 lx nowhere
    row = en17037.daylight_provision_illuminance(e, lit)
    assert row.level == "minimum"
    assert row.per_level["minimum"]["share_of_hours_E_T"] == 1.0
    assert row.per_level["medium"]["share_of_hours_E_T"] == 0.0
    assert row.indicative and "17037" in row.source


def test_windowless_box_and_night_hours():
    e = np.zeros((8760, 12))
    assert en17037.daylight_provision_illuminance(e).level == "not met"
    # counting the night as daylight hours halves the time share: 400 lx for 12 h a day is then exactly 50 %
    e, lit = _year(400.0)
    assert en17037.daylight_provision_illuminance(e).per_level["minimum"]["share_of_hours_E_T"] == 0.5
    e[: 8760 // 2 + 24] = 0.0    # a little less than half the lit hours left
    assert en17037.daylight_provision_illuminance(e, lit).level == "not met"


def test_plane_shares_by_hand():
    # 60 % of the plane at 800 lx, 40 % at 200 lx, every hour: E_T 750 over 50 % yes, E_TM 500 over 95 % no;
    # 300/100 lx: yes/yes -> minimum; 500/300: 60 %/60 % -> no
    e = np.tile(np.r_[np.full(12, 800.0), np.full(8, 200.0)], (100, 1))
    row = en17037.daylight_provision_illuminance(e)
    assert row.level == "minimum"
    assert row.per_level["high"]["share_of_hours_E_T"] == 1.0 and row.per_level["high"]["share_of_hours_E_TM"] == 0.0


def test_daylight_factor_method():
    # DF 2 % everywhere with E_v,d 15 klx: D_T(min) = 2 %, D_T(medium) = 3.33 %
    row = en17037.daylight_provision_daylight_factor(np.full(50, 2.0), 15000.0)
    assert row.level == "minimum"
    assert row.per_level["minimum"]["D_T"] == pytest.approx(2.0)
    assert row.per_level["medium"]["D_T"] == pytest.approx(100 * 500 / 15000)
    assert en17037.daylight_provision_daylight_factor(np.full(50, 6.0), 12000.0).level == "medium"  # D_T(high) 6.25 %
    assert en17037.daylight_provision_daylight_factor(np.full(50, 6.3), 12000.0).level == "high"
    with pytest.raises(ValueError):
        en17037.daylight_provision_daylight_factor([1.0], 0.0)


def test_sunlight_glare_view():
    assert [en17037.sunlight_exposure(h).level for h in (1.0, 1.5, 3.9, 4.0)] == ["not met", "minimum", "medium",
                                                                                 "high"]
    d = np.full(100, 0.30)
    d[:4] = 0.5                  # 4 % of the hours above every limit: high
    assert en17037.glare_protection(d).level == "high"
    d[:6] = 0.42                 # 6 % above 0.35 and 0.40, none above 0.45: minimum
    assert en17037.glare_protection(d).level == "minimum"
    d[:6] = 0.5
    assert en17037.glare_protection(d).level == "not met"
    assert en17037.view_out(30, 25, 2).level == "medium"
    assert en17037.view_out(60, 10, 3).level == "minimum"
    assert en17037.view_out(10, 100, 3).level == "not met"
    for bad in (lambda: en17037.glare_protection([]), lambda: en17037.sunlight_exposure(-1),
                lambda: en17037.view_out(10, 5, 4), lambda: en17037.daylight_provision_illuminance(np.ones(5))):
        with pytest.raises(ValueError):
            bad()


def test_table_marks_missing_rows_not_assessed():
    rows = en17037.table(sunlight=en17037.sunlight_exposure(3.0))
    assert [r.criterion for r in rows] == ["daylight provision", "exposure to sunlight", "protection from glare",
                                           "view out"]
    assert [r.level for r in rows] == ["not assessed", "medium", "not assessed", "not assessed"]
    assert all(r.indicative for r in rows)


def test_api_table_and_bad_input():
    from radiometer import api
    from radiometer.errors import RadiometerError

    e, lit = _year(20000.0)
    rows = api.en17037_table(illuminance=e, daylight_hours=lit, sunlight_hours=2.0, dgp=np.full(10, 0.3),
                             view_out=(30, 25, 2))
    assert [r["level"] for r in rows] == ["high", "minimum", "high", "medium"]
    rows = api.en17037_table(daylight_factor=np.full(9, 2.0), median_external_illuminance_lux=15000.0)
    assert [r["level"] for r in rows] == ["minimum", "not assessed", "not assessed", "not assessed"]
    for kwargs in ({"daylight_factor": [2.0]}, {"view_out": (1, 2)}, {"dgp": []}, {"illuminance": np.ones(3)}):
        with pytest.raises(RadiometerError, match="EN 17037"):
            api.en17037_table(**kwargs)

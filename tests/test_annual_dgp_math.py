"""Annual DGP, the pure part (radiometry/metrics/glare_dgp.py: sun_glare_source, hourly_dgp): at the hours the
sun is seen, full DGP with the sun's disc equals ``dgp`` for the same E_v, L, omega and P; at the others the
simplified DGPs; the sun's disc luminance and its position index from the direct sun at the eye."""

import math

import numpy as np
import pytest

from radiometer.radiometry.metrics import glare, glare_dgp

VIEW = (0.0, -1.0, 0.0)  # looking south (+Y north)


def _sun(alt_deg, az_deg):
    a, z = math.radians(alt_deg), math.radians(az_deg)
    return np.array([math.cos(a) * math.sin(z), math.cos(a) * math.cos(z), math.sin(a)])


def test_sun_disc_solid_angle():
    # 0.533 deg across: pi (0.2665 deg)^2 to first order
    assert glare_dgp.SUN_SOLID_ANGLE_SR == pytest.approx(math.pi * math.radians(0.2665) ** 2, rel=1e-5)
    assert glare_dgp.SUN_SOLID_ANGLE_SR == pytest.approx(6.8e-5, rel=2e-3)


def test_sun_source_seen_only_in_front_and_when_it_reaches_the_eye():
    s = np.array([_sun(30, 180), _sun(30, 0), _sun(20, 200), _sun(25, 170), _sun(-5, 180)])  # S, N, SSW, SSE, night
    e_dn = np.array([80000.0, 80000.0, 60000.0, 70000.0, 0.0])
    cos = np.maximum(s @ np.array(VIEW), 0.0)
    t_pane = 0.8
    # at the eye: open, open (but behind), open, through a pane of 0.8, nothing
    at_eye = e_dn * cos * np.array([1.0, 1.0, 1.0, t_pane, 1.0])
    at_eye[2] = 0.0  # the third sun is blocked by an opaque wall
    seen, lum, p = glare_dgp.sun_glare_source(VIEW, s, e_dn, at_eye)
    assert seen.tolist() == [True, False, False, True, False]
    assert lum[0] == pytest.approx(80000.0 / glare_dgp.SUN_SOLID_ANGLE_SR, rel=1e-12)
    assert lum[3] == pytest.approx(t_pane * 70000.0 / glare_dgp.SUN_SOLID_ANGLE_SR, rel=1e-12)
    assert lum[[1, 2, 4]].tolist() == [0.0, 0.0, 0.0]
    sigma, tau, elev = glare.view_angles(VIEW, s[3])
    assert sigma == pytest.approx(math.degrees(math.acos(cos[3])), abs=1e-9)
    assert p[3] == pytest.approx(float(glare_dgp.position_index_dgp(sigma, tau, elev)), rel=1e-12)
    # straight ahead and level: sigma 0, P 1
    _seen, _lum, p0 = glare_dgp.sun_glare_source(VIEW, [_sun(0.0, 180)], [1e5], [1e5])
    assert p0[0] == pytest.approx(1.0, abs=1e-9)


def test_hourly_dgp_is_dgp_with_the_sun_and_dgps_without():
    ev = np.array([3000.0, 3000.0, 450.0, 25000.0, 800.0, 0.0])
    L = np.array([0.0, 2e7, 5e6, 1.2e9, 0.0, 0.0])
    p = np.array([1.0, 2.5, 4.0, 1.3, 1.0, 1.0])
    w = glare_dgp.SUN_SOLID_ANGLE_SR
    for low in (False, True):
        d, se = glare_dgp.hourly_dgp(ev, L, p, low_light_correction=low)
        assert np.all(se == 0.0)  # no E_v error given
        for t in range(len(ev)):
            if L[t] > 0:
                ref = glare_dgp.dgp(ev[t], [L[t]], [w], [p[t]], low_light_correction=low)
            else:
                ref = float(glare_dgp.dgp_simplified(ev[t])) * (float(glare_dgp.low_light_factor(ev[t])) if low else 1.0)
            assert d[t] == pytest.approx(ref, abs=1e-12), (t, low)
    d, _se = glare_dgp.hourly_dgp(ev, L, p)
    assert d[0] == pytest.approx(6.22e-5 * 3000 + 0.184, abs=1e-12)   # DGPs by hand
    assert d[1] > d[0] + 0.05 and d[3] == 1.0                          # the sun raises it; capped at 1
    assert d[5] == pytest.approx(0.184, abs=1e-12)                      # dark hour: DGPs' offset


def test_hourly_dgp_std_error_is_the_derivative_times_ev_error():
    ev = np.array([3000.0, 3000.0, 600.0])
    L = np.array([0.0, 2e7, 1e7])
    p = np.array([1.0, 2.5, 3.0])
    se_ev = np.array([30.0, 30.0, 12.0])
    for low in (False, True):
        d, se = glare_dgp.hourly_dgp(ev, L, p, vertical_illuminance_std_error=se_ev, low_light_correction=low)
        h = 1e-3 * ev
        up, _ = glare_dgp.hourly_dgp(ev + h, L, p, low_light_correction=low)
        dn, _ = glare_dgp.hourly_dgp(ev - h, L, p, low_light_correction=low)
        np.testing.assert_allclose(se, np.abs(up - dn) / (2 * h) * se_ev, rtol=1e-5)
    # capped far above 1 (still 1 two standard errors lower): no error
    d, se = glare_dgp.hourly_dgp([25000.0], [1.2e9], [1.3], vertical_illuminance_std_error=[500.0])
    assert d[0] == 1.0 and se[0] == 0.0

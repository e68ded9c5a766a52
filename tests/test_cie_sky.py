"""CIE standard general skies (radiometry/skies/cie_sky.py): closed forms, an independent integration of the
ISO 15469 formulas written here, NaN/inf and n-dimensional behaviour."""

import math

import numpy as np
import pytest

from radiometer.radiometry.skies import cie_sky

# ISO 15469:2004 / CIE S 011/E:2003 Table 1, typed again here from the standard for the independent check.
ISO_TABLE = {1: (4, -0.7, 0, -1, 0), 2: (4, -0.7, 2, -1.5, 0.15), 3: (1.1, -0.8, 0, -1, 0),
             4: (1.1, -0.8, 2, -1.5, 0.15), 5: (0, -1, 0, -1, 0), 6: (0, -1, 2, -1.5, 0.15),
             7: (0, -1, 5, -2.5, 0.3), 8: (0, -1, 10, -3, 0.45), 9: (-1, -0.55, 2, -1.5, 0.15),
             10: (-1, -0.55, 5, -2.5, 0.3), 11: (-1, -0.55, 10, -3, 0.45), 12: (-1, -0.32, 10, -3, 0.45),
             13: (-1, -0.32, 16, -3, 0.3), 14: (-1, -0.15, 16, -3, 0.3), 15: (-1, -0.15, 24, -2.8, 0.15)}


def sun_vector(elevation_deg, azimuth_deg):
    el, az = math.radians(elevation_deg), math.radians(azimuth_deg)
    return np.array([math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), math.sin(el)])


def brute_force(normals, sky, sun, n_zen=240):
    """Independent: midpoint rule in zenith/azimuth angles (Z, alpha) with the ISO formulas written
    out here in angle form, the horizon clipped per cell by the midpoint only; L / Lz integrated."""
    zs = math.acos(sun[2])
    alpha_s = math.atan2(sun[0], sun[1])
    dz = (math.pi / 2) / n_zen
    z = (np.arange(n_zen) + 0.5) * dz
    n_az = 4 * n_zen
    da = 2 * math.pi / n_az
    az = (np.arange(n_az) + 0.5) * da
    Z, A = np.meshgrid(z, az, indexing="ij")
    if sky == "overcast":
        rel = (1 + 2 * np.cos(Z)) / 3
    else:
        a, b, c, d, e = ISO_TABLE[sky]
        cos_chi = np.cos(zs) * np.cos(Z) + np.sin(zs) * np.sin(Z) * np.cos(np.abs(A - alpha_s))
        chi = np.arccos(np.clip(cos_chi, -1, 1))
        f = 1 + c * (np.exp(d * chi) - math.exp(d * math.pi / 2)) + e * cos_chi ** 2
        phi = 1 + a * np.exp(b / np.cos(Z))
        f_zs = 1 + c * (math.exp(d * zs) - math.exp(d * math.pi / 2)) + e * math.cos(zs) ** 2
        rel = f * phi / (f_zs * (1 + a * math.exp(b)))
    out = []
    for n in np.asarray(normals, float):
        n = n / np.linalg.norm(n)
        cos_inc = n[0] * np.sin(Z) * np.sin(A) + n[1] * np.sin(Z) * np.cos(A) + n[2] * np.cos(Z)
        out.append(float(np.sum(rel * np.maximum(cos_inc, 0) * np.sin(Z)) * dz * da))
    return np.array(out)


def test_overcast_closed_forms():
    i_h, err = cie_sky.sky_integral([0, 0, 1], "overcast")
    assert i_h == pytest.approx(7 * math.pi / 9, rel=1e-12)  # E_h = 7 pi Lz / 9
    assert err < 1e-12
    # Vertical plane, derived in closed form: Lz (pi/6 + 4/9); ratio E_v/E_h = 0.396 (Tregenza & Wilson,
    # "Daylighting: Architecture and Lighting Design" (2011), CIE overcast sky, unobstructed vertical plane).
    for n in ([0, 1, 0], [1, 0, 0], [-0.6, 0.8, 0]):
        i_v, _ = cie_sky.sky_integral(n, "overcast")
        assert i_v == pytest.approx(math.pi / 6 + 4 / 9, rel=1e-12)
    assert (math.pi / 6 + 4 / 9) / (7 * math.pi / 9) == pytest.approx(0.396, abs=5e-4)
    assert cie_sky.zenith_luminance(7 * math.pi / 9, "overcast") == pytest.approx(1.0, rel=1e-12)


def test_uniform_sky_type_5_is_a_closed_form():
    # a = c = e = 0: L = Lz everywhere on the sky, so I(n) = pi (1 + n_z) / 2.
    rng = np.random.default_rng(5)
    n = rng.normal(size=(7, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    i, err = cie_sky.sky_integral(n, 5)
    np.testing.assert_allclose(i, np.pi * (1 + n[:, 2]) / 2, rtol=1e-10, atol=1e-12)
    assert np.all(err <= 1e-9)


SUNS = [(35.0, 160.0), (8.0, 250.0), (70.0, 10.0)]
NORMALS = [(0, 0, 1), (0, 1, 0), (0, -1, 0), (1, 0, 0), (0.5, -0.5, 0.7), (0.2, 0.9, -0.4)]


@pytest.mark.parametrize("sky", ["overcast"] + list(range(1, 16)))
def test_all_types_against_independent_integration(sky):
    for el, az in SUNS if cie_sky.needs_sun(sky) else SUNS[:1]:
        sun = sun_vector(el, az)
        i, err = cie_sky.sky_integral(np.array(NORMALS, float), sky, sun)
        assert np.all(err <= 1e-6 * i)  # the stated quadrature error
        np.testing.assert_allclose(i, brute_force(NORMALS, sky, sun), rtol=1e-4, err_msg=f"{sky} {el} {az}")


def test_quadrature_converged_to_1e6():
    # Orders 48 (default) and 96 agree to < 1e-6 relative for the sharpest circumsolar peak, a low sun
    # grazing a tilted plane's horizon, and every type.
    sun = sun_vector(3.0, 100.0)
    normals = np.array([[0, 0, 1], [0.99, 0, 0.1], [0.3, -0.9, 0.2]], float)
    for sky in range(1, 16):
        a, _ = cie_sky.sky_integral(normals, sky, sun)
        b, _ = cie_sky.sky_integral(normals, sky, sun, order=96)
        np.testing.assert_allclose(a, b, rtol=1e-6)


def test_relative_luminance_iso_values():
    # At the zenith L/Lz = 1; the ISO ratio between the horizon-adjacent and zenith elements.
    sun = sun_vector(40.0, 180.0)
    for sky in range(1, 16):
        assert cie_sky.relative_luminance([0, 0, 1], sky, sun) == pytest.approx(1.0, rel=1e-12)
    # Type 1 (ISO overcast): L(Z)/Lz = (1 + 4 exp(-0.7 / cos Z)) / (1 + 4 exp(-0.7)), independent of azimuth.
    z = math.radians(60)
    d = np.array([[math.sin(z), 0, math.cos(z)], [0, -math.sin(z), math.cos(z)]])
    np.testing.assert_allclose(cie_sky.relative_luminance(d, 1, sun),
                               (1 + 4 * math.exp(-0.7 / 0.5)) / (1 + 4 * math.exp(-0.7)), rtol=1e-12)
    assert cie_sky.relative_luminance([0, 1, -0.2], 12, sun) == 0.0  # below the horizon: not sky


def test_plane_illuminance_ground_and_scaling():
    e_h = 12_000.0
    e, err = cie_sky.plane_illuminance([[0, 0, 1], [0, 0, -1], [0, 1, 0]], "overcast",
                                       horizontal_illuminance=e_h, ground_reflectance=0.3)
    assert e[0] == pytest.approx(e_h, rel=1e-12)
    assert e[1] == pytest.approx(0.3 * e_h, rel=1e-12)  # the ground alone: rho E_h
    lz = 9 * e_h / (7 * math.pi)
    assert e[2] == pytest.approx(lz * (math.pi / 6 + 4 / 9) + 0.3 * e_h / 2, rel=1e-12)
    sun = sun_vector(30, 200)
    e12, _ = cie_sky.plane_illuminance([0, 0, 1], 12, sun, horizontal_illuminance=e_h)
    assert float(e12) == pytest.approx(e_h, rel=1e-12)


def test_nan_inf_and_bad_input():
    sun = sun_vector(30, 200)
    vals = [-1.0, 0.0, 1.0, -np.inf, np.inf, np.nan]
    normals = np.array([[a, b, c] for a in vals for b in vals for c in vals[:3]], float)
    i, err = cie_sky.sky_integral(normals, 12, sun)
    finite = np.all(np.isfinite(normals), axis=1)
    bad = ~finite | np.all(np.where(finite[:, None], normals, 1.0) == 0, axis=1)
    assert np.all(np.isnan(i[bad])) and np.all(np.isfinite(i[~bad]))
    rel = cie_sky.relative_luminance(normals, 12, sun)
    assert np.all(np.isnan(rel[bad]))
    with pytest.raises(ValueError, match="sun"):
        cie_sky.sky_integral([0, 0, 1], 12)
    with pytest.raises(ValueError, match="below the horizon"):
        cie_sky.sky_integral([0, 0, 1], 12, [0, 1, -0.1])
    with pytest.raises(ValueError, match="sky type"):
        cie_sky.parse_sky_type(16)
    with pytest.raises(ValueError, match="sky type"):
        cie_sky.parse_sky_type("clear")
    assert cie_sky.parse_sky_type("cie:12") == 12 and cie_sky.parse_sky_type("Overcast") == "overcast"
    with pytest.raises(ValueError):
        cie_sky.plane_illuminance([0, 0, 1], "overcast", horizontal_illuminance=np.nan)


def test_n_dimensional():
    sun = sun_vector(25, 130)
    n1 = np.array([0.3, -0.5, 0.8])
    i1, _ = cie_sky.sky_integral(n1, 13, sun)
    assert np.shape(i1) == ()
    i2, e2 = cie_sky.sky_integral(np.tile(n1, (6, 1)), 13, sun)
    assert i2.shape == (6,) and e2.shape == (6,)
    i3, _ = cie_sky.sky_integral(np.tile(n1, (2, 3, 1)), 13, sun)
    assert i3.shape == (2, 3)
    np.testing.assert_allclose(i2, float(i1), rtol=1e-14)
    np.testing.assert_allclose(i3, float(i1), rtol=1e-14)
    r = cie_sky.relative_luminance(np.tile(n1, (2, 3, 1)), 13, sun)
    assert r.shape == (2, 3)


def test_world_object_irradiance_matches_plane_illuminance():
    sun = sun_vector(30, 200)
    lz = cie_sky.zenith_luminance(10_000.0, 12, sun)
    world = cie_sky.CIESkyWorld(12, sun, lz / 683.0, cie_sky.ground_luminance(10_000.0, 0.2) / 683.0)
    n = np.array([[0, 0, 1], [0, 1, 0], [0.2, 0.3, -0.9]], float)
    e, err = world.irradiance(n)
    ref, _ = cie_sky.plane_illuminance(n, 12, sun, horizontal_illuminance=10_000.0)
    np.testing.assert_allclose(683.0 * e[:, 1], ref, rtol=1e-12)
    d, value = world.brightest()
    assert d @ sun > 0.99  # a type-12 sky is brightest around the sun

"""Photometry, units and statistics of radiometer.radiometry (pure numpy tier)."""

import numpy as np
import pytest

from radiometer.radiometry.photometry import _cie_tables as cie
from radiometer.radiometry.photometry import efficacy as ph
from radiometer.radiometry.sampling import stats
from radiometer.radiometry import units
from radiometer.radiometry.constants import K_M_LM_PER_W

colour = pytest.importorskip("colour")

# colour-science's "sRGB" uses the 4-decimal IEC 61966-2-1 matrix (Y row off by ~5e-5), so the
# derived BT.709 matrix is the reference for the linear Rec.709 working space.
SPACES = {"Rec.709": "ITU-R BT.709", "Linear Rec.709": "ITU-R BT.709", "Rec.2020": "ITU-R BT.2020", "ACEScg": "ACEScg"}


@pytest.mark.parametrize("ours,theirs", sorted(SPACES.items()))
def test_luminance_weights_match_colour_science(ours, theirs):
    # Reference: colour-science RGB_COLOURSPACES[...].matrix_RGB_to_XYZ, Y row.
    expected = colour.RGB_COLOURSPACES[theirs].matrix_RGB_to_XYZ[1]
    np.testing.assert_allclose(ph.luminance_weights(ours), expected, atol=1e-6)
    assert ph.luminance_weights(ours).sum() == pytest.approx(1.0, abs=1e-12)


def test_full_rgb_to_xyz_matrix_matches_colour_science():
    cs = colour.RGB_COLOURSPACES["ITU-R BT.2020"]
    np.testing.assert_allclose(ph.rgb_to_xyz_matrix(cs.primaries, cs.whitepoint), cs.matrix_RGB_to_XYZ, atol=1e-9)


def test_unknown_colour_space_and_bad_primaries_raise():
    with pytest.raises(ValueError, match="unknown colour space"):
        ph.luminance_weights("Display P3 nonsense")
    with pytest.raises(ValueError, match="NaN"):
        ph.rgb_to_xyz_matrix([[0.64, 0.33], [0.3, np.nan], [0.15, 0.06]], [0.3127, 0.329])


def test_embedded_cie_tables_match_colour_science():
    from colour.colorimetry import SDS_LEFS_PHOTOPIC
    v = SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"]
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    wl = cie.WAVELENGTHS_NM
    np.testing.assert_allclose(cie.PHOTOPIC_V, v[wl], rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(np.stack([cie.CMF_XBAR, cie.CMF_YBAR, cie.CMF_ZBAR], 1), cmfs[wl], rtol=1e-8, atol=1e-12)


def test_efficacy_of_monochromatic_555nm_is_683():
    wl = np.arange(360.0, 831.0, 1.0)
    spd = np.where(np.abs(wl - 555.0) < 0.5, 1.0, 0.0)  # one bin; trapezoid weights cancel
    spd = np.exp(-0.5 * ((wl - 555.0) / 0.05) ** 2)
    assert ph.efficacy_of_spectrum(wl, spd) == pytest.approx(683.0, rel=1e-3)


@pytest.mark.parametrize("temperature", [2700.0, 4000.0, 6500.0])
def test_blackbody_efficacy_matches_colour_science(temperature):
    # Reference: colour.sd_blackbody (Planck) and colour's V(lambda) on 360-830/5 nm, 683 int V S / int S
    # (colour.luminous_efficacy itself needs numpy >= 2 for np.trapezoid).
    from colour.colorimetry import SDS_LEFS_PHOTOPIC
    shape = colour.SpectralShape(360, 830, 5)
    sd = colour.sd_blackbody(temperature, shape)
    v = SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"][sd.wavelengths]
    expected = 683.0 * np.trapz(v * sd.values, sd.wavelengths) / np.trapz(sd.values, sd.wavelengths)
    # colour-science uses the CIE c2 = 1.4388e-2 m K; with the same c2 the results agree to 1e-9.
    assert ph.blackbody_efficacy(temperature, c2_m_k=1.4388e-2) == pytest.approx(expected, rel=1e-9)
    assert ph.blackbody_efficacy(temperature) == pytest.approx(expected, rel=1e-4)  # exact SI c2


def test_equal_energy_visible_efficacy():
    # Equal-energy spectrum over 360-830 nm: 683 * int V / 470 nm (int V ~ 106.86 nm, CIE table sum).
    wl = cie.WAVELENGTHS_NM
    expected = 683.0 * np.trapz(cie.PHOTOPIC_V, wl) / 470.0
    assert ph.efficacy_of_spectrum(wl, np.ones_like(wl)) == pytest.approx(expected, rel=1e-12)
    assert 150.0 < expected < 160.0


def test_blackbody_rgb_matches_blender_temperature_color():
    # Reference: bpy 5.0.1 Light.temperature_color at 2700 K (measured; also docs/FACTS.md).
    blender = np.array([1.9350767135620117, 0.803530752658844, 0.19172148406505585])
    ours = ph.blackbody_rgb(2700.0)
    np.testing.assert_allclose(ours, blender, rtol=5e-4)
    assert ph.luminance_factor(ours) == pytest.approx(1.0, abs=1e-12)


def test_white_one_watt_is_683_lumens_and_round_trips():
    assert ph.watts_to_lumens(1.0) == pytest.approx(683.0, rel=1e-12)
    assert ph.lumens_to_watts(683.0, colour=(1, 0, 0)) == pytest.approx(1.0 / ph.luminance_weights()[0])
    assert ph.candela_to_watts(ph.watts_to_candela(50.0)) == pytest.approx(50.0)
    assert ph.watts_to_candela(4 * np.pi) == pytest.approx(683.0)
    assert ph.lux_to_sun_strength(683.0) == pytest.approx(1.0)
    assert ph.sun_strength_to_lux(1.0, efficacy=ph.EFFICACY["radiance_179"]) == pytest.approx(179.0)
    assert ph.area_watts_to_nits(np.pi, 1.0) == pytest.approx(683.0)
    assert ph.nits_to_area_watts(ph.area_watts_to_nits(7.0, 2.0), 2.0) == pytest.approx(7.0)
    with pytest.raises(ValueError, match="luminance"):
        ph.lumens_to_watts(1.0, colour=(0, 0, 0))


def test_luminous_is_vectorised_and_rejects_nan():
    rgb = np.ones((2, 4, 3))
    out = ph.luminous(rgb)
    assert out.shape == (2, 4)
    np.testing.assert_allclose(out, K_M_LM_PER_W)
    with pytest.raises(ValueError, match="NaN"):
        ph.luminous([1.0, np.nan, 1.0])
    with pytest.raises(ValueError):
        ph.luminous([1.0, np.inf, 1.0])


def test_scene_to_metres_and_validation():
    np.testing.assert_allclose(units.scene_to_metres([[1.0, 2.0, 3.0]], 0.01), [[0.01, 0.02, 0.03]])
    for bad in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="scale_length"):
            units.scene_to_metres(1.0, bad)
    with pytest.raises(ValueError, match=">= 0"):
        units.check_nonnegative([-1.0], "x")


def test_batch_mean_and_student_interval():
    values = np.array([1.0, 2.0, 3.0, 4.0])
    mean, se = stats.batch_mean(values)
    assert mean == 2.5
    assert se == pytest.approx(np.std(values, ddof=1) / 2.0)
    assert stats.t_half_width_95(values) == pytest.approx(3.182446305284263 * se)  # t(0.975, 3)
    assert stats.relative_standard_error(values) == pytest.approx(se / 2.5)
    assert stats.samples_for_target(0.02, 100, 0.01) == 400
    with pytest.raises(ValueError):
        stats.batch_mean([1.0])

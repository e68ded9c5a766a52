"""Issue 35, pure tier: the band renders' proven range, the RGB-only conversion, and the numpy spectral
radiosity reference (tests/spectral_radiosity.py) against closed forms."""

import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

from radiometer.radiometry.photometry import action_spectra, spectral, spectral_bands  # noqa: E402

import spectral_radiosity as ref  # noqa: E402


def _red():
    wl = spectral.WAVELENGTHS_NM
    return 0.05 + 0.7 / (1.0 + np.exp(-(wl - 600.0) / 8.0))


def test_bands_cover_the_grid_and_keep_every_material_within_tolerance():
    refl = np.stack([_red(), np.full(401, 0.8), 0.3 + 0.1 * np.sin(spectral.WAVELENGTHS_NM / 30.0)])
    for max_bands in (4, 12, 32):
        edges = spectral_bands.plan_bands(refl, max_bands)
        assert edges[0] == 0 and edges[-1] == 401 and np.all(np.diff(edges) > 0)
        assert len(edges) - 1 <= max_bands
    fine = spectral_bands.plan_bands(refl, 32)
    coarse = spectral_bands.plan_bands(refl, 4)
    width = lambda e: max(np.ptp(refl[:, a:b], axis=1).max() for a, b in zip(e[:-1], e[1:]))  # noqa: E731
    assert width(fine) < width(coarse)
    assert len(spectral_bands.channel_layout(5)) == 4  # 10 channels in renders of 3


def _gain(rho_wall, rho_white):
    """A room's rendered light per unit power: one bounce off the walls, two off walls then white, and an
    infinite series off white (monotone in every reflectance, as every path sum is)."""
    return 0.3 * rho_wall + 0.2 * rho_wall * rho_white + 0.1 * rho_white / (1.0 - 0.6 * rho_white)


@pytest.mark.parametrize("light", ["A", "LED-B3", "FL2", "D65"])
def test_band_range_contains_the_truth_whatever_the_spectra_do_inside_a_band(light):
    """With renders stood in by the gain's values at the band ends (no noise), the proven range holds the
    spectral truth for E_v and every alpha-opic sum, and the estimate lies in it."""
    refl = np.stack([_red(), np.full(401, 0.85) - 0.05 * (spectral.WAVELENGTHS_NM > 700)])
    p = spectral.cie_illuminant(light)[None, :]
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.ACTION_SPECTRA])
    truth = (p[0] * _gain(refl[0], refl[1])) @ w.T
    for max_bands in (3, 8, 24):
        edges = spectral_bands.plan_bands(refl, max_bands)
        rmin, rmax, t = spectral_bands.band_table(refl, edges)
        pb = spectral_bands.band_sums(p, edges)[0]
        values = {(b, e): pb[b] * _gain(*(rmax[b] if e else rmin[b])) for b in range(len(edges) - 1) for e in (0, 1)}
        ses = {k: 0.0 for k in values}
        out = spectral_bands.combine(edges, p, w, t.mean(axis=0), values, ses,
                                     spectral_bands.channel_layout(len(edges) - 1))
        assert np.all(out["lower"] <= truth * (1 + 1e-12)) and np.all(truth <= out["upper"] * (1 + 1e-12))
        assert np.all(out["lower"] <= out["estimate"]) and np.all(out["estimate"] <= out["upper"])
        assert np.all(out["std_error"] == 0.0)
    # the range has content: 24 bands hold E_v within 5 % here (3.2 % measured)
    assert (out["upper"][0] - out["lower"][0]) / truth[0] < 0.05


def test_band_standard_error_adds_linearly_within_a_render_and_in_quadrature_across():
    edges = [0, 200, 401]
    p = np.ones((1, 401))
    w = np.ones((1, 401))
    t = np.full(401, 0.5)
    values = {(0, 0): 1.0, (0, 1): 1.0, (1, 0): 1.0, (1, 1): 1.0}
    ses = {(0, 0): 0.1, (0, 1): 0.1, (1, 0): 0.1, (1, 1): 0.1}
    out = spectral_bands.combine(edges, p, w, t, values, ses, spectral_bands.channel_layout(2))
    # a channel holds its band's light; each enters with weight (ratio 1) x 0.5 (t = 1/2):
    # render 1 holds (0,0), (0,1), (1,0): 0.05 x 3 added linearly; render 2 holds (1,1): 0.05; in quadrature
    assert out["std_error"][0] == pytest.approx(math.hypot(0.15, 0.05), rel=1e-12)


def test_rgb_only_estimate_is_exact_in_a_grey_room():
    """Grey walls: the gain is the same in every channel and at every wavelength, so the conversion is exact."""
    p = spectral.cie_illuminant("LED-B3")
    light_rgb = np.array([0.9, 1.0, 1.2])
    gain = 0.37
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.ACTION_SPECTRA])
    est = spectral_bands.rgb_only_estimate(gain * light_rgb, light_rgb, p, w)
    assert est == pytest.approx(gain * (p @ w.T), rel=1e-12)


def test_box_upsampling_keeps_white_and_grey_flat():
    assert np.all(spectral_bands.box_reflectance((1, 1, 1)) == 1.0)
    assert np.all(spectral_bands.box_reflectance((0.4, 0.4, 0.4)) == 0.4)
    r = spectral_bands.box_reflectance((0.7, 0.1, 0.05))
    assert r[spectral.WAVELENGTHS_NM == 650][0] == 0.7 and r[spectral.WAVELENGTHS_NM == 450][0] == 0.05


def test_mallett_upsampling_round_trips_and_keeps_white_and_grey_flat():
    """Mallett & Yuksel's decomposition (the upsampling of a colour with no spectrum): white is 1 and a grey flat
    (the basis renormalised to sum to 1), the spectrum stays in [0, 1], and its Rec.709 colour under D65
    (colour-science's CMFs and matrix, tests/spectral_radiosity.py) is the colour again."""
    assert np.allclose(spectral_bands.mallett_reflectance((1, 1, 1)), 1.0, rtol=0, atol=1e-15)
    assert np.ptp(spectral_bands.mallett_reflectance((0.4, 0.4, 0.4))) == 0.0  # flat to the bit: nothing to sweep
    rng = np.random.default_rng(7)
    for rgb in rng.uniform(0.0, 1.0, (40, 3)):
        r = spectral_bands.mallett_reflectance(rgb)
        assert r.min() >= 0.0 and r.max() <= 1.0
        assert np.allclose(ref.rec709_of_reflectance(r[::5]), rgb, rtol=0, atol=2e-4)
    assert np.allclose(spectral_bands.mallett_reflectance((1.7, -0.2, 0.5)),
                       spectral_bands.mallett_reflectance((1.0, 0.0, 0.5)))  # clipped to the cube


# --- the reference's own checks ---------------------------------------------------------------------

def test_point_to_polygon_form_factor_matches_the_parallel_rectangle_closed_form():
    """A differential area under the corner of a parallel a x b rectangle at distance c (standard closed form)."""
    a, b, c = 1.3, 0.7, 0.9
    A, B = a / c, b / c
    closed = (A / math.sqrt(1 + A * A) * math.atan(B / math.sqrt(1 + A * A))
              + B / math.sqrt(1 + B * B) * math.atan(A / math.sqrt(1 + B * B))) / (2 * math.pi)
    poly = np.array([[0, 0, c], [a, 0, c], [a, b, c], [0, b, c]], float)
    ff = ref.point_to_polygon_ff(np.zeros((1, 3)), np.array([[0, 0, 1.0]]), poly[None])[0, 0]
    assert ff == pytest.approx(closed, rel=1e-12)


def test_meter_sees_the_whole_hemisphere_of_the_box_and_the_light_all_of_it():
    corners, normals, areas, _names = ref.patches(0.5)
    for loc, nrm in ref.METERS.values():
        assert ref.gather_ff(loc, nrm, corners).sum() == pytest.approx(1.0, abs=1e-12)
    assert ref.patch_solid_angles(corners, ref.LIGHT_M).sum() == pytest.approx(4 * math.pi, rel=1e-12)


def test_grey_box_radiosity_conserves_energy():
    """Uniform reflectance rho in a closed box: all exitance lands on the walls, so the total exitance is
    rho Phi / (1 - rho), Phi = 4 pi I (a check of the direct term, the form factors and the solve)."""
    rho, intensity = 0.6, 2.0
    corners, normals, areas, names, f = ref._geometry(0.9, 3)
    e0 = ref.patch_solid_angles(corners, ref.LIGHT_M) / areas * intensity
    b = np.linalg.solve(np.eye(len(areas)) - rho * f, rho * e0)
    assert np.sum(areas * b) == pytest.approx(rho * 4 * math.pi * intensity / (1 - rho), rel=1e-3)
    assert np.allclose(f.sum(axis=1), 1.0, atol=1e-9) and np.all(f >= 0)


def test_a_channel_bound_widens_the_range_by_its_weight():
    edges = [0, 200, 401]
    p, w, t = np.ones((1, 401)), np.ones((1, 401)), np.full(401, 0.5)
    values = {(b, e): 1.0 for b in (0, 1) for e in (0, 1)}
    ses = {k: 0.0 for k in values}
    layout = spectral_bands.channel_layout(2)
    plain = spectral_bands.combine(edges, p, w, t, values, ses, layout)
    wide = spectral_bands.combine(edges, p, w, t, values, ses, layout, channel_bound={(0, 0): 0.1, (1, 1): 0.2})
    assert wide["lower"][0] == pytest.approx(plain["lower"][0] - 0.1, rel=1e-12)
    assert wide["upper"][0] == pytest.approx(plain["upper"][0] + 0.2, rel=1e-12)
    assert wide["estimate"][0] == plain["estimate"][0]

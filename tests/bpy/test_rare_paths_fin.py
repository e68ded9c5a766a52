"""The fin scene of issue 18 (case 5): a meter lit only by a sunlit Lambertian patch that a black fin
mostly hides (tests/bpy/fin_scene.py, exact reference). The issue measured 0 lx with a stated error of 0
where 58.5 lx arrived, and readings 3.2 % and 8 % low stating 0.85 %. Coverage over 50 seeds:
bench/coverage_rare_paths_fin.md."""

import importlib.util
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

_spec = importlib.util.spec_from_file_location("fin_scene", pathlib.Path(__file__).with_name("fin_scene.py"))
fin = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fin)


def test_reference_is_lamberts_formula_and_agrees_with_a_quadrature():
    """The reference (Lambert's contour formula over the visible rectangle) against a midpoint
    quadrature of L cos cos / r^2 over the whole patch with each ray tested against the fin quad."""
    n = 600
    y = -1 + (np.arange(n) + 0.5) * 2 / n
    z = (np.arange(n) + 0.5) * 2 / n
    yy, zz = np.meshgrid(y, z)
    points = np.stack([np.zeros_like(yy), yy, zz], axis=-1)
    for label, meter in fin.METERS.items():
        m = np.asarray(meter)
        r = points - m
        d = np.linalg.norm(r, axis=-1)
        at_fin = m + ((fin.FIN_X - m[0]) / r[..., 0])[..., None] * r
        blocked = (at_fin[..., 1] > -1.5) & (at_fin[..., 1] < fin.FIN_EDGE) & (at_fin[..., 2] > -0.5) & (at_fin[..., 2] < 2.5)
        kernel = (r @ np.asarray(fin.NORMAL)) / d * (-r[..., 0] / d) / d ** 2
        quadrature = fin.patch_luminance() * float(np.sum(np.where(blocked, 0.0, kernel))) * (2 / n) ** 2
        ref, hidden = fin.reference_lux(label)
        # the visibility edge cuts midpoint cells: first-order error ~ one cell row of the sliver
        assert quadrature == pytest.approx(ref, rel=2e-3), label
    assert fin.reference_lux("99 % hidden")[1] == pytest.approx(0.989, abs=1e-3)


def _reading(label, seed):
    from radiometer import api

    return api.measure_illuminance(fin.METERS[label], fin.NORMAL, scene=bpy.context.scene, quality="preview",
                                   seed=seed)


def test_mostly_hidden_patch_never_reads_zero_with_zero_error(clean_blender):
    """99 % hidden: the sliver is found with probability ~2.4e-3 a sample, so the 512-sample pilot misses
    it 30 % of the time (the issue's 0 lx +- 0); seed 1's pilot does (measured: the DARK_FLOOR round follows). The reading must find the light,
    state a non-zero error, and lie within it."""
    from radiometer.radiometry.sampling import allocation

    fin.build(bpy.context.scene)
    ref, _hidden = fin.reference_lux("99 % hidden")
    r = _reading("99 % hidden", 1)
    assert r.samples >= allocation.DARK_FLOOR
    assert r.illuminance > 0.0 and r.rel_std_error > 0.0 and not r.exact
    assert abs(r.illuminance - ref) <= 3 * r.rel_std_error * r.illuminance, (r.illuminance, ref, r.rel_std_error)


def test_half_hidden_patch_within_its_stated_error(clean_blender):
    fin.build(bpy.context.scene)
    ref, _hidden = fin.reference_lux("half hidden")
    for seed in (1, 1001, 2001):
        r = _reading("half hidden", seed)
        assert abs(r.illuminance - ref) <= max(3 * r.rel_std_error * r.illuminance, 0.005 * ref), (seed, r.illuminance, ref)


def test_rare_sliver_reading_within_its_stated_error(clean_blender):
    """97 % hidden: Cycles' tabulated Sobol table with scrambling distance 1 read the sliver 4-5 % low
    whatever the seed (its mean is the table's, not the integral); the stated error then had to include
    that floor; since issue 32 each texel's table is rotated (no floor needed). Seeds 1, 3001 and 4001
    are seeds 0, 3 and 4 of bench/coverage_rare_paths_fin.py: before the floor they read -6.3 %, -7.8 %
    and -12.1 % stating 4.2 %, 4.1 % and 3.7 % (z -1.6, -2.1, -3.7)."""
    fin.build(bpy.context.scene)
    ref, _hidden = fin.reference_lux("97 % hidden")
    for seed in (1, 3001, 4001):
        r = _reading("97 % hidden", seed)
        assert r.rel_std_error > 0.0
        assert abs(r.illuminance - ref) <= max(3 * r.rel_std_error * r.illuminance, 0.005 * ref), (seed, r.illuminance, ref)


_hspec = importlib.util.spec_from_file_location("hdri_sun_scene", pathlib.Path(__file__).with_name("hdri_sun_scene.py"))
hdri = importlib.util.module_from_spec(_hspec)
_hspec.loader.exec_module(hdri)


def test_hdri_with_a_sun_disc_open_and_through_an_opening(clean_blender):
    """Issue 18: an HDRI world with a 3 x 3-pixel sun disc (92-98 % of the light). In the open the reading
    is the image's closed form, exact to 1e-4 of an independent row-by-row integral; in a black room lit
    through a ceiling opening it is rendered, within max(3 s.e., 0.5 %) of the exact reference (the disc
    wholly visible, the sky through the opening by Lambert's formula). 50-seed coverage:
    bench/coverage_rare_paths_hdri.md."""
    from radiometer import api

    scene = hdri.build(bpy.context.scene)
    ref, _share = hdri.reference_lux("open")
    r = api.measure_illuminance(hdri.METERS["open"], hdri.NORMAL, scene=scene, quality="preview")
    assert r.exact and abs(r.illuminance / ref - 1.0) <= 1e-4, (r.illuminance, ref)
    ref, _share = hdri.reference_lux("room")
    r = api.measure_illuminance(hdri.METERS["room"], hdri.NORMAL, scene=scene, quality="preview", seed=1)
    assert not r.exact and r.rel_std_error > 0.0
    assert abs(r.illuminance - ref) <= max(3 * r.rel_std_error * r.illuminance, 0.005 * ref), (r.illuminance, ref)

"""Emitter spectra and CIE S 026 / CIE 191 quantities (radiometry.photometry.spectral, radiometry.photometry.action_spectra).

References, each independent of the code under test:
- luxpy 1.12.5's CIE S 026 toolbox (tests/luxpy_s026.py, in its own interpreter): alpha-opic ELR, DER,
  EDI and irradiances, and its 1 nm D65, A and action-spectrum tables;
- colour-science 0.4.6: V(lambda) and V'(lambda) (also for the S/P ratio), CIE A, the D-series, F and LED
  tables, Planck's law;
- CIE S 026/E:2018's own rounded D65 ELRs (0.8173, 1.4558, 1.6289, 1.4497, 1.3262 mW/lm);
- CIE 191:2010's defining equations (the mesopic fixed point) and, at L_p = 1 cd/m², luxpy's iteration.
"""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from radiometer.errors import RadiometerError
from radiometer.radiometry.photometry import _cie_tables
from radiometer.radiometry.photometry import _spectral_tables as tables
from radiometer.radiometry.photometry import action_spectra as aos
from radiometer.radiometry.photometry import spectral

WL = spectral.WAVELENGTHS_NM
LUXPY_ORDER = [2, 1, 0, 3, 4]  # luxpy's rows (l, m, s, rh, mel) -> ours (s, m, l, rh, mel)


def _led_spectrum():
    """A phosphor-white LED shape at 1 nm (blue pump plus a broad phosphor), as a maker's file has it."""
    return np.exp(-0.5 * ((WL - 450.0) / 10.0) ** 2) + 0.7 * np.exp(-0.5 * ((WL - 580.0) / 55.0) ** 2)


SPECTRA = {
    "blackbody 2700 K": spectral.planck(2700.0),
    "blackbody 4000 K": spectral.planck(4000.0),
    "blackbody 6500 K": spectral.planck(6500.0),
    "CIE A": spectral.cie_illuminant("A"),
    "CIE D65": spectral.cie_illuminant("D65"),
    "CIE LED-B3": spectral.cie_illuminant("LED-B3"),
    "CIE FL2": spectral.cie_illuminant("FL2"),
    "LED file": _led_spectrum(),
}


@pytest.fixture(scope="module")
def luxpy_ref():
    request = {"spectra": [v.tolist() for v in SPECTRA.values()],
               "mesopic": [[1.0, sp] for sp in (0.4, 0.65, 1.0, 1.3, 1.8, 2.5)]}
    script = os.path.join(os.path.dirname(__file__), "luxpy_s026.py")
    run = subprocess.run([sys.executable, script], input=json.dumps(request), capture_output=True, text=True,
                         cwd=os.path.dirname(__file__), timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    out = json.loads(run.stdout)
    assert out["version"] == "v1.12.5"
    return out


# --- the bundled tables against their sources --------------------------------------------------------

def test_action_spectra_are_cie_s026_table_2_as_luxpy_ships_it(luxpy_ref):
    ref = np.nan_to_num(np.array(luxpy_ref["action_spectra"]))[LUXPY_ORDER]
    assert np.array_equal(aos.ACTION_SPECTRA, ref)
    assert np.allclose(aos.ACTION_SPECTRA.max(axis=1), 1.0, atol=1e-3)  # each peaks at 1
    assert WL[np.argmax(aos.ACTION_SPECTRA[4])] == 490.0  # melanopic peak (CIE S 026)


def test_d65_and_a_tables_match_luxpy(luxpy_ref):
    assert np.array_equal(tables.D65_1NM, luxpy_ref["D65_1nm"])
    # CIE A: our closed form against luxpy's 1 nm table (CIE's, 6 significant digits)
    assert np.allclose(spectral.cie_illuminant_a(), luxpy_ref["A_1nm"], rtol=5e-6, atol=0)


def test_luminous_efficiency_tables_match_colour_science_and_the_5nm_table():
    from colour.colorimetry import SDS_LEFS_PHOTOPIC, SDS_LEFS_SCOTOPIC

    assert np.array_equal(aos.PHOTOPIC_V, SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"][WL])
    # S 026's rhodopic spectrum is CIE 1951 V'(lambda) (equal to the last bit of the two decimal parses)
    assert np.allclose(aos.SCOTOPIC_V, SDS_LEFS_SCOTOPIC["CIE 1951 Scotopic Standard Observer"][WL], rtol=1e-14, atol=0)
    # the 1 nm V(lambda) is the project's 5 nm table where both are sampled (one V, two samplings)
    on5 = (_cie_tables.WAVELENGTHS_NM >= 380) & (_cie_tables.WAVELENGTHS_NM <= 780)
    assert np.allclose(aos.PHOTOPIC_V[::5], _cie_tables.PHOTOPIC_V[on5], rtol=1e-14, atol=0)


def test_illuminant_tables_match_colour_science():
    import colour

    for name in tables.TABLE_ILLUMINANTS:
        sd = colour.SDS_ILLUMINANTS[name]
        assert np.array_equal(spectral.cie_illuminant(name, sd.wavelengths), sd.values), name
    d65 = colour.SDS_ILLUMINANTS["D65"]
    on = d65.wavelengths >= 380
    assert np.array_equal(spectral.cie_illuminant("D65", d65.wavelengths[on]), d65.values[on])


def test_cie_a_closed_form_matches_the_tabulated_illuminant():
    import colour

    a = colour.SDS_ILLUMINANTS["A"]
    assert np.allclose(spectral.cie_illuminant_a(a.wavelengths), a.values, rtol=5e-6, atol=0)
    assert spectral.cie_illuminant_a(560.0) == pytest.approx(100.0, rel=1e-15)


@pytest.mark.parametrize("cct", [4000.0, 5003.0, 6504.0, 7504.0, 12000.0, 25000.0])
def test_daylight_series_matches_colour_science(cct):
    import colour

    xy = colour.temperature.CCT_to_xy_CIE_D(cct)
    assert np.allclose(spectral.daylight_xy(cct), xy, rtol=0, atol=1e-15)
    sd = colour.sd_CIE_illuminant_D_series(xy)
    assert np.allclose(spectral.cie_daylight(cct, sd.wavelengths), sd.values, rtol=1e-12, atol=1e-12)


def test_mallett_basis_table_matches_colour_science():
    from colour.recovery import MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019 as mallett

    assert np.array_equal(mallett.wavelengths, tables.TABLE_WAVELENGTHS)
    for k, key in enumerate("RGB"):
        assert np.array_equal(getattr(tables, f"MALLETT2019_{key}"), mallett.values[:, k])


def test_d65_formula_and_table_agree_to_the_tables_rounding():
    # D65's table is the formula at 6504 K rounded (CIE 015); within 0.1 % relative over 380-780 nm
    formula = spectral.cie_daylight(spectral.D65_CCT_K)
    assert np.max(np.abs(formula / tables.D65_1NM - 1)) < 1e-3


def test_planck_matches_colour_science():
    from colour.colorimetry import planck_law

    h, c = 6.62607015e-34, 299792458.0
    for t in (1000.0, 2700.0, 6500.0, 20000.0):
        ref = planck_law(WL * 1e-9, t, c1=2 * math.pi * h * c**2, c2=1.4388e-2) * 1e-9  # colour's is per sr
        assert np.allclose(spectral.planck(t), ref, rtol=1e-12, atol=0)


def test_blackbody_cct_is_its_temperature_on_the_projects_locus():
    from radiometer.radiometry.photometry import colorimetry

    x = np.interp(WL, _cie_tables.WAVELENGTHS_NM, _cie_tables.CMF_XBAR)
    y = np.interp(WL, _cie_tables.WAVELENGTHS_NM, _cie_tables.CMF_YBAR)
    z = np.interp(WL, _cie_tables.WAVELENGTHS_NM, _cie_tables.CMF_ZBAR)
    s = spectral.planck(3000.0)[::5]
    cct, duv = colorimetry.cct_duv(colorimetry.xyz_to_uv(np.array([s @ x[::5], s @ y[::5], s @ z[::5]])))
    assert cct == pytest.approx(3000.0, abs=1.0) and abs(duv) < 1e-4


# --- CIE S 026 against luxpy to 1e-6 --------------------------------------------------------------

def test_alpha_opic_quantities_match_luxpy_to_1e6(luxpy_ref):
    spd = np.array(list(SPECTRA.values()))
    ev = aos.K_M_S026_LM_PER_W * spd @ aos.PHOTOPIC_V
    assert np.allclose(ev, luxpy_ref["ev"], rtol=1e-6, atol=0)
    elr = np.array(luxpy_ref["elr"])[:, LUXPY_ORDER]
    der = np.array(luxpy_ref["der"])[:, LUXPY_ORDER]
    edi = np.array(luxpy_ref["edi"])[:, LUXPY_ORDER]
    eeas = np.array(luxpy_ref["eeas"])[:, LUXPY_ORDER]
    assert np.allclose(aos.alpha_opic_elr(spd), elr, rtol=1e-6, atol=0)
    assert np.allclose(aos.alpha_opic_der(spd), der, rtol=1e-6, atol=0)
    assert np.allclose(aos.alpha_opic_edi(spd, ev), edi, rtol=1e-6, atol=0)
    assert np.allclose(aos.alpha_opic_irradiance(spd, ev), eeas, rtol=1e-6, atol=0)


def test_sp_ratio_matches_colour_science_tables():
    # luxpy's "1951_20_scotopic" is not CIE 1951 V'(lambda) (it peaks at 0.9976 at 507 nm), so the S/P
    # reference is colour-science's V and V' tables, integrated by numpy's trapezoid (colour 0.4.6's
    # luminous_flux calls np.trapezoid, absent from the pinned numpy 1.26). Zero at 379 and 781 nm makes the
    # trapezoid over 379-781 nm the plain 1 nm sum over 380-780 nm that CIE S 026 prescribes.
    from colour.colorimetry import SDS_LEFS_PHOTOPIC, SDS_LEFS_SCOTOPIC

    wl = np.arange(379.0, 782.0)
    v = SDS_LEFS_PHOTOPIC["CIE 1924 Photopic Standard Observer"][wl[1:-1]]
    vp = SDS_LEFS_SCOTOPIC["CIE 1951 Scotopic Standard Observer"][wl[1:-1]]
    for name, spd in SPECTRA.items():
        ext = lambda f: np.concatenate([[0.0], spd * f, [0.0]])  # noqa: E731
        ref = 1700.06 * np.trapz(ext(vp), wl) / (683.002 * np.trapz(ext(v), wl))
        assert aos.sp_ratio(spd) == pytest.approx(ref, rel=1e-6), name


def test_d65_der_is_one_and_its_elr_the_standards():
    assert np.array_equal(aos.alpha_opic_der(spectral.cie_illuminant("D65")), np.ones(5))
    assert aos.melanopic_der(spectral.cie_illuminant("D65")) == 1.0
    # CIE S 026/E:2018: K_alpha,v(D65) in mW/lm, rounded to 4 decimals (S, M, L cone, rhodopic, melanopic)
    assert np.array_equal(np.round(aos.D65_ELR_W_PER_LM * 1e3, 4), [0.8173, 1.4558, 1.6289, 1.4497, 1.3262])


def test_der_is_independent_of_scale_and_edi_is_linear():
    a = spectral.cie_illuminant("A")
    assert np.allclose(aos.alpha_opic_der(a * 7.3), aos.alpha_opic_der(a), rtol=1e-14)
    assert np.allclose(aos.alpha_opic_edi(a, 500.0), 500.0 * aos.alpha_opic_der(a), rtol=1e-14)
    # mel-EDI is linear in light: two lights' EDIs add to the EDI of their sum
    d = spectral.cie_illuminant("D65")
    ev = lambda s: aos.K_M_S026_LM_PER_W * s @ aos.PHOTOPIC_V  # noqa: E731
    both = aos.alpha_opic_edi(a + d, ev(a + d))
    assert np.allclose(both, aos.alpha_opic_edi(a, ev(a)) + aos.alpha_opic_edi(d, ev(d)), rtol=1e-12)


def test_warm_light_is_less_melanopic_than_daylight():
    ders = [aos.melanopic_der(spectral.planck(t)) for t in (2700.0, 4000.0, 6500.0)]
    assert ders[0] < ders[1] < ders[2] and ders[0] < 0.5 and 0.8 < ders[2] < 1.0


# --- CIE 191 mesopic ----------------------------------------------------------------------------------

def test_mesopic_is_the_fixed_point_of_cie_191():
    lp = np.geomspace(0.006, 4.9, 25)[:, None]
    sp = np.array([0.4, 0.65, 1.0, 1.6, 2.5])[None, :]
    lmes, m = aos.mesopic_luminance(lp, sp)
    assert lmes.shape == (25, 5)
    vp = 683.0 / 1699.0
    again = (m * lp + (1 - m) * lp * sp * vp) / (m + (1 - m) * vp)
    assert np.allclose(again, lmes, rtol=1e-13, atol=0)
    inside = (lmes > 0.005) & (lmes < 5.0)
    assert np.allclose(m[inside], 0.7670 + 0.3334 * np.log10(lmes[inside]), rtol=0, atol=1e-12)
    assert np.allclose(lmes[:, 2], lp[:, 0], rtol=1e-13)  # S/P = 1: mesopic = photopic
    assert np.all((lmes[:, 3:] > lp) & (lmes[:, :2] < lp))  # bluer light gains, redder loses


def test_mesopic_limits():
    lmes, m = aos.mesopic_luminance([10.0, 0.001], [2.0, 2.0])
    assert m[0] == 1.0 and lmes[0] == 10.0
    assert m[1] == 0.0 and lmes[1] == pytest.approx(0.002, rel=1e-14)


def test_mesopic_rises_with_photopic_and_scotopic_luminance():
    """The mesopic meter's 95 % interval takes the corners of the (L_p, L_s) box (spectral_reflected.
    mesopic_reading): that holds only if L_mes never falls as L_p or L_s grows. Checked on a fine grid over
    L_p 1e-4..1e3 cd/m², S/P 0.25..4 (the fixed point reached from m = 0.5, as CIE 191 starts)."""
    lp = np.geomspace(1e-4, 1e3, 241)
    ls = np.geomspace(1e-4 * 0.25, 1e3 * 4.0, 281)
    LP, LS = np.meshgrid(lp, ls, indexing="ij")
    sp = LS / LP
    keep = (sp >= 0.25) & (sp <= 4.0)
    lmes, _m = aos.mesopic_luminance(LP, sp)
    lmes = np.where(keep, lmes, np.nan)
    d_p = np.diff(lmes, axis=0)  # along L_p at fixed L_s
    d_s = np.diff(lmes, axis=1)  # along L_s at fixed L_p
    assert np.nanmin(d_p / np.abs(lmes[:-1])) >= -1e-12 and np.nanmin(d_s / np.abs(lmes[:, :-1])) >= -1e-12


def test_mesopic_matches_luxpy_where_its_iteration_is_cie_191(luxpy_ref):
    # luxpy 1.12.5's get_cie_mesopic_adaptation puts S/P where CIE 191 has L_s = L_p S/P, so it agrees
    # with CIE 191 only at L_p = 1 cd/m²; it stops at np.isclose on m (rtol 1e-5).
    sp = np.array([0.4, 0.65, 1.0, 1.3, 1.8, 2.5])
    lmes, m = aos.mesopic_luminance(1.0, sp)
    assert np.allclose(lmes, luxpy_ref["mesopic"][0], rtol=1e-4, atol=0)
    assert np.allclose(m, luxpy_ref["mesopic"][1], rtol=1e-4, atol=0)


# --- colour-science style robustness ---------------------------------------------------------------

def test_n_dimensional():
    s = spectral.cie_illuminant("FL11")
    one = aos.alpha_opic_der(s)
    for shape in ((6,), (2, 3)):
        many = np.broadcast_to(s, shape + s.shape)
        assert np.allclose(aos.alpha_opic_der(many), np.broadcast_to(one, shape + (5,)), rtol=1e-14)
        assert np.allclose(aos.sp_ratio(many), aos.sp_ratio(s), rtol=1e-14)
    t = np.array([[2700.0, 4000.0], [5000.0, 6500.0]])
    assert spectral.planck(t).shape == (2, 2, WL.size)
    assert spectral.cie_daylight(np.array([5000.0, 6500.0, 9000.0])).shape == (3, WL.size)
    lmes, m = aos.mesopic_luminance(np.full((2, 3), 0.5), 1.5)
    assert lmes.shape == m.shape == (2, 3) and np.allclose(lmes, lmes.flat[0], rtol=1e-15)


def test_nan_and_inf_do_not_crash():
    cases = np.array([-1.0, 0.0, 1.0, -np.inf, np.inf, np.nan])
    spectral.planck(cases)
    spectral.cie_daylight(cases)
    spectral.daylight_xy(cases)
    aos.mesopic_luminance(cases, cases)
    aos.mesopic_luminance(cases[:, None], cases[None, :])
    spd = np.repeat(cases[:, None], WL.size, axis=1)
    aos.alpha_opic_der(spd)
    aos.sp_ratio(spd)
    aos.alpha_opic_edi(spectral.cie_illuminant("A"), cases)
    assert np.all(np.isnan(aos.alpha_opic_der(np.zeros(WL.size))))  # no light: no ratio, not a crash
    assert np.isnan(spectral.cie_daylight(3000.0)).all()  # outside the D-series' range


def test_wrong_grid_is_refused():
    with pytest.raises(ValueError, match="380-780 nm"):
        aos.alpha_opic_der(np.ones(95))


# --- spectral files and spectrum settings -----------------------------------------------------------

def _write(tmp_path, text, name="led.csv"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_spectral_file_round_trip(tmp_path):
    led = _led_spectrum()
    path = _write(tmp_path, "wavelength_nm,relative_power\n" + "".join(f"{w:g},{v:.17g}\n" for w, v in zip(WL, led)))
    wl, power = spectral.read_spectrum_csv(path)
    assert np.array_equal(wl, WL) and np.array_equal(power, led)
    label, s = spectral.spectrum_from_spec(path)
    assert label == "file led.csv" and np.array_equal(s, led)
    # semicolons, a comment, a 5 nm file beyond 380-780 nm: interpolated linearly
    text = "# maker's file\n" + "".join(f"{w};{v}\n" for w, v in zip(range(360, 835, 5), np.linspace(1, 2, 95)))
    label, s = spectral.spectrum_from_spec(_write(tmp_path, text, "five.txt"))
    assert np.allclose(s, 1 + (WL - 360) / 470.0, rtol=1e-12)


@pytest.mark.parametrize("text, message", [
    ("380,1\n390,x\n", "line 2: expected two numbers"),
    ("380,1\n", "no spectrum"),
    ("400,1\n780,1\n", "covers 400-780 nm"),
    ("380,1\n390,-1\n", "line 2: relative power must be finite and >= 0"),
    ("380,1\n370,1\n", "line 2: wavelengths must rise"),
    ("380,1\n400,1\n780,1\n", "steps of up to"),
    ("".join(f"{w},0\n" for w in range(380, 790, 10)), "zero everywhere"),
    ("380,1\n780,nan\n", "line 2: relative power"),
    ("380\n780,1\n", "line 1: expected two numbers"),
    ("10,1\n780,1\n", "outside 200-2000 nm"),
])
def test_malformed_spectral_files_get_one_line(tmp_path, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(spectral.SpectralFileError) as info:
        spectral.read_spectrum_csv(path)
    assert message in str(info.value) and "\n" not in str(info.value) and path in str(info.value)
    assert isinstance(info.value, RadiometerError)


def test_unreadable_spectral_files(tmp_path):
    for path, message in ((str(tmp_path / "missing.csv"), "no such file"), (str(tmp_path), "is a directory")):
        with pytest.raises(spectral.SpectralFileError, match=message):
            spectral.read_spectrum_csv(path)
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"\0\1\2")
    with pytest.raises(spectral.SpectralFileError, match="binary"):
        spectral.read_spectrum_csv(str(binary))
    big = tmp_path / "big.csv"
    with open(big, "wb") as fh:
        fh.truncate(spectral.MAX_FILE_BYTES + 1)
    with pytest.raises(spectral.SpectralFileError, match="too large"):
        spectral.read_spectrum_csv(str(big))


@pytest.mark.parametrize("spec, label", [
    ("A", "CIE A"), ("D65", "CIE D65"), ("LED-B3", "CIE LED-B3"), ("FL2", "CIE FL2"),
    ("D5000", "CIE daylight 5000 K"), ("D:5500K", "CIE daylight 5500 K"),
    ("blackbody:2700", "blackbody 2700 K"), ("blackbody 4000K", "blackbody 4000 K"),
])
def test_spectrum_settings(spec, label):
    got, s = spectral.spectrum_from_spec(spec)
    assert got == label and s.shape == WL.shape and np.all(np.isfinite(s)) and s.max() > 0


@pytest.mark.parametrize("spec, message", [
    ("D3000", "4000 K to 25000 K"), ("blackbody:-5", "unknown spectrum"), ("blackbody:100", "500-100000 K"),
    ("sodium", "unknown spectrum"), ("", "a spectrum must be"), (3, "a spectrum must be"),
])
def test_bad_spectrum_settings(spec, message):
    with pytest.raises(RadiometerError, match=message):
        spectral.spectrum_from_spec(spec)


def test_circadian_verdicts_claim_only_what_the_reading_proves():
    """radiometry/metrics/circadian.py: met from the low end, not met only from a whole reading's high end."""
    from radiometer.radiometry.metrics import circadian

    assert circadian.rate(300.0) == {1: "met", 3: "met"}
    assert circadian.rate(200.0, 190.0, 210.0) == {1: "met", 3: "not met"}
    assert circadian.rate(200.0, 190.0, 260.0) == {1: "met", 3: "unknown"}       # the interval straddles 250
    assert circadian.rate(100.0, whole=False) == {1: "unknown", 3: "unknown"}    # a lower bound below
    assert circadian.rate(140.0, 130.0, 150.0) == {1: "unknown", 3: "not met"}
    s = circadian.summary([circadian.rate(300.0), circadian.rate(200.0, 190.0, 210.0)])
    assert s["points"] == 1 and not s["points_may_be_higher"] and s["share"][3]["not met"] == 0.5
    s = circadian.summary([circadian.rate(300.0), circadian.rate(100.0, whole=False)])
    assert s["points"] == 0 and s["points_may_be_higher"]
    assert s["thresholds_eml"][1] == pytest.approx(150.1, abs=0.1)                # WELL's 150 EML
    s = circadian.summary([circadian.rate(100.0, 90.0, 110.0), circadian.rate(100.0, whole=False)])
    assert s["points"] == 0 and not s["points_may_be_higher"]                     # one eye already misses both
    with pytest.raises(ValueError):
        circadian.rate(math.nan)
    with pytest.raises(ValueError):
        circadian.summary([])

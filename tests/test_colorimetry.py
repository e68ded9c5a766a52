"""EV100, CCT and Duv (issue 23 item 6) against colour-science and ISO 2720's constants."""

import math
import warnings

import numpy as np
import pytest

from radiometer.radiometry.photometry import colorimetry, efficacy as photometry
from radiometer.readings import IlluminanceReading, LuminanceReading, format_quantity, format_value

colour = pytest.importorskip("colour")


def test_ev100_closed_forms():
    # EV = log2(E S / C): 250 lx at ISO 100, C = 250 -> EV 6.643856; 2.5 lx -> 0 EV (by definition)
    assert colorimetry.ev100_incident(2.5) == pytest.approx(0.0, abs=1e-15)
    assert colorimetry.ev100_incident(2560) == pytest.approx(math.log2(1024))
    assert colorimetry.ev100_incident(3.4, receptor="dome") == pytest.approx(0.0, abs=1e-15)
    # reflected: L S / K with K = 12.5: L = 0.125 cd/m^2 -> EV 0; 4 cd/m^2 -> EV 5
    assert colorimetry.ev100_reflected(0.125) == pytest.approx(0.0, abs=1e-15)
    assert colorimetry.ev100_reflected(4.0) == pytest.approx(5.0)
    out = colorimetry.ev100_incident([-1.0, 0.0, 1.0, -np.inf, np.inf, np.nan])
    assert out[0] == -np.inf and out[1] == -np.inf and out[4] == np.inf and np.isnan(out[5])
    with pytest.raises(ValueError):
        colorimetry.ev100_incident(1.0, receptor="sphere")


def test_ev100_against_the_published_table():
    # colour-science has no exposure-value function (it lives in colour-hdri, not installed): the reference
    # is the ISO 2720 table as printed in "Exposure value" (Wikipedia, "Relationship of EV to lighting
    # conditions": EV100 = 0 <-> 2.5 lx with a flat receptor C = 250, 0.125 cd/m^2 with K = 12.5), each EV
    # doubling the light.
    for ev in range(-2, 17):
        assert colorimetry.ev100_incident(2.5 * 2.0**ev) == pytest.approx(ev, abs=1e-12)
        assert colorimetry.ev100_reflected(0.125 * 2.0**ev) == pytest.approx(ev, abs=1e-12)


@pytest.mark.parametrize("cct", [1500.0, 2700.0, 4000.0, 6500.0, 10000.0, 25000.0])
@pytest.mark.parametrize("duv", [0.0, 0.01, -0.02])
def test_cct_duv_against_colour_ohno(cct, duv):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        uv = np.asarray(colour.temperature.CCT_to_uv_Ohno2013(np.array([cct, duv])))
        ref_cct, ref_duv = colour.temperature.uv_to_CCT_Ohno2013(uv)
    got_cct, got_duv = colorimetry.cct_duv(uv)
    # colour-science tabulates the locus from 1 nm CMFs; ours sums 5 nm tables: 1e-4 relative measured
    assert got_cct == pytest.approx(ref_cct, rel=2e-4)
    assert got_duv == pytest.approx(ref_duv, abs=2e-6)


@pytest.mark.parametrize("space, colour_name", [("Linear Rec.709", "ITU-R BT.709"), ("Rec.2020", "ITU-R BT.2020"),
                                                ("ACEScg", "ACEScg")])
def test_cct_of_rgb_in_working_space_against_colour(space, colour_name):
    rng = np.random.default_rng(3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cs = colour.RGB_COLOURSPACES[colour_name]
        for t in (2700.0, 4000.0, 5600.0):
            xyz_white = colour.xy_to_XYZ(colour.temperature.CCT_to_xy_CIE_D(t) if t >= 4000 else
                                         colour.temperature.CCT_to_xy_Kang2002(t))
            rgb = colour.XYZ_to_RGB(xyz_white, cs, apply_cctf_encoding=False) * rng.uniform(0.5, 20)
            ref = colour.temperature.uv_to_CCT_Ohno2013(colour.xy_to_UCS_uv(colour.XYZ_to_xy(
                colour.RGB_to_XYZ(rgb, cs, apply_cctf_decoding=False))))
            got = colorimetry.cct_duv_of_rgb(rgb, space)
            assert got[0] == pytest.approx(ref[0], rel=5e-4) and got[1] == pytest.approx(ref[1], abs=2e-5)


def test_cct_shapes_and_bad_values():
    rgb = np.stack([photometry.blackbody_rgb(2700.0)] * 6).reshape(2, 3, 3)
    cct, duv = colorimetry.cct_duv_of_rgb(rgb)
    assert cct.shape == (2, 3) and np.allclose(cct, 2700, rtol=1e-4) and np.allclose(duv, 0, atol=1e-5)
    assert all(math.isnan(v) for v in colorimetry.cct_duv_of_rgb((0.0, 0.0, 0.0)))
    assert all(math.isnan(v) for v in colorimetry.cct_duv_of_rgb((0.0, 1.0, 0.0)))  # pure green: no CCT
    assert all(math.isnan(v) for v in colorimetry.cct_duv_of_rgb((np.nan, 1.0, 1.0)))


def _reading(rgb, lux, space="Linear Rec.709", se=0.011):
    return IlluminanceReading(irradiance_rgb=rgb, irradiance=lux / 683, illuminance=lux, rel_std_error=se,
                              method="render", samples=1, seconds=0.0, efficacy=683.0, colour_space=space)


def test_reading_fields_and_formatting():
    r = _reading(tuple(photometry.blackbody_rgb(3000.0)), 402.283)
    assert r.ev100 == pytest.approx(math.log2(402.283 * 100 / 250))
    assert r.cct_k == pytest.approx(3000, rel=2e-4) and abs(r.duv) < 1e-4
    d = r.to_dict()
    assert d["ev100"] == pytest.approx(r.ev100) and d["cct_k"] == pytest.approx(r.cct_k)
    dark = _reading((0.0, 0.0, 0.0), 0.0)
    assert dark.to_dict()["ev100"] is None and dark.to_dict()["cct_k"] is None
    lum = LuminanceReading(radiance_rgb=(1.0, 1.0, 1.0), radiance=1.0, luminance=4.0, rel_std_error=0.01,
                           method="render", samples=1, seconds=0.0, efficacy=683.0, colour_space="Linear Rec.709",
                           acceptance_deg=1.0)
    assert lum.ev100 == pytest.approx(5.0)
    assert lum.cct_k == pytest.approx(6504, abs=5)  # Rec.709 white is D65: CCT 6504 K (CIE 015)
    assert format_quantity(402.283, "lx", 0.0112) == "402 lx ±1.1 %"
    assert format_value(402.283, 0.0012) == "402.3"
    assert format_quantity(87.8477, "W", exact=True) == "87.848 W exact"


def test_photographic_text():
    from radiometer.readings import photographic_summary

    r = _reading(tuple(photometry.blackbody_rgb(3000.0)), 250.0)
    assert photographic_summary(r) == "EV100 6.6 (incident, flat sensor) · 3000 K, Duv +0.000"
    assert photographic_summary(_reading((0.0, 0.0, 0.0), 0.0)) == ""
    # a tiny negative Duv rounds to +0.000, never '-0.000' (seen in the client report's meter table)
    from radiometer.readings import photographic_text

    assert -0.0005 < colorimetry.cct_duv_of_rgb((1.0, 0.9375, 1.0), "Linear Rec.709")[1] < 0  # Duv -0.000496
    assert photographic_text("illuminance", 250.0, (1.0, 0.9375, 1.0), "Linear Rec.709").endswith("Duv +0.000")

"""Photometric file reader (radiometry.photometry.photometric_files): every LM-63 version, TILT variant,
symmetry and EULUMDAT symmetry, written here, with flux computed independently of the reader."""

import math
import os

import numpy as np
import pytest

from radiometer.radiometry.photometry import photometric_files as pf

FORMAT_LINES = {"LM-63-1986": None, "LM-63-1991": "IESNA91", "LM-63-1995": "IESNA:LM-63-1995",
                "LM-63-2002": "IESNA:LM-63-2002", "LM-63-2019": "IES:LM-63-2019"}


def ies_text(v, h, cd, *, fmt="IESNA:LM-63-2002", tilt="TILT=NONE", n_lamps=1, lumens=-1.0, multiplier=1.0,
             ptype=1, ballast=1.0, third=1.0, keywords=("[MANUFAC] Acme Lighting", "[LUMCAT] X-1")):
    """LM-63 text; ``cd`` is (n_h, n_v); values spread over lines of 7 as real files do."""
    v, h, cd = np.asarray(v, float), np.asarray(h, float), np.asarray(cd, float)
    out = [fmt] if fmt else []
    out += list(keywords) + [tilt]
    out.append(f"{n_lamps} {lumens:g} {multiplier:g} {v.size} {h.size} {ptype} 2 0.1 0.2 0.0")
    out.append(f"{ballast:g} {third:g} 42")

    def chunks(a):
        a = list(a)
        return [" ".join(f"{x:.12g}" for x in a[i:i + 7]) for i in range(0, len(a), 7)]
    out += chunks(v) + chunks(h)
    for row in cd:
        out += chunks(row)
    return "\n".join(out) + "\n"


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="latin-1")
    return str(path)


V_FULL = np.arange(0.0, 180.0 + 1e-9, 5.0)
V_LOWER = np.arange(0.0, 90.0 + 1e-9, 2.5)


def cos_lobe(v):
    return np.where(v <= 90.0, 100.0 * np.cos(np.radians(np.minimum(v, 90.0))), 0.0)


# --- flux of closed forms ----------------------------------------------------------------------

@pytest.mark.parametrize("fmt", sorted(FORMAT_LINES))
def test_isotropic_gives_4_pi_i0_in_every_version(tmp_path, fmt):
    text = ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 250.0)], fmt=FORMAT_LINES[fmt])
    p = pf.read_photometry(write(tmp_path, "iso.ies", text))
    assert p.file_format == fmt
    assert p.symmetry == "axial"
    assert p.lumens == pytest.approx(4.0 * math.pi * 250.0, rel=1e-10)
    assert p.max_candela == 250.0
    assert p.rated_lumens is None                       # lumens -1: absolute photometry
    assert p.metadata["MANUFAC"] == "Acme Lighting" and p.metadata["LUMCAT"] == "X-1"


@pytest.mark.parametrize("h, symmetry", [([0.0], "axial"), ([0.0, 45.0, 90.0], "quadrilateral"),
                                          ([0.0, 60.0, 120.0, 180.0], "bilateral"),
                                          ([90.0, 180.0, 270.0], "bilateral-90-270"),
                                          ([0.0, 90.0, 180.0, 270.0, 360.0], "none"),
                                          ([0.0, 90.0, 180.0, 270.0], "none")])
def test_cosine_lobe_gives_pi_i0_for_every_symmetry(tmp_path, h, symmetry):
    # I0 cos(theta) on the lower hemisphere: flux pi I0 (independent closed form). The reader
    # integrates the interpolated table (Catmull-Rom at 2.5 deg, zero from the horizon up): the
    # interpolation error is 1.6e-4 here.
    cd = [cos_lobe(V_LOWER)] * len(h)
    p = pf.read_photometry(write(tmp_path, "lobe.ies", ies_text(V_LOWER, h, cd)))
    assert p.symmetry == symmetry
    assert p.lumens == pytest.approx(math.pi * 100.0, rel=3e-4)
    assert p.beam_angle_deg == pytest.approx(120.0, abs=0.02)        # cos = 0.5 at 60 deg
    assert p.field_angle_deg == pytest.approx(2 * math.degrees(math.acos(0.1)), abs=0.05)


def test_flux_of_an_asymmetric_distribution_matches_a_fine_independent_sum(tmp_path):
    # I(theta, C) = 100 (1 + 0.5 cos C) cos(theta) below the horizon: flux pi * 100 (cos C averages
    # to 0). Tabulated at 10 deg in C over the full circle.
    h = np.arange(0.0, 360.0 + 1e-9, 10.0)
    cd = [cos_lobe(V_LOWER) * (1.0 + 0.5 * math.cos(math.radians(c))) for c in h]
    p = pf.read_photometry(write(tmp_path, "asym.ies", ies_text(V_LOWER, h, cd)))
    assert p.symmetry == "none"
    assert p.lumens == pytest.approx(math.pi * 100.0, rel=3e-4)
    assert p.candela_at(30.0, 0.0) == pytest.approx(150.0 * math.cos(math.radians(30.0)), rel=1e-10)
    assert p.candela_at(30.0, 180.0) == pytest.approx(50.0 * math.cos(math.radians(30.0)), rel=1e-10)


def test_candela_multiplier_ballast_factor_and_rated_lumens(tmp_path):
    text = ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 10.0)], multiplier=2.0, ballast=0.9,
                    n_lamps=2, lumens=1000.0)
    p = pf.read_photometry(write(tmp_path, "mult.ies", text))
    assert p.max_candela == pytest.approx(18.0)
    assert p.rated_lumens == 2000.0
    assert p.lumens == pytest.approx(4 * math.pi * 18.0)
    assert p.candela_per_klm[0, 0] == pytest.approx(18.0 / 2.0)


@pytest.mark.parametrize("fmt, applied", [("LM-63-1991", True), ("LM-63-1995", True), ("LM-63-2002", False),
                                          ("LM-63-2019", False)])
def test_second_factor_multiplies_only_where_it_is_the_ballast_lamp_factor(tmp_path, fmt, applied):
    text = ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 10.0)], fmt=FORMAT_LINES[fmt], third=0.5)
    p = pf.read_photometry(write(tmp_path, "f.ies", text))
    assert p.max_candela == pytest.approx(5.0 if applied else 10.0)


def test_keywords_more_and_1986_labels(tmp_path):
    text = ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 1.0)], fmt=None,
                    keywords=("Acme 1986 label line", "second label"))
    p = pf.read_photometry(write(tmp_path, "old.ies", text))
    assert p.file_format == "LM-63-1986" and "Acme 1986 label line" in p.metadata["LABEL"]
    text = ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 1.0)],
                    keywords=("[LUMINAIRE] Long name", "[MORE] continued", "[_USER] x"))
    p = pf.read_photometry(write(tmp_path, "more.ies", text))
    assert p.metadata["LUMINAIRE"] == "Long name\ncontinued" and p.metadata["_USER"] == "x"


def test_tilt_include_and_tilt_file(tmp_path):
    tilt = "TILT=INCLUDE\n1\n3\n0 45 90\n1.0 0.9 0.7"
    p = pf.read_photometry(write(tmp_path, "t.ies", ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 5.0)], tilt=tilt)))
    assert p.tilt.geometry == 1 and p.tilt.angles_deg == (0.0, 45.0, 90.0)
    assert p.tilt.factor(67.5) == pytest.approx(0.8)
    assert p.max_candela == 5.0                                  # TILT is reported, not applied
    write(tmp_path, "lamp.tlt", "2\n2\n0 90\n1 0.5\n")
    p = pf.read_photometry(write(tmp_path, "tf.ies", ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 5.0)],
                                                              tilt="TILT=lamp.tlt")))
    assert p.tilt.source == "lamp.tlt" and p.tilt.factor(45.0) == pytest.approx(0.75)


def test_type_b_and_a_flux(tmp_path):
    # Isotropic in type B, angles -90..90 both ways: 4 pi I0 (d omega = cos V dV dH covers the sphere
    # twice over H in -180..180, once over -90..90 x -90..90 ... the hemisphere pair: 2 pi I0 x 2).
    v = np.arange(-90.0, 90.0 + 1e-9, 5.0)
    h = np.arange(-90.0, 90.0 + 1e-9, 10.0)
    p = pf.read_photometry(write(tmp_path, "b.ies", ies_text(v, h, np.full((h.size, v.size), 3.0), ptype=2)))
    assert p.photometric_type == "B"
    assert p.lumens == pytest.approx(2.0 * math.pi * 3.0, rel=1e-9)       # the front hemisphere only
    v0 = np.arange(0.0, 90.0 + 1e-9, 5.0)
    h0 = np.arange(0.0, 90.0 + 1e-9, 10.0)
    p = pf.read_photometry(write(tmp_path, "a.ies", ies_text(v0, h0, np.full((h0.size, v0.size), 3.0), ptype=3)))
    assert p.photometric_type == "A" and p.lumens == pytest.approx(2.0 * math.pi * 3.0, rel=1e-9)
    with pytest.raises(ValueError, match="type-C"):
        p.candela_at(0.0, 0.0)


# --- interpolation ------------------------------------------------------------------------------

def test_candela_at_is_exact_at_tabulated_angles_and_vectorised(tmp_path):
    rng = np.random.default_rng(1)
    h = np.array([0.0, 30.0, 90.0, 150.0, 180.0])
    cd = rng.uniform(10.0, 100.0, (h.size, V_FULL.size))
    p = pf.read_photometry(write(tmp_path, "r.ies", ies_text(V_FULL, h, cd)))
    vv, hh = np.meshgrid(V_FULL[:-1], h, indexing="xy")
    np.testing.assert_allclose(p.candela_at(vv, hh), cd[:, :-1], rtol=1e-10)
    # bilateral: C and 360 - C agree
    np.testing.assert_allclose(p.candela_at(vv, 360.0 - hh), cd[:, :-1], rtol=1e-10)
    assert p.candela_at(V_FULL[:3], 30.0).shape == (3,)
    assert p.candela_at(np.zeros((2, 3)), np.zeros((2, 1))).shape == (2, 3)
    assert np.isnan(p.candela_at(np.nan, 0.0))
    # The reader answers the table at a tabulated 180 deg (Cycles' lookup gives 0 there: the light
    # model of the meter keeps that, see catmull_rom_table); issue 18.
    assert p.candela_at(180.0, 0.0) == pytest.approx(cd[0, -1], rel=1e-10)
    np.testing.assert_allclose(p.candela_at(180.0, h), cd[:, -1], rtol=1e-10)
    assert pf.catmull_rom_table(*p.full_table(), 0.0, 180.0) == 0.0


def test_symmetries_expand_as_lm63_says(tmp_path):
    v = V_LOWER
    rows = {c: cos_lobe(v) * (1 + c / 100.0) for c in (90.0, 135.0, 180.0, 225.0, 270.0)}
    p = pf.read_photometry(write(tmp_path, "s.ies", ies_text(v, sorted(rows), [rows[c] for c in sorted(rows)])))
    assert p.symmetry == "bilateral-90-270"
    # I(C) = I(180 - C): C = 0 reads the 180 plane, C = 45 the 135 plane, C = 315 the 225 plane.
    assert p.candela_at(20.0, 0.0) == pytest.approx(rows[180.0][8], rel=1e-10)
    assert p.candela_at(20.0, 45.0) == pytest.approx(rows[135.0][8], rel=1e-10)
    assert p.candela_at(20.0, 315.0) == pytest.approx(rows[225.0][8], rel=1e-10)
    quad = {0.0: 1.0, 45.0: 2.0, 90.0: 3.0}
    p = pf.read_photometry(write(tmp_path, "q.ies", ies_text(v, list(quad), [cos_lobe(v) * k for k in quad.values()])))
    for c, k in ((135.0, 2.0), (180.0, 1.0), (225.0, 2.0), (270.0, 3.0), (315.0, 2.0)):
        assert p.candela_at(0.0 + 20.0, c) == pytest.approx(k * cos_lobe(np.array([20.0]))[0], rel=1e-10), c


def test_interpolation_is_catmull_rom_on_indices():
    # Between tabulated angles the value is Cycles' cubic: check one by hand.
    h = np.array([0.0, 360.0])
    v = np.array([0.0, 10.0, 20.0, 30.0, 40.0])
    row = np.array([10.0, 20.0, 40.0, 30.0, 10.0])
    table = np.vstack([row, row])
    a, b, c, d, x = 20.0, 40.0, 30.0, 10.0, 0.25              # between 20 and 30 deg, 22.5 deg
    expected = 0.5 * (((d + 3 * (b - c) - a) * x + (2 * a - 5 * b + 4 * c - d)) * x + (c - a)) * x + b
    assert pf.catmull_rom_table(h, v, table, 0.0, 22.5) == pytest.approx(expected, rel=1e-10)
    # first cell mirrors across the nadir (a = row[1])
    a, b, c, d, x = 20.0, 10.0, 20.0, 40.0, 0.5
    expected = 0.5 * (((d + 3 * (b - c) - a) * x + (2 * a - 5 * b + 4 * c - d)) * x + (c - a)) * x + b
    assert pf.catmull_rom_table(h, v, table, 0.0, 5.0) == pytest.approx(expected, rel=1e-10)
    # last cell repeats the end (d = c) when the table stops short of the zenith
    a, b, c, d, x = 40.0, 30.0, 10.0, 10.0, 0.5
    expected = 0.5 * (((d + 3 * (b - c) - a) * x + (2 * a - 5 * b + 4 * c - d)) * x + (c - a)) * x + b
    assert pf.catmull_rom_table(h, v, table, 0.0, 35.0) == pytest.approx(expected, rel=1e-10)


# --- EULUMDAT -----------------------------------------------------------------------------------

def ldt_text(isym, mc, dc, gammas, planes_cd, flux=1000.0, n_lamps=1, conversion=1.0):
    g = np.asarray(gammas, float)
    out = ["Acme Europe", "1", str(isym), str(mc), f"{dc:g}", str(g.size), f"{g[1] - g[0]:g}", "report 7",
           "Downlight 9", "DL-9", "dl9.ldt", "2026-01-01 test", "100", "0", "50", "80", "0", "10", "10", "10",
           "10", "100", "80", f"{conversion:g}", "0", "1", str(n_lamps), "LED", f"{flux:g}", "3000K", "80", "12.5"]
    out += ["0.5"] * 10
    out += [f"{i * dc:g}" for i in range(mc)]
    out += [f"{x:g}" for x in g]
    for row in planes_cd:
        out += [f"{x:.12g}" for x in row]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("isym, n_planes", [(0, 12), (1, 1), (2, 7), (3, 7), (4, 4)])
def test_eulumdat_cosine_lobe_every_symmetry(tmp_path, isym, n_planes):
    # 100 cd/klm cos(gamma) below the horizon with 2000 lm of lamps: I0 = 200 cd, flux pi I0.
    rows = [cos_lobe(V_LOWER)] * n_planes
    p = pf.read_photometry(write(tmp_path, "l.ldt", ldt_text(isym, 12, 30.0, V_LOWER, rows, flux=2000.0)))
    assert p.file_format == "EULUMDAT"
    assert p.horizontal_angles_deg.size == n_planes
    assert p.max_candela == pytest.approx(200.0)
    assert p.rated_lumens == 2000.0
    assert p.lumens == pytest.approx(math.pi * 200.0, rel=3e-4)
    assert p.metadata["luminaire_name"] == "Downlight 9"


def test_eulumdat_c90_c270_planes_are_stored_from_90(tmp_path):
    rows = [cos_lobe(V_LOWER) * (1 + k) for k in range(7)]           # planes 90, 120, ..., 270
    p = pf.read_photometry(write(tmp_path, "s3.ldt", ldt_text(3, 12, 30.0, V_LOWER, rows)))
    np.testing.assert_allclose(p.horizontal_angles_deg, np.arange(90.0, 271.0, 30.0))
    assert p.candela_at(20.0, 0.0) == pytest.approx(p.candela_at(20.0, 180.0), rel=1e-10)
    assert p.candela_at(20.0, 180.0) == pytest.approx(4 * cos_lobe(np.array([20.0]))[0], rel=1e-10)


# --- bad input: one line naming the line and what was expected ---------------------------------

def _bad(tmp_path, text, name="bad.ies"):
    with pytest.raises(pf.PhotometricFileError) as info:
        pf.read_photometry(write(tmp_path, name, text))
    message = str(info.value)
    assert "\n" not in message
    return message


def test_truncated_file(tmp_path):
    text = ies_text(V_FULL, [0.0, 90.0], [np.ones(V_FULL.size)] * 2)
    message = _bad(tmp_path, text[: int(len(text) * 0.8)])
    assert "end of file" in message and "candela values" in message


def test_wrong_counts(tmp_path):
    text = ies_text(V_FULL, [0.0], [np.ones(V_FULL.size)]).replace(f" {V_FULL.size} 1 1 2", f" {V_FULL.size - 2} 1 1 2")
    message = _bad(tmp_path, text)
    assert "line" in message and ("increasing" in message or "end of the file" in message)


def test_negative_candela(tmp_path):
    cd = np.ones(V_FULL.size)
    cd[5] = -3.0
    message = _bad(tmp_path, ies_text(V_FULL, [0.0], [cd]))
    assert "non-negative" in message and "-3" in message


def test_angles_out_of_order(tmp_path):
    v = V_FULL.copy()
    v[3], v[4] = v[4], v[3]
    message = _bad(tmp_path, ies_text(v, [0.0], [np.ones(v.size)]))
    assert "increasing order" in message and "vertical" in message
    line_no = int(message.split("line ")[1].split(":")[0])
    lines = ies_text(v, [0.0], [np.ones(v.size)]).split("\n")
    assert "15" in lines[line_no - 1].split()                    # the line that holds the culprit


def test_missing_tilt_file(tmp_path):
    message = _bad(tmp_path, ies_text(V_FULL, [0.0], [np.ones(V_FULL.size)], tilt="TILT=nowhere.tlt"))
    assert "nowhere.tlt" in message and "line 4" in message


def test_other_bad_inputs(tmp_path):
    assert "TILT" in _bad(tmp_path, "IESNA:LM-63-2002\n[TEST] x\n1 2 3\n")
    assert "horizontal angles" in _bad(tmp_path, ies_text(V_FULL, [0.0, 45.0], [np.ones(V_FULL.size)] * 2))
    assert "photometric type" in _bad(tmp_path, ies_text(V_FULL, [0.0], [np.ones(V_FULL.size)], ptype=7))
    assert "empty" in _bad(tmp_path, "")
    assert "binary" in _bad(tmp_path, "\0\0\0")
    assert "symmetry indicator" in _bad(tmp_path, ldt_text(7, 12, 30.0, V_LOWER, []), "x.ldt")
    good = ldt_text(1, 12, 30.0, V_LOWER, [cos_lobe(V_LOWER)])
    assert "end of file" in _bad(tmp_path, "\n".join(good.split("\n")[:-10]), "t.ldt")
    with pytest.raises(pf.PhotometricFileError, match="no such file"):
        pf.read_photometry(os.path.join(str(tmp_path), "absent.ies"))


# --- Cycles' reading and the canonical text ------------------------------------------------------

def test_canonical_text_reads_back_identically_in_cycles_processing(tmp_path):
    v = V_LOWER
    rows = {c: cos_lobe(v) * (1 + c / 100.0) for c in (90.0, 135.0, 180.0, 225.0, 270.0)}
    p = pf.read_photometry(write(tmp_path, "s.ies", ies_text(v, sorted(rows), [rows[c] for c in sorted(rows)])))
    h, vv, table = pf.cycles_ies_table(pf.to_ies_text(p))
    hf, vf, tf = p.full_table()
    np.testing.assert_allclose(h, hf, atol=1e-5)
    np.testing.assert_allclose(table / pf.CYCLES_CANDELA_TO_WATT, tf, rtol=1e-6)
    # Cycles itself rotates a raw 90-270 table instead of mirroring it: C = 0 reads the 90 plane.
    h, vv, table = pf.cycles_ies_table(ies_text(v, sorted(rows), [rows[c] for c in sorted(rows)]))
    assert table[0, 8] / pf.CYCLES_CANDELA_TO_WATT == pytest.approx(rows[90.0][8], rel=1e-6)
    assert p.candela_at(20.0, 0.0) == pytest.approx(rows[180.0][8], rel=1e-10)


def test_summary_is_json_serialisable(tmp_path):
    import json

    p = pf.read_photometry(write(tmp_path, "iso.ies", ies_text(V_FULL, [0.0], [np.full(V_FULL.size, 1.0)])))
    s = json.loads(json.dumps(p.summary()))
    assert s["lumens"] == pytest.approx(4 * math.pi) and s["manufacturer"] == "Acme Lighting"

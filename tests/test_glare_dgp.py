"""DGP (Wienold & Christoffersen 2006) from a luminance picture: closed forms, properties, evalglare.

References: the closed-form E_v of a uniform rectangle (the differential-area-to-parallel-rectangle form
factor) and its exact solid angle (Van Oosterom & Strackee); Radiance's evalglare 3.06 (shipped with
pyradiance, a test-only package) on the same HDR pictures.
"""

import math
import pathlib
import subprocess

import numpy as np
import pytest

from radiometer.radiometry.metrics import glare
from radiometer.radiometry.metrics import glare_dgp

VIEW = (0.0, 1.0, 0.0)
UP = (0.0, 0.0, 1.0)


# --- the formula -------------------------------------------------------------------------------------

def test_dgp_formula_values():
    # no source: 5.87e-5 E + 0.16; one source: the log term by hand
    assert glare_dgp.dgp(2000.0) == pytest.approx(5.87e-5 * 2000 + 0.16, abs=1e-12)
    s = 3000.0 ** 2 * 0.05 / 1.5 ** 2
    assert glare_dgp.dgp(2000.0, [3000.0], [0.05], [1.5]) == pytest.approx(
        5.87e-5 * 2000 + 9.18e-2 * math.log10(1 + s / 2000 ** 1.87) + 0.16, abs=1e-12)
    assert glare_dgp.dgp(1e6, [1e9], [1e-3], [1.0]) == 1.0          # capped
    with pytest.raises(ValueError):
        glare_dgp.dgp(0.0)
    with pytest.raises(ValueError):
        glare_dgp.dgp(float("nan"))


def test_low_light_correction_and_simplified():
    # Wienold 2009: factor exp(0.024 E - 4) / (1 + exp(0.024 E - 4)) below 1000 lx, 1 above
    e = 300.0
    f = math.exp(0.024 * e - 4) / (1 + math.exp(0.024 * e - 4))
    assert glare_dgp.dgp(e, low_light_correction=True) == pytest.approx(f * (5.87e-5 * e + 0.16))
    assert glare_dgp.dgp(1500.0, low_light_correction=True) == glare_dgp.dgp(1500.0)
    assert glare_dgp.low_light_factor([0.0, 999.0, 1000.0, 1e9]) == pytest.approx(
        [math.exp(-4) / (1 + math.exp(-4)), math.exp(0.024 * 999 - 4) / (1 + math.exp(0.024 * 999 - 4)), 1, 1])
    assert glare_dgp.dgp_simplified([0.0, 1000.0, 1e6]) == pytest.approx([0.184, 0.184 + 0.0622, 1.0])


def test_classes():
    assert [glare_dgp.dgp_class(v) for v in (0.2, 0.3499, 0.35, 0.3999, 0.40, 0.4499, 0.45, 0.9)] == [
        "imperceptible", "imperceptible", "perceptible", "perceptible", "disturbing", "disturbing",
        "intolerable", "intolerable"]
    with pytest.raises(ValueError):
        glare_dgp.dgp_class(float("nan"))


def test_monotone():
    ev = np.linspace(200, 6000, 30)
    assert np.all(np.diff([glare_dgp.dgp(e) for e in ev]) > 0)         # more light at the eye: more glare
    # the same source against a brighter surround (higher E_v): less contrast, the log term falls
    contrast = [glare_dgp.dgp(e, [5000.0], [0.02], [1.3]) - glare_dgp.dgp(e) for e in ev]
    assert np.all(np.diff(contrast) < 0)
    lum = np.geomspace(1e3, 1e6, 30)
    assert np.all(np.diff([glare_dgp.dgp(2000, [L], [0.02], [1.3]) for L in lum]) > 0)
    om = np.geomspace(1e-4, 0.5, 30)
    assert np.all(np.diff([glare_dgp.dgp(2000, [5e4], [w], [1.3]) for w in om]) > 0)
    p = np.linspace(1, 16, 30)
    assert np.all(np.diff([glare_dgp.dgp(2000, [5e4], [0.02], [q]) for q in p]) < 0)
    # the Guth-Iwata position index grows off the line of sight, above and below it
    s = np.linspace(1, 80, 40)
    for tau in (10.0, 60.0):
        assert np.all(np.diff(glare_dgp.position_index_dgp(s, tau, 1.0)) >= 0)
        assert np.all(np.diff(glare_dgp.position_index_dgp(s, 180 - tau, -1.0)) >= 0)
    assert glare_dgp.position_index_dgp(0.0, 0.0, 1.0) == pytest.approx(1.0)
    assert glare_dgp.position_index_dgp(89.0, 0.0, 1.0) == 16.0        # capped as evalglare caps it


def test_fisheye_geometry():
    dirs, w, ok = glare_dgp.angular_fisheye(400, 400, VIEW, UP)
    assert w.sum() == pytest.approx(2 * math.pi, rel=2e-3)             # the hemisphere in front
    # E_v of a uniform hemisphere of luminance 1: pi (cosine-weighted sum)
    assert np.sum(w * np.clip(dirs @ np.array(VIEW), 0, 1)) == pytest.approx(math.pi, rel=2e-3)
    # the centre looks along the view; the top row's middle looks up (+Z), the right edge's middle +X
    assert dirs[0, 200] @ np.array(UP) > 0.99 and dirs[200, 399] @ np.array((1.0, 0, 0)) > 0.99
    assert np.allclose(np.linalg.norm(dirs, axis=-1), 1.0)


# --- closed form: a uniform rectangle on a uniform background -------------------------------------

def _rect_form_factor(a, b):
    """Form factor from a differential area to a parallel a x b rectangle (distance 1) whose corner lies
    on the area's normal (Howell's catalogue, C-11)."""
    A, B = a, b
    return (A / math.sqrt(1 + A * A) * math.atan(B / math.sqrt(1 + A * A))
            + B / math.sqrt(1 + B * B) * math.atan(A / math.sqrt(1 + B * B))) / (2 * math.pi)


def _rect_picture(n, half_w, half_h, L_src, L_bg):
    """Angular fisheye of a rectangle (x in [-half_w, half_w], z in [-half_h, half_h]) on the plane y = 1."""
    dirs, w, ok = glare_dgp.angular_fisheye(n, n, VIEW, UP)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = dirs[..., 0] / dirs[..., 1]
        z = dirs[..., 2] / dirs[..., 1]
    inside = (dirs[..., 1] > 0) & (np.abs(x) <= half_w) & (np.abs(z) <= half_h)
    return np.where(inside, L_src, L_bg), dirs, w, ok


def test_uniform_rectangle_closed_form():
    # a 0.8 x 0.5 rectangle of 8000 cd/m² centred on the line of sight at 1 m, background 40 cd/m²:
    # E_v = pi L_bg + (L - L_bg) pi F (exact), omega exact, P = 1 at its centre (on the line of sight)
    hw, hh, L, Lb = 0.4, 0.25, 8000.0, 40.0
    F = 4 * _rect_form_factor(hw, hh)
    ev = math.pi * Lb + (L - Lb) * math.pi * F
    corners = np.array([[-hw, 1, -hh], [hw, 1, -hh], [hw, 1, hh], [-hw, 1, hh]])
    omega = glare.polygon_solid_angle((0, 0, 0), corners)
    expected = glare_dgp.dgp(ev, [L], [omega], [1.0])
    pic, dirs, w, ok = _rect_picture(1200, hw, hh, L, Lb)
    r = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP)
    assert len(r.sources) == 1
    assert r.vertical_illuminance == pytest.approx(ev, rel=2e-3)
    assert r.sources[0]["solid_angle"] == pytest.approx(omega, rel=3e-3)
    assert r.sources[0]["position_index"] == pytest.approx(1.0, abs=1e-3)
    assert r.dgp == pytest.approx(expected, abs=1e-3)
    assert abs(r.dgp - expected) <= r.dgp_pixel_error < 0.01          # the stated pixelation covers the error
    assert 0.3 < expected < 0.9                                       # a case where the source term matters


def test_threshold_modes_and_bad_input():
    pic, dirs, w, ok = _rect_picture(200, 0.4, 0.25, 8000.0, 40.0)
    fixed = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP, threshold_cd_m2=1e5)
    assert fixed.sources == [] and fixed.dgp == pytest.approx(glare_dgp.dgp(fixed.vertical_illuminance))
    rel = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP, threshold_factor=5)
    assert rel.threshold_cd_m2 == pytest.approx(5 * rel.mean_luminance) and len(rel.sources) == 1
    # task zone on the dark background: threshold 5 x 40 cd/m²
    task = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP, task=((0, 1, -1), 0.2))
    assert task.threshold_cd_m2 == pytest.approx(200.0)
    with pytest.raises(ValueError):
        glare_dgp.dgp_from_picture(np.zeros_like(pic), dirs, w, ok, VIEW, UP)
    with pytest.raises(ValueError):
        glare_dgp.dgp_from_picture(np.where(ok, np.nan, 0), dirs, w, ok, VIEW, UP)


# --- against evalglare -----------------------------------------------------------------------------

def _evalglare():
    pyradiance = pytest.importorskip("pyradiance")
    exe = pathlib.Path(pyradiance.__file__).parent / "bin" / "evalglare"
    if not exe.exists():
        pytest.skip("evalglare not found in pyradiance")
    return exe


def _write_hdr(path, luminance):
    """Write the picture with Radiometer's encoder; return what Radiance decodes from its bytes
    ((mantissa + 0.5) 2^(exponent - 136) x 179, grey), so both programs read the same numbers."""
    data = glare_dgp.radiance_picture(luminance, VIEW, UP)
    path.write_bytes(data)
    h, w = luminance.shape
    px = np.frombuffer(data[len(data) - 4 * h * w:], np.uint8).reshape(h, w, 4).astype(float)
    return np.where(px[..., 3] > 0, (px[..., 1] + 0.5) * np.ldexp(1.0, px[..., 3].astype(int) - 136), 0.0) * 179.0


def _run_evalglare(exe, path, *args):
    out = subprocess.run([str(exe), "-d", *args, "-vta", "-vh", "180", "-vv", "180", "-vd", "0", "1", "0",
                          "-vu", "0", "0", "1", str(path)], capture_output=True, text=True, timeout=120)
    lines = out.stdout.splitlines()
    names, values = next(x for x in lines if x.startswith("dgp,av_lum,E_v")).split(":")
    result = dict(zip(names.split(","), map(float, values.split())))
    result["sources"] = int(next(x for x in lines if " No pixels " in x).split()[0])
    return result


def _disc(dirs, centre, radius_deg):
    c = np.asarray(centre, float)
    c = c / np.linalg.norm(c)
    return dirs @ c >= math.cos(math.radians(radius_deg))


def _rect(dirs, azimuth_deg, elevation_deg, half_w_deg, half_h_deg):
    az = np.degrees(np.arctan2(dirs[..., 0], dirs[..., 1]))
    el = np.degrees(np.arcsin(np.clip(dirs[..., 2], -1, 1)))
    return (np.abs(az - azimuth_deg) <= half_w_deg) & (np.abs(el - elevation_deg) <= half_h_deg)


N = 256


def _views():
    dirs, w, ok = glare_dgp.angular_fisheye(N, N, VIEW, UP)
    room = np.where(dirs[..., 2] > 0, 60.0, 25.0)                      # ceiling/walls and a darker floor
    views = {}
    # sun in view through a pane: window of 2500 cd/m² sky, the sun's disc (1.5 deg across) at 4e6 cd/m²
    sun = room.copy()
    window = _rect(dirs, 10, 15, 25, 15)
    sun[window] = 2500.0
    sun[_disc(dirs, (math.sin(math.radians(15)), math.cos(math.radians(15)), math.tan(math.radians(20))), 0.75)] = 4e6
    views["sun through a pane"] = sun
    # bright overcast window ahead: 6000 cd/m² over a large opening
    overcast = room.copy()
    overcast[_rect(dirs, 0, 8, 35, 22)] = 6000.0
    views["bright overcast window"] = overcast
    # window at the side: 60 deg to the right, 9000 cd/m²
    side = room.copy()
    side[_rect(dirs, 60, 10, 15, 25)] = 9000.0
    views["window at the side"] = side
    # dark room: 8 cd/m² walls, a dim 150 cd/m² window: no source above 2000 cd/m²
    dark = np.where(dirs[..., 2] > 0, 8.0, 4.0)
    dark[_rect(dirs, -20, 5, 20, 15)] = 150.0
    views["dark room"] = dark
    # a bright patch below the line of sight (Iwata's position index)
    below = room.copy()
    below[_rect(dirs, 15, -25, 20, 10)] = 12000.0
    views["source below the line of sight"] = below
    # two panes split by a 3 deg mullion (one source: within 0.1 rad) and a lamp 40 deg away (another)
    panes = room.copy()
    panes[_rect(dirs, -12, 10, 10, 12) | _rect(dirs, 11, 10, 10, 12)] = 5000.0
    panes[_disc(dirs, (0.64, 0.77, 0.0), 2.0)] = 20000.0
    views["two panes and a lamp"] = panes
    return dirs, w, ok, views


@pytest.mark.parametrize("name", ["sun through a pane", "bright overcast window", "window at the side", "dark room",
                                  "source below the line of sight", "two panes and a lamp"])
def test_against_evalglare(tmp_path, name):
    exe = _evalglare()
    dirs, w, ok, views = _views()
    path = tmp_path / "view.hdr"
    pic = _write_hdr(path, views[name])
    ref = _run_evalglare(exe, path)
    ours = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP)
    assert ours.vertical_illuminance == pytest.approx(ref["E_v"], rel=0.01)
    assert ours.dgp == pytest.approx(ref["dgp"], abs=0.02)
    assert len(ours.sources) == ref["sources"]


def test_against_evalglare_relative_threshold(tmp_path):
    # evalglare -b 5: five times the picture's mean luminance
    exe = _evalglare()
    dirs, w, ok, views = _views()
    path = tmp_path / "view.hdr"
    pic = _write_hdr(path, views["window at the side"])
    ref = _run_evalglare(exe, path, "-b", "5")
    ours = glare_dgp.dgp_from_picture(pic, dirs, w, ok, VIEW, UP, threshold_factor=5)
    assert ours.mean_luminance == pytest.approx(ref["av_lum"], rel=0.01)
    assert ours.dgp == pytest.approx(ref["dgp"], abs=0.02)


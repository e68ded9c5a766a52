"""The spectral (CIE S 026) reading of the direct part: a light of known spectrum over a black floor.

Reference (independent of the pipeline): E_v in closed form, efficacy x Y(colour) x P / (4 pi d^2) for a
point light of power P at height d over the meter (Y: Rec.709 luminance weights from colour-science, the
light's colour as Blender states it, ``temperature_color`` for a blackbody), times the mel-DER (and every
alpha-opic DER) of its spectrum from luxpy 1.12.5's CIE S 026 toolbox (tests/luxpy_s026.py, in its own
interpreter). Acceptance (issue 35): equal to 1e-6 for blackbody 2700/4000/6500 K, CIE A, D65 and an LED file.
"""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402
from radiometer.radiometry.photometry import spectral  # noqa: E402

HEIGHT_M, POWER_W = 2.0, 100.0
LUXPY_ORDER = [2, 1, 0, 3, 4]  # luxpy's (l, m, s, rh, mel) -> S 026 order (s, m, l, rh, mel)
ALPHA = ("s_cone", "m_cone", "l_cone", "rhodopic", "melanopic")


def _led():
    wl = spectral.WAVELENGTHS_NM
    return np.exp(-0.5 * ((wl - 450.0) / 10.0) ** 2) + 0.7 * np.exp(-0.5 * ((wl - 580.0) / 55.0) ** 2)


CASES = {  # name: (light settings, the spectrum luxpy is given)
    "blackbody 2700 K": ({"use_temperature": True, "temperature": 2700.0}, lambda: spectral.planck(2700.0)),
    "blackbody 4000 K": ({"use_temperature": True, "temperature": 4000.0}, lambda: spectral.planck(4000.0)),
    "blackbody 6500 K": ({"use_temperature": True, "temperature": 6500.0}, lambda: spectral.planck(6500.0)),
    "CIE A": ({"spectrum": "A"}, lambda: spectral.cie_illuminant_a()),
    "CIE D65": ({"spectrum": "D65"}, lambda: spectral.cie_illuminant("D65")),
    "LED file": ({"spectrum": "FILE"}, _led),
}


@pytest.fixture(scope="module")
def luxpy_der():
    request = {"spectra": [make().tolist() for _, make in CASES.values()]}
    script = os.path.join(os.path.dirname(os.path.dirname(__file__)), "luxpy_s026.py")
    run = subprocess.run([sys.executable, script], input=json.dumps(request), capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    der = np.array(json.loads(run.stdout)["der"])[:, LUXPY_ORDER]
    return dict(zip(CASES, der))


def _y709(rgb):
    import colour

    return float(np.asarray(rgb, float) @ colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_RGB_to_XYZ[1])


def _scene(build, tmp_path, settings):
    scene = bpy.context.scene
    build.black_world(scene)
    # a black floor 0.5 m below the meter (a meter on a surface is raised by an epsilon: not a closed form)
    build.plane(scene, size=4.0, location=(0.0, 0.0, -0.5), albedo=0.0, name="floor")
    light = build.light(scene, "POINT", (0.0, 0.0, HEIGHT_M), energy=POWER_W, shadow_soft_size=0.0,
                        use_soft_falloff=False)
    for key in ("use_temperature", "temperature"):
        if key in settings:
            setattr(light.data, key, settings[key])
    if settings.get("spectrum") == "FILE":
        path = tmp_path / "led.csv"
        path.write_text("nm,relative\n" + "".join(f"{w:g},{v:.17g}\n" for w, v in zip(spectral.WAVELENGTHS_NM, _led())))
        light.data["radiometer_spectrum"] = str(path)
    elif "spectrum" in settings:
        light.data["radiometer_spectrum"] = settings["spectrum"]
    return scene, light


@pytest.mark.parametrize("name", list(CASES))
def test_direct_mel_edi_is_ev_times_mel_der_exactly(clean_blender, build, tmp_path, luxpy_der, name):
    scene, light = _scene(build, tmp_path, CASES[name][0])
    colour = light.data.temperature_color if light.data.use_temperature else light.data.color
    ev = scene.radiometer.efficacy * _y709(colour) * POWER_W / (4.0 * math.pi * HEIGHT_M**2)
    r = api.spectral_reading((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    assert r["part"] == "direct" and r["exact"] and r["complete"], r
    assert r["illuminance_lx"] == pytest.approx(ev, rel=1e-6)
    der = luxpy_der[name]
    assert r["mel_edi_lx"] == pytest.approx(ev * der[4], rel=1e-6)
    assert r["mel_der"] == pytest.approx(der[4], rel=1e-6)
    for i, a in enumerate(ALPHA):
        assert r["alpha_opic_edi_lx"][a] == pytest.approx(ev * der[i], rel=1e-6), a
    (row,) = r["lights"]
    assert row["light"] == light.name and row["exact"]
    assert "reflected" in " ".join(r["not_included"]) and r["units"]["mel_edi_lx"] == "lx"
    json.dumps(r, allow_nan=False)  # JSON as it is


def test_unknown_and_tinted_spectra_are_said_and_the_sum_is_a_lower_bound(clean_blender, build, tmp_path):
    scene, warm = _scene(build, tmp_path, {"use_temperature": True, "temperature": 3000.0})
    rgb = build.light(scene, "POINT", (1.0, 0.0, HEIGHT_M), name="rgb", energy=50.0, shadow_soft_size=0.0)
    tinted = build.light(scene, "POINT", (-1.0, 0.0, HEIGHT_M), name="tinted", energy=50.0, shadow_soft_size=0.0,
                         use_temperature=True, temperature=3000.0, color=(1.0, 0.5, 0.5))
    r = api.spectral_reading((0.0, 0.0, 0.0))
    assert not r["complete"] and not r["exact"]
    text = " ".join(r["notes"])
    assert "lower bound" in text and rgb.name in text and tinted.name in text and warm.name not in text
    rows = {row["light"]: row for row in r["lights"]}
    assert rows[warm.name]["spectrum"] == "blackbody 3000 K"
    assert rows[rgb.name]["spectrum"] is None and "no known spectrum: an RGB colour only" in rows[rgb.name]["note"]
    assert "tints the 3000 K blackbody" in rows[tinted.name]["note"]
    assert r["mel_edi_lx"] == pytest.approx(rows[warm.name]["mel_edi_lx"], rel=1e-12)
    assert r["illuminance_known_spectrum_lx"] == pytest.approx(rows[warm.name]["illuminance_lx"], rel=1e-12)
    assert r["illuminance_lx"] == pytest.approx(sum(row["illuminance_lx"] for row in r["lights"]), rel=1e-12)
    assert r["mel_der"] == pytest.approx(rows[warm.name]["mel_der"], rel=1e-12)


def test_sun_is_daylight_at_its_cct_and_the_world_d65(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "SUN", energy=3.0, angle=0.0, use_temperature=True, temperature=5500.0)
    r = api.spectral_reading((0.0, 0.0, 0.0))
    assert r["lights"][0]["spectrum"] == "CIE daylight 5500 K (sun)" and r["exact"]
    from radiometer.radiometry.photometry import action_spectra

    assert r["mel_der"] == pytest.approx(float(action_spectra.melanopic_der(spectral.cie_daylight(5500.0))), rel=1e-12)
    assert not any("world" in s for s in r["not_included"])          # a black world gives no light


def test_the_worlds_direct_light_is_read_with_its_spectrum(clean_blender, build):
    """A uniform white world of radiance s (W/(m² sr) per channel) over an open meter: E = pi s in closed form
    (nothing above the horizon), E_v = K pi s, and mel-EDI = E_v x mel-DER of the world's spectrum (D65 by
    default: 1; D5000 when set): exact. A wall above the horizon makes the world rendered: left out, said so."""
    from radiometer.radiometry.photometry import action_spectra

    scene = bpy.context.scene
    strength = 0.7
    from radiometer.compat import ensure_node_tree

    scene.world = bpy.data.worlds.new("white sky")
    background = ensure_node_tree(scene.world).nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = strength
    ev = scene.radiometer.efficacy * math.pi * strength
    r = api.spectral_reading((0.0, 0.0, 0.0))
    (row,) = r["lights"]
    assert row["light"] == "world" and row["spectrum"] == "CIE D65 (default sky, not stated)" and r["exact"] and r["complete"]
    assert r["illuminance_lx"] == pytest.approx(ev, rel=1e-6) and r["mel_edi_lx"] == pytest.approx(ev, rel=1e-6)
    assert not any("world" in s for s in r["not_included"])
    scene.world["radiometer_spectrum"] = "D5000"
    r = api.spectral_reading((0.0, 0.0, 0.0))
    der = float(action_spectra.melanopic_der(spectral.cie_daylight(5000.0)))
    assert r["mel_edi_lx"] == pytest.approx(ev * der, rel=1e-6) and r["exact"]
    build.plane(scene, size=2.0, location=(0.0, 1.5, 1.0), rotation=(math.pi / 2, 0.0, 0.0), name="wall")
    r = api.spectral_reading((0.0, 0.0, 0.0))
    assert any(s.startswith("the world (rendered") and "CIE daylight 5000 K" in s for s in r["not_included"]), r["not_included"]
    assert r["mel_edi_lx"] == 0.0 and not r["exact"]
    out = api.circadian_check((0.0, 0.0, -1.2), (0.0, 1.0, 0.0), scene=scene)   # the eye faces the wall
    assert any(s.startswith("the world") for s in out["eyes"][0]["left_out"])


@pytest.mark.parametrize("setting, message", [
    ("/no/such/spectrum.csv", "no such file"), ("sodium", "unknown spectrum"), ("D1000", "4000 K to 25000 K")])
def test_bad_spectrum_settings_get_one_line(clean_blender, build, tmp_path, setting, message):
    _scene(build, tmp_path, {"spectrum": setting})
    with pytest.raises(RadiometerError) as info:
        api.spectral_reading((0.0, 0.0, 0.0))
    assert message in str(info.value) and "radiometer_spectrum" in str(info.value) and "\n" not in str(info.value)


def test_bad_arguments(clean_blender, build, tmp_path):
    _scene(build, tmp_path, {"spectrum": "A"})
    with pytest.raises(RadiometerError, match="quantity"):
        api.spectral_reading((0.0, 0.0, 0.0), quantity="photopic")
    with pytest.raises(RadiometerError, match="location"):
        api.spectral_reading((0.0, math.nan, 0.0))


def test_cli_measure_quantity_melanopic(clean_blender, build, tmp_path, capsys, luxpy_der):
    from radiometer import cli

    scene, light = _scene(build, tmp_path, CASES["CIE A"][0])
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    out = tmp_path / "r.json"
    assert cli._blender_cli(["measure", "--quantity", "melanopic", "--json", str(out)]) == 0
    (meter,) = json.loads(out.read_text())["meters"]
    sr = meter["spectral"]
    assert sr["exact"] and sr["units"]["mel_edi_lx"] == "lx"
    assert sr["mel_edi_lx"] == pytest.approx(meter["illuminance"] * luxpy_der["CIE A"][4], rel=1e-6)
    text = capsys.readouterr().out
    assert "mel-EDI" in text and "direct light only" in text and "exact" in text
    assert cli._blender_cli(["measure", "--quantity", "scotopic"]) == 2
    assert "--quantity" in capsys.readouterr().err


def test_spectrum_metrics_and_mesopic_api(luxpy_der):
    m = api.spectrum_metrics("A")
    assert m["spectrum"] == "CIE A" and m["units"]["sp_ratio"] == "1"
    assert m["mel_der"] == pytest.approx(luxpy_der["CIE A"][4], rel=1e-6)
    for i, a in enumerate(ALPHA):
        assert m["alpha_opic_der"][a] == pytest.approx(luxpy_der["CIE A"][i], rel=1e-6)
    assert api.spectrum_metrics("D65")["mel_der"] == 1.0
    json.dumps(m, allow_nan=False)
    mes = api.mesopic_luminance(0.5, 1.0)  # S/P = 1: mesopic = photopic (CIE 191)
    assert mes["mesopic_cd_m2"] == pytest.approx(0.5, rel=1e-13) and 0 < mes["m"] < 1
    assert mes["units"]["mesopic_cd_m2"] == "cd/m²"
    for bad in ((-1.0, 1.0), (1.0, math.inf), ("x", 1.0)):
        with pytest.raises(RadiometerError) as info:
            api.mesopic_luminance(*bad)
        assert "\n" not in str(info.value)
    with pytest.raises(RadiometerError, match="unknown spectrum"):
        api.spectrum_metrics("sodium")


def test_sidebar_melanopic_reading_of_a_meter_object(clean_blender, build, tmp_path):
    """radiometer.melanopic_reading on the active illuminance meter stores the direct reading's mel-EDI,
    mel-DER and S/P on it (what the sidebar shows); a new Measure clears it, a luminance meter is refused."""
    scene, _light = _scene(build, tmp_path, CASES["CIE D65"][0])
    meter = api.add_meter("ILLUMINANCE", (0.0, 0.0, 0.0), context=bpy.context)
    bpy.context.view_layer.objects.active = meter
    assert bpy.ops.radiometer.melanopic_reading() == {"FINISHED"}
    want = api.spectral_reading((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    m = meter.radiometer_meter
    assert m.mel_edi == pytest.approx(want["mel_edi_lx"], rel=1e-6) and m.mel_der == pytest.approx(1.0, rel=1e-6)
    assert m.spectral_status.startswith("exact")
    # with reflections: the band renders (the floor reflects nothing up to a meter on it, so the total is the
    # direct part within its interval), the status says which reading it is
    assert bpy.ops.radiometer.melanopic_reading(reflected=True) == {"FINISHED"}
    assert m.spectral_status.startswith("direct + reflected (band renders): 95 % interval")
    assert m.mel_edi == pytest.approx(want["mel_edi_lx"], rel=0.05)
    api.measure_meters([meter], quality="preview")
    assert m.spectral_status == ""                      # the new reading's spectral one is not measured yet
    spot = api.add_meter("LUMINANCE", (0.0, 0.0, 0.5), context=bpy.context)
    with pytest.raises(RadiometerError, match="not an illuminance meter"):
        api.meter_melanopic_reading(spot)
    bpy.context.view_layer.objects.active = spot
    assert not bpy.ops.radiometer.melanopic_reading.poll()


def test_report_meters_carry_the_direct_mel_edi(clean_blender, build, tmp_path):
    """The report's meter rows hold each illuminance meter's direct mel-EDI (the markdown and client tables
    print it; '>=' where a light without a spectrum is left out)."""
    from radiometer.measure.reports import report
    from radiometer.readings import format_melanopic, format_value

    scene, light = _scene(build, tmp_path, CASES["CIE D65"][0])
    meter = api.add_meter("ILLUMINANCE", (0.0, 0.0, 0.0), context=bpy.context)
    m = report._melanopic(scene, meter)
    want = api.spectral_reading((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))["mel_edi_lx"]
    assert m["mel_edi_lx"] == pytest.approx(want, rel=1e-9) and m["complete"] and m["exact"]
    assert format_melanopic(m) == f"{format_value(want, exact=True)} lx" and "e+" not in format_melanopic(m)
    del light.data["radiometer_spectrum"]                 # an RGB light: no spectrum, left out
    m = report._melanopic(scene, meter)
    assert not m["complete"] and format_melanopic(m) == ">= 0 lx"
    assert format_melanopic(None) == "-"

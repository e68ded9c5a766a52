"""Issue 35: mesopic luminance of a luminance (spot) meter's scene reading (CIE 191:2010), by band renders.

A grey plane (flat reflectance 0.5) under a 4000 K point light, black world: the plane's luminance at the
spot is the closed form L = rho E / pi, E = I cos(theta) / d^2 (one bounce, nothing else to reflect), and a flat
reflectance keeps the light's spectrum, so S/P is the blackbody's exactly.
"""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.demo import builders  # noqa: E402
from radiometer.measure.blender import scene_guard  # noqa: E402
from radiometer.radiometry.photometry import action_spectra, spectral  # noqa: E402

LIGHT = (0.0, 0.0, 2.0)
METER = (0.0, -1.0, 1.0)
SPOT = (0.0, 0.3, 0.0)


def _scene(power_w):
    scene = bpy.context.scene
    builders.metric_cycles_scene(scene)
    builders.black_world(scene)
    plane = builders.add_plane(scene, size=20.0, albedo=0.5, name="grey")
    plane.data.materials[0]["radiometer_reflectance"] = 0.5
    light = builders.add_light(scene, "POINT", LIGHT, energy=power_w, shadow_soft_size=0.0, use_temperature=True,
                               temperature=4000.0)
    return scene, light


def _closed_form(scene, light, direction, acceptance_deg):
    """The plane's luminance averaged over the meter's cone (uniform in solid angle: what a spot meter reads),
    by a fine polar quadrature of L = rho I cos(theta) / (pi d^2) where each direction meets the plane."""
    from radiometer.measure.blender import request as request_of

    _space, weights, efficacy = request_of.build(scene).photometry
    colour = np.asarray(tuple(light.data.temperature_color), float)
    intensity = efficacy * float(colour @ weights) * light.data.energy / (4.0 * math.pi)  # cd
    half = math.radians(acceptance_deg) / 2
    # cos(alpha) uniform in [cos(half), 1] is uniform in solid angle: midpoints in it and in azimuth
    c = 1.0 - (np.arange(400) + 0.5) / 400 * (1.0 - math.cos(half))
    phi = (np.arange(256) + 0.5) / 256 * 2 * math.pi
    c, phi = np.meshgrid(c, phi, indexing="ij")
    sn = np.sqrt(1.0 - c**2)
    axis = np.asarray(direction, float)
    u = np.cross(axis, (1.0, 0.0, 0.0))
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    dirs = c[..., None] * axis + sn[..., None] * (np.cos(phi)[..., None] * u + np.sin(phi)[..., None] * v)
    t = -METER[2] / dirs[..., 2]
    hit = np.asarray(METER) + t[..., None] * dirs
    d = np.asarray(LIGHT) - hit
    e = intensity * d[..., 2] / np.linalg.norm(d, axis=-1) ** 3  # lx on the plane
    return float(np.mean(0.5 * e / math.pi))  # cd/m²


@pytest.mark.parametrize("power_w, regime", [(1.0, "mesopic"), (2000.0, "photopic")])
def test_mesopic_luminance_of_a_grey_plane(clean_blender, power_w, regime):
    scene, light = _scene(power_w)
    direction = np.asarray(SPOT) - np.asarray(METER)
    direction /= np.linalg.norm(direction)
    before = scene_guard.scene_fingerprint(scene)
    r = api.mesopic_reading(METER, tuple(direction), acceptance_deg=1.0, quality="preview", seed=0)
    assert scene_guard.scene_fingerprint(scene) == before and not light.data.use_nodes
    assert light.data.use_temperature and light.data.energy == power_w  # put back after the band renders
    lp_true = _closed_form(scene, light, direction, 1.0)
    sp_true = float(action_spectra.sp_ratio(spectral.planck(4000.0)))
    lp = r["photopic_cd_m2"]
    assert lp["low_95"] <= lp_true <= lp["high_95"], (lp, lp_true)
    # a flat reflectance keeps the light's spectrum: S/P is the blackbody's, whatever the noise
    assert r["sp_ratio"] == pytest.approx(sp_true, rel=1e-9)
    lmes_true, _ = action_spectra.mesopic_luminance(lp_true, sp_true)
    mes = r["mesopic_cd_m2"]
    assert mes["low_95"] <= lmes_true <= mes["high_95"], (mes, lmes_true)
    assert r["regime"] == regime and r["units"]["mesopic_cd_m2"] == "cd/m²" and not r["exact"]
    if regime == "mesopic":
        assert mes["estimate"] > lp["estimate"]  # S/P 1.87: a bluish light gains in mesopic vision
    else:
        assert mes["estimate"] == pytest.approx(lp["estimate"], rel=1e-12)


def test_a_light_without_spectrum_is_one_line(clean_blender):
    scene, light = _scene(10.0)
    light.data.use_temperature = False
    light.data.color = (1.0, 0.5, 0.2)
    with pytest.raises(api.RadiometerError, match="no known spectrum"):
        api.mesopic_reading(METER, (0.0, 1.0, -1.0))
    with pytest.raises(api.RadiometerError, match="acceptance_deg"):
        api.mesopic_reading(METER, (0.0, 1.0, -1.0), acceptance_deg=0.0)


def test_cli_measure_melanopic_reflected_reads_a_luminance_meter_mesopic(clean_blender, tmp_path, capsys):
    import json

    from radiometer import cli

    scene, light = _scene(1.0)
    direction = np.asarray(SPOT) - np.asarray(METER)
    direction /= np.linalg.norm(direction)
    import mathutils

    rotation = mathutils.Vector((0.0, 0.0, -1.0)).rotation_difference(mathutils.Vector(direction)).to_euler()
    api.add_meter("LUMINANCE", METER, rotation=tuple(rotation))
    out = tmp_path / "m.json"
    assert cli._blender_cli(["measure", "--quantity", "melanopic", "--reflected", "--quality", "preview",
                             "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "mesopic (CIE 191)" in printed and "mesopic\n" in printed, printed
    (m,) = json.loads(out.read_text())["meters"]
    sr = m["spectral"]
    lmes_true, _ = action_spectra.mesopic_luminance(_closed_form(scene, light, direction, 1.0),
                                                    float(action_spectra.sp_ratio(spectral.planck(4000.0))))
    assert sr["mesopic_cd_m2"]["low_95"] <= lmes_true <= sr["mesopic_cd_m2"]["high_95"]

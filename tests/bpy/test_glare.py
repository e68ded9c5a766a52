"""UGR (issue 23 item 3) on a small office against an independent CIE 117 computation written
differently: solid angles and direct illuminance by numerical integration over each panel (400 x 400
cells), the position index from Guth's geometry (H, T, R: height above the eye, lateral offset, distance
along the line of sight; tau = atan(T/H), sigma = atan(sqrt(H² + T²)/R)), the background from the
reference patch render of the total vertical illuminance (tests/bpy/reference.py) minus the integrated
direct part. And against Radiance's evalglare on a fisheye render of the same office (test-only)."""

import importlib.util
import math
import os
import subprocess
import sys

import bpy
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import office  # noqa: E402
import reference  # noqa: E402

from radiometer import api  # noqa: E402


def _panel_integrals(eye, view, centre, side, cells=400):
    """(solid angle sr, projected solid angle on the plane facing ``view``) of a down-facing square."""
    h = side / 2
    t = (np.arange(cells) + 0.5) / cells * side - h
    gx, gy = np.meshgrid(centre[0] + t, centre[1] + t)
    r = np.stack([gx - eye[0], gy - eye[1], np.full_like(gx, centre[2] - eye[2])], -1)
    dist = np.linalg.norm(r, axis=-1)
    cos_src = r[..., 2] / dist            # the panel faces -z: cos between its normal and the ray back to the eye
    da = (side / cells) ** 2
    omega = float(np.sum(cos_src * da / dist**2))
    cos_eye = np.maximum(r @ np.asarray(view, float) / dist, 0.0)
    return omega, float(np.sum(cos_eye * cos_src * da / dist**2))


def _levin(sigma, tau):
    return math.exp((35.2 - 0.31889 * tau - 1.22 * math.exp(-2 * tau / 9)) / 1000 * sigma
                    + (21 + 0.26667 * tau - 0.002963 * tau * tau) / 1e5 * sigma * sigma)


def test_ugr_office_area_lights_against_independent_cie117(clean_blender):
    scene = bpy.context.scene
    office.build(scene)
    eye, view = np.array(office.EYE), np.array(office.VIEW)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="standard")
    assert len(g.sources) == 4 and not g.left_out
    lum = office.panel_luminance()
    terms, e_direct = 0.0, 0.0
    for name, (x, y) in zip(("Panel 1", "Panel 2", "Panel 3", "Panel 4"), office.PANELS):
        omega, projected = _panel_integrals(eye, view, (x, y, office.PANEL_Z), office.PANEL)
        H, T, R = office.PANEL_Z - eye[2], abs(x - eye[0]), y - eye[1]
        tau, sigma = math.degrees(math.atan2(T, H)), math.degrees(math.atan(math.hypot(H, T) / R))
        p = _levin(sigma, tau)
        terms += lum**2 * omega / p**2
        e_direct += lum * projected
        mine = next(s for s in g.sources if s["name"] == name)
        assert mine["luminance"] == pytest.approx(lum, rel=1e-5)
        assert mine["solid_angle"] == pytest.approx(omega, rel=1e-4)
        assert mine["position_index"] == pytest.approx(p, rel=1e-6)  # float32 light positions
    e_rgb, se, _info = reference.reference_irradiance(scene, tuple(eye), tuple(view), target_rel_error=3e-3)
    e_total = reference.luminance(e_rgb)[1]
    lb = (e_total - e_direct) / math.pi
    expected = 8 * math.log10(0.25 / lb * terms)
    assert g.background_luminance == pytest.approx(lb, rel=0.03)
    assert abs(g.ugr - expected) < 0.5, (g.ugr, expected, g.background_luminance, lb)
    assert g.ugr_std_error < 0.2


def _emissive_square(scene, name, centre, side, strength):
    """A down-facing square mesh with an Emission shader (white, ``strength``): radiance = strength W/(m² sr)
    per channel (Blender manual: strength 1 shows the colour as it is)."""
    h = side / 2
    x, y, z = centre
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(x - h, y - h, z), (x - h, y + h, z), (x + h, y + h, z), (x + h, y - h, z)], [], [(0, 1, 2, 3)])
    mesh.materials.append(office.emission_material(name, strength))
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def test_ugr_emissive_meshes_against_independent_cie117(clean_blender):
    """The office's panels as emitting squares (Emission shader, radiance = the area panels' P / (pi A)):
    each is a source of luminance K x strength, its solid angle the 400 x 400-cell integral, p from Guth's
    geometry at its centre; the background excludes their direct light (E_total - E_ind = the integrated
    direct illuminance at the eye)."""
    scene = bpy.context.scene
    office.build(scene, panels=False)
    strength = office.PANEL_POWER / (math.pi * office.PANEL ** 2)  # W/(m² sr)
    for k, (x, y) in enumerate(office.PANELS):
        _emissive_square(scene, f"Glow {k + 1}", (x, y, office.PANEL_Z), office.PANEL, strength)
    eye, view = np.array(office.EYE), np.array(office.VIEW)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="standard")
    assert len(g.sources) == 4, g.left_out
    lum = 683.0 * strength
    terms, e_direct = 0.0, 0.0
    for k, (x, y) in enumerate(office.PANELS):
        omega, projected = _panel_integrals(eye, view, (x, y, office.PANEL_Z), office.PANEL)
        H, T, R = office.PANEL_Z - eye[2], abs(x - eye[0]), y - eye[1]
        p = _levin(math.degrees(math.atan(math.hypot(H, T) / R)), math.degrees(math.atan2(T, H)))
        terms += lum**2 * omega / p**2
        e_direct += lum * projected
        mine = next(s for s in g.sources if s["name"].startswith(f"Glow {k + 1}"))
        assert mine["luminance"] == pytest.approx(lum, rel=1e-6)
        assert mine["solid_angle"] == pytest.approx(omega, rel=1e-4)
        assert mine["position_index"] == pytest.approx(p, rel=1e-6)
    assert g.total_illuminance - g.indirect_illuminance == pytest.approx(e_direct, rel=0.03)
    expected = 8 * math.log10(0.25 / g.background_luminance * terms)
    assert abs(g.ugr - expected) < 0.05, (g.ugr, expected)


def test_ugr_left_out_sources_are_named(clean_blender):
    scene = bpy.context.scene
    lights = office.build(scene)
    lights[0].location.z = 1.0  # below the eye's line of sight (eye at 1.2 m): outside CIE 117's field
    lights[0].rotation_euler = (-math.pi / 2, 0.0, 0.0)  # facing the eye (-y), so it is not just seen from behind
    point = bpy.data.lights.new("Bare Lamp", "POINT")
    obj = bpy.data.objects.new("Bare Lamp", point)
    obj.location = (0.0, 1.0, 2.5)
    scene.collection.objects.link(obj)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="preview")
    left = {d["name"]: d["reason"] for d in g.left_out}
    assert "below the line of sight" in left["Panel 1"]
    assert "luminous area" in left["Bare Lamp"]
    assert len(g.sources) == 3
    with pytest.raises(api.RadiometerError if hasattr(api, "RadiometerError") else Exception):
        api.glare_ugr(office.EYE, (0, 0, 1), scene=scene)


# pyradiance where this interpreter finds it (a worktree or the LTS venv has no .venv of its own)
_PYRADIANCE = importlib.util.find_spec("pyradiance")
RADIANCE = os.path.dirname(_PYRADIANCE.origin) if _PYRADIANCE and _PYRADIANCE.origin else ""


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists(os.path.join(RADIANCE, "bin", "evalglare")), reason="pyradiance not installed")
def test_ugr_office_against_evalglare(clean_blender, tmp_path):
    """evalglare on a 160 x 160 fisheye (rpict -vta, 2 ambient bounces): its UGR within about 1, for the
    office's area-light panels and for the same office lit by IES luminaires of the same luminance (a
    0.6 m opening with I = I0 cos(gamma), I0 = L A, is a Lambertian panel of luminance L: one Radiance
    scene, one evalglare run, serves both)."""
    scene = bpy.context.scene
    panels = office.build(scene)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="standard")
    for obj in panels:
        bpy.data.objects.remove(obj)
    _ies_luminaires(scene, tmp_path, office.panel_luminance() * office.PANEL ** 2)  # I0 = L A, cd
    g_ies = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="standard")
    assert len(g_ies.sources) == 4, g_ies.left_out
    env = dict(os.environ, RAYPATH=f".:{os.path.join(RADIANCE, 'lib')}")
    b = os.path.join(RADIANCE, "bin")
    rad = office.radiance_scene(str(tmp_path / "office.rad"))
    oct_path, hdr = tmp_path / "office.oct", tmp_path / "fish.hdr"
    with open(oct_path, "wb") as f:
        subprocess.run([os.path.join(b, "oconv"), rad], stdout=f, check=True, env=env)
    view = ["-vta", "-vp", *map(str, office.EYE), "-vd", *map(str, office.VIEW), "-vu", "0", "0", "1",
            "-vh", "180", "-vv", "180"]
    with open(hdr, "wb") as f:
        subprocess.run([os.path.join(b, "rpict"), *view, "-x", "160", "-y", "160", "-ab", "2", "-ad", "512", "-as",
                        "0", "-aa", "0.15", "-ar", "64", "-ps", "1", "-dj", "0", str(oct_path)], stdout=f, check=True,
                       env=env)
    out = subprocess.run([os.path.join(b, "evalglare"), "-vta", "-vh", "180", "-vv", "180", "-b", "2000", str(hdr)],
                         capture_output=True, text=True, check=True, env=env).stdout
    names, values = out.split(":")
    result = dict(zip(names.split(","), map(float, values.split())))
    print(f"UGR {g.ugr:.2f} (Lb {g.background_luminance:.1f} cd/m²), IES {g_ies.ugr:.2f} (Lb "
          f"{g_ies.background_luminance:.1f} cd/m²); evalglare {result['ugr']:.2f}")
    assert abs(g.ugr - result["ugr"]) < 1.0, (g.ugr, result)
    assert abs(g_ies.ugr - result["ugr"]) < 1.0, (g_ies.ugr, result)


IES_COSINE = """IESNA:LM-63-2002
[TEST] cosine panel for the glare test
[LUMINAIRE] 600 x 600 mm panel, I = I0 cos(gamma)
TILT=NONE
1 -1 1 19 1 1 2 0.6 0.6 0
1 1 30
{v}
0
{cd}
"""


def _ies_luminaires(scene, folder, i0):
    """The office's four panels as IES luminaires: a 0.6 m square opening, I = i0 cos(gamma) cd."""
    v = [5.0 * k for k in range(19)]
    path = folder / "panel.ies"
    path.write_text(IES_COSINE.format(v=" ".join(f"{a:g}" for a in v),
                                      cd=" ".join(f"{i0 * math.cos(math.radians(a)):.6f}" for a in v)))
    for k, (x, y) in enumerate(office.PANELS):
        api.import_luminaire(str(path), scene=scene, location=(x, y, office.PANEL_Z), name=f"Luminaire {k + 1}")


def test_ugr_office_ies_luminaires_against_independent_cie117(clean_blender, tmp_path):
    """IES luminaires with a 0.6 x 0.6 m flat opening and I = I0 cos(gamma): L = I0 / A in every direction,
    omega = A cos(gamma) / d² (CIE 117's definitions), direct E at the eye = sum I cos(theta_eye) / d²."""
    scene = bpy.context.scene
    office.build(scene, panels=False)
    i0 = 2500.0  # cd
    _ies_luminaires(scene, tmp_path, i0)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="standard")
    assert len(g.sources) == 4, g.left_out
    eye, view = np.array(office.EYE), np.array(office.VIEW)
    area = 0.36
    terms, e_direct = 0.0, 0.0
    for x, y in office.PANELS:
        r = np.array([x, y, office.PANEL_Z]) - eye
        d = float(np.linalg.norm(r))
        cos_gamma = r[2] / d
        omega = area * cos_gamma / d**2
        H, T, R = r[2], abs(r[0]), r[1]
        p = _levin(math.degrees(math.atan(math.hypot(H, T) / R)), math.degrees(math.atan2(T, H)))
        terms += (i0 / area) ** 2 * omega / p**2
        e_direct += i0 * cos_gamma * (r @ view) / d / d**2
    for s in g.sources:
        assert s["luminance"] == pytest.approx(i0 / area, rel=2e-3)  # Catmull-Rom between 5-degree rows
    e_rgb, _se, _info = reference.reference_irradiance(scene, tuple(eye), tuple(view), target_rel_error=3e-3)
    lb = (reference.luminance(e_rgb)[1] - e_direct) / math.pi
    expected = 8 * math.log10(0.25 / lb * terms)
    assert abs(g.ugr - expected) < 0.5, (g.ugr, expected, g.background_luminance, lb)


def test_glare_cli(clean_blender, tmp_path, capsys):
    from radiometer import cli

    scene = bpy.context.scene
    office.build(scene)
    blend = str(tmp_path / "office.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    obs = [str(v) for v in office.EYE + office.VIEW]
    assert cli.main(["glare", blend, "--observer", *obs, "--quality", "preview", "--json", str(tmp_path / "g.json")]) == 0
    text = capsys.readouterr().out
    assert "UGR " in text and "Panel 1" in text and "cd/m²" in text
    assert cli.main(["glare", blend]) == 2  # nothing asked: one line, exit code 2

"""DGP at an observer (issue 34): a rendered fisheye of an emitting rectangle against the closed form
(E_v = L pi F with F the differential-area-to-rectangle form factor, omega exact, P = 1 on the line of
sight), and Radiance's evalglare (test-only, shipped with pyradiance) on the same rendered HDR."""

import math
import os
import pathlib
import subprocess
import sys

import bpy
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import office  # noqa: E402

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402
from radiometer.measure.blender import scene_guard  # noqa: E402
from radiometer.radiometry.metrics import glare
from radiometer.radiometry.metrics import glare_dgp  # noqa: E402

EYE = (0.0, 0.0, 1.2)
VIEW = (0.0, 1.0, 0.0)
HW, HH, STRENGTH = 0.4, 0.25, 8.0       # half sizes (m) of the rectangle 1 m ahead; emission strength


def _glowing_rectangle(scene):
    x0, x1, z0, z1 = -HW, HW, EYE[2] - HH, EYE[2] + HH
    mesh = bpy.data.meshes.new("Window")
    mesh.from_pydata([(x0, 1.0, z0), (x1, 1.0, z0), (x1, 1.0, z1), (x0, 1.0, z1)], [], [(0, 1, 2, 3)])
    mesh.materials.append(office.emission_material("Window", STRENGTH))
    scene.collection.objects.link(bpy.data.objects.new("Window", mesh))


def _closed_form():
    def corner(a, b):  # form factor, differential area to a parallel a x b rectangle with a corner on its normal
        return (a / math.sqrt(1 + a * a) * math.atan(b / math.sqrt(1 + a * a))
                + b / math.sqrt(1 + b * b) * math.atan(a / math.sqrt(1 + b * b))) / (2 * math.pi)

    lum = 683.0 * STRENGTH                      # white emission: Y = strength, K = 683 lm/W
    ev = lum * math.pi * 4 * corner(HW, HH)
    omega = glare.polygon_solid_angle((0, 0, 0), [(-HW, 1, -HH), (HW, 1, -HH), (HW, 1, HH), (-HW, 1, HH)])
    return glare_dgp.dgp(ev, [lum], [omega], [1.0]), ev


def test_dgp_of_a_glowing_rectangle_closed_form_and_evalglare(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    _glowing_rectangle(scene)
    before = scene_guard.scene_fingerprint(scene)
    hdr = tmp_path / "fisheye.hdr"
    g = api.glare_dgp(EYE, VIEW, scene=scene, quality="preview", resolution=96, hdr_path=str(hdr))
    assert scene_guard.scene_fingerprint(scene) == before and "radiometer_dgp_fisheye" not in bpy.data.objects
    expected, ev = _closed_form()
    print(f"DGP {g.dgp:.4f} ±{g.dgp_std_error:.4f} ±{g.dgp_resolution_error:.4f} (closed form {expected:.4f}); E_v {g.vertical_illuminance:.1f} "
          f"(picture {g.picture_vertical_illuminance:.1f}, exact {ev:.1f}) lx")
    assert len(g.sources) == 1 and g.dgp_class == glare_dgp.dgp_class(g.dgp)
    assert g.vertical_illuminance == pytest.approx(ev, rel=max(0.01, 3 * g.vertical_illuminance_rel_std_error))
    assert g.picture_vertical_illuminance == pytest.approx(ev, rel=0.02)
    assert abs(g.dgp - expected) <= 3 * math.hypot(g.dgp_std_error, g.dgp_resolution_error)
    pyradiance = pytest.importorskip("pyradiance")
    exe = pathlib.Path(pyradiance.__file__).parent / "bin" / "evalglare"
    if not exe.exists():
        pytest.skip("evalglare not found in pyradiance")
    out = subprocess.run([str(exe), "-d", str(hdr)], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ)).stdout
    names, values = next(x for x in out.splitlines() if x.startswith("dgp,av_lum,E_v")).split(":")
    ref = dict(zip(names.split(","), map(float, values.split())))
    print(f"evalglare on the same HDR: DGP {ref['dgp']:.4f}, E_v {ref['E_v']:.1f} lx")
    assert abs(g.dgp - ref["dgp"]) < 0.02


def test_dgp_bad_input_one_line(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    for kwargs in ({"resolution": 8}, {"threshold_cd_m2": -1.0}):
        with pytest.raises(RadiometerError):
            api.glare_dgp(EYE, VIEW, scene=scene, **kwargs)
    with pytest.raises(RadiometerError, match="vertical"):
        api.glare_dgp(EYE, (0, 0, 1), scene=scene)
    with pytest.raises(RadiometerError, match="no light"):   # a black world: nothing reaches the eye
        api.glare_dgp(EYE, VIEW, scene=scene, resolution=16)


def test_glare_cli_dgp(clean_blender, build, tmp_path, capsys):
    from radiometer import cli

    scene = bpy.context.scene
    build.black_world(scene)
    _glowing_rectangle(scene)
    out = tmp_path / "g.json"
    obs = [str(v) for v in (*EYE, *VIEW)]
    assert cli._blender_cli(["glare", "--index", "dgp", "--quality", "preview", "--resolution", "48",
                             "--observer", *obs, "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "DGP 0." in text and "glare sources" in text
    import json

    data = json.loads(out.read_text())
    assert 0.3 < data["observers"][0]["dgp"] < 0.4
    # bad input: one line, non-zero exit, nothing written
    assert cli._blender_cli(["glare", "--index", "dgp", "--json", str(tmp_path / "x.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--index dgp needs --observer" in err
    assert not (tmp_path / "x.json").exists()
    assert cli._blender_cli(["glare", "--index", "dgp", "--observer", *obs, "--observer", *obs,
                             "--hdr", str(tmp_path / "f.hdr")]) == 2
    assert "exactly one --observer" in capsys.readouterr().err

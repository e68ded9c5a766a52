"""The Radiance export (api.export_radiance, `radiometer export-radiance`, measure/reports/radiance_export.py):
the exported scene, run with Radiance's rtrace (pyradiance's binaries, test-only), reads the same daylight
factor and illuminance as Radiometer in the side-lit room (6 mm pane) and the daylit demo room, within
the combined standard errors; bad input gets one line and writes nothing; the scene is untouched.

Radiance runs as a path tracer with a stated standard error (tests/bpy/radiance_run.py: -ab 32 with a
1e-9 weight limit, converged in bounces for these rooms, whose highest reflectance is 0.7).

Radiance's results are cached: an earlier rtrace run on byte-identical exported files (every file Radiance
reads, SHA-256), the same command line and sample counts and the same Radiance build is taken from
tests/data/radiance_cache/<key>.json (tests/bpy/radiance_run.py, cached_rtrace_lux). A change of the export
changes the key: rtrace runs again and the test writes the new entry, to be committed. Set
RADIOMETER_RADIANCE_RERUN=1 to run rtrace every time (the cache is then neither read nor overwritten)."""

import json
import math
import os
import subprocess
import sys

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.errors import RadiometerError

sys.path.insert(0, os.path.dirname(__file__))
import daylight_room as room  # noqa: E402
from radiance_run import cached_rtrace_lux, radiance_env  # noqa: E402

def _state(scene):
    ids = {name: sorted(b.name for b in getattr(bpy.data, name)) for name in ("objects", "worlds", "lights", "materials")}
    return ids, scene.world, scene.render.engine, scene.render.resolution_x, scene.cycles.samples


def _agree(name, ours, our_rel, ref, ref_rel):
    se = math.hypot(our_rel * ours, ref_rel * ref)
    print(f"{name}: Radiometer {ours:.5g} +- {100 * our_rel:.2f} %, Radiance {ref:.5g} +- {100 * ref_rel:.2f} % "
          f"({(ours - ref) / se:+.2f} sigma)")
    assert abs(ours - ref) <= 3 * se, name


def _work_plane(scene, name, size, location):
    import bmesh

    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=0.5)
    bm.to_mesh(me)
    bm.free()
    ob = bpy.data.objects.new(name, me)
    ob.scale = (size[0], size[1], 1.0)
    ob.location = location
    ob.hide_render = True  # an imaginary plane
    scene.collection.objects.link(ob)
    return ob


def test_side_lit_room_through_a_pane_reads_the_same_in_radiance(clean_blender, tmp_path):
    """Daylight factor (the CIE overcast sky of sky_overcast.rad) and illuminance under the scene's own
    CIE clear sky type 12 (sky.rad, its brightfunc with the sun's indicatrix) behind the 6 mm pane."""
    scene = bpy.context.scene
    room.build_blender(scene)
    room.add_pane_blender(scene)
    sun = np.array([0.3, -0.8, 0.5])
    sun /= np.linalg.norm(sun)
    api.set_cie_sky(scene, 12, horizontal_illuminance_lux=20_000.0, sun_direction=sun, ground_reflectance=0.2)
    plane = _work_plane(scene, "Work plane", (3.0, 2.0), (2.0, 1.5, 0.85))
    before = _state(scene)
    out = tmp_path / "rad"
    result = api.export_radiance(str(out), resolution=(3, 1))
    assert _state(scene) == before
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(["README.txt", "radiance_export.json", "radiometer_overcast.cal", "radiometer_sky.cal",
                            "scene.rad", "sky.rad", "sky_gensky.rad", "sky_overcast.rad", "work_plane.pts"])
    manifest = json.loads((out / "radiance_export.json").read_text())
    assert manifest["summary"]["panes"] == 1 and manifest["summary"]["grids"][0]["plane"] == plane.name
    assert "glass" in (out / "scene.rad").read_text() and "gensky -ang" in (out / "sky_gensky.rad").read_text()
    assert "gensky" in (out / "sky.rad").read_text() and result["unmapped"] == []

    points = np.loadtxt(out / "work_plane.pts")[:, :3]
    assert np.allclose(points, [(1.0, 1.5, 0.85), (2.0, 1.5, 0.85), (3.0, 1.5, 0.85)])
    ref, ref_rel = cached_rtrace_lux(str(out), "sky_overcast.rad", "work_plane.pts", 300_000)
    df = api.daylight_factor(points, quality="standard", seed=7, ground_reflectance=0.2)
    for k, r in enumerate(df):
        _agree(f"DF at {points[k]}", r.daylight_factor, r.rel_std_error, ref[k] / 100.0, ref_rel[k])
    ref, ref_rel = cached_rtrace_lux(str(out), "sky.rad", "work_plane.pts", 300_000)
    e = api.measure_illuminance(points, quality="standard", seed=7)
    for k, r in enumerate(e):
        _agree(f"E under CIE sky 12 at {points[k]}", r.illuminance, r.rel_std_error, ref[k], ref_rel[k])
    assert _state(scene) == before


def _view_matches_the_camera(scene, cam, vf):
    """Radiance's rays of the view (vwrays, 4 x 3 pixel centres, top row first) land where Blender's own
    projection of the camera (world_to_camera_view: sensor fit, lens, shift, render aspect) puts those
    pixel centres."""
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector

    bindir, _libdir = room.radiance_bin()
    out = subprocess.run([os.path.join(bindir, "vwrays"), "-vf", vf, "-x", "4", "-y", "3", "-pa", "0"],
                         capture_output=True, text=True, check=True)
    rays = np.array(out.stdout.split(), float).reshape(-1, 6)
    assert len(rays) == 12
    axis = -np.array(cam.matrix_world.to_3x3().col[2], float)
    for k, (o, d) in enumerate(zip(rays[:, :3], rays[:, 3:])):
        u, v = (k % 4 + 0.5) / 4, 1 - (k // 4 + 0.5) / 3
        x, y, z = world_to_camera_view(scene, cam, Vector(o + 2.0 * d))
        assert (x, y, z) == pytest.approx((u, v, 2.0 * float(d @ axis)), abs=1e-5)


def test_daylit_demo_room_reads_the_same_in_radiance(clean_blender, tmp_path):
    """The daylit demo room (separate closed boxes, a 6 mm Glass BSDF slab of IOR 1.5, the SPA sun of the
    March equinox in London, a black world): illuminance from the sun through the pane (sky.rad's solar
    source), and the daylight factor (sky_overcast.rad), at the demo's floor and desk meters."""
    from radiometer.demo import daylight
    from radiometer.operators.meter import add_meter

    scene = daylight.build(bpy.context.scene)
    api.set_sun(scene, daylight.SITE["latitude_deg"], daylight.SITE["longitude_deg"], daylight.local_time())
    names = ["Floor in the sun patch", "Desk height near window", "Floor, back corner"]
    for name in names:
        add_meter(bpy.context, "ILLUMINANCE", daylight.METERS[name][0]).name = name
    cam = scene.objects["Camera"]  # the demo room's own camera (issue 34), set to a view with a shift here
    cam.location, cam.rotation_euler = (0.0, 1.8, 1.5), (math.radians(80), 0.0, math.radians(170))
    cam.data.lens, cam.data.shift_x, cam.data.shift_y = 24.0, 0.1, -0.05
    scene.camera = cam
    before = _state(scene)
    out = tmp_path / "rad"
    result = api.export_radiance(str(out))
    assert _state(scene) == before
    assert result["summary"]["meters"] == names and result["summary"]["sky"] == "none"
    assert result["summary"]["views"] == [{"camera": "Camera", "file": "camera.vf", "active": True}]
    assert (out / "camera.vf").read_text().startswith("rview -vtv -vp 0 1.8 1.5 -vd ")
    _view_matches_the_camera(scene, cam, str(out / "camera.vf"))
    sky = (out / "sky.rad").read_text()
    assert "source" in sky and "light" in sky  # the sun
    pts = np.loadtxt(out / "meters.pts")
    assert np.allclose(pts[:, :3], [daylight.METERS[n][0] for n in names], atol=1e-6)

    ref, ref_rel = cached_rtrace_lux(str(out), "sky.rad", "meters.pts", 100_000)
    readings = api.measure_illuminance(pts[:, :3], pts[:, 3:], quality="standard", seed=11)
    for name, r, e_ref, rel in zip(names, readings, ref, ref_rel):
        _agree(f"sun, {name}", r.illuminance, r.rel_std_error, e_ref, rel)
    ref, ref_rel = cached_rtrace_lux(str(out), "sky_overcast.rad", "meters.pts", 300_000)
    df = api.daylight_factor(pts[:, :3], pts[:, 3:], quality="standard", seed=11, ground_reflectance=0.2)
    for name, r, e_ref, rel in zip(names, df, ref, ref_rel):
        _agree(f"DF, {name}", r.daylight_factor, r.rel_std_error, e_ref / 100.0, rel)
    assert _state(scene) == before


def test_bad_input_writes_nothing(clean_blender, build, tmp_path):
    from radiometer import cli

    scene = bpy.context.scene
    build.plane(scene, size=2.0, location=(0, 0, 0), name="floor")
    afile = tmp_path / "a_file"
    afile.write_text("keep")
    with pytest.raises(RadiometerError, match="not a folder"):
        api.export_radiance(str(afile))
    assert afile.read_text() == "keep"
    with pytest.raises(RadiometerError, match="ground_reflectance"):
        api.export_radiance(str(tmp_path / "x"), ground_reflectance=2.0)
    with pytest.raises(RadiometerError, match="not both"):
        api.export_radiance(str(tmp_path / "x"), resolution=(2, 2), spacing=0.5)
    assert not (tmp_path / "x").exists()
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if not os.access(locked, os.W_OK):  # root writes anywhere
            with pytest.raises(RadiometerError):
                api.export_radiance(str(locked))
            assert list(locked.iterdir()) == []
    finally:
        locked.chmod(0o700)
    assert cli._blender_cli(["export-radiance", str(afile)]) == 2
    out = tmp_path / "cli"
    assert cli._blender_cli(["export-radiance", str(out), "--json", str(tmp_path / "r.json")]) == 0
    assert (out / "scene.rad").exists() and "floor" in (out / "scene.rad").read_text()
    readme = (out / "README.txt").read_text()
    assert "the world is black" in readme and "Not mapped" in readme
    blend = tmp_path / "saved.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend), copy=True)
    out2 = tmp_path / "from_file"
    assert cli.main(["export-radiance", str(blend), str(out2)]) == 0  # the documented form: scene.blend OUT/
    assert (out2 / "scene.rad").read_text() == (out / "scene.rad").read_text()
    assert cli.main(["export-radiance", str(blend), str(afile)]) == 2 and afile.read_text() == "keep"


def _ies(folder):
    """An IES file whose intensity varies with both angles: cd = 1000 (1 + cos v) (1 + 0.5 sin v cos C) / 2 over
    v 0..180 deg by 5, C 0..360 by 5 (a type C file of full symmetry)."""
    v, h = np.arange(0.0, 181.0, 5.0), np.arange(0.0, 361.0, 5.0)
    rv, rh = np.radians(v)[None, :], np.radians(h)[:, None]
    cd = 500.0 * (1 + np.cos(rv)) * (1 + 0.5 * np.sin(rv) * np.cos(rh))  # (n_h, n_v); one value at each pole
    chunks = lambda a: [" ".join(f"{x:.8g}" for x in a[i:i + 7]) for i in range(0, len(a), 7)]  # noqa: E731
    lines = ["IESNA:LM-63-2002", "[TEST] lobed", "TILT=NONE", f"1 -1 1 {v.size} {h.size} 1 2 0 0 0", "1 1 0"]
    lines += chunks(v) + chunks(h) + [c for row in cd for c in chunks(row)]
    path = folder / "lobed.ies"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_lights_read_the_same_in_radiance(clean_blender, build, tmp_path):
    """Area (rectangle, disk), point, spot (blend 0) and a rotated IES light over a black world and no
    geometry, in a scene of 0.5 m units: Radiometer's closed forms (exact) against rtrace's direct calculation (-ab 0, -ds 0.002 -dj 0:
    area sources subdivided until a piece is 1/500 of its distance). Agreement within 0.5 % (the sources'
    subdivision and the 5 mm spheres standing in for points: (r/d)^2 < 1e-4) plus, for the IES light, the
    export's stated resampling error of its table."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (-1.5, 0.0, 2.0), (0.3, 0.0, 0.0), energy=300.0, size=0.6, size_y=0.3,
                shape="RECTANGLE", name="panel")
    build.light(scene, "AREA", (1.5, 1.0, 2.5), energy=200.0, size=0.5, shape="DISK", name="disk")
    build.light(scene, "POINT", (0.0, -1.5, 2.0), energy=150.0, shadow_soft_size=0.0, name="bulb")
    build.light(scene, "SPOT", (0.5, 1.5, 3.0), energy=500.0, shadow_soft_size=0.0, spot_size=math.radians(70),
                spot_blend=0.0, name="spot")
    api.import_luminaire(str(_ies(tmp_path)), location=(0.0, 0.0, 2.2), rotation_euler=(0.4, 0.0, 0.7),
                         name="lobed")
    scene.unit_settings.scale_length = 0.5  # 1 scene unit = 0.5 m: the export writes metres
    rng = np.random.default_rng(5)
    points = np.c_[rng.uniform(-2.5, 2.5, (12, 2)), np.zeros(12)]  # scene units
    result = api.export_radiance(str(tmp_path / "rad"))
    folder = str(tmp_path / "rad")
    assert [u for u in result["unmapped"] if "lobed" in u or "panel" in u] == []
    error = result["summary"]["photometric_resampling_error"]["lobed"]
    assert 0 <= error < 0.005
    env = radiance_env(folder)
    with open(os.path.join(folder, "lights.oct"), "wb") as f:
        subprocess.run(["oconv", "scene.rad"], cwd=folder, env=env, stdout=f, check=True)
    rays = "".join(f"{x} {y} {z} 0 0 1\n" for x, y, z in 0.5 * points)
    out = subprocess.run(["rtrace", "-h", "-I+", "-ab", "0", "-ds", "0.002", "-dj", "0", "-dc", "1", "-dt", "0",
                          "lights.oct"], cwd=folder, env=env, input=rays, capture_output=True, text=True, check=True)
    ref = 179.0 * np.array(out.stdout.split(), float).reshape(-1, 3) @ np.array([0.265, 0.670, 0.065])
    ours = api.measure_illuminance(points, method="analytic")
    assert all(r.exact for r in ours)
    for p, r, e in zip(points, ours, ref):
        print(f"lights at {p}: Radiometer {r.illuminance:.6g} lx, Radiance {e:.6g} lx ({r.illuminance / e - 1:+.2e})")
        assert r.illuminance == pytest.approx(e, rel=0.005 + error)


def _material(name, kind, **inputs):
    from radiometer.measure.blender.materials import shader_material

    m, node = shader_material(name, kind, inputs)
    return m, m.node_tree, node


def test_materials_are_mapped_or_listed(clean_blender, build, tmp_path):
    """Principled dielectric -> plastic with the Fresnel reflectance of its IOR and roughness^2; Metallic 1
    -> metal; Glossy -> metal; a textured Diffuse -> grey plastic 0.5, listed with its name; an emitting
    plane -> light of its radiance x K / 179."""
    scene = bpy.context.scene
    build.black_world(scene)
    specs = {"paint": ("ShaderNodeBsdfPrincipled", {"Base Color": (0.6, 0.5, 0.4, 1), "Roughness": 0.3, "IOR": 1.5}),
             "steel": ("ShaderNodeBsdfPrincipled", {"Base Color": (0.7, 0.7, 0.7, 1), "Metallic": 1.0,
                                                    "Roughness": 0.2}),
             "chrome": ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9, 1), "Roughness": 0.1}),
             "wood": ("ShaderNodeBsdfDiffuse", {}),
             "lamp": ("ShaderNodeEmission", {"Color": (1, 1, 1, 1), "Strength": 10.0})}
    for k, (name, (kind, inputs)) in enumerate(specs.items()):
        plane = build.plane(scene, size=1.0, location=(2.0 * k, 0, 0), name=f"{name} plane")
        m, tree, node = _material(name, kind, **inputs)
        if name == "wood":
            tex = tree.nodes.new("ShaderNodeTexNoise")
            tree.links.new(tex.outputs["Color"], node.inputs["Color"])
        plane.data.materials.clear()
        plane.data.materials.append(m)
    result = api.export_radiance(str(tmp_path / "rad"))
    text = (tmp_path / "rad" / "scene.rad").read_text()

    def args(kind, name):
        block = text.split(f"void {kind} {name}\n", 1)[1].split("\n")
        return [float(v) for v in block[2].split()[1:]]

    f0 = ((1.5 - 1) / 2.5) ** 2
    assert args("plastic", "paint") == pytest.approx([0.6, 0.5, 0.4, f0, 0.09], abs=1e-6)
    assert args("metal", "steel") == pytest.approx([0.7, 0.7, 0.7, 1.0, 0.04], abs=1e-6)
    assert args("metal", "chrome") == pytest.approx([0.9, 0.9, 0.9, 1.0, 0.01], abs=1e-6)
    assert args("plastic", "wood") == pytest.approx([0.5, 0.5, 0.5, 0, 0])
    assert [u for u in result["unmapped"] if u.startswith("wood")] == [
        "wood (material): Diffuse BSDF with a linked Color (texture); written as grey plastic 0.5"]
    assert args("light", "lamp_plane__lamp__light0") == pytest.approx([10.0 * 683 / 179] * 3, rel=1e-6)
    assert "lamp plane [lamp]: emitting surface written as Radiance light" in "\n".join(result["unmapped"])
    assert "wood (material)" in (tmp_path / "rad" / "README.txt").read_text()

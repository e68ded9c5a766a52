"""Worlds (issue 14): the Environment Texture's orientation measured by rendering, world-lit readings
analytic vs rendered, world photometry and calibration.

Reference numbers: renders of a white Lambertian patch (tests/bpy/reference.py, independent of
Radiometer) or Radiometer's own render path; closed form E = pi L for a uniform world (FACTS.md).
"""

import importlib.util
import math
import pathlib

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.radiometry.skies import environment


def _load(name):
    spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")  # tests/bpy/reference.py: imports nothing from Radiometer


def env_world(scene, pixels, *, interpolation="Closest", strength=1.0, rotation=None):
    """World = Background <- Environment Texture of ``pixels`` (H, W, 3, top row first)."""
    h, w = pixels.shape[:2]
    img = bpy.data.images.new("env", w, h, float_buffer=True, alpha=False)
    rgba = np.concatenate([pixels, np.ones((h, w, 1))], axis=-1)[::-1].astype(np.float32)
    img.pixels.foreach_set(rgba.ravel())
    world = bpy.data.worlds.new("env")
    tree = ensure_node_tree(world)
    bg = tree.nodes["Background"]
    bg.inputs["Strength"].default_value = strength
    env = tree.nodes.new("ShaderNodeTexEnvironment")
    env.image, env.interpolation = img, interpolation
    tree.links.new(env.outputs["Color"], bg.inputs["Color"])
    if rotation is not None:
        mapping = tree.nodes.new("ShaderNodeMapping")
        coord = tree.nodes.new("ShaderNodeTexCoord")
        mapping.inputs["Rotation"].default_value = rotation
        tree.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
        tree.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    scene.world = world
    return world


def constant_world(scene, colour=(1.0, 1.0, 1.0), strength=1.0):
    world = bpy.data.worlds.new("const")
    bg = ensure_node_tree(world).nodes["Background"]
    bg.inputs["Color"].default_value = tuple(colour) + (1.0,)
    bg.inputs["Strength"].default_value = strength
    scene.world = world
    return world


def quarter_band(h=8, w=16):
    px = np.zeros((h, w, 3))
    px[:, w // 2: w // 2 + w // 4] = 1.0  # u in [1/2, 3/4)
    return px


def test_environment_texture_orientation_by_rendering(clean_blender):
    """MEASURED: the image's columns u in [1/2, 3/4) light a patch facing +X and one facing -Y
    equally and nothing facing -X or +Y (the centre column faces +X, u = 3/4 faces -Y); the top
    rows light +Z. The model (BLENDER_WORLD_ROTATION) predicts the same numbers."""
    scene = bpy.context.scene
    px = quarter_band()
    px[:2] += 0.5  # and the top rows, a little
    env_world(scene, px)
    world = api.world_model(scene)
    assert world.kind == "equirect" and world.exact
    for n in [(1, 0, 0), (0, -1, 0), (-1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 0, -1)]:
        e_ref, rel, _info = reference.reference_irradiance(scene, (0, 0, 0), n, target_rel_error=2e-3, max_seconds=20)
        e_model, _err = world.irradiance(n)
        se = max(rel * abs(e_ref[1]), 1e-9)
        assert abs(e_model[1] - e_ref[1]) < 3 * se + 1e-6, (n, e_model, e_ref, rel)
    # and the fact in words: +X and -Y see the band, -X and +Y do not
    e = {n: world.irradiance(n)[0][1] for n in [(1, 0, 0), (0, -1, 0), (-1, 0, 0), (0, 1, 0)]}
    assert e[(1, 0, 0)] == pytest.approx(e[(0, -1, 0)]) and e[(-1, 0, 0)] < 0.2 * e[(1, 0, 0)]


def test_mapping_rotation_is_followed(clean_blender):
    """A Mapping node rotating 90 deg about Z: the rendered patch and the model agree."""
    scene = bpy.context.scene
    env_world(scene, quarter_band(), rotation=(0.0, 0.0, math.pi / 2))
    world = api.world_model(scene)
    assert world.kind == "equirect"
    for n in [(1, 0, 0), (0, 1, 0), (0, -1, 0)]:
        e_ref, rel, _ = reference.reference_irradiance(scene, (0, 0, 0), n, target_rel_error=3e-3, max_seconds=20)
        e_model, _ = world.irradiance(n)
        assert abs(e_model[1] - e_ref[1]) < 3 * max(rel * abs(e_ref[1]), 1e-9) + 1e-6, (n, e_model, e_ref)


def test_uniform_world_reading_is_exact_and_analytic(clean_blender, build):
    scene = bpy.context.scene
    constant_world(scene, (0.5, 1.0, 2.0), strength=3.0)
    build.plane(scene, size=4.0, location=(0, 0, -0.5))  # below the meter's horizon: cannot matter
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1))
    assert r.method == "analytic" and r.exact
    assert np.allclose(r.irradiance_rgb, np.pi * 3.0 * np.array([0.5, 1.0, 2.0]), rtol=1e-12)
    assert "world" in r.parts["analytic"]


def test_geometry_above_the_horizon_makes_the_world_rendered(clean_blender, build):
    scene = bpy.context.scene
    constant_world(scene, strength=1.0)
    build.plane(scene, size=1.0, location=(0, 0, 1.0), albedo=0.0)  # a black 1 m roof 1 m above
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), quality="preview")
    assert r.method in ("render", "hybrid") and not r.exact
    assert any("world" in note for note in r.notes)
    # view factor of a centred a x a square at height c (4 corner rectangles, Howell's catalog B-3):
    # F = 4/(2 pi) * 2 * A/sqrt(1+A^2) * atan(A/sqrt(1+A^2)), A = a/(2c) = 0.5 -> 0.23945
    q = 0.5 / math.sqrt(1.25)
    view = 4 / (2 * math.pi) * 2 * q * math.atan(q)
    expected = math.pi * (1 - view)
    assert abs(r.irradiance - expected) < 3 * r.rel_std_error * r.irradiance + 1e-9


def hot_spot_map(h=32, w=64):
    """A dim sky plus a sun-like hot spot: one pixel 2000 x brighter, at 30 deg elevation."""
    px = np.full((h, w, 3), 0.05)
    px[h // 2:] = 0.01  # darker below the horizon
    px[h // 3 - 1, int(w * 0.6)] = (100.0, 90.0, 80.0)
    return px


@pytest.mark.parametrize("interpolation", ["Closest", "Linear"])
def test_hot_spot_world_analytic_agrees_with_render(clean_blender, interpolation):
    """World-lit readings: analytic (the image's pixels, or its bilinear interpolant) vs Cycles.

    The hot spot is ONE pixel of a 64 x 32 image (5.6 deg x 5.6 deg): the analytic integral uses the
    same pixels Cycles looks up, so the image resolution is not an approximation here; with Linear
    interpolation Cycles spreads it bilinearly, and the analytic value follows (the pixel sum would
    differ by the amount printed in the assertion message)."""
    scene = bpy.context.scene
    env_world(scene, hot_spot_map(), interpolation=interpolation)
    normals = [(0, 0, 1), (0.3, -0.8, 0.5), (-1, 0, 0.2)]
    analytic = api.measure_illuminance([(0, 0, 0)] * 3, normals)
    rendered = api.measure_illuminance([(0, 0, 0)] * 3, normals, method="render", target_rel_error=2e-3)
    world = api.world_model(scene)
    pixel_sum = world.irradiance if interpolation == "Closest" else None
    for a, r in zip(analytic, rendered):
        assert a.method == "analytic"
        assert a.exact == (interpolation == "Closest")
        se = r.rel_std_error * abs(r.irradiance)
        assert abs(a.irradiance - r.irradiance) < 3 * se, (a.irradiance, r.irradiance, se, pixel_sum)
    if interpolation == "Linear":
        plain = environment.irradiance(world.radiance, np.array(normals, float), world.rotation)[0]
        weights = np.array([0.2126, 0.7152, 0.0722])
        # the bilinear interpolant differs measurably from the pixel sum at the meter facing the spot
        diff = [abs(a.irradiance - float(p @ weights)) / a.irradiance for a, p in zip(analytic, plain)]
        assert max(diff) > 1e-4


def test_world_illuminance_brightest_and_calibration(clean_blender):
    scene = bpy.context.scene
    env_world(scene, hot_spot_map(), strength=2.0)
    info = api.world_illuminance(scene)
    assert info["method"] == "analytic"
    d = np.array(info["brightest_direction"])
    # the hot spot's pixel centre: row h/3 - 1, column 0.6 w (pixel directions of the model)
    dirs, _ = environment.pixel_directions(32, 64, environment.BLENDER_WORLD_ROTATION)
    assert np.allclose(d, dirs[32 // 3 - 1, int(64 * 0.6)])
    assert info["brightest_luminance"] == pytest.approx(683 * 2.0 * (0.2126 * 100 + 0.7152 * 90 + 0.0722 * 80), rel=1e-4)  # Rec.709 Y; the scene's weights differ by ~5e-6
    out = api.calibrate_world(scene, 10000.0)
    assert out["illuminance_after"] == pytest.approx(10000.0, rel=1e-6)  # the socket stores float32
    assert out["new_strength"] == pytest.approx(2.0 * 10000.0 / info["illuminance"], rel=1e-12)
    assert scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value == pytest.approx(
        out["new_strength"], rel=1e-6)
    # the render agrees with the calibrated value
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="render", target_rel_error=3e-3)
    assert abs(r.illuminance - 10000.0) < 3 * r.rel_std_error * r.illuminance
    with pytest.raises(api.RadiometerError):
        api.calibrate_world(scene, -5.0)


def test_sky_texture_is_rendered_and_said_so(clean_blender):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("sky")
    tree = ensure_node_tree(world)
    sky = tree.nodes.new("ShaderNodeTexSky")
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    scene.world = world
    model = api.world_model(scene)
    assert not model.modelled and "Sky Texture" in model.reason
    info = api.world_illuminance(scene)
    assert info["method"] == "render" and info["illuminance"] > 0
    assert any("Sky Texture" in n for n in info["notes"])
    assert len(bpy.data.scenes) == 1  # the temporary scene is gone


def test_irradiance_map_of_the_world_and_of_a_radiance_map(clean_blender, tmp_path):
    from radiometer.measure.blender import exr

    scene = bpy.context.scene
    constant_world(scene, (1.0, 1.0, 1.0), strength=0.5)
    out = api.irradiance_environment_map("world", str(tmp_path / "irr.exr"), resolution=(16, 8))
    img = exr.read_rgb(out["path"])
    assert img.shape == (8, 16, 3) and np.allclose(img, math.pi * 0.5, rtol=1e-6)
    assert out["coefficients"]["L00"][0] == pytest.approx(0.5 * math.sqrt(4 * math.pi), rel=1e-9)
    m = api.capture_radiance_map((0, 0, 0), str(tmp_path / "rad.exr"), resolution=16, quality="preview")
    out2 = api.irradiance_environment_map(m, str(tmp_path / "irr2.exr"), method="sh9", resolution=(8, 4))
    assert np.allclose(exr.read_rgb(out2["path"]), math.pi * 0.5, rtol=1e-4)
    with pytest.raises(api.RadiometerError):
        api.irradiance_environment_map("world", str(tmp_path / "nope" / "x.exr"))


def test_unit_scale_divides_the_world_by_scale_squared(clean_blender):
    """README "Conventions": a world's radiance is per scene unit^2 (as Cycles renders it)."""
    scene = bpy.context.scene
    constant_world(scene, strength=1.0)
    scene.unit_settings.scale_length = 0.5
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1))
    assert r.exact and r.irradiance == pytest.approx(math.pi / 0.25, rel=1e-12)
    assert api.world_illuminance(scene)["irradiance"] == pytest.approx(math.pi / 0.25, rel=1e-12)


def test_calibrate_operator_is_undoable_and_panel_registers(clean_blender):
    scene = bpy.context.scene
    constant_world(scene, strength=1.0)
    assert hasattr(bpy.types, "RADIOMETER_PT_world")
    assert "UNDO" in bpy.types.RADIOMETER_OT_calibrate_world.bl_options
    assert bpy.ops.radiometer.calibrate_world(illuminance=683.0 * math.pi * 3.0) == {"FINISHED"}
    strength = scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value
    assert strength == pytest.approx(3.0, rel=1e-6)  # 683 lm/W x pi x 3 W/m^2 -> strength 3 for white
    assert bpy.ops.radiometer.world_illuminance() == {"FINISHED"}
    assert bpy.ops.radiometer.world_irradiance_map() == {"FINISHED"}
    assert any(img.name.endswith("_irradiance.exr") for img in bpy.data.images)


def test_cli_world_calibrates_and_writes_the_map(clean_blender, tmp_path, capsys):
    from radiometer import cli
    from radiometer.measure.blender import exr

    scene = bpy.context.scene
    env_world(scene, hot_spot_map(), strength=1.0)
    blend = tmp_path / "w.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    before = blend.read_bytes()
    out = tmp_path / "irr.exr"
    calibrated = tmp_path / "calibrated.blend"
    assert cli._blender_cli(["world", "--calibrate", "20000", "--out", str(calibrated),
                             "--irradiance-map", str(out)]) == 0
    text = capsys.readouterr().out
    assert "20000 lx" in text and "L00" in text and f"saved the calibrated scene to {calibrated}" in text
    assert exr.read_rgb(str(out)).shape == (32, 64, 3)
    # nothing else beside the outputs: no temp file, no .blend1 backup of one (measure.blender.blend_file.save_copy)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["calibrated.blend", "irr.exr", "w.blend"]
    assert api.world_illuminance(scene)["illuminance"] == pytest.approx(20000.0, rel=1e-6)
    # the input is untouched, the session still names it, and the new file holds the calibration
    assert blend.read_bytes() == before and bpy.data.filepath == str(blend)
    strength = scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value
    bpy.ops.wm.open_mainfile(filepath=str(calibrated))  # (the generated map is not saved: compare the strength)
    assert bpy.context.scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value == strength != 1.0
    bpy.ops.wm.open_mainfile(filepath=str(blend))
    for argv, word in ((["world", "--calibrate", "-3"], "--calibrate"),
                       (["world", "--calibrate", "100", "--out", str(blend)], "input"),
                       (["world", "--out", str(tmp_path / "x.blend")], "--calibrate")):
        assert cli._blender_cli(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and word in err and "Traceback" not in err, err
    assert blend.read_bytes() == before and not (tmp_path / "x.blend").exists()
    # without --out: calibrated in this run only, and it says so
    env_world(bpy.context.scene, hot_spot_map(), strength=1.0)  # (the reopened file lost the generated map)
    assert cli._blender_cli(["world", "--calibrate", "1000"]) == 0
    assert "--out FILE.blend saves" in capsys.readouterr().out and blend.read_bytes() == before


def smooth_map(h=32, w=64):
    """A smooth world: L = 1 + 0.5 (d . a) + 0.4 (d . b)^2 at the pixel centres (Environment Texture frame)."""
    dirs, _ = environment.pixel_directions(h, w, environment.BLENDER_WORLD_ROTATION)
    a, b = np.array([0.6, -0.3, 0.74]), np.array([0.0, 0.8, -0.6])
    value = 1 + 0.5 * dirs @ (a / np.linalg.norm(a)) + 0.4 * (dirs @ b) ** 2
    return np.stack([value, 0.8 * value, 0.6 * value], axis=-1)


def test_mirror_ball_probe_render_and_its_resolution_loss(clean_blender):
    """The lecture's capture: a chrome ball rendered in the world, converted to the equirect map.

    The rendered ball matches the ideal mirror-ball mapping (environment.equirect_to_probe); the
    map recovered from it is accurate where the ball shows the world well (directions towards the
    camera) and loses resolution towards the direction behind the ball, which the ball squeezes
    into its rim: angular pixel size 4 / (S cos(theta / 2)) rad for a ball S pixels wide, theta
    measured from the direction towards the camera."""
    from radiometer.measure.authoring import world as world_module

    scene = bpy.context.scene
    px = smooth_map()
    env_world(scene, px)
    h, w = px.shape[:2]
    dirs, solid = environment.pixel_directions(h, w, environment.BLENDER_WORLD_ROTATION)
    errors = {}
    for size in (64, 256):
        probe, cam = world_module.render_mirror_ball(scene, size=size, samples=1)
        ideal = environment.equirect_to_probe(px, size, environment.BLENDER_WORLD_ROTATION, cam)
        inside = environment.probe_to_directions(size)[1]
        rel = np.abs(probe - ideal)[inside][:, 0] / ideal[inside][:, 0]
        assert np.percentile(rel, 90) < 0.05, np.percentile(rel, [50, 90, 99])
        back = environment.probe_to_equirect(probe, (h, w), environment.BLENDER_WORLD_ROTATION, cam)
        theta = np.degrees(np.arccos(np.clip(dirs @ cam[:, 2], -1, 1)))  # from the direction towards the camera
        err = np.abs(back[..., 0] - px[..., 0]) / px[..., 0]
        errors[size] = {zone: float(np.sum((solid * err)[(theta >= lo) & (theta < hi)])
                                    / np.sum(solid[(theta >= lo) & (theta < hi)]))
                        for zone, (lo, hi) in {"front": (0, 90), "side": (90, 150), "back": (150, 181)}.items()}
    print("mean relative error of the map recovered from the ball, by zone:", errors)
    assert errors[256]["front"] < 0.01
    assert errors[256]["back"] > 2 * errors[256]["front"]  # the rim's resolution loss
    assert errors[256]["side"] <= errors[64]["side"]
    assert len(bpy.data.scenes) == 1 and not bpy.data.objects
    assert not bpy.data.meshes and not bpy.data.cameras and not bpy.data.materials  # the rig is gone too

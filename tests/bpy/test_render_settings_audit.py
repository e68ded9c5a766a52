"""Audit of render settings: a user's setting must not change what Radiometer measures.

Each test sets one of the user's render settings to a harmful value and checks the reading against an
independent reference: a closed form, or the same scene measured with Cycles' defaults. Every
harmful value here was measured to change a reading before ``render_settings.apply`` /
``sensors.run_bake`` overrode it (the numbers are in the comments of those functions).
"""

import math
import os

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.measure.meter import point_meter as meter
from radiometer.measure.render import render_settings, sensors
from radiometer.measure.blender import scene_guard


def _area(scene, build, z, energy=50.0, size=0.5):
    return build.light(scene, "AREA", (0.0, 0.0, z), energy=energy, size=size)


def _square_irradiance(radiance, half, h):
    """E at distance h on the axis of a square Lambertian emitter of half-side ``half`` (facing it)."""
    x = half / h
    term = x / math.sqrt(1 + x * x) * math.atan(x / math.sqrt(1 + x * x))
    return radiance * 4 * term  # Lambert's polygon formula, four symmetric edges


def _emitter(scene, strength=2.5, size=2.0, name="emitter", collection=None):
    h = size / 2
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    em = tree.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = strength
    tree.links.new(em.outputs["Emission"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    (collection or scene.collection).objects.link(obj)
    return obj


def _close(reading, expected, k=4.0, floor=1e-6):
    """|reading - expected| within k standard errors (plus float32 rounding)."""
    tol = k * reading.rel_std_error * abs(reading.irradiance) + floor * abs(expected)
    return abs(reading.irradiance - expected) <= tol


# --- lights are transparent (transparent_max_bounces) ----------------------------------------------

@pytest.mark.parametrize("user_value", [0, 8])
def test_light_behind_a_light_reaches_the_meter(clean_blender, build, user_value):
    """Two area lights stacked on the meter's axis: the far one is seen through the near one."""
    scene = bpy.context.scene
    build.black_world(scene)
    _area(scene, build, 2.0)
    _area(scene, build, 3.0)  # completely hidden behind the nearer light, seen only through it
    scene.cycles.transparent_max_bounces = user_value
    closed = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="analytic").irradiance
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    assert r.rel_std_error < 2e-3
    assert _close(r, closed), (r.irradiance, closed)


def test_luminance_meter_sees_both_stacked_lights(clean_blender, build):
    """Looking up through a 0.5 m area light at a second one behind it: L = 2 P / (pi A)."""
    scene = bpy.context.scene
    build.black_world(scene)
    _area(scene, build, 2.0)
    _area(scene, build, 3.0)
    r = api.measure_luminance((0, 0, 1.0), (0, 0, 1), acceptance_deg=2.0, scene=scene, quality="preview")
    assert r.radiance == pytest.approx(2 * 50.0 / (math.pi * 0.25), rel=1e-4)


# --- film, pixel filter, output file ----------------------------------------------------------------

def test_film_exposure_does_not_scale_a_bake(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2.0), energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=0.2, location=(5, 5, 0))  # some geometry so auto/render bakes
    scene.cycles.film_exposure = 4.0
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    assert _close(r, 100.0 / (4 * math.pi) / 1.0 ** 2, floor=1e-5), r.irradiance


@pytest.mark.parametrize("setting", ["film_exposure", "stamp", "dwaa", "multiview", "use_solid", "holdout",
                                     "indirect_only", "material_override"])
def test_luminance_of_an_emitter_whatever_the_user_set(clean_blender, build, setting):
    """An emission of strength 2.5 has radiance 2.5 W/(m^2 sr), to float32 rounding."""
    scene = bpy.context.scene
    build.black_world(scene)
    if setting in ("holdout", "indirect_only"):
        coll = bpy.data.collections.new("c")
        scene.collection.children.link(coll)
        _emitter(scene, collection=coll)
        setattr(bpy.context.view_layer.layer_collection.children["c"], setting, True)
    else:
        _emitter(scene)
    if setting == "film_exposure":
        scene.cycles.film_exposure = 4.0
    elif setting == "stamp":  # "Burn Into Image": text drawn into the pixels
        scene.render.use_stamp = True
        scene.render.use_stamp_note = True
        scene.render.stamp_note_text = "XXXXXXXXXXXX"
        scene.render.stamp_font_size = 20
    elif setting == "dwaa":  # lossy EXR codec
        scene.render.image_settings.exr_codec = "DWAA"
    elif setting == "multiview":  # stereo: two offset cameras, two files
        scene.render.use_multiview = True
    elif setting == "use_solid":
        bpy.context.view_layer.use_solid = False
    elif setting == "material_override":
        bpy.context.view_layer.material_override = bpy.data.materials.new("grey")
    layer = bpy.context.view_layer
    r = api.measure_luminance((0, 0, 1.0), (0, 0, -1.0), acceptance_deg=1.0, scene=scene, quality="preview")
    assert r.radiance == pytest.approx(2.5, rel=1e-5)
    # The pointer overrides come back (the scene guard does not snapshot pointers).
    if setting == "material_override":
        assert layer.material_override is not None and layer.material_override.name == "grey"
    if setting in ("holdout", "indirect_only"):
        assert getattr(layer.layer_collection.children["c"], setting) is True


def test_pixel_filter_does_not_blur_the_radiance_map(clean_blender, build, tmp_path):
    """Map irradiance under a 2 m emitting square 1 m away: Lambert's polygon formula."""
    scene = bpy.context.scene
    build.black_world(scene)
    _emitter(scene)
    scene.cycles.pixel_filter_type = "GAUSSIAN"
    scene.cycles.filter_width = 20.0
    m = api.capture_radiance_map((0, 0, 1.0), str(tmp_path / "map.exr"), resolution=32, scene=scene,
                                 quality="preview")
    closed = _square_irradiance(2.5, 1.0, 1.0)
    # The map's own discretisation error at 64 x 32 px is 0.03 %; the 20 px filter gave -1 %.
    assert m.irradiance_for((0, 0, -1))[1] == pytest.approx(closed, rel=3e-3)


# --- the view layer ---------------------------------------------------------------------------------

def _white_world(scene, strength=1.0):
    world = bpy.data.worlds.new("white")
    bg = ensure_node_tree(world).nodes["Background"]
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs["Strength"].default_value = strength
    scene.world = world
    return world


@pytest.mark.parametrize("setting", ["use_sky", "world_override"])
def test_world_light_reaches_the_sensor(clean_blender, build, setting):
    """A uniform white sky of radiance L gives E = pi L on an upward meter (no geometry)."""
    scene = bpy.context.scene
    _white_world(scene, 1.0)
    if setting == "use_sky":
        bpy.context.view_layer.use_sky = False
    else:
        bpy.context.view_layer.world_override = _white_world(scene, 3.0)
        scene.world = bpy.data.worlds["white"]
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), scene=scene, method="render")
    assert _close(r, math.pi, floor=1e-5), r.irradiance
    if setting == "world_override":
        assert bpy.context.view_layer.world_override.name == "white.001"


def _noisy_room(scene, build):
    build.black_world(scene)
    build.light(scene, "AREA", (0.0, 0.0, 2.0), energy=200.0, size=1.0)
    build.plane(scene, size=6.0, albedo=0.8)


@pytest.mark.parametrize("setting", ["time_limit", "sample_subset", "layer_samples_bounded"])
def test_bake_uses_the_recorded_sample_count(clean_blender, build, setting):
    """Readings stated with N samples per texel have the error of N samples (the default run's)."""
    scene = bpy.context.scene
    _noisy_room(scene, build)
    ref = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    if setting == "time_limit":
        scene.cycles.time_limit = 1e-4
    elif setting == "sample_subset":
        scene.cycles.use_sample_subset = True
        scene.cycles.sample_subset_length = 2
    else:
        scene.cycles.use_layer_samples = "BOUNDED"
        bpy.context.view_layer.samples = 1
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    assert r.rel_std_error < 1.5 * ref.rel_std_error, (r.rel_std_error, ref.rel_std_error)
    assert abs(r.irradiance - ref.irradiance) < 4 * math.hypot(r.rel_std_error * r.irradiance,
                                                               ref.rel_std_error * ref.irradiance)


def test_view_layer_samples_do_not_override_camera_renders(clean_blender, build):
    """view_layer.samples = 1 made each luminance render use 1 sample instead of the recorded count."""
    scene = bpy.context.scene
    _noisy_room(scene, build)
    args = dict(acceptance_deg=10.0, scene=scene, quality="preview")
    ref = api.measure_luminance((0.3, 0, 1.0), (0, 0, -1), **args)
    bpy.context.view_layer.samples = 1
    r = api.measure_luminance((0.3, 0, 1.0), (0, 0, -1), **args)
    assert ref.rel_std_error > 0
    assert r.rel_std_error < 2.0 * ref.rel_std_error, (r.rel_std_error, ref.rel_std_error)


# --- sampling: unbiased, and texels independent ----------------------------------------------------

def _texel_estimates(scene, samples, texels=16, medium=False, seen=None):
    """Raw per-texel estimates (texels, texels) of one upward meter, with the measurement's settings
    (``medium``: those of a scene with a participating medium; ``seen``: a dict given the scrambling
    distance the bake ran with)."""
    layer = bpy.context.view_layer
    with scene_guard.preserved_scene(scene):
        needs = meter.capture_model(scene).needs
        render_settings.apply(scene, samples=samples, bounces=16, needs=dict(needs, volume=True) if medium else needs)
        if seen is not None:
            seen["scrambling_distance"] = scene.cycles.scrambling_distance
        est, _info = sensors.bake_irradiance(scene, layer, [(0, 0, 1.0)], [(0, 0, 1)], samples=samples,
                                             texels=texels)
    return est[:, 0, 1].reshape(texels, texels)


def _one_area_light(scene, build):
    build.black_world(scene)
    _area(scene, build, 2.0, size=1.5)
    return api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="analytic").irradiance


@pytest.mark.parametrize("setting", ["distance_0", "distance_0.1", "auto_distance"])
def test_texel_spread_gives_an_honest_error(clean_blender, build, setting):
    """Scrambling distance < 1 makes texels share samples: their spread no longer measures the error
    of their mean (distance 0.1, 4 samples: mean -6.6 % off with a stated error of 0.03 %)."""
    scene = bpy.context.scene
    closed = _one_area_light(scene, build)
    if setting == "distance_0":
        scene.cycles.scrambling_distance = 0.0
    elif setting == "distance_0.1":
        scene.cycles.scrambling_distance = 0.1
    else:
        scene.cycles.auto_scrambling_distance = True  # 0.05 * 4 / sqrt(4 samples) = 0.1
        scene.cycles.scrambling_distance = 0.05
    grid = _texel_estimates(scene, samples=4)
    se = grid.std(ddof=1) / math.sqrt(grid.size)
    assert abs(grid.mean() - closed) < 4 * se, (grid.mean(), closed, se)


@pytest.mark.parametrize("medium", [True, False])
def test_rotated_table_is_unbiased_with_independent_texels(clean_blender, build, medium):
    """Issue 18 (F2) with a medium, issue 32 without one (rare paths read through the fixed table were
    -0.82 z, 86 % coverage in the fin scene): the measurement rotates each texel's sample table by its own
    uniform shift (scrambling distance 1 - 2^-20): every sample is then uniform on the unit cube, so at 4
    samples, where a limited rotation (0.1) read -6.6 % stating 0.03 %, the texels' mean is the closed form
    within its batch-means error and neighbouring texels are uncorrelated."""
    scene = bpy.context.scene
    closed = _one_area_light(scene, build)
    seen = {}
    grid = _texel_estimates(scene, samples=4, texels=48, medium=medium, seen=seen)
    assert 0.999 < seen["scrambling_distance"] < 1.0 and seen["scrambling_distance"] == render_settings.ROTATED_TABLE
    assert scene.cycles.scrambling_distance == 1.0  # the user's value back
    se = grid.std(ddof=1) / math.sqrt(grid.size)
    assert abs(grid.mean() - closed) < 4 * se, (grid.mean(), closed, se)
    dev = grid - grid.mean()
    pairs = np.concatenate([(dev[:, 1:] * dev[:, :-1]).ravel(), (dev[1:, :] * dev[:-1, :]).ravel()])
    rho = pairs.mean() / dev.var()
    assert abs(rho) < 4 / math.sqrt(pairs.size), rho


@pytest.mark.parametrize("pattern", ["BLUE_NOISE", "AUTOMATIC"])
def test_neighbouring_texels_are_uncorrelated(clean_blender, build, pattern):
    """Blue noise (also what AUTOMATIC chose here) anti-correlates neighbours (measured rho ~ -0.1):
    batch means would then overstate the error. Tabulated Sobol: rho within noise of 0."""
    scene = bpy.context.scene
    _one_area_light(scene, build)
    scene.cycles.sampling_pattern = pattern
    dev = _texel_estimates(scene, samples=64, texels=48)
    dev = dev - dev.mean()
    pairs = np.concatenate([(dev[:, 1:] * dev[:, :-1]).ravel(), (dev[1:, :] * dev[:-1, :]).ravel()])
    rho = pairs.mean() / dev.var()
    assert abs(rho) < 4 / math.sqrt(pairs.size), rho


def test_path_guiding_is_off(clean_blender, build):
    """Guiding learns from other pixels (texels stop being independent); measured here it did not bias
    the reading but made its error 7x larger than the default's for the same recorded samples."""
    scene = bpy.context.scene
    build.black_world(scene)
    _area(scene, build, 2.0)
    build.light(scene, "POINT", (1.0, 0.5, 1.5), energy=30.0, shadow_soft_size=0.0)
    build.plane(scene, size=6.0, albedo=0.8)
    ref = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    scene.cycles.use_guiding = True
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    assert r.rel_std_error < 2 * ref.rel_std_error, (r.rel_std_error, ref.rel_std_error)


@pytest.mark.parametrize("setting", ["light_tree_off", "min_light_bounces"])
def test_user_sampling_choices_that_are_unbiased(clean_blender, build, setting):
    """The light tree and the roulette start change variance only: kept as the user set them, and
    the reading still agrees with the closed form (stacked lights, a point light, a floor)."""
    scene = bpy.context.scene
    build.black_world(scene)
    _area(scene, build, 2.0)
    _area(scene, build, 3.0)
    build.light(scene, "POINT", (1.0, 0.5, 1.5), energy=30.0, shadow_soft_size=0.0)
    build.plane(scene, size=6.0, albedo=0.8)  # below the upward meter
    if setting == "light_tree_off":
        scene.cycles.use_light_tree = False
    else:
        scene.cycles.min_light_bounces = 10
    closed = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="analytic").irradiance
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    assert _close(r, closed, floor=1e-5), (r.irradiance, closed, r.rel_std_error)


def test_fast_gi_does_not_replace_indirect_light(clean_blender, build):
    """A downward meter sees only light reflected by the floor; fast GI turned it into 0."""
    scene = bpy.context.scene
    _noisy_room(scene, build)
    ref = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    scene.cycles.use_fast_gi = True
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    assert ref.irradiance > 1.0
    assert abs(r.irradiance - ref.irradiance) < 4 * math.hypot(r.rel_std_error * r.irradiance,
                                                               ref.rel_std_error * ref.irradiance)


# --- bake operator options taken from the scene ----------------------------------------------------

@pytest.mark.parametrize("setting", ["selected_to_active", "save_external", "view_from_camera"])
def test_scene_bake_settings_are_not_used(clean_blender, build, setting):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2.0), energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=0.2, location=(5, 5, 0))
    bake = scene.render.bake
    if setting == "selected_to_active":
        bake.use_selected_to_active = True  # raised "No valid selected objects"
        bake.use_cage = True
        bake.cage_extrusion = 0.5
        bake.max_ray_distance = 0.01
    elif setting == "save_external":
        bake.save_mode = "EXTERNAL"
        bake.use_split_materials = True
    else:
        cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
        scene.collection.objects.link(cam)
        cam.location = (0, 0, 0.5)  # behind the upward sensor
        scene.camera = cam
        bake.view_from = "ACTIVE_CAMERA"
    before = scene_guard.scene_fingerprint(scene)
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, 1), scene=scene, method="render")
    assert _close(r, 100.0 / (4 * math.pi), floor=1e-5), r.irradiance
    assert scene_guard.scene_fingerprint(scene) == before


# --- the record ------------------------------------------------------------------------------------

def test_record_states_light_bounce_limits(clean_blender, build):
    """Per-light max bounces are the user's light definition: kept, and stated in the record."""
    scene = bpy.context.scene
    _noisy_room(scene, build)
    light = next(ob for ob in scene.objects if ob.type == "LIGHT")
    ref = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    assert ref.render_settings["bounce_limited_lights"] == []
    light.data.cycles.max_bounces = 0
    r = api.measure_illuminance((0, 0, 1.0), (0, 0, -1), scene=scene, method="render", quality="preview")
    assert r.render_settings["bounce_limited_lights"] == [light.name]
    assert r.render_settings["transparent_bounces"] == 1024
    # Only light reflected by the floor reaches a downward meter, and the limit cuts (most of) it.
    assert r.irradiance < 0.05 * ref.irradiance
    assert light.data.cycles.max_bounces == 0

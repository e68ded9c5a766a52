"""Luminance spot meter and radiance maps against closed forms (issue 3)."""

import math

import bmesh
import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.radiometry.skies import environment
from radiometer.compat import ensure_node_tree
from radiometer.measure.meter import camera


def emitter(scene, location, strength, size=1.0, rotation=(0.0, 0.0, 0.0), name="emitter", sphere=False):
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    if sphere:
        bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=size)
    else:
        bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=size / 2)
    bm.to_mesh(mesh)
    bm.free()
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    em = tree.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = strength
    tree.links.new(em.outputs["Emission"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.location, obj.rotation_euler = location, rotation
    scene.collection.objects.link(obj)
    return obj


def test_luminance_of_an_emitting_panel(clean_blender, build):
    """An emission shader of strength S renders radiance S W/(m^2 sr); luminance = 683 S (white)."""
    scene = bpy.context.scene
    build.black_world(scene)
    emitter(scene, (0.0, 0.0, 0.0), strength=2.5, size=2.0)
    r = api.measure_luminance((0.0, 0.0, 1.0), (0.0, 0.0, -1.0), acceptance_deg=1.0)
    assert r.radiance == pytest.approx(2.5, rel=1e-4)
    assert r.luminance == pytest.approx(683.0 * 2.5, rel=1e-4)


def test_luminance_of_a_lambertian_card_under_a_sun(clean_blender, build):
    """L = rho E / pi for a Lambertian reflector (the lecture's ideal diffuse reflection)."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "SUN", energy=3.0, angle=0.0)
    build.plane(scene, size=4.0, albedo=0.5)
    r = api.measure_luminance((0.3, 0.0, 1.0), (-0.3, 0.0, -1.0), acceptance_deg=2.0)
    expected = 0.5 * 3.0 / math.pi
    # Sun of angle 0 = delta light: the 1e-4 for delta-lit readings.
    assert r.radiance == pytest.approx(expected, rel=1e-4)


def test_delta_light_is_invisible_to_the_luminance_meter(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.0, 0.0, 0.0), energy=1000.0, shadow_soft_size=0.0)
    r = api.measure_luminance((0.0, 0.0, 2.0), (0.0, 0.0, -1.0))
    assert r.radiance == 0.0
    assert any("invisible" in note for note in r.notes)


@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, 0, -1)])
def test_radiance_map_directions(clean_blender, build, tmp_path, axis):
    """The brightest pixel of the map points at an emitting sphere placed along ``axis``."""
    scene = bpy.context.scene
    build.black_world(scene)
    emitter(scene, tuple(4.0 * np.array(axis, float)), strength=1.0, size=0.5, sphere=True)
    m = api.capture_radiance_map((0, 0, 0), str(tmp_path / "map.exr"), resolution=64)
    from radiometer.measure.blender import exr

    img = exr.read_rgb(m.path).mean(axis=2)
    dirs, _ = environment.pixel_directions(*img.shape, camera._PANO_ROTATION)
    centroid = np.einsum("hw,hwc->c", img, dirs)
    centroid /= np.linalg.norm(centroid)
    assert np.dot(centroid, axis) > 0.995


def test_radiance_map_of_uniform_sky_gives_pi_L(clean_blender, tmp_path):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("sky")
    ensure_node_tree(world).nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.7
    scene.world = world
    m = api.capture_radiance_map((0, 0, 0), str(tmp_path / "sky.exr"), resolution=32)
    # The pixel weights are exact (radiometry.skies.environment.irradiance): Cycles' noise is what is left.
    assert m.irradiance == pytest.approx(math.pi * 0.7, rel=1e-4)
    assert np.allclose(m.irradiance_for((1, 0, 0)), math.pi * 0.7, rtol=1e-4)
    assert any("CANNOT see delta lights" in n for n in m.notes)


def test_equirect_solid_angles_cover_the_sphere():
    _dirs, solid = environment.pixel_directions(16, 32)
    assert solid.sum() == pytest.approx(4 * math.pi, rel=1e-12)


def test_measure_operator_handles_every_meter_kind(clean_blender, monkeypatch, tmp_path):
    """One Measure covers illuminance, luminance and radiance-map meters and stores SI readings."""
    from radiometer.measure.meter import camera as camera_mod

    monkeypatch.setattr(camera_mod, "default_map_path", lambda name: str(tmp_path / f"{name}.exr"))
    scene = bpy.context.scene
    world = bpy.data.worlds.new("sky")
    from radiometer.compat import ensure_node_tree

    tree = ensure_node_tree(world)
    tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    scene.world = world
    scene.radiometer.quality = "preview"
    kinds = ("ILLUMINANCE", "LUMINANCE", "RADIANCE_MAP")
    for kind in kinds:
        bpy.ops.radiometer.add_meter(kind=kind)
    assert bpy.ops.radiometer.measure(only_selected=False) == {"FINISHED"}
    meters = {ob.radiometer_meter.kind: ob.radiometer_meter for ob in scene.objects if ob.radiometer_meter.is_meter}
    assert set(meters) == set(kinds) and all(m.has_reading for m in meters.values())
    # Uniform sky of radiance L: E = pi L (lecture), luminance = K L.
    ill = meters["ILLUMINANCE"]
    # (a uniform sky has zero variance under cosine sampling; FloatProperty stores float32)
    assert ill.value == pytest.approx(math.pi * 0.5, rel=max(3 * ill.rel_std_error, 1e-6))
    assert meters["LUMINANCE"].photometric == pytest.approx(683 * 0.5, rel=1e-4)
    assert meters["RADIANCE_MAP"].value == pytest.approx(math.pi * 0.5, rel=1e-4)
    assert meters["RADIANCE_MAP"].map_path.endswith(".exr")

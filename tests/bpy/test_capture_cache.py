"""The capture cache (issue 17): one capture per scene state, never a stale model.

Every reading here is a closed form (``method="analytic"``: point lights, no surface above the
meter), so the expected numbers are P / (4 pi r^2) (Blender's point light, FACTS.md) and a stale
model would show as the old number.
"""

import dataclasses
import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.measure.capture import capture_cache, scene_capture
from radiometer.measure.analyses import light_isolation
from radiometer.measure.meter import point_meter as meter

K = 683.0  # lm/W, the default efficacy; a white light's CIE Y weight is 1


def _lux(location=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 1.0)):
    return api.measure_illuminance(location, normal, method="analytic").illuminance


def _point_lux(power_w, distance_m):
    return K * power_w / (4.0 * math.pi * distance_m**2)


@pytest.fixture
def captures(monkeypatch):
    """Counts the real (probe-render) captures of the geometry, full or partial (``captures.partial``: the
    partial ones alone); ``captures.lights`` counts the lights-only ones, with a probe render or without
    (``captures.rereads``: those without, ``scene_capture.relight``, None when it declined)."""
    calls = _Calls()
    for name, where in (("capture", (calls,)), ("capture_partial", (calls, calls.partial)),
                        ("capture_lights", (calls.lights,)), ("relight", (calls.rereads,))):
        real = getattr(scene_capture, name)

        def counting(*args, _real=real, _where=where, _name=name, **kwargs):
            result = _real(*args, **kwargs)
            for target in _where:
                if result is not None:  # relight declined: the probe follows (counted there)
                    target.append(args)
            if _name == "relight" and result is not None:
                calls.lights.append(args)
            return result

        monkeypatch.setattr(scene_capture, name, counting)
    capture_cache.clear()
    return calls


class _Calls(list):
    def __init__(self):
        super().__init__()
        self.lights = []
        self.partial = []
        self.rereads = []


def test_unchanged_scene_is_captured_once_and_an_edit_is_seen(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    assert _lux() == pytest.approx(_point_lux(100.0, 2.0), rel=1e-7)
    assert _lux() == pytest.approx(_point_lux(100.0, 2.0), rel=1e-7)
    assert len(captures) == 1  # the second reading reused the capture
    lamp.data.energy = 250.0
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    lamp.location.z = 4.0
    assert _lux() == pytest.approx(_point_lux(250.0, 4.0), rel=1e-7)
    # Lights-only edits: the lights were read again (twice), the geometry kept from the one full capture;
    # both (a light's data, a light moved) without a probe render.
    assert len(captures) == 1 and len(captures.lights) == 2 and len(captures.rereads) == 2


def test_edits_blender_does_not_announce_are_still_seen(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    hidden = bpy.data.collections.new("off in viewports")
    scene.collection.children.link(hidden)
    hidden.hide_viewport = True  # not in the viewport's depsgraph, still rendered
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 1.0), energy=10.0, shadow_soft_size=0.0)
    scene.collection.objects.unlink(lamp)
    hidden.objects.link(lamp)
    panel = build.light(scene, "AREA", location=(0.0, 0.0, 3.0), energy=50.0, size=0.5)  # faces down (-Z)
    before = _lux()
    assert before > 1.5 * _point_lux(10.0, 1.0)  # the panel adds a good share
    lamp.data.energy = 20.0
    after_lamp = _lux()
    assert after_lamp - before == pytest.approx(_point_lux(10.0, 1.0), rel=1e-6)
    panel.data.cycles.is_portal = True  # a Python-defined Cycles property: fires no depsgraph update
    assert _lux() == pytest.approx(_point_lux(20.0, 1.0), rel=1e-7)
    panel.data.cycles.is_portal = False
    assert _lux() == pytest.approx(after_lamp, rel=1e-9)
    scene.unit_settings.scale_length = 2.0  # 1 scene unit = 2 m: the lamp is 2 m away
    assert _lux() == pytest.approx((after_lamp - _point_lux(20.0, 1.0)) / 4 + _point_lux(20.0, 2.0), rel=1e-6)


def test_ies_text_edit_is_seen(clean_blender, build, captures, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    v = np.arange(0.0, 180.0 + 1e-9, 10.0)

    def ies(candela):
        return "\n".join(["IESNA:LM-63-2002", "TILT=NONE", f"1 -1 1 {v.size} 1 1 2 0 0 0", "1 1 10",
                          " ".join(f"{x:g}" for x in v), "0", " ".join(f"{candela:g}" for _ in v)]) + "\n"

    path = tmp_path / "iso.ies"
    path.write_text(ies(100.0))
    obj = api.import_luminaire(str(path), location=(0.0, 0.0, 2.0))
    first = _lux()
    assert first == pytest.approx(100.0 / 4.0, rel=1e-6)  # I / r^2, lux
    text = next(node.ies for node in obj.data.node_tree.nodes if node.bl_idname == "ShaderNodeTexIES")
    text.from_string(ies(300.0))  # editing a text data-block fires no depsgraph update
    assert _lux() == pytest.approx(300.0 / 4.0, rel=1e-6)


def test_world_image_pixels_are_read_again(clean_blender, captures):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("image world")
    scene.world = world
    tree = ensure_node_tree(world)  # Blender 4.5 gives a new world no tree until use_nodes is set
    image = bpy.data.images.new("sky", 8, 4, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(np.ones(8 * 4 * 4, np.float32))
    texture = tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image, texture.interpolation = image, "Closest"
    tree.links.new(texture.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    first = _lux()
    assert first == pytest.approx(K * math.pi, rel=1e-6)  # uniform radiance 1: E = pi L
    image.pixels.foreach_set(np.full(8 * 4 * 4, 2.0, np.float32))  # pixels fire no depsgraph update
    assert _lux() == pytest.approx(2.0 * K * math.pi, rel=1e-6)


def test_inverse_square_check_captures_the_unchanged_scene_once(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 3.0), rotation=(0.0, 0.0, 0.0), energy=100.0,
                shadow_soft_size=0.0)
    result = api.check_inverse_square("point", method="analytic", distances=[0.5, 1.0, 2.0])
    assert result is not None
    # The whole scene once (light, free space, the lights to switch off), the isolated scene once: it
    # was 4 (light_spec, free_distance, rendering_light_objects, then the measurement). The isolated
    # scene has the same geometry: only its lights are read again (issue 17).
    assert len(captures) == 1 and len(captures.lights) == 1


def test_rendered_inverse_square_check_captures_twice(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 3.0), energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=8.0, location=(0.0, 0.0, -0.5), albedo=0.5)  # reflects: the total is rendered
    result = api.check_inverse_square("point", method="render", samples=16, distances=[0.5, 1.0, 2.0])
    assert result.method == "render" and result.direct_method == "analytic"  # two measurements, one model
    # The scene, then the light alone once for both the total and its direct light (was 5 in all); the
    # light alone keeps the scene's geometry, its lights are read again (issue 17).
    assert len(captures) == 1 and len(captures.lights) == 1


def test_model_is_a_copy_with_shared_geometry(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=10.0)
    build.plane(scene, size=4.0)
    a = meter.capture_model(scene, bpy.context.view_layer)
    a.lights.clear()
    a.needs["geometry"] = False
    b = meter.capture_model(scene, bpy.context.view_layer)
    assert len(captures) == 1 and len(b.lights) == 1 and b.needs["geometry"]
    assert b.geometry is a.geometry


def test_other_scene_and_frame_are_their_own_entries(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 1.0), energy=10.0, shadow_soft_size=0.0)
    lamp.keyframe_insert("location", frame=1)
    lamp.location.z = 2.0
    lamp.keyframe_insert("location", frame=2)
    scene.frame_set(1)
    assert _lux() == pytest.approx(_point_lux(10.0, 1.0), rel=1e-7)
    scene.frame_set(2)
    assert _lux() == pytest.approx(_point_lux(10.0, 2.0), rel=1e-7)
    other = bpy.data.scenes.new("other")
    build.black_world(other)
    build.light(other, "POINT", location=(0.0, 0.0, 0.5), energy=10.0, shadow_soft_size=0.0)
    reading = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="analytic", scene=other)
    assert reading.illuminance == pytest.approx(_point_lux(10.0, 0.5), rel=1e-7)
    assert light_isolation.scene_model(scene).lights[0].spec.position[2] == pytest.approx(2.0)


def test_a_driver_reading_a_custom_property_is_followed(clean_blender, build, captures):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    lamp["power"] = 100.0
    driver = lamp.data.driver_add("energy").driver
    driver.type = "SCRIPTED"
    variable = driver.variables.new()
    variable.name = "p"
    variable.targets[0].id_type, variable.targets[0].id = "OBJECT", lamp
    variable.targets[0].data_path = '["power"]'
    driver.expression = "p"
    assert _lux() == pytest.approx(_point_lux(100.0, 2.0), rel=1e-7)
    lamp["power"] = 300.0  # a custom property: Blender announces no update, the render reads the new value
    assert _lux() == pytest.approx(_point_lux(300.0, 2.0), rel=1e-7)
    assert len(captures) == 2  # an animated scene is captured every time


def test_render_only_settings_are_followed(clean_blender, captures):
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_cube_add()
    subdivision = bpy.context.active_object.modifiers.new("subdivision", "SUBSURF")
    subdivision.levels = subdivision.render_levels = 1
    layer = bpy.context.view_layer
    assert meter.capture_model(scene, layer).geometry.count == 6 * 4 * 2  # the render's level: 1
    assert meter.capture_model(scene, layer).geometry.count == 48 and len(captures) == 1
    subdivision.render_levels = 2  # only the render sees it: Blender announces no update
    assert meter.capture_model(scene, layer).geometry.count == 6 * 16 * 2
    assert len(captures) == 2


def _rendered_scene(build):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=6.0, location=(0.0, 0.0, 3.0), rotation=(math.pi, 0.0, 0.0), albedo=0.5)
    return lamp


def _render(**kwargs):
    return api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), method="render", samples=16, **kwargs)


def test_a_measurement_keeps_its_capture_for_the_next_call(clean_blender, build, captures):
    _rendered_scene(build)
    restamps = capture_cache.stats()["restamps"]
    first, second = _render(), _render(seed=1)
    assert len(captures) == 1  # the bakes changed the scene and restored it: the capture stays valid
    assert capture_cache.stats()["restamps"] == restamps + 2
    assert second.irradiance == pytest.approx(first.irradiance, rel=0.2)


def test_a_callback_that_edits_the_scene_spoils_the_capture(clean_blender, build, captures):
    lamp = _rendered_scene(build)
    scene, layer = bpy.context.scene, bpy.context.view_layer

    def power():
        return float(np.sum(meter.capture_model(scene, layer).lights[0].spec.rgb_power))

    def progress(done, total, seconds_left=None):
        lamp.data.energy = 300.0  # a user's callback editing the scene mid-measurement

    at_100 = power()  # capture 1
    _render(progress=progress)  # served from capture 1; the callback's edit spoils it
    at_300 = power()  # capture 2
    assert at_300 == pytest.approx(3.0 * at_100, rel=1e-12) and len(captures) == 2
    before = power()  # a hit
    moved = []

    def cancelled():
        if not moved:
            lamp.location.z = 1.0
            moved.append(True)
        return False

    _render(cancelled=cancelled)  # served from capture 2, then spoiled by the callback
    assert meter.capture_model(scene, layer).lights[0].spec.position[2] == pytest.approx(1.0)  # capture 3
    assert len(captures) == 3 and power() == pytest.approx(before)


def test_a_failed_measurement_does_not_keep_its_capture(clean_blender, build, captures):
    _rendered_scene(build)
    from radiometer.errors import MeasurementCancelled

    with pytest.raises(MeasurementCancelled):
        _render(cancelled=lambda: True)
    hits = capture_cache.stats()["hits"]
    _render()
    # Not served as it was: read again (the cancelled run changed only settings, which it restored, so
    # the render's instances are the same and only the lights are read again).
    assert capture_cache.stats()["hits"] == hits and len(captures) + len(captures.lights) == 2



def _shadow_only_plane(build, scene, size, z, name):
    """A plane that only casts shadows (reflects nothing: no indirect light), so readings stay closed forms."""
    plane = build.plane(scene, size=size, location=(0.0, 0.0, z), name=name)
    plane.visible_diffuse = plane.visible_glossy = plane.visible_transmission = False
    return plane


def test_lights_only_edits_keep_the_geometry_and_geometry_edits_are_captured(clean_blender, build, captures):
    scene, layer = bpy.context.scene, bpy.context.view_layer
    world = build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    floor = _shadow_only_plane(build, scene, 4.0, -1.0, "floor")  # below the meter: blocks nothing
    empty = bpy.data.objects.new("an empty", None)
    scene.collection.objects.link(empty)
    assert _lux() == pytest.approx(_point_lux(100.0, 2.0), rel=1e-7)
    geometry = meter.capture_model(scene, layer).geometry
    lamp.data.energy = 250.0  # light data
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    lamp.location = (1.0, 0.0, 2.0)  # light moved: E = I cos / r^2
    assert _lux() == pytest.approx(_point_lux(250.0, math.sqrt(5.0)) * 2.0 / math.sqrt(5.0), rel=1e-7)
    lamp.location = (0.0, 0.0, 2.0)
    empty.location.x = 3.0  # an object the capture does not read (a meter writing its reading is one)
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 0.5  # the world: uniform, nothing above the horizon
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0) + K * math.pi * 0.5, rel=1e-6)
    model = meter.capture_model(scene, layer)
    assert model.world_emits and model.geometry is geometry and model.geometry.count == 2
    assert len(captures) == 1 and len(captures.lights) == 3
    background.inputs["Strength"].default_value = 0.0

    # Geometry edits: captured again, and the proofs see the new geometry.
    floor.location.z = 1.0  # now between the lamp and the meter: the lamp is blocked, exactly 0
    assert _lux() == pytest.approx(0.0, abs=1e-9)
    assert len(captures) == 2
    floor.location.z = -1.0
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    _shadow_only_plane(build, scene, 0.5, 1.5, "new occluder")  # an object added
    assert _lux() == pytest.approx(0.0, abs=1e-9)
    assert meter.capture_model(scene, layer).geometry.count == 4
    assert len(captures) == 4
    displace = floor.modifiers.new("lift", "DISPLACE")  # a modifier added, then changed
    displace.strength, displace.mid_level = 0.0, 0.0
    scene.objects["new occluder"].hide_render = True  # a visibility change: captured again too
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    displace.strength = 1.5  # the floor rises to z = 0.5: between the lamp and the meter
    assert _lux() == pytest.approx(0.0, abs=1e-9)
    assert len(captures) == 6 and len(captures.lights) == 3
    scene.objects["new occluder"].hide_render = False  # visibility alone: the render's instances differ
    displace.strength = 0.0
    assert _lux() == pytest.approx(0.0, abs=1e-9)  # the new occluder blocks the lamp again
    assert len(captures) == 7
    scene.objects["new occluder"].hide_render = True
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    assert len(captures) == 8
    lights = len(captures.lights)
    floor.visible_camera = False  # a flag the capture does not read (a visibility update): geometry kept
    scene.render.resolution_x = 123  # a scene setting: the same
    assert _lux() == pytest.approx(_point_lux(250.0, 2.0), rel=1e-7)
    assert len(captures) == 8 and len(captures.lights) == lights + 1


def test_a_light_edit_after_a_rendered_reading_keeps_the_geometry(clean_blender, build, captures):
    lamp = _rendered_scene(build)
    first = _render()
    lamp.data.energy = 300.0
    second = _render(seed=1)
    assert len(captures) == 1 and len(captures.lights) == 1  # the bake's own changes were restamped
    assert second.irradiance == pytest.approx(3.0 * first.irradiance, rel=0.2)


def _same(a, b):
    """Exact equality of two capture values (dataclasses, enums, arrays, containers) field by field."""
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(_same(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.array_equal(np.asarray(a), np.asarray(b))
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    return a == b


def _light_scene(build):
    """Point, spot (two objects share its data), area, sun, a point light instanced twice by a collection
    instance, and a shadow-only floor."""
    scene = bpy.context.scene
    build.black_world(scene)
    lamps = {"point": build.light(scene, "POINT", location=(0.3, 0.0, 2.0), energy=100.0),
             "spot": build.light(scene, "SPOT", location=(0.0, 1.0, 2.5), rotation=(0.3, 0.0, 0.0), energy=80.0,
                                 spot_size=1.0),
             "area": build.light(scene, "AREA", location=(-1.0, 0.0, 2.0), energy=60.0, size=0.5),
             "sun": build.light(scene, "SUN", rotation=(0.2, 0.1, 0.0), energy=2.0)}
    twin = bpy.data.objects.new("spot twin", lamps["spot"].data)
    twin.location = (1.0, -1.0, 2.5)
    scene.collection.objects.link(twin)
    group = bpy.data.collections.new("lamp group")  # not in the scene: rendered only through its instances
    build.light(scene, "POINT", location=(0.0, 0.0, 3.0), energy=40.0, name="grouped", collection=group)
    for x in (-2.0, 2.0):
        holder = bpy.data.objects.new(f"holder {x}", None)
        holder.instance_type, holder.instance_collection, holder.location = "COLLECTION", group, (x, 0.0, 0.0)
        scene.collection.objects.link(holder)
    _shadow_only_plane(build, scene, 4.0, -1.0, "floor")
    lamps["grouped"] = bpy.data.objects["grouped"]
    return scene, lamps


def test_light_edits_are_read_without_a_probe_and_equal_a_full_capture(clean_blender, build, captures):
    """Issue 17: after edits of lights alone (data, moves), ``scene_capture.relight`` replays the probe's
    light instances with their data and matrices read again: the model's lights, world and needs equal a
    full capture's (value for value), and no probe render ran; where relight cannot vouch for the render
    (an object's flags edited, an instanced light or one disabled in viewports moved) the probe runs."""
    scene, lamps = _light_scene(build)
    layer = bpy.context.view_layer

    def read_and_compare(fast, count=7):
        rereads = capture_cache.stats()["light_rereads"]
        model = capture_cache.capture(scene, layer)
        assert capture_cache.stats()["light_rereads"] == rereads + int(fast)
        full = scene_capture.capture(scene, layer)
        assert len(model.lights) == count
        assert _same(model.lights, full.lights)
        assert model.world_emits == full.world_emits and model.world_volume == full.world_volume
        assert _same(model.needs, full.needs)
        capture_cache.capture(scene, layer)  # the reference capture's own restore: a probe, stamped again
        return model

    read_and_compare(False)
    edits = [lambda: setattr(lamps["point"].data, "energy", 150.0),
             lambda: setattr(lamps["spot"].data, "color", (1.0, 0.5, 0.25)),  # two objects share it
             lambda: setattr(lamps["spot"].data, "spot_size", 0.7),
             lambda: setattr(lamps["area"].data, "shape", "ELLIPSE"),
             lambda: setattr(lamps["area"].data, "size", 0.8),
             lambda: setattr(lamps["sun"].data, "angle", 0.1),
             lambda: setattr(lamps["grouped"].data, "energy", 10.0),  # instanced twice
             lambda: setattr(lamps["point"].data, "use_shadow", False),  # the shadow flag of its visibility
             lambda: (setattr(lamps["point"].data, "use_temperature", True),
                      setattr(lamps["point"].data, "temperature", 3000.0)),
             lambda: setattr(lamps["point"].data, "type", "SPOT"),
             lambda: setattr(lamps["point"], "location", (0.5, -0.2, 1.8)),  # moved
             lambda: setattr(lamps["area"], "rotation_euler", (0.4, 0.1, 0.2)),  # turned
             lambda: (setattr(lamps["spot"], "location", (0.2, 0.8, 2.4)),  # moved and edited in one batch
                      setattr(lamps["spot"].data, "energy", 90.0))]
    for edit in edits:
        edit()
        read_and_compare(True)
    assert len(captures.rereads) == len(edits)
    lamps["grouped"].location.z = 2.5  # an instanced light moved: its instances' matrices are the render's
    read_and_compare(False)
    hidden = bpy.data.collections.new("off in viewports")
    bpy.context.scene.collection.children.link(hidden)
    hidden.hide_viewport = True  # a light there is rendered but its matrix is not evaluated in the viewport
    bpy.context.scene.collection.objects.unlink(lamps["sun"])
    hidden.objects.link(lamps["sun"])
    read_and_compare(False)
    lamps["sun"].rotation_euler.x = 0.5
    read_and_compare(False)
    # An object's flag edited together with its data (one batch): relight sees it and declines.
    lamps["area"].data.energy = 30.0
    lamps["area"].visible_glossy = False
    read_and_compare(False)
    lamps["area"].data.energy = 20.0
    lamps["area"].hide_render = True  # gone from the render: not replayed
    rereads = capture_cache.stats()["light_rereads"]
    assert len(capture_cache.capture(scene, layer).lights) == 6
    assert capture_cache.stats()["light_rereads"] == rereads
    assert len(captures.rereads) == len(edits)
    lamps["point"].location.x = 0.1  # the sun, disabled in viewports, still sends every light to the probe
    read_and_compare(False, count=6)
    hidden.objects.unlink(lamps["sun"])
    bpy.context.scene.collection.objects.link(lamps["sun"])
    read_and_compare(False, count=6)
    lamps["point"].location.x = 0.2  # relight again after the declines (their probes recorded afresh)
    read_and_compare(True, count=6)


def test_a_reading_after_a_light_data_edit_is_the_same_bit_for_bit(clean_blender, build, captures):
    """The same seed after a light-data edit: the reading through ``relight`` equals, field for field, the
    one through a full capture of the same scene (a Cycles-rendered part and closed forms)."""
    lamp = _rendered_scene(build)
    _render()
    lamp.data.energy = 300.0
    fast = _render(seed=5)
    assert len(captures.rereads) == 1 and len(captures) == 1
    capture_cache.clear()
    bpy.context.view_layer.update()
    full = _render(seed=5)
    assert len(captures) == 2
    a, b = dataclasses.asdict(fast), dataclasses.asdict(full)
    a.pop("seconds"), b.pop("seconds")
    assert a == b


def test_a_light_moved_is_read_right_for_a_view_layer_that_is_not_the_active_one(clean_blender, build, captures):
    """``relight`` takes a moved light's matrix from the capture's own view layer's depsgraph (Blender copies
    only the active depsgraph's evaluation back to the objects)."""
    scene, lamps = _light_scene(build)
    other = scene.view_layers.new("other layer")
    assert bpy.context.view_layer != other
    capture_cache.capture(scene, other)
    for k, location in enumerate([(0.7, 0.1, 1.5), (-0.4, 0.3, 2.2)]):
        lamps["point"].location = location
        rereads = capture_cache.stats()["light_rereads"]
        model = capture_cache.capture(scene, other)
        assert capture_cache.stats()["light_rereads"] == rereads + 1
        point = next(lt for lt in model.lights if lt.name == "point")
        assert np.allclose(point.spec.position, location, atol=1e-6)
        assert len(model.lights) == 7 and _same(model.lights, scene_capture.capture(scene, other).lights)
        capture_cache.capture(scene, other)  # the reference capture's restore: stamped again


def test_each_view_layer_is_captured_alone(clean_blender, build, captures):
    """The probe renders only the view layer asked for (Blender renders every enabled one, and the last
    one's capture used to be kept: the first layer read the second's lights), and the layers' render
    switches are given back."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=10.0, name="everywhere")
    only_first = bpy.data.collections.new("only in the first layer")
    scene.collection.children.link(only_first)
    build.light(scene, "POINT", location=(0.0, 0.0, 3.0), energy=10.0, name="first only", collection=only_first)
    first, other = scene.view_layers[0], scene.view_layers.new("other layer")
    other.layer_collection.children["only in the first layer"].exclude = True
    other.use = False  # a layer the user does not render: still captured when asked for
    for layer, names in ((first, {"everywhere", "first only"}), (other, {"everywhere"})):
        assert {lt.name for lt in scene_capture.capture(scene, layer).lights} == names
    assert [layer.use for layer in scene.view_layers] == [True, False]

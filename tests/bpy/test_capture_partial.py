"""Issue 17: after a geometry edit the capture reads again only what the edit may have reached
(``capture_cache`` -> ``scene_capture.capture_partial``), and the model equals a full capture's.

Each step edits the scene, takes the cached capture (a partial one), then a full capture with
``scene_capture.capture`` directly, and compares every array; the objects whose meshes were read are
counted (``scene_capture._mesh_triangles``). Readings are closed forms (a point light, shadow-only
geometry), so the proofs seeing the new geometry shows as 0 lx or P / (4 pi r^2) exactly.
"""

import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.measure.capture import capture_cache, scene_capture

K = 683.0  # lm/W, white light (FACTS.md)
_CUBE_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def _box(scene, name, location, half=0.2, collection=None):
    """A shadow-only box (reflects nothing, so readings stay closed forms)."""
    verts = [(x * half, y * half, z * half) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], _CUBE_FACES)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    obj.visible_diffuse = obj.visible_glossy = obj.visible_transmission = False
    (collection or scene.collection).objects.link(obj)
    return obj


def _assert_same(partial, full):
    a, b = partial.geometry, full.geometry
    assert a.object_names == b.object_names and a.object_ids == b.object_ids and a.unmodelled == b.unmodelled
    for name in ("triangles", "object_index", "casts_shadow", "opaque", "reflects", "emissive", "pane_of",
                 "tri_min", "tri_max"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert partial.needs == full.needs
    assert [light.source_id for light in partial.lights] == [light.source_id for light in full.lights]


@pytest.fixture
def reads(monkeypatch):
    """Names of the objects whose meshes a capture read (to_mesh), reset by ``reads.clear()``."""
    names = []
    real = scene_capture._mesh_triangles

    def counting(obj):
        names.append(obj.original.name)
        return real(obj)

    monkeypatch.setattr(scene_capture, "_mesh_triangles", counting)
    capture_cache.clear()
    return names


def _lux():
    return api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), method="analytic").illuminance


def test_partial_capture_equals_a_full_one_after_each_kind_of_geometry_edit(clean_blender, build, reads):
    scene, layer = bpy.context.scene, bpy.context.view_layer
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    floor = build.plane(scene, size=4.0, location=(0.0, 0.0, -1.0), name="floor")
    floor.visible_diffuse = floor.visible_glossy = floor.visible_transmission = False
    occluder = _box(scene, "occluder", (3.0, 0.0, 1.0))
    shaped = _box(scene, "shaped", (-3.0, 0.0, 1.0))
    subdivide = shaped.modifiers.new("smooth", "SUBSURF")
    subdivide.levels = subdivide.render_levels = 1
    kit = bpy.data.collections.new("kit")
    _box(scene, "kit box", (0.0, 3.0, 1.0), collection=kit)  # instanced only
    for k in range(2):
        instancer = bpy.data.objects.new(f"instancer {k}", None)
        instancer.instance_type, instancer.instance_collection = "COLLECTION", kit
        instancer.location = (k * 1.0, 0.0, 0.0)
        scene.collection.objects.link(instancer)
    hidden = _box(scene, "viewport-disabled", (0.0, -3.0, 1.0))
    hidden.hide_viewport = True  # rendered, but Blender reports no edit of it (measured)

    def step(expected_reads):
        before = capture_cache.stats()["partial_captures"]
        reads.clear()
        partial = capture_cache.capture(scene, layer)
        assert capture_cache.stats()["partial_captures"] == before + 1
        assert sorted(reads) == sorted(expected_reads)
        _assert_same(partial, scene_capture.capture(scene, layer))
        return partial

    partial_before = capture_cache.stats()["partial_captures"]
    full = capture_cache.capture(scene, layer)
    assert capture_cache.stats()["partial_captures"] == partial_before
    assert sorted(reads) == ["floor", "kit box", "occluder", "shaped", "viewport-disabled"]  # the kit box once
    assert full.geometry.count == 2 + 12 + 6 * 4 * 2 + 2 * 12 + 12  # floor, box, subdivided box, 2 instances, box
    occluder.location = (0.0, 0.0, 1.0)  # moved: transformed again, nothing read
    step(["viewport-disabled"])
    occluder.location.x = 3.0
    subdivide.levels = 2  # a modifier changed (the viewport's levels): that object alone
    step(["shaped", "viewport-disabled"])
    subdivide.render_levels = 2  # a render-only setting: fires nothing, found by its hash
    assert step(["shaped", "viewport-disabled"]).geometry.count > full.geometry.count
    added = _box(scene, "added", (0.0, 3.0, -0.5))  # added: read; the others kept
    step(["added", "viewport-disabled"])
    bpy.data.objects.remove(added)  # deleted
    step(["viewport-disabled"])
    mesh = kit.objects["kit box"].data  # the instanced collection's mesh edited: read once, both instances
    mesh.vertices[0].co.z -= 0.05
    mesh.update()
    step(["kit box", "viewport-disabled"])
    material = bpy.data.materials.new("tint")
    occluder.data.materials.append(material)  # a slot added: Blender reports the mesh changed
    step(["occluder", "viewport-disabled"])
    material.diffuse_color = (0.2, 0.3, 0.4, 1.0)  # a material edited: Blender reports its user changed too
    step(["occluder", "viewport-disabled"])
    hidden.location.z = 0.5  # announced by nothing: a partial capture still reads it
    occluder.location.x = 2.5
    assert not np.array_equal(full.geometry.triangles, step(["viewport-disabled"]).geometry.triangles)


def test_a_geometry_node_edit_captures_everything(clean_blender, build, reads):
    scene, layer = bpy.context.scene, bpy.context.view_layer
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    box = _box(scene, "box", (0.0, 0.0, 1.0))
    other = _box(scene, "other", (3.0, 0.0, 1.0))
    tree = bpy.data.node_groups.new("lift", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    group_in, group_out = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
    tree.links.new(group_in.outputs[0], group_out.inputs[0])
    box.modifiers.new("nodes", "NODES").node_group = tree
    capture_cache.capture(scene, layer)
    move = tree.nodes.new("GeometryNodeTransform")  # the tree edited: Blender reports the tree alone
    move.inputs["Translation"].default_value = (0.0, 0.0, 0.5)
    tree.links.new(group_in.outputs[0], move.inputs[0])
    tree.links.new(move.outputs[0], group_out.inputs[0])
    before = capture_cache.stats()["partial_captures"]
    reads.clear()
    model = capture_cache.capture(scene, layer)
    assert capture_cache.stats()["partial_captures"] == before and sorted(reads) == ["box", "other"]
    _assert_same(model, scene_capture.capture(scene, layer))
    assert other.name in model.geometry.object_names


def test_the_proofs_see_the_moved_occluder(clean_blender, build, reads):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    occluder = _box(scene, "occluder", (3.0, 0.0, 1.0))
    _box(scene, "still", (-3.0, 0.0, 1.0))
    clear = K * 100.0 / (4.0 * math.pi * 2.0**2)  # Blender's point light: I = P / (4 pi)
    assert _lux() == pytest.approx(clear, rel=1e-7)
    partial = capture_cache.stats()["partial_captures"]
    occluder.location.x = 0.0  # between the lamp and the meter: exactly blocked
    assert _lux() == pytest.approx(0.0, abs=1e-9)
    occluder.location.x = 3.0
    assert _lux() == pytest.approx(clear, rel=1e-7)
    assert capture_cache.stats()["partial_captures"] == partial + 2


def test_edits_of_an_object_disabled_in_viewports_are_seen(clean_blender, build, reads):
    """Blender reports no edit of an object disabled in viewports (measured: not even a call of the
    handler); its transform and mesh are part of the cache's render-only state, so the reading changes."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    hidden = _box(scene, "viewport-disabled", (3.0, 0.0, 1.0))
    hidden.hide_viewport = True
    _box(scene, "still", (-3.0, 0.0, 1.0))
    clear = K * 100.0 / (4.0 * math.pi * 2.0**2)
    assert _lux() == pytest.approx(clear, rel=1e-7)
    partial = capture_cache.stats()["partial_captures"]
    hidden.location.x = 0.0  # moved between the lamp and the meter
    reads.clear()
    assert _lux() == pytest.approx(0.0, abs=1e-9)
    assert reads == ["viewport-disabled"]
    for vertex in hidden.data.vertices:  # its mesh moved out of the way again, by its vertices
        vertex.co.x += 2.0
    hidden.data.update()
    assert _lux() == pytest.approx(clear, rel=1e-7)
    assert capture_cache.stats()["partial_captures"] == partial + 2


def test_only_images_that_can_move_vertices_count_as_geometry_edits(clean_blender):
    """A bake writes an image (Blender reports it); such an edit keeps the triangles unless a texture or a
    geometry node reads the image."""
    plain = bpy.data.images.new("baked", 4, 4, float_buffer=True)
    assert not capture_cache._image_feeds_geometry(plain)
    texture = bpy.data.textures.new("height", "IMAGE")
    texture.image = plain  # a Displace modifier could read it
    assert capture_cache._image_feeds_geometry(plain)
    other = bpy.data.images.new("nodes", 4, 4)
    tree = bpy.data.node_groups.new("sample", "GeometryNodeTree")
    node = tree.nodes.new("GeometryNodeImageTexture")
    assert not capture_cache._image_feeds_geometry(other)
    node.inputs["Image"].default_value = other
    assert capture_cache._image_feeds_geometry(other)


def _material(name, node, **inputs):
    from radiometer.compat import ensure_node_tree

    material = bpy.data.materials.new(name)
    tree = ensure_node_tree(material)
    tree.nodes.clear()
    shader = tree.nodes.new(node)
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    tree.links.new(shader.outputs[0], tree.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
    return material


def test_panes_and_emitting_surfaces_equal_a_full_capture_after_an_edit(clean_blender, build, reads):
    """Thin panes (by object index) and emissive meshes are read by the same walk: after an unrelated
    object moved, and after the pane itself moved, they equal a full capture's."""
    scene, layer = bpy.context.scene, bpy.context.view_layer
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    mover = _box(scene, "mover", (3.0, 0.0, 1.0))
    pane = build.plane(scene, size=1.0, location=(0.0, 0.0, 1.0), name="pane")
    pane.data.materials[0] = _material("glass", "ShaderNodeBsdfGlass", IOR=1.5)
    glow = build.plane(scene, size=0.5, location=(2.0, 2.0, 2.5), name="glow")
    glow.data.materials[0] = _material("glow", "ShaderNodeEmission", Strength=3.0)

    def same(partial, full):
        assert set(partial.panes) == set(full.panes) == {partial.geometry.object_names.index("pane")}
        for k, p in partial.panes.items():
            q = full.panes[k]
            assert (p.name, p.ior, p.thickness, p.source_id, p.slots) == (q.name, q.ior, q.thickness, q.source_id,
                                                                          q.slots)
            assert np.array_equal(p.geometry.heights, q.geometry.heights)
            assert np.array_equal(p.geometry.normal, q.geometry.normal)
        assert [m.name for m in partial.emissive_meshes] == [m.name for m in full.emissive_meshes]
        assert len(partial.emissive_meshes) == 1
        for m, n in zip(partial.emissive_meshes, full.emissive_meshes):
            assert np.array_equal(m.triangles, n.triangles) and np.array_equal(m.radiance, n.radiance)
            assert m.source_id == n.source_id
        for name in ("triangles", "object_index", "opaque", "emissive", "pane_of", "tri_min", "tri_max"):
            assert np.array_equal(getattr(partial.geometry, name), getattr(full.geometry, name)), name

    capture_cache.capture(scene, layer)
    for edit, expected in ((lambda: setattr(mover.location, "x", 2.5), []),
                           (lambda: setattr(pane.location, "z", 1.2), []),  # transformed again, not read
                           (lambda: setattr(glow.location, "x", 1.5), [])):
        edit()
        before = capture_cache.stats()["partial_captures"]
        reads.clear()
        partial = capture_cache.capture(scene, layer)
        assert capture_cache.stats()["partial_captures"] == before + 1 and reads == expected
        same(partial, scene_capture.capture(scene, layer))
    assert partial.panes[partial.geometry.object_names.index("pane")].geometry.heights[0] == pytest.approx(1.2)

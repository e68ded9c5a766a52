"""Meters sealed off from every source (issue 31, dark meters; radiometry/scene/sealed.py): on the other side
of a closed opaque shell from every light they read exactly 0, spend no sample and say why; where the proof
does not hold (a light that casts no shadow, a shell with a hole, a wall that lets some rays through) they
are measured as before."""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

INSIDE, OUTSIDE = (0.0, 0.0, 0.5), [(3.0, 0.0, 1.0), (0.0, -3.0, 1.0), (1.0 + 2e-3, 0.3, 1.2)]
OUT_NORMALS = [(-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 0.0, 0.0)]  # facing the box; the last on its wall


def _box_with_lights(build):
    scene = bpy.context.scene
    build.black_world(scene)
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.0))  # closed box 2 x 2 x 2 m
    build.light(scene, "POINT", location=(0.0, 0.0, 1.5), energy=100.0, shadow_soft_size=0.05)
    build.light(scene, "AREA", location=(0.3, 0.2, 1.9), energy=50.0, size=0.4)
    return scene, bpy.context.scene.objects["Cube"]


def test_meters_outside_a_closed_lit_box_read_exactly_zero(clean_blender, build):
    from radiometer import api

    _box_with_lights(build)
    readings = api.measure_illuminance([INSIDE] + OUTSIDE, [(0.0, 0.0, 1.0)] + OUT_NORMALS, quality="preview")
    inside, outside = readings[0], readings[1:]
    assert inside.illuminance > 0 and not inside.exact
    for r in outside:
        assert r.illuminance == 0.0 and r.exact and r.samples == 0 and r.rel_std_error == 0.0
        assert any("sealed off" in note for note in r.notes), r.notes
    assert not any("sealed off" in note for note in inside.notes)


@pytest.mark.parametrize("breach", ["no_shadow", "hole", "shadow_rays_pass", "shadow_linking"])
def test_no_proof_where_light_may_get_out(clean_blender, build, breach):
    """Each breach lets light out (or is not known not to): the outside meters are rendered, not proven."""
    import bmesh

    from radiometer import api

    scene, box = _box_with_lights(build)
    if breach == "no_shadow":
        bpy.data.objects["point"].data.use_shadow = False  # its light goes through every surface
    elif breach == "hole":
        mesh = bmesh.new()
        mesh.from_mesh(box.data)
        bmesh.ops.delete(mesh, geom=[f for f in mesh.faces if f.normal.x > 0.5], context="FACES_ONLY")
        mesh.to_mesh(box.data)
        mesh.free()
    elif breach == "shadow_linking":  # an emitting card inside whose shadow rays ignore the box
        card = build.plane(scene, size=0.3, location=(0.0, 0.0, 1.0), name="card")
        tree = card.data.materials[0].node_tree
        tree.nodes.clear()
        emission = tree.nodes.new("ShaderNodeEmission")
        tree.links.new(emission.outputs[0], tree.nodes.new("ShaderNodeOutputMaterial").inputs["Surface"])
        blockers = bpy.data.collections.new("blockers")
        card.light_linking.blocker_collection = blockers
    else:
        box.visible_shadow = False
    r = api.measure_illuminance(OUTSIDE[0], OUT_NORMALS[0], quality="preview", stop_dark=True)
    assert not r.exact and r.samples > 0
    assert not any("sealed off" in note for note in r.notes)
    if breach == "hole":  # the meter faces the open side of the lit box: it reads the light
        assert r.illuminance > 0


def _shader_material(name, build_tree):
    from radiometer.compat import ensure_node_tree

    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    build_tree(tree, tree.nodes.new("ShaderNodeOutputMaterial"))
    return mat


def _grouped_principled(tree, out, **inputs):
    """A Principled BSDF inside a node group (as asset libraries wrap materials)."""
    group = bpy.data.node_groups.new("wrapped", "ShaderNodeTree")
    group.interface.new_socket("BSDF", in_out="OUTPUT", socket_type="NodeSocketShader")
    principled = group.nodes.new("ShaderNodeBsdfPrincipled")
    for key, value in inputs.items():
        principled.inputs[key].default_value = value
    group.links.new(principled.outputs[0], group.nodes.new("NodeGroupOutput").inputs[0])
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    tree.links.new(node.outputs[0], out.inputs["Surface"])


@pytest.mark.parametrize("material", ["alpha_in_group", "subsurface", "ray_portal"])
def test_no_proof_through_a_material_that_passes_light(clean_blender, build, material):
    """Review of the proof (reproduced with renders): a Principled BSDF with alpha inside a node group, subsurface
    scattering and a Ray Portal BSDF on one face each let light out of the box; none may seal it."""
    from radiometer import api

    _scene, box = _box_with_lights(build)
    if material == "alpha_in_group":
        box.data.materials.append(_shader_material("grouped", lambda t, o: _grouped_principled(t, o, Alpha=0.1)))
    elif material == "subsurface":
        box.data.materials.append(_shader_material("sss", lambda t, o: _grouped_principled(
            t, o, **{"Subsurface Weight": 1.0})))
    else:
        box.data.materials.append(_shader_material("diffuse", lambda t, o: t.links.new(
            t.nodes.new("ShaderNodeBsdfDiffuse").outputs[0], o.inputs["Surface"])))
        box.data.materials.append(_shader_material("portal", lambda t, o: t.links.new(
            t.nodes.new("ShaderNodeBsdfRayPortal").outputs[0], o.inputs["Surface"])))
        for polygon in box.data.polygons:
            polygon.material_index = 1 if polygon.normal.x > 0.5 else 0
    r = api.measure_illuminance(OUTSIDE[0], OUT_NORMALS[0], quality="preview", stop_dark=True)
    assert not r.exact and not any("sealed off" in note for note in r.notes)


def test_a_background_shader_card_is_a_source(clean_blender, build):
    """A card with a Background shader inside a closed box emits (Cycles renders it as emission): the meter
    inside is not cut off from it, although the sun outside is."""
    from radiometer import api

    scene = bpy.context.scene
    build.black_world(scene)
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.0))
    build.light(scene, "SUN", location=(0.0, 0.0, 5.0), energy=3.0)
    card = build.plane(scene, size=0.3, location=(0.0, 0.5, 1.0), name="card")
    card.data.materials[0] = _shader_material("glow", lambda t, o: t.links.new(
        t.nodes.new("ShaderNodeBackground").outputs[0], o.inputs["Surface"]))
    r = api.measure_illuminance((0.0, 0.0, 0.5), (0.0, 0.0, 1.0), quality="preview", stop_dark=True)
    assert not r.exact and not any("sealed off" in note for note in r.notes)


def test_a_closed_cupboard_in_daylight_reads_zero(clean_blender, build):
    """Sun and sky outside, a meter inside a closed box (no light inside): the sources at infinity are cut
    off by the shell; a meter outside it is not."""
    from radiometer import api

    scene = bpy.context.scene
    api.set_cie_sky(scene, "overcast")
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5))
    sun = build.light(scene, "SUN", location=(0.0, 0.0, 5.0), energy=3.0)
    sun.rotation_euler = (0.5, 0.2, 0.0)
    readings = api.measure_illuminance([(0.0, 0.0, 0.3), (3.0, 0.0, 0.0)], [(0.0, 0.0, 1.0), (0.0, 0.0, 1.0)],
                                       quality="preview")
    assert readings[0].illuminance == 0.0 and readings[0].exact and readings[0].samples == 0
    assert readings[1].illuminance > 0 and math.isfinite(readings[1].rel_std_error)


def test_closed_components_are_closed_surfaces_only():
    from radiometer.radiometry.skies import sky_aperture

    def box(lo, hi):
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        v = np.array([[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)], float)
        quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        return np.array([[v[a], v[b], v[c]] for q in quads for a, b, c in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))])

    closed, other = box((0, 0, 0), (1, 1, 1)), box((3, 0, 0), (4, 1, 1))[:-2]  # the second lacks one face
    comps = sky_aperture.closed_components(np.concatenate([closed, other]), 1e-6)
    assert len(comps) == 1 and sorted(comps[0].tolist()) == list(range(12))
    inside = sky_aperture.inside_enclosures([(0.5, 0.5, 0.5), (2.0, 0.5, 0.5)], closed, [], 1e-6)
    assert inside == [True, False]


@pytest.mark.parametrize("outside", ["open", "obstruction"])
def test_a_closed_cupboard_in_a_daylit_room_reads_zero_in_the_daylight_factor(clean_blender, outside):
    """The daylight factor's split path (the proven sky component plus a render of the rest, issue 31): a meter in a
    closed box on the floor of the side-lit room reads exactly 0 with no sample spent, whether the opening is made an
    emitter (open window) or the sky's direct emission is gated off (a block outside); one in the room does not."""
    import importlib.util
    import pathlib

    from radiometer import api

    spec = importlib.util.spec_from_file_location("daylight_room",
                                                  pathlib.Path(__file__).with_name("daylight_room.py"))
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + (room.obstruction_quads() if outside == "obstruction" else []))
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(3.0, 2.3, 0.41))  # 1 cm above the floor, closed
    rs = api.daylight_factor([(3.0, 2.3, 0.4), (2.0, 1.5, 0.85)], target_rel_error=0.02, seed=4)
    boxed, open_ = rs
    assert boxed.daylight_factor == 0.0 and boxed.exact and boxed.rel_std_error == 0.0
    assert boxed.sky_component == 0.0
    assert any("sealed off" in note for note in boxed.notes), boxed.notes
    assert open_.daylight_factor > 0.5 and not open_.exact and math.isfinite(open_.rel_std_error)
    assert open_.sky_component is not None  # the split path ran (the sky component proven there)


def _daylight_room():
    import importlib.util
    import pathlib

    spec = importlib.util.spec_from_file_location("daylight_room", pathlib.Path(__file__).with_name("daylight_room.py"))
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    return room


# the side-lit room (4 x 3 x 2.7 m, its window in the wall y = 0): meters outside it, behind the window's plane
BEHIND = [(-1.0, 1.5, 0.85), (5.0, 2.0, 1.5), (2.0, 4.0, 3.5), (-1.0, 0.5, 0.5)]
BEHIND_NORMALS = [(0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -0.6, -0.8)]
FRONT, FRONT_NORMAL = (2.0, -1.0, 1.5), (0.0, 1.0, 0.0)  # outside, facing the window


def _lit_room_with_a_window(build, extra=()):
    room = _daylight_room()
    scene = bpy.context.scene
    build.black_world(scene)
    room.build_blender(scene, room.quads() + list(extra))
    build.light(scene, "AREA", location=(2.0, 1.5, 2.6), energy=200.0, size=0.6)
    return scene, room


def test_meters_behind_the_window_of_a_lit_room_read_exactly_zero(clean_blender, build):
    """Issue 31 (dark meters): every light inside a closed room whose one opening looks out on nothing, the world
    black: light leaving the window travels on in front of it and never returns, so a meter outside the room and
    behind the window's plane reads exactly 0 with no sample (before: 65 536 samples each, an infinite error).
    One in front of the window, and one in the room, are lit and measured. A whole render at a proven meter,
    with no proof, finds nothing either."""
    from radiometer import api

    _lit_room_with_a_window(build)
    readings = api.measure_illuminance(BEHIND + [FRONT, (2.0, 1.5, 0.85)],
                                       BEHIND_NORMALS + [FRONT_NORMAL, (0.0, 0.0, 1.0)], quality="preview")
    for r in readings[:len(BEHIND)]:
        assert r.illuminance == 0.0 and r.exact and r.samples == 0 and r.rel_std_error == 0.0
        assert any("openings look out on nothing" in note for note in r.notes), r.notes
    front, inside = readings[len(BEHIND):]
    for r in (front, inside):
        assert r.illuminance > 1.0 and not any("sealed off" in note for note in r.notes)
    rendered = api.measure_illuminance(BEHIND[3], BEHIND_NORMALS[3], method="render", samples=65536)
    assert rendered.illuminance == 0.0 and rendered.samples == 65536


@pytest.mark.parametrize("breach", ["ground", "world", "lamp_outside", "lamp_in_the_window"])
def test_no_proof_behind_the_window_where_light_may_come_back(clean_blender, build, breach):
    """A ground plane in front of the window (it sends the window's light back behind the window's plane), an
    emitting world, a lamp outside, a lamp in the opening (part of it in front): nothing is proven behind the
    window; where light does arrive there it is measured."""
    from radiometer import api
    from radiometer.compat import ensure_node_tree

    room = _daylight_room()
    scene, room = _lit_room_with_a_window(build, room.ground_quads() if breach == "ground" else ())
    if breach == "world":
        background = ensure_node_tree(scene.world).nodes["Background"]
        background.inputs["Color"].default_value, background.inputs["Strength"].default_value = (0.5, 0.5, 0.5, 1), 1.0
    elif breach == "lamp_outside":
        build.light(scene, "POINT", location=(-3.0, 1.5, 1.0), energy=50.0, shadow_soft_size=0.05)
    elif breach == "lamp_in_the_window":
        build.light(scene, "POINT", location=(2.0, 0.0, 1.5), energy=50.0, shadow_soft_size=0.05)
    readings = api.measure_illuminance(BEHIND, BEHIND_NORMALS, quality="preview")
    for r in readings:  # (the meter above the roof, facing up, sees no surface: exact 0 by the plan's own proof)
        assert not any("openings look out on nothing" in note for note in r.notes), (r.location, r.notes)
    assert all(r.illuminance > 0 or not r.exact for r in readings[:2] + readings[3:])  # no zero proven
    if breach != "lamp_in_the_window":  # the downward meter beside the room sees the lit ground, the world, the lamp
        assert readings[3].illuminance > 0.0


@pytest.mark.parametrize("pane", ["as built", "mirrored object", "outer face turned in", "mirrored and turned in",
                                  "single face", "frosted"])
def test_a_glazed_window_keeps_the_proof_while_its_pane_sends_nothing_back(clean_blender, build, pane):
    """A 6 mm thin pane standing 6 mm in front of the window's plane (tests/bpy/daylight_room.py): rendered as thin
    glass it passes a ray on or mirrors it where the ray meets a face's front, so a ray leaving the room keeps moving
    away (its side faces are perpendicular to the plane, its outer face turned away): the meters behind the plane
    stay proven dark, and a whole render of 65 536 samples at one of them reads 0; so in a mirrored object (scale
    x -1 over a mirrored mesh whose faces Blender shows outwards: its captured triangles wind inwards, and Cycles
    takes Blender's side). With the outer face turned in (as Blender shows it,
    mirrored or not) the pane would mirror light back past the wall: not proven; nor a single face 6 mm out, which
    mirrors from both sides. A frosted pane (roughness 0.5) is a refractor rendered as it is: not proven."""
    from radiometer import api

    _scene, room = _lit_room_with_a_window(build)
    if pane == "single face":  # one polygon in the window's plane moved 6 mm out, facing out
        x0, x1, z0, z1 = room.WINDOW
        glass = room.add_pane_blender(bpy.context.scene, [[(x0, -0.006, z0), (x1, -0.006, z0), (x1, -0.006, z1),
                                                            (x0, -0.006, z1)]])
    else:
        glass = room.add_pane_blender(bpy.context.scene)
    if "mirrored" in pane:  # scale x -1 over a mirrored mesh (its faces flipped, so Blender shows them outwards):
        for v in glass.data.vertices:  # the same slab in the world, through a mirrored transform
            v.co.x = -v.co.x
        for poly in glass.data.polygons:
            poly.flip()
        glass.scale = (-1.0, 1.0, 1.0)
        bpy.context.view_layer.update()
    if "turned in" in pane:
        glass.data.polygons[0].flip()  # the -y face (outside), as Blender shows it
        glass.data.update()
    elif pane == "frosted":
        next(n for n in glass.data.materials[0].node_tree.nodes if n.type == "BSDF_GLASS").inputs["Roughness"] \
            .default_value = 0.5
    readings = api.measure_illuminance(BEHIND[:2] + BEHIND[3:], BEHIND_NORMALS[:2] + BEHIND_NORMALS[3:],
                                       quality="preview")
    proven = [any("openings look out on nothing" in note for note in r.notes) for r in readings]
    if pane in ("as built", "mirrored object"):
        assert all(proven) and all(r.exact and r.illuminance == 0.0 and r.samples == 0 for r in readings)
        rendered = api.measure_illuminance(BEHIND[3], BEHIND_NORMALS[3], method="render", samples=65536)
        assert rendered.illuminance == 0.0 and rendered.samples == 65536
    else:
        assert not any(proven)


@pytest.mark.parametrize("breach", [None, "lamp outside", "ground"])
def test_meters_outside_a_lit_room_of_boxes_read_exactly_zero(clean_blender, build, breach):
    """A room of nine separate boxes that touch (no single closed surface; tests/bpy/daylight_room.py), lit inside,
    the world black: the walls' outer faces cover the box round the scene but for the window, so light leaves only
    through the face holding the window and never returns, and meters outside beside or behind the room read exactly
    0 with no sample; a whole render of 65 536 samples at one reads 0. A lamp outside the room, or a ground plane
    (it widens the box, whose faces it leaves uncovered, and sends the window's light back), prove nothing."""
    from radiometer import api

    room = _daylight_room()
    scene = bpy.context.scene
    build.black_world(scene)
    room.build_boxes_blender(scene, room.boxes_room_boxes())
    build.light(scene, "AREA", location=(2.0, 2.5, 2.7), energy=200.0, size=0.6)
    if breach == "lamp outside":
        build.light(scene, "POINT", location=(-3.0, 2.0, 1.0), energy=50.0, shadow_soft_size=0.05)
    elif breach == "ground":
        room.build_blender(scene, room.ground_quads(z=-0.21))
    outside = [(-1.5, 2.0, 0.85), (5.5, 1.0, 1.5), (2.0, 6.5, 0.5)]
    normals = [(0.0, 0.0, 1.0), (-1.0, 0.0, 0.0), (0.0, -0.6, -0.8)]
    readings = api.measure_illuminance(outside + [(2.0, -1.5, 1.5)], normals + [(0.0, 1.0, 0.0)], quality="preview")
    proven = [any("in front only of faces of it that opaque surfaces cover whole" in n for n in r.notes)
              for r in readings]
    front = readings[-1]
    assert front.illuminance > 1.0 and not proven[-1]  # it sees the window
    if breach is None:
        assert all(proven[:-1]) and all(r.exact and r.illuminance == 0.0 and r.samples == 0 for r in readings[:-1])
        rendered = api.measure_illuminance(outside[2], normals[2], method="render", samples=65536)
        assert rendered.illuminance == 0.0 and rendered.samples == 65536
    else:
        assert not any(proven) and readings[0].illuminance + readings[2].illuminance > 0.0


def test_meters_beside_a_lit_box_open_at_the_top_read_exactly_zero(clean_blender, build):
    """A lit box with its top face deleted (no hole in a face, so no opening of a shell): its four sides and bottom
    cover the faces of the box round the scene, so its light leaves upwards only; meters beside it, below the top,
    read exactly 0 with no sample, and one above it, looking down into it, is lit."""
    import bmesh

    from radiometer import api

    build.black_world(bpy.context.scene)
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.0))
    build.light(bpy.context.scene, "POINT", location=(0.0, 0.0, 1.5), energy=100.0, shadow_soft_size=0.0)
    box = bpy.context.scene.objects["Cube"]
    mesh = bmesh.new()
    mesh.from_mesh(box.data)
    bmesh.ops.delete(mesh, geom=[f for f in mesh.faces if f.normal.z > 0.5], context="FACES_ONLY")
    mesh.to_mesh(box.data)
    mesh.free()
    readings = api.measure_illuminance([(3.0, 0.0, 1.0), (0.0, -3.0, 1.9), (0.5, 0.5, 3.0)],
                                       [(-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0)], quality="preview")
    for r in readings[:2]:
        assert r.illuminance == 0.0 and r.exact and r.samples == 0
        assert any("cover whole" in note for note in r.notes)
    assert readings[2].illuminance > 1.0 and not readings[2].exact

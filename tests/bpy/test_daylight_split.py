"""The daylight factor split (issue 31): where the sky component (SC) is proven in closed form
(measure/analyses/sky_component.py), ``method="auto"`` reads SC + a render of the rest: with the openings
as emitters linked out of the meters where nothing lies outside them (or only a ground plane below them: then they
emit the sky alone), else with the sky's direct emission gated off. Independent of that split: the render of everything (``method="render"``, another
seed; Radiance against it in test_daylight_factor.py), and the closed form alone."""

import importlib.util
import math
import pathlib

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.measure.analyses import sky_component
from radiometer.measure.analyses.daylight_factor import SKY_HORIZONTAL_LUX


def _room():
    spec = importlib.util.spec_from_file_location("daylight_room", pathlib.Path(__file__).with_name("daylight_room.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


room = _room()


def _state(scene):
    ids = {name: sorted(b.name for b in getattr(bpy.data, name))
           for name in ("objects", "worlds", "lights", "materials", "meshes", "images", "collections")}
    return ids, scene.world, scene.cycles.samples


def _se(r):
    return r.rel_std_error * r.daylight_factor


def _ground_mesh(scene):
    """A ground plane outside the room, just below its floor: nothing of it stands between a point in the
    room and the sky, but it lies in front of the window, below it: the openings emit the sky alone."""
    me = bpy.data.meshes.new("ground")
    me.from_pydata([(-20.0, -20.0, -0.01), (24.0, -20.0, -0.01), (24.0, 23.0, -0.01), (-20.0, 23.0, -0.01)], [],
                   [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("ground", me))


@pytest.mark.parametrize("outside", ["nothing", "ground"])
def test_split_agrees_with_the_whole_render(clean_blender, outside, monkeypatch):
    monkeypatch.setattr(sky_component, "_LINK_CHECKS", {})  # each kind of emitter's own linking check, run here
    scene = bpy.context.scene
    room.build_blender(scene)
    if outside == "ground":
        _ground_mesh(scene)
    user_world = bpy.data.worlds.new("user world")
    scene.world = user_world
    before = _state(scene)
    points = room.POINTS + [(1.2, 0.4, 1.6)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=11, method="render")
    pts = np.asarray(points, float)
    closed = sky_component.sky_components(scene, pts, np.broadcast_to((0.0, 0.0, 1.0), pts.shape),
                                          ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
    for a, w, c in zip(auto, whole, closed):
        se = math.hypot(_se(a), _se(w))
        print(f"split {a.daylight_factor:.4f} +- {_se(a):.4f} % (SC {a.sky_component:.4f}, reflected "
              f"{a.reflected_component:.4f}); whole render {w.daylight_factor:.4f} +- {_se(w):.4f} %")
        assert a.method.startswith("hybrid") and not a.exact and w.method == "render"
        assert a.sky_component == 100.0 * c.sky_lux / SKY_HORIZONTAL_LUX  # the closed form, unchanged
        assert a.reflected_component == a.daylight_factor - a.sky_component and a.reflected_component > 0
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * se
        assert 0 < a.rel_std_error <= 0.0101  # the target counts the proven part
        assert any("sky component proven" in n for n in a.notes)
        if outside == "nothing":  # the openings as emitters: the ground seen straight is the ERC, exact
            assert any("light linking was checked" in n and "does NOT" not in n for n in a.notes)
            assert a.externally_reflected_component == 100.0 * c.ground_lux / SKY_HORIZONTAL_LUX
            assert math.isclose(a.internally_reflected_component,
                                a.reflected_component - a.externally_reflected_component, rel_tol=1e-12)
            assert a.internally_reflected_component > 0
        else:  # a ground plane in front, below the opening: it emits the sky alone, upwards; the ground is rendered
            assert any("light linking was checked" in n and "does NOT" not in n for n in a.notes)
            assert any("emitted the sky's radiance into the room, upwards" in n and "ground plane seen through them "
                       "rendered" in n for n in a.notes), a.notes
            assert any("0 lx with the meter linked out under the sky (its ground black)" in n for n in a.notes), \
                [n for n in a.notes if "linking" in n]
            assert a.externally_reflected_component is None and a.internally_reflected_component is None
        assert w.sky_component is None and w.reflected_component is None
    assert _state(scene) == before


def test_unproven_points_fall_back_and_say_why(clean_blender):
    scene = bpy.context.scene
    room.build_blender(scene)
    before = _state(scene)
    # inside (proven) and outside the room in front of its wall (its sky proven past every surface, but the gate path
    # is not taken beside the openings' emitters: rendered whole)
    inside, outside = api.daylight_factor([(2.0, 1.5, 0.85), (2.0, -2.0, 1.0)], seed=2)
    assert inside.sky_component > 0 and inside.method.startswith("hybrid")
    assert outside.sky_component is None and not outside.exact and outside.method == "render"
    assert any("proven (the point is outside the only closed shell" in n and "not taken beside the openings' "
               "emitters" in n for n in outside.notes), outside.notes
    # an obstruction outside in front of the window: the sky past its silhouette in closed form (issue 31), the
    # rest (its reflection too) rendered; a board through the point itself: no proof, the whole is rendered
    me = bpy.data.meshes.new("block")
    me.from_pydata([(0.0, -3.0, 0.0), (4.0, -3.0, 0.0), (4.0, -3.0, 6.0), (0.0, -3.0, 6.0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("block", me))
    before = _state(scene)
    blocked = api.daylight_factor((2.0, 1.5, 0.85), seed=2)
    assert 0.0 < blocked.sky_component < 0.8 * inside.sky_component and blocked.method.startswith("hybrid")
    assert blocked.externally_reflected_component is None and not blocked.exact
    assert any("silhouettes clipped exactly" in n for n in blocked.notes)
    assert blocked.daylight_factor < inside.daylight_factor
    me = bpy.data.meshes.new("board")
    me.from_pydata([(1.8, 1.5, 0.5), (2.2, 1.5, 0.5), (2.2, 1.5, 1.5), (1.8, 1.5, 1.5)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("board", me))
    before = _state(scene)
    refused = api.daylight_factor((2.0, 1.5, 0.85), seed=2)
    assert refused.sky_component is None and refused.reflected_component is None
    assert refused.method == "render" and not refused.exact
    assert any("passes within" in n for n in refused.notes), refused.notes
    assert _state(scene) == before


def test_a_cabinet_against_the_wall_keeps_the_split(clean_blender):
    """Furniture is normal use: a cabinet in the corner of floor and side wall (a closed box sharing their seam) and a
    column from floor to ceiling leave the room closed, so the openings still emit and the sky seen straight is
    proven; before, the seam's edge used four times refused the room and every point took the slower gate path. The
    split agrees with the whole render; a meter inside the cabinet reads exactly 0 (sealed off)."""
    scene = bpy.context.scene
    room.build_blender(scene)
    for name, lo, hi in (("cabinet", (3.5, 1.5, 0.0), (4.0, 2.5, 2.0)), ("column", (0.4, 2.2, 0.0), (0.7, 2.5, 2.7))):
        me = bpy.data.meshes.new(name)
        me.from_pydata([tuple(v) for v in room.box_triangles(lo, hi).reshape(-1, 3)], [],
                       [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(12)])
        scene.collection.objects.link(bpy.data.objects.new(name, me))
    before = _state(scene)
    points = [(2.0, 1.5, 0.85), (3.0, 2.0, 0.85), (3.75, 2.0, 0.85)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points[:2], target_rel_error=0.01, seed=11, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and a.sky_component > 0, a.notes
        assert any("convex opening(s) in a closed opaque shell" in n for n in a.notes), a.notes
        assert any("light linking was checked" in n for n in a.notes)
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * math.hypot(_se(a), _se(w))
    boxed = auto[2]
    assert boxed.daylight_factor == 0.0 and boxed.exact and boxed.rel_std_error == 0.0
    assert any(n.startswith("sealed off") for n in boxed.notes), boxed.notes


def test_a_window_frame_is_one_opening_and_its_sky_is_proven(clean_blender):
    """A window frame with a mullion standing half out of the opening (tests/bpy/daylight_room.py
    ``window_frame_boxes``): before, the rings of its faces counted as four more openings (the sky counted again
    through each: DF 8.4 % for 3.3 % in issue 31's room). Now the room has one opening, the sky past the frame's
    silhouette is proven, and, since next-event estimation from the bars to an emitter beside them has tails the
    stated error misses, the opening is not made an emitter: the rest is rendered on the gate path, which agrees
    with the whole render."""
    scene = bpy.context.scene
    room.build_blender(scene)
    points = [(2.0, 0.75, 0.85), (1.2, 0.4, 1.6), (2.0, 2.5, 0.85)]
    pts = np.asarray(points, float)
    up = np.broadcast_to((0.0, 0.0, 1.0), pts.shape)
    bare = sky_component.sky_components(scene, pts, up, ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
    room.build_boxes_objects(scene, room.window_frame_boxes())
    before = _state(scene)
    framed = sky_component.sky_components(scene, pts, up, ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=11, method="render")
    for a, w, b, f in zip(auto, whole, bare, framed):
        assert f.apertures == 1 and 0.5 * b.sky_lux < f.sky_lux < b.sky_lux  # the frame's bars hide part of the sky
        assert a.method.startswith("hybrid") and a.sky_component == 100.0 * f.sky_lux / SKY_HORIZONTAL_LUX
        assert any("1 convex opening(s) in a closed opaque shell" in n and "opaque parts stand out of opening 1" in n
                   for n in a.notes), a.notes
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * math.hypot(_se(a), _se(w))


def test_a_sill_at_the_windows_edge_keeps_the_room_and_is_gated(clean_blender):
    """An interior sill whose back face lies on the wall and whose top is the window's bottom edge: before, the back
    face hid that edge ("no opening found"). Now the room has its one opening and the sky past the sill is proven
    in the closed room; next-event estimation from the sill's top beside the edge to an emitter in the opening has
    heavy tails (30 seeds x 6 points at 1 %: one point scattered 1.83 x its stated error), so the opening is not
    made an emitter (the reason says so) and the rest is gated; it agrees with the whole render."""
    scene = bpy.context.scene
    room.build_blender(scene)
    x0, x1, z0, _z1 = room.WINDOW
    room.build_boxes_objects(scene, [((x0 - 0.1, 0.0, z0 - 0.05), (x1 + 0.1, 0.25, z0))], name="sill", rho=0.6)
    from radiometer.measure.meter import point_meter as meter

    openings = sky_component.openings_to_world(meter.capture_model(scene))
    assert not openings.loops and "meets the outline of opening 1 at an angle" in openings.reason
    points = [(2.0, 0.75, 0.85), (1.2, 0.4, 1.6), (2.0, 2.5, 0.85)]
    before = _state(scene)
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=11, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and a.sky_component > 0, a.notes
        assert any("1 convex opening(s) in a closed opaque shell" in n for n in a.notes), a.notes
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * math.hypot(_se(a), _se(w))


def test_the_rest_gathered_from_the_walls_agrees_with_the_whole_render(clean_blender, monkeypatch):
    """Issue 31's room with its window open: the light the walls reflect, gathered from one-sample bakes at random
    points of their cells and weighed by each meter's cos cos / r^2 (``surface_gather``: normally from 300 meters,
    here forced for four), agrees with the whole render at each point; the scene is left as it was. A meter nearer
    a wall than ``MIN_DISTANCE_M`` renders its own rest."""
    from radiometer.measure.meter import surface_gather

    monkeypatch.setattr(surface_gather, "MIN_METERS", 1)
    scene = bpy.context.scene
    room.build_blender(scene, room.quads(4.0, 6.0, 3.0))
    points = [(2.0, 1.0, 0.85), (2.8, 2.0, 0.85), (0.5, 5.5, 0.85), (3.5, 1.5, 1.6), (2.0, 3.0, 0.05)]
    before = _state(scene)
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=11, method="render")
    for k, (a, w) in enumerate(zip(auto, whole)):
        gathered = any("gathered from" in n for n in a.notes)
        assert gathered == (k < 4), a.notes  # the last meter is 5 cm over the floor
        assert a.method.startswith("hybrid") and not a.exact
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * math.hypot(_se(a), _se(w)), (a.daylight_factor,
                                                                                                w.daylight_factor)


def test_obstruction_split_agrees_with_the_whole_render(clean_blender):
    """Facing a block (reflectance 0.2) 4 m outside: the sky past its silhouette in closed form plus the rest
    rendered with the sky's direct emission gated off, against the whole render (another seed), per point within
    4 combined standard errors; faster to reach the same target is the bench's (bench/coverage_daylight_emitters.md)."""
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + room.obstruction_quads())
    before = _state(scene)
    points = [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 2.5, 0.85), (1.2, 0.4, 1.6)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=5)
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=6, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and a.sky_component is not None and a.sky_component < a.daylight_factor
        combined = math.hypot(a.rel_std_error * a.daylight_factor, w.rel_std_error * w.daylight_factor)
        assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)
    assert auto[2].sky_component == 0.0  # the block hides all the sky through the window from there
    assert _state(scene) == before


def test_pane_and_obstruction_split_agrees_with_the_whole_render(clean_blender):
    """A 6 mm pane in the window and the block outside: the sky past the block through the pane, weighted by its
    T(theta) with a hard bound, plus the rest rendered through the gate, against the whole render."""
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + room.obstruction_quads())
    room.add_pane_blender(scene)
    before = _state(scene)
    points = [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (1.2, 0.4, 1.6)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=5)
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=6, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and 0.0 < a.sky_component < a.daylight_factor
        assert any("silhouettes clipped exactly" in n and "thin pane" in n and "bounded;" in n for n in a.notes)
        combined = math.hypot(a.rel_std_error * a.daylight_factor, w.rel_std_error * w.daylight_factor)
        assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)
    assert _state(scene) == before


def test_grid_reports_the_sky_component(clean_blender, build):
    scene = bpy.context.scene
    room.build_blender(scene)
    plane = build.plane(scene, size=2.0, location=(2.0, 1.5, 0.85), name="work plane")
    plane.hide_render = True
    g = api.daylight_factor_grid(plane, resolution=(3, 2), quality="preview", seed=4)
    assert g.sky_component.shape == (2, 3) and np.all(g.sky_component > 0)
    assert np.all(g.sky_component < g.daylight_factor) and g.method.startswith("hybrid") and not g.exact
    assert any("proven in closed form at 6 of 6 points" in n for n in g.notes)
    d = g.to_dict()
    assert np.array(d["sky_component"]).shape == (2, 3)
    # the openings as emitters: the BRE parts add up to the DF at every point (ERC: ground seen straight)
    assert np.allclose(g.sky_component + g.externally_reflected_component + g.internally_reflected_component,
                       g.daylight_factor, rtol=1e-12) and np.all(g.internally_reflected_component > 0)
    rows = g.csv_text().splitlines()
    assert rows[0].endswith("sky_component_percent,erc_percent,irc_percent") and len(rows) == 7
    assert float(rows[1].split(",")[-1]) == pytest.approx(g.internally_reflected_component.ravel()[0], rel=1e-5)


def test_a_gate_that_fails_its_check_is_not_used(clean_blender, monkeypatch):
    # As if Cycles reported another Ray Depth for a sensor's direct world hits: the check sees the direct
    # band read 0 instead of the sky, and the SC is not used (the whole is rendered, and said so).
    monkeypatch.setattr(sky_component, "DIRECT_DEPTH", 1.0)
    monkeypatch.setattr(sky_component, "_GATE_CHECKS", {})
    scene = bpy.context.scene
    room.build_blender(scene)
    me = bpy.data.meshes.new("block")  # a block outside, in front of the window: the gate, not the openings' emitters
    me.from_pydata([(0.0, -3.0, 0.0), (4.0, -3.0, 0.0), (4.0, -3.0, 6.0), (0.0, -3.0, 6.0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("block", me))
    before = _state(scene)
    r = api.daylight_factor((2.0, 1.5, 0.85), quality="preview", seed=1)
    assert r.sky_component is None and r.method == "render" and r.daylight_factor > 5.0
    assert any("does NOT hold" in n for n in r.notes)
    assert _state(scene) == before


def test_linking_that_fails_its_check_renders_through_the_emitters(clean_blender, monkeypatch):
    # As if light linking let an emitting mesh's light reach a linked-out sensor: the check sees it, no
    # closed-form part is used and the whole is rendered through the openings' emitters (said so).
    real = sky_component.check_emitter_linking
    seen = []

    def failing(*args, **kwargs):
        ok, note = real(*args, **kwargs)
        seen.append(ok)
        return False, note + ": linking does NOT keep them out here"

    monkeypatch.setattr(sky_component, "check_emitter_linking", failing)
    monkeypatch.setattr(sky_component, "_LINK_CHECKS", {})
    scene = bpy.context.scene
    room.build_blender(scene)
    before = _state(scene)
    r = api.daylight_factor((2.0, 1.5, 0.85), quality="preview", seed=1)
    assert seen == [True]  # the real check passed on this Blender
    assert r.sky_component is None and r.method == "render" and not r.exact and r.daylight_factor > 5.0
    assert any("rendered all the light here" in n and "does NOT" in n for n in r.notes)
    assert _state(scene) == before


@pytest.mark.parametrize("pane,ground", [(False, False), (True, False), (False, True)])
def test_opening_emitters_carry_the_closed_form(clean_blender, pane, ground):
    # The openings' emitters, rendered straight (0 bounces, nothing linked out), against the closed form
    # of the sky and ground through the opening (radiometry/skies/sky_aperture.py): the same radiance by
    # direction, so the same illuminance at points facing up, sideways and at the window. With a ground plane in
    # front (below the opening) the emitters carry the sky alone and let the rest through: under the black world
    # (as the linking check reads) the ground plane is dark at 0 bounces, so they read the sky's closed form alone.
    import json

    from radiometer.measure.analyses import daylight_factor as dfm
    from radiometer.measure.blender import scene_guard
    from radiometer.measure.blender import request as request_of
    from radiometer.measure.capture.world_capture import CIE_SKY_TAG
    from radiometer.measure.meter import point_meter as meter
    from radiometer.measure.render import adaptive

    scene = bpy.context.scene
    room.build_blender(scene)
    if pane:  # the 6 mm pane: its T(theta) by bounding subdivision against the thin-pane stand-in's render
        room.add_pane_blender(scene)
    pts = np.array([(2.0, 1.5, 0.85), (2.0, 0.75, 1.2), (0.5, 2.0, 1.5)])
    dirs = np.array([(0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (1.0, 0.0, 0.0)])
    if ground:  # the world's ground seen through the opening in closed form, before the ground plane is there
        bare = sky_component.sky_components(scene, pts, dirs, ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
        _ground_mesh(scene)
    with scene_guard.preserved_scene(scene) as snapshot:
        request = request_of.build(scene)
        dfm.overcast_only(request, snapshot, 0.2)
        model = meter.capture_model(scene)
        closed = sky_component.sky_components(scene, pts, dirs, ground_reflectance=0.2,
                                              horizontal_lux=SKY_HORIZONTAL_LUX, model=model)
        openings = sky_component.openings_to_world(model)
        assert len(openings.loops) == 1 and np.allclose(openings.outward[0], (0.0, -1.0, 0.0))
        assert openings.sky_only == ground
        sky_world = scene.world
        keys, dark = sky_component.add_opening_emitters(request, openings, json.loads(scene.world[CIE_SKY_TAG]))
        scene.world = dark
        bpy.context.view_layer.update()
        _space, weights, efficacy = request.photometry
        run = adaptive.render_hybrid(request, pts, dirs, needs=model.needs, bounces=0, fixed_samples=65536,
                                     panes=model.panes)
        if ground:  # the rays the sky-only emitters let through: downwards, they meet the world's ground
            plane = bpy.data.objects["ground"]
            plane.hide_render = True
            scene.world = sky_world
            bpy.context.view_layer.update()
            through = adaptive.render_hybrid(request, pts, dirs, needs=model.needs, bounces=0, fixed_samples=65536,
                                             panes=model.panes, exclusions=[keys] * len(pts))
    lux = efficacy * (run["mean_rgb"] @ weights)
    se = efficacy * run["se"]
    if ground:  # linked out of the emitters (the sky), the meters see the world's ground through them: its closed form
        down, down_se = efficacy * (through["mean_rgb"] @ weights), efficacy * through["se"]
        for k, c in enumerate(bare):
            print(f"through the emitters {down[k]:.3f} +- {down_se[k]:.3f} lx; the ground's closed form "
                  f"{c.ground_lux:.3f} lx")
        for k, c in enumerate(bare):
            assert abs(down[k] - c.ground_lux) <= 4.0 * down_se[k] + 1e-4 * c.ground_lux
        assert max(c.ground_lux for c in bare) > 50.0  # the sideways meter sees the ground through the window
    for k, c in enumerate(closed):
        expected = c.sky_lux + (0.0 if ground else c.ground_lux)
        print(f"emitters {lux[k]:.3f} +- {se[k]:.3f} lx; closed form {expected:.3f} +- {c.bound_lux:.3f} lx (bound)")
        assert (c.glazed == 1) == pane and (c.bound_lux > 0) == pane
        assert expected > 50.0 and abs(lux[k] - expected) <= 4.0 * se[k] + c.bound_lux + 1e-4 * expected


@pytest.mark.parametrize("mullion", [None, (1.95, 2.05)])
def test_room_of_boxes_split_agrees_with_the_whole_render(clean_blender, mullion):
    """A room built of nine separate boxes that touch (thick walls, floor and roof; no single closed surface), as
    users build one: the sky over every direction that meets no surface (obstructed_aperture.open_directions) in
    closed form, the rest rendered through the gate, against the whole render (another seed); with a mullion too.
    The room was rendered whole before (its 'openings' could not be proven)."""
    scene = bpy.context.scene
    room.build_boxes_blender(scene, room.boxes_room_boxes(mullion=mullion))
    before = _state(scene)
    points = [(2.0, 1.0, 0.85), (2.0, 2.5, 0.85), (1.0, 4.0, 0.85), (3.5, 0.5, 1.5)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=7)
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=8, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and 0.0 < a.sky_component < a.daylight_factor, a.notes
        assert any("meets no surface at all" in note for note in a.notes)
        # its window found as a gap in the scene's bounding faces and made an emitter, its gate checked
        assert any(f"{1 if mullion is None else 2} gap(s) in the scene's bounding faces" in note for note in a.notes)
        assert any("envelope emitters' gate was checked" in note and "does NOT" not in note for note in a.notes)
        combined = math.hypot(a.rel_std_error * a.daylight_factor, w.rel_std_error * w.daylight_factor)
        assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)
    assert _state(scene) == before


def test_room_as_one_solid_with_thick_walls_split_agrees_with_the_whole_render(clean_blender):
    """The room of boxes joined into one closed solid (a Boolean union: walls, floor and roof with depth, the window a
    tunnel through them), as a solidified or imported room is. Its closed shell has no opening (the tunnel's mouths are
    closed by its reveal) and the room's air lies outside it: each point was refused ("outside the room holding the
    openings") and the room rendered whole, 45x slower. Now such a point takes the proof that needs no room (the sky past every surface), and the window is an
    emitter as in the room of boxes; auto against the whole render (another seed)."""
    scene = bpy.context.scene
    solid = room.build_solid_blender(scene, room.boxes_room_boxes())
    assert len(solid.data.materials) == 3 and len(scene.objects) == 1
    before = _state(scene)
    points = [(2.0, 1.0, 0.85), (1.0, 4.0, 0.85)]
    auto = api.daylight_factor(points, target_rel_error=0.015, seed=5)
    whole = api.daylight_factor(points, target_rel_error=0.015, seed=6, method="render")
    for a, w in zip(auto, whole):
        assert a.method.startswith("hybrid") and 0.0 < a.sky_component < a.daylight_factor, a.notes
        # the tunnel's mouths are holes in the walls' planes that its reveal closes: the solid has no opening
        assert any("closed by other faces: a tunnel through a solid" in note and "meets no surface at all" in note
                   for note in a.notes), a.notes
        assert any("1 gap(s) in the scene's bounding faces" in note for note in a.notes)
        combined = math.hypot(_se(a), _se(w))
        assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)
    # the closed form alone: the same sky component as the room of boxes it was joined from (the same geometry)
    pts = np.array(points)
    joined = sky_component.sky_components(scene, pts, np.broadcast_to((0.0, 0.0, 1.0), pts.shape),
                                          ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
    assert _state(scene) == before
    bpy.data.objects.remove(solid)
    room.build_boxes_blender(scene, room.boxes_room_boxes())
    boxes = sky_component.sky_components(scene, pts, np.broadcast_to((0.0, 0.0, 1.0), pts.shape),
                                         ground_reflectance=0.2, horizontal_lux=SKY_HORIZONTAL_LUX)
    for j, b in zip(joined, boxes):
        assert j.sky_lux == pytest.approx(b.sky_lux, rel=1e-9) and j.sky_lux > 0.0


def test_a_meter_outdoors_in_front_of_the_window_keeps_the_emitters_away(clean_blender):
    """An envelope emitter is dark to rays that cross it inwards: a meter outside the room of boxes, in front of its
    window and facing it, would see the emitter where the wall and the room lie behind it. So with such a meter the
    window is not made an emitter (said why), and the reading agrees with the whole render (another seed); a meter
    beside the room, behind the emitter's plane, keeps them."""
    scene = bpy.context.scene
    room.build_boxes_blender(scene, room.boxes_room_boxes())
    before = _state(scene)
    front = [(2.0, -1.5, 1.2)]
    a = api.daylight_factor(front, (0.0, 1.0, 0.0), target_rel_error=0.015, seed=21)[0]
    w = api.daylight_factor(front, (0.0, 1.0, 0.0), target_rel_error=0.015, seed=22, method="render")[0]
    assert a.method.startswith("hybrid") and 0.0 < a.sky_component < a.daylight_factor
    assert any("stand outside the scene's bounding box in front of a gap" in n for n in a.notes), a.notes
    assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * math.hypot(_se(a), _se(w)), (a.daylight_factor,
                                                                                            w.daylight_factor)
    beside = api.daylight_factor([(-1.5, 2.5, 1.2)], (1.0, 0.0, 0.0), target_rel_error=0.05, seed=23)[0]
    assert any("1 gap(s) in the scene's bounding faces" in n for n in beside.notes), beside.notes
    assert _state(scene) == before


@pytest.mark.parametrize("second", ["back window", "skylight"])
def test_room_of_boxes_with_two_openings_agrees_with_the_whole_render(clean_blender, second):
    """Two gaps in the bounding box's faces, on two faces: a second window in the back wall, or a skylight in the
    roof (the gap on the top face). Both become emitters; auto against the whole render (another seed)."""
    t, w, d, h = 0.2, 4.0, 5.0, 2.8
    boxes = [b for b in room.boxes_room_boxes() if not (b[0][1] == d or b[0][2] == h)]  # no back wall, no roof
    if second == "back window":
        boxes += [((-t, d, 0.0), (1.2, d + t, h)), ((2.8, d, 0.0), (w + t, d + t, h)), ((1.2, d, 0.0), (2.8, d + t, 1.0)),
                  ((1.2, d, 2.0), (2.8, d + t, h)), ((-t, -t, h), (w + t, d + t, h + t))]
    else:
        boxes += [((-t, d, 0.0), (w + t, d + t, h)), ((-t, -t, h), (1.4, d + t, h + t)), ((2.6, -t, h), (w + t, d + t, h + t)),
                  ((1.4, -t, h), (2.6, 1.9, h + t)), ((1.4, 3.1, h), (2.6, d + t, h + t))]
    scene = bpy.context.scene
    room.build_boxes_blender(scene, boxes)
    before = _state(scene)
    points = [(2.0, 2.5, 0.85), (0.8, 4.2, 0.85)]
    auto = api.daylight_factor(points, target_rel_error=0.02, seed=11)
    whole = api.daylight_factor(points, target_rel_error=0.02, seed=12, method="render")
    for a, w_ in zip(auto, whole):
        assert a.method.startswith("hybrid") and 0.0 < a.sky_component < a.daylight_factor
        assert any("2 gap(s) in the scene's bounding faces" in n for n in a.notes), a.notes
        combined = math.hypot(a.rel_std_error * a.daylight_factor, w_.rel_std_error * w_.daylight_factor)
        assert abs(a.daylight_factor - w_.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w_.daylight_factor)
    assert _state(scene) == before


def test_envelope_emitters_that_fail_their_check_are_not_used(clean_blender, monkeypatch):
    # As if Cycles reported another Ray Depth for the light an emitting mesh sends a sensor straight: the check sees
    # the direct band read a fraction of the sky, the window's emitter is taken away again and the rest is rendered
    # through the world's gate alone, as before (said so); the reading still agrees with the whole render.
    monkeypatch.setattr(sky_component, "EMITTER_DIRECT_DEPTH", 2.0)
    monkeypatch.setattr(sky_component, "_ENVELOPE_CHECKS", {})
    scene = bpy.context.scene
    room.build_boxes_blender(scene, room.boxes_room_boxes())
    before = _state(scene)
    a = api.daylight_factor((2.0, 2.5, 0.85), target_rel_error=0.02, seed=3)
    w = api.daylight_factor((2.0, 2.5, 0.85), target_rel_error=0.02, seed=4, method="render")
    assert a.method.startswith("hybrid") and a.sky_component > 0.0
    assert any("envelope emitters' gate" in n and "does NOT hold" in n for n in a.notes)
    assert not any("gap(s) in the scene's bounding faces" in n for n in a.notes)
    combined = math.hypot(a.rel_std_error * a.daylight_factor, w.rel_std_error * w.daylight_factor)
    assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)
    assert _state(scene) == before
    monkeypatch.setattr(sky_component, "_ENVELOPE_CHECKS", {})  # the next test proves it again


def test_room_of_boxes_behind_a_pane_split_agrees_with_the_whole_render(clean_blender, monkeypatch):
    """The room of boxes with a 6 mm pane in its window (touching the reveals): the open directions that pass
    through the pane carry its T(theta) with a hard bound (its rim between 0 and the open sky), the rest rendered
    through the gate, against the whole render (another seed)."""
    scene = bpy.context.scene
    room.build_boxes_blender(scene, room.boxes_room_boxes())
    monkeypatch.setattr(room, "WINDOW", (1.0, 3.0, 0.9, 2.2))
    room.add_pane_blender(scene)
    points = [(2.0, 1.0, 0.85), (2.0, 2.5, 0.85), (1.0, 4.0, 0.85), (3.5, 0.5, 1.5)]
    scs = sky_component.sky_components(scene, np.array(points), np.array([(0.0, 0.0, 1.0)] * 4), ground_reflectance=0.2,
                                       horizontal_lux=SKY_HORIZONTAL_LUX)
    assert all(c.sky_lux is not None and c.glazed == 1 and 0.0 < c.bound_lux < 0.02 * c.sky_lux for c in scs), \
        [c.reason for c in scs]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=9)
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=10, method="render")
    # behind a pane the window is not made an emitter (its readings scattered more than they stated), and it says so
    assert all(any("nor the gaps in the scene's bounding faces: see-through surfaces" in n for n in a.notes) for a in auto)
    for a, w, c in zip(auto, whole, scs):
        assert a.method.startswith("hybrid") and a.sky_component == pytest.approx(100.0 * c.sky_lux / SKY_HORIZONTAL_LUX)
        combined = math.hypot(a.rel_std_error * a.daylight_factor, w.rel_std_error * w.daylight_factor)
        assert abs(a.daylight_factor - w.daylight_factor) <= 4.0 * combined, (a.daylight_factor, w.daylight_factor)


def _blacken(ob):
    for m in ob.data.materials:
        next(n for n in m.node_tree.nodes if n.type == "BSDF_DIFFUSE").inputs["Color"].default_value = (0, 0, 0, 1)


@pytest.mark.parametrize("pane", [False, True])
def test_black_room_reads_its_proven_part_alone(clean_blender, pane):
    """Issue 31: in a room whose every surface is a black Diffuse BSDF nothing reflects, so the daylight factor is
    the sky and the ground seen through the opening alone: exact (or, behind a pane, within the pane's T(theta)
    bound), nothing rendered. Before, each meter took 65 536 samples of nothing and stated an infinite error. The
    whole render (another seed, no proof) agrees; greying the walls again (a material edit) renders the rest."""
    scene = bpy.context.scene
    ob = room.build_blender(scene)
    if pane:
        room.add_pane_blender(scene)
    _blacken(ob)
    before = _state(scene)
    points = [(2.0, 1.5, 0.85), (2.0, 2.9, 0.85), (0.5, 0.5, 1.5)]
    auto = api.daylight_factor(points, target_rel_error=0.01, seed=3)
    assert _state(scene) == before
    whole = api.daylight_factor(points, target_rel_error=0.01, seed=11, method="render")
    for a, w in zip(auto, whole):
        print(f"black room: {a.daylight_factor:.4f} +- {_se(a):.5f} % ({a.method}, exact {a.exact}); whole render "
              f"{w.daylight_factor:.4f} +- {_se(w):.4f} %")
        assert a.method == "analytic" and a.exact is (not pane)
        assert a.rel_std_error == 0.0 if not pane else 0.0 < a.rel_std_error < 0.005
        assert a.internally_reflected_component == 0.0
        assert a.daylight_factor == a.sky_component + a.externally_reflected_component
        assert any("is all the light here" in n for n in a.notes)
        assert abs(a.daylight_factor - w.daylight_factor) <= 3.0 * math.hypot(_se(a), _se(w))
    _blacken_undo = next(m for m in ob.data.materials if m.name.startswith("walls"))
    next(n for n in _blacken_undo.node_tree.nodes if n.type == "BSDF_DIFFUSE").inputs["Color"].default_value = \
        (0.5, 0.5, 0.5, 1)
    grey = api.daylight_factor(points[0], target_rel_error=0.02, seed=3)
    assert grey.method.startswith("hybrid") and not grey.exact and grey.internally_reflected_component > 0


@pytest.mark.parametrize("kind", ["openings", "ground", "solid"])
def test_cancelled_part_way_the_scene_is_as_before(clean_blender, kind):
    """A daylight factor cancelled part-way, on each emitter path (the openings as emitters; the sky-only emitters
    with a ground plane in front; the envelope emitters of a room as one solid), leaves the scene as it was: every
    setting, the world, the data-blocks (no emitter, world or material left behind). The cancel is asked at the
    first and at the last of the checks that a whole run makes (one before each bake, after the emitters are made)."""
    from radiometer.errors import MeasurementCancelled
    from radiometer.measure.blender.scene_guard import scene_fingerprint

    scene = bpy.context.scene
    if kind == "solid":
        room.build_solid_blender(scene, room.boxes_room_boxes())
        points = [(2.0, 1.0, 0.85), (2.0, 3.5, 0.85)]
    else:
        room.build_blender(scene)
        if kind == "ground":
            _ground_mesh(scene)
        points = [(2.0, 1.0, 0.85), (2.0, 2.5, 0.85)]
    scene.world = bpy.data.worlds.new("user world")
    calls = {"n": 0, "stop": None}

    def cancelled():
        calls["n"] += 1
        return calls["stop"] is not None and calls["n"] >= calls["stop"]

    before = scene_fingerprint(scene)
    api.daylight_factor(points, target_rel_error=0.01, seed=3, cancelled=cancelled)
    whole = calls["n"]
    assert whole >= 2 and scene_fingerprint(scene) == before
    for stop in sorted({1, whole}):
        calls.update(n=0, stop=stop)
        with pytest.raises(MeasurementCancelled):
            api.daylight_factor(points, target_rel_error=0.01, seed=3, cancelled=cancelled)
        assert calls["n"] == stop
        assert scene_fingerprint(scene) == before

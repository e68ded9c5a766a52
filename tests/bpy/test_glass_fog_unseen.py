"""Issue 18 acceptance on scenes the window and fog corpus does not hold (T8's QA; every case and
seed in bench/qa_glass_fog.md, made by bench/qa_glass_fog.py). The cheap, decisive cases: clear panes
under delta lights and a 0.53 degree sun against this suite's own Fresnel slab
(``glass_fog_unseen_scenes.fresnel_slab``, not ``radiometry/scene/thin_glass.py``), a volume cube and a
glossy floor against converged patch renders cached in glass_fog_unseen_references.json
(make_glass_fog_unseen_references.py)."""

import importlib.util
import json
import math
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

HERE = pathlib.Path(__file__).resolve().parent


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_tgfu_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


u = _load("glass_fog_unseen_scenes")
STORED = json.loads((HERE / "glass_fog_unseen_references.json").read_text())["values"]


def _stored(key, point, normal):
    entry = STORED[key]
    assert np.allclose(entry["point"], point) and np.allclose(entry["normal"], normal), \
        "stale reference: re-run make_glass_fog_unseen_references.py"
    return u.lux(entry["E_rgb"]), float(entry["rel_std_error"])


def _check(reading, ref_lux, ref_se):
    """Issue 18's three criteria, each on its own (the reference's s.e. in quadrature; 0 for a closed
    form): (1) within max(3 x s.e., 0.5 %); (2) marked exact: within 1e-4 of a closed form; (3) stating
    < 5 %: off by at most 5 x the statement."""
    err = abs(reading.illuminance / ref_lux - 1.0)
    se = float(reading.rel_std_error)
    combined = math.hypot(se, ref_se)
    assert err <= max(3.0 * combined, 0.005), ("criterion 1", reading.illuminance, ref_lux, err, se, reading.notes)
    if reading.exact:
        assert ref_se == 0.0 and err <= 1e-4, ("criterion 2", reading.illuminance, ref_lux, err)
    if se < 0.05:
        assert err <= max(5.0 * combined, 1e-9), ("criterion 3", reading.illuminance, ref_lux, err, se)


def _crosses(scene, point, towards, name):
    """The ray from ``point`` towards ``towards`` (a unit direction) first hits object ``name``: the
    closed form's condition (the light is seen through that pane) checked by Blender's own ray cast."""
    dg = bpy.context.evaluated_depsgraph_get()
    hit, _loc, _n, _i, obj, _m = scene.ray_cast(dg, tuple(np.asarray(point) + 1e-4 * np.asarray(towards)), tuple(towards))
    return hit and obj.name == name


def test_fresnel_slab_of_this_suite():
    """The suite's own slab: normal incidence 2n/(n^2 + 1) for a clear pane, and a 45 degree value
    from Hecht's r_s, r_p (n = 1.5: R_s = 0.09201, R_p = 0.008466 per interface, Hecht 4.42, 4.43)."""
    assert u.fresnel_slab(1.0, 1.5)[0] == pytest.approx(2 * 1.5 / (1.5 ** 2 + 1), rel=1e-12)
    rs, rp = 0.092013, 0.0084663
    hecht = 0.5 * sum((1 - r) / (1 + r) for r in (rs, rp))
    assert u.fresnel_slab(math.cos(math.radians(45.0)), 1.5)[0] == pytest.approx(hecht, rel=2e-5)
    assert np.allclose(u.REC709_Y, [0.2126390, 0.7151687, 0.0721923], atol=1e-7)


def test_tilted_tinted_skylight(clean_blender):
    from radiometer import api

    scene, [(_label, point, normal)] = u.skylight_tilted("POINT")
    v = np.asarray(u.SKYLIGHT["point"], float)
    assert _crosses(scene, point, v / np.linalg.norm(v), "Skylight")
    expected = u.skylight_tilted_expected("POINT")
    r = api.measure_illuminance(point, normal, scene=scene, method="auto")
    assert r.exact and r.method == "analytic"
    assert r.illuminance == pytest.approx(expected, rel=1e-9)
    _check(r, expected, 0.0)
    scene, [(_label, point, normal)] = u.skylight_tilted("SUN")
    assert _crosses(scene, point, u.sun_direction(u.SKYLIGHT["sun_rotation"]), "Skylight")
    expected = u.skylight_tilted_expected("SUN")
    for method in ("auto", "render"):
        _check(api.measure_illuminance(point, normal, scene=scene, method=method, quality="preview"), expected, 0.0)


def test_trick_glass_on_a_solidify_modifier(clean_blender):
    from radiometer import api

    scene, [(_label, point, normal)] = u.trick_solidified()
    assert _crosses(scene, point, u.sun_direction(u.TRICK["sun_rotation"]), "Solid pane")
    expected = u.trick_solidified_expected()
    for method in ("auto", "render"):
        r = api.measure_illuminance(point, normal, scene=scene, method=method, quality="preview")
        assert any("trick" in note for note in r.notes)
        _check(r, expected, 0.0)


def test_vertical_principled_pane_and_a_tilted_meter(clean_blender):
    from radiometer import api

    scene, [(_label, point, normal)] = u.principled_vertical()
    v = np.asarray(u.PRINCIPLED["point"]) - np.asarray(point)
    assert _crosses(scene, point, v / np.linalg.norm(v), "Principled pane")
    expected = u.principled_vertical_expected()
    r = api.measure_illuminance(point, normal, scene=scene, method="auto")
    assert r.exact and r.illuminance == pytest.approx(expected, rel=1e-9)
    _check(r, expected, 0.0)


def test_double_glazing_in_a_wall_low_sun(clean_blender):
    """A black room behind double glazing, sun at 25 degrees: the floor's sun patch and the desk read
    the two panes' closed form (adding formula). (The shaded floor, which reads 0 stating an infinite
    error after the dark-pilot floor's 65 536 samples, is in bench/qa_glass_fog.md only: seconds.)"""
    from radiometer import api

    scene, cases = u.wall_double_glazing()
    to_sun = u.sun_direction(scene.objects["sun"].rotation_euler)
    for label, point, _n in cases:
        assert _crosses(scene, point, to_sun, "Room" if "shade" in label else "Pane 2"), label
    for label, point, normal in cases:
        if "shade" in label:
            continue
        # the desk by auto (a hybrid: the rendered rest of a black room is dark), the floor by closed form
        method = "auto" if "desk" in label else "analytic"
        r = api.measure_illuminance(point, normal, scene=scene, method=method, quality="preview")
        assert any("Pane 1" in note for note in r.notes) and any("Pane 2" in note for note in r.notes)
        _check(r, u.wall_double_glazing_expected(label), 0.0)


def test_grey_room_behind_double_glazing_against_a_patch_render(clean_blender):
    """The same room, grey (albedo 0.5): the sun patch and the shade (light only by interreflection of
    the sun patch) against patch renders with the panes as constant thin glass at the sun's angle."""
    from radiometer import api

    scene, cases = u.wall_double_glazing(0.5)
    for label, point, normal in cases[:2]:
        quality = "standard" if "shade" in label else "preview"
        r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality=quality)
        assert r.method == ("render" if "shade" in label else "hybrid") and not r.exact, (label, r.method)
        _check(r, *_stored(f"grey_room_glazing/{label}", point, normal))


def test_volume_cube_against_a_patch_render(clean_blender):
    from radiometer import api

    scene, cases = u.fog_cube()
    readings = api.measure_illuminance([c[1] for c in cases], [c[2] for c in cases], scene=scene, method="auto",
                                       quality="standard")
    for (label, point, normal), r in zip(cases, readings):
        assert not r.exact and r.method == "render", (label, r.method)
        _check(r, *_stored(f"fog_cube/{label}", point, normal))


def test_glossy_floor_onto_a_wall_meter_against_a_patch_render(clean_blender):
    from radiometer import api

    scene, [(label, point, normal)] = u.glossy_wall()
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality="standard")
    _check(r, *_stored(f"glossy_wall/{label}", point, normal))


def test_glossy_floor_onto_a_wall_meter_at_preview_seed_4(clean_blender):
    """Issue 18 (T8 QA, F1): seed 4 stopped after a 512-sample pilot that missed the floor's highlight
    and read 25 % low stating 1.6 %; the highlight floor (``measure/meter/sample_floors.py``) now holds it."""
    from radiometer import api

    scene, [(label, point, normal)] = u.glossy_wall()
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality="preview", seed=4)
    _check(r, *_stored(f"glossy_wall/{label}", point, normal))


def test_rendered_point_light_through_a_tilted_pane_states_float32_rounding(clean_blender):
    """Issue 18 (T8 QA, F3): rendered, it read 1.2e-7 low (one float32 ulp) stating 1.0e-8; a rendered
    reading's error now has a float32 floor (``meter.FLOAT32_FLOOR``) and no more."""
    from radiometer import api
    from radiometer.measure.meter import point_meter as meter

    scene, [(_label, point, normal)] = u.skylight_tilted("POINT")
    r = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview")
    assert r.illuminance == pytest.approx(u.skylight_tilted_expected("POINT"), rel=1e-6)  # right to float32
    _check(r, u.skylight_tilted_expected("POINT"), 0.0)
    assert meter.FLOAT32_FLOOR <= r.rel_std_error < 2 * meter.FLOAT32_FLOOR  # the floor, not a wide bound


def test_sun_through_double_glazing_into_a_foggy_room_seed_0(clean_blender):
    """Issue 18 (T8 QA, F5): the fog box (a Volume and no Surface) stopped the crossing proof, so the
    light bouncing between the panes (0.69 % at 25 deg), which a render cannot find, was neither added
    nor stated: seed 0 read -2.05 % stating 0.45 % (z -4.5). Its faces are null interfaces now: the
    panes are proved crossed and the sun is rendered for the fog, through one stand-in pane that renders
    the inter-pane light, so no bound is added for it (F2 fixed: 20 seeds cover without it)."""
    from radiometer import api
    from radiometer.measure.capture import glass, scene_capture
    from radiometer.radiometry.scene import scene_model

    scene, cases = u.foggy_room()
    label, point, normal = cases[0]
    model = scene_capture.capture(scene)
    fog = model.geometry.object_names.index("Room fog")
    assert not model.geometry.casts_shadow[fog] and not model.geometry.reflects[fog]
    assert [name for name, _lo, _hi in model.volumes] == ["Room fog"]
    [note] = glass.stack_notes(model)
    assert "rendered as one stand-in pane" in note and "24 mm deep" in note
    # The proof holds through the fog: the sun crosses both panes whole (inter-pane share 0.68 % at 25
    # deg, the test's own slab: R^2 of one pane at cos 25 deg) and is rendered for the fog alone.
    plan = scene_model.plan_direct(model, np.array([point], float), np.array([normal], float))
    R1 = u.fresnel_slab_r(math.cos(math.radians(u.WALL["elevation_deg"])), u.f32(u.WALL["ior"]))
    assert plan.interpane[0, 0] == pytest.approx(float(np.max(R1 * R1)), rel=1e-3)
    assert "Room fog" in plan.reason[0, 0] and "occluded" not in plan.reason[0, 0]
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality="preview", seed=0)
    assert not r.exact and r.rel_error_bound == 0.0
    _check(r, *_stored(f"foggy_room/{label}", point, normal))


def test_double_glazing_rendered_as_one_stand_in_pane(clean_blender):
    """Issue 18, F5: rendered as two thin panes, the sun through double glazing read -0.69 % (the light
    bouncing between the panes is a specular chain no render finds); the unit is rendered as ONE stand-in
    pane with the adding formula's T and R (the other pane clear), so ``render`` reads this suite's own
    Fresnel slab stacked (``double_glazing_optics``) to the sun disc's spread of T. A stack whose gap is
    deep next to its outline keeps a pane each (rays entering the gap from the side meet one pane)."""
    from radiometer import api
    from radiometer.measure.capture import glass, scene_capture
    from radiometer.measure.blender import scene_guard

    scene, cases = u.wall_double_glazing()
    label, point, normal = cases[0]
    panes = scene_capture.capture(scene).needs["thin_panes"]
    [(lead, group)] = glass.stand_in_stacks(panes)
    assert sorted(p.name for p in group) == ["Pane 1", "Pane 2"]
    with scene_guard.preserved_scene(scene) as snapshot:
        glass.swap_panes(snapshot, panes)
        names = {ob.name: ob.material_slots[0].material.name for ob in scene.objects if ob.name.startswith("Pane")}
        assert names[lead.name].startswith("radiometer thin pane")
        assert [n for k, n in names.items() if k != lead.name][0].startswith("radiometer clear pane")
    assert scene.objects["Pane 1"].material_slots[0].material.name == "double glazing"  # given back
    r = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview")
    assert r.illuminance == pytest.approx(u.wall_double_glazing_expected(label), rel=1e-4)
    assert r.rel_error_bound == 0.0  # the stand-in renders the light between the panes: nothing to bound
    scene.objects["Pane 2"].location.y = 0.5  # a 0.5 m gap next to a 1.2 m outline: no stand-in
    assert glass.stand_in_stacks(scene_capture.capture(scene).needs["thin_panes"]) == []
    # Separate thin panes miss that light (a specular chain): the reading is low by about its share
    # and states it as a bound.
    apart = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview")
    assert any("rendered as separate thin panes: its closed-form share" in note for note in apart.notes)
    assert apart.rel_error_bound > 0.005
    assert apart.illuminance < r.illuminance <= apart.illuminance * (1.0 + apart.rel_error_bound) * (1 + 1e-4)


def test_a_fog_box_with_a_surface_still_blocks(clean_blender):
    """A box with a Volume AND an opaque Surface is no null interface: it still casts shadows."""
    from radiometer.measure.capture import scene_capture

    scene, _cases = u.foggy_room()
    mat = scene.objects["Room fog"].material_slots[0].material
    tree = mat.node_tree
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    tree.links.new(diffuse.outputs[0], tree.nodes["Material Output"].inputs["Surface"])
    model = scene_capture.capture(scene)
    fog = model.geometry.object_names.index("Room fog")
    assert model.geometry.casts_shadow[fog] and model.geometry.reflects[fog]


def test_rendered_point_light_through_a_vertical_slab_states_no_edge_face_mirror(clean_blender):
    """Issue 18 (T8 QA, F4): rendered, the vertical Principled pane read right (-1.8e-7) but stated 69.6 %:
    the lamp's mirror image in the slab's 5 mm edge face (reachable only through the slab) was counted.
    A thin pane's edge faces give no mirror image; its two face planes still do."""
    from radiometer import api
    from radiometer.measure.capture import glass, scene_capture

    scene, [(_label, point, normal)] = u.principled_vertical()
    model = scene_capture.capture(scene)
    tris, _owners = glass.mirror_triangles(model)
    geom = next(iter(model.panes.values())).geometry
    offsets = tris.reshape(-1, 3) @ geom.normal
    assert len(tris) == 4 and all(np.min(np.abs(offsets - h)) < 1e-6 for h in geom.heights)
    assert np.all(np.min(np.abs(offsets[:, None] - np.array(geom.heights)[None, :]), axis=1) < 1e-6)
    r = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview")
    assert not any("mirror image" in note for note in r.notes)
    assert r.rel_std_error < 1e-5
    _check(r, u.principled_vertical_expected(), 0.0)

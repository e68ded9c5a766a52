"""The sun's first bounce as emitters (issue 31, the low sun: measure/meter/sun_bounce.py) against Cycles' own
Sun light, rendered as it is, where that converges (a morning sun through the demo room's window onto the floor),
and what a low-sun step leaves behind."""

import datetime as dt

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.demo import daylight
from radiometer.measure.analyses import sun_study
from radiometer.measure.blender import request as request_of, scene_guard
from radiometer.measure.meter import point_meter as meter

pytestmark = pytest.mark.usefixtures("clean_blender")

SITE = daylight.SITE
METERS = np.array([(-1.0, -1.0, 0.75), (0.5, 0.0, 0.75), (1.5, 1.5, 0.75), (0.0, 1.0, 1.8), (-1.5, 0.5, 0.75)])


def _room(pane_renders=True):
    scene = daylight.build(bpy.context.scene, pane_renders=pane_renders)
    scene.world = None
    return scene


def _principled(name, **inputs):
    """A new material: Blender's default Principled BSDF with ``inputs`` set."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    node = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    return mat


@pytest.mark.parametrize("pane_renders, principled_floor", [(True, False), (False, False), (True, True)])
def test_emitters_read_what_the_sun_light_reads(pane_renders, principled_floor):
    """A 9:00 equinox sun (22 deg) lights a floor patch that the meters' rays find easily: the Sun light's
    own render is the reference. Both readings at a 1 % target; |difference| within 4 combined s.e. With a
    Principled BSDF floor whose only layer is its diffuse base (Specular IOR Level 0), read as Lambertian."""
    scene = _room(pane_renders)
    if principled_floor:
        floor = bpy.data.objects["Floor"]
        floor.data.materials.clear()
        floor.data.materials.append(_principled("matte floor", **{"Base Color": (0.35, 0.3, 0.25, 1.0),
                                                                  "Specular IOR Level": 0.0, "Roughness": 0.4}))
    info = api.set_sun(scene, SITE["latitude_deg"], SITE["longitude_deg"], daylight.local_time((2026, 3, 20, 9, 0)))
    sun = bpy.data.objects[info["object"]]
    normals = np.tile((0.0, 0.0, 1.0), (len(METERS), 1))
    normals[3] = (0.0, 1.0, 0.0)  # facing the back wall, away from the window
    request = request_of.build(scene, target_rel_error=0.01, seed=5)
    lamp = meter.measure_illuminance(METERS, normals, request)
    with scene_guard.preserved_scene(scene) as snapshot:
        model = meter.capture_model(scene, request.view_layer)
        bounce, reason, plan = sun_study.sun_bounce_readings(request.but(seed=6), model, sun, info, METERS, normals,
                                                             snapshot)
    assert bounce is not None, reason
    assert plan.piece_count() > 0
    assert any("first bounce" in n for n in bounce[0].notes) or plan.notes
    for a, b in zip(lamp, bounce):
        se = np.hypot(a.rel_std_error * a.illuminance, b.rel_std_error * b.illuminance)
        assert abs(a.illuminance - b.illuminance) <= 4.0 * se, (a.illuminance, b.illuminance, se)
        assert not b.exact and b.illuminance > 0


def test_low_sun_step_reads_the_reveal_and_leaves_the_scene_as_it_was():
    """A 2 deg sun grazing the south facade: the room is lit only by the west reveal's sunlit strip and the
    sun's image in the pane. The step takes the emitters, states finite errors, and the scene is unchanged."""
    scene = _room()
    when = dt.datetime(2026, 3, 20, 6, 19, 39, tzinfo=dt.timezone.utc)  # London, the sun 2.0 deg high
    scene.view_layers[0].update()
    before = {name: len(getattr(bpy.data, name)) for name in ("objects", "meshes", "materials", "lights")}
    fingerprint = scene_guard.scene_fingerprint(scene)
    r = api.sun_study(METERS[:3], (0.0, 0.0, 1.0), [when], latitude_deg=SITE["latitude_deg"],
                      longitude_deg=SITE["longitude_deg"], scene=scene, quality="preview", seed=2)
    assert 1.5 < float(r.sun[0]["elevation_deg"]) < 2.5
    assert any("first bounce" in n for n in r.notes), r.notes
    assert np.all(np.isfinite(r.rel_std_error)) and np.all(r.illuminance > 0)
    assert scene_guard.scene_fingerprint(scene) == fingerprint
    assert {name: len(getattr(bpy.data, name)) for name in before} == before


def test_a_glossy_sunlit_surface_keeps_the_sun_rendered():
    """The Lambertian condition: a Principled floor in the sun is not a Lambertian emitter."""
    scene = _room()
    floor = bpy.data.objects["Floor"]
    mat = bpy.data.materials.new("glossy floor")
    ensure_node_tree(mat)  # a Principled BSDF
    floor.data.materials.clear()
    floor.data.materials.append(mat)
    info = api.set_sun(scene, SITE["latitude_deg"], SITE["longitude_deg"], daylight.local_time((2026, 3, 20, 12, 0)))
    request = request_of.build(scene)
    from radiometer.measure.meter import sun_bounce

    bounce = sun_bounce.plan(meter.capture_model(scene, request.view_layer), np.asarray(info["direction"]), 0.0023)
    assert not bounce.proven and "not Lambertian" in bounce.reason and "glossy floor" in bounce.reason
    assert "Specular IOR Level 0.5" in bounce.reason  # Blender's default: a dielectric layer over the diffuse


def test_a_principled_bsdf_is_lambertian_only_with_its_diffuse_base_alone():
    """``shader_kinds.lambertian_albedo``: each Principled layer or lobe turned on, or a texture on the base
    colour, refuses; with all off the base colour is the albedo."""
    from radiometer.measure.capture import shader_kinds

    matte = {"Base Color": (0.6, 0.5, 0.4, 1.0), "Specular IOR Level": 0.0}
    rgb, why = shader_kinds.lambertian_albedo(_principled("matte", **matte))
    assert why == "" and rgb == pytest.approx((0.6, 0.5, 0.4))
    for name, value in (("Metallic", 1.0), ("Transmission Weight", 0.5), ("Coat Weight", 0.2),
                        ("Sheen Weight", 0.3), ("Alpha", 0.5), ("Emission Strength", 2.0),
                        ("Diffuse Roughness", 0.5), ("Subsurface Weight", 0.1), ("Thin Film Thickness", 300.0)):
        rgb, why = shader_kinds.lambertian_albedo(_principled(name, **dict(matte, **{name: value})))
        assert rgb is None and name in why, (name, why)
    textured = _principled("textured", **matte)
    tree = textured.node_tree
    tex = tree.nodes.new("ShaderNodeTexChecker")
    tree.links.new(tex.outputs["Color"], next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
                   .inputs["Base Color"])
    rgb, why = shader_kinds.lambertian_albedo(textured)
    assert rgb is None and "linked" in why


def test_with_a_sky_the_step_reads_the_sun_as_emitters_and_the_parts_add_up():
    """With the overcast sky a 2 deg step reads the sun's first bounce as emitters (a dark pilot cannot
    show itself under a sky); its readings equal the sun's alone plus the sky's alone within 4 combined s.e."""
    scene = _room()
    when = dt.datetime(2026, 3, 20, 6, 19, 39, tzinfo=dt.timezone.utc)
    points, normals = METERS[:3], (0.0, 0.0, 1.0)
    common = dict(latitude_deg=SITE["latitude_deg"], longitude_deg=SITE["longitude_deg"], scene=scene,
                  quality="standard")
    both = api.sun_study(points, normals, [when], sky="overcast", seed=1, **common)
    assert any("with the sky, the sun's first bounce" in n for n in both.notes), both.notes
    sun = api.sun_study(points, normals, [when], seed=2, **common)
    # the sky alone: a step whose sun is below the horizon keeps the sky (the same horizontal illuminance)
    night = dt.datetime(2026, 3, 20, 0, 0, tzinfo=dt.timezone.utc)
    sky = api.sun_study(points, normals, [night], sky="overcast", seed=3, **common)
    total = both.illuminance[0]
    parts = sun.illuminance[0] + sky.illuminance[0]
    se = np.sqrt((both.rel_std_error[0] * total) ** 2 + (sun.rel_std_error[0] * sun.illuminance[0]) ** 2
                 + (sky.rel_std_error[0] * sky.illuminance[0]) ** 2)
    assert np.all(np.abs(total - parts) <= 4.0 * se), (total, parts, se)


def test_a_step_cancelled_with_its_emitters_in_the_scene_leaves_it_as_it_was(monkeypatch):
    """Cancelled once the sun's first-bounce emitters are in the scene: the emitter mesh, its material and the
    hidden sun are undone; the fingerprint and the data-block counts are as before."""
    from radiometer.errors import MeasurementCancelled
    from radiometer.measure.meter import sun_bounce

    scene = _room()
    scene.view_layers[0].update()
    before = {name: len(getattr(bpy.data, name)) for name in ("objects", "meshes", "materials", "lights", "worlds")}
    fingerprint = scene_guard.scene_fingerprint(scene)
    added = []
    add = sun_bounce.add_emitters
    monkeypatch.setattr(sun_bounce, "add_emitters", lambda *a, **k: added.append(1) or add(*a, **k))
    when = dt.datetime(2026, 3, 20, 6, 19, 39, tzinfo=dt.timezone.utc)
    with pytest.raises(MeasurementCancelled):
        api.sun_study(METERS[:3], (0.0, 0.0, 1.0), [when], latitude_deg=SITE["latitude_deg"],
                      longitude_deg=SITE["longitude_deg"], scene=scene, quality="preview",
                      cancelled=lambda: bool(added))
    assert added
    scene.view_layers[0].update()
    assert scene_guard.scene_fingerprint(scene) == fingerprint
    assert {name: len(getattr(bpy.data, name)) for name in before} == before

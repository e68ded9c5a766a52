"""Glare rates only what the eye sees (issue 32), and EN 12464-1 compliance measures the electric lighting.

The test office (tests/bpy/office.py): four 0.6 m ceiling panels, eye at 1.2 m looking +y. A vertical
opaque baffle at y = 0.8 m hanging from the ceiling hides the two far panels (y = 1.4 m) from the eye: by
similar triangles the rays from the eye to them cross y = 0.8 m between z = 2.44 m and 2.71 m. Down to
z = 2.3 m it hides them whole; down to 2.6 m only the part whose rays pass above 2.6 m (the share of the
solid angle integrated here independently on a 400 x 400 grid of each panel)."""

import math
import os
import sys

import bmesh
import bpy
import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import office  # noqa: E402
from test_glare import _emissive_square, _ies_luminaires, _levin, _panel_integrals  # noqa: E402

from radiometer import api  # noqa: E402

BAFFLE_Y = 0.8


def _baffle(scene, z0):
    mesh = bpy.data.meshes.new("Baffle")
    mesh.from_pydata([(-3, BAFFLE_Y, z0), (3, BAFFLE_Y, z0), (3, BAFFLE_Y, 3.0), (-3, BAFFLE_Y, 3.0)], [], [(0, 1, 2, 3)])
    mesh.materials.append(office.grey_material("baffle"))
    obj = bpy.data.objects.new("Baffle", mesh)
    scene.collection.objects.link(obj)
    return obj


def _terms(names_xy, lum):
    eye, view = np.array(office.EYE), np.array(office.VIEW)
    total = 0.0
    for x, y in names_xy:
        omega, _projected = _panel_integrals(eye, view, (x, y, office.PANEL_Z), office.PANEL)
        H, T, R = office.PANEL_Z - eye[2], abs(x - eye[0]), y - eye[1]
        total += lum ** 2 * omega / _levin(math.degrees(math.atan(math.hypot(H, T) / R)),
                                           math.degrees(math.atan2(T, H))) ** 2
    return total


def test_baffle_hides_area_ies_and_emissive_sources(clean_blender, tmp_path):
    """Panels 3 and 4 behind the baffle, as an area light, an IES luminaire (0.6 m opening) and an emitting
    mesh: each listed as hidden by 'Baffle', UGR that of panels 1 and 2 alone (independent CIE 117 sum)."""
    scene = bpy.context.scene
    panels = office.build(scene)
    _baffle(scene, 2.3)
    x3, y3 = office.PANELS[2]
    x4, y4 = office.PANELS[3]
    for obj in panels[2:]:
        bpy.data.objects.remove(obj)
    strength = office.PANEL_POWER / (math.pi * office.PANEL ** 2)
    _emissive_square(scene, "Glow 3", (x3, y3, office.PANEL_Z), office.PANEL, strength)
    _ies_luminaires(scene, tmp_path, office.panel_luminance() * office.PANEL ** 2)  # at all four places
    for obj in [o for o in scene.objects if o.name.startswith("Luminaire")]:
        if abs(obj.location.x - x4) > 1e-6 or abs(obj.location.y - y4) > 1e-6:
            bpy.data.objects.remove(obj)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="preview")
    hidden = {d["name"]: d["reason"] for d in g.left_out}
    assert sorted(s["name"] for s in g.sources) == ["Panel 1", "Panel 2"], (g.sources, g.left_out)
    assert len(hidden) == 2 and all("hidden from the eye by 'Baffle'" in r for r in hidden.values()), hidden
    assert any(n.startswith("Glow 3") for n in hidden) and any(n.startswith("Luminaire") for n in hidden)
    assert all(s["visible_fraction_bounds"] == (1.0, 1.0) for s in g.sources)
    expected = 8 * math.log10(0.25 / g.background_luminance * _terms(office.PANELS[:2], office.panel_luminance()))
    assert abs(g.ugr - expected) < 0.01, (g.ugr, expected)
    assert math.isfinite(g.ugr_std_error) and not g.error_unknown and "hidden from the eye" in g.summary()


def _seen_share(x, y, z_cut, cells=400):
    """Share of a down-facing panel's solid angle whose rays from the eye cross y = BAFFLE_Y below z_cut."""
    eye = np.array(office.EYE)
    t = (np.arange(cells) + 0.5) / cells * office.PANEL - office.PANEL / 2
    gx, gy = np.meshgrid(x + t, y + t)
    r = np.stack([gx - eye[0], gy - eye[1], np.full_like(gx, office.PANEL_Z - eye[2])], -1)
    d = np.linalg.norm(r, axis=-1)
    w = r[..., 2] / d ** 3
    z_at = eye[2] + r[..., 2] * (BAFFLE_Y - eye[1]) / r[..., 1]
    return float((w * (z_at < z_cut)).sum() / w.sum())


def test_partly_hidden_panels_are_cut_to_what_the_eye_sees(clean_blender):
    scene = bpy.context.scene
    office.build(scene)
    _baffle(scene, 2.6)
    g = api.glare_ugr(office.EYE, office.VIEW, scene=scene, quality="preview")
    by = {s["name"]: s for s in g.sources}
    assert len(by) == 4
    for name, (x, y) in zip(("Panel 3", "Panel 4"), office.PANELS[2:]):
        share = _seen_share(x, y, 2.6)
        lo, hi = by[name]["visible_fraction_bounds"]
        assert 0.3 < share < 0.9 and lo <= share <= hi and hi - lo < 0.05, (share, lo, hi)
        assert by[name]["visible_fraction"] == pytest.approx(share, abs=0.005)
        omega, _ = _panel_integrals(np.array(office.EYE), np.array(office.VIEW), (x, y, office.PANEL_Z), office.PANEL)
        assert by[name]["solid_angle"] == pytest.approx(omega * by[name]["visible_fraction"], rel=1e-4)  # 400² cells
        assert "partly hidden by 'Baffle'" in by[name]["visibility"]
    lo, hi = g.ugr_visibility_range
    assert lo <= g.ugr <= hi


def test_eye_outside_the_room_rates_nothing_behind_the_wall(clean_blender):
    scene = bpy.context.scene
    office.build(scene)
    g = api.glare_ugr((0.0, -2.5, 1.2), office.VIEW, scene=scene, quality="preview")
    assert not g.sources and g.ugr == -math.inf
    assert sorted(d["name"] for d in g.left_out) == ["Panel 1", "Panel 2", "Panel 3", "Panel 4"]
    assert all("hidden from the eye by 'Room'" in d["reason"] for d in g.left_out)
    text = g.summary()
    assert "4 hidden from the eye" in text and "inf" not in text and "nan" not in text


def test_compliance_in_a_sunlit_room_measures_the_electric_lighting(clean_blender, build):
    """The office without its ceiling, under a sun and a grey emitting world: the compliance grid equals
    the grid measured with the sun and the world switched off by hand, is far below the sunlit grid, and
    the table says daylight was off; the scene comes back as it was."""
    scene = bpy.context.scene
    office.build(scene)
    room = bpy.data.objects["Room"]
    bm = bmesh.new()
    bm.from_mesh(room.data)
    bmesh.ops.delete(bm, geom=[f for f in bm.faces if f.normal.z < -0.5], context="FACES")
    bm.to_mesh(room.data)
    bm.free()
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy = 20.0  # W/m²: 13 660 lx on the floor
    scene.collection.objects.link(sun)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    world = scene.world
    plane = build.plane(scene, size=1.0, location=(0.0, 0.5, 0.75), name="Work Plane")
    plane.scale = (4.0, 2.4, 1.0)
    plane.hide_render = True
    sunlit = api.illuminance_grid(plane, resolution=(4, 3), quality="preview")
    out = api.en12464_compliance(plane, "office_writing", quality="preview", scene=scene)
    assert not sun.hide_render and scene.world == world  # restored
    sun.hide_render = True
    scene.world = None
    electric = api.illuminance_grid(plane, resolution=(4, 3), quality="preview")
    sun.hide_render, scene.world = False, world
    checks = {c["quantity"]: c for c in out["checks"]}
    g = out["grid"]
    assert sunlit.stats["avg"] > 3 * electric.stats["avg"]
    # the same electric lighting on the compliance grid (its own EN 12464-1 spacing): means agree
    se = g.stats["avg"] * float(np.max(g.rel_std_error)) + electric.stats["avg"] * float(np.max(electric.rel_std_error))
    assert abs(g.stats["avg"] - electric.stats["avg"]) < 3 * se + 0.05 * electric.stats["avg"]
    assert checks["Ēm"]["achieved"] == pytest.approx(0.8 * g.stats["avg"])
    assert "sun(s) 'Sun'" in checks["Ēm"]["note"] and "emitting world" in checks["Ēm"]["note"]
    assert "electric lighting only" in out["lighting"]
    # The client report measures its grids with the scene as it is: it says daylight is included.
    from radiometer.measure.reports import client_report

    assert "DAYLIGHT INCLUDED" in client_report.daylight_words(scene) and "'Sun'" in client_report.daylight_words(scene)
    sun.hide_render, scene.world = True, None
    assert client_report.daylight_words(scene) == ""

"""The proven sky component (measure/analyses/sky_component.py, radiometry/skies/sky_aperture.py) against Cycles: in
the side-lit room with every surface black and a black ground, the rendered daylight factor IS the
direct sky through the window, so the closed form must lie within the render's stated error."""

import importlib.util
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


def _components(scene, points, ground_reflectance=0.0, normal=(0.0, 0.0, 1.0)):
    pts = np.asarray(points, float)
    return sky_component.sky_components(scene, pts, np.broadcast_to(normal, pts.shape),
                                        ground_reflectance=ground_reflectance, horizontal_lux=SKY_HORIZONTAL_LUX)


def test_black_room_render_equals_the_closed_form_sky_component(clean_blender, monkeypatch):
    room = _room()
    monkeypatch.setattr(room, "RHO", {"floor": 0.0, "ceiling": 0.0, "walls": 0.0})
    scene = bpy.context.scene
    room.build_blender(scene)
    points = room.POINTS + [(1.2, 0.4, 1.6)]
    sc = _components(scene, points)
    # method="render": the whole render (method="auto" would now read the closed form itself, issue 31)
    rs = api.daylight_factor(points, ground_reflectance=0.0, target_rel_error=0.01, seed=2, method="render")
    for r, c in zip(rs, sc):
        assert c.sky_lux is not None and c.reason == "" and c.apertures == 1, c.reason
        df_sc = 100.0 * c.sky_lux / SKY_HORIZONTAL_LUX
        se = r.rel_std_error * r.daylight_factor
        print(f"black room: rendered DF {r.daylight_factor:.5f} % +- {se:.5f}, closed-form SC {df_sc:.5f} %")
        assert not r.exact and abs(r.daylight_factor - df_sc) <= 4.0 * se
        assert c.ground_lux == 0.0


def test_black_room_behind_an_obstruction_render_equals_the_clipped_closed_form(clean_blender, monkeypatch):
    """A black room facing a black block: the rendered daylight factor IS the sky seen past the block through
    the window, so the closed form over the window minus the block's silhouette must lie within the render's
    stated error (points that see sky above the block, one that sees none)."""
    room = _room()
    monkeypatch.setattr(room, "RHO", {"floor": 0.0, "ceiling": 0.0, "walls": 0.0})
    monkeypatch.setattr(room, "RHO_EXTRA", {"obstruction": 0.0})
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + room.obstruction_quads())
    points = [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (1.2, 0.4, 1.6), (2.0, 2.5, 0.85)]
    sc = _components(scene, points)
    rs = api.daylight_factor(points, ground_reflectance=0.0, target_rel_error=0.01, seed=3, method="render")
    for r, c in zip(rs, sc):
        assert c.sky_lux is not None and c.clipped == 1, c.reason
        df_sc = 100.0 * c.sky_lux / SKY_HORIZONTAL_LUX
        if df_sc == 0.0:  # the block hides all the sky seen through the window from there: no light at all
            assert r.daylight_factor == 0.0
            continue
        se = r.rel_std_error * r.daylight_factor
        print(f"black room, block: rendered DF {r.daylight_factor:.5f} % +- {se:.5f}, clipped closed form "
              f"{df_sc:.5f} %")
        assert abs(r.daylight_factor - df_sc) <= 4.0 * se
    assert sc[-1].sky_lux == 0.0 and all(c.sky_lux > 0.0 for c in sc[:-1])


def test_black_room_behind_a_pane_and_an_obstruction_render_equals_the_bounded_closed_form(clean_blender, monkeypatch):
    """The same black room and block, a 6 mm pane in the window: the sky past the block's silhouette weighted by
    the pane's T(theta), with its hard bound, against the whole render."""
    room = _room()
    monkeypatch.setattr(room, "RHO", {"floor": 0.0, "ceiling": 0.0, "walls": 0.0})
    monkeypatch.setattr(room, "RHO_EXTRA", {"obstruction": 0.0})
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + room.obstruction_quads())
    points = [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (1.2, 0.4, 1.6)]
    bare = _components(scene, points)
    room.add_pane_blender(scene)
    sc = _components(scene, points)
    rs = api.daylight_factor(points, ground_reflectance=0.0, target_rel_error=0.01, seed=3, method="render")
    for r, c, b in zip(rs, sc, bare):
        assert c.sky_lux is not None and c.clipped == 1 and c.glazed == 1, c.reason
        assert c.ground_lux == 0.0  # these points see no ground through the window
        assert 0.0 < c.bound_lux < 0.02 * c.sky_lux and c.sky_lux < 0.93 * b.sky_lux  # the pane passes < 93 %
        df_sc, df_bound = (100.0 * v / SKY_HORIZONTAL_LUX for v in (c.sky_lux, c.bound_lux))
        se = r.rel_std_error * r.daylight_factor
        print(f"black room, pane, block: rendered DF {r.daylight_factor:.5f} % +- {se:.5f}, closed form {df_sc:.5f} "
              f"+- {df_bound:.5f} % (bound)")
        assert abs(r.daylight_factor - df_sc) <= 4.0 * se + df_bound


def test_refusals_say_why(clean_blender):
    room = _room()
    scene = bpy.context.scene
    room.build_blender(scene)
    out = _components(scene, [(2.0, -2.0, 1.0), (2.0, 1.5, 0.85), (2.0, 2.0, 10.0)], ground_reflectance=0.2)
    # outdoors, in front of the wall: outside the room's closed shell, so the sky over the directions that meet no
    # surface (the room hides part of it); high above the room nothing does: the overcast sky's E_h, 10 000 lx
    assert "outside the only closed shell" in out[0].past_every_surface and out[0].ground_lux is None
    assert 0.5 * SKY_HORIZONTAL_LUX < out[0].sky_lux < SKY_HORIZONTAL_LUX
    assert out[2].sky_lux == pytest.approx(SKY_HORIZONTAL_LUX, rel=1e-9)
    assert out[1].sky_lux > 0 and out[1].ground_lux == 0.0  # the point at 0.85 m sees no ground through the window
    high = _components(scene, [(2.0, 2.5, 2.0)], ground_reflectance=0.2, normal=(0.0, -1.0, 0.0))[0]
    assert high.sky_lux > 0 and high.ground_lux > 0  # facing the window from 2 m: its lower part shows the ground
    # an obstruction outside in front of the window: the sky past its silhouette (issue 31), less than the open sky
    open_lux = _components(scene, [(2.0, 1.5, 0.85)])[0].sky_lux
    me = bpy.data.meshes.new("block")
    me.from_pydata([(0.0, -3.0, 0.0), (4.0, -3.0, 0.0), (4.0, -3.0, 6.0), (0.0, -3.0, 6.0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("block", me))
    blocked = _components(scene, [(2.0, 1.5, 0.85)])[0]
    assert blocked.clipped == 1 and 0.0 < blocked.sky_lux < 0.8 * open_lux and blocked.ground_lux == 0.0
    # one reaching from outside through the window back over the point: its part in front of the point clipped
    me = bpy.data.meshes.new("awning")
    me.from_pydata([(1.5, -3.0, 1.0), (2.5, -3.0, 1.0), (2.5, 2.5, 1.9), (1.5, 2.5, 1.9)], [], [(0, 1, 2, 3)])
    awning = bpy.data.objects.new("awning", me)
    scene.collection.objects.link(awning)
    under = _components(scene, [(2.0, 1.5, 0.85)])[0]
    assert under.clipped == 1 and 0.0 <= under.sky_lux < blocked.sky_lux
    bpy.data.objects.remove(awning)
    # a board through the point itself: refused, not clipped
    me = bpy.data.meshes.new("board")
    me.from_pydata([(1.8, 1.5, 0.5), (2.2, 1.5, 0.5), (2.2, 1.5, 1.5), (1.8, 1.5, 1.5)], [], [(0, 1, 2, 3)])
    board = bpy.data.objects.new("board", me)
    scene.collection.objects.link(board)
    refused = _components(scene, [(2.0, 1.5, 0.85)])[0]
    assert refused.sky_lux is None and "passes within" in refused.reason, refused.reason
    bpy.data.objects.remove(board)
    # a colour-neutral pane in the opening: its T(theta) weighs the sky, with a hard bound (issue 31); the
    # open window's closed form times the pane's T at normal incidence bounds it from above, and times its
    # T at the steepest incidence the point sees from below (T falls with the angle)
    bpy.data.objects.remove(bpy.data.objects["block"])
    open_sky = _components(scene, [(2.0, 1.5, 0.85)])[0].sky_lux
    room.add_pane_blender(scene)
    glazed = _components(scene, [(2.0, 1.5, 0.85)])[0]
    from radiometer.radiometry.scene import thin_glass

    x0, x1, z0, z1 = room.WINDOW
    steepest = min(abs(1.5) / np.linalg.norm(np.array([x, 1.5, z - 0.85])) for x in (x0, x1) for z in (z0, z1))
    t_lo, t_hi = (float(thin_glass.slab(c, room.IOR, room.PANE)[0][..., 1]) for c in (steepest, 1.0))
    assert glazed.glazed == 1 and glazed.apertures == 1 and 0 < glazed.bound_lux < 0.01 * glazed.sky_lux
    assert t_lo * open_sky - glazed.bound_lux <= glazed.sky_lux <= t_hi * open_sky + glazed.bound_lux

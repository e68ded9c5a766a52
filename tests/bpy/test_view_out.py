"""api.view_out (EN 17037 view out from the scene's geometry) in the side-lit room of the daylight tests
(tests/bpy/daylight_room.py) built in Blender: its window's sight angle in closed form (the jambs'
azimuths from the eye), a pane in the opening looked through, a block outside as the landscape, "not
assessed" where nothing outside is modelled, scene units other than metres, nothing left changed."""

import importlib.util
import math
import pathlib

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.errors import RadiometerError


def _load(name):
    spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


room = _load("daylight_room")
EYES = [(2.0, 1.5, 1.2), (1.0, 2.5, 1.2), (3.0, 2.5, 1.2), (2.0, 0.8, 1.2)]


def _angle(eye):
    x0, x1 = room.WINDOW[:2]
    return math.degrees(math.atan2(x1 - eye[0], eye[1]) - math.atan2(x0 - eye[0], eye[1]))


def _state():
    return sorted(ob.name for ob in bpy.data.objects), sorted(m.name for m in bpy.data.meshes)


def test_view_out_through_a_glazed_window_onto_a_block(clean_blender):
    scene = bpy.context.scene
    room.build_blender(scene, room.quads() + room.obstruction_quads(gap=25.0, width=60.0, height=8.0))
    room.add_pane_blender(scene)
    before = _state()
    r = api.view_out(EYES, scene=scene)
    assert r.openings == 1
    for eye, angle, layers in zip(EYES, r.horizontal_sight_angle_deg, r.layers):
        assert abs(angle - _angle(eye)) <= 0.5          # the pane is looked through
        assert layers == ["sky", "landscape", "ground"]
    assert np.all(r.outside_distance_m >= 25.0) and np.all(r.outside_distance_m < 40.0)
    # the angles are 67, 33, 33, 103 deg: 75 % of the eyes reach 33 deg (medium), 25-40 m (medium), 3 layers
    assert r.en17037["level"] == "medium"
    assert r.en17037["values"]["points"] == 4
    assert _state() == before


def test_view_out_not_assessed_without_surroundings_and_in_millimetres(clean_blender):
    scene = bpy.context.scene
    room.build_blender(scene)
    r = api.view_out(EYES[0], scene=scene)
    assert r.en17037["level"] == "not assessed" and "nothing outside" in r.en17037["note"]
    assert r.layers == [["sky", "ground"]]
    # the same room in millimetres (scale_length 0.001): eyes in scene units, angles and metres the same
    ob = scene.objects["room"]
    ob.scale = (1000.0, 1000.0, 1000.0)
    scene.unit_settings.scale_length = 0.001
    r_mm = api.view_out([v * 1000.0 for v in EYES[0]], scene=scene)
    assert r_mm.horizontal_sight_angle_deg[0] == pytest.approx(r.horizontal_sight_angle_deg[0], abs=1e-9)
    assert np.allclose(r_mm.eyes, [EYES[0]])
    with pytest.raises(RadiometerError, match="eyes"):
        api.view_out([1.0, 2.0], scene=scene)

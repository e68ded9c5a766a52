"""Issue 18: the sample floor for meters lit by a glossy highlight (``measure/meter/sample_floors.py``; its
coverage is measured in bench/glossy_highlight_floor.py and bench/qa_glass_fog.md F1): the floor's size
against a hand computation of the highlight's geometry, and where it does not apply."""

import importlib.util
import math
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

HERE = pathlib.Path(__file__).resolve().parent


def _scenes():
    spec = importlib.util.spec_from_file_location("_tsf_scenes", HERE / "glass_fog_unseen_scenes.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _floor(scene, point, normal, which="highlight_floor"):
    from radiometer.measure.meter import point_meter as meter, sample_floors

    model = meter.capture_model(scene, scene.view_layers[0])
    return getattr(sample_floors, which)(model, np.array([point], float), np.array([normal], float))


def _roughness(value):
    mat = bpy.data.materials["metal floor 0.15"]
    [node] = [nd for nd in mat.node_tree.nodes if "Roughness" in nd.inputs]
    node.inputs["Roughness"].default_value = value


def test_highlight_floor_of_a_glossy_floor_by_hand(clean_blender):
    """Wall meter at (2, 0, 0.6) facing -x, a 0.5 m area light at (0, 0, 2.2) facing down, a GGX floor of
    roughness 0.15 at z = 0: the light's image at z = -2.2 is seen through the floor point (1.5714, 0, 0),
    over a path L = |(-2, 0, -2.8)| = 3.4409 m; Omega = 0.25 x cos_l / L^2 + pi (1.3 x 0.15^2)^2 and the
    floor 100 pi / (Omega x cos_m)."""
    u = _scenes()
    scene, [(_label, point, normal)] = u.glossy_wall()
    floor, names = _floor(scene, point, normal)
    at = np.array([2.0 - 2.0 * 0.6 / 2.8, 0.0, 0.0])
    path = math.hypot(2.0, 2.8)
    cos_m = 2.0 / path
    cos_l = 2.2 / float(np.linalg.norm(at - [0.0, 0.0, 2.2]))
    omega = 0.25 * cos_l / path ** 2 + math.pi * (1.3 * 0.15 ** 2) ** 2
    expected = 100.0 * math.pi / (omega * cos_m)
    assert floor[0] == pytest.approx(expected, rel=1e-3) and names == ["'area' in 'Floor'"]
    # a mirror-sharp floor is the sharp-mirror bound's case, a rough one's highlight a pilot finds
    for rough in (0.05, 0.7):
        _roughness(rough)
        assert _floor(scene, point, normal) == (None, []), rough
    # a meter facing away from the floor (its horizon hides the mirror point): no floor
    _roughness(0.15)
    assert _floor(scene, (2.0, 0.0, 0.6), (0.0, 0.0, 1.0))[0] is None



def test_a_dielectric_highlight_gets_a_floor_too(clean_blender):
    """Issue 18: a polished Principled floor (Metallic 0, roughness 0.15) read the wall meter's highlight
    low at preview (35 of 50 seeds within 1.96 s.e., worst z -4.35; bench/glossy_highlight_floor.json):
    its specular layer is a glossy reflector like a metal's, with the same floor. Up to
    DIELECTRIC_ROUGHNESS_MAX (0.3; float32 0.30000001 counts); IOR 1 reflects nothing; a smooth coat on a
    rough base counts by its own roughness."""
    from radiometer.measure.meter import sample_floors

    u = _scenes()
    scene, [(_label, point, normal)] = u.glossy_wall()
    node = u.principled_floor(0.15)
    floor, names = _floor(scene, point, normal)
    assert floor is not None and floor[0] > 20000 and names == ["'area' in 'Floor'"]
    node.inputs["Roughness"].default_value = 0.3
    assert _floor(scene, point, normal)[0] is not None
    node.inputs["Roughness"].default_value = 0.5  # wide and weak: measured to need none (88-90 % either way)
    assert _floor(scene, point, normal) == (None, [])
    node.inputs["Roughness"].default_value = 0.15
    node.inputs["IOR"].default_value = 1.0  # no Fresnel reflection at all
    assert _floor(scene, point, normal) == (None, [])
    node.inputs["Roughness"].default_value = 0.6
    node.inputs["IOR"].default_value = 1.5
    node.inputs["Coat Weight"].default_value = 1.0
    node.inputs["Coat Roughness"].default_value = 0.2
    assert sample_floors.glossy_roughness(bpy.data.materials["metal floor 0.15"]) == pytest.approx(0.2)
    assert _floor(scene, point, normal)[0] is not None


def test_an_emitting_mesh_seen_in_a_glossy_floor_gets_the_same_floor(clean_blender):
    """Issue 18: the glossy wall's area light as an emitting mesh of the same size and place read the
    highlight 5.7 % low on average at preview (36 of 50 seeds within 1.96 s.e., worst z -23; after: 46/50,
    every one within 3; bench/glossy_highlight_floor.json, --light emissive). Its image is a small bright
    region like a light's: the floor is the same hand computation as for the area light."""
    u = _scenes()
    scene, [(_label, point, normal)] = u.glossy_wall()
    area_floor, _names = _floor(scene, point, normal)
    u.emitting_panel(scene)
    floor, names = _floor(scene, point, normal)
    assert floor[0] == pytest.approx(area_floor[0], rel=1e-6) and names == ["'Panel [panel emission]' in 'Floor'"]
    scene.objects["Panel"].visible_glossy = False  # no glossy ray sees it: no highlight
    assert _floor(scene, point, normal) == (None, [])

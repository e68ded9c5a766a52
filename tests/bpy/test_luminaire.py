"""Luminaires: Cycles' own IES facts measured by rendering, and imported photometric files read
exactly by the meter (analytic) and by Cycles (render), axially symmetric and asymmetric, rotated.

Renders use the independent reference harness (tests/bpy/reference.py: a tiny white diffuse patch
seen by an orthographic camera, E = pi x pixel); a delta light gives it one exact sample, so the
rendered numbers agree to float32 precision at tabulated angles.
"""

import importlib.util
import math
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytest.importorskip("OpenEXR")

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402
from radiometer.radiometry.photometry import photometric_files as pf  # noqa: E402


def _load(name):
    spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).with_name(f"{name}.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")


def ies_text(v, h, cd, multiplier=1.0):
    out = ["IESNA:LM-63-2002", "[MANUFAC] Test", "TILT=NONE",
           f"1 -1 {multiplier:g} {len(v)} {len(h)} 1 2 0 0 0", "1 1 10",
           " ".join(f"{x:g}" for x in v), " ".join(f"{x:g}" for x in h)]
    out += [" ".join(f"{x:.10g}" for x in row) for row in cd]
    return "\n".join(out) + "\n"


V = np.arange(0.0, 90.0 + 1e-9, 5.0)


def asymmetric(v, c):
    """A smooth asymmetric distribution, pole-consistent (same value at v = 0 for every C)."""
    v, c = np.radians(v), np.radians(c)
    return 300.0 + 200.0 * np.sin(v) * (1.0 + 0.6 * np.cos(c) + 0.3 * np.sin(2.0 * c))


def axial(v):
    return 900.0 * np.cos(np.radians(v)) ** 3 + 20.0


@pytest.fixture
def scene(clean_blender, build):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    build.black_world(s)
    return s


def _direction(matrix, v_deg, c_deg):
    """World direction of (vertical, C) in Radiometer's convention for a light with this matrix."""
    v, c = math.radians(v_deg), math.radians(c_deg)
    local = np.array([math.sin(v) * math.cos(c), math.sin(v) * math.sin(c), -math.cos(v)])
    d = np.asarray(matrix)[:3, :3] @ local
    return d / np.linalg.norm(d)


# --- Cycles' own IES texture: orientation, normalisation, interpolation ---------------------

def _bare_ies_light(scene, text, energy=1.0):
    data = bpy.data.lights.new("ies", "POINT")
    data.shadow_soft_size = 0.0
    data.energy = energy
    data.use_nodes = True
    tree = data.node_tree
    node = tree.nodes.new("ShaderNodeTexIES")
    node.mode = "INTERNAL"
    node.ies = bpy.data.texts.new("raw.ies")
    node.ies.from_string(text)
    tree.links.new(node.outputs["Fac"], tree.nodes["Emission"].inputs["Strength"])
    obj = bpy.data.objects.new("ies", data)
    scene.collection.objects.link(obj)
    return obj


def _rendered_intensity(scene, origin, direction, distance=2.0):
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    e, _rel, _ = reference.reference_irradiance(scene, tuple(np.asarray(origin) + distance * d), tuple(-d),
                                                target_rel_error=1e-3, max_seconds=20.0)
    return e[1] * distance**2            # W/sr (white light: every channel alike)


def test_cycles_ies_orientation_normalisation_and_interpolation(scene):
    # Distinct C planes: 100 x (1, 2, 5, 3) + 50 cos(v); a bare IES Texture (default vector).
    h = [0.0, 90.0, 180.0, 270.0, 360.0]
    planes = [1.0, 2.0, 5.0, 3.0, 1.0]
    v = np.arange(0.0, 180.0 + 1e-9, 15.0)
    cd = [100.0 * k + 50.0 * np.cos(np.radians(v)) for k in planes]
    _bare_ies_light(scene, ies_text(v, h, cd), energy=2.0)
    s = 1.0 / math.sqrt(3.0)                                    # 60 deg from the nadir
    got = {name: _rendered_intensity(scene, (0, 0, 0), d) * pf.CYCLES_IES_EFFICACY / 2.0
           for name, d in (("-Y", (0, -1, -s)), ("-X", (-1, 0, -s)), ("+Y", (0, 1, -s)), ("+X", (1, 0, -s)))}
    at60 = 50.0 * math.cos(math.radians(60.0))
    # Cycles: C0 along local -Y, C90 along -X, C180 along +Y, C270 along +X (mirrored against
    # LM-63's counter-clockwise-from-above), and energy E gives E * cd / 177.83 W/sr.
    for name, plane in (("-Y", 1.0), ("-X", 2.0), ("+Y", 5.0), ("+X", 3.0)):
        assert got[name] == pytest.approx(100.0 * plane + at60, rel=2e-4), name
    # Interpolation between tabulated angles is Catmull-Rom on indices (v = 50 deg, C = 135 deg:
    # direction with atan2(x, y) + pi = 135 deg).
    c_cycles, v_test = math.radians(135.0 - 180.0), math.radians(50.0)
    d = (math.sin(v_test) * math.sin(c_cycles), math.sin(v_test) * math.cos(c_cycles), -math.cos(v_test))
    table = pf.cycles_ies_table(ies_text(v, h, cd))
    expected = pf.catmull_rom_table(*table, 135.0, 50.0) / pf.CYCLES_CANDELA_TO_WATT
    linear = 100.0 * 3.5 + 50.0 * (2 * math.cos(math.radians(45.0)) + math.cos(math.radians(60.0))) / 3
    rendered = _rendered_intensity(scene, (0, 0, 0), d) * pf.CYCLES_IES_EFFICACY / 2.0
    assert rendered == pytest.approx(expected, rel=5e-4)
    assert abs(expected - linear) / expected > 5e-3           # the test can tell cubic from linear


# --- imported luminaires read by the meter and by Cycles ---------------------------------------

CASES = {
    "axial": ([0.0], lambda v, c: axial(v)),
    "asymmetric": (list(np.arange(0.0, 360.0 + 1e-9, 30.0)), asymmetric),
}
ANGLES = [(0.0, 0.0), (30.0, 0.0), (45.0, 120.0), (60.0, 210.0), (20.0, 300.0), (85.0, 90.0)]


@pytest.mark.parametrize("case", sorted(CASES))
def test_imported_luminaire_analytic_and_rendered(scene, tmp_path, case):
    h, func = CASES[case]
    cd = [func(V, c) for c in h]
    path = tmp_path / f"{case}.ies"
    path.write_text(ies_text(V, h, cd, multiplier=0.5))
    photometry = api.read_photometry(str(path))
    obj = api.import_luminaire(str(path), location=(0.2, -0.1, 3.0), rotation_euler=(0.4, -0.25, 0.9))
    bpy.context.view_layer.update()
    m = np.array(obj.matrix_world)
    points, normals, expected = [], [], []
    for k, (v, c) in enumerate(ANGLES):
        d = _direction(m, v, c)
        r = 1.5 + 0.25 * k
        n = -d + np.array([0.2, -0.1, 0.15])
        n /= np.linalg.norm(n)
        points.append(m[:3, 3] + r * d)
        normals.append(n)
        intensity = 0.5 * func(np.array(v), np.array(c))          # candela multiplier 0.5
        assert photometry.candela_at(v, c) == pytest.approx(intensity, rel=1e-9)
        expected.append(intensity * float(n @ -d) / r**2)
    expected = np.array(expected)
    analytic = api.measure_illuminance(np.array(points), np.array(normals), method="analytic")
    lux = np.array([x.illuminance for x in analytic])
    np.testing.assert_allclose(lux, expected, rtol=1e-4)
    assert all(x.exact for x in analytic)
    rendered = api.measure_illuminance(np.array(points), np.array(normals), method="render", quality="standard")
    lux_r = np.array([x.illuminance for x in rendered])
    se = np.array([x.rel_std_error for x in rendered]) * lux_r
    assert np.all(np.abs(lux_r - expected) <= np.maximum(3 * se, 0.0) + 0.01 * expected)
    # The sensor-patch harness, independent of the meter: one direction is enough here.
    e_ref, _rel, _ = reference.reference_irradiance(scene, tuple(points[2]), tuple(normals[2]), max_seconds=20.0)
    assert 683.0 * e_ref[1] == pytest.approx(expected[2], rel=1e-3)


def test_flux_of_imported_light_is_in_its_properties(scene, tmp_path):
    path = tmp_path / "iso.ies"
    v = np.arange(0.0, 180.0 + 1e-9, 10.0)
    path.write_text(ies_text(v, [0.0], [np.full(v.size, 100.0)]))
    obj = api.import_luminaire(str(path))
    assert obj.data["radiometer_lumens"] == pytest.approx(4 * math.pi * 100.0)
    assert obj.data.type == "POINT" and obj.data.shadow_soft_size == 0.0
    assert obj.data.energy == pytest.approx(pf.CYCLES_IES_EFFICACY / 683.0, rel=1e-6)


def test_efficacy_convention_is_followed(scene, tmp_path):
    scene.radiometer.efficacy_convention = "CUSTOM"
    scene.radiometer.efficacy = 179.0
    path = tmp_path / "iso.ies"
    v = np.arange(0.0, 180.0 + 1e-9, 10.0)
    path.write_text(ies_text(v, [0.0], [np.full(v.size, 100.0)]))
    obj = api.import_luminaire(str(path), location=(0, 0, 2))
    assert obj.data.energy == pytest.approx(pf.CYCLES_IES_EFFICACY / 179.0, rel=1e-6)
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="analytic")
    assert r.illuminance == pytest.approx(100.0 / 4.0, rel=1e-5)


def test_occluded_luminaire_is_zero_and_edited_tree_is_rendered(scene, tmp_path, build):
    path = tmp_path / "iso.ies"
    v = np.arange(0.0, 180.0 + 1e-9, 10.0)
    path.write_text(ies_text(v, [0.0], [np.full(v.size, 100.0)]))
    obj = api.import_luminaire(str(path), location=(0, 0, 2))
    build.plane(scene, size=1.0, location=(0, 0, 1))
    r = api.predict_illuminance((0, 0, 0), (0, 0, 1))
    assert r[0]["exact"] and "photometric" in r[0]["model"]
    reading = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="analytic")
    assert reading.illuminance == 0.0
    # Anything else in the tree (here a Math node scaling the IES output) is no closed form any more.
    tree = obj.data.node_tree
    ies = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeTexIES")
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    math_node = tree.nodes.new("ShaderNodeMath")
    tree.links.new(ies.outputs["Fac"], math_node.inputs[0])
    tree.links.new(math_node.outputs[0], emission.inputs["Strength"])
    with pytest.raises(RadiometerError, match="node tree"):
        api.measure_illuminance((2, 0, 0), (0, 0, 1), method="analytic")


@pytest.mark.parametrize("text, match", [
    ("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 19 1 1 2 0 0 0\n1 1 10\n0 5 10\n", "end of file"),
    ("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n1 2 3 4\n", "end of the file"),
    ("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n1 -2 3\n", "non-negative"),
    ("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 45\n0\n1 2 3\n", "increasing"),
    ("IESNA:LM-63-2002\nTILT=lamp.tlt\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n1 2 3\n", "lamp.tlt"),
])
def test_bad_input_creates_nothing(scene, tmp_path, text, match):
    path = tmp_path / "bad.ies"
    path.write_text(text)
    before = (len(bpy.data.objects), len(bpy.data.lights), len(bpy.data.texts))
    with pytest.raises(RadiometerError, match=match):
        api.import_luminaire(str(path))
    assert (len(bpy.data.objects), len(bpy.data.lights), len(bpy.data.texts)) == before

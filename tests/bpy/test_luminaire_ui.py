"""Luminaire import operator, File > Import menu, goniometric diagrams from a light, EULUMDAT
import and the law checks on a photometric light."""

import math
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402

V = np.arange(0.0, 90.0 + 1e-9, 5.0)


def ies_text(v, h, cd):
    out = ["IESNA:LM-63-2002", "[LUMINAIRE] Test downlight", "TILT=NONE", f"1 1000 1 {len(v)} {len(h)} 1 2 0 0 0",
           "1 1 10", " ".join(f"{x:g}" for x in v), " ".join(f"{x:g}" for x in h)]
    out += [" ".join(f"{x:.10g}" for x in row) for row in cd]
    return "\n".join(out) + "\n"


def lobe(v):
    return 800.0 * np.cos(np.radians(v)) ** 2 + 10.0


@pytest.fixture
def scene(clean_blender, build):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    build.black_world(s)
    return s


def _menu_draw_functions():
    menu = bpy.types.TOPBAR_MT_file_import
    return [getattr(f, "__name__", "") for f in menu._dyn_ui_initialize()] if hasattr(menu, "_dyn_ui_initialize") else []


def test_operator_imports_at_the_cursor_and_menu_entry_comes_and_goes(scene, tmp_path):
    import radiometer

    path = tmp_path / "down.ies"
    path.write_text(ies_text(V, [0.0], [lobe(V)]))
    scene.cursor.location = (1.0, 2.0, 3.0)
    assert bpy.ops.radiometer.import_luminaire(filepath=str(path)) == {"FINISHED"}
    obj = bpy.context.active_object
    assert obj.type == "LIGHT" and tuple(obj.location) == pytest.approx((1.0, 2.0, 3.0))
    assert "_menu" in _menu_draw_functions()
    radiometer.unregister()
    try:
        assert "_menu" not in _menu_draw_functions()
    finally:
        radiometer.register()


def test_operator_bad_file_cancels_and_creates_nothing(scene, tmp_path):
    path = tmp_path / "bad.ies"
    path.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 45\n")
    before = len(bpy.data.objects), len(bpy.data.lights), len(bpy.data.texts)
    with pytest.raises(RuntimeError, match="end of file"):
        bpy.ops.radiometer.import_luminaire(filepath=str(path))
    assert (len(bpy.data.objects), len(bpy.data.lights), len(bpy.data.texts)) == before


def test_goniometric_diagram_from_file_and_from_light(scene, tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "down.ies"
    path.write_text(ies_text(V, [0.0, 90.0], [lobe(V), 0.5 * lobe(V)]))
    out = api.goniometric_diagram(str(path), tmp_path / "file.png")
    assert os.path.getsize(out) > 1000
    obj = api.import_luminaire(str(path))
    os.remove(path)                      # the light's own IES text is enough
    from radiometer.measure.capture import luminaires

    p = luminaires.photometry_of_light(obj)
    assert p.candela_at(30.0, 90.0) == pytest.approx(0.5 * lobe(np.array(30.0)), rel=1e-8)
    assert p.candela_at(30.0, 0.0) == pytest.approx(lobe(np.array(30.0)), rel=1e-8)
    out = api.goniometric_diagram(obj, tmp_path / "light.png")
    assert os.path.getsize(out) > 1000
    with pytest.raises(RadiometerError):
        api.goniometric_diagram(bpy.data.objects.new("empty", None), tmp_path / "x.png")


def test_eulumdat_import_is_read_exactly(scene, tmp_path):
    # Symmetry 4 (quadrant), 4 C-planes stored (0, 30, 60, 90) of 12, cd/klm x 2000 lm / 1000.
    lines = ["Acme", "1", "4", "12", "30", str(V.size), "5", "r", "Quad", "Q-1", "q.ldt", "d",
             "100", "100", "50", "80", "80", "10", "10", "10", "10", "100", "80", "1", "0", "1", "1", "LED", "2000",
             "3000K", "80", "20"] + ["0.5"] * 10 + [f"{30 * i}" for i in range(12)] + [f"{x:g}" for x in V]
    planes = [lobe(V) * (1.0 + 0.1 * k) for k in range(4)]
    for row in planes:
        lines += [f"{x:.10g}" for x in row]
    path = tmp_path / "q.ldt"
    path.write_text("\n".join(lines) + "\n")
    obj = api.import_luminaire(str(path), location=(0.0, 0.0, 2.5))
    bpy.context.view_layer.update()
    for v, c, k in ((30.0, 60.0, 2), (45.0, 120.0, 2), (20.0, 270.0, 3), (35.0, 330.0, 1)):
        a, cc = math.radians(v), math.radians(c)
        d = np.array([math.sin(a) * math.cos(cc), math.sin(a) * math.sin(cc), -math.cos(a)])
        point = np.array(obj.location) + 2.0 * d
        r = api.measure_illuminance(point, -d, method="analytic")
        assert r.illuminance == pytest.approx(2.0 * lobe(np.array(v)) * (1 + 0.1 * k) / 4.0, rel=1e-4), (v, c)


def test_law_checks_on_a_photometric_light(scene, tmp_path):
    path = tmp_path / "down.ies"
    path.write_text(ies_text(V, [0.0], [lobe(V)]))
    obj = api.import_luminaire(str(path), location=(0.0, 0.0, 3.0))
    result = api.check_inverse_square(obj, method="analytic")
    assert result.passed and result.near_field_limit == 0.0


def test_luminaire_array_on_a_work_plane_matches_the_hand_calculation(scene, tmp_path):
    # Four downlights 2.2 m above a work plane; E at each grid point = sum of I(theta, C) cos / d^2,
    # computed here from the file (the number a lighting designer computes by hand).
    h = np.arange(0.0, 360.0 + 1e-9, 30.0)
    cd = [lobe(V) * (1.0 + 0.3 * math.cos(math.radians(c))) for c in h]
    path = tmp_path / "asym.ies"
    path.write_text(ies_text(V, h, cd))
    photometry = api.read_photometry(str(path))
    spots = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
    for x, y in spots:
        api.import_luminaire(str(path), location=(x, y, 3.0))
    xs, ys = np.meshgrid(np.linspace(-1.5, 1.5, 4), np.linspace(-1.5, 1.5, 4))
    points = np.stack([xs.ravel(), ys.ravel(), np.full(xs.size, 0.8)], axis=1)
    hand = np.zeros(len(points))
    for x, y in spots:
        rel = points - (x, y, 3.0)
        d = np.linalg.norm(rel, axis=1)
        theta = np.degrees(np.arccos(-rel[:, 2] / d))
        c = np.degrees(np.arctan2(rel[:, 1], rel[:, 0]))
        hand += photometry.candela_at(theta, c) * (-rel[:, 2] / d) / d**2
    readings = api.measure_illuminance(points, np.tile((0.0, 0.0, 1.0), (len(points), 1)), method="analytic")
    np.testing.assert_allclose([r.illuminance for r in readings], hand, rtol=1e-4)

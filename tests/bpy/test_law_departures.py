"""Law checks say what a departure is (issue 23): the near field of an extended source or Blender's soft
falloff is the departure the closed form of the light's own shape predicts, physics and not a fault; the
plots are drawn in lux (the scene's efficacy) with that closed form beside the measurement.

References: the on-axis Lambertian square E = L 4 (b/s) atan(b/s) (Howell's catalogue C-11; see
test_analysis_laws.py) departs from I/d^2 by -47 % at 0.6 side lengths; the isotropic point source follows
I/d^2 exactly. Closed forms only (method "analytic"): no render, no noise.
"""

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.measure.analyses import law_checks
from radiometer.measure.reports import report


def test_area_light_near_field_is_expected_not_a_fault(clean_blender, build, tmp_path):
    pytest.importorskip("matplotlib")
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "AREA", (0, 0, 0), energy=50.0, shape="SQUARE", size=0.5)
    r = api.check_inverse_square(light, method="analytic", plot=str(tmp_path / "inv.png"))
    assert not r.passed and r.expected_departure
    assert r.departure.startswith("near field within 2.9 m") and "area light 0.5 x 0.5 m" in r.departure
    assert r.efficacy == pytest.approx(683.0) and r.description == "area light 0.5 x 0.5 m"
    assert report.verdict(r.to_dict()) == "near field"
    c = api.check_cosine_law(light, location=(0, 0, -0.4), method="analytic", plot=str(tmp_path / "cos.png"))
    assert not c.passed and c.expected_departure and "below the meter's horizon" in c.departure
    assert report.verdict(c.to_dict()) == "near field"
    text = report.summary_table({"meters": [], "inverse_square": [r.to_dict()], "cosine": [c.to_dict()], "grids": []})
    assert "near field" in text and "departs" not in text.split("\n")[1]
    for name in ("inv.png", "cos.png"):
        assert (tmp_path / name).read_bytes()[:4] == b"\x89PNG"


def test_point_light_has_no_departure(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "POINT", (0, 0, 3), energy=100.0, shadow_soft_size=0.0)
    r = api.check_inverse_square(light, method="analytic")
    assert r.passed and not r.expected_departure and r.departure == ""
    assert report.verdict(r.to_dict()) == "ok"


def test_a_departure_the_shape_does_not_explain_is_not_excused(clean_blender):
    """Synthetic sweep: the direct light falls 5 % below the light's own closed form at the two nearest
    distances (a fault, not the shape), so the departure is not 'expected'."""

    class Spec:
        kind, radius, soft_falloff, extents, shape = "AREA", 0.0, False, (0.5, 0.5), "SQUARE"

    d = np.array([0.3, 0.6, 1.2, 2.4, 4.8])
    model_dev = np.array([-0.3, -0.1, -0.03, -0.008, -0.002])
    predicted = 1.0 / d**2
    model = predicted * (1 + model_dev)
    se = np.full(d.size, 1e-3)
    ok = np.abs(model_dev) <= 0.01
    judged = np.ones(d.size, bool)
    args = (Spec(), d)
    expected, words = law_checks._expected_inverse_square(*args, model, se, model, model_dev, ok, judged, 2.4, True,
                                                          False, 0.01)
    assert expected and "near field within 2.4 m" in words
    faulty = model * np.array([0.95, 0.95, 1, 1, 1])
    assert law_checks._expected_inverse_square(*args, faulty, se, model, model_dev, ok, judged, 2.4, True, False,
                                               0.01) == (False, "")


def test_report_checks_each_luminaire_type_once(clean_blender, build):
    """Eight equal panels and one other light: two law checks, the others named as of the same type."""
    scene = bpy.context.scene
    build.black_world(scene)
    panels = [build.light(scene, "AREA", (x, 0, 2.9), energy=15.0, shape="SQUARE", size=0.6) for x in range(8)]
    lamp = build.light(scene, "POINT", (0, 2, 2.0), energy=10.0)
    bigger = build.light(scene, "AREA", (0, -2, 2.9), energy=15.0, shape="SQUARE", size=0.6)
    bigger.scale = (2.0, 1.0, 1.0)  # the object's scale makes it another luminaire
    bpy.context.view_layer.update()
    types = report.light_types(panels + [lamp, bigger])
    assert [(rep.name, [o.name for o in same]) for rep, same in types] == [
        (panels[0].name, [p.name for p in panels[1:]]), (lamp.name, []), (bigger.name, [])]
    assert report.law_check_budget({"quality": "preview", "target_rel_error": 0.02, "time_budget_s": None},
                                   "preview") == {"quality": "preview", "samples": report.PREVIEW_LAW_SAMPLES}
    own = {"quality": "preview", "target_rel_error": None, "time_budget_s": 3.0}
    assert report.law_check_budget(own, "preview") == own  # the user's time budget wins
    checked = [{"light": panels[0].name, "kind": "AREA", "error": "not measured in this test"}]
    text = report.summary_table({"meters": [], "inverse_square": checked, "cosine": [], "grids": [],
                                 "law_types": {panels[0].name: [p.name for p in panels[1:]]}})
    assert f"{panels[0].name}: also stands for" in text and "and 3 more" in text


def test_sidebar_says_near_field_not_flag(clean_blender, build, tmp_path):
    """The sidebar's law table and the operator's report say 'near field' for an area light's expected
    departure (they said 'FLAG' / 'flagged')."""
    from radiometer.panels.analysis import _yes

    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "AREA", (0, 0, 0), energy=50.0, shape="SQUARE", size=0.5)
    scene.radiometer_analysis.output_dir = str(tmp_path) + "/"
    assert bpy.ops.radiometer.check_inverse_square(light="__ALL__") == {"FINISHED"}
    item = scene.radiometer_analysis.laws[light.name]
    assert item.inverse_checked and not item.inverse_passed and item.inverse_expected
    assert _yes(item.inverse_passed, item.inverse_expected) == "near field" and _yes(False) == "departs"

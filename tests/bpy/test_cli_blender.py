"""The `blender -c radiometer` entry point runs the same implementation as `python -m radiometer`."""

import json
import math

import bpy
import pytest

from radiometer import cli


def test_blender_cli_measures_meters_of_the_open_file(clean_blender, build, tmp_path, capsys):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    out = tmp_path / "r.json"
    assert cli._blender_cli(["measure", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["meters"][0]["illuminance"] == pytest.approx(683 * 100 / (16 * math.pi), rel=1e-6)
    assert "lx" in capsys.readouterr().out


def test_blender_cli_bad_option_is_one_line(clean_blender, capsys):
    assert cli._blender_cli(["measure", "--nope"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("radiometer: error")


def test_measure_without_meters_is_a_clear_error(clean_blender, capsys):
    assert cli._blender_cli(["measure"]) == 2
    assert "no light meters" in capsys.readouterr().err


def _convergence_with_nan():
    return {"target": "meter M", "reference_kind": "closed form", "target_error": 0.01,
            "fit": {"slope": -0.5, "slope_se": float("nan"), "time_slope": None, "time_slope_se": None},
            "samples_for_target": float("nan"), "seconds_for_target": None, "seconds_for_target_by_time_fit": None,
            "rows": [{"samples_per_texel": 4, "samples": 64, "seconds": 0.1, "rms_error": 0.02,
                      "std_error": float("nan")},
                     {"samples_per_texel": 16, "samples": 256, "seconds": 0.2, "rms_error": None, "std_error": None}],
            "targeted": {"samples": None, "seconds": 0.3, "rel_std_error": float("nan"), "rms_error": None,
                         "target_rel_error": None, "reached": False}}


def test_report_text_survives_nan_and_none(clean_blender):
    from radiometer.measure.reports import report

    rep = {"scene": "S", "file": "", "quality": "standard", "method": "auto", "seconds": 1.0, "errors": [],
           "meters": [{"name": "Lamp.1", "quantity": "illuminance", "illuminance": float("nan"), "exact": False,
                       "rel_std_error": None, "method": "render"}],
           "inverse_square": [], "cosine": [], "grids": [], "convergence": _convergence_with_nan()}
    rep["summary"] = report.summary_table(rep)
    md = report.markdown(rep)
    assert "## Convergence" in md and "n/a" in md and "Lamp.1" in md
    assert "n/a" in rep["summary"]


def test_report_of_nan_convergence_writes_json_and_markdown(clean_blender, tmp_path, monkeypatch):
    from radiometer.measure.analyses import analysis
    from radiometer.measure.reports import report

    class FakeStudy:
        def to_dict(self):
            return _convergence_with_nan()

    monkeypatch.setattr(analysis, "convergence_study", lambda *a, **k: FakeStudy())
    mesh = bpy.data.meshes.new("Work Plane")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [], [(0, 1, 2)])
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Work Plane", mesh))
    monkeypatch.setattr(report, "work_planes", lambda scene: [])  # no grid, but the study's target below
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    monkeypatch.setattr(report.meter_objects, "run_step", lambda *a, **k: [])
    from radiometer import api

    rep = api.export_report(str(tmp_path), scene=bpy.context.scene)
    assert json.loads((tmp_path / "report.json").read_text())["convergence"]["rows"][0]["std_error"] is None
    assert "## Convergence" in (tmp_path / "report.md").read_text() and rep["convergence"]["target"] == "meter M"


def test_report_plot_names_are_unique_per_object_name(clean_blender):
    from radiometer.measure.reports import report

    names = ("Lamp.1", "Lamp_1", "Lampe größer", "Lampe grösser", "LAMP.1")
    assert len({report.plot_stem(n, among=names) for n in names}) == 5
    assert report.plot_stem("Work Plane") == "work_plane"


def test_radiance_map_paths_are_private_and_distinct(clean_blender):
    import os
    import tempfile

    from radiometer.measure.meter import meter_objects as meters

    a, b = meters.map_path("Map.1"), meters.map_path("Map_1")
    assert a != b and os.path.dirname(a) == os.path.dirname(b)
    assert os.path.dirname(a) != os.path.join(tempfile.gettempdir(), "radiometer")
    try:
        user = bpy.utils.extension_path_user("radiometer")
    except (ValueError, RuntimeError):
        user = None
    if user is None or not a.startswith(user):
        assert os.stat(os.path.dirname(os.path.dirname(a))).st_mode & 0o777 == 0o700


def test_cli_measure_cancelled_flag_is_exit_130(clean_blender, build, capsys, monkeypatch):
    # The measurement sees the Ctrl-C flag at its next poll: MeasurementCancelled becomes exit 130.
    from radiometer.commands import _io

    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    monkeypatch.setattr(_io.Interrupt, "cancelled", lambda self: True)
    assert cli._blender_cli(["measure"]) == 130
    assert "interrupted" in capsys.readouterr().err

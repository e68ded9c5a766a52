"""Issue 33: a cancelled report leaves the previous report set intact, and no temporary file.

Before: a cancel during the report's picture was caught as a RadiometerError, so the run went on,
replaced report.html alone (without the picture) and left report.pdf/json/md of the previous run
and a 0-byte .report.*.tmp.pdf. Here the report is cancelled at evenly spread polls of
``cancelled()`` (every part of the run: meters, law checks, the grid, the picture, the client
report), and once by a MeasurementCancelled raised from the picture itself; after each the folder
is byte for byte the previous set. Then a finished run replaces the set whole.

One point light over a 'Work Plane' (analytic grid, preview), a 32 x 24 px camera whose report picture is
rendered at 32 x 24 px too (client_report.PICTURE_LONGEST_PX, 240 by default): ~2 s a run.
"""

import hashlib
import json
import os

import bpy
import pytest

from radiometer.errors import MeasurementCancelled

pytest.importorskip("matplotlib")


def _state(folder):
    return {name: hashlib.sha1(open(os.path.join(folder, name), "rb").read()).hexdigest()
            for name in sorted(os.listdir(folder))}


def _scene(build):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    build.black_world(scene)
    build.light(scene, "POINT", (0.0, 0.0, 2.0), name="lamp", energy=100.0, shadow_soft_size=0.0)
    build.plane(scene, size=1.0, name="Work Plane")
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.0, 1.5), (1.1, 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = 32, 24
    return scene


def _report(scene, out, cancelled=None, **kw):
    from radiometer import api

    return api.export_report(str(out), scene=scene, quality="preview", convergence=False, cancelled=cancelled,
                                **kw)


@pytest.mark.slow
def test_cancel_at_any_point_keeps_the_previous_set(clean_blender, build, tmp_path, monkeypatch):
    from radiometer.measure.reports import client_report

    monkeypatch.setattr(client_report, "PICTURE_LONGEST_PX", 32)  # the camera's own 32 x 24 px
    scene = _scene(build)
    out = tmp_path / "report"
    polls = []
    _report(scene, out, cancelled=lambda: polls.append(1) and False, project={"name": "first"})
    previous = _state(out)
    listed = json.loads((out / "report.json").read_text())["files"]
    assert sorted(listed) == sorted(previous)  # the manifest names the whole set, nothing else is there
    assert {"report.html", "report.pdf", "report.md", "report.json", "luminance.png"} <= set(previous)
    assert len(polls) > 10

    def cancel_at(k):
        seen = []

        def cancelled():
            seen.append(1)
            return len(seen) >= k

        return cancelled

    points = sorted({max(1, round(len(polls) * f)) for f in (0.0, 0.25, 0.5, 0.75, 0.95)} | {len(polls)})
    for k in points:
        with pytest.raises(MeasurementCancelled):
            _report(scene, out, cancelled=cancel_at(k), project={"name": "second"})
        assert _state(out) == previous, f"cancelled at poll {k} of {len(polls)}"

    # The case of issue 33: the picture itself raises MeasurementCancelled (its renders saw the flag).
    from radiometer.measure.analyses import luminance_image

    def cancelled_picture(*args, **kwargs):
        raise MeasurementCancelled("luminance image cancelled")

    monkeypatch.setattr(luminance_image, "luminance_image", cancelled_picture)
    with pytest.raises(MeasurementCancelled):
        _report(scene, out, project={"name": "third"})
    assert _state(out) == previous
    monkeypatch.undo()

    # A finished run replaces the set whole: every file new (the project name is in html, json, md, pdf).
    _report(scene, out, project={"name": "fourth"}, client=False)
    now = _state(out)
    assert sorted(json.loads((out / "report.json").read_text())["files"]) == sorted(now)
    assert "report.html" not in now and "report.pdf" not in now  # the previous set's, not this one's
    assert now["report.json"] != previous["report.json"]


def test_report_operator_cancelled_between_parts_leaves_no_staging_folder(clean_blender, build, tmp_path):
    # The Report operator runs the report as steps; Esc between two parts leaves the generator suspended.
    # Its end closes it, so the staging folder inside the output folder goes at once (not at GC).
    from radiometer.operators import analysis as ops

    scene = _scene(build)
    out = tmp_path / "ui"
    scene.radiometer_analysis.output_dir = str(out)
    task = ops.report_task(bpy.context, convergence=False)
    task.step()  # the meters / first law check
    assert [n for n in os.listdir(out) if n.startswith(".report.staging")]
    task.request_cancel()
    task.step()
    task.on_end()
    assert os.listdir(out) == []

"""The client's report (issue 23 item 7): schedule, compliance, readings, HTML and PDF without absolute paths."""

import os
import shutil
import subprocess
import sys

import bpy
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import office  # noqa: E402

from radiometer import api  # noqa: E402
from radiometer.measure.blender import request as request_of  # noqa: E402

pytest.importorskip("matplotlib")

IES = """IESNA:LM-63-2002
[LUMINAIRE] Downlight DL-1
TILT=NONE
1 2000 1 3 1 1 2 0.2 0.2 0
1 1 25
0 45 90
0
800 500 0
"""


def test_client_report_html_pdf(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    office.build(scene)
    ies = tmp_path / "dl1.ies"
    ies.write_text(IES)
    for k in range(2):
        api.import_luminaire(str(ies), scene=scene, location=(-2.0 + 4.0 * k, -1.0, 2.9), name="DL-1")
    plane = build.plane(scene, size=1.0, location=(0.0, 0.5, 0.75), name="Work Plane")
    plane.scale = (4.0, 2.4, 1.0)
    plane.hide_render = True
    out = tmp_path / "client"
    out.mkdir()
    g = api.illuminance_grid(plane, resolution=(6, 4), quality="preview", png=str(out / "isolux_work_plane.png"))
    reading = api.measure_illuminance((0.0, 0.0, 0.8), (0, 0, 1), quality="preview")
    report = {"quality": "preview", "grids": [g.to_dict()], "meters": [dict(name="Desk", **reading.to_dict())],
              "inverse_square": [], "cosine": [], "convergence": None, "errors": []}
    from radiometer.measure.reports import client_report

    client = client_report.client_report(report, str(out), request=request_of.build(scene, quality="preview"),
                                         project={"name": "Office 2.14"}, task="office_writing",
                                         maintenance_factor=0.8, observers=[(office.EYE, office.VIEW)])
    by_type = {s["file"] or s["type"]: s for s in client["schedule"]}
    assert by_type["dl1.ies"]["count"] == 2 and by_type["dl1.ies"]["power_w"] == pytest.approx(25.0)
    flux = by_type["dl1.ies"]["flux_lm"]
    assert flux > 0 and by_type["dl1.ies"]["efficacy_lm_w"] == pytest.approx(flux / 25.0)
    panels = [s for s in client["schedule"] if s["type"].startswith("Blender area")]
    assert panels and panels[0]["count"] == 4
    assert panels[0]["flux_lm"] == pytest.approx(683 * office.PANEL_POWER, rel=1e-6)  # white: K x P
    comp = client["compliance"][0]
    assert {c["quantity"] for c in comp["checks"]} >= {"Ēm", "U0", "UGR (observer 1)", "Ra"}
    text = (out / "report.html").read_text()
    assert "Office 2.14" in text and "EN 12464-1:2011 Table 5.26" in text and "Luminaire schedule" in text
    assert "Desk" in text and " lx ±" in text and "EV100" in text
    assert str(tmp_path) not in text and "isolux_work_plane.png" in text  # file names only, no absolute paths
    assert "FLAG" not in text
    assert "e+0" not in text and "e-1" not in text  # plain numbers for a client (was '+1.32e+03 lx' margins)
    assert "indicative values" in text  # the EN 12464-1 rows could not be checked against the standard's text
    pdf = out / "report.pdf"
    assert pdf.read_bytes()[:5] == b"%PDF-"
    if shutil.which("pdftoppm"):
        subprocess.run(["pdftoppm", "-png", "-r", "30", str(pdf), str(out / "page")], check=True)
        assert len([p for p in os.listdir(out) if p.startswith("page")]) >= 2


def test_sun_cosine_check_point_is_in_the_room(clean_blender, build):
    """The report runs a sun's cosine check at the first work plane's centre, never at the origin."""
    from radiometer.measure.reports import report

    scene = bpy.context.scene
    plane = build.plane(scene, size=2.0, location=(1.0, 2.0, 0.75), name="Work Plane")
    plane.scale = (2.0, 1.0, 1.0)
    bpy.context.view_layer.update()  # matrix_world of objects made through bpy.data (a report measures first)
    assert report._room_point(report.work_planes(scene), []) == pytest.approx((1.0, 2.0, 0.75))
    assert report._room_point([], []) is None


def test_schedule_flux_of_blender_lights_honours_colour_temperature_and_exposure(clean_blender, build):
    """Luminaire schedule, Blender lights: flux = K x Y(colour x temperature colour) x P x 2^exposure with
    Rec.709 luminance weights and K = 683 lm/W (the scene's defaults); two lights that differ only in
    colour temperature are two rows, not one."""
    from radiometer.measure.reports.client_report import luminaire_schedule

    scene = bpy.context.scene
    y709 = (0.2126, 0.7152, 0.0722)
    fluxes = {}
    for kelvin in (2700.0, 6500.0):
        light = build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=10.0, name=f"warm {kelvin:.0f}")
        light.data.color = (1.0, 0.5, 0.25)
        light.data.use_temperature = True
        light.data.temperature = kelvin
        light.data.exposure = 1.0
        rgb = [c * t for c, t in zip(light.data.color, light.data.temperature_color)]
        fluxes[round(683.0 * 10.0 * 2.0 * sum(w * c for w, c in zip(y709, rgb)), 3)] = kelvin
    rows = luminaire_schedule(scene)
    assert len(rows) == 2
    got = sorted(r["flux_lm"] for r in rows)
    want = sorted(fluxes)
    assert got == pytest.approx(want, rel=1e-4)

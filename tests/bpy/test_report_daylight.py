"""The report's daylight section (issue 34) in the daylit demo room, which has no electric light: the
daylight factor, the annual metrics from the synthetic weather file (its name and period shown), the
sunlight hours, DGP at the camera, the EN 17037 table and the maps, in report.json, report.md, the
HTML and the PDF; the section's bad input is one error before any measurement, nothing written."""

import json
import os

import bpy
import pytest

from radiometer import api
from radiometer.demo import daylight
from radiometer.errors import RadiometerError
from radiometer.measure.reports import client_report, daylight_section
from radiometer.radiometry.metrics import en17037


def _daylit_room(tmp_path):
    scene = daylight.build(bpy.context.scene, glass=True, pane_renders=False)  # an open window: no caustic
    api.set_sun(scene, daylight.SITE["latitude_deg"], daylight.SITE["longitude_deg"], daylight.local_time())
    bpy.context.view_layer.update()
    return scene, daylight.write_weather(str(tmp_path))


def test_daylight_section_in_every_report_file(clean_blender, tmp_path, monkeypatch):
    monkeypatch.setattr(daylight_section, "SUN_STEP_MIN", 120)  # a cheap sun study: 12 times on 21 March
    monkeypatch.setattr(daylight_section, "DGP_RESOLUTION", 32)
    monkeypatch.setattr(client_report, "PICTURE_LONGEST_PX", 32)  # the camera's picture at 32 x 24 px, not 240
    scene, epw = _daylit_room(tmp_path)
    assert not [ob for ob in scene.objects if ob.type == "LIGHT" and ob.data.type != "SUN"]  # no electric light
    out = tmp_path / "report"
    rep = api.export_report(str(out), scene=scene, quality="preview", convergence=False, daylight="auto", epw=epw,
                            median_external_illuminance_lux=14000.0, daylight_resolution=(2, 2))
    section = rep["daylight"]
    assert "Radiometer Sun" in section["sky"]  # "auto": the scene has a sun
    dome = bpy.app.version >= (5, 0, 0)  # the annual run's sky dome needs 5.0: on 4.5 it is one error line
    # on 4.5 the annual run and the camera's annual glare are one error line each
    assert section["errors"] == [] if dome else (len(section["errors"]) == 2
                                                 and all("needs Blender 5.0" in e for e in section["errors"]))
    assert section["weather"]["file"] == daylight.WEATHER_FILE and section["weather"]["whole_year"]
    plane = section["planes"][0]
    df = plane["daylight_factor"]
    assert df["points"] == 4 and 0 < df["minimum_percent"] <= df["average_percent"] <= df["maximum_percent"]
    assert df["uniformity"] == pytest.approx(df["minimum_percent"] / df["average_percent"], rel=1e-9)
    if dome:
        annual = plane["annual"]
        assert 0 <= annual["sDA_300_50_percent"] <= 100 and annual["occupied_hours"] == 3650
        lo, hi = annual["sDA_range_2se_percent"]
        assert lo <= annual["sDA_300_50_percent"] <= hi
    hours = plane["sunlight_hours"]
    assert hours["day"] == "2026-03-21" and hours["step_min"] == 120
    assert 0 <= hours["minimum_h"] <= hours["mean_h"] <= hours["maximum_h"] <= 12.5
    rows = {row["criterion"]: row for row in plane["en17037"]}
    # the table's sunlight level is the standard's for the plane's sunniest point
    assert rows["exposure to sunlight"]["level"] == en17037.sunlight_exposure(hours["maximum_h"]).level
    # the annual run's hours; without them (4.5) the DF method with the E_v,d given
    assert rows["daylight provision"]["method"] == ("target illuminance (hourly)" if dome
                                                    else "daylight factor (E_v,d 14000 lx)")
    # glare protection from the camera's annual DGP over the occupied hours (issue 34)
    if dome:
        a = section["annual_dgp"]
        assert a["camera"] == "Camera" and a["occupied_hours"] == 3650
        assert rows["protection from glare"]["level"] == a["en17037_level"] != "not assessed"
        assert rows["protection from glare"]["values"]["hours"] == 3650
    else:
        assert rows["protection from glare"]["level"] == "not assessed"
    dgp = section["dgp"]
    assert dgp["camera"] == "Camera" and 0 <= dgp["dgp"] <= 1 and dgp["vertical_illuminance_lx"] > 0
    maps = ["daylight_factor_work_plane.png", "sunlight_hours_work_plane.png"] + ["sda_work_plane.png"] * dome
    files = json.loads((out / "report.json").read_text())["files"]
    assert set(maps) <= set(files) and all((out / name).exists() for name in maps)
    assert not [p for p in os.listdir(out) if p.startswith(".")]  # no staging folder left
    md = (out / "report.md").read_text()
    assert "## Daylight" in md and daylight.WEATHER_FILE in md and "![Daylight factor" in md
    assert ("sDA300/50%" in md) == dome
    page = (out / "report.html").read_text()
    assert "Daylight factor on Work Plane" in page and "Daylight: maps" in page and "EN 17037 on Work Plane" in page
    assert "sunlight_hours_work_plane.png" in page
    assert ("Annual daylight glare at the camera Camera" in page) == dome
    assert (out / "report.pdf").stat().st_size > 0


def test_daylight_section_bad_input_is_one_error_before_any_measurement(clean_blender, tmp_path):
    scene, epw = _daylit_room(tmp_path)
    bad = tmp_path / "short_records.epw"
    lines = open(epw, encoding="latin-1").read().splitlines()
    lines[20] = ",".join(lines[20].split(",")[:10])  # a record missing its radiation fields
    bad.write_text("\n".join(lines) + "\n", encoding="latin-1")
    out = tmp_path / "report"
    with pytest.raises(RadiometerError, match="weather file: .*line 21"):
        api.export_report(str(out), scene=scene, quality="preview", convergence=False, daylight=True, epw=str(bad))
    assert not out.exists() or os.listdir(out) == []
    bpy.data.objects.remove(bpy.data.objects["Work Plane"])
    with pytest.raises(RadiometerError, match="needs a work plane"):
        api.export_report(str(out), scene=scene, quality="preview", convergence=False, daylight=True)
    assert not out.exists() or os.listdir(out) == []
    with pytest.raises(RadiometerError, match="daylight must be"):
        api.export_report(str(out), scene=scene, daylight="yes")

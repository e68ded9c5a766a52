"""Illuminance grids (issue 5) against per-point closed forms, and the report/CLI end to end.

References: point source E = P cos(theta) / (4 pi r^2) (lecture); Lambertian rectangle parallel to the
receiver, E = L * sum over corners of the corner-rectangle projected solid angle
1/2 [X/sqrt(X^2+h^2) atan(Y/sqrt(X^2+h^2)) + Y/sqrt(Y^2+h^2) atan(X/sqrt(Y^2+h^2))] (Howell C-11),
with L = P / (pi A) (FACTS.md, normalized area light).
"""

import json
import math
import os

import bpy
import numpy as np
import pytest

from radiometer import api, cli
from radiometer.errors import RadiometerError
from radiometer.measure.blender.scene_guard import scene_fingerprint


def corner(x, y, h):
    """Signed projected solid angle of the rectangle [0, x] x [0, y] at height h above the foot point."""
    ax, ay = np.abs(x), np.abs(y)
    sx, sy = np.sqrt(ax**2 + h**2), np.sqrt(ay**2 + h**2)
    value = 0.5 * (ax / sx * np.arctan(ay / sx) + ay / sy * np.arctan(ax / sy))
    return np.sign(x) * np.sign(y) * value


def rectangle_irradiance(points, centre, half, h, radiance):
    x0, x1 = centre[0] - half - points[..., 0], centre[0] + half - points[..., 0]
    y0, y1 = centre[1] - half - points[..., 1], centre[1] + half - points[..., 1]
    return radiance * (corner(x1, y1, h) - corner(x0, y1, h) - corner(x1, y0, h) + corner(x0, y0, h))


def work_plane(build, scene, size=2.0, height=0.75, hidden=True):
    plane = build.plane(scene, size=size, location=(0.1, -0.2, height), name="Work Plane")
    plane.hide_render = hidden
    return plane


def test_grid_of_point_light_matches_closed_form(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.3, 0.2, 2.5), energy=100.0, shadow_soft_size=0.0)
    plane = work_plane(build, scene)
    plane.rotation_euler = (0.2, 0.0, 0.5)  # a tilted, turned plane: normals and layout must follow it
    before = scene_fingerprint(scene)
    g = api.illuminance_grid(plane, resolution=(7, 5), method="render")
    assert scene_fingerprint(scene) == before
    assert g.lux.shape == (5, 7) and g.points.shape == (5, 7, 3)
    n = np.array(g.normal)
    # Euler XYZ: R = Rz(0.5) Rx(0.2); R (0, 0, 1) = (sin .5 sin .2, -cos .5 sin .2, cos .2); float32 matrix
    assert n == pytest.approx([math.sin(.5) * math.sin(.2), -math.cos(.5) * math.sin(.2), math.cos(.2)], abs=1e-6)
    to_light = np.array([0.3, 0.2, 2.5]) - g.points
    r = np.linalg.norm(to_light, axis=-1)
    expected = 683.0 * 100 / (4 * math.pi) * (to_light @ n) / r**3  # lux, white light
    assert np.max(np.abs(g.lux / expected - 1)) < 0.01
    s = g.stats
    assert s["avg"] == pytest.approx(g.lux.mean()) and s["min"] == g.lux.min() and s["max"] == g.lux.max()
    assert s["u0"] == pytest.approx(g.lux.min() / g.lux.mean())
    # cell centres: the first point is half a cell in from the plane's local corner
    local = np.array(plane.matrix_world.inverted() @ __import__("mathutils").Vector(g.points[0, 0]))
    assert local[:2] == pytest.approx([-1 + 1 / 7, -1 + 1 / 5], abs=1e-6)


def test_grid_of_square_area_light_within_1_percent(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    power, side, height = 200.0, 1.0, 1.75
    build.light(scene, "AREA", (0.0, 0.0, height), energy=power, shape="SQUARE", size=side)
    plane = work_plane(build, scene, height=0.75)
    g = api.illuminance_grid(plane, method="render", target_rel_error=0.002)
    # EN 12464-1 for d = 2 m: p = 0.2 * 5^log10(2) = 0.325 m -> ceil(2 / 0.325) = 7 points a side
    assert (g.nx, g.ny) == (7, 7) and "EN 12464-1" in g.spacing_rule
    radiance = power / (math.pi * side**2)
    expected = 683.0 * rectangle_irradiance(g.points, (0, 0), side / 2, height - g.points[..., 2], radiance)
    assert np.max(g.rel_std_error) < 0.003  # the comparison below is meaningful at this noise
    assert np.max(np.abs(g.lux / expected - 1)) < 0.01


def test_grid_png_csv_and_bad_input(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2.5), energy=100.0, shadow_soft_size=0.0)
    plane = work_plane(build, scene)
    png, csv_path = str(tmp_path / "iso.png"), str(tmp_path / "grid.csv")
    g = api.illuminance_grid(plane, spacing=0.5, png=png, csv=csv_path)
    assert (g.nx, g.ny) == (4, 4) and g.method == "analytic" and g.exact
    assert open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert len(open(csv_path).read().strip().splitlines()) == 1 + 16
    json.dumps(g.to_dict())
    with pytest.raises(RadiometerError, match="at least 1 x 1"):
        api.illuminance_grid(plane, resolution=(0, 3))
    empty = bpy.data.objects.new("Empty Plane", bpy.data.meshes.new("empty"))
    scene.collection.objects.link(empty)
    with pytest.raises(RadiometerError, match="no vertices"):
        api.illuminance_grid(empty)
    with pytest.raises(RadiometerError, match="not a mesh"):
        api.illuminance_grid(scene.objects["point"])


def test_report_and_cli_end_to_end(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0, 0, 2.5), energy=100.0, shape="SQUARE", size=0.5)
    build.light(scene, "SUN", energy=2.0)
    work_plane(build, scene)
    blend = str(tmp_path / "s.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    out = tmp_path / "report"
    assert cli.main(["report", blend, "--out", str(out), "--quality", "preview"]) == 0
    data = json.load(open(out / "report.json"))
    kinds = {r["light"]: r for r in data["inverse_square"]}
    assert "no position" in kinds["sun"]["error"]
    assert kinds["area"]["near_field_limit"] == pytest.approx(5.7431 * 0.5, rel=0.02)
    assert data["grids"][0]["stats"]["u0"] > 0
    text = open(out / "report.md").read()
    assert "isolux_work_plane.png" in text and os.path.exists(out / "isolux_work_plane.png")
    assert cli.main(["grid", blend, "--resolution", "0", "2"]) == 2  # bad input: one line, exit code 2
    assert cli.main(["check", blend, "--light", "sun", "--json", str(tmp_path / "c.json")]) == 0


def test_operators_store_results_for_the_sidebar(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2.5), energy=100.0, shadow_soft_size=0.1)
    build.light(scene, "SUN", energy=2.0)
    settings = scene.radiometer_analysis
    settings.output_dir = str(tmp_path) + os.sep
    assert bpy.ops.radiometer.check_inverse_square(light="__ALL__") == {"FINISHED"}
    assert bpy.ops.radiometer.check_cosine_law(light="__ALL__") == {"FINISHED"}
    point = settings.laws["point"]
    assert point.inverse_checked and not point.inverse_passed and "soft falloff" in point.inverse_causes
    assert point.near_field_limit == pytest.approx(math.sqrt(99) * 0.1, rel=0.02)
    assert "horizon" in point.cosine_causes  # the disk of radius 0.1 m seen from 1 m sinks from 84.3 deg
    assert not settings.laws["sun"].inverse_checked and settings.laws["sun"].cosine_passed
    with pytest.raises(RuntimeError, match="pick a work plane"):
        bpy.ops.radiometer.illuminance_grid()
    assert bpy.ops.radiometer.illuminance_grid(create_plane=True) == {"FINISHED"}
    assert settings.work_plane.location.z == pytest.approx(0.75) and settings.work_plane.hide_render
    assert settings.grid_nx > 0 and settings.grid_avg > 0 and os.path.exists(settings.grid_image)
    assert bpy.ops.radiometer.export_report(convergence=False) == {"FINISHED"}
    assert os.path.exists(settings.report_path)


def test_report_names_with_control_characters_and_a_nan_light(clean_blender, build, tmp_path):
    """Issue 21 finding 14: a name with a newline or "|" stays one table cell in report.md; a light of
    NaN power makes `report` fail with one line (exit 2), as `measure` does, and writes nothing."""
    scene = bpy.context.scene
    build.black_world(scene)
    light = build.light(scene, "POINT", (0, 0, 2.0), energy=100.0, shadow_soft_size=0.0)
    light.name = "Lamp\nrow|two\x07"
    out = tmp_path / "report"
    api.export_report(str(out), quality="preview")
    text = open(out / "report.md").read()
    heading = [line for line in text.splitlines() if line.startswith("### Lamp")]
    assert heading and set(heading) == {"### Lamp row\\|two  (POINT)"}  # inverse-square and cosine sections
    light.data.energy = float("nan")
    blend = str(tmp_path / "nan.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    assert cli.main(["report", blend, "--out", str(tmp_path / "r2"), "--quality", "preview"]) == 2
    assert not (tmp_path / "r2").exists() or not any((tmp_path / "r2").iterdir())  # no file written
    with pytest.raises(RadiometerError, match="non-finite"):
        api.export_report(str(tmp_path / "r3"))

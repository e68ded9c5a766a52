"""Isolux plot of a scaled, rotated, non-square work plane (issue 23): axes in metres, against the CSV."""

import csv
import math

import bpy
import numpy as np
import pytest

from radiometer import api

pytest.importorskip("matplotlib")


def test_isolux_of_scaled_rotated_plane_spans_the_csv_in_metres(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.5, 0.3, 2.5), energy=200.0, shadow_soft_size=0.0)
    plane = build.plane(scene, size=1.0, location=(0.4, -0.3, 0.75), name="Work Plane")
    plane.hide_render = True
    plane.scale = (5.0, 3.0, 1.0)  # Add Plane, then scale: 5 m x 3 m
    plane.rotation_euler = (0.0, 0.0, math.radians(30))
    png, csv_path = tmp_path / "iso.png", tmp_path / "grid.csv"
    g = api.illuminance_grid(plane, resolution=(10, 6), method="analytic", png=str(png), csv=str(csv_path))
    assert g.size == pytest.approx((5.0, 3.0), rel=1e-6)
    origin, u, v, labels = g.plot_frame()
    assert np.linalg.norm(u) == pytest.approx(5.0, rel=1e-6) and np.linalg.norm(v) == pytest.approx(3.0, rel=1e-6)
    assert math.degrees(math.atan2(u[1], u[0])) == pytest.approx(30.0, abs=1e-4)
    assert labels[0].endswith("(m)")
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    xy = np.array([[float(r["x"]), float(r["y"])] for r in rows])
    # cell centres: half a cell in from the plane's edges, along the rotated axes
    ref = origin + (np.arange(10)[None, :, None] + 0.5) / 10 * u + (np.arange(6)[:, None, None] + 0.5) / 6 * v
    assert xy == pytest.approx(ref.reshape(-1, 2), abs=2e-5)  # the CSV prints 6 digits
    # the drawn axes: the same figure the PNG was written from spans the CSV points and the plane
    from radiometer.plots import isolux

    fig = isolux.isolux_figure(g.lux, origin, u, v, stats=g.stats, axis_labels=labels)
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 < xy[:, 0].min() and x1 > xy[:, 0].max() and y0 < xy[:, 1].min() and y1 > xy[:, 1].max()
    width = 5 * math.cos(math.radians(30)) + 3 * math.sin(math.radians(30))  # the rotated plane's bounding box
    assert x1 - x0 == pytest.approx(width * 1.06, rel=1e-4)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_isolux_of_a_wall_is_in_the_plane_own_metres(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.0, -2.0, 1.5), energy=100.0, shadow_soft_size=0.0)
    wall = build.plane(scene, size=2.0, location=(0.0, 0.0, 1.5), rotation=(math.radians(90), 0, 0), name="Wall")
    wall.scale = (2.0, 1.0, 1.0)
    g = api.illuminance_grid(wall, resolution=(4, 2), method="analytic")
    origin, u, v, labels = g.plot_frame()
    assert list(origin) == [0.0, 0.0] and u == pytest.approx([4.0, 0.0]) and v == pytest.approx([0.0, 2.0])
    assert "plane" in labels[0]


def test_grid_cli_prints_digits_the_error_supports(clean_blender, build, tmp_path, capsys):
    from radiometer import cli

    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0.5, 0.3, 2.5), energy=200.0, shadow_soft_size=0.0)
    plane = build.plane(scene, size=2.0, location=(0.0, 0.0, 0.75), name="Work Plane")
    plane.hide_render = True
    blend = str(tmp_path / "g.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    assert cli.main(["grid", blend, "--resolution", "3", "2", "--method", "analytic"]) == 0
    line = [t for t in capsys.readouterr().out.splitlines() if t.startswith("E_avg")][0]
    # exact closed forms: 5 significant digits, "exact", units on every number
    assert " lx exact" in line and "E_min" in line and line.count(" lx") >= 3 and "e+" not in line

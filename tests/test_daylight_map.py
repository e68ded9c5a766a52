"""Daylight maps (issue 34): the room in plan (radiometry/scene/plan_section.py: a section of triangles at a
height and the shell's openings, checked against the room's own closed-form dimensions) and the plan-view
map (plots/daylight_map.py: unit on the scale, stated error in the title, unmeasured points drawn and
counted as such, never as a colour; the PNG written whole or not at all). Pure (matplotlib Agg)."""

import pathlib
import runpy
import types

import numpy as np
import pytest

from radiometer.radiometry.scene import plan_section
from radiometer.radiometry.skies import sky_aperture


def _room():
    """tests/bpy/daylight_room.py as a namespace (its names run as a script)."""
    return types.SimpleNamespace(**runpy.run_path(str(pathlib.Path(__file__).parent / "bpy" / "daylight_room.py")))


def _triangles(quads):
    out = []
    for q in quads:
        q = np.asarray(q, float)
        out += [q[[0, 1, 2]], q[[0, 2, 3]]]
    return np.array(out)


def test_section_of_the_side_lit_room_is_its_outline():
    room = _room()
    tris = _triangles([q for _name, q in room.quads()])
    # a 4 x 3 m box cut at 0.85 m (below the 0.9 m sill): the whole 14 m perimeter, nothing inside it
    walls = plan_section.section_segments(tris, 0.85)
    lengths = np.linalg.norm(walls[:, 1] - walls[:, 0], axis=1)
    assert lengths.sum() == pytest.approx(2 * (room.W + room.D), rel=1e-12)
    ends = walls.reshape(-1, 2)
    on_edge = (np.isclose(ends[:, 0], 0) | np.isclose(ends[:, 0], room.W) | np.isclose(ends[:, 1], 0)
               | np.isclose(ends[:, 1], room.D))
    assert on_edge.all()
    # at 1.5 m the window (x 1-3 m in the wall y = 0) is a gap: 14 - 2 m of wall
    cut = plan_section.section_segments(tris, 1.5)
    assert np.linalg.norm(cut[:, 1] - cut[:, 0], axis=1).sum() == pytest.approx(14.0 - 2.0, rel=1e-12)
    # the plane's own height: a work plane lying in it and a triangle touching it at one vertex give nothing
    lying = _triangles([[(0, 0, 0.85), (1, 0, 0.85), (1, 1, 0.85), (0, 1, 0.85)]])
    touching = np.array([[(0, 0, 0.85), (1, 0, 2.0), (0, 1, 2.0)]])
    assert len(plan_section.section_segments(np.vstack([lying, touching]), 0.85)) == 0


def test_openings_in_plan_window_and_roof_light():
    room = _room()
    tris = _triangles([q for _name, q in room.quads()])
    walls, openings = plan_section.room_plan(tris, np.ones(len(tris), bool), 0.85)
    assert len(openings) == 1
    seg = openings[0]
    assert sorted(map(tuple, np.round(seg, 12))) == [(1.0, 0.0), (3.0, 0.0)]  # the window's span in the wall
    # a ceiling at 2.7 m with a 1 x 1 m roof light at x 1.5-2.5, y 1-2: drawn as its closed outline
    H = 2.7
    ceiling = [[(0, 0, H), (0, 1, H), (4, 1, H), (4, 0, H)], [(0, 2, H), (0, 3, H), (4, 3, H), (4, 2, H)],
               [(0, 1, H), (0, 2, H), (1.5, 2, H), (1.5, 1, H)], [(2.5, 1, H), (2.5, 2, H), (4, 2, H), (4, 1, H)]]
    (ring,) = plan_section.plan_openings(_triangles(ceiling))
    assert np.allclose(ring[0], ring[-1]) and len(ring) == 5
    area = 0.5 * abs(np.sum(ring[:-1, 0] * ring[1:, 1] - ring[1:, 0] * ring[:-1, 1]))
    assert area == pytest.approx(1.0, rel=1e-12)
    # opaque=False triangles (a glass pane) are left out of the section
    assert len(plan_section.room_plan(tris, np.zeros(len(tris), bool), 0.85)[0]) == 0


def test_room_of_boxes_has_only_its_window_as_opening():
    """The demo's daylit room (demo/daylight.py: 4 x 4 x 3 m of separate 0.1 m boxes, a 2 x 1.2 m window,
    sill 0.9 m, in the south wall y = -2.1..-2.0 m). The walls' bottom faces at z = 0 form a ring around the
    floor's top face and their top faces one around the roof's bottom face: coplanar faces, no opening.
    Before the fix both rings were drawn as openings along the four inner walls."""
    hx, hy, h, t, w, sill, head = 2.0, 2.0, 3.0, 0.1, 1.0, 0.9, 2.1
    boxes = _room().box_room_boxes(t, hx, hy, h, w, sill, head)
    tris = np.concatenate([_room().box_triangles(lo, hi) for lo, hi in boxes])
    found = sky_aperture.find_apertures(tris, 1e-6)
    assert len(found) == 2  # the window's outer (y = -2.1 m) and inner (y = -2.0 m) outlines
    for loop, normal in found:
        assert np.allclose(np.abs(normal), (0, 1, 0))
        assert np.allclose(loop.min(axis=0)[[0, 2]], (-w, sill)) and np.allclose(loop.max(axis=0)[[0, 2]], (w, head))
    segs = sorted(plan_section.plan_openings(tris), key=lambda s: s[0, 1])
    assert [sorted(map(tuple, np.round(s, 9))) for s in segs] == [[(-1.0, -2.1), (1.0, -2.1)],
                                                                 [(-1.0, -2.0), (1.0, -2.0)]]
    # a real hole beside a coplanar face is still one: cut a 1 x 1 m roof light (x 0..1, y 0..1) in the roof
    # box's bottom face, whose plane the walls' top faces share
    roof_light = [((-hx - t, -hy - t, h), (hx + t, 0.0, h + t)), ((-hx - t, 1.0, h), (hx + t, hy + t, h + t)),
                  ((-hx - t, 0.0, h), (0.0, 1.0, h + t)), ((1.0, 0.0, h), (hx + t, 1.0, h + t))]
    tris = np.concatenate([_room().box_triangles(lo, hi) for lo, hi in boxes[:1] + roof_light + boxes[2:]])
    holes = [loop for loop, normal in sky_aperture.find_apertures(tris, 1e-6) if abs(normal[2]) > 0.5]
    assert len(holes) == 2 and all(np.allclose(loop.min(axis=0), (0, 0, z)) and np.allclose(loop.max(axis=0), (1, 1, z))
                                   for loop, z in zip(sorted(holes, key=lambda s: s[0, 2]), (h, h + t)))


def test_error_share_text():
    from radiometer.plots.daylight_map import error_share_text

    assert error_share_text([0.012, 0.008, np.nan]) == "1 s.e. <= 1.2 % at every measured point"
    assert error_share_text([0.01, 0.02, np.nan], 0.015) == \
        "1 s.e. <= 1.5 % at 50 % of the 2 measured points (worst 2 %)"
    assert error_share_text([np.nan]) == "no point measured"


def test_lattice_shape():
    from radiometer.plots.daylight_map import lattice_shape

    xs, ys = np.meshgrid(0.25 + 0.5 * np.arange(5), 0.3 + 0.6 * np.arange(3))
    pts = np.c_[xs.ravel(), ys.ravel(), np.full(15, 0.85)]
    assert lattice_shape(pts) == (3, 5)
    rot = np.array([[0.6, -0.8], [0.8, 0.6]])
    assert lattice_shape(pts[:, :2] @ rot.T) == (3, 5)  # a rotated plane's grid
    assert lattice_shape(np.c_[np.arange(6.0), np.zeros(6)]) is None  # one row: no cells
    assert lattice_shape([[0, 0], [1, 0.1], [0, 1], [1.3, 1]]) is None  # scattered


def _grid(nx=6, ny=4):
    xs, ys = np.meshgrid((np.arange(nx) + 0.5) * 4 / nx, (np.arange(ny) + 0.5) * 3 / ny)
    return np.dstack([xs, ys]), 10 * np.exp(-ys / 0.8)


def test_map_unit_title_and_unmeasured_points():
    pytest.importorskip("matplotlib")
    from matplotlib.patches import Polygon

    from radiometer.plots.daylight_map import daylight_map_figure

    pts, df = _grid()
    df[2, 3] = np.nan
    df[0, 0] = np.inf
    fig = daylight_map_figure(df, pts, quantity="daylight factor", unit="%", title="Daylight factor",
                              error_text="DF relative 1 s.e. <= 1.2 % at every measured point",
                              walls=[[(0, 0), (4, 0)], [(4, 0), (4, 3)]], openings=[np.array([(1, 0), (3, 0)])],
                              section_height=0.85)
    ax, bar = fig.axes
    assert bar.get_ylabel() == "daylight factor (%)"
    assert ax.get_title() == "Daylight factor\nDF relative 1 s.e. <= 1.2 % at every measured point"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "not measured (2 of 24 points)" in legend
    assert "walls (section at z = 0.85 m)" in legend and "openings" in legend
    # the unmeasured cells are masked out of the colour mesh and drawn as hatched patches at their places
    mesh = ax.collections[0]
    masked = np.ma.getmaskarray(mesh.get_array()).reshape(df.shape)
    assert masked[2, 3] and masked[0, 0] and masked.sum() == 2
    hatched = [p for p in ax.patches if isinstance(p, Polygon) and p.get_hatch()]
    centres = sorted(tuple(np.round(p.get_xy()[:4].mean(axis=0), 9)) for p in hatched)
    assert centres == sorted([tuple(np.round(pts[2, 3], 9)), tuple(np.round(pts[0, 0], 9))])
    # the scale runs over the measured values only (0 to the largest finite one)
    assert mesh.norm.vmin == 0.0 and mesh.norm.vmax == pytest.approx(np.nanmax(np.where(np.isfinite(df), df, np.nan)))
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_scattered_points_and_flags():
    pytest.importorskip("matplotlib")
    from radiometer.plots.daylight_map import daylight_map_figure

    fig = daylight_map_figure(np.array([80.0, 40.0, np.nan]), np.array([[2, 0.75], [2, 1.5], [2, 2.5]]),
                              quantity="occupied hours at 300 lx or more", unit="%", vmin=0, vmax=100,
                              flagged=[False, True, False], flagged_label="uncertain at 2 s.e.")
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend == ["not measured (1 of 3 points)", "uncertain at 2 s.e. (1 point)"]
    assert len(ax.collections[0].get_offsets()) == 2  # only the measured points carry a colour
    assert fig.axes[1].get_ylabel() == "occupied hours at 300 lx or more (%)"
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_png_whole_or_not_at_all(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    from radiometer.plots.daylight_map import daylight_map_png

    pts, df = _grid()
    path = tmp_path / "df.png"
    assert daylight_map_png(str(path), df, pts, quantity="daylight factor", unit="%") == str(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["df.png"]
    before = path.read_bytes()

    def broken(self, fname, **kwargs):
        with open(fname, "wb") as f:
            f.write(b"\x89PNG half")
        raise OSError("disk full")

    monkeypatch.setattr(Figure, "savefig", broken)
    from radiometer.errors import RadiometerError

    with pytest.raises(RadiometerError, match="disk full"):
        daylight_map_png(str(path), df, pts, quantity="daylight factor", unit="%")
    assert path.read_bytes() == before and [p.name for p in tmp_path.iterdir()] == ["df.png"]


def test_plan_height():
    from radiometer.errors import RadiometerError
    from radiometer.plots.daylight_map import plan_height

    assert plan_height([0.85, 0.85, 0.85 + 5e-5]) == pytest.approx(0.85)
    with pytest.raises(RadiometerError, match="between z = 0.850 m and 1.200 m"):
        plan_height([0.85, 1.2, 0.85])
    with pytest.raises(RadiometerError, match="finite"):
        plan_height([0.85, np.nan])

"""Isolux plot (issue 23): standard levels, plain labels, smooth field, metric axes (pure, matplotlib Agg)."""

import math

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from radiometer.plots import isolux


def test_standard_levels_are_the_standard_steps():
    # EN 12464-1's scale of illuminances: 20, 30, 50, 75, 100, 150, 200, 300, 500, 750, 1000, 1500, 2000
    assert list(isolux.standard_levels(120, 820)) == [150, 200, 300, 500, 750]
    assert list(isolux.standard_levels(40, 2100)) == [50, 100, 200, 500, 1000, 2000]  # thinned: every other
    assert len(isolux.standard_levels(1, 1e5)) <= 8
    # a narrow range still gets isolines, at round numbers
    narrow = isolux.standard_levels(210, 270)
    assert len(narrow) >= 2 and all(210 < v < 270 and v % 10 == 0 for v in narrow)
    assert isolux.standard_levels(5, 5).size == 0
    assert isolux.standard_levels(float("nan"), 3).size == 0


def test_labels_are_plain_numbers():
    assert [isolux.format_lux(v) for v in (1500, 1110, 29100, 75, 7.5, 0.75, 0.2)] == \
        ["1500", "1110", "29100", "75", "7.5", "0.75", "0.2"]


def test_smooth_field_passes_through_the_measured_points_and_is_exact_for_a_quadratic():
    ny, nx = 5, 7
    xs, ys = (np.arange(nx) + 0.5) / nx, (np.arange(ny) + 0.5) / ny
    gx, gy = np.meshgrid(xs, ys)
    z = 300 + 100 * gx + 40 * gy + 80 * gx**2
    s, t, f = isolux.smooth_field(z, samples=(8 * nx + 1, 8 * ny + 1))
    # s = (i + 0.5) / nx lies on the fine grid at index 8 i + 4 (s = k / (8 nx))
    assert f[4::8, 4::8] == pytest.approx(z, rel=1e-12)
    fs, ft = np.meshgrid(s, t)
    inner = (fs > xs[1]) & (fs < xs[-2]) & (ft > ys[1]) & (ft < ys[-2])
    exact = 300 + 100 * fs + 40 * ft + 80 * fs**2
    assert np.max(np.abs(f - exact)[inner]) < 1e-9  # Keys' cubic reproduces quadratics


def test_rotated_scaled_plane_axes_in_metres():
    """A 5 x 3 m plane turned by 30 deg: the axes span its rotated outline, not a unit square."""
    a = math.radians(30)
    u = 5 * np.array([math.cos(a), math.sin(a)])
    v = 3 * np.array([-math.sin(a), math.cos(a)])
    o = np.array([1.0, -2.0]) - 0.5 * (u + v)
    lux = np.outer(np.linspace(200, 600, 5), np.ones(9)) + np.linspace(0, 300, 9)
    fig = isolux.isolux_figure(lux, o, u, v, stats={"avg": 512.3, "min": 200, "max": 900, "u0": 0.39},
                               title="t", mark_points=True)
    ax = fig.axes[0]
    corners = isolux.plane_outline(o, u, v)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    width = 5 * math.cos(a) + 3 * math.sin(a)
    depth = 5 * math.sin(a) + 3 * math.cos(a)
    assert x0 <= corners[:, 0].min() and x1 >= corners[:, 0].max()
    assert (x1 - x0) == pytest.approx(width * 1.06 if width > depth else width + 0.06 * depth, rel=1e-9)
    assert (y1 - y0) == pytest.approx(depth + 0.06 * max(width, depth), rel=1e-9)
    texts = [t.get_text() for t in ax.texts]
    assert "300" in texts or "500" in texts  # isoline labels at standard steps, plain numbers
    assert not any("e+" in t for t in texts)
    assert "E_avg 512 lx" in ax.get_title()
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_png_written_atomically(tmp_path):
    path = tmp_path / "iso.png"
    z = np.array([[100.0, 200.0], [300.0, 900.0]])
    assert isolux.isolux_png(str(path), z, (0, 0), (2, 0), (0, 1)) == str(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["iso.png"]


def test_other_plots_have_plain_axes_and_words(tmp_path):
    from radiometer.plots import convergence, goniometric, laws

    assert convergence.fit_in_words(-0.5) == "error halves with every 4x more samples"
    assert convergence.fit_in_words(0.1) == ""
    # beam/field angles of I = I0 cos^4: 50 % at acos(0.5^(1/4)) = 32.76 deg each side (closed form)
    v = np.linspace(0, 90, 3601)
    i = 600 * np.cos(np.radians(v)) ** 4
    assert goniometric.spread_angle(v, i, i, 0.5) == pytest.approx(2 * math.degrees(math.acos(0.5 ** 0.25)), abs=1e-3)
    assert goniometric.spread_angle(v, i, i, 0.1) == pytest.approx(2 * math.degrees(math.acos(0.1 ** 0.25)), abs=1e-3)
    batwing = np.sin(np.radians(v)) + 0.01
    assert goniometric.spread_angle(v, batwing, batwing, 0.5) is None
    laws.cosine_plot(str(tmp_path / "c.png"), [0, 30, 60], [1, 0.866, 0.5], [0.01] * 3, title="x " * 80)
    assert (tmp_path / "c.png").read_bytes()[:4] == b"\x89PNG"
    assert "\n" in laws._wrapped("x " * 80)


def test_false_colour_scale_range():
    from radiometer.plots.false_colour_image import scale_range

    v = np.concatenate([np.linspace(12, 80, 1000), [5000.0]])
    assert scale_range(v, "log") == (1.0, 100.0)  # two decades around the room, the lamp pixel clipped
    assert scale_range(v, "log", (0.1, 1e4)) == (0.1, 1e4)
    assert scale_range(np.zeros(4), "log") == (1e-3, 1.0)
    with pytest.raises(ValueError):
        scale_range(v, "log", (0.0, 10.0))

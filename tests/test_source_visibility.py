"""radiometry.scene.source_visibility: which part of a luminous polygon an eye sees, proven or bounded.

References: closed forms of the geometry (a straight baffle edge cuts a square panel at a line whose
place follows from similar triangles; the visible share of its solid angle is integrated independently
on a 600 x 600 grid of the panel's cells)."""

import numpy as np
import pytest

from radiometer.radiometry.scene import scene_model
from radiometer.radiometry.scene import source_visibility as sv

EYE = np.zeros(3)
PANEL = np.array([[-.3, -.3, 2.0], [.3, -.3, 2.0], [.3, .3, 2.0], [-.3, .3, 2.0]])  # 0.6 m square, 2 m above


def _quad(centre, ex, ey):
    c, ex, ey = (np.asarray(v, float) for v in (centre, ex, ey))
    p = [c - ex / 2 - ey / 2, c + ex / 2 - ey / 2, c + ex / 2 + ey / 2, c - ex / 2 + ey / 2]
    return [[p[0], p[1], p[2]], [p[0], p[2], p[3]]]


def _geometry(tris, opaque=True):
    tris = np.asarray(tris, float)
    return scene_model.SceneGeometry(triangles=tris, object_index=np.zeros(len(tris), int), object_names=["Baffle"],
                                     casts_shadow=np.array([True]), opaque=np.full(len(tris), opaque),
                                     reflects=np.array([True]), emissive=np.zeros(len(tris), bool))


def _visible_share(edge_x_at_1m, cells=600):
    """Share of the panel's solid angle whose ray from the eye passes z = 1 m at x >= edge (the baffle
    covers x < edge there): cell centres, weight cos / d² (cos = z / d)."""
    t = (np.arange(cells) + 0.5) / cells * 0.6 - 0.3
    x, y = np.meshgrid(t, t)
    d = np.sqrt(x * x + y * y + 4.0)
    w = 2.0 / d ** 3
    seen = x / 2.0 >= edge_x_at_1m
    return float((w * seen).sum() / w.sum())


def test_whole_baffle_proves_the_panel_hidden_at_the_first_cell():
    part = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(_quad([0, 0, 1], [1, 0, 0], [0, 1, 0])), 1e-7)
    assert part.status == sv.HIDDEN and part.upper == 0.0 and part.fraction == 0.0
    assert part.blockers == ["Baffle"] and part.cells == 1  # one proof: the quad's diagonal is interior


def test_baffle_off_to_the_side_and_a_flush_ceiling_leave_it_in_full_view():
    far = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(_quad([5, 5, 1], [1, 0, 0], [0, 1, 0])), 1e-7)
    flush = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(_quad([0, 0, 2], [8, 0, 0], [0, 8, 0])), 1e-7)
    behind = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(_quad([0, 0, 2.5], [8, 0, 0], [0, 8, 0])), 1e-7)
    for part in (far, flush, behind):
        assert part.status == sv.CLEAR and part.lower == 1.0 and part.fraction == 1.0
        assert part.omega_seen[0] == part.omega[0]


@pytest.mark.parametrize("edge", [0.0, 0.07, -0.11])
def test_partly_hidden_panel_bounds_hold_the_integrated_share(edge):
    """A baffle at z = 1 m covering x < edge: the proven bounds contain the independently integrated share
    and the estimate is within 1 % of it."""
    baffle = _quad([edge - 1.0, 0, 1], [2, 0, 0], [0, 2, 0])
    part = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(baffle), 1e-7)
    share = _visible_share(edge)
    assert part.status == sv.MIXED
    assert part.lower <= share <= part.upper
    assert part.upper - part.lower < 0.06
    assert part.fraction == pytest.approx(share, abs=0.01)


def test_glass_does_not_hide_and_is_named():
    part = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(_quad([0, 0, 1], [1, 0, 0], [0, 1, 0]), opaque=False),
                        1e-7)
    assert part.status == sv.CLEAR and part.see_through == ["Baffle"]


def test_a_baffle_with_a_hole_is_not_proven_hidden():
    """Four quads framing a 0.1 m hole at the pyramid's axis: not hidden (the hole's edges are boundary
    edges inside the section); the estimate sees the hole."""
    tris = []
    for c, ex, ey in (([0, 0.3, 1], [1, 0, 0], [0, 0.5, 0]), ([0, -0.3, 1], [1, 0, 0], [0, 0.5, 0]),
                      ([0.3, 0, 1], [0.5, 0, 0], [0, 0.1, 0]), ([-0.3, 0, 1], [0.5, 0, 0], [0, 0.1, 0])):
        tris += _quad(c, ex, ey)
    part = sv.seen_part(EYE, sv.polygon_cells(PANEL), _geometry(tris), 1e-7)
    assert part.status == sv.MIXED and part.upper > 0.0
    hole = (0.1 * 0.1 / 1.0) / (0.6 * 0.6 / 4.0)  # the hole's share of the section, paraxial (~0.11)
    assert part.fraction == pytest.approx(hole, rel=0.15)

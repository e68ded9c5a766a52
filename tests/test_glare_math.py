"""CIE 117 UGR building blocks (pure): solid angles, Levin's position index, the UGR sum."""

import math

import numpy as np
import pytest

from radiometer.radiometry.metrics import glare


def test_solid_angle_of_a_square_on_axis_closed_form():
    # square of side a at distance d on its axis: Omega = 4 asin(a^2 / (a^2 + 4 d^2)) (closed form)
    a, d = 0.6, 1.7
    sq = np.array([[-a / 2, -a / 2, d], [a / 2, -a / 2, d], [a / 2, a / 2, d], [-a / 2, a / 2, d]])
    assert glare.polygon_solid_angle((0, 0, 0), sq) == pytest.approx(4 * math.asin(a * a / (a * a + 4 * d * d)),
                                                                     rel=1e-12)
    assert glare.polygon_solid_angle((0, 0, 0), sq[::-1]) == pytest.approx(4 * math.asin(a * a / (a * a + 4 * d * d)))


def test_solid_angle_of_a_disk_on_axis():
    r, d = 0.3, 2.0
    poly = glare.disk_polygon((0, 0, d), (2 * r, 0, 0), (0, 2 * r, 0))
    assert glare.polygon_solid_angle((0, 0, 0), poly) == pytest.approx(2 * math.pi * (1 - d / math.hypot(d, r)),
                                                                       rel=3e-6)


def test_position_index_levin_values():
    # on the line of sight p = 1; Levin's form at sigma = 45 deg straight above (tau = 0):
    # exp((35.2 - 1.22) 1e-3 * 45 + 21e-5 * 2025) = exp(1.5291 + 0.42525)
    assert glare.position_index(0.0, 0.0) == pytest.approx(1.0)
    assert glare.position_index(45.0, 0.0) == pytest.approx(math.exp(33.98e-3 * 45 + 21e-5 * 45**2))
    # farther off the line of sight, a source matters less: p grows with sigma at any tau
    s = np.linspace(1, 80, 50)
    for tau in (0.0, 30.0, 60.0, 90.0):
        assert np.all(np.diff(glare.position_index(s, tau)) > 0)


def test_view_angles_and_field():
    sigma, tau, elev = glare.view_angles((0, 1, 0), np.array([[0, 1, 1], [1, 1, 0], [0, 1, -1], [0, -1, 0.1]]))
    assert sigma == pytest.approx([45, 45, 45, 180 - math.degrees(math.atan(0.1))])
    assert tau[0] == pytest.approx(0) and tau[1] == pytest.approx(90) and tau[2] == pytest.approx(180)
    assert list(glare.in_field(sigma, elev)) == [True, False, False, False]
    with pytest.raises(ValueError):
        glare.view_frame((0, 0, 1))


def test_ugr_formula():
    # one source: UGR = 8 log10(0.25 / Lb * L^2 w / p^2)
    assert glare.ugr(40.0, [10000.0], [0.01], [2.0]) == pytest.approx(8 * math.log10(0.25 / 40 * 1e8 * 0.01 / 4))
    assert glare.ugr(40.0, [], [], []) == -math.inf
    with pytest.raises(ValueError):
        glare.ugr(0.0, [1.0], [0.01], [1.0])


def test_projected_opening_and_units():
    assert glare.projected_opening_area(0.6, 0.6, 0.0, 60.0) == pytest.approx(0.18)
    assert glare.projected_opening_area(-0.2, -0.2, 0.0, 0.0) == pytest.approx(math.pi * 0.01)
    assert glare.projected_opening_area(0.6, 0.6, 0.1, 0.0) is None
    assert glare.luminous_opening_m({"units_type": 1, "luminous_width": 2.0, "luminous_length": 1.0,
                                     "luminous_height": 0.0}) == pytest.approx((0.6096, 0.3048, 0.0))
    assert glare.luminous_opening_m({"luminous_width_mm": 0, "luminous_length_mm": 200}) == (-0.2, -0.2, 0.0)
    assert glare.luminous_opening_m({"units_type": 2, "luminous_width": 0, "luminous_length": 0,
                                     "luminous_height": 0}) is None


def test_triangles_and_patches_make_one_source():
    """A square split into two triangles: the triangles' solid angles add up to the square's (Van Oosterom &
    Strackee both ways, and the closed form of a square on its axis, 4 asin(a² / (a² + 4 h²))); uniform
    patches keep their luminance; the centre is the centre of the luminous area."""
    from radiometer.radiometry.metrics import glare as g

    eye = np.array([0.3, -0.2, 0.0])
    square = np.array([[-0.5, -0.5, 2.0], [0.5, -0.5, 2.0], [0.5, 0.5, 2.0], [-0.5, 0.5, 2.0]])
    tris = np.array([square[[0, 1, 2]], square[[0, 2, 3]]])
    omega = g.triangle_solid_angles(eye, tris)
    assert omega.sum() == pytest.approx(g.polygon_solid_angle(eye, square), rel=1e-12)
    on_axis = g.triangle_solid_angles(np.zeros(3), tris).sum()
    assert on_axis == pytest.approx(4 * np.arcsin(1.0 / (1.0 + 4 * 2.0**2)), rel=1e-12)
    lum, total, centre = g.patches_as_one_source(tris.mean(axis=1), [0.5, 0.5], [800.0, 800.0], omega)
    assert lum == pytest.approx(800.0) and total == pytest.approx(omega.sum()) and centre == pytest.approx([0, 0, 2])
    lum, _total, _c = g.patches_as_one_source(tris.mean(axis=1), [0.5, 0.5], [600.0, 800.0], [1.0, 1.0])
    assert lum == pytest.approx(np.sqrt((600.0**2 + 800.0**2) / 2))  # L² omega is the sum of the patches' terms

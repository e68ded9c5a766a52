"""Thin glass (issue 18): Fresnel, the slab's closed form, stacks and the crossing proofs."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from radiometer.radiometry.scene import thin_glass


@given(st.floats(0.0, 1.0), st.floats(1.01, 3.0), st.floats(0.0, 0.05), st.floats(0.0, 50.0),
       st.floats(0.0, 1.0), st.floats(0.0, 1.0))
@settings(max_examples=100, deadline=None)
def test_energy_is_conserved(cos_i, ior, d, sigma, tint_t, tint_r):
    T, R, A = thin_glass.slab(cos_i, ior, d, (sigma,) * 3, (tint_t,) * 3, (tint_r,) * 3)
    assert np.all(T >= 0) and np.all(R >= 0) and np.all(A >= -1e-12)
    assert np.allclose(T + R + A, 1.0, atol=1e-12)


@pytest.mark.parametrize("ior", [1.33, 1.45, 1.5, 1.52, 2.4])
def test_normal_incidence_closed_forms(ior):
    r0 = ((ior - 1) / (ior + 1)) ** 2
    rs, rp = thin_glass.fresnel_dielectric(1.0, ior)
    assert rs == pytest.approx(r0, rel=1e-12) and rp == pytest.approx(r0, rel=1e-12)
    # One interface passes 1 - r0; a clear pane with all its internal reflections (1 - r0)/(1 + r0).
    T, R, A = thin_glass.slab(1.0, ior)
    assert T == pytest.approx(np.full(3, (1 - r0) / (1 + r0)), rel=1e-12)
    assert T == pytest.approx(np.full(3, 2 * ior / (ior ** 2 + 1)), rel=1e-12)
    assert A == pytest.approx(np.zeros(3), abs=1e-15)
    # Absorption: a 6 mm pane of sigma_a = 10 / m at normal incidence (internal transmittance a).
    a = np.exp(-10 * 0.006)
    T, R, _A = thin_glass.slab(1.0, ior, 0.006, (10.0,) * 3)
    assert T == pytest.approx(np.full(3, (1 - r0) ** 2 * a / (1 - (r0 * a) ** 2)), rel=1e-12)


def test_known_values_and_limits():
    # Brewster's angle: p-polarised light is not reflected.
    ior = 1.5
    cos_b = np.cos(np.arctan(ior))
    assert thin_glass.fresnel_dielectric(cos_b, ior)[1] == pytest.approx(0.0, abs=1e-15)
    # Textbook value: n = 1.5 at 45 degrees, R_s = 0.0920, R_p = 0.0085 (Hecht, Optics, fig. 4.49).
    rs, rp = thin_glass.fresnel_dielectric(np.cos(np.radians(45)), 1.5)
    assert rs == pytest.approx(0.09202, abs=5e-5) and rp == pytest.approx(0.00847, abs=5e-5)
    # Grazing incidence: nothing passes.
    T, R, _ = thin_glass.slab(1e-9, 1.5)
    assert np.all(T < 1e-8) and np.allclose(R, 1.0, atol=1e-8)
    # Monotone in the angle (no absorption): T falls from normal to grazing.
    T = thin_glass.slab(np.linspace(1.0, 0.0, 200), 1.52)[0][:, 0]
    assert np.all(np.diff(T) <= 1e-15)
    # Tint acts per crossing: a Glass BSDF of colour c passes c^2 of the clear pane when r -> 0.
    T, _R, _A = thin_glass.slab(1.0, 1.0 + 1e-9, tint_t=(0.5, 0.8, 1.0))
    assert T == pytest.approx([0.25, 0.64, 1.0], rel=1e-9)
    # Vectorised over any leading shape; NaN/inf in do not crash.
    assert thin_glass.slab(np.ones((2, 5)), 1.5)[0].shape == (2, 5, 3)
    thin_glass.slab(np.array([np.nan, np.inf, -np.inf, -1.0, 2.0]), 1.5)


def test_stack_of_two_panes_is_the_adding_formula():
    t, r, _ = thin_glass.slab(1.0, 1.52)
    T2, R2 = thin_glass.stack([(t, r), (t, r)])
    assert T2 == pytest.approx(t * t / (1 - r * r), rel=1e-12)
    # The adding formula of two clear interfaces is the slab itself: one interface T = 1 - r0.
    r0 = ((1.52 - 1) / 2.52) ** 2
    Ts, Rs = thin_glass.stack([(np.full(3, 1 - r0), np.full(3, r0))] * 2)
    assert Ts == pytest.approx(t, rel=1e-12) and Rs == pytest.approx(r, rel=1e-12)


def _box(lo, hi):
    """12 triangles of an axis-aligned box (a flat slab when one side is thin)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]])
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return np.array([[v[a], v[b], v[c]] for a, b, c, d in quads] + [[v[a], v[c], v[d]] for a, b, c, d in quads])


def test_pane_geometry_and_crossings():
    tol = 1e-9
    slab_tris = _box((-1, -0.003, 0.0), (1, 0.003, 2.0))  # a 2 x 2 m pane, 6 mm thick, normal along y
    geom, why = thin_glass.pane_geometry(slab_tris, tol)
    assert geom is not None, why
    assert geom.thickness == pytest.approx(0.006) and abs(geom.normal[1]) == pytest.approx(1.0)
    ok, c = thin_glass.segment_crossing(geom, (0, -2, 1), (0.5, 2, 1.5), tol)
    assert ok and c == pytest.approx(4 / np.linalg.norm([0.5, 4, 0.5]))
    assert not thin_glass.segment_crossing(geom, (0, -2, 1), (4, 2, 1), tol)[0]   # leaves past the edge
    assert not thin_glass.segment_crossing(geom, (0, -2, 1), (0, -1, 1), tol)[0]  # never reaches it
    assert not thin_glass.segment_crossing(geom, (0, 0.0, 1), (0, 2, 1), tol)[0]  # starts inside the glass
    base = np.array([[-0.1, 5, 0.9], [0.1, 5, 0.9], [0.1, 5, 1.1], [-0.1, 5, 1.1]])
    ok, cmin, cmax = thin_glass.pyramid_crossing(geom, (0, -1, 1.0), base, tol)
    assert ok and cmax == 1.0 and cmin == pytest.approx(6 / np.linalg.norm([0.1, 6, 0.1]))
    assert not thin_glass.pyramid_crossing(geom, (0, -1, 1.9), base + [0, 0, 2.0], tol)[0]
    # A single face is a pane too; an L-shaped face, a bent sheet or a bevelled slab are not.
    face = slab_tris[[0, 6]]
    assert thin_glass.pane_geometry(face, tol)[0] is not None
    assert thin_glass.pane_geometry(face[:1], tol)[0] is not None  # a triangular pane
    apart = np.concatenate([face[:1], face[:1] + [3.0, 0, 0]])   # two panes in one object: holes in the hull
    assert "outline" in thin_glass.pane_geometry(apart, tol)[1]
    bent = face.copy()
    bent[1, 2, 2] += 0.1
    assert thin_glass.pane_geometry(bent, tol)[0] is None


def test_parallel_panes_are_a_stack_and_their_interpane_share_is_r_squared():
    """Issue 18, F5: two identical clear panes pass T^2 / (1 - R^2), of which the light bounced between
    them is the share R^2 (R the single pane's reflectance, the slab's own closed form 2 r0 / (1 + r0)
    at normal incidence); panes side by side or crossed are no stack."""
    tol = 1e-9

    def pane(name, lo, hi, ior=1.52):
        geom, why = thin_glass.pane_geometry(_box(lo, hi), tol)
        assert geom is not None, why
        return thin_glass.Pane(name=name, ior=ior, thickness=geom.thickness, geometry=geom)

    a = pane("a", (-1, 0.000, 0), (1, 0.004, 2))
    b = pane("b", (-0.5, 0.020, 0.5), (0.5, 0.024, 1.5))   # behind a, overlapping it
    beside = pane("beside", (3, 0.020, 0), (4, 0.024, 2))  # parallel but outside a's outline
    crossed = pane("crossed", (2, -1, 0), (2.004, 1, 2))   # normal along x
    assert thin_glass.parallel_stacks({1: a, 2: b, 3: beside, 4: crossed}) == [[1, 2]]
    assert thin_glass.parallel_stacks({1: a, 3: beside, 4: crossed}) == []
    r0 = ((1.52 - 1) / 2.52) ** 2
    R = 2 * r0 / (1 + r0)
    assert thin_glass.interpane_share([a, b], 1.0) == pytest.approx(R * R, rel=1e-12)
    assert thin_glass.interpane_share([a], 1.0) == 0.0
    assert thin_glass.interpane_share([a, b], 0.5) > R * R  # Fresnel R grows with the angle

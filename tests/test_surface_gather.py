"""radiometry.sampling.surface_gather: the cells cover the surfaces, the points fall uniformly in them, and the
estimate of the light a Lambertian surface sends a meter is unbiased against an independent closed form."""

import math

import numpy as np

from radiometer.radiometry.sampling import surface_gather as sg


def _square(z=0.0, size=2.0):
    a = np.array([[-1, -1, z], [1, -1, z], [1, 1, z], [-1, 1, z]], float) * [size / 2, size / 2, 1]
    return np.array([a[[0, 1, 2]], a[[0, 2, 3]]])


def _area(t):
    return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)


def test_subdivide_and_refine_cover_the_triangles():
    tris = _square(size=3.0)
    cells, owner = sg.subdivide(tris, 0.5)
    assert np.isclose(_area(cells).sum(), 9.0) and set(owner) == {0, 1}
    assert np.all([np.isclose(_area(cells[owner == k]).sum(), _area(tris[k:k + 1])[0]) for k in (0, 1)])
    fine, fown = sg.refine(cells, owner, np.array([[0.0, 0.0, 0.3]]), 0.05)
    assert np.isclose(_area(fine).sum(), 9.0) and len(fine) > len(cells)
    centre = np.linalg.norm(fine.mean(axis=1)[:, :2], axis=1)
    assert _area(fine[centre < 0.2]).max() < _area(fine[centre > 1.2]).max()  # finer under the meter


def test_uniform_points_fall_inside_and_spread_evenly():
    tri = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], float)
    rng = np.random.default_rng(3)
    p = np.array([sg.uniform_points(tri, rng)[0] for _ in range(20000)])
    assert np.all(p[:, :2] >= 0) and np.all(p[:, 0] + p[:, 1] <= 1)
    # uniform in a triangle: mean at the centroid, P(x < 0.5) = 1 - 0.25 = 0.75
    assert np.allclose(p[:, :2].mean(axis=0), [1 / 3, 1 / 3], atol=0.01)
    assert abs(np.mean(p[:, 0] < 0.5) - 0.75) < 0.01


def test_gathered_light_of_a_uniform_square_is_its_form_factor():
    """A uniform Lambertian square of radiance L above a meter facing it: E = L x pi x the point-to-square form
    factor (closed form for a square centred over the point, e.g. Howell's catalogue C-11). The gather estimate
    (one random point per cell, many draws) must agree within its own batch-means error, and the error be honest."""
    h, s = 1.0, 2.0                       # height, side
    a = s / (2 * h)
    ff = 2.0 / math.pi * (a / math.sqrt(1 + a * a) * math.atan(a / math.sqrt(1 + a * a))) * 2  # Howell C-11 (centred)
    tris = _square(z=h, size=s)
    cells, _owner = sg.subdivide(tris, 0.4)
    areas = _area(cells)
    down = np.tile([0.0, 0.0, -1.0], (len(cells), 1))
    p, n = np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.0, 1.0]])
    rng = np.random.default_rng(7)
    draws = np.array([sg.transfer(p, n, sg.uniform_points(cells, rng), down, areas).sum() for _ in range(400)])
    est, se = draws.mean(), draws.std(ddof=1) / math.sqrt(len(draws))
    truth = math.pi * ff  # E for L = 1
    assert abs(est - truth) <= 4 * se + 1e-12, (est, truth, se)
    assert se < 0.01 * truth

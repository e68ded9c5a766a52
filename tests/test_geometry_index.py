"""Issue 17: the triangle grid and the per-object structures that sensor placement and the proofs share
(radiometry.scene.visibility.TriangleGrid, radiometry.scene.scene_model.SceneGeometry), built in O(T). Checked against
the definitions they index: brute-force box overlap, numpy's own reductions, per-object masks."""

import numpy as np

from radiometer.radiometry.scene import scene_model, visibility


def _soup(rng, n, big=0.1):
    """Random triangles in a 6 x 5 x 3 m box: mostly small, a share ``big`` spanning many cells."""
    centre = rng.uniform([-3, -2.5, 0], [3, 2.5, 3], (n, 1, 3))
    size = np.where(rng.random((n, 1, 1)) < big, 2.0, 0.05)
    return centre + size * rng.normal(size=(n, 3, 3))


def test_grid_query_is_exactly_the_box_overlap():
    rng = np.random.default_rng(7)
    tris = _soup(rng, 4000)
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    grid = visibility.TriangleGrid(lo, hi)
    for _ in range(300):
        a, b = np.sort(rng.uniform([-4, -3.5, -1], [4, 3.5, 4], (2, 3)), axis=0)
        if rng.random() < 0.3:
            b = a  # a point, as sensor placement asks
        pad = float(rng.choice([0.0, 1e-6, 0.2]))
        expect = np.flatnonzero(visibility.aabb_overlap(lo, hi, a, b, pad))
        assert np.array_equal(grid.query(a, b, pad), expect)


def test_grid_with_more_cells_than_16_bits_and_flat_scenes():
    rng = np.random.default_rng(3)
    tris = _soup(rng, 1500, big=0.3)
    tris[:, :, 2] = 0.0  # a flat floor: one cell thick in z
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    for cells in (32, 48):  # 48 per axis: more cells than 16-bit keys hold
        grid = visibility.TriangleGrid(lo, hi, cells_per_axis=cells)
        for _ in range(100):
            a, b = np.sort(rng.uniform([-4, -3.5, -0.1], [4, 3.5, 0.1], (2, 3)), axis=0)
            assert np.array_equal(grid.query(a, b, 0.01), np.flatnonzero(visibility.aabb_overlap(lo, hi, a, b, 0.01)))
    assert visibility.TriangleGrid(np.zeros((0, 3)), np.zeros((0, 3))).query([0, 0, 0], [1, 1, 1], 0.1).size == 0


def test_bounds_and_column_reductions_equal_numpys():
    rng = np.random.default_rng(1)
    tris = _soup(rng, 500)
    lo, hi = scene_model.triangle_bounds(tris)
    assert np.array_equal(lo, tris.min(axis=1)) and np.array_equal(hi, tris.max(axis=1))
    x = rng.normal(size=(300, 3))
    assert np.array_equal(visibility.column_min(x), x.min(axis=0))
    assert np.array_equal(visibility.column_max(x), x.max(axis=0))


def _reference_object_vertices(g):
    """The definition: each object's triangles by mask, its box from its vertices."""
    out = {}
    for k in range(len(g.object_names)):
        mask = g.object_index == k
        verts = g.triangles[mask].reshape(-1, 3)
        if len(verts):
            out[k] = (verts, verts.min(axis=0), verts.max(axis=0), g.triangles[mask & g.emissive])
    return out


def test_object_vertices_contiguous_and_shuffled():
    rng = np.random.default_rng(5)
    tris = _soup(rng, 900)
    counts = [400, 0, 300, 200]  # one object without triangles
    index = np.repeat(np.arange(4), counts)
    emissive = rng.random(900) < 0.2
    for order in (np.arange(900), rng.permutation(900)):  # a capture's order, and hand-built geometry's
        g = scene_model.SceneGeometry(triangles=tris[order], object_index=index[order], object_names=list("abcd"),
                                      casts_shadow=np.ones(4, bool), reflects=np.ones(4, bool),
                                      opaque=np.ones(900, bool), emissive=emissive[order])
        assert (g.object_ranges() is not None) == np.array_equal(order, np.arange(900))
        ref = _reference_object_vertices(g)
        got = g.object_vertices()
        assert [k for k, *_ in got] == [0, 2, 3]  # largest first, the empty object left out
        for k, verts, corners, emitting in got:
            r_verts, r_lo, r_hi, r_emit = ref[k]
            assert np.array_equal(verts, r_verts) and np.array_equal(emitting, r_emit)
            assert np.array_equal(corners.min(axis=0), r_lo) and np.array_equal(corners.max(axis=0), r_hi)
            assert len(corners) == 8


def test_lazy_grid_scans_then_builds_with_the_same_answers():
    rng = np.random.default_rng(11)
    tris = _soup(rng, 3000)
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    lazy = visibility.LazyTriangleGrid(lo, hi)
    for k in range(2 * lazy.BUILD_AFTER):
        assert lazy.built == (k > lazy.BUILD_AFTER)  # scans first, the grid once it pays
        a, b = np.sort(rng.uniform([-4, -3.5, -1], [4, 3.5, 4], (2, 3)), axis=0)
        pad = float(rng.choice([0.0, 1e-6, 0.2]))
        assert np.array_equal(lazy.query(a, b, pad), np.flatnonzero(visibility.aabb_overlap(lo, hi, a, b, pad)))
    far = lazy.query([50, 50, 50], [51, 51, 51], 0.1)
    assert far.size == 0 and visibility.LazyTriangleGrid(np.zeros((0, 3)), np.zeros((0, 3))).query(
        [0, 0, 0], [1, 1, 1], 0.1).size == 0
    g = scene_model.SceneGeometry(triangles=tris, object_index=np.zeros(3000, int), object_names=["soup"])
    assert isinstance(g.grid, visibility.LazyTriangleGrid) and g.grid is g.grid  # one per geometry

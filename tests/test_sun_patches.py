"""The sunlit polygons (radiometry/scene/sun_patches.py) against an independent Monte Carlo: rays cast from
random points of each surface towards the sun (and towards its image in the pane) through the triangles
by brute force (Moller-Trumbore), the pane crossed as its thin-pane model has it."""

import numpy as np
import pytest

from radiometer.radiometry.scene import sun_patches, thin_glass

WALL, PANE = 0.1, 0.006


def box(lo, hi):
    """12 triangles (outward) of an axis-aligned box."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], float)
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (3, 0, 4, 7)]
    return np.array([v[[a, b, c]] for a, b, c, d in faces] + [v[[a, c, d]] for a, b, c, d in faces])


def room(window=(2.0, 0.9, 2.1), pane=True):
    """The demo's 4 x 4 x 3 m room with 0.1 m walls and a south window (a 6 mm pane at mid-wall)."""
    hx, hy, h, t = 2.0, 2.0, 3.0, WALL
    w, sill, head = window[0] / 2, window[1], window[2]
    y0, y1 = -hy - t, -hy
    parts = [box((-hx - t, -hy - t, -t), (hx + t, hy + t, 0.0)), box((-hx - t, -hy - t, h), (hx + t, hy + t, h + t)),
             box((-hx - t, hy, 0.0), (hx + t, hy + t, h)), box((hx, -hy, 0.0), (hx + t, hy, h)),
             box((-hx - t, -hy, 0.0), (-hx, hy, h)),
             box((-hx - t, y0, 0.0), (hx + t, y1, sill)), box((-hx - t, y0, head), (hx + t, y1, h)),
             box((-hx - t, y0, sill), (-w, y1, head)), box((w, y0, sill), (hx + t, y1, head))]
    tris = np.concatenate(parts)
    panes = []
    if pane:
        yc = -hy - t / 2
        pt = box((-w, yc - PANE / 2, sill), (w, yc + PANE / 2, head))
        geom, why = thin_glass.pane_geometry(pt, 1e-7)
        assert geom is not None, why
        panes.append(thin_glass.Pane(name="pane", ior=1.5, thickness=PANE, geometry=geom))
    return tris, panes


def _hits(origins, d, tris, t_max=None):
    """(N,) bool: the ray from each origin along d meets a triangle at 1e-9 < t (< t_max)."""
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    p = np.cross(d, e2)
    det = e1 @ np.zeros(3) if False else np.einsum("mk,mk->m", e1, p)
    ok = np.abs(det) > 1e-15
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = origins[:, None, :] - tris[None, :, 0]
    u = np.einsum("nmk,mk->nm", s, p) * inv
    q = np.cross(s, e1[None])
    v = np.einsum("nmk,k->nm", q, d) * inv
    t = np.einsum("nmk,mk->nm", q, e2) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
    if t_max is not None:
        hit &= t < t_max[:, None]
    return hit.any(axis=1)


def _cross_pane(origins, d, pane):
    """(crosses (N,), t (N,), cos): where the ray along d meets the pane's mid-plane inside its outline."""
    outline = sun_patches.pane_outline(pane.geometry)
    n = np.asarray(pane.geometry.normal, float)
    c = float(d @ n)
    t = ((outline[0] - origins) @ n) / c if abs(c) > 1e-15 else np.full(len(origins), -1.0)
    x = origins + t[:, None] * d
    inside = t > 1e-9
    for k in range(len(outline)):
        a, b = outline[k], outline[(k + 1) % len(outline)]
        inside &= np.cross(b - a, x - a) @ n * np.sign(np.cross(outline[1] - outline[0], outline[2] - outline[1]) @ n) >= 0
    return inside, t, abs(c)


def monte_carlo(tris, occ_mask, panes, d, receiver, n=4000, seed=0):
    """(direct, mirror) flux (m^2, channel 0) on triangle ``receiver``'s sunlit side per unit normal irradiance."""
    rng = np.random.default_rng(seed)
    tri = tris[receiver]
    r1, r2 = rng.random(n), rng.random(n)
    flip = r1 + r2 > 1
    r1[flip], r2[flip] = 1 - r1[flip], 1 - r2[flip]
    pts = tri[0] + r1[:, None] * (tri[1] - tri[0]) + r2[:, None] * (tri[2] - tri[0])
    nrm = np.cross(tri[1] - tri[0], tri[2] - tri[0])
    area = 0.5 * np.linalg.norm(nrm)
    nrm /= np.linalg.norm(nrm)
    occ = tris[occ_mask]
    out = []
    c = float(nrm @ d)
    n_lit = nrm if c > 0 else -nrm
    lift = pts + 1e-7 * n_lit
    factor = np.where(_hits(lift, d, occ), 0.0, 1.0)
    for pane in panes:
        crosses, _t, cp = _cross_pane(lift, d, pane)
        factor = np.where(crosses, factor * pane.optics(cp)[0][0], factor)
    out.append(area * abs(c) * factor.mean())
    mirror = 0.0
    for pane in panes:
        pn = np.asarray(pane.geometry.normal, float)
        pn = pn if pn @ d > 0 else -pn
        image = d - 2 * (d @ pn) * pn
        ci = float(nrm @ image)
        n_img = nrm if ci > 0 else -nrm
        lift = pts + 1e-7 * n_img
        side = (lift - sun_patches.pane_outline(pane.geometry)[0]) @ pn > 0
        crosses, t, cp = _cross_pane(lift, image, pane)
        ok = side & crosses & ~_hits(lift, image, occ, t_max=t)
        at = lift + t[:, None] * image + 1e-7 * pn
        ok &= ~_hits(at, d, occ)
        mirror += area * abs(ci) * pane.optics(cp)[1][0] * ok.mean()
    out.append(mirror)
    return out


@pytest.mark.parametrize("direction", [
    (0.0259, -0.781, 0.624),   # midday (38 deg), the sun through the pane onto the floor
    (0.9983, -0.0413, 0.0349),  # 2 deg, 2.4 deg south of east: only the west reveal is lit
    (0.5, -0.6, 0.3),
])
def test_sunlit_polygons_match_rays(direction):
    tris, panes = room()
    d = np.asarray(direction, float)
    d /= np.linalg.norm(d)
    occ = np.ones(len(tris), bool)
    pieces = sun_patches.sunlit_pieces(tris, occ, occ, d, panes=panes, tol=1e-7)
    assert pieces.proven
    flux = pieces.flux()[:, 0]
    kinds = np.array(pieces.kind)
    rng = np.random.default_rng(1)
    # every lit triangle and a sample of the unlit ones
    lit = np.unique(pieces.triangle)
    others = np.setdiff1d(np.arange(len(tris)), lit)
    chosen = np.concatenate([lit, rng.choice(others, size=min(6, len(others)), replace=False)])
    quads = sorted({min(k, _partner(tris, k)) for k in chosen})  # the box faces' two triangles, merged
    for k in quads:
        pair = (k, _partner(tris, k))
        mc = np.sum([monte_carlo(tris, occ, panes, d, j, n=2000) for j in pair], axis=0)
        area = sum(0.5 * np.linalg.norm(np.cross(tris[j, 1] - tris[j, 0], tris[j, 2] - tris[j, 0])) for j in pair)
        se = area * 0.5 / np.sqrt(2000) + 1e-9  # binomial s.e. of a lit share at 2000 rays a triangle, m^2
        for i, kind in enumerate(("direct", "mirror")):
            got = flux[np.isin(pieces.triangle, pair) & (kinds == kind)].sum()
            assert abs(got - mc[i]) <= 5 * se, (k, kind, got, mc[i])


def _partner(tris, k):
    """The other triangle of k's quad (the box faces are two triangles each, k and k + 6)."""
    base = (k // 12) * 12
    j = k - base
    return base + (j + 6) % 12


def test_pieces_do_not_overlap_and_stay_on_their_surface():
    tris, panes = room()
    d = np.array([0.3, -0.8, 0.5])
    d /= np.linalg.norm(d)
    occ = np.ones(len(tris), bool)
    pieces = sun_patches.sunlit_pieces(tris, occ, occ, d, panes=panes, tol=1e-7, mirrors=False)
    area = pieces.area()
    for k in np.unique(pieces.triangle):
        tri_area = 0.5 * np.linalg.norm(np.cross(tris[k, 1] - tris[k, 0], tris[k, 2] - tris[k, 0]))
        partner = _partner(tris, k)
        assert area[pieces.triangle == k].sum() <= 2 * tri_area * (1 + 1e-9)
        n = np.cross(tris[k, 1] - tris[k, 0], tris[k, 2] - tris[k, 0])
        n /= np.linalg.norm(n)
        for poly in np.asarray(pieces.polygons, dtype=object)[pieces.triangle == k]:
            assert np.allclose((poly - tris[k, 0]) @ n, 0.0, atol=1e-9)
        assert partner is not None


def test_disc_cubature_integrates_quadratics_over_the_disc():
    d = np.array([0.2, -0.5, 0.8])
    a = np.radians(0.265)
    dirs, w = sun_patches.disc_cubature(d, a)
    assert np.isclose(w.sum(), 1.0)
    d = d / np.linalg.norm(d)
    ang = np.arccos(np.clip(dirs @ d, -1, 1))
    assert np.all(ang <= a * (1 + 1e-9))
    # mean of the squared angle over a uniform disc of radius a is a^2 / 2
    assert np.isclose(np.sum(w * ang ** 2), a ** 2 / 2, rtol=1e-6, atol=0.0)
    assert np.isclose(np.sum(w * ang ** 4), a ** 4 / 3, rtol=1e-5, atol=0.0)
    dirs2, w2 = sun_patches.disc_cubature(d, a, degree=2)
    ang2 = np.arccos(np.clip(dirs2 @ d, -1, 1))
    assert len(w2) == 3 and np.isclose(w2.sum(), 1.0) and np.isclose(np.sum(w2 * ang2 ** 2), a ** 2 / 2, rtol=1e-6, atol=0.0)
    # degree 2 only: the fourth moment is off (1/4 against 1/3 of a^4)
    assert not np.isclose(np.sum(w2 * ang2 ** 4), a ** 4 / 3, rtol=1e-2, atol=0.0)


def test_merge_pairs_keeps_area():
    tris, _ = room(pane=False)
    polys, owner = sun_patches.merge_pairs(tris, [0] * len(tris), 1e-9)
    assert len(polys) == len(tris) // 2
    area = sum(sun_patches.polygon_area_3d(p[[0, 1, 2, 3]] if not np.allclose(p[3], p[2]) else p[:3]) for p in polys)
    tri_area = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1).sum()
    assert np.isclose(area, tri_area)


def test_work_beyond_its_limits_is_refused_with_the_reason():
    tris, panes = room()
    occ = np.ones(len(tris), bool)
    d = np.array([0.3, -0.8, 0.5]) / np.linalg.norm([0.3, -0.8, 0.5])
    late = sun_patches.sunlit_pieces(tris, occ, occ, d, panes=panes, deadline=0.0)
    assert not late.proven and "time" in late.reason and not late.polygons
    many = sun_patches.sunlit_pieces(tris, occ, occ, d, panes=panes, max_pairs=10)
    assert not many.proven and "pairs" in many.reason
    few = sun_patches.sunlit_pieces(tris, occ, occ, d, panes=panes, max_pieces=3)
    assert not few.proven and "pieces" in few.reason


def test_an_image_that_lights_another_pane_is_refused():
    """Two panes in an L: the sun's image in one lights the other, whose own reflection of it (two reflections)
    is not cast, so the polygons are refused with the reason (the step then renders the sun)."""
    def pane(lo, hi, name):
        geom, why = thin_glass.pane_geometry(box(lo, hi), 1e-7)
        assert geom is not None, why
        return thin_glass.Pane(name=name, ior=1.5, thickness=PANE, geometry=geom)

    a = pane((0.2, -PANE / 2, 0.0), (1.2, PANE / 2, 1.0), "A")
    b = pane((-PANE / 2, 0.2, 0.0), (PANE / 2, 1.2, 1.0), "B")
    floor = box((-3.0, -3.0, -0.2), (3.0, 3.0, -0.1))
    occ = np.ones(len(floor), bool)
    d = np.array([0.5, 0.8, 0.3]) / np.linalg.norm([0.5, 0.8, 0.3])
    both = sun_patches.sunlit_pieces(floor, occ, occ, d, panes=[a, b], tol=1e-7)
    assert not both.proven and "two reflections" in both.reason and "'A'" in both.reason
    alone = sun_patches.sunlit_pieces(floor, occ, occ, d, panes=[a], tol=1e-7)
    assert alone.proven and "mirror" in alone.kind  # A's image lights the floor

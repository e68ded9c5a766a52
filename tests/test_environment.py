"""Environment maps (radiometry/skies/environment.py) against closed forms, on maps the tests write as EXR.

Reference numbers and where they come from:
* uniform radiance L over the sphere: E = pi L for every normal (the lecture; Lambert);
* L only above the horizon, meter tilted by theta: E = pi L (1 + cos theta) / 2 (the sky view
  factor of a tilted plane, e.g. Howell's catalog of configuration factors, B-? "plane to sky");
* a spherical cap of angular radius alpha wholly above the horizon, its axis at theta from the
  normal: E = pi L sin^2(alpha) cos(theta) (the projected solid angle of a cap; for small alpha
  this is L Omega cos(theta), Omega = 2 pi (1 - cos alpha));
* SH9: |E_9 - E| <= (3/32) * integral of L (kernel truncation, environment.py; Ramamoorthi &
  Hanrahan 2001's "at most 9 %" for a directional source).
"""

import math

import numpy as np
import pytest

from radiometer.radiometry.skies import environment as env

OpenEXR = pytest.importorskip("OpenEXR")


def write_exr(path, rgb):
    rgba = np.concatenate([rgb, np.ones(rgb.shape[:2] + (1,))], axis=-1).astype(np.float32)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGBA": rgba}) as f:
        f.write(str(path))


def roundtrip(tmp_path, rgb, name="map.exr"):
    from radiometer.measure.blender import exr

    write_exr(tmp_path / name, rgb)
    return exr.read_rgb(str(tmp_path / name))


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def cap_map(h, w, rows, value):
    """Radiance ``value`` in the top ``rows`` rows (a cap around the local +Y pole)."""
    m = np.zeros((h, w, 3))
    m[:rows] = value
    return m, np.pi * rows / h  # cap angular radius (rows are whole latitude bands)


def test_pixel_solid_angles_are_the_sphere_and_the_bands():
    solid, m, centre, r = env.pixel_geometry(16, 32)
    assert solid.sum() == pytest.approx(4 * np.pi, rel=1e-13)
    # the band between latitudes: 2 pi (sin lat1 - sin lat0) / W per pixel
    assert solid[0, 0] == pytest.approx(2 * np.pi * (1 - math.cos(math.pi / 16)) / 32, rel=1e-13)
    assert np.allclose(m.sum(axis=(0, 1)), 0.0, atol=1e-13)


def test_uniform_world_gives_pi_L_for_every_normal(tmp_path):
    rng = np.random.default_rng(7)
    L = np.array([0.7, 1.3, 2.0])
    lmap = roundtrip(tmp_path, np.broadcast_to(L, (24, 48, 3)).copy())
    normals = rng.normal(size=(40, 3))
    for rotation in (np.eye(3), env.BLENDER_WORLD_ROTATION, random_rotation(rng)):
        e, err = env.irradiance(lmap, normals, rotation)
        assert np.allclose(e, np.pi * L.astype(np.float32), rtol=1e-4)
        assert np.max(np.abs(e / (np.pi * L.astype(np.float32)) - 1)) < 1e-7
        assert np.all(err < 1e-6)


@pytest.mark.parametrize("rows", [16, 15])  # horizon on a pixel edge, and pixels straddling it
def test_sky_above_horizon_gives_the_tilted_view_factor(tmp_path, rows):
    h, w = 32, 64
    lmap, _ = cap_map(h, w, rows, 1.0)
    lmap = roundtrip(tmp_path, lmap)
    theta = np.linspace(0.0, np.pi, 19)
    phi = 0.37
    normals = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)], axis=-1)
    e, _err = env.irradiance(lmap, normals)
    if rows == h // 2:
        expected = np.pi * (1 + np.cos(theta)) / 2
        assert np.max(np.abs(e[:, 0] - expected)) < 1e-4
    else:
        # the sky ends at latitude delta above the horizon: a cap of angular radius pi/2 - delta
        alpha = np.pi * rows / h
        assert e[0, 0] == pytest.approx(np.pi * math.sin(alpha) ** 2, rel=1e-9)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_small_bright_disk_gives_L_omega_cos_theta(tmp_path, seed):
    rng = np.random.default_rng(seed)
    L = 5000.0
    lmap, alpha = cap_map(128, 256, 2, L)  # a cap of radius 2.8 deg: a sun-like disk
    lmap = roundtrip(tmp_path, lmap)
    rot = random_rotation(rng)
    axis = rot @ np.array([0.0, 1.0, 0.0])
    # normals at theta from the disk's axis, up to 80 deg (disk wholly above the horizon)
    for theta in np.radians([0.0, 30.0, 60.0, 80.0]):
        side = np.cross(axis, rng.normal(size=3))
        side /= np.linalg.norm(side)
        n = math.cos(theta) * axis + math.sin(theta) * side
        e, _ = env.irradiance(lmap, n, rot)
        exact = np.pi * L * math.sin(alpha) ** 2 * math.cos(theta)
        assert e[0] == pytest.approx(exact, rel=1e-4)
        omega = 2 * np.pi * (1 - math.cos(alpha))
        assert e[0] == pytest.approx(L * omega * math.cos(theta), rel=alpha ** 2)


def test_disk_crossing_the_horizon_matches_fine_quadrature():
    """A cap cut by the horizon: compare with a brute-force midpoint sum on 64x finer cells."""
    lmap, _ = cap_map(8, 16, 2, 1.0)
    n = np.array([math.sin(1.3), math.cos(1.3), 0.0])  # 74.5 deg: the horizon cuts the 45 deg cap
    e, err = env.irradiance(lmap, n)
    fine = 64
    dirs, solid = env.pixel_directions(8 * fine, 16 * fine)
    inside = np.repeat(np.repeat(lmap[..., 0], fine, 0), fine, 1)
    brute = np.sum(inside * solid * np.clip(dirs @ n, 0, None))
    assert e[0] == pytest.approx(brute, rel=2e-4)  # the midpoint rule's own error at 1/64 pixel
    assert err[0] < 1e-6 * e[0]


def test_shapes_and_nan_normals():
    lmap = np.random.default_rng(0).random((8, 16, 3))
    n = np.random.default_rng(1).normal(size=(2, 3, 3))
    e, _ = env.irradiance(lmap, n)
    flat, _ = env.irradiance(lmap, n.reshape(-1, 3))
    assert e.shape == (2, 3, 3) and np.allclose(e.reshape(-1, 3), flat)
    e1, _ = env.irradiance(lmap, n[0, 0])
    assert e1.shape == (3,) and np.allclose(e1, flat[0])
    bad = np.array([[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0], [0, 0, 1.0]])
    with np.errstate(invalid="ignore"):
        e, _ = env.irradiance(lmap, bad)
    assert np.all(np.isnan(e[:3])) and np.all(np.isfinite(e[3]))


def test_sh9_coefficients_of_a_uniform_world():
    c = env.sh9_coefficients(np.ones((16, 32, 3)))
    assert c[0, 0] == pytest.approx(math.sqrt(4 * math.pi), rel=1e-12)  # L00 = L * 4 pi * Y00
    assert np.allclose(c[1:], 0.0, atol=1e-12)


def test_sh9_is_exact_for_the_sky_step_and_within_its_bound_for_a_disk():
    # E(theta) = pi (1 + cos theta)/2 is band-limited (l <= 1): SH9 reproduces it.
    sky, _ = cap_map(32, 64, 16, 1.0)
    n = np.random.default_rng(2).normal(size=(30, 3))
    e, _ = env.irradiance(sky, n)
    assert np.allclose(env.sh9_irradiance(env.sh9_coefficients(sky), n), e, atol=1e-9)
    # A small disk is as far from band-limited as a map gets: the error approaches the bound at
    # the normal perpendicular to the disk (t = 0), and never exceeds it.
    disk, _ = cap_map(64, 128, 1, 1.0)
    result = env.irradiance_map(disk, resolution=(64, 32), method="exact")
    bound = env.sh9_error_bound(disk)[0]
    measured = result["sh9_error"][0]
    assert measured <= bound
    assert measured > 0.7 * bound  # nearly tight (3/32 = 9.4 % of a point source's peak E)
    sh = env.irradiance_map(disk, resolution=(64, 32), method="sh9")
    assert np.max(np.abs(sh["map"] - result["map"])) == pytest.approx(measured)


def test_irradiance_map_of_a_sky_is_the_view_factor():
    sky, _ = cap_map(32, 64, 16, 2.0)
    out = env.irradiance_map(sky, resolution=(32, 16))
    dirs, _ = env.pixel_directions(16, 32)
    expected = 2.0 * np.pi * (1 + dirs[..., 1]) / 2
    assert np.max(np.abs(out["map"][..., 0] - expected)) < 1e-9


def test_direction_to_pixel_inverts_pixel_directions():
    for rot in (np.eye(3), env.BLENDER_WORLD_ROTATION, env.RADIANCE_MAP_ROTATION):
        dirs, _ = env.pixel_directions(12, 24, rot)
        row, col = env.direction_to_pixel(dirs, (12, 24), rot)
        assert np.array_equal(row, np.arange(12)[:, None].repeat(24, 1))
        assert np.array_equal(col, np.arange(24)[None, :].repeat(12, 0))


def test_brightest_direction():
    m = np.zeros((8, 16, 3))
    m[2, 5] = (1.0, 2.0, 3.0)
    d, value, (row, col) = env.brightest(m, env.BLENDER_WORLD_ROTATION)
    assert (row, col) == (2, 5) and np.allclose(value, (1, 2, 3))
    assert np.allclose(d, env.pixel_directions(8, 16, env.BLENDER_WORLD_ROTATION)[0][2, 5])


def test_bilinear_supersample_converges_and_keeps_constants():
    const = np.full((8, 16, 3), 2.5)
    assert np.allclose(env.bilinear_supersample(const, 4), 2.5)
    m = np.zeros((16, 32, 3))
    m[5, 9] = 1000.0  # a one-pixel hot spot
    n = env.pixel_directions(16, 32)[0][5, 9]
    e = {f: env.irradiance(env.bilinear_supersample(m, f), n)[0][0] for f in (2, 4, 8)}
    pixel = env.irradiance(m, n)[0][0]
    # second order: the 2 -> 8 change is 15/16 of the whole error of factor 2, 4 -> 8 about 1/4 of it
    assert abs(e[4] - e[8]) < 0.3 * abs(e[2] - e[8]) + 1e-12 * pixel
    # bilinear smearing moves the hot spot's E by a small, finite amount
    assert 0 < abs(e[8] - pixel) / pixel < 0.05


def test_mirror_ball_roundtrip_and_its_resolution_loss():
    """Equirect -> ideal mirror ball -> equirect: the ball squeezes the backward hemisphere into
    its rim, so a probe of S pixels resolves the back worse than the front. Measured: the pixel
    that looks straight back (towards the camera's direction, -view) is resolved only on a thin rim."""
    h, w = 32, 64
    rng = np.random.default_rng(3)
    lmap = rng.random((h, w, 3))
    errors = {}
    for size in (64, 256, 1024):
        probe = env.equirect_to_probe(lmap, size)
        back = env.probe_to_equirect(probe, (h, w))
        wrong = np.any(back != lmap, axis=-1)
        dirs, solid = env.pixel_directions(h, w)
        errors[size] = float(np.sum(solid * wrong) / (4 * np.pi))
        # pixels facing the camera (local +Z half) come back exactly once the ball is fine enough
        front = dirs[..., 2] > 0.2
        if size >= 256:
            assert not np.any(wrong & front)
    assert errors[1024] < errors[256] < errors[64]

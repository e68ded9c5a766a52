"""Analytic light models of radiometer.radiometry.emitters (the Blender light kinds) against closed forms
(pure numpy tier)."""

import math

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.scene import geometry
from radiometer.radiometry.emitters import area as area_emitter
from radiometer.radiometry.emitters import CyclesLight
from radiometer.radiometry.emitters.spot import spot_attenuation

UP = np.array([[0.0, 0.0, 1.0]])


def _tilt(deg):
    t = math.radians(deg)
    return np.array([[math.sin(t), 0.0, math.cos(t)]])


def test_point_inverse_square_and_cosine_law_exact():
    spec = CyclesLight(kind="POINT", rgb_power=[100.0, 50.0, 1.0])
    r = np.array([0.001, 0.5, 2.0, 10_000.0])
    pts = np.stack([np.zeros(4), np.zeros(4), -r], 1)
    e = spec.irradiance_at(pts, np.tile(UP, (4, 1)))[0]
    np.testing.assert_allclose(e, np.outer(1.0 / (4 * np.pi * r**2), [100.0, 50.0, 1.0]), rtol=1e-14)
    for deg in (0.0, 30.0, 60.0, 89.999):
        e = spec.irradiance_at([[0, 0, -2.0]], _tilt(deg))[0][0, 0]
        assert e == pytest.approx(100.0 / (16 * np.pi) * math.cos(math.radians(deg)), rel=1e-12)
    assert spec.irradiance_at([[0, 0, -2.0]], _tilt(90.001))[0][0, 0] == 0.0


def test_disk_area_light_matches_lecture_uniform_disk():
    # Lecture (Foundations of CG, "Uniform Disk Source"): E = pi L r^2 / (r^2 + h^2), L = P / (pi A).
    for h in (0.01, 1.0, 100.0):
        spec = CyclesLight(kind="AREA", position=[0, 0, h], shape="DISK", size=1.0, rgb_power=[100.0] * 3)
        radiance = 100.0 / (np.pi * np.pi * 0.25)
        expected = np.pi * radiance * 0.25 / (0.25 + h * h)
        assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(expected, rel=1e-7)


@pytest.mark.parametrize("tilt", [0.0, 40.0, 75.0, 85.0, 95.0])
def test_disk_polygon_agrees_with_snyder_cap_under_horizon(tilt):
    # Two independent formulas: Lambert's polygon (equal-area 2048-gon, clipped) vs Snyder's cap.
    r, h = 0.5, 0.8
    spec = CyclesLight(kind="AREA", position=[0, 0, h], shape="DISK", size=2 * r, rgb_power=[1.0] * 3)
    radiance = 1.0 / (np.pi * np.pi * r * r)
    cap = geometry.cap_projected_solid_angle(math.cos(math.radians(tilt)), r * r / (r * r + h * h))
    assert spec.irradiance_at([[0, 0, 0.0]], _tilt(tilt))[0][0, 0] == pytest.approx(radiance * cap, rel=1e-6)


def test_square_head_on_matches_form_factor_formula():
    # Differential-area-to-rectangle form factor (Howell catalogue C-11): four corner terms.
    a, h = 0.5, 1.0
    x = a / h
    corner = 0.5 * (x / math.sqrt(1 + x * x) * math.atan(x / math.sqrt(1 + x * x))) * 2
    spec = CyclesLight(kind="AREA", position=[0, 0, h], rgb_power=[100.0] * 3)
    expected = 100.0 / np.pi * 4 * corner
    assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(23.946, abs=1e-3)  # docs/FACTS.md Cycles render: 23.949


def test_uniform_sky_gives_pi_l():
    # A hemisphere of uniform radiance L gives E = pi L: cap with sigma = 90 deg, and a huge area light.
    assert geometry.cap_projected_solid_angle(1.0, 1.0) == pytest.approx(np.pi, rel=1e-15)
    spec = CyclesLight(kind="AREA", position=[0, 0, 1.0], size=1e7, rgb_power=[1e14] * 3)
    radiance = 1e14 / (np.pi * 1e14)
    assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(np.pi * radiance, rel=1e-6)


def test_cap_formula_matches_numerical_integration():
    sigma = math.radians(25.0)
    for theta_deg in (0.0, 70.0, 90.0, 105.0, 114.0):
        theta = math.radians(theta_deg)
        n = np.array([math.sin(theta), 0.0, math.cos(theta)])
        g, w = np.polynomial.legendre.leggauss(400)
        t = 0.5 * (g + 1) * (1 - math.cos(sigma))            # 1 - cos(gamma)
        phi = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
        sg = np.sqrt(t * (2 - t))[:, None]
        d = np.stack([sg * np.cos(phi), sg * np.sin(phi), np.broadcast_to((1 - t)[:, None], sg.shape * np.array([1, 4000]))], -1)
        f = np.maximum(d @ n, 0.0)
        numeric = np.sum(f * (0.5 * w * (1 - math.cos(sigma)))[:, None]) * (2 * np.pi / 4000)
        exact = geometry.cap_projected_solid_angle(math.cos(theta), math.sin(sigma) ** 2)
        assert exact == pytest.approx(numeric, rel=2e-5, abs=1e-9)


def test_sun_cap_normal_irradiance_is_energy_and_cosine_law_above_horizon():
    spec = CyclesLight(kind="SUN", angle=math.radians(10), rgb_power=[3.0] * 3)
    assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(3.0, rel=1e-12)
    assert spec.irradiance_at([[5, 5, 5.0]], _tilt(60))[0][0, 0] == pytest.approx(1.5, rel=1e-12)
    assert 0.0 < spec.irradiance_at([[0, 0, 0.0]], _tilt(92))[0][0, 0] < 0.05
    assert spec.irradiance_at([[0, 0, 0.0]], _tilt(96))[0][0, 0] == 0.0
    with pytest.raises(ValueError, match="no position"):
        spec.intensity_towards([0, 0, -1.0])


def test_soft_falloff_sphere_and_disk_models():
    # Soft falloff on: P / (4 pi (R^2 + r^2)); FACTS measured 59 %, 80 %, 94 % at R = 0.5.
    spec = CyclesLight(kind="POINT", radius=0.5, soft_falloff=True, rgb_power=[100.0] * 3)
    for r, fraction in ((0.6, 0.59), (1.0, 0.80), (2.0, 0.94)):
        e = spec.irradiance_at([[0, 0, -r]], UP)[0][0, 0]
        assert e == pytest.approx(100.0 / (4 * np.pi * (0.25 + r * r)), rel=1e-12)
        assert e / (100.0 / (4 * np.pi * r * r)) == pytest.approx(fraction, abs=0.006)
    sphere = CyclesLight(kind="POINT", radius=0.5, soft_falloff=False, rgb_power=[100.0] * 3)
    assert sphere.irradiance_at([[0, 0, -0.6]], UP)[0][0, 0] == pytest.approx(100 / (4 * np.pi * 0.36), rel=1e-12)
    assert sphere.irradiance_at([[0, 0, -0.1]], UP)[0][0, 0] == pytest.approx(100 / (4 * np.pi * 0.25), rel=1e-12)


def test_spot_with_radius_quadrature_converges_to_delta_spot_far_away():
    kw = dict(kind="SPOT", spot_size=math.radians(40), spot_blend=0.3, rgb_power=[100.0] * 3)
    far = [[0.5, 0.0, -20.0]]
    delta = CyclesLight(**kw).irradiance_at(far, UP)[0][0, 0]
    for soft in (True, False):
        e = CyclesLight(radius=0.01, soft_falloff=soft, **kw).irradiance_at(far, UP)[0][0, 0]
        assert e == pytest.approx(delta, rel=1e-5)
    assert CyclesLight(radius=0.1, **kw).exactness()[1] == "quadrature"


def test_spread_quadrature_matches_brute_force_and_flux():
    spec = CyclesLight(kind="AREA", position=[0, 0, 1.0], spread=math.radians(30), rgb_power=[100.0] * 3)
    # Whole spread cone inside the light: E = P / A (flux-preserving normalisation).
    assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(100.0, rel=1e-6)
    # Foot point outside the light, tilted receiver: midpoint rule over 2000^2 cells.
    p, n = np.array([0.55, 0.2, 0.0]), _tilt(20)[0]
    m = 2000
    x = (np.arange(m) + 0.5) / m - 0.5
    gx, gy = np.meshgrid(x, x)
    v = np.stack([gx.ravel(), gy.ravel(), np.ones(m * m)], 1) - p
    r = np.linalg.norm(v, axis=1)
    cos_l, cos_r = v[:, 2] / r, np.maximum(v @ n / r, 0)
    h = math.radians(15)
    att = np.maximum((math.tan(h) - np.sqrt(1 - cos_l**2) / cos_l) / (math.tan(h) - h), 0)
    brute = 100 / np.pi * np.sum(att * cos_r * cos_l / r**2) / m**2
    assert spec.irradiance_at([p], [n])[0][0, 0] == pytest.approx(brute, rel=1e-4)
    lambertian = CyclesLight(kind="AREA", position=[0, 0, 1.0], rgb_power=[100.0] * 3)
    almost = CyclesLight(kind="AREA", position=[0, 0, 1.0], spread=math.radians(179.99), rgb_power=[100.0] * 3)
    assert almost.irradiance_at([p], [n])[0][0, 0] == pytest.approx(
        lambertian.irradiance_at([p], [n])[0][0, 0], rel=1e-3)


def test_area_far_field_follows_radiant_intensity():
    spec = CyclesLight(kind="AREA", position=[0, 0, 0.0], size=0.2, rgb_power=[10.0] * 3)
    d = np.array([0.3, 0.1, -1.0]) / np.linalg.norm([0.3, 0.1, -1.0])
    intensity = spec.intensity_towards(d)[0]
    assert intensity == pytest.approx(10.0 / np.pi * -d[2], rel=1e-12)
    r = 1000.0
    e = spec.irradiance_at([r * d], [-d])[0][0, 0]
    assert e * r * r == pytest.approx(intensity, rel=1e-7)


def test_behind_area_and_spot_outside_cone_are_zero():
    area = CyclesLight(kind="AREA", position=[0, 0, 1.0], rgb_power=[1.0] * 3)
    assert area.irradiance_at([[0, 0, 2.0]], [[0, 0, -1.0]])[0][0, 0] == 0.0
    spot = CyclesLight(kind="SPOT", spot_size=math.radians(30), spot_blend=0.0, rgb_power=[1.0] * 3)
    assert spot.irradiance_at([[1.0, 0, -1.0]], UP)[0][0, 0] == 0.0


def test_light_spec_from_values_scale_length_and_normalize():
    values = dict(type="POINT", energy=100.0, color=(1, 1, 1), shadow_soft_size=0.0,
                  matrix_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2.0], [0, 0, 0, 1]])
    e1 = emitters.from_blender_values(values, 1.0).irradiance_at([[0, 0, 0.0]], UP)[0]
    e2 = emitters.from_blender_values(values, 0.01).irradiance_at([[0, 0, 0.0]], UP)[0]
    np.testing.assert_allclose(e2, e1 / 0.01**2, rtol=1e-12)  # E_SI = E_scene / scale^2
    off = emitters.from_blender_values({**values, "normalize": False, "exposure": 1.0}, 1.0)
    np.testing.assert_allclose(off.rgb_power, 100.0 * 2 * 4)  # Cycles Light::area = 4 for radius 0
    area = emitters.from_blender_values(dict(type="AREA", energy=10.0, size=2.0, shape="SQUARE", normalize=False,
                                              matrix_world=np.diag([1.5, 1.0, 1.0, 1.0]).tolist()), 1.0)
    np.testing.assert_allclose(area.rgb_power, 10.0 * 3.0 * 2.0)
    temp = emitters.from_blender_values({**values, "use_temperature": True, "temperature": 2700.0,
                                          "color": (1.0, 0.5, 0.25)}, 1.0)
    np.testing.assert_allclose(temp.rgb_power / 100.0 / np.array([1.0, 0.5, 0.25]),
                               [1.935, 0.8035, 0.1917], rtol=1e-3)  # multiplies colour (bpy tier)


def test_n_dimensional_inputs_and_invalid_values():
    spec = CyclesLight(kind="AREA", position=[0, 0, 1.0], rgb_power=[1.0, 2.0, 3.0])
    pts = np.zeros((2, 5, 3))
    out = spec.irradiance_at(pts, np.broadcast_to(UP[0], pts.shape))[0]
    assert out.shape == (2, 5, 3)
    np.testing.assert_allclose(out[..., 1], 2 * out[..., 0])
    with pytest.raises(ValueError, match="NaN"):
        spec.irradiance_at([[np.nan, 0, 0]], UP)[0]
    with pytest.raises(ValueError, match="NaN"):
        spec.irradiance_at([[0, 0, 0]], [[np.inf, 0, 1]])[0]
    with pytest.raises(ValueError, match="zero vector"):
        spec.irradiance_at([[0, 0, 0]], [[0, 0, 0]])[0]
    with pytest.raises(ValueError, match="zero distance"):
        CyclesLight(kind="POINT").irradiance_at([[0, 0, 0.0]], UP)[0]
    with pytest.raises(ValueError, match="kind"):
        CyclesLight(kind="HEMI")
    with pytest.raises(ValueError, match="orthonormal"):
        CyclesLight(axes=np.ones((3, 3)))


@pytest.mark.parametrize("kind", ["POINT", "SPOT", "SUN", "AREA"])
def test_extremes_have_no_overflow_or_nan(kind):
    # 1 mm to 10 km, 1e-6 W to 1e9 W, grazing 89.999 deg; RuntimeWarnings are errors in this suite.
    for power in (1e-6, 1e9):
        spec = CyclesLight(kind=kind, rgb_power=[power] * 3, spot_size=math.radians(60), angle=math.radians(1))
        r = np.array([1e-3, 1.0, 1e4])
        pts = np.stack([np.zeros(3), np.zeros(3), -r], 1)
        for normal in (UP, _tilt(89.999)):
            e = spec.irradiance_at(pts, np.repeat(normal, 3, 0))[0]
            assert np.all(np.isfinite(e)) and np.all(e >= 0.0)
            if kind != "SUN":
                assert e[0, 0] > e[2, 0] > 0.0


# --- sheared/mirrored transforms, error bounds, bad energies --------------------------------

def _sheared_matrix(mirror=False):
    from math import cos, sin
    a, b, c = 0.6, 0.4, 0.3
    rx = np.array([[1, 0, 0], [0, cos(a), -sin(a)], [0, sin(a), cos(a)]])
    ry = np.array([[cos(b), 0, sin(b)], [0, 1, 0], [-sin(b), 0, cos(b)]])
    rz = np.array([[cos(c), -sin(c), 0], [sin(c), cos(c), 0], [0, 0, 1]])
    m = np.diag([-2.0 if mirror else 2.0, 0.5, 1.0]) @ rz @ ry @ rx
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = m, [0.1, 0.05, 1.0]
    return out


@pytest.mark.parametrize("mirror", [False, True])
def test_sheared_transform_is_accepted_and_uses_the_full_matrix(mirror):
    mw = _sheared_matrix(mirror)
    spot = emitters.from_blender_values(dict(type="SPOT", energy=100.0, spot_size=math.radians(60), spot_blend=0.3,
                                              shadow_soft_size=0.0, matrix_world=mw.tolist(), name="S"))
    assert spot.is_sheared and np.allclose(spot.axes.T @ spot.axes, np.eye(3))
    np.testing.assert_allclose(spot.emission_direction, -mw[:3, 2] / np.linalg.norm(mw[:3, 2]), rtol=1e-12)
    # Cone factor: z of the direction mapped by the inverse object matrix (Cycles' itfm).
    d = unit_d = np.array([0.1, -0.2, -1.0]) / np.linalg.norm([0.1, -0.2, -1.0])
    local = np.linalg.solve(mw[:3, :3], unit_d)
    z = -local[2] / np.linalg.norm(local)
    c = math.cos(math.radians(30))
    x = np.clip((z - c) / ((1 - c) * 0.3), 0, 1)
    assert spot_attenuation(spot, d) == pytest.approx(x * x * (3 - 2 * x), rel=1e-12, abs=1e-15)
    area = emitters.from_blender_values(dict(type="AREA", energy=100.0, shape="RECTANGLE", size=0.6, size_y=0.3,
                                              matrix_world=mw.tolist()))
    eu, ev = area.edges
    np.testing.assert_allclose(eu, mw[:3, 0] * 0.6)
    np.testing.assert_allclose(ev, mw[:3, 1] * 0.3)
    assert area.area_m2 == pytest.approx(np.linalg.norm(eu) * np.linalg.norm(ev))  # Cycles' Light::area
    e, bound = area.relative_irradiance([[0, 0, 0.0]], UP)
    assert e[0, 0] > 0 and 0 < bound[0] < 0.01 and not area.exactness()[0]


@pytest.mark.parametrize("shape", ["SQUARE", "DISK"])
def test_sheared_area_sampler_model_reduces_to_lambert_polygon_without_shear(shape):
    # The model of Cycles' light sampler, run on an orthogonal frame, must equal the closed form.
    spec = CyclesLight(kind="AREA", position=[0.1, -0.2, 1.0], axes=np.eye(3), scale=[1.3, 0.7, 1.0], shape=shape,
                     size=0.8, rgb_power=[1.0] * 3)
    pts, nrm = np.array([[0.3, 0.1, 0.0], [0.0, 0.0, 0.5]]), np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    exact = spec.irradiance_at(pts, nrm)[0][:, 0]
    model = area_emitter._sheared_area_nee(spec, pts, nrm, 64)
    np.testing.assert_allclose(model, exact, rtol=5e-5 if shape == "DISK" else 1e-9)


def test_spot_with_radius_narrow_cone_matches_brute_force_within_its_bound():
    # Cap (sphere seen from the receiver) far wider than the 20 deg cone: edges cut through the cap.
    for soft, blend, pos in ((False, 0.2, [0.0, 0.0, 1.0]), (True, 0.0, [0.15, 0.0, 1.0]), (True, 0.3, [0.2, 0.1, 0.7])):
        spec = CyclesLight(kind="SPOT", position=pos, radius=0.3, soft_falloff=soft, spot_size=math.radians(20),
                         spot_blend=blend, scale=[1.5, 0.8, 1.0], rgb_power=[100.0] * 3)
        e, bound = spec.relative_irradiance([[0, 0, 0.0]], UP)
        # Brute force: midpoint rule on a 1500 x 1500 grid in (t, phi) over the same cap.
        w = np.array(pos) / np.linalg.norm(pos)
        d2 = np.dot(pos, pos)
        s2 = 0.09 / (0.09 + d2) if soft else 0.09 / d2
        tmax = 1 - math.sqrt(1 - s2)
        m = 1500
        t = (np.arange(m) + 0.5) / m * tmax
        phi = (np.arange(m) + 0.5) / m * 2 * np.pi
        e1 = np.cross(w, [1.0, 0, 0]); e1 /= np.linalg.norm(e1); e2 = np.cross(w, e1)
        sg = np.sqrt(t * (2 - t))[:, None, None]
        dirs = (1 - t)[:, None, None] * w + sg * (np.cos(phi)[None, :, None] * e1 + np.sin(phi)[None, :, None] * e2)
        f = spot_attenuation(spec, -dirs) * np.maximum(dirs[..., 2], 0)
        brute = 100 / (4 * np.pi**2 * 0.09) * f.sum() * (tmax / m) * (2 * np.pi / m)
        assert e[0, 0] == pytest.approx(brute, rel=max(3 * bound[0], 2e-4))
        assert bound[0] < 5e-3


def test_disk_bound_covers_the_polygon_error_at_the_rim():
    spec = CyclesLight(kind="AREA", position=[0, 0, 0.001], shape="DISK", size=1.0, rgb_power=[1.0] * 3)
    for x in (0.4999, 0.5001, 0.3):
        e, bound = spec.relative_irradiance([[x, 0, 0.0]], UP)
        ref = geometry.polygon_projected_solid_angle(area_emitter._outline_world(spec, 2**17), np.array([[x, 0, 0.0]]), UP)
        err = abs(e[0, 0] / (ref[0] / (np.pi * spec.area_m2)) - 1)
        assert err <= bound[0] + 1e-12
    assert spec.relative_irradiance([[0, 0, 0.0]], UP)[1][0] < 1e-12


def test_negative_energy_gives_negative_irradiance_and_says_so():
    values = dict(type="POINT", energy=-50.0, shadow_soft_size=0.0, name="Neg",
                  matrix_world=[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1.0], [0, 0, 0, 1]])
    spec = emitters.from_blender_values(values)
    assert spec.irradiance_at([[0, 0, 0.0]], UP)[0][0, 0] == pytest.approx(-50 / (4 * np.pi), rel=1e-12)
    assert "negative energy" in spec.exactness()[2]


@pytest.mark.parametrize("field, value", [("energy", float("nan")), ("energy", float("inf")),
                                          ("color", (1.0, float("nan"), 1.0)), ("exposure", float("nan"))])
def test_non_finite_energy_or_colour_names_the_light_and_field(field, value):
    values = {**dict(type="AREA", energy=10.0, name="Key light", matrix_world=np.eye(4).tolist()), field: value}
    with pytest.raises(ValueError, match=f"'Key light'.*{field}") as info:
        emitters.from_blender_values(values)
    assert "\n" not in str(info.value)

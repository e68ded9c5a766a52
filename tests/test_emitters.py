"""The Emitter interface (radiometry/emitters): properties every kind must obey (Mitsuba 3 style), and
the flux closed forms that the one photometric integration is checked against.

Independent references: the inverse-square law (E d^2 -> I far away), the linearity of irradiance in
the receiver's normal while the whole source is above its horizon (the cosine law, E(n) = n . V), the
flux as the integral of the intensity over a spherical Fibonacci set of 200 000 directions (a quadrature
that shares nothing with the emitters' own flux: its error for a cap's indicator is ~N^-3/4 = 1e-4), and
closed forms (isotropic table: 4 pi I; cosine table: pi I0; hard-edged circular spot: P (1 - cos h) / 2).
"""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings, strategies as st

from radiometer.radiometry import emitters
from radiometer.radiometry.skies.cie_sky import CIESkyWorld
from radiometer.radiometry.emitters import EmitterFlags
from radiometer.radiometry.emitters.photometric import Photometry, table_flux
from radiometer.radiometry.skies.environment import WorldLight

SETTINGS = settings(max_examples=12, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def _fibonacci(count=200_000):
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    phi = np.pi * (1.0 + 5 ** 0.5) * k
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


FIB = _fibonacci()
#: A hard cone edge is an indicator's jump: the set's error scales as N^-3/4 of the sphere, so these get
#: 2 000 000 directions (and cones of at least 1 rad, where that is < 3e-4 of their flux).
FIB_FINE = _fibonacci(2_000_000)


def _rotation(a, b, c):
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rz @ ry @ rx


angles = st.tuples(*(st.floats(-math.pi, math.pi) for _ in range(3)))
colour = st.tuples(*(st.floats(0.1, 5.0) for _ in range(3)))


def _smooth_table(seed, n_h=9, n_v=13):
    """A smooth non-negative (n_h, n_v) table over C 0..360 and v 0..180 deg (W/sr per W)."""
    rng = np.random.default_rng(seed)
    h = np.linspace(0.0, 360.0, n_h)
    v = np.linspace(0.0, 180.0, n_v)
    a = rng.uniform(0.2, 1.0, 3)
    values = (a[0] + a[1] * np.cos(np.radians(v))[None, :] ** 2
              + a[2] * (1 + np.cos(np.radians(h)))[:, None] * np.sin(np.radians(v))[None, :] ** 2)
    return Photometry.light_table(h_deg=h, v_deg=v, values=values / (4 * np.pi))


@st.composite
def positioned_emitters(draw):
    """An emitter with a position: point, sphere, spot, area (every shape, spread), photometric, mesh."""
    kind = draw(st.sampled_from(["point", "sphere", "spot", "spot_sphere", "area", "photometric", "mesh"]))
    rot = _rotation(*draw(angles))
    pos = np.array(draw(st.tuples(*(st.floats(-2, 2) for _ in range(3)))))
    rgb = np.array(draw(colour))
    if kind == "mesh":
        tris = pos + np.array(draw(st.lists(st.tuples(*(st.floats(-0.3, 0.3) for _ in range(9))),
                                            min_size=1, max_size=4))).reshape(-1, 3, 3)
        cross = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
        assume(np.all(cross > 1e-3))
        return emitters.EmissiveMesh(tris, rgb)
    if kind == "photometric":
        scale = np.array(draw(st.tuples(*(st.floats(0.5, 2.0) for _ in range(3)))))
        return emitters.CyclesLight(kind="POINT", position=pos, axes=rot, scale=scale, rgb_power=rgb,
                                intensity_table=_smooth_table(draw(st.integers(0, 1000))))
    if kind in ("point", "sphere"):
        return emitters.CyclesLight(kind="POINT", position=pos, axes=rot, rgb_power=rgb,
                                radius=0.0 if kind == "point" else draw(st.floats(0.01, 0.3)),
                                soft_falloff=draw(st.booleans()))
    if kind.startswith("spot"):
        scale = np.array(draw(st.tuples(*(st.floats(0.5, 2.0) for _ in range(3)))))
        blend = draw(st.sampled_from([0.0, 0.15, 0.6, 1.0]))
        return emitters.CyclesLight(kind="SPOT", position=pos, axes=rot, scale=scale, rgb_power=rgb,
                                radius=0.0 if kind == "spot" else draw(st.floats(0.01, 0.2)),
                                soft_falloff=draw(st.booleans()), spot_blend=blend,
                                spot_size=draw(st.floats(0.2 if blend else 1.0, 3.0)))
    shape = draw(st.sampled_from(["SQUARE", "RECTANGLE", "DISK", "ELLIPSE"]))
    return emitters.CyclesLight(kind="AREA", position=pos, axes=rot, rgb_power=rgb, shape=shape,
                            size=draw(st.floats(0.05, 0.8)), size_y=draw(st.floats(0.05, 0.8)),
                            scale=np.array([draw(st.floats(0.5, 2.0)), draw(st.floats(0.5, 2.0)), 1.0]),
                            spread=draw(st.sampled_from([math.pi, 2.0, 1.0, 0.4])))


def _extent(em):
    """Radius (m) of a ball about the emitter's centre that holds every emitting point."""
    if isinstance(em, emitters.EmissiveMesh):
        return float(np.max(np.linalg.norm(em.triangles.reshape(-1, 3) - _centre(em), axis=1)))
    if em.kind == "AREA":
        eu, ev = em.edges
        return 0.5 * float(np.linalg.norm(eu) + np.linalg.norm(ev))
    return em.radius


def _centre(em):
    if isinstance(em, emitters.EmissiveMesh):
        return em.triangles.reshape(-1, 3).mean(axis=0)
    return np.asarray(em.position, float)


def _out_direction(em, draw_dir):
    """A world direction leaving the emitter where it emits (area lights: in front)."""
    d = np.asarray(draw_dir, float)
    d = d / np.linalg.norm(d)
    if not isinstance(em, emitters.EmissiveMesh) and em.kind == "AREA" and d @ em.emission_direction < 0.2:
        d = d - (d @ em.emission_direction - 0.5) * em.emission_direction
        d = d / np.linalg.norm(d)
    return d


directions = st.tuples(*(st.floats(-1, 1) for _ in range(3))).filter(lambda v: np.linalg.norm(v) > 0.2)


@SETTINGS
@given(positioned_emitters(), directions)
def test_inverse_square_law_far_away(em, draw_dir):
    """E d^2 -> I(d) on a receiver facing the source, 1000 source sizes away."""
    d = _out_direction(em, draw_dir)
    if isinstance(em, emitters.CyclesLight) and em.kind == "SPOT" and em.spot_blend == 0.0:
        # A hard cone edge has no limit across it: stay clear of it by more than the source subtends.
        z = -(np.linalg.solve(em.matrix, d) / np.linalg.norm(np.linalg.solve(em.matrix, d)))[2]
        assume(abs(z - math.cos(em.spot_size / 2)) > 1e-2)
    if isinstance(em, emitters.CyclesLight) and em.kind == "AREA" and em.spread < math.pi:
        # The spread's cut-off (tan a = tan(s/2)) is a kink: far away every point of the light sees it at once.
        cos_a = float(d @ em.emission_direction)
        assume(abs(math.acos(min(cos_a, 1.0)) - em.spread / 2) > 2e-2)
    distance = 1000.0 * max(_extent(em), 0.1)
    p = _centre(em) + distance * d
    e, _bound = em.irradiance_at(p, -d)
    intensity = em.intensity_towards(d)
    np.testing.assert_allclose(e * distance**2, intensity, rtol=1e-3, atol=1e-9 * np.max(np.abs(intensity)) + 1e-12)


@SETTINGS
@given(positioned_emitters(), directions, st.floats(0.0, 1.0), st.floats(0.05, 1.0))
def test_cosine_law_irradiance_is_linear_in_the_normal(em, draw_dir, mix, spread):
    """While the whole source is above the receiver's horizon, E(n) = n . V (the cosine law): for two
    normals n1, n2 and n = a n1 + b n2, E(n/|n|) |n| = a E(n1) + b E(n2)."""
    d = _out_direction(em, draw_dir)
    distance = 5.0 * max(_extent(em), 0.05)
    p = _centre(em) + distance * d
    half = math.asin(min(_extent(em) / distance, 1.0))
    tilt = (math.pi / 2 - half - 0.05) * spread            # keep every emitting point above the horizons
    helper = np.array([1.0, 0, 0]) if abs(d[0]) < 0.9 else np.array([0, 1.0, 0])
    t = np.cross(d, helper)
    t /= np.linalg.norm(t)
    n1 = -d * math.cos(tilt) + t * math.sin(tilt)
    n2 = -d * math.cos(tilt) - t * math.sin(tilt)
    a, b = mix, 1.0 - mix
    n3 = a * n1 + b * n2
    e1 = em.irradiance_at(p, n1)[0]
    e2 = em.irradiance_at(p, n2)[0]
    e3 = em.irradiance_at(p, n3 / np.linalg.norm(n3))[0] * np.linalg.norm(n3)
    np.testing.assert_allclose(e3, a * e1 + b * e2, rtol=1e-7, atol=1e-12 * (np.max(np.abs(e1)) + np.max(np.abs(e2))))


@SETTINGS
@given(positioned_emitters())
def test_power_is_the_integral_of_the_intensity(em):
    """power_w() = the intensity integrated over the sphere (a Fibonacci set: independent quadrature)."""
    hard = isinstance(em, emitters.CyclesLight) and em.kind == "SPOT" and em.spot_blend == 0.0
    integral = 4.0 * np.pi * em.intensity_towards(FIB_FINE if hard else FIB).mean(axis=0)
    np.testing.assert_allclose(em.power_w(), integral, rtol=1e-3)
    weights = np.array([0.2126, 0.7152, 0.0722])
    assert em.luminous_flux_lm(weights, 683.0) == pytest.approx(683.0 * float(em.power_w() @ weights), rel=1e-12)


@SETTINGS
@given(positioned_emitters(), st.lists(st.tuples(*(st.floats(-5, 5) for _ in range(6))), min_size=1, max_size=8))
def test_non_negative_and_finite(em, receivers):
    pts = np.array([r[:3] for r in receivers])
    nrm = np.array([r[3:] for r in receivers])
    assume(np.all(np.linalg.norm(nrm, axis=1) > 1e-3))
    assume(np.all(np.linalg.norm(pts - _centre(em), axis=1) > 1e-3 + _extent(em)))
    e, bound = em.irradiance_at(pts, nrm)
    assert e.shape == (len(pts), 3) and np.all(np.isfinite(e)) and np.all(e >= 0.0)
    if bound is not None:
        assert np.all(np.isfinite(bound)) and np.all(bound >= 0.0)
    i = em.intensity_towards(nrm)
    assert np.all(np.isfinite(i)) and np.all(i >= 0.0)
    p = em.power_w()
    assert np.all(np.isfinite(p)) and np.all(p >= 0.0)


@SETTINGS
@given(angles, st.floats(0.0, 0.5), colour, st.floats(0.0, 1.0), st.floats(0.05, 1.0))
def test_sun_cosine_law_and_flags(rot, angle, rgb, mix, spread):
    sun = emitters.CyclesLight(kind="SUN", axes=_rotation(*rot), rgb_power=np.array(rgb), angle=angle)
    assert isinstance(sun, emitters.SunLight) and sun.flags & EmitterFlags.INFINITE
    assert bool(sun.flags & EmitterFlags.DELTA_DIRECTION) == (angle == 0.0)
    to_sun = -sun.emission_direction
    # Facing the sun: E = E_n exactly (a uniform cap seen whole).
    np.testing.assert_allclose(sun.irradiance_at(np.zeros(3), to_sun)[0], rgb, rtol=1e-12)
    tilt = (math.pi / 2 - angle / 2 - 0.05) * spread
    helper = np.array([1.0, 0, 0]) if abs(to_sun[0]) < 0.9 else np.array([0, 1.0, 0])
    t = np.cross(to_sun, helper)
    t /= np.linalg.norm(t)
    n = to_sun * math.cos(tilt) + t * math.sin(tilt)
    np.testing.assert_allclose(sun.irradiance_at(np.zeros(3), n)[0], np.array(rgb) * math.cos(tilt), rtol=1e-9)
    assert np.all(np.isinf(sun.power_w()))
    with pytest.raises(ValueError, match="no position"):
        sun.intensity_towards(to_sun)


def test_environment_emitters_wrap_the_world_maths():
    world = WorldLight("constant", np.array([0.5, 1.0, 2.0]))
    assert isinstance(world, emitters.Emitter) and world.flags == EmitterFlags.INFINITE
    e, err = world.irradiance_at(np.zeros((4, 3)), np.array([[0, 0, 1.0], [1, 0, 0], [0, -1, 0], [0.3, 0.2, -1]]))
    np.testing.assert_allclose(e, np.pi * np.array([[0.5, 1.0, 2.0]] * 4), rtol=1e-12)    # E = pi L, any normal
    assert np.all(err == 0.0)
    assert np.all(np.isinf(world.power_w()))
    with pytest.raises(ValueError, match="infinity"):
        world.intensity_towards([0, 0, 1.0])
    unmodelled = WorldLight(None, reason="a sky texture")
    assert unmodelled.flags & EmitterFlags.RENDERED_ONLY
    with pytest.raises(ValueError, match="sky texture"):
        unmodelled.irradiance_at(np.zeros(3), [0, 0, 1.0])
    # The CIE overcast sky (Moon & Spencer, L = Lz (1 + 2 cos z) / 3): horizontal irradiance Lz x 7 pi / 9.
    sky = CIESkyWorld("overcast", None, 2.0, 0.0)
    e, err = sky.irradiance_at(np.zeros(3), [0, 0, 1.0])
    assert e[0] == pytest.approx(2.0 * 7 * np.pi / 9, rel=1e-6) and np.all(err >= 0)


def test_constructing_a_light_returns_the_emitter_of_its_kind():
    assert type(emitters.CyclesLight(kind="POINT")) is emitters.PointLight
    assert type(emitters.CyclesLight(kind="SPOT")) is emitters.SpotLight
    assert type(emitters.CyclesLight(kind="AREA")) is emitters.AreaLight
    assert type(emitters.CyclesLight(kind="SUN")) is emitters.SunLight
    table = _smooth_table(1)
    assert type(emitters.CyclesLight(kind="POINT", intensity_table=table)) is emitters.PhotometricLight
    import dataclasses
    import pickle

    spot = dataclasses.replace(emitters.CyclesLight(kind="POINT"), kind="SPOT")
    assert type(spot) is emitters.SpotLight
    sun = pickle.loads(pickle.dumps(emitters.CyclesLight(kind="SUN", angle=0.1)))
    assert type(sun) is emitters.SunLight and sun.angle == 0.1
    with pytest.raises(ValueError, match="kind must be one of"):
        emitters.CyclesLight(kind="LASER")
    with pytest.raises(ValueError, match="radius 0 only"):
        emitters.CyclesLight(kind="SPOT", intensity_table=table)
    ident = emitters.SourceId(123, "", (4, 0), -1)
    em = emitters.from_blender_values({"type": "AREA", "energy": 5.0}, source_id=ident,
                                      visibility=emitters.RayVisibility.ALL & ~emitters.RayVisibility.SHADOW)
    assert em.source_id == ident and not em.visibility & emitters.RayVisibility.SHADOW


# --- flux closed forms: the one integration (table_flux) ----------------------------------------------

def test_flux_of_an_isotropic_and_a_cosine_table():
    h = np.linspace(0.0, 360.0, 5)
    v = np.linspace(0.0, 180.0, 19)
    iso = np.full((h.size, v.size), 100.0)
    assert table_flux(h, v, iso) == pytest.approx(4 * np.pi * 100.0, rel=1e-12)
    # I0 cos(v) on the lower hemisphere, 0 above: pi I0. Catmull-Rom reproduces cos between the
    # nodes to ~1e-5 (1 deg steps); the clamp at the horizon is where the table reaches 0.
    v1 = np.linspace(0.0, 180.0, 181)
    cosine = np.maximum(np.cos(np.radians(v1)), 0.0)[None, :] * np.full((h.size, 1), 100.0)
    assert table_flux(h, v1, cosine) == pytest.approx(np.pi * 100.0, rel=1e-4)
    # The light: rgb_power x the table's flux (W per W); a non-uniform scale warps the directions but
    # an isotropic table stays isotropic (the Jacobian integrates to 4 pi over the sphere).
    light = emitters.CyclesLight(kind="POINT", rgb_power=np.array([1.0, 2.0, 3.0]), scale=np.array([1.0, 3.0, 0.5]),
                             intensity_table=Photometry.light_table(h_deg=h, v_deg=v, values=iso / 100.0))
    np.testing.assert_allclose(light.power_w(), 4 * np.pi * np.array([1.0, 2.0, 3.0]), rtol=1e-6)


@pytest.mark.parametrize("size_deg,blend", [(30.0, 0.0), (90.0, 0.0), (150.0, 0.0), (60.0, 0.5), (120.0, 1.0)])
def test_spot_power_closed_form(size_deg, blend):
    """Cycles' spot emits P/(4 pi) x smoothstep((z - c) / ((1 - c) blend)): its flux is
    P/2 [(1 - c)(1 - blend) + (1 - c) blend (1 - 1/2)] = P (1 - c)(1 - blend/2) / 2 (the smoothstep's
    mean is 1/2)."""
    c = math.cos(math.radians(size_deg) / 2)
    spot = emitters.CyclesLight(kind="SPOT", rgb_power=np.array([2.0, 2.0, 2.0]), spot_size=math.radians(size_deg),
                            spot_blend=blend, axes=_rotation(0.3, -1.0, 2.0))
    np.testing.assert_allclose(spot.power_w(), 2.0 * (1 - c) * (1 - blend / 2) / 2, rtol=1e-12)


def test_emissive_mesh_power_and_irradiance():
    """A unit square of two triangles with radiance L: power 2 pi L (both sides); on its axis at height
    h, E = L x the square's projected solid angle (the same as an area light of that radiance)."""
    sq = np.array([[[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0]], [[-0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]]])
    mesh = emitters.EmissiveMesh(sq, [1.0, 2.0, 0.5])
    assert mesh.flags == EmitterFlags.AREA | EmitterFlags.RENDERED_ONLY and mesh.area_m2 == pytest.approx(1.0)
    np.testing.assert_allclose(mesh.power_w(), 2 * np.pi * np.array([1.0, 2.0, 0.5]), rtol=1e-12)
    area = emitters.CyclesLight(kind="AREA", position=np.array([0, 0, 0.0]), axes=np.diag([1.0, -1.0, -1.0]),
                            size=1.0, rgb_power=np.pi * np.array([1.0, 2.0, 0.5]))      # L = P / (pi A)
    for h in (0.3, 1.0, 4.0):
        for sign in (1.0, -1.0):                                                         # both sides emit
            e, bound = mesh.irradiance_at([0, 0.1, sign * h], [0, 0, -sign])
            assert bound is None
            ref = area.irradiance_at([0, 0.1, h], [0, 0, -1.0])[0]
            np.testing.assert_allclose(e, ref, rtol=1e-12)
    unknown = emitters.EmissiveMesh(sq, None)
    assert np.all(np.isnan(unknown.power_w()))


def test_a_sheared_area_light_with_spread_is_rendered_only():
    """Its bound is NaN in the model (Cycles' sampling of it is not modelled): no bound, RENDERED_ONLY."""
    shear = np.array([[1.0, 0.6, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    light = emitters.CyclesLight(kind="AREA", rgb_power=np.ones(3), spread=1.0, matrix=shear, position=np.zeros(3))
    assert light.is_sheared and light.flags & EmitterFlags.RENDERED_ONLY
    e, bound = light.irradiance_at([0.0, 0.0, -1.0], [0.0, 0.0, 1.0])
    assert bound is None and np.all(np.isfinite(e))
    plain = emitters.CyclesLight(kind="AREA", rgb_power=np.ones(3), spread=1.0)
    assert plain.flags == EmitterFlags.AREA and plain.irradiance_at([0.0, 0.0, -1.0], [0.0, 0.0, 1.0])[1] is not None

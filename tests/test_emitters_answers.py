"""What each emitter kind answers in place of a caller's switch on its kind (issue 30), against closed forms
written here: a square's on-axis solid angle, a Lambertian panel's luminance P / (pi A), a flat luminous
opening's projected area w l cos(gamma) (CIE 117's definitions), a sphere's and a sun disc's solid angle."""

import math

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.emitters import CyclesLight, Photometry, light_class

K = 683.0
W = np.array([0.2126, 0.7152, 0.0722])


def _photometric(opening=None, read=True, c=0.05, power=(2.0, 2.0, 2.0)):
    table = Photometry.light_table([0.0, 90.0, 180.0, 270.0, 360.0], [0.0, 90.0, 180.0], np.full((5, 3), c),
                                   luminous_opening=opening, opening_read=read)
    return CyclesLight(kind="POINT", position=(1.0, 2.0, 3.0), rgb_power=power, intensity_table=table)


def test_size_position_and_words_of_each_kind():
    area = CyclesLight(kind="AREA", shape="RECTANGLE", size=0.6, size_y=0.3)
    sphere = CyclesLight(kind="POINT", radius=0.1, soft_falloff=False)
    spot = CyclesLight(kind="SPOT")
    sun = CyclesLight(kind="SUN", angle=0.01)
    assert (area.size_m, sphere.size_m, spot.size_m, sun.size_m) == (0.6, 0.2, 0.0, 0.0)
    assert [x.has_position for x in (area, sphere, spot, sun)] == [True, True, True, False]
    assert [x.may_render_small for x in (area, sphere, spot, sun)] == [False, True, True, True]
    assert area.describe() == "area light 0.6 x 0.3 m" and sphere.describe() == "point light, radius 0.1 m"
    assert sun.describe() == "sun light" and spot.describe() == "spot light"
    assert sphere.interior_radius_m == 0.1 and CyclesLight(kind="POINT", radius=0.1).interior_radius_m == 0.0
    assert "soft falloff" in CyclesLight(kind="POINT", radius=0.1).near_field_words()
    assert "not a point" in area.near_field_words()


def test_a_record_of_values_is_answered_by_its_kinds_class():
    class Record:
        kind, radius, soft_falloff, extents, shape = "AREA", 0.0, False, (0.5, 0.5), "DISK"
    assert light_class(Record()) is emitters.AreaLight
    assert light_class(Record()).describe(Record()) == "area light, disk 0.5 m"
    assert light_class(CyclesLight(kind="SUN")) is emitters.SunLight


def test_lambertian_panel_seen_on_axis():
    """A 1 m square of power P seen from h = 2 m on its axis: L = K Y(P) / (pi A), omega = 4 asin(a² / (a² + 4h²))."""
    a, h, p = 1.0, 2.0, 50.0
    panel = CyclesLight(kind="AREA", shape="SQUARE", size=a, rgb_power=(p, p, p))
    (lum, omega, centre, outline), why = panel.luminous_area_seen((0.0, 0.0, -h), K, W, 16)
    assert why is None
    assert lum == pytest.approx(K * p * W.sum() / (math.pi * a * a), rel=1e-12)
    assert omega == pytest.approx(4 * math.asin(a * a / (a * a + 4 * h * h)), rel=1e-12)
    assert np.allclose(centre, 0.0) and outline.shape == (4, 3)
    assert panel.luminous_area_seen((0.0, 0.0, h), K, W, 16) == (None, "seen from behind: it emits nothing towards the eye")


def test_photometric_opening_seen_at_an_angle():
    """Flat 0.6 x 0.3 m opening, isotropic table: L = I / (w l cos gamma), omega = w l cos gamma / d²."""
    light = _photometric((0.3, 0.6, 0.0))
    gamma = math.radians(30.0)
    d = 2.5
    eye = np.array([1.0, 2.0, 3.0]) + d * np.array([math.sin(gamma), 0.0, -math.cos(gamma)])
    (lum, omega, centre, outline), why = light.luminous_area_seen(eye, K, W, 64)
    intensity = K * 2.0 * 0.05 * W.sum()
    projected = 0.3 * 0.6 * math.cos(gamma)
    assert why is None
    assert lum == pytest.approx(intensity / projected, rel=1e-9)
    assert omega == pytest.approx(projected / d ** 2, rel=1e-9)
    assert np.allclose(centre, (1.0, 2.0, 3.0)) and np.ptp(outline, axis=0) == pytest.approx([0.6, 0.3, 0.0])


@pytest.mark.parametrize("opening, read, words", [
    ((0.3, 0.6, 0.0), False, "not at hand"), (None, True, "no luminous opening"),
    ((0.3, 0.6, 0.1), True, "with height")])
def test_photometric_opening_says_why_not(opening, read, words):
    geometry, why = _photometric(opening, read).luminous_area_seen((1.0, 2.0, 1.0), K, W, 64)
    assert geometry is None and words in why


def test_sun_and_delta_lights_have_no_luminous_area():
    assert "daylight glare" in CyclesLight(kind="SUN").luminous_area_seen((0, 0, 1), K, W, 16)[1]
    assert "without a luminous area" in CyclesLight(kind="SPOT").luminous_area_seen((0, 0, -1), K, W, 16)[1]
    assert "inside the light" in CyclesLight(kind="POINT").luminous_area_seen((0, 0, 0), K, W, 16)[1]


def test_mirror_image_solid_angles():
    """Sun disc pi (angle / 2)², sphere pi R² / L², delta 0."""
    assert CyclesLight(kind="SUN", angle=0.02).mirror_image_solid_angle((0, 0, 0), 5.0) == pytest.approx(math.pi * 1e-4)
    assert CyclesLight(kind="POINT", radius=0.2).mirror_image_solid_angle((0, 0, 0), 4.0) == pytest.approx(
        math.pi * 0.04 / 16)
    assert CyclesLight(kind="POINT").mirror_image_solid_angle((0, 0, 0), 4.0) == 0.0


def test_occlusion_regions_hold_the_light():
    points = np.array([[0.0, 0.0, -3.0], [1.0, 0.0, -2.0]])
    kind, ends, inside = CyclesLight(kind="POINT").occlusion_bases(points, 100.0, 16)
    assert kind == "segment" and np.allclose(ends, 0.0) and not inside.any()
    kind, bases, inside = CyclesLight(kind="POINT", radius=0.5).occlusion_bases(points, 100.0, 16)
    assert kind == "polytope" and bases.shape == (2, 16, 3)
    kind, ends, _ = CyclesLight(kind="SUN").occlusion_bases(points, 100.0, 16)
    assert kind == "segment" and np.allclose(ends - points, [0.0, 0.0, 100.0])

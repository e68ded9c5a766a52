"""Issue 32 in Blender: a 45 deg roof pane with its rotation applied to the mesh is a thin pane (the sun
through it was 0 lx +-inf), an open-floor sun beside a window is exact, and a lamp with shadows off behind
a wall is exact. References: the sun's E_dn cos(theta) times the clear plate's T from Fresnel's equations
and Stokes' sum (written out in tests/test_thin_glass_recognition.py, independent of thin_glass.slab)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import glass_fog_scenes as scenes  # noqa: E402
from test_thin_glass_recognition import _plate_T  # noqa: E402

E_DN = 100.0  # W/m^2 per channel, white: the Y weights sum to 1


def _roof(apply, far=False):
    """A 6 x 6 m pane, 6 mm thick (IOR 1.52), 3 m over the meter, tilted 45 deg about x, the sun 30 deg
    from the zenith: the sun's ray meets the pane 15 deg off its normal. ``apply``: the rotation (and,
    ``far``, a 1 km offset moved back by the object's location, as a CAD import leaves it) is in the mesh."""
    scene = scenes.reset()
    scenes._world(scene, strength=0.0)
    mat = scenes.glass_material("roof glass", "glass", 1.52)
    ob = scenes.add_pane(scene, "Roof", mat, centre=(0.0, 0.0, 0.0), size=(6.0, 6.0), thickness=0.006)
    ob.location = (0.0, 0.0, 3.0)
    ob.rotation_euler = (math.radians(45.0), 0.0, 0.0)
    if apply:
        bpy.context.view_layer.update()
        from mathutils import Matrix, Vector

        offset = Vector((1000.0, -600.0, 40.0)) if far else Vector((0.0, 0.0, 0.0))
        ob.data.transform(Matrix.Translation(offset) @ ob.matrix_world)
        ob.matrix_world = Matrix.Translation(-offset)
    scenes._light(scene, "SUN", (0.0, 0.0, 5.0), rotation=(math.radians(30.0), 0.0, 0.0), energy=E_DN,
                  angle=math.radians(0.53))
    return scene


@pytest.mark.parametrize("apply,far", [(False, False), (True, False), (True, True)])
def test_roof_pane_with_its_rotation_applied_is_a_pane(clean_blender, apply, far):
    from radiometer import api

    scene = _roof(apply, far)
    r = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), scene=scene, quality="preview")
    assert any("thin glass 'Roof'" in n for n in r.notes), r.notes
    assert not any("not a thin pane" in n for n in r.notes), r.notes
    cos = math.cos(math.radians(30.0))
    expected = 683.0 * E_DN * cos * _plate_T(math.cos(math.radians(15.0)))
    assert r.method == "analytic" and math.isfinite(r.rel_std_error)
    assert r.illuminance == pytest.approx(expected, rel=1e-4)


def test_a_taper_is_named_and_its_caustic_is_a_bound(clean_blender):
    """A pane whose upper face is 0.3 % smaller (a taper: 9 mm at its 3 m half-width) is no thin pane: the
    notes name it and why, and the sun through it is a caustic stated as a bound, never 0 +-inf."""
    from radiometer import api

    scene = _roof(True)
    ob = bpy.data.objects["Roof"]
    mesh = ob.data
    centre = sum((v.co for v in mesh.vertices), mesh.vertices[0].co * 0) / len(mesh.vertices)
    normal = mesh.polygons[0].normal
    for v in mesh.vertices:
        if (v.co - centre).dot(normal) > 0:
            v.co = centre + (v.co - centre) * 0.997 + normal * (v.co - centre).dot(normal) * 0.003
    r = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), scene=scene, quality="preview")
    why = [n for n in r.notes if "'Roof' transmits light but is not a thin pane" in n]
    assert why and "not square" in why[0] and "shifts 9 mm" in why[0], (why, r.notes)
    # A bound, never 0 +-inf: a finite relative error, or (the rendered part found nothing) a finite
    # one-sided bound that holds the caustic's closed-form share.
    stated = math.isfinite(r.rel_std_error) or (r.upper_bound_lux is not None and 0 < r.upper_bound_lux < math.inf)
    assert stated and r.rel_error_bound > 0.0, (r.illuminance, r.rel_std_error, r.upper_bound_lux, r.notes)


def test_open_floor_sun_beside_a_window_is_exact(clean_blender):
    """The sun (40 deg up) on the meter's side of a window 5 m away: its mirror image in the pane comes
    up 4.2 m at the window, above its 2.5 m head, so nothing reflects the sun to the meter: exact."""
    from radiometer import api

    scene = scenes.reset()
    scenes._world(scene, strength=0.0)
    ob = scenes.add_pane(scene, "Window", scenes.glass_material("g", "glass", 1.52), centre=(0.0, 0.0, 0.0),
                         size=(2.0, 2.0), thickness=0.006)
    ob.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # vertical, in the plane y = 0
    ob.location = (0.0, 0.0, 1.5)
    # Rotation x = 50 deg turns the sun's light (local -Z) to (0, sin 50, -cos 50): it comes from -y, the
    # meter's side of the window, 40 deg up.
    scenes._light(scene, "SUN", (0.0, 0.0, 5.0), rotation=(math.radians(50.0), 0.0, 0.0), energy=E_DN,
                  angle=math.radians(0.53))
    r = api.measure_illuminance((0.0, -5.0, 0.0), (0.0, 0.0, 1.0), scene=scene, quality="preview")
    assert r.exact and r.method == "analytic", r.notes
    assert r.illuminance == pytest.approx(683.0 * E_DN * math.sin(math.radians(40.0)), rel=2e-5)
    # 1 m from the window the meter sees the sun in the pane: reflected light, not exact, finite.
    near = api.measure_illuminance((0.0, -1.0, 0.0), (0.0, 0.0, 1.0), scene=scene, quality="preview")
    assert not near.exact and math.isfinite(near.rel_std_error) and near.rel_std_error > 0.0, near.notes


def test_lamp_without_shadow_behind_a_wall_reads_exact(clean_blender):
    """A lamp with shadows off behind a wall lights the meter through it (the closed form); the wall's
    side the meter sees is lit by nothing: exact, not 'no measurement' (+-inf)."""
    from radiometer import api

    scene = bpy.context.scene
    scenes._world(scene, strength=0.0)
    mesh = bpy.data.meshes.new("Wall")
    mesh.from_pydata([(-3, 1.0, 0), (3, 1.0, 0), (3, 1.0, 2.5), (-3, 1.0, 2.5)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("Wall", mesh))
    scenes._light(scene, "POINT", (0.0, 2.0, 1.0), energy=100.0, shadow_soft_size=0.0, use_shadow=False)
    r = api.measure_illuminance((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), scene=scene, quality="preview")
    expected = 683.0 * 100.0 / (4 * math.pi) / 4.0  # I / d^2, normal incidence, 2 m
    assert r.exact and r.rel_std_error == 0.0, r.notes
    assert r.illuminance == pytest.approx(expected, rel=1e-9)

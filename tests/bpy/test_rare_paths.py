"""Honest errors on rare paths (issue 18): a rendered reading of 0 never states an error of 0 when
light could arrive by a path that the pilot may have missed."""

import math

import pytest

bpy = pytest.importorskip("bpy")


def test_dark_meter_facing_a_surface_states_no_zero_error(clean_blender, build):
    from radiometer import api
    from radiometer.radiometry import allocation

    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", location=(0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    # A black card above a meter that faces it, away from the lamp: nothing reaches the meter, but
    # the card lies above its horizon, so the pilot's 0 is not proof.
    build.plane(scene, size=0.5, location=(0.0, 0.0, -0.5), albedo=0.0, name="card")
    r = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), quality="preview")
    assert r.illuminance == 0.0 and r.method in ("render", "hybrid")
    assert math.isinf(r.rel_std_error)
    assert r.samples >= allocation.DARK_FLOOR
    assert any("found no rendered light" in note for note in r.notes)
    # The same meter facing the lamp reads the closed form exactly, with nothing to render.
    lit = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), quality="preview")
    assert lit.illuminance == pytest.approx(683 * 100 / (4 * math.pi) / 4, rel=1e-6)

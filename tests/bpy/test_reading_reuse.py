"""Issue 17, the fixed cost of one reading: what a reading proves or places on a kept capture is kept for
the next reading of the same points (``meter._plan_direct``, ``meter._placement_memo``), and the readings
are the same, field for field, as with nothing kept; any change of the model proves again."""

import dataclasses
import math

import bpy
import pytest

from radiometer import api
from radiometer.measure.capture import capture_cache
from radiometer.measure.meter import point_meter as meter
from radiometer.radiometry.scene import scene_model


@pytest.fixture
def proofs(monkeypatch):
    """Counts ``scene_model.plan_direct`` calls; starts with nothing kept."""
    calls = []
    real = scene_model.plan_direct

    def counting(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(scene_model, "plan_direct", counting)
    capture_cache.clear()
    _forget()
    return calls


def _forget():
    meter._LAST_PLAN[:] = [None, None, None]
    meter._PLACEMENT[:] = [None, {}]


def _fields(reading):
    values = dataclasses.asdict(reading)
    values.pop("seconds")
    return values


def _scene(build):
    """A point light over a desk (the meter lies on it: a placement note) under a reflecting ceiling
    (indirect light: the reading is a hybrid with a rendered part)."""
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", location=(0.0, 0.0, 1.0), energy=50.0, shadow_soft_size=0.0)
    build.plane(scene, size=1.0, location=(0.0, 0.0, 0.0), name="desk")
    build.plane(scene, size=6.0, location=(0.0, 0.0, 2.0), rotation=(math.pi, 0.0, 0.0), albedo=0.5)
    return lamp


def _read(seed):
    return api.measure_illuminance((0.1, 0.0, 0.0), (0.0, 0.0, 1.0), method="hybrid", samples=16, seed=seed)


def test_a_repeated_reading_reuses_its_proofs_and_equals_a_fresh_one(clean_blender, build, proofs):
    lamp = _scene(build)
    first = _read(1)
    assert len(proofs) == 1 and any("on the surface of 'desk'" in note for note in first.notes)
    again = _read(2)
    assert len(proofs) == 1  # same model, same point: the proofs were kept
    _forget()
    fresh = _read(2)
    assert len(proofs) == 2
    assert _fields(again) == _fields(fresh)  # bit for bit, notes included
    lamp.data.energy = 100.0  # a new light: proved again, and the closed form follows it
    edited = _read(2)
    assert len(proofs) == 3
    # The same seed, twice the power: the closed form and the rendered part both double (Cycles is
    # linear in a light's power at a fixed seed), so a stale proof or closed form would show.
    assert edited.parts["analytic"] == ["point"]
    assert edited.irradiance == pytest.approx(2.0 * fresh.irradiance, rel=1e-9)


def test_a_moved_occluder_is_proved_again(clean_blender, build, proofs):
    lamp = _scene(build)
    first = _read(1)
    blocker = build.plane(bpy.context.scene, size=0.5, location=(0.0, 0.0, 0.5), name="blocker")
    blocked = _read(1)
    assert len(proofs) == 2 and blocked.irradiance < 0.1 * first.irradiance  # the lamp's light is gone
    blocker.location.z = -0.5  # under the desk now: the light reaches the meter again
    clear = _read(1)
    assert len(proofs) == 3
    assert clear.irradiance > 10.0 * blocked.irradiance
    assert lamp.data.energy == 50.0

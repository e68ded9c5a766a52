"""Participating media in the scene model (issue 18): a volume on the way removes `exact`."""

import numpy as np

from radiometer.radiometry import emitters
from radiometer.radiometry.scene import scene_model


def _empty_model(*specs, volumes=(), world_volume=False):
    return scene_model.SceneModel(lights=[scene_model.ModelLight(s.name, s) for s in specs],
                                  geometry=scene_model.SceneGeometry(), volumes=list(volumes),
                                  world_volume=world_volume)


LAMP = emitters.CyclesLight(name="lamp", kind="POINT", position=(0, 0, 2.0), radius=0.0)
PANEL = emitters.CyclesLight(name="panel", kind="AREA", position=(0, 0, 2.0), size=0.6)


def test_no_medium_stays_exact():
    plan = scene_model.plan_direct(_empty_model(LAMP, PANEL), [[0, 0, 0.0]], [[0, 0, 1]])
    assert plan.exact_points().all()


def test_world_volume_renders_every_light_and_scatters_everywhere():
    model = _empty_model(LAMP, PANEL, world_volume=True)
    plan = scene_model.plan_direct(model, [[0, 0, 0.0], [0, 0, 3.0]], [[0, 0, 1], [0, 0, 1]])
    assert (plan.status == scene_model.RENDER).all()
    assert "world's volume" in plan.reason[0, 0]
    # Light scattered by the medium reaches even a meter facing away from the light.
    assert plan.indirect.all() and not plan.exact_points().any()


def test_volume_object_on_the_segment_or_above_the_horizon():
    fog = ("Fog", np.array([-0.5, -0.5, 0.8]), np.array([0.5, 0.5, 1.2]))
    model = _empty_model(LAMP, volumes=[fog])
    # Under the fog box: the lamp's segment crosses it.
    under = scene_model.plan_direct(model, [[0, 0, 0.0]], [[0, 0, 1]])
    assert under.status[0, 0] == scene_model.RENDER and "'Fog'" in under.reason[0, 0]
    # Beside it, facing up: the segment misses the box, but the fog lies above the horizon and scatters.
    beside = scene_model.plan_direct(model, [[3, 0, 0.0]], [[0, 0, 1]])
    assert beside.status[0, 0] == scene_model.EXACT
    assert beside.indirect[0] and "'Fog'" in beside.indirect_reason[0] and not beside.exact_points()[0]
    # Beside it, facing away from the fog box (down): exact again.
    away = scene_model.plan_direct(model, [[3, 0, 0.0]], [[0, 0, -1]])
    assert away.exact_points()[0]

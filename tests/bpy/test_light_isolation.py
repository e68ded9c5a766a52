"""Light isolation finds a light by its identity (the capture's ``SourceId``), not its name (issue 17).

Two objects share one light data-block, and one is renamed after the scene was captured: each must
still get its own emitter (at its own position), each must be found again from the capture's keys
(as the hybrid meter's light linking does), and isolating one must switch the other off.
"""

import bpy
import numpy as np

from radiometer.measure.analyses import light_isolation
from radiometer.measure.meter import point_meter as meter
from radiometer.measure.capture import scene_capture


def test_shared_light_data_and_a_rename_are_isolated_by_identity(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    first = build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    second = bpy.data.objects.new("second lamp", first.data)  # a second instance of the same light data
    second.location = (1.5, 0.0, 2.5)
    scene.collection.objects.link(second)
    bpy.context.view_layer.update()
    model = light_isolation.scene_model(scene)
    assert len(model.lights) == 2

    second.name = "renamed after the capture"  # the model still carries the old label
    assert all(lt.name != second.name for lt in model.lights)
    for obj, where in ((first, (0.0, 0.0, 2.0)), (second, (1.5, 0.0, 2.5))):
        spec = light_isolation.light_spec(obj, scene, model)
        np.testing.assert_allclose(spec.position, where, atol=1e-12)  # scale_length 1: metres
    assert light_isolation.rendering_light_objects(scene, model) == sorted([first, second], key=lambda o: o.name)
    # The hybrid meter excludes lights from its sensors by these keys (light linking): one per object.
    keys = {meter.light_object_key(lt) for lt in model.lights}
    assert set(scene_capture.source_objects(keys).values()) == {first, second}
    with light_isolation.isolated_light(scene, second, model) as off:
        assert off == [first.name] and first.hide_render and not second.hide_render
    assert not first.hide_render and not second.hide_render

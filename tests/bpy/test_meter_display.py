"""What the sidebar and the viewport say about a stored reading (issue 18: never '0 lx ±0 %' for a
rendered reading that found no light yet)."""

import math

import pytest

bpy = pytest.importorskip("bpy")


def _reading(**overrides):
    from radiometer.readings import IlluminanceReading

    fields = dict(irradiance_rgb=(0.0, 0.0, 0.0), irradiance=0.0, illuminance=0.0, rel_std_error=math.inf,
                  method="render", samples=4096, seconds=0.1, efficacy=683.0, colour_space="Linear Rec.709",
                  notes=["1 meter(s) found no rendered light in 4,096+ samples"])
    fields.update(overrides)
    return IlluminanceReading(**fields)


def test_a_dark_rendered_reading_keeps_its_unknown_error(clean_blender):
    from radiometer import api
    from radiometer.panels.meter import format_reading

    ob = bpy.data.objects.new("meter", None)
    bpy.context.scene.collection.objects.link(ob)
    ob.radiometer_meter.is_meter = True
    api.store_reading(ob, _reading())
    m = ob.radiometer_meter
    assert math.isinf(m.rel_std_error) and not m.exact
    text = format_reading(m)
    assert text.startswith("0 lx") and "±0" not in text and "n/a" in text
    # A converged reading still shows its error with two significant digits.
    api.store_reading(ob, _reading(illuminance=402.283, irradiance=402.283 / 683, rel_std_error=0.011))
    assert format_reading(ob.radiometer_meter) == "402 lx ±1.1 %"

"""Photographer's readout on real readings (issue 23 item 6): EV100, CCT and Duv of the light at a meter,
in the readings, the CLI table and the sidebar; the reference CCT is colour-science's Ohno 2013 on the
light's own RGB (Blender's temperature colour), computed independently of the meter."""

import math
import types
import warnings

import bpy
import numpy as np
import pytest

from radiometer import api

colour = pytest.importorskip("colour")


def test_reading_of_a_2700k_light(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    lamp.data.use_temperature = True
    lamp.data.temperature = 2700.0
    r = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), scene=scene)
    assert r.exact
    rgb = np.array(lamp.data.temperature_color)  # the colour Cycles gives the light (FACTS.md)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        xyz = colour.RGB_to_XYZ(rgb, colour.RGB_COLOURSPACES["ITU-R BT.709"], apply_cctf_decoding=False)
        ref_cct, ref_duv = colour.temperature.uv_to_CCT_Ohno2013(colour.xy_to_UCS_uv(colour.XYZ_to_xy(xyz)))
    assert r.cct_k == pytest.approx(ref_cct, rel=5e-4)
    assert r.duv == pytest.approx(ref_duv, abs=2e-5)
    assert abs(r.cct_k - 2700) < 60  # Blender's fitted temperature table is close to Planck
    assert r.ev100 == pytest.approx(math.log2(r.illuminance * 100 / 250), abs=1e-12)

    from radiometer.commands.measure import format_table

    meter = types.SimpleNamespace(name="Desk")
    line = format_table([(meter, r)]).splitlines()[1]
    assert f"{r.illuminance:.5g}"[:3] in line and "lx" in line and "exact" in line
    assert f"EV100 {r.ev100:.1f} (incident, flat sensor)" in line and f"{round(r.cct_k, -1):.0f} K" in line


def test_sidebar_shows_ev_and_cct(clean_blender, build):
    from radiometer.panels.meter import RADIOMETER_PT_active_meter

    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    lamp.data.color = (1.0, 1.0, 1.0)
    from radiometer.operators.meter import add_meter

    meter = add_meter(bpy.context, "ILLUMINANCE", (0.0, 0.0, 0.0))
    api.measure_meters(scene=scene)
    labels = []
    layout = types.SimpleNamespace(prop=lambda *a, **k: None, label=lambda text="", **k: labels.append(text),
                                   box=lambda: layout, column=lambda **k: layout, row=lambda **k: layout,
                                   operator=lambda *a, **k: types.SimpleNamespace())  # Blender returns the operator properties
    context = types.SimpleNamespace(active_object=meter, scene=scene)
    RADIOMETER_PT_active_meter.draw(types.SimpleNamespace(layout=layout), context)
    photo = [t for t in labels if t.startswith("EV100")]
    assert photo and "incident, flat sensor" in photo[0] and "6500 K" in photo[0]  # white Rec.709 = D65

"""Does a refactor change a reading? Readings of one checkout on fixed scenes and seeds, printed as one JSON
line (``RESULT {...}``, floats as Python writes them, so equal means bit-identical).

Run it once per checkout, each seen as ``radiometer`` through its own site folder, and compare the lines:

    mkdir -p /tmp/a_site /tmp/b_site
    ln -s /path/to/old/checkout /tmp/a_site/radiometer; ln -s /path/to/new/checkout /tmp/b_site/radiometer
    PYTHONPATH=/tmp/a_site .venv/bin/python bench/same_readings.py > a.log
    PYTHONPATH=/tmp/b_site .venv/bin/python bench/same_readings.py > b.log

What it reads (the paths a request takes through the house): the meter (closed forms and renders) in the
tests' office, its UGR, a grid, a luminance reading; an area light's inverse-square and cosine checks; the
daylight factor (the sky component split) in the tests' side-lit room, the world's illuminance and meter
readings under a CIE sky, a sun-study step; a spectral reading with the reflected part (band renders).
Results: bench/same_readings.md.
"""
import json
import pathlib
import sys
import tempfile

import bpy
import numpy as np

import radiometer
from radiometer import api

sys.path[:0] = [radiometer.__path__[0] + "/tests/bpy", radiometer.__path__[0] + "/tests"]
import daylight_room  # noqa: E402
import office  # noqa: E402
import spectral_room  # noqa: E402

out = {"tree": radiometer.__path__[0]}


def fresh():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    return bpy.context.scene

s = fresh(); office.build(s)
pts = [(0, 0, 0.8), (1.5, 1.0, 0.8), (-2.5, -1.5, 0.8)]
out["office_E"] = [r.illuminance for r in api.measure_illuminance(pts, (0, 0, 1), quality="preview", seed=3)]
out["office_E_se"] = [r.rel_std_error for r in api.measure_illuminance(pts, (0, 0, 1), quality="preview", seed=3)]
g = api.glare_ugr(office.EYE, office.VIEW, quality="preview")
out["ugr"] = [g.ugr, g.ugr_std_error, g.background_luminance]
bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0, 0, 0.8)); plane = bpy.context.active_object
grid = api.illuminance_grid(plane, resolution=(3, 2), quality="preview", seed=1)
out["grid"] = np.asarray(grid.lux).ravel().tolist()
lum = api.measure_luminance((0, 0, 1.5), (0, 0, 1), quality="preview")
out["lum"] = [lum.luminance, lum.rel_std_error]

from radiometer.demo import builders
s = fresh(); builders.black_world(s)
lamp = builders.add_light(s, "AREA", (0.0, 0.0, 2.5), name="lamp", energy=200.0, size=0.4)
builders.add_plane(s, size=6.0, albedo=0.6, name="floor")
law = api.check_inverse_square(lamp, quality="preview")
out["law"] = [[row.measured, row.direct] for row in law.rows]
cos = api.check_cosine_law(lamp, quality="preview")
out["cos"] = [[row.measured, row.direct] for row in cos.rows]

s = fresh(); daylight_room.build_blender(s)
dfs = api.daylight_factor(daylight_room.POINTS, quality="preview", seed=2)
out["df"] = [(r.daylight_factor, r.rel_std_error, r.sky_component) for r in dfs]
api.set_cie_sky(s, "cie:12", horizontal_illuminance_lux=12000.0, sun_direction=(0.3, -0.5, 0.81))
out["world"] = api.world_illuminance(s)["illuminance"]
out["sky_E"] = [r.illuminance for r in api.measure_illuminance(daylight_room.POINTS, (0, 0, 1), quality="preview", seed=5)]
import datetime as dt  # noqa: E402

tz = dt.timezone(dt.timedelta(hours=1))
st = api.sun_study(daylight_room.POINTS, (0, 0, 1), [dt.datetime(2026, 3, 21, 11, tzinfo=tz)], latitude_deg=48.2, longitude_deg=16.4, quality="preview")
out["sun"] = np.asarray(st.illuminance).ravel().tolist()

s = fresh()
with tempfile.TemporaryDirectory() as d:
    scene, light = s, None
    res = spectral_room.build(s, pathlib.Path(d))
    light = res[1] if isinstance(res, tuple) else res
    loc, nrm = spectral_room.ref.METERS["eye"]
    r = api.spectral_reading(loc, nrm, reflected=True, quality="preview", seed=4)
    out["spectral"] = [r["illuminance_lx"], r["mel_edi_lx"], r["interval_95"]["mel_edi_lx"]["low_95"]]
print("RESULT " + json.dumps(out, default=float))

"""Run Radiance at the annual DGP's eyes in the non-saturated annual room (``annual_room.py``) and write
annual_dgp_reference.json.

    .venv/bin/python tests/bpy/make_annual_dgp_reference.py

Radiance's daylight coefficients at each eye (``annual_room.radiance_two_phase``: rcontrib over MF:1 bins
and a ground bin, the ray's direction the line of sight), lux per cd/m^2, which the test multiplies by
Radiometer's sky matrix; and Honeybee's imageless annual glare whole: those coefficients x gendaymtx,
DGPs = 6.22e-5 E_v + 0.184 per occupied hour, the hours at or above 0.35 / 0.40 / 0.45. Run twice
(rcontrib's ambient sampling differs from run to run): both runs are kept, their difference is Radiance's
own noise. Nothing of Radiometer's measurement code runs (its EPW reader and occupied hours only).
"""

import importlib.util
import json
import pathlib
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
JSON_PATH = HERE / "annual_dgp_reference.json"
#: (eye, line of sight): looking at the window, along the window wall, at the window obliquely
EYES = [((2.0, 2.0, 1.2), (0.0, -1.0, 0.0)), ((2.0, 2.0, 1.2), (1.0, 0.0, 0.0)),
        ((1.0, 3.0, 1.2), (0.7071067811865476, -0.7071067811865476, 0.0))]
LIMITS = (0.35, 0.40, 0.45)
AMBIENT_DIVISIONS = 65536


def main():
    from radiometer.radiometry.metrics import daylight_metrics
    from radiometer.radiometry.sun import epw

    spec = importlib.util.spec_from_file_location("annual_room", HERE / "annual_room.py")
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    runs = []
    with tempfile.TemporaryDirectory(prefix="radiometer-annual-dgp-ref-") as folder:
        epw_path = room.write_epw(pathlib.Path(folder) / "year.epw")
        occ = daylight_metrics.occupied_hours(epw.read_epw(epw_path).midpoint_hours())
        t0 = time.perf_counter()
        for _ in range(2):
            e, dc = room.radiance_two_phase(folder, epw_path, [p for p, _v in EYES], [v for _p, v in EYES],
                                            ambient_divisions=AMBIENT_DIVISIONS)
            dgps = 6.22e-5 * e[occ] + 0.184
            runs.append({"dc_lux_per_cd_m2": dc.T.tolist(),  # (eye, patch)
                         "gendaymtx_hours_at_or_above": {f"{lim:.2f}": [int(np.sum(dgps[:, k] >= lim))
                                                                        for k in range(len(EYES))] for lim in LIMITS},
                         "gendaymtx_mean_occupied_ev_lux": [float(v) for v in e[occ].mean(axis=0)]})
        seconds = time.perf_counter() - t0
    ref = {"eyes": [list(p) for p, _v in EYES], "views": [list(v) for _p, v in EYES],
           "occupied_hours": int(occ.sum()), "runs": runs, "seconds_radiance": seconds,
           "source": f"Radiance (pyradiance binaries): rcontrib -ab 8 -ad {AMBIENT_DIVISIONS} -lw 1e-6 over MF:1 "
                     "bins + ground, the ray along the line of sight; gendaymtx -m 1 of epw2wea for the whole "
                     "imageless chain, DGPs = 6.22e-5 E_v + 0.184 (Honeybee's imageless annual glare); two runs"}
    JSON_PATH.write_text(json.dumps(ref, indent=1) + "\n", encoding="utf-8")
    print({k: v for k, v in ref.items() if k != "runs"},
          [{k: v for k, v in run.items() if k != "dc_lux_per_cd_m2"} for run in runs])


if __name__ == "__main__":
    main()

"""Run Radiance on the non-saturated annual room (``annual_room.py``) and write annual_reference.json.

    .venv/bin/python tests/bpy/make_annual_reference.py

Radiance two-phase sDA and direct-sun ASE (see annual_room.py); nothing of Radiometer's measurement
code runs (its EPW reader and LM-83 counting only, which tests/test_annual_sky.py checks on
constructed cases). A few minutes on two cores.
"""

import importlib.util
import json
import pathlib
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
JSON_PATH = HERE / "annual_reference.json"


def main():
    spec = importlib.util.spec_from_file_location("annual_room", HERE / "annual_room.py")
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    with tempfile.TemporaryDirectory(prefix="radiometer-annual-ref-") as folder:
        epw_path = room.write_epw(pathlib.Path(folder) / "year.epw")
        t0 = time.perf_counter()
        ref = room.radiance_annual(folder, epw_path)
        ref["seconds_radiance"] = time.perf_counter() - t0
    ref["source"] = ("Radiance (pyradiance binaries): two-phase rcontrib -ab 8 -ad 16384 -lw 1e-6 x gendaymtx -m 1 "
                     "for sDA; rcontrib -ab 0 with one 0.533 deg sun per occupied hour (pvlib SPA) x gendaymtx -d "
                     "direct normal illuminance for ASE")
    JSON_PATH.write_text(json.dumps(ref, indent=1) + "\n", encoding="utf-8")
    print({k: v for k, v in ref.items() if not isinstance(v, list)})


if __name__ == "__main__":
    main()

"""Issue 35: the spectral reading of a coloured room against an independent numpy spectral radiosity.

``python bench/spectral_room.py reference``: solve the box (tests/spectral_radiosity.py) at h = 0.4 and 0.2 m
(and 0.1 m with ``--fine``), write tests/bpy/spectral_room_reference.json (per 1 cd).
``python bench/spectral_room.py seeds N [quality]``: N seeds of ``api.spectral_reading(reflected=True)`` in
the Blender box (tests/bpy/spectral_room.py), the coverage of the 95 % intervals, bench/spectral_room.json/.md.
Run from the repository root with PYTHONPATH holding ``radiometer``.
"""

import json
import os
import pathlib
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "tests"), str(HERE.parent / "tests" / "bpy")]


def make_reference(fine=False):
    import spectral_radiosity as ref

    out = {m: {} for m in ref.METERS}
    runs = [(0.4, 3), (0.2, 3)] + ([(0.1, 2)] if fine else [])
    for h, q in runs:
        t0 = time.perf_counter()
        r = ref.solve(ref.light_spectrum("blackbody:4000"), 1.0, h=h, q=q)
        for m in ref.METERS:
            out[m][str(h)] = {p: r[m]["quantities"][p] for p in ("direct", "reflected", "total")}
        print(f"h = {h} m, q = {q}: {r['patches']} patches, {time.perf_counter() - t0:.0f} s", flush=True)
    path = HERE.parent / "tests" / "bpy" / "spectral_room_reference.json"
    path.write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")
    print("wrote", path)


def run_seeds(n, quality):
    import tempfile

    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    import radiometer
    from radiometer import api
    from radiometer.demo import builders
    import spectral_room

    radiometer.register()
    scene = bpy.context.scene
    builders.metric_cycles_scene(scene)
    light = spectral_room.build(scene, pathlib.Path(tempfile.mkdtemp()))
    value, error = spectral_room.expected(scene, light)
    loc, nrm = spectral_room.ref.METERS["eye"]
    rows = []
    for seed in range(n):
        t0 = time.perf_counter()
        row = spectral_room.reading_row(api.spectral_reading(loc, nrm, reflected=True, quality=quality, seed=seed))
        row["seconds"] = time.perf_counter() - t0
        rows.append(row)
        print(seed, {k: round(v, 2) for k, v in row.items()}, flush=True)
    ev, mel = value[("total", "illuminance_lx")], value[("total", "mel_edi_lx")]
    cover_ev = sum(r["ev_lo"] <= ev <= r["ev_hi"] for r in rows)
    cover_mel = sum(r["mel_lo"] <= mel <= r["mel_hi"] for r in rows)
    summary = {"quality": quality, "seeds": n, "reference": {f"{p} {q}": v for (p, q), v in value.items()},
               "reference_discretisation": {f"{p} {q}": v for (p, q), v in error.items()},
               "covered_ev": cover_ev, "covered_mel": cover_mel, "rows": rows}
    (HERE / "spectral_room.json").write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps({k: v for k, v in summary.items() if k != "rows"}, indent=1))


if __name__ == "__main__":
    if sys.argv[1] == "reference":
        make_reference(fine="--fine" in sys.argv)
    else:
        run_seeds(int(sys.argv[2]), sys.argv[3] if len(sys.argv) > 3 else "preview")

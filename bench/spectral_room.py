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
    name = "spectral_room.json" if quality == "preview" else f"spectral_room_{quality}.json"
    (HERE / name).write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps({k: v for k, v in summary.items() if k != "rows"}, indent=1))


def write_md():
    """bench/spectral_room.md from bench/spectral_room.json (and the RGB-only bound in the product)."""
    from radiometer.radiometry.photometry import spectral_bands

    d = json.loads((HERE / "spectral_room.json").read_text())
    ref = d["reference"]
    rows = d["rows"]
    n = len(rows)
    bound = spectral_bands.RGB_ONLY_REL_BOUND
    rgb_in = {"ev": 0, "mel": 0}
    for r in rows:
        for key, q, se in (("ev", "illuminance_lx", "rgb_ev_se"), ("mel", "mel_edi_lx", "rgb_mel_se")):
            est = r[f"rgb_{key}_reflected"]
            rgb_in[key] += abs(est - ref[f"reflected {q}"]) <= bound[q] * abs(est) + 1.96 * r[se]
    mean = lambda k: sum(r[k] for r in rows) / n  # noqa: E731
    lines = [
        "# Issue 35: the spectral reading of a red room against a numpy spectral radiosity",
        "",
        "`bench/spectral_room.py seeds 50 preview` (bpy 5.0.1, the 2-core shared machine); the reference",
        "`tests/spectral_radiosity.py` (5 nm; patches of 0.1 m, its change from 0.2 m counted as its uncertainty),",
        "`tests/bpy/spectral_room_reference.json`. Box 4 x 3 x 2.7 m, ColorChecker red walls, white 9.5 ceiling,",
        "neutral 8 floor, a 100 W point light of 4000 K at (1.6, 1.4, 2.1) m, a vertical meter at (3.2, 1.1, 1.2) m",
        "facing -x. `api.spectral_reading(reflected=True, quality='preview', seed=s)`, s = 0..%d." % (n - 1),
        "",
        "Reference refinement, eye meter, reflected part per cd (patch side m: E_v, mel-EDI lx): " + "; ".join(
            f"{h}: {v['reflected']['illuminance_lx']:.5f}, {v['reflected']['mel_edi_lx']:.5f}" for h, v in
            sorted(json.loads((HERE.parent / "tests" / "bpy" / "spectral_room_reference.json").read_text())["eye"].items(),
                   key=lambda kv: -float(kv[0]))) + ".",
        "",
        "| quantity | reference (lx) | its discretisation (lx) | mean reading (lx) | mean s.e. (lx) | mean band bound (lx) | 95 %% intervals covering |" ,
        "|---|---|---|---|---|---|---|",
        f"| E_v total | {ref['total illuminance_lx']:.1f} | {d['reference_discretisation']['total illuminance_lx']:.1f} | "
        f"{mean('ev'):.1f} | {mean('ev_se'):.1f} | {mean('ev_band'):.1f} | {d['covered_ev']}/{n} |",
        f"| mel-EDI total | {ref['total mel_edi_lx']:.1f} | {d['reference_discretisation']['total mel_edi_lx']:.1f} | "
        f"{mean('mel'):.1f} | {mean('mel_se'):.1f} | {mean('mel_band'):.1f} | {d['covered_mel']}/{n} |",
        f"| E_v direct (exact) | {ref['direct illuminance_lx']:.2f} | 0 | {mean('ev_direct'):.2f} | 0 | 0 | |",
        f"| mel-EDI direct (exact) | {ref['direct mel_edi_lx']:.2f} | 0 | {mean('mel_direct'):.2f} | 0 | 0 | |",
        f"| E_v reflected, bands | {ref['reflected illuminance_lx']:.1f} | | {mean('ev_reflected'):.1f} | | | |",
        f"| mel-EDI reflected, bands | {ref['reflected mel_edi_lx']:.1f} | | {mean('mel_reflected'):.1f} | | | |",
        f"| E_v reflected, RGB-only | {ref['reflected illuminance_lx']:.1f} | | {mean('rgb_ev_reflected'):.1f} | "
        f"{mean('rgb_ev_se'):.1f} | bound {100 * bound['illuminance_lx']:.1f} %% | {rgb_in['ev']}/{n} within bound + 1.96 s.e. |",
        f"| mel-EDI reflected, RGB-only | {ref['reflected mel_edi_lx']:.1f} | | {mean('rgb_mel_reflected'):.1f} | "
        f"{mean('rgb_mel_se'):.1f} | bound {100 * bound['mel_edi_lx']:.1f} %% | {rgb_in['mel']}/{n} within bound + 1.96 s.e. |",
        "",
        f"Time per reading (bands + RGB-only, preview): mean {mean('seconds'):.1f} s on the loaded 2-core machine.",
        "",
        "| seed | E_v (lx) | 95 % interval | mel-EDI (lx) | 95 % interval | RGB-only reflected E_v / mel-EDI (lx) |",
        "|---|---|---|---|---|---|",
    ]
    std = HERE / "spectral_room_standard.json"
    if std.exists():  # `seeds 20 standard`: the same check at standard quality (64 bands, 16384 samples per render)
        e = json.loads(std.read_text())
        m = lambda k: sum(r[k] for r in e["rows"]) / len(e["rows"])  # noqa: E731
        lines[-3:-3] = [
            "", f"Standard quality (`seeds {e['seeds']} standard`, bench/spectral_room_standard.json): E_v {m('ev'):.1f} lx "
            f"(s.e. {m('ev_se'):.1f}, band bound {m('ev_band'):.1f}), covering {e['covered_ev']}/{e['seeds']}; mel-EDI "
            f"{m('mel'):.1f} lx (s.e. {m('mel_se'):.1f}, band bound {m('mel_band'):.1f}), covering "
            f"{e['covered_mel']}/{e['seeds']}; reflected part E_v {m('ev_reflected'):.1f} lx, mel-EDI "
            f"{m('mel_reflected'):.1f} lx; {m('seconds'):.1f} s per reading."]
    lines = [x.replace("%%", "%") for x in lines]
    for k, r in enumerate(rows):
        lines.append(f"| {k} | {r['ev']:.1f} | {r['ev_lo']:.1f}-{r['ev_hi']:.1f} | {r['mel']:.1f} | "
                     f"{r['mel_lo']:.1f}-{r['mel_hi']:.1f} | {r['rgb_ev_reflected']:.1f} / {r['rgb_mel_reflected']:.1f} |")
    (HERE / "spectral_room.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:20]))


if __name__ == "__main__":
    if sys.argv[1] == "reference":
        make_reference(fine="--fine" in sys.argv)
    elif sys.argv[1] == "md":
        write_md()
    else:
        run_seeds(int(sys.argv[2]), sys.argv[3] if len(sys.argv) > 3 else "preview")

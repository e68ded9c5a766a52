"""Issue 35: the spectral reading of daylight indoors (the world's light through an opening) against an
independent numpy spectral radiosity.

The red room of ``bench/spectral_room.py`` with a floor-to-ceiling opening (x 1.2-2.8 m) in wall y0 and no
light: a uniform white world (D65, the default sky spectrum) lights it through the opening
(``tests/spectral_radiosity.py``: ``solve_daylit``, the opening a Lambertian emitter of the world's radiance).

``python bench/spectral_daylit.py reference [--fine]``: solve at h = 0.4 and 0.2 m (and 0.1 m), write
tests/bpy/spectral_room_daylit_reference.json (per 1 cd/m² of world luminance).
``python bench/spectral_daylit.py seeds N [quality]``: N seeds of ``api.spectral_reading(reflected=True)``
at the eye and desk meters, the coverage of the 95 % intervals: bench/spectral_daylit.json and .md.
Run from the repository root with PYTHONPATH holding ``radiometer``.
"""

import json
import pathlib
import sys
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "tests"), str(HERE.parent / "tests" / "bpy")]
REFERENCE = HERE.parent / "tests" / "bpy" / "spectral_room_daylit_reference.json"


def make_reference(fine=False):
    import spectral_radiosity as ref

    out = {m: {} for m in ref.METERS}
    for h, q in [(0.4, 3), (0.2, 3)] + ([(0.1, 2)] if fine else []):
        t0 = time.perf_counter()
        r = ref.solve_daylit(ref._d65(), 1.0, h=h, q=q)
        for m in ref.METERS:
            out[m][str(h)] = {p: r[m]["quantities"][p] for p in ("direct", "reflected", "total")}
        print(f"h = {h} m, q = {q}: {r['patches']} patches, {time.perf_counter() - t0:.0f} s", flush=True)
    REFERENCE.write_text(json.dumps(out, indent=1, sort_keys=True) + "\n")
    print("wrote", REFERENCE)


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
    world = spectral_room.build_daylit(scene, pathlib.Path(tempfile.mkdtemp()))
    summary = {"quality": quality, "seeds": n, "meters": {}}
    for meter in ("eye", "desk"):
        value, error = spectral_room.expected_daylit(scene, world, meter)
        loc, nrm = spectral_room.ref.METERS[meter]
        rows = []
        for seed in range(n):
            t0 = time.perf_counter()
            r = api.spectral_reading(loc, nrm, reflected=True, quality=quality, seed=seed)
            row = spectral_room.reading_row(r)
            row["seconds"] = time.perf_counter() - t0
            rows.append(row)
            print(meter, seed, {k: round(v, 2) for k, v in row.items() if v is not None}, flush=True)
        ev, mel = value[("total", "illuminance_lx")], value[("total", "mel_edi_lx")]
        summary["meters"][meter] = {
            "reference": {f"{p} {q}": v for (p, q), v in value.items()},
            "reference_discretisation": {f"{p} {q}": v for (p, q), v in error.items()},
            "covered_ev": sum(r["ev_lo"] <= ev <= r["ev_hi"] for r in rows),
            "covered_mel": sum(r["mel_lo"] <= mel <= r["mel_hi"] for r in rows), "rows": rows}
    (HERE / "spectral_daylit.json").write_text(json.dumps(summary, indent=1) + "\n")
    write_md()


def write_md():
    d = json.loads((HERE / "spectral_daylit.json").read_text())
    n = d["seeds"]
    refinement = json.loads(REFERENCE.read_text())
    lines = [
        "# Issue 35: daylight indoors, spectral reading against a numpy spectral radiosity",
        "",
        f"`bench/spectral_daylit.py seeds {n} {d['quality']}` (bpy 5.0.1, the 2-core shared machine). The red room",
        "of `bench/spectral_room.md` (4 x 3 x 2.7 m, ColorChecker red walls, white 9.5 ceiling, neutral 8 floor)",
        "with a floor-to-ceiling opening (x 1.2-2.8 m) in wall y = 0 and no light: a uniform white world of",
        "strength 1 (683 cd/m²) with the default sky spectrum (CIE D65) lights it. Reference:",
        "`tests/spectral_radiosity.py` `solve_daylit` (5 nm; the opening a Lambertian emitter of the world's",
        "radiance; patches of 0.1 m, their change from 0.2 m counted as the reference's uncertainty).",
        "Meters: eye (3.2, 1.1, 1.2) m facing -x, desk (2.8, 2.2, 0.8) m facing up.",
        "",
        "Reference refinement, reflected part per cd/m² of world luminance (patch side m: E_v, mel-EDI lx): " + "; ".join(
            f"{m} {h}: {v['reflected']['illuminance_lx']:.5f}, {v['reflected']['mel_edi_lx']:.5f}"
            for m in refinement for h, v in sorted(refinement[m].items(), key=lambda kv: -float(kv[0]))) + ".",
        "",
        "| meter | quantity | reference (lx) | its discretisation (lx) | mean reading (lx) | mean s.e. (lx) | "
        "mean band bound (lx) | 95 % intervals covering |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for meter, e in d["meters"].items():
        rows, ref, disc = e["rows"], e["reference"], e["reference_discretisation"]
        mean = lambda k: sum(r[k] for r in rows) / len(rows)  # noqa: E731
        for key, q, label in (("ev", "illuminance_lx", "E_v"), ("mel", "mel_edi_lx", "mel-EDI")):
            lines.append(f"| {meter} | {label} total | {ref['total ' + q]:.1f} | {disc['total ' + q]:.2f} | "
                         f"{mean(key):.1f} | {mean(key + '_se'):.2f} | {mean(key + '_band'):.2f} | "
                         f"{e['covered_' + key]}/{len(rows)} |")
        lines.append(f"| {meter} | mel-EDI / E_v | {ref['total mel_edi_lx'] / ref['total illuminance_lx']:.4f} | | "
                     f"{mean('mel') / mean('ev'):.4f} | | | |")
    secs = [r["seconds"] for e in d["meters"].values() for r in e["rows"]]
    lines += ["", f"Time per reading (band renders, {d['quality']}): mean {sum(secs) / len(secs):.1f} s on the "
              "shared 2-core machine. The RGB-only estimate is not given where the world emits (its light has no "
              "one power to take the render's gain from)."]
    (HERE / "spectral_daylit.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    if sys.argv[1] == "reference":
        make_reference(fine="--fine" in sys.argv)
    elif sys.argv[1] == "md":
        write_md()
    else:
        run_seeds(int(sys.argv[2]), sys.argv[3] if len(sys.argv) > 3 else "preview")

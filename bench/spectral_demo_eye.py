"""Issue 35: the spectral reading at the demo camera's eye in the daylit demo room (demo/daylight.py: a south
window, sun D55 and the CIE clear sky at noon on the March equinox, London), N seeds of
``api.spectral_reading(reflected=True)`` at preview, the coverage of their 95 % intervals.

The eye: (0, 1.6, 1.2) m facing -y (the demo camera's position and view), a grey room (walls 0.6, floor 0.3),
so E_v needs no spectral model of the materials and mel-EDI = sum over sources of E_v(source) x its mel-DER.
Two rooms:

* ``open``: the pane hidden from renders (an open window). References: each source alone (sun: world black;
  sky: sun hidden) by ``tests/bpy/reference.py``'s patch renders, which share no code with Radiometer.
* ``glazed``: the 6 mm Glass BSDF pane as the demo builds it. A patch render cannot see the sun patch through
  a Glass BSDF (a caustic, docs/FACTS.md), so the references are Radiometer's photopic meter at standard
  quality, each source alone, pooled over 4 seeds: a cross-check of the band renders against the meter
  (whose glass is checked against patch renders of thin panes in bench/qa_glass_fog.md), not independent.

    PYTHONPATH=<dir holding radiometer> python bench/spectral_demo_eye.py N   # bench/spectral_demo_eye.{json,md}
"""

import json
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "tests" / "bpy")]
EYE = ((0.0, 1.6, 1.2), (0.0, -1.0, 0.0))


def _room(glazed):
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    import radiometer
    from radiometer.demo import daylight
    from radiometer.measure.authoring import sun as sun_light

    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = daylight.build(bpy.context.scene, glass=True, pane_renders=glazed)
    sun = sun_light.set_sun(scene, daylight.SITE["latitude_deg"], daylight.SITE["longitude_deg"],
                            daylight.local_time())
    daylight.set_clear_sky(scene, sun)
    return scene


def _alone(scene, source):
    """Hide the other source (render visibility / the world's strength); returns an undo callable."""
    sun = next(ob for ob in scene.objects if ob.type == "LIGHT")
    if source == "sun":
        world = scene.world
        scene.world = None
        return lambda: setattr(scene, "world", world)
    sun.hide_render = True
    return lambda: setattr(sun, "hide_render", False)


def references(scene, glazed):
    """E_v (lx) and its standard error at the eye, per source."""
    from radiometer import api

    out = {}
    for source in ("sun", "sky"):
        undo = _alone(scene, source)
        try:
            if glazed:
                vals = [api.measure_illuminance(*EYE, scene=scene, quality="standard", seed=1000 + 17 * k)
                        for k in range(4)]
                e = np.array([r.illuminance for r in vals])
                se = np.array([r.illuminance * r.rel_std_error for r in vals])
                w = 1.0 / se ** 2
                out[source] = {"E_v": float(np.sum(w * e) / np.sum(w)), "se": float(np.sqrt(1.0 / np.sum(w))),
                               "by": "photopic meter, standard, 4 seeds (inverse-variance mean)"}
            else:
                import reference

                rgb, rel, info = reference.reference_irradiance(scene, EYE[0], EYE[1], target_rel_error=2e-3,
                                                                max_seconds=240.0, seed=5)
                _y, lux = reference.luminance(rgb)
                out[source] = {"E_v": float(lux), "se": float(lux * rel), "by": "tests/bpy/reference.py patch render",
                               "seconds": info["seconds"]}
        finally:
            undo()
        print(source, out[source], flush=True)
    return out


def run(n, out=HERE):
    from radiometer import api

    summary = {"seeds": n, "quality": "preview", "rooms": {}}
    for room in ("open", "glazed"):
        scene = _room(room == "glazed")
        refs = references(scene, room == "glazed")
        sun = next(ob for ob in scene.objects if ob.type == "LIGHT")
        der = {"sun": api.spectrum_metrics(sun.data.get("radiometer_spectrum", "D55"))["mel_der"],
               "sky": api.spectrum_metrics(scene.world.get("radiometer_spectrum", "D65"))["mel_der"]}
        ev = sum(r["E_v"] for r in refs.values())
        mel = sum(refs[s]["E_v"] * der[s] for s in refs)
        se = float(np.hypot(*[r["se"] for r in refs.values()]))
        rows = []
        for seed in range(n):
            t0 = time.perf_counter()
            s = api.spectral_reading(*EYE, scene=scene, reflected=True, quality="preview", seed=seed)
            iv, im = s["interval_95"]["illuminance_lx"], s["interval_95"]["mel_edi_lx"]
            rows.append({"seed": seed, "seconds": time.perf_counter() - t0,
                         **{f"ev_{k}": iv[k] for k in ("estimate", "low_95", "high_95", "std_error", "band_bound")},
                         **{f"mel_{k}": im[k] for k in ("estimate", "low_95", "high_95", "std_error", "band_bound")}})
            print(room, seed, round(iv["estimate"], 1), round(im["estimate"], 1), flush=True)
        summary["rooms"][room] = {"references": refs, "mel_der": der, "E_v": ev, "E_v_se": se, "mel_edi": mel,
                                  "rows": rows}
        (out / "spectral_demo_eye.json").write_text(json.dumps(summary, indent=1) + "\n")
    write_md(out)
    return summary


def write_md(out=HERE):
    d = json.loads((out / "spectral_demo_eye.json").read_text())
    lines = ["# Issue 35: the spectral reading at the demo camera's eye", "",
             f"`bench/spectral_demo_eye.py {d['seeds']}` (bpy 5.0.1, the 2-core shared machine): the daylit demo room "
             "(sun D55 and the CIE clear sky at noon on the March equinox, London; grey walls 0.6 and floor 0.3), a "
             "vertical meter at the demo camera's position (0, 1.6, 1.2) m facing its view (-y), "
             f"`api.spectral_reading(reflected=True, quality=\"{d['quality']}\")` over seeds 0-{d['seeds'] - 1}. "
             "References per source, E_v (sun alone: world black; sky alone: sun hidden); mel-EDI = sum of each "
             "source's E_v x its mel-DER (exact for a grey room). z = (estimate - reference) / stated s.e.", "",
             "| room | reference by | E_v ref (lx) | mean E_v (lx) | mean s.e. | mean z, sd z | E_v covered | "
             "mel-EDI ref (lx) | mean mel-EDI | mel-EDI covered |", "|---|---|---|---|---|---|---|---|---|---|"]
    for room, e in d["rooms"].items():
        rows = e["rows"]
        z = np.array([(r["ev_estimate"] - e["E_v"]) / r["ev_std_error"] for r in rows])
        cov_ev = sum(r["ev_low_95"] <= e["E_v"] <= r["ev_high_95"] for r in rows)
        cov_mel = sum(r["mel_low_95"] <= e["mel_edi"] <= r["mel_high_95"] for r in rows)
        by = next(iter(e["references"].values()))["by"]
        lines.append(f"| {room} | {by} | {e['E_v']:.1f} ± {e['E_v_se']:.1f} | "
                     f"{np.mean([r['ev_estimate'] for r in rows]):.1f} | {np.mean([r['ev_std_error'] for r in rows]):.1f}"
                     f" | {z.mean():+.2f}, {z.std(ddof=1):.2f} | {cov_ev}/{len(rows)} | {e['mel_edi']:.1f} | "
                     f"{np.mean([r['mel_estimate'] for r in rows]):.1f} | {cov_mel}/{len(rows)} |")
    secs = [r["seconds"] for e in d["rooms"].values() for r in e["rows"]]
    lines += ["", "Per source (lx): " + "; ".join(
        f"{room} {s} {v['E_v']:.1f} ± {v['se']:.1f} (mel-DER {e['mel_der'][s]:.4f})"
        for room, e in d["rooms"].items() for s, v in e["references"].items()) + "."]
    pm = d["rooms"]["open"].get("photopic_meter")
    if pm:
        lines += ["", f"Radiometer's photopic meter in the open room (both sources, standard, {pm['seeds']} seeds, "
                  f"inverse-variance mean): {pm['E_v']:.1f} ± {pm['se']:.1f} lx, against the patch renders' "
                  f"{d['rooms']['open']['E_v']:.1f} lx: the band renders share the meter's offset, if any."]
    lines += [
"", f"Time per reading: mean {np.mean(secs):.1f} s. The first 6 seeds of the glazed room are the ones an "
        "earlier session took for a bias (estimates +0.6 to +5 %, 4 of 6 covering)."]
    (out / "spectral_demo_eye.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def bench_spectral_demo_eye(quick=False):
    """``make bench`` section (bench/run.py): 50 seeds and the photopic cross-check; quick: 3 seeds into a temporary
    folder (quick runs never overwrite results)."""
    import tempfile

    if quick:
        return run(3, pathlib.Path(tempfile.mkdtemp(prefix="radiometer-bench-")))
    run(50)
    photopic_open()
    return json.loads((HERE / "spectral_demo_eye.json").read_text())


def photopic_open(seeds=6):
    """Radiometer's photopic meter at standard in the open room (both sources), appended to the json: does the
    meter share the band renders' offset from the patch renders?"""
    from radiometer import api

    scene = _room(False)
    v = np.array([(r.illuminance, r.illuminance * r.rel_std_error) for r in
                  (api.measure_illuminance(*EYE, scene=scene, quality="standard", seed=500 + k) for k in range(seeds))])
    w = 1.0 / v[:, 1] ** 2
    d = json.loads((HERE / "spectral_demo_eye.json").read_text())
    d["rooms"]["open"]["photopic_meter"] = {"E_v": float(np.sum(w * v[:, 0]) / np.sum(w)),
                                            "se": float(np.sqrt(1.0 / np.sum(w))), "seeds": seeds}
    (HERE / "spectral_demo_eye.json").write_text(json.dumps(d, indent=1) + "\n")
    write_md()


if __name__ == "__main__":
    if sys.argv[1] == "md":
        write_md()
    elif sys.argv[1] == "photopic-open":
        photopic_open()
    else:
        run(int(sys.argv[1]))

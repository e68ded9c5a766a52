"""Issue 18 (F1 of bench/qa_glass_fog.md): coverage of the stated error for a wall meter lit by a metal
floor's glossy reflection of an area light (``glass_fog_unseen_scenes.glossy_wall``) at several floor
roughnesses, at ``preview``. Picks the roughness range of ``measure/meter/sample_floors.py``'s highlight floor
and measures it.

    .venv/bin/python bench/glossy_highlight_floor.py refs 0.3 0.5      # patch-render references (cached)
    .venv/bin/python bench/glossy_highlight_floor.py run 0.15 0.3 0.5 [--seeds 50] [--tag after]
    .venv/bin/python bench/glossy_highlight_floor.py refs 0.15 --floor principled   # a dielectric floor

``--light emissive`` replaces the area light by an emitting 0.5 m square mesh (Emission strength 250).
``--floor principled`` replaces the metal floor by a Principled BSDF (base colour 0.5, Metallic 0, IOR 1.5,
the given roughness): a polished stone or lacquered floor, whose highlight is the Fresnel reflection.

``--tag before`` runs with the highlight floor switched off (``sample_floors.highlight_floor`` patched
to find nothing): the code as F1 measured it.

References: ``tests/bpy/reference.py`` (a tiny white Lambertian patch seen by an orthographic Cycles
camera, E = pi x pixel; none of Radiometer's measurement code), target 0.2 %, seed 7, cached in
bench/glossy_highlight_floor.json with the readings (mean z, coverage within 1.96 and 3 combined s.e.).
Roughness 0.15 uses the QA's stored reference (tests/bpy/glass_fog_unseen_references.json).
"""

import json
import math
import pathlib
import sys
import time

import bpy

ROOT = pathlib.Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests" / "bpy"
OUT = ROOT / "bench" / "glossy_highlight_floor.json"


sys.path.insert(0, str(ROOT / "bench"))
from scenes import load_test_module as _load  # noqa: E402


u = _load("glass_fog_unseen_scenes")


FLOOR = ["metal"]
LIGHT = ["area"]


def _key(rough):
    key = f"{rough:g}" if FLOOR[0] == "metal" else f"{FLOOR[0]} {rough:g}"
    return key if LIGHT[0] == "area" else f"{LIGHT[0]} {key}"


def build(roughness):
    scene, [(label, point, normal)] = u.glossy_wall()
    if FLOOR[0] == "principled":
        u.principled_floor(roughness)
    else:
        mat = bpy.data.materials["metal floor 0.15"]
        [node] = [nd for nd in mat.node_tree.nodes if "Roughness" in nd.inputs]
        node.inputs["Roughness"].default_value = roughness
    if LIGHT[0] == "emissive":
        u.emitting_panel(scene)
    return scene, label, point, normal


def _data():
    return json.loads(OUT.read_text()) if OUT.exists() else {"references": {}, "runs": {}}


def refs(roughnesses):
    reference = _load("reference")
    data = _data()
    for rough in roughnesses:
        scene, label, point, normal = build(rough)
        at = reference.lift_off_surface(scene, point, normal)
        e_rgb, se, info = reference.reference_irradiance(scene, at, normal, target_rel_error=2e-3, max_seconds=240.0,
                                                         seed=7)
        data["references"][_key(rough)] = {"lux": u.lux(e_rgb), "rel_std_error": se, "samples": info.get("samples"),
                                            "seconds": round(info["seconds"], 1)}
        print(rough, data["references"][_key(rough)], flush=True)
        OUT.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


def run(roughnesses, seeds, tag, quality="preview"):
    import radiometer
    from radiometer import api

    if tag == "before":  # the code without the highlight floor (as bench/qa_glass_fog.md F1 measured it)
        from radiometer.measure.meter import sample_floors

        sample_floors.highlight_floor = lambda model, points_m, normals: (None, [])
    data = _data()
    stored = json.loads((TESTS / "glass_fog_unseen_references.json").read_text())["values"]
    for rough in roughnesses:
        if _key(rough) in data["references"]:
            ref = data["references"][_key(rough)]
            ref_lux, ref_se = ref["lux"], ref["rel_std_error"]
        else:
            assert rough == 0.15 and FLOOR[0] == "metal" and LIGHT[0] == "area", "make its reference first (refs)"
            e = stored["glossy_wall/wall meter lit via a glossy floor"]
            ref_lux, ref_se = u.lux(e["E_rgb"]), e["rel_std_error"]
        scene, label, point, normal = build(rough)
        radiometer.register()
        zs, samples, errs, t0 = [], [], [], time.perf_counter()
        try:
            for seed in range(seeds):
                r = api.measure_illuminance(point, normal, scene=scene, method="auto", quality=quality, seed=seed)
                err = r.illuminance / ref_lux - 1.0
                zs.append(err / math.hypot(r.rel_std_error, ref_se))
                samples.append(int(r.samples))
                errs.append(err)
        finally:
            radiometer.unregister()
        row = {"floor": FLOOR[0], "light": LIGHT[0], "roughness": rough, "quality": quality, "seeds": seeds, "ref_lux": ref_lux, "ref_se": ref_se,
               "within_1.96": sum(abs(z) <= 1.96 for z in zs), "within_3": sum(abs(z) <= 3 for z in zs),
               "mean_z": sum(zs) / seeds, "worst_z": max(zs, key=abs), "mean_err": sum(errs) / seeds,
               "worst_err": max(errs, key=abs), "samples_median": sorted(samples)[seeds // 2],
               "samples_min": min(samples), "seconds": round(time.perf_counter() - t0, 1)}
        data["runs"][f"{tag}/{quality}/{_key(rough)}"] = row
        print(json.dumps(row), flush=True)
        OUT.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    from scenes import pop_option

    args = sys.argv[1:]
    seeds, tag, quality = pop_option(args, "--seeds", 50, int), pop_option(args, "--tag", "before"), \
        pop_option(args, "--quality", "preview")
    FLOOR[0], LIGHT[0] = pop_option(args, "--floor", FLOOR[0]), pop_option(args, "--light", LIGHT[0])
    if args[0] == "refs":
        refs([float(a) for a in args[1:]])
    else:
        run([float(a) for a in args[1:]], seeds, tag, quality)

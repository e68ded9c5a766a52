"""Precompute the slow independent references of the realistic-scene tests into reference_values.json.

Run it from the repository root with the venv's Python (bpy as a module):

    .venv/bin/python tests/bpy/make_reference_values.py            # every stored case
    .venv/bin/python tests/bpy/make_reference_values.py window_room # one corpus scene

Like ``reference.py`` it imports nothing from Radiometer: the numbers come from the harness
(``reference.reference_irradiance``, a tiny white Lambertian patch seen by an orthographic Cycles camera)
on the scenes built by ``corpus.py``. Each entry records its provenance (harness, seed, target,
Blender version, date). ``test_realistic_scenes.py`` uses a stored value only when the stored case
point/normal still match the corpus (else it recomputes it live) and keeps a representative subset of
cases computed live on every run.

Two kinds of reference:
* ``full``: the scene as it is (the agreed reference);
* ``singles``: the sum of the scene's lights rendered ONE AT A TIME (every other light object
  ``hide_render``), used where Cycles' own full-scene estimate is measured to be biased by the mix of
  lights (light-tree selection with a non-uniformly scaled spot, MIS weights of a sheared area light;
  see the corpus docstrings). Light transport is linear in the lights, so the sum is what a consistent
  renderer converges to.
"""

import datetime
import importlib.util
import json
import math
import pathlib
import sys

import bpy

HERE = pathlib.Path(__file__).resolve().parent
JSON_PATH = HERE / "reference_values.json"
TARGET = 1e-3       # relative standard error of every stored reference (tolerance is >= 0.5 %)
SEED = 0
MAX_SECONDS = 240.0


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_rs_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")
corpus = _load("corpus")

#: (corpus scene, case label) -> kinds of reference stored. Only the slow ones are stored; the rest of
#: the corpus is computed live by the test.
STORED = {
    ("window_room", "floor in shade"): ("full",),
    ("window_room", "back wall"): ("full",),
    ("hidden_lights", "floor centre"): ("full", "singles"),
    ("hidden_lights", "facing wall"): ("full", "singles"),
    ("hidden_lights", "near negative"): ("full", "singles"),
    ("hidden_lights", "under no-diffuse"): ("full", "singles"),
    ("transformed_lights", "squashed spot, 0.9 m along x"): ("singles",),
    ("transformed_lights_sheared_mis_off", "squashed spot, 0.9 m along x"): ("singles",),
    ("transformed_lights", "under sheared"): ("singles",),
    ("transformed_lights", "under sheared, tilted"): ("singles",),
}


def case_scene(built, case):
    return bpy.data.scenes[case.scene_name] if case.scene_name else built["scene"]


def sensor_point(scene, case):
    """Where the reference patch sits: on-surface cases are lifted into free space (reference.py)."""
    return reference.lift_off_surface(scene, case.point, case.normal) if case.on_surface else tuple(case.point)


def full_reference(scene, case, target=TARGET, seed=SEED, max_seconds=MAX_SECONDS):
    """(E_Y W/m^2 SI, rel s.e., seconds) of the scene as it is."""
    e, rel, info = reference.reference_irradiance(scene, sensor_point(scene, case), case.normal,
                                                  target_rel_error=target, max_seconds=max_seconds, seed=seed)
    return reference.luminance(e)[0], rel, info["seconds"]


def singles_reference(scene, case, target=TARGET, seed=SEED, max_seconds=MAX_SECONDS):
    """Sum over the scene's light objects rendered one at a time: (E_Y, rel s.e., seconds, parts)."""
    lights = [ob for ob in scene.objects if ob.type == "LIGHT"]
    saved = {ob.name: ob.hide_render for ob in lights}
    total, var, seconds, parts = 0.0, 0.0, 0.0, {}
    try:
        for ob in lights:
            if saved[ob.name]:
                continue  # does not render anyway
            for other in lights:
                other.hide_render = saved[other.name] if other is ob else True
            e, rel, info = reference.reference_irradiance(scene, sensor_point(scene, case), case.normal,
                                                          target_rel_error=target, max_seconds=max_seconds,
                                                          seed=seed)
            y = reference.luminance(e)[0]
            parts[ob.name] = y
            total += y
            var += (rel * y) ** 2 if math.isfinite(rel) else 0.0
            seconds += info["seconds"]
    finally:
        for ob in lights:
            ob.hide_render = saved[ob.name]
    return total, (math.sqrt(var) / abs(total) if total else 0.0), seconds, parts


def compute(names=None):
    entries = []
    by_scene = {}
    for (scene_name, label), kinds in STORED.items():
        if names and scene_name not in names:
            continue
        by_scene.setdefault(scene_name, []).append((label, kinds))
    for scene_name, wanted in by_scene.items():
        built = corpus.BUILDERS[scene_name]()
        cases = {c.label: c for c in built["cases"]}
        for label, kinds in wanted:
            case = cases[label]
            scene = case_scene(built, case)
            entry = {"scene": scene_name, "case": label, "point": list(case.point), "normal": list(case.normal),
                     "on_surface": bool(case.on_surface)}
            if "full" in kinds:
                y, rel, s = full_reference(scene, case)
                entry["full"] = {"E": y, "rel_std_error": rel, "seconds": round(s, 2)}
            if "singles" in kinds:
                y, rel, s, parts = singles_reference(scene, case)
                entry["singles"] = {"E": y, "rel_std_error": rel, "seconds": round(s, 2), "parts": parts}
            print(json.dumps(entry), flush=True)
            entries.append(entry)
    return entries


def main(argv):
    names = set(argv) or None
    old = json.loads(JSON_PATH.read_text()) if JSON_PATH.exists() else {"values": []}
    new = compute(names)
    keep = [e for e in old.get("values", []) if names and e["scene"] not in names]
    data = {
        "provenance": {
            "harness": "tests/bpy/reference.py reference_irradiance (white Lambertian patch, orthographic "
                       "Cycles camera, E = pi x pixel, batch-means standard error); 'singles' = sum of the "
                       "lights rendered one at a time",
            "generator": "tests/bpy/make_reference_values.py",
            "seed": SEED, "target_rel_error": TARGET, "max_seconds": MAX_SECONDS,
            "blender": bpy.app.version_string, "device": "CPU",
            "date": datetime.date.today().isoformat(),
        },
        "values": keep + new,
    }
    JSON_PATH.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {len(data['values'])} values to {JSON_PATH}")


if __name__ == "__main__":
    main(sys.argv[1:])

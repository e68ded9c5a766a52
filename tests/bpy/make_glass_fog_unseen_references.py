"""Render the independent references of ``test_glass_fog_unseen.py`` (issue 18 acceptance on scenes
the corpus does not hold) into glass_fog_unseen_references.json.

    .venv/bin/python tests/bpy/make_glass_fog_unseen_references.py             # every rendered scene
    .venv/bin/python tests/bpy/make_glass_fog_unseen_references.py fog_cube    # some (merged in)

Numbers from ``reference.reference_irradiance`` (a tiny white Lambertian patch seen by an orthographic
Cycles camera, E = pi x pixel, standard error over pixels) on the scenes of
``glass_fog_unseen_scenes.RENDERED``, each patch lifted off its surface by ``reference.lift_off_surface``
(1e-6 m: a bias below 2e-5); nothing of Radiometer's measurement code runs. Each value keeps its own
relative standard error and sample count. The closed-form cases need no cache. The grey room behind
double glazing is rendered on ``REFERENCE_SCENES`` (the panes as one face of constant thin glass at the
sun's angle: the sun through real glass is a caustic no render finds).
"""

import datetime
import importlib.util
import json
import pathlib
import sys

import bpy

HERE = pathlib.Path(__file__).resolve().parent
JSON_PATH = HERE / "glass_fog_unseen_references.json"
TARGET = 1e-3
SEED = 7
MAX_SECONDS = 300.0


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_gfur_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(names):
    reference, scenes = _load("reference"), _load("glass_fog_unseen_scenes")
    data = json.loads(JSON_PATH.read_text()) if JSON_PATH.exists() else {"values": {}}
    data["provenance"] = {
        "harness": "tests/bpy/reference.py reference_irradiance (white Lambertian patch, orthographic Cycles "
                   "camera, E = pi x pixel, standard error over pixels)",
        "generator": "tests/bpy/make_glass_fog_unseen_references.py", "scenes": "tests/bpy/glass_fog_unseen_scenes.py",
        "seed": SEED, "target_rel_error": TARGET, "max_seconds": MAX_SECONDS,
        "blender": bpy.app.version_string, "device": "CPU", "date": datetime.date.today().isoformat()}
    for name in names or list(scenes.RENDERED):
        build = scenes.REFERENCE_SCENES.get(name, scenes.RENDERED[name][0])
        scene, cases = build()
        for label, point, normal in cases:
            at = reference.lift_off_surface(scene, point, normal)
            e_rgb, se, info = reference.reference_irradiance(scene, at, normal, target_rel_error=TARGET,
                                                             max_seconds=MAX_SECONDS, seed=SEED)
            data["values"][f"{name}/{label}"] = {"point": list(point), "normal": list(normal), "E_rgb": list(e_rgb),
                                                 "rel_std_error": se, "samples": info.get("samples"),
                                                 "seconds": round(info["seconds"], 1)}
            print(name, label, e_rgb, se, info["samples"], round(info["seconds"], 1), flush=True)
            JSON_PATH.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])

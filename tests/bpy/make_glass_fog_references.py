"""Render the slow independent references of ``test_glass_fog.py`` into glass_fog_references.json.

    .venv/bin/python tests/bpy/make_glass_fog_references.py            # every scene
    .venv/bin/python tests/bpy/make_glass_fog_references.py fog_point  # some scenes (merged in)

The numbers come from ``reference.reference_irradiance`` (a tiny white Lambertian patch seen by an
orthographic Cycles camera, E = pi x pixel, batch-means standard error) on the scenes that
``glass_fog_scenes.py`` builds; nothing of Radiometer's measurement code runs. A patch render in a
world volume costs minutes (every camera path crosses the medium), hence the cache.

The skylight room's reference is two renders added: ``window_room_sun`` (black sky, the pane as thin
glass at the sun's angle with T and R from the slab's closed form: every sun ray crosses it at that
angle) and ``window_room_sky`` (the sun hidden, the real Glass BSDF pane: a sky is a large source,
so Cycles converges through real refraction).

The frosted windows (``frosted_<light>_<roughness>``) are patch renders through the real rough Glass
BSDF: at roughness 0.3 they converge to 0.2 % in the time allowed; at 0.2 the point light's stops at
0.6 % (the rough lobe is a rarer path for the patch too); 0.1 is not cached (it does not converge).
"""

import datetime
import importlib.util
import json
import pathlib
import sys

import bpy

HERE = pathlib.Path(__file__).resolve().parent
JSON_PATH = HERE / "glass_fog_references.json"
TARGET = 2e-3
SEED = 0
MAX_SECONDS = 300.0


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_gf_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(names):
    reference, scenes = _load("reference"), _load("glass_fog_scenes")
    data = json.loads(JSON_PATH.read_text()) if JSON_PATH.exists() else {"values": {}}
    data["provenance"] = {
        "harness": "tests/bpy/reference.py reference_irradiance (white Lambertian patch, orthographic Cycles "
                   "camera, E = pi x pixel, batch-means standard error)",
        "generator": "tests/bpy/make_glass_fog_references.py", "scenes": "tests/bpy/glass_fog_scenes.py",
        "seed": SEED, "target_rel_error": TARGET, "max_seconds": MAX_SECONDS,
        "blender": bpy.app.version_string, "device": "CPU", "date": datetime.date.today().isoformat()}
    for name in names or list(scenes.SCENES):
        scene, cases = scenes.SCENES[name]()
        for label, point, normal in cases:
            # Meters on the floor: the patch sits just off the surface (reference.lift_off_surface).
            at = reference.lift_off_surface(scene, point, normal) if point[2] == 0.0 else point
            e_rgb, se, info = reference.reference_irradiance(scene, at, normal, target_rel_error=TARGET,
                                                             max_seconds=MAX_SECONDS, seed=SEED)
            data["values"][f"{name}/{label}"] = {"point": list(point), "normal": list(normal), "E_rgb": list(e_rgb),
                                                 "rel_std_error": se, "samples": info.get("samples")}
            print(name, label, e_rgb, se, flush=True)
            JSON_PATH.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])

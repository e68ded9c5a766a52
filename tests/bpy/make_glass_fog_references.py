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

import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import reference_cache  # noqa: E402

JSON_PATH = HERE / "glass_fog_references.json"
TARGET = 2e-3
SEED = 0
MAX_SECONDS = 300.0


def main(names):
    scenes = reference_cache.load("glass_fog_scenes")
    reference_cache.render_into(
        JSON_PATH, {name: scenes.SCENES[name] for name in names or list(scenes.SCENES)},
        generator="tests/bpy/make_glass_fog_references.py", scenes_file="tests/bpy/glass_fog_scenes.py",
        target=TARGET, seed=SEED, max_seconds=MAX_SECONDS,
        lift=lambda point: point[2] == 0.0)  # meters on the floor: the patch sits just off the surface


if __name__ == "__main__":
    main(sys.argv[1:])

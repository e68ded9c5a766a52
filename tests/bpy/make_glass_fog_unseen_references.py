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

import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import reference_cache  # noqa: E402

JSON_PATH = HERE / "glass_fog_unseen_references.json"
TARGET = 1e-3
SEED = 7
MAX_SECONDS = 300.0


def main(names):
    scenes = reference_cache.load("glass_fog_unseen_scenes")
    reference_cache.render_into(
        JSON_PATH, {name: scenes.REFERENCE_SCENES.get(name, scenes.RENDERED[name][0])
                    for name in names or list(scenes.RENDERED)},
        generator="tests/bpy/make_glass_fog_unseen_references.py",
        scenes_file="tests/bpy/glass_fog_unseen_scenes.py", target=TARGET, seed=SEED, max_seconds=MAX_SECONDS,
        error_kind="standard error over pixels")


if __name__ == "__main__":
    main(sys.argv[1:])

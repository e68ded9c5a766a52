"""Issue 30: one request per measurement, built once at the api and passed down.

Static checks of measure/ (Blender-free: the source is read, not imported): the scene's unit scale, its
view layer and its photometry are derived in one place (``measure/blender/request.py``; the capture keeps
its own copy of the scale in the scene model it builds), and no level below the api takes the scene together
with the caller's budget keywords again, except the cluster tasks, which run on a worker's copy of the scene
and carry plain values (they build their request there).
"""

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
MEASURE = ROOT / "measure"

#: Where the request is built, and the capture (it models the scene as Cycles renders it, scale included).
DERIVES = {"measure/blender/request.py"}
CAPTURE = "measure/capture/"

#: Cluster tasks: plain values in, their request built on the worker (radiometer.cluster.run_scene_tasks).
TASKS = {("measure/analyses/annual.py", "patch_coefficients"), ("measure/analyses/annual.py", "dome_task"),
         ("measure/analyses/sun_study.py", "sun_study_step"), ("measure/analyses/daylight_factor.py",
                                                                "daylight_factor_chunk"),
         ("measure/analyses/batch.py", "measure_file")}

#: Not a caller's budget under the same name: (module, function) -> why.
NOT_A_BUDGET = {
    ("measure/analyses/sky_component.py", "sky_components"):
        "target_rel_error: the resolved target (a number) that sizes a pane's bound; the scene: captured only "
        "when no model is given",
    ("measure/authoring/world.py", "render_mirror_ball"): "samples: the probe picture's samples per pixel",
}

#: The caller's keywords a request carries.
BUDGET = {"quality", "target_rel_error", "samples", "time_budget_s", "progress", "cancelled", "client"}

#: The rooms above the renderer: they take a request, never the scene with a budget.
ROOMS = ("measure/meter/", "measure/authoring/", "measure/analyses/", "measure/reports/")


def _modules():
    for path in sorted(MEASURE.rglob("*.py")):
        rel = path.relative_to(ROOT).as_posix()
        yield rel, path.read_text()


def test_the_scale_and_view_layer_are_derived_in_one_place():
    found = []
    for rel, text in _modules():
        if rel in DERIVES or rel.startswith(CAPTURE) or rel == "measure/blender/temporary_scene.py":
            continue  # (the temporary scene copies the user's scale: a write, not a reading)
        for k, line in enumerate(text.splitlines(), 1):
            code = line.split("#", 1)[0]
            if "unit_settings.scale_length" in code or "view_layers[0]" in code:
                found.append(f"{rel}:{k}: {line.strip()}")
    assert not found, "derive these from the request instead:\n" + "\n".join(found)


def test_the_photometry_is_read_in_one_place():
    found = [rel for rel, text in _modules()
             if rel not in DERIVES and ("scene_photometry" in text or "efficacy.of(" in text)]
    assert not found, found


def test_no_level_below_the_api_takes_the_scene_with_a_budget_again():
    found = []
    for rel, text in _modules():
        if not rel.startswith(ROOMS):
            continue
        for node in ast.walk(ast.parse(text)):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            names = {a.arg for a in node.args.args + node.args.kwonlyargs}
            if "scene" in names and names & BUDGET and (rel, node.name) not in TASKS | set(NOT_A_BUDGET):
                found.append(f"{rel}: {node.name}({', '.join(sorted(names & (BUDGET | {'scene'})))})")
    assert not found, "take a request (measure.blender.request) instead:\n" + "\n".join(found)


def test_the_checks_see_what_they_forbid():
    """The scans are not vacuous: the request module itself derives what the others may not."""
    text = (MEASURE / "blender" / "request.py").read_text()
    assert "unit_settings.scale_length" in text and "view_layers[0]" in text and "efficacy.of(" in text
    tasks = {(rel, node.name) for rel, text in _modules() if rel.startswith(ROOMS)
             for node in ast.walk(ast.parse(text)) if isinstance(node, ast.FunctionDef)}
    assert TASKS | set(NOT_A_BUDGET) <= tasks  # every allowed one still exists (a renamed one would leave a hole)

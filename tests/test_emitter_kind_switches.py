"""The Emitter is finished (issue 30): outside ``radiometry/emitters/`` at most 5 places ask a light for its
kind. Each kind's answer (size, luminous area seen from an eye, near field, mirror images, ...) lives in its
class; a caller asks the emitter, never ``spec.kind == "AREA"``.

A place is a source line that reads ``.kind`` of a light or emitter record (``spec.kind``, ``light.spec.kind``,
``lt.spec.kind``, ``emitter.kind``, ...) or asks ``hasattr``/``getattr`` for it, found in the syntax tree of
every module of the add-on but tests/ and radiometry/emitters/. An object reading its own field
(``self.kind``) is not a caller asking a light. Meters (``radiometer_meter.kind``), results (``result.kind``),
worlds and BRDF parameters are not lights.
"""

import ast
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
LIMIT = 5
#: Names a light or emitter goes by in the add-on; the record is the last name before ``.kind``.
LIGHT_NAMES = {"spec", "emitter", "light", "lt", "lamp", "source", "src"}
SKIP_DIRS = {"tests", ".venv", ".venv-lts", ".git", "__pycache__", "build", "dist"}


def _last_name(node):
    """The last identifier of an expression (``light.spec`` -> 'spec', ``lights[i]`` -> 'lights')."""
    while isinstance(node, (ast.Subscript, ast.Call)):
        node = node.value if isinstance(node, ast.Subscript) else node.func
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Name):
        return node.id
    return ""


def _is_light(node):
    name = _last_name(node).lower()
    return name in LIGHT_NAMES or name.endswith(("_spec", "_emitter"))


def kind_questions(source):
    """Line numbers where ``source`` asks a light for its kind."""
    lines = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Attribute) and node.attr == "kind" and _is_light(node.value):
            lines.add(node.lineno)
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("getattr", "hasattr")
              and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant) and node.args[1].value == "kind"
              and _is_light(node.args[0])):
            lines.add(node.lineno)
    return lines


def add_on_modules():
    """(path relative to the add-on's root, source) of every module but tests/ and radiometry/emitters/."""
    for folder, dirs, files in os.walk(ROOT):
        rel_dir = pathlib.Path(folder).relative_to(ROOT)
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith(".")
                         and (rel_dir / d).as_posix() != "radiometry/emitters")
        for name in sorted(f for f in files if f.endswith(".py")):
            yield (rel_dir / name).as_posix(), (pathlib.Path(folder) / name).read_text(encoding="utf-8")


def test_the_counter_sees_every_form_of_the_question():
    source = ("if spec.kind == 'AREA':\n    pass\n"                      # 1
              "x = light.spec.kind in ('POINT', 'SPOT')\n"                # 3
              "y = [lt for lt in lights if lt.spec.kind != 'SUN']\n"      # 4
              "z = hasattr(lt.spec, 'kind')\n"                            # 5
              "w = self.kind, result.kind, ob.radiometer_meter.kind, world.kind\n"  # 6: not lights
              "v = model.lights[0].spec.kind\n"                           # 7
              "u = getattr(area_spec, 'kind', None)\n")                   # 8
    assert kind_questions(source) == {1, 3, 4, 5, 7, 8}


def test_the_walk_covers_the_add_on_and_leaves_out_the_emitters():
    rels = {rel for rel, _src in add_on_modules()}
    assert "measure/analyses/glare.py" in rels and "radiometry/scene/scene_model.py" in rels
    assert not any(r.startswith(("radiometry/emitters/", "tests/")) for r in rels)


def test_at_most_five_places_outside_the_emitters_ask_a_light_for_its_kind():
    places = [f"{rel}:{line}" for rel, src in add_on_modules() for line in sorted(kind_questions(src))]
    print(f"{len(places)} place(s) ask a light for its kind: {places}")
    assert len(places) <= LIMIT, ("ask the emitter instead (radiometry/emitters/: one class per kind answers); "
                                  f"{len(places)} places: {places}")


@pytest.mark.parametrize("module", ["measure/analyses/glare.py", "measure/analyses/light_isolation.py",
                                    "measure/meter/sample_floors.py", "measure/meter/point_meter.py",
                                    "radiometry/scene/scene_model.py"])
def test_the_modules_that_switched_most_now_ask_the_emitter(module):
    """Those that held 22 of the 40 switches (issue 30) hold none."""
    assert not kind_questions((ROOT / module).read_text(encoding="utf-8"))

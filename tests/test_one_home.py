"""One home each (issue 17): K, the working colour space and its RGB->Y weights, the JSON/NaN policy.

Read statically over the package (tests, bench, tools and docs apart), so a new copy fails here.
"""

import ast
import json
import math
import os

import numpy as np
import pytest

from radiometer.outputs import json_safe

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOT_PACKAGE = {".git", ".venv", ".venv-lts", "tests", "bench", "tools", "docs", "out", "dist", ".ci", "__pycache__"}
REC709_Y = (0.2126, 0.7152, 0.0722)

#: Known copies not removed this session, with the owner and the date.
EXCEPTIONS = {
    ("rec709", "brdf/plots.py"): "2026-12-01: BRDF plots weigh RGB by Rec.709 (H5 owns brdf/plots.py)",
    ("rec709", "radiometry/skies/environment.py"): "2026-12-01: `brightest(weights=...)` default (H1 edits it)",
    ("rec709", "radiometry/skies/cie_sky.py"): "2026-12-01: `brightest(weights=...)` default, as environment.py (H4's "
                                         "new module)",
}


def _sources():
    for root, dirs, files in os.walk(REPO):
        dirs[:] = [d for d in dirs if d not in NOT_PACKAGE and not d.startswith(".")]
        for name in files:
            if name.endswith(".py"):
                path = os.path.join(root, name)
                yield os.path.relpath(path, REPO), ast.parse(open(path, encoding="utf-8").read())


def _findings():
    found = {}
    for rel, tree in _sources():
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and type(node.value) in (int, float) and node.value == 683:
                found.setdefault(("683", rel), node.lineno)
            if isinstance(node, (ast.Tuple, ast.List)) and len(node.elts) == 3 and all(
                    isinstance(e, ast.Constant) and isinstance(e.value, float) for e in node.elts) \
                    and tuple(e.value for e in node.elts) == REC709_Y:
                found.setdefault(("rec709", rel), node.lineno)
            if isinstance(node, ast.Attribute) and node.attr == "colorspace" and \
                    isinstance(node.value, ast.Attribute) and node.value.attr == "data":
                found.setdefault(("colorspace", rel), node.lineno)
    return found


def test_each_constant_has_one_home():
    found = _findings()
    homes = {("683", os.path.join("radiometry", "constants.py")), ("colorspace", "compat.py")}
    stray = {key: line for key, line in found.items() if key not in homes and key not in EXCEPTIONS}
    assert not stray, ("import K from radiometry.constants, the working space from compat.working_colour_space "
                       f"and the weights from radiometry.photometry.efficacy.luminance_weights: {stray}")
    stale = [key for key in EXCEPTIONS if key not in found]
    assert not stale, f"fixed, so delete from EXCEPTIONS: {stale}"


def test_json_policy_nan_and_inf_are_null_everywhere():
    class Result:
        def to_dict(self):
            return {"values": np.array([[1.0, np.nan], [np.inf, -np.inf]]), "n": np.int64(3)}

    value = {"a": np.float32(2.5), "b": (1, float("nan")), "c": Result(), "d": [np.bool_(True), None, "x"]}
    safe = json_safe(value)
    assert safe == {"a": 2.5, "b": [1, None], "c": {"values": [[1.0, None], [None, None]], "n": 3},
                    "d": [True, None, "x"]}
    json.dumps(safe, allow_nan=False)  # strict JSON


def test_cli_and_analyses_use_the_one_policy():
    pytest.importorskip("bpy")
    from radiometer.commands._io import json_text
    from radiometer.measure.analyses.analysis_common import plain

    value = {"E": np.array([1.0, math.nan]), "rows": [(math.inf, 2)]}
    assert json.loads(json_text(value)) == json_safe(value) == plain(value) == {"E": [1.0, None], "rows": [[None, 2]]}

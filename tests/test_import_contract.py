"""The import contract (issue 17): layers, no circles, no private names across packages.

A private name (``_x``) of another package is refused whether it is imported (``from m import _x``) or
read from an imported module (``m._x``). Read statically with ``ast`` over every ``.py`` file of the
package (tests, bench, tools and docs are not part of the extension), counting imports inside
functions too: a function-level import is still a dependency, it only hides a circle until the
function runs.

Layers, lowest first; a module may import its own layer and the layers below it, never above:

==========  ======================================================================================
core        pure Python + numpy: ``radiometry/``, ``brdf/``, ``errors``, ``quality``, ``readings``,
            ``outputs``, ``validation``, ``progress``. Never imports bpy, mathutils, bmesh, gpu, blf.
plots       pictures (matplotlib, lazily): ``plots/``, the one home for drawing a figure. Plain numbers
            in, a file out; imports only the core, never bpy.
host        Blender side: ``compat``, ``measure/``, ``shading/``, ``demo/``, ``cluster/``.
api         ``api``: the stable Python API over the host.
ui / cli    ``operators/``, ``panels/``, ``props/``, ``registration`` / ``cli``, ``commands/``,
            ``__main__``. Two peers on top: neither imports the other; subcommands never import
            ``cli`` (shared helpers belong in ``commands/_io.py``); ``props/`` never imports
            ``operators/`` or ``panels/``. Neither peer imports ``measure/``: they call the ``api``
            (issue 30), so the host can change behind one boundary with its argument checks.
==========  ======================================================================================

Why plots sit below the host (decided 2026-12-02, issue 17): ``plots/`` is pure like the core (it
never imports bpy: this test checks it), and the analyses promise their picture with their numbers
(``plot=`` paths on ``check_inverse_square``, the grid's isolux, the report's figures, in the api, the
operators and the CLI alike). Drawing above the host would mean every analysis returns half its
result and each of its three callers draws the rest, three copies of the same calls. So the analyses
(host) draw through ``plots/``, and ``plots/`` may use nothing above the core: a figure function takes
arrays and a path, never a scene, which keeps it testable without Blender. ``brdf/plots.py`` is the
BRDF library's own diagnostics (the library ships without the extension); the extension draws BRDFs
through ``plots/brdf.py``.

The package root (``__init__.py``) is the composition root: it imports the UI and the CLI inside
``register()`` and is exempt from the layers and from the circle check (edges to and from it are
left out), as Blender's extension entry point has to be.

Known violations that could not be fixed this session without restructuring files another engineer
was editing at the same time are listed in ``EXCEPTIONS`` with the date, the reason and the owner.
An exception that no longer occurs makes the test fail too, so the list only shrinks.
"""

import ast
import os

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOT_PACKAGE = {".git", ".venv", ".venv-lts", "tests", "bench", "tools", "docs", "out", "dist", ".ci",
               "__pycache__", ".pytest_cache"}
BLENDER_MODULES = {"bpy", "mathutils", "bmesh", "gpu", "gpu_extras", "blf", "bpy_extras", "_bpy", "idprop",
                   "bl_math", "bl_ui", "addon_utils", "aud", "freestyle", "imbuf"}

LAYER_OF_TOP = {
    "radiometry": "core", "brdf": "core", "errors": "core", "quality": "core", "readings": "core",
    "outputs": "core", "validation": "core", "progress": "core",
    "plots": "plots",
    "compat": "host", "measure": "host", "shading": "host", "demo": "host", "cluster": "host",
    "api": "api",
    "operators": "ui", "panels": "ui", "props": "ui", "registration": "ui",
    "cli": "cli", "commands": "cli", "__main__": "cli",
}
RANK = {"core": 0, "plots": 1, "host": 2, "api": 3, "ui": 4, "cli": 4}
# measure/'s rooms, left to right (issue 30): a room imports its own room and the rooms to its left, never
# one to its right; no module sits in measure/ outside a room.
MEASURE_ROOMS = ("blender", "capture", "render", "meter", "authoring", "analyses", "reports")
# Inside the UI layer: properties are data that operators and panels read, never the other way round.
FORBIDDEN_WITHIN = {("props", "operators"), ("props", "panels"), ("operators", "panels")}
PURE_LAYERS = {"core", "plots"}
# The UI and the CLI reach measure/ only through the api (issue 30): kind "api" below.
THROUGH_THE_API = {"ui", "cli"}
# Host code takes settings as arguments (issue 30): only the operators, the panels (and the api, which
# builds the request) read the UI's property groups; measure/ reads none (kind "props": an attribute
# of that name, or the name as a string, as in getattr(scene, "radiometer", None)).
PROPERTY_GROUPS = {"radiometer", "radiometer_meter", "radiometer_analysis", "radiometer_daylight", "radiometer_brdf"}

# (kind, importer, imported or None): the reason, dated. Kinds: "layer", "blender", "circle", "private",
# "room", "root", "api", "props".
# A circle is named by its sorted member modules joined with " <-> ".
_TODAY = "2026-12-01"
EXCEPTIONS = {
    ("blender", "outputs", "bpy"):
        "permanent: outputs.user_folder asks Blender for the extension's user folder inside a try, and falls "
        "back to a private temporary folder without bpy",
    ("root", "commands._io", "register"):
        "permanent: with bpy as a module nothing enables the add-on, so the CLI registers it through the "
        "extension's own entry point (the function Blender calls); the root imports the CLI only inside it",
}


# --- the module graph ---------------------------------------------------------------------------

def package_modules(repo=REPO):
    """{dotted module name relative to the package root ('' = root): (path, is_package)}."""
    modules = {}
    for root, dirs, files in os.walk(repo):
        dirs[:] = sorted(d for d in dirs if d not in NOT_PACKAGE and not d.startswith("."))
        if root != repo and not os.path.exists(os.path.join(root, "__init__.py")):
            dirs[:] = []
            continue
        for name in sorted(files):
            if not name.endswith(".py"):
                continue
            path = os.path.join(root, name)
            parts = os.path.relpath(path, repo)[:-3].split(os.sep)
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            modules[".".join(parts)] = (path, is_package)
    return modules


class Import:
    """One imported name: ``target`` a package module or ``None``; ``external`` the top-level name of an
    outside module; ``name`` the imported attribute when it is not a module (for the private-name rule)."""

    def __init__(self, target=None, external=None, name=None, line=0):
        self.target, self.external, self.name, self.line = target, external, name, line


def _imports_of(module, path, is_package, modules):
    tree = ast.parse(open(path, encoding="utf-8").read(), filename=path)
    found, bound = [], {}  # bound: local name -> package module it names
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                name = alias.name
                if name == "radiometer" or name.startswith("radiometer."):
                    found.append(Import(target=_nearest(name[len("radiometer."):], modules), line=node.lineno))
                else:
                    found.append(Import(external=name.split(".")[0], line=node.lineno))
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                source = node.module or ""
                if source != "radiometer" and not source.startswith("radiometer."):
                    found.append(Import(external=source.split(".")[0], line=node.lineno))
                    continue
                base = source[len("radiometer."):] if source != "radiometer" else ""
            else:
                parts = module.split(".") if module else []
                if not is_package:
                    parts = parts[:-1]
                parts = parts[:len(parts) - (node.level - 1)]
                base = ".".join(parts + ([node.module] if node.module else []))
            for alias in node.names:
                candidate = f"{base}.{alias.name}" if base else alias.name
                if candidate in modules:
                    found.append(Import(target=candidate, line=node.lineno))
                    bound[alias.asname or alias.name] = candidate
                else:
                    found.append(Import(target=_nearest(base, modules), name=alias.name, line=node.lineno))
    # ``from . import mod`` then ``mod._private``: a private name used across packages all the same.
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in bound:
            found.append(Import(target=bound[node.value.id], name=node.attr, line=node.lineno))
    return found


def _nearest(dotted, modules):
    parts = dotted.split(".") if dotted else []
    while parts and ".".join(parts) not in modules:
        parts.pop()
    return ".".join(parts)


def build_graph(repo=REPO):
    modules = package_modules(repo)
    return modules, {m: _imports_of(m, path, pkg, modules) for m, (path, pkg) in modules.items()}


def layer(module):
    return LAYER_OF_TOP.get(module.split(".")[0]) if module else None


def _package(module, modules):
    """The package a module lives in ('' for top-level modules; a package is its own)."""
    return module if modules[module][1] else module.rpartition(".")[0]


def violations(modules, graph):
    """Every breach of the contract as a set of (kind, importer, imported) keys (see EXCEPTIONS)."""
    found = set()
    for module, imports in graph.items():
        if not module:
            continue
        own = layer(module)
        for imp in imports:
            if imp.external is not None:
                if own in PURE_LAYERS and imp.external in BLENDER_MODULES:
                    found.add(("blender", module, imp.external))
                continue
            target = imp.target
            if target:
                other = layer(target)
                if own and other and other != own and (RANK[other] > RANK[own] or RANK[other] == RANK[own]):
                    found.add(("layer", module, target))
                if module.startswith("commands.") and target == "cli":
                    found.add(("layer", module, target))
                if (module.split(".")[0], target.split(".")[0]) in FORBIDDEN_WITHIN:
                    found.add(("layer", module, target))
                if own in THROUGH_THE_API and target.split(".")[0] == "measure":
                    found.add(("api", module, target))
            if target and module.startswith("measure.") and target.startswith("measure."):
                if _room_rank(target) > _room_rank(module):
                    found.add(("room", module, target))
            if target == "" and imp.name:  # a name of the root package: only its entry point may be used there
                found.add(("root", module, imp.name))
            if imp.name and imp.name.startswith("_") and not imp.name.startswith("__") \
                    and target and _package(target, modules) != _package(module, modules):
                found.add(("private", module, f"{target}.{imp.name}"))
    for members in circles(graph):
        found.add(("circle", " <-> ".join(sorted(members)), None))
    for module, (path, _is_package) in modules.items():
        if module.split(".")[0] == "measure":
            found.update(("props", module, name) for name in property_groups_read(path))
    return found


def property_groups_read(path):
    """The UI property groups a file touches: ``x.radiometer_meter`` or the name as a string."""
    tree = ast.parse(open(path, encoding="utf-8").read(), filename=path)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr in PROPERTY_GROUPS:
            names.add(node.attr)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in PROPERTY_GROUPS:
            names.add(node.value)
    return names


def _room_rank(module):
    parts = module.split(".")
    if len(parts) < 3 and not (len(parts) == 2 and parts[1] in MEASURE_ROOMS):
        return -1 if module == "measure" else len(MEASURE_ROOMS)  # a loose module: flagged by its own test
    return MEASURE_ROOMS.index(parts[1]) if parts[1] in MEASURE_ROOMS else len(MEASURE_ROOMS)


def circles(graph):
    """Strongly connected components of more than one module (Tarjan), root package left out."""
    edges = {m: sorted({i.target for i in imps if i.target and i.target != m}) for m, imps in graph.items() if m}
    edges = {m: [t for t in targets if t] for m, targets in edges.items()}
    index, low, stack, on_stack, result = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                result.append(component)

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return result


@pytest.fixture(scope="module")
def contract():
    modules, graph = build_graph()
    return modules, graph, violations(modules, graph)


# --- the contract -------------------------------------------------------------------------------

def test_every_top_level_module_has_a_layer(contract):
    modules, _graph, _found = contract
    unplaced = sorted({m.split(".")[0] for m in modules if m and layer(m) is None})
    assert not unplaced, f"add these to LAYER_OF_TOP in {__file__}: {unplaced}"


def test_no_new_violations(contract):
    _modules, _graph, found = contract
    new = sorted(found - set(EXCEPTIONS), key=str)
    assert not new, "import contract broken (fix the import, or move the function down a layer):\n" + \
        "\n".join(f"  {kind}: {a} -> {b}" for kind, a, b in new)


def test_exceptions_still_needed(contract):
    _modules, _graph, found = contract
    stale = sorted(set(EXCEPTIONS) - found, key=str)
    assert not stale, f"fixed, so delete from EXCEPTIONS: {stale}"


def test_exceptions_are_dated_or_permanent():
    for key, reason in EXCEPTIONS.items():
        assert reason.startswith(("permanent:", "20")), (key, reason)


# --- the checker itself: it finds what it claims to find ----------------------------------------

def _write(tmp_path, files):
    for rel, text in files.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return build_graph(str(tmp_path))


def test_checker_sees_function_level_circles_and_upward_imports(tmp_path):
    modules, graph = _write(tmp_path, {
        "__init__.py": "def register():\n    from . import operators\n",
        "radiometry/__init__.py": "",
        "radiometry/a.py": "def f():\n    from .b import g\n",
        "radiometry/b.py": "from radiometer.radiometry import a\nimport bpy\n",
        "measure/__init__.py": "",
        "measure/m.py": "from ..operators import x\nfrom ..radiometry.a import _hidden\nfrom ..radiometry import b\n"
                        "def f():\n    return b._inner, b.public\n",
        "operators/__init__.py": "",
        "operators/x.py": "import bpy\nfrom ..measure import m\n",
        "commands/__init__.py": "",
        "commands/c.py": "def run():\n    from ..cli import deliver\n",
        "cli.py": "from .commands import c\n",
    })
    found = violations(modules, graph)
    assert ("circle", "radiometry.a <-> radiometry.b", None) in found
    assert ("blender", "radiometry.b", "bpy") in found
    assert ("layer", "measure.m", "operators.x") in found
    assert ("private", "measure.m", "radiometry.a._hidden") in found
    assert ("private", "measure.m", "radiometry.b._inner") in found  # attribute of an imported module
    assert not any(key[2] == "radiometry.b.public" for key in found)
    assert ("layer", "commands.c", "cli") in found
    assert ("circle", "measure.m <-> operators.x", None) in found
    assert not any(kind == "blender" and a == "operators.x" for kind, a, _b in found)  # UI may use bpy
    assert not any("''" in str(key) or key[1] == "" for key in found)  # the root is the composition root


def test_checker_places_plots_between_core_and_host(tmp_path):
    modules, graph = _write(tmp_path, {
        "__init__.py": "",
        "radiometry/__init__.py": "",
        "radiometry/r.py": "",
        "plots/__init__.py": "",
        "plots/p.py": "from ..radiometry import r\nfrom ..measure import m\nimport bpy\n",
        "measure/__init__.py": "",
        "measure/m.py": "def draw():\n    from ..plots import p\n",
        "measure/n.py": "from ..plots.p import figure\n",
    })
    found = violations(modules, graph)
    assert ("layer", "plots.p", "measure.m") in found  # a figure takes numbers, never a scene
    assert ("blender", "plots.p", "bpy") in found
    assert not any(a.startswith("measure.") and kind == "layer" for kind, a, _b in found)  # host may draw
    assert not any(a == "plots.p" and b == "radiometry.r" for _kind, a, b in found)



def test_measure_is_named_rooms(contract):
    """measure/ holds only its rooms (issue 30): every module sits in one of ``MEASURE_ROOMS``."""
    modules, _graph, _found = contract
    loose = sorted(m for m in modules if m.startswith("measure.") and m.split(".")[1] not in MEASURE_ROOMS)
    assert not loose, f"put these in one of measure/'s rooms {MEASURE_ROOMS}: {loose}"
    rooms = sorted({m.split(".")[1] for m in modules if m.startswith("measure.")})
    assert len(rooms) <= 8, rooms


def test_no_folder_is_a_hall():
    """No package folder holds more than 16 Python files directly (issue 30)."""
    halls = {}
    for module, (path, _is_package) in package_modules().items():
        folder = os.path.relpath(os.path.dirname(path), REPO)
        halls[folder] = halls.get(folder, 0) + 1
    big = {folder: n for folder, n in halls.items() if n > 16 and folder != "."}
    assert not big, f"split these folders into named rooms: {big}"


def test_checker_sees_rooms_in_the_wrong_order(tmp_path):
    modules, graph = _write(tmp_path, {
        "__init__.py": "def register():\n    pass\n",
        "measure/__init__.py": "",
        "measure/capture/__init__.py": "",
        "measure/capture/c.py": "from ..meter import m\n",
        "measure/meter/__init__.py": "",
        "measure/meter/m.py": "from ..capture import c\n",
        "commands/__init__.py": "",
        "commands/k.py": "def run():\n    from .. import register\n",
    })
    found = violations(modules, graph)
    assert ("room", "measure.capture.c", "measure.meter.m") in found
    assert not any(kind == "room" and a == "measure.meter.m" for kind, a, _b in found)
    assert ("root", "commands.k", "register") in found


def test_every_package_folder_says_what_it_holds():
    """Each package folder has a README.md whose first line says what lives there (issue 17)."""
    modules = package_modules()
    folders = sorted({os.path.dirname(path) for m, (path, is_package) in modules.items() if m and is_package})
    missing = [os.path.relpath(f, REPO) for f in folders
               if not os.path.isfile(os.path.join(f, "README.md"))
               or not open(os.path.join(f, "README.md"), encoding="utf-8").readline().strip()]
    assert not missing, f"add a README.md (one line: what lives here) to {missing}"


def test_checker_sends_the_ui_and_the_cli_through_the_api(tmp_path):
    modules, graph = _write(tmp_path, {
        "__init__.py": "",
        "measure/__init__.py": "",
        "measure/meter/__init__.py": "",
        "measure/meter/m.py": "",
        "api.py": "def f():\n    from .measure.meter import m\n",
        "operators/__init__.py": "",
        "operators/o.py": "def run():\n    from ..measure.meter import m\n    from .. import api\n",
        "props/__init__.py": "",
        "props/p.py": "from ..measure.meter.m import x\n",
        "commands/__init__.py": "",
        "commands/c.py": "import radiometer.measure.meter.m\n",
        "cli.py": "from .measure import meter\n",
    })
    found = violations(modules, graph)
    assert ("api", "operators.o", "measure.meter.m") in found
    assert ("api", "props.p", "measure.meter.m") in found
    assert ("api", "commands.c", "measure.meter.m") in found
    assert ("api", "cli", "measure.meter") in found
    assert not any(a == "api" for _kind, a, _b in found)  # the api is where the host is called
    assert not any(b == "api" for _kind, _a, b in found)  # calling the api is the way


def test_checker_sees_property_groups_read_in_measure(tmp_path):
    modules, graph = _write(tmp_path, {
        "__init__.py": "",
        "measure/__init__.py": "",
        "measure/meter/__init__.py": "",
        "measure/meter/m.py": "def f(ob, scene):\n    return ob.radiometer_meter.kind, getattr(scene, 'radiometer')\n",
        "measure/meter/n.py": "def g(settings):\n    return settings['quality']  # radiometer settings as arguments\n",
        "operators/__init__.py": "",
        "operators/o.py": "def run(context):\n    return context.scene.radiometer.quality\n",
        "api.py": "def f(ob):\n    return ob.radiometer_meter.kind\n",
    })
    found = violations(modules, graph)
    assert ("props", "measure.meter.m", "radiometer_meter") in found
    assert ("props", "measure.meter.m", "radiometer") in found
    assert not any(kind == "props" and a in ("measure.meter.n", "operators.o", "api") for kind, a, _b in found)

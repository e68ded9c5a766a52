"""Safety (issue 6): nothing in the package evaluates text (no eval/exec/compile of strings that could
come from a .blend), CLI paths are validated with one-line errors, and measurements write files only
where the user asked (or under the extension's user folder / a cleaned-up temporary folder)."""

import ast
import os
import pathlib
import tempfile

import bpy
import pytest

import radiometer
from radiometer import api, cli

PACKAGE = pathlib.Path(radiometer.__file__).resolve().parent
EXCLUDED = {"tests", "bench", "tools", ".venv", ".venv-lts", "docs", "out", "dist", ".git"}
FORBIDDEN_CALLS = {"eval", "exec", "compile", "execfile", "__import__"}
FORBIDDEN_ATTRS = {"as_module", "execfile", "run_path", "run_module", "loads"}  # Text.as_module, runpy, pickle


def package_sources():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        if rel.parts[0] in EXCLUDED:
            continue
        yield rel, path.read_text(encoding="utf-8")


def test_package_has_python_files_to_check():
    names = {str(rel) for rel, _ in package_sources()}
    assert {"api.py", "cli.py", "measure/meter/point_meter.py", "operators/meter.py"} <= names


def test_no_eval_exec_or_text_execution_in_the_package():
    offenders = []
    for rel, source in package_sources():
        for node in ast.walk(ast.parse(source, filename=str(rel))):
            if not isinstance(node, ast.Call):
                continue
            func = node.func
            if isinstance(func, ast.Name) and func.id in FORBIDDEN_CALLS:
                literal = node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)
                if func.id == "__import__" and literal:
                    continue  # __import__("mathutils"): a fixed module name, not text from a file
                offenders.append(f"{rel}:{node.lineno} {func.id}()")
            elif isinstance(func, ast.Attribute) and func.attr in FORBIDDEN_ATTRS:
                base = func.value.id if isinstance(func.value, ast.Name) else ""
                if func.attr == "loads" and base in {"json", ""}:
                    continue  # json.loads parses data, it does not execute it
                offenders.append(f"{rel}:{node.lineno} .{func.attr}()")
    assert offenders == []


def test_the_check_would_catch_eval():
    tree = ast.parse("x = eval(obj.radiometer_meter.notes)")
    assert any(isinstance(n, ast.Call) and getattr(n.func, "id", None) == "eval" for n in ast.walk(tree))


def test_no_pickle_or_shell_in_the_package():
    offenders = []
    for rel, source in package_sources():
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                mods = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
                offenders += [f"{rel}:{node.lineno} import {m}" for m in mods if m.split(".")[0] in {"pickle", "marshal", "shelve"}]
            if isinstance(node, ast.keyword) and node.arg == "shell" and getattr(node.value, "value", False) is True:
                offenders.append(f"{rel}:{node.lineno} shell=True")
    assert offenders == []


@pytest.mark.parametrize("kind", ["missing", "directory", "not_blend"])
def test_cli_validates_blend_path(clean_blender, tmp_path, capsys, kind):
    path = {"missing": tmp_path / "nope.blend", "directory": tmp_path, "not_blend": tmp_path / "fake.blend"}[kind]
    if kind == "not_blend":
        path.write_text("import os; os.remove('/')  # not a .blend")
    code = cli.main(["measure", str(path)])
    err = capsys.readouterr().err.strip()
    assert code == cli.EXIT_BAD_INPUT
    assert err.startswith("radiometer: error:") and "\n" not in err and "Traceback" not in err


def test_cli_json_into_missing_folder_is_refused(clean_blender, build, tmp_path, capsys):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    blend = tmp_path / "s.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    code = cli.main(["measure", str(blend), "--json", str(tmp_path / "missing" / "r.json")])
    assert code == cli.EXIT_BAD_INPUT
    assert "does not exist" in capsys.readouterr().err
    assert not (tmp_path / "missing").exists()


def test_measurements_write_no_files_outside_temp(clean_blender, build, tmp_path, monkeypatch):
    """Readings of every kind write nothing in the working folder or next to the .blend; the only
    file a user gets is the radiance map at the path they gave; the temp folder ends empty."""
    work = tmp_path / "work"
    work.mkdir()
    private_tmp = tmp_path / "tmp"
    private_tmp.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(private_tmp))
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0, 0, 2), energy=30.0, size=0.5)
    build.plane(scene, size=4.0, albedo=0.5, name="floor")
    blend = tmp_path / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    files_before = sorted(os.listdir(tmp_path))
    api.measure_illuminance((0, 0, 0.5), method="render", quality="preview")
    api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
    target = tmp_path / "maps" / "m.exr"
    target.parent.mkdir()
    api.capture_radiance_map((0, 0, 1.0), str(target), resolution=8, quality="preview")
    assert list(work.iterdir()) == []
    assert list(private_tmp.iterdir()) == []
    assert sorted(os.listdir(tmp_path)) == sorted(files_before + ["maps"])
    assert [p.name for p in target.parent.iterdir()] == ["m.exr"]


def test_default_map_path_is_under_extension_user_dir_or_temp(clean_blender):
    from radiometer.measure.meter import camera

    path = pathlib.Path(camera.default_map_path("../../etc/passwd"))
    # The meter name cannot climb out of the folder: no separators or dots survive in the stem.
    assert "/" not in path.name and ".." not in path.name and path.name.startswith("etc_passwd")
    assert camera.default_map_path("Lamp.1") != camera.default_map_path("Lamp_1")
    allowed = [pathlib.Path(tempfile.gettempdir()).resolve()]
    try:
        allowed.append(pathlib.Path(bpy.utils.extension_path_user("radiometer")).resolve())
    except (ValueError, RuntimeError):
        pass
    assert any(path.resolve().is_relative_to(root) for root in allowed), path

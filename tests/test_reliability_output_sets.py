"""Issue 33, output sets: a set of files (a report's html/pdf/md/json and pictures) is replaced together
or not at all, its every target is checked before the work, implicit outputs (the PNG beside a
luminance EXR) join the "two outputs name one file" check, a signal after the outputs were written
says which, and a cancel never hides under a broader error.

The FileSet tests need no Blender; the CLI tests use the tiny scene of test_reliability_outputs
(a point light over a 'Work Plane'), refused before any render, or a 5 x 5 analytic grid.
"""

import ast
import hashlib
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from radiometer import outputs
from radiometer.errors import RadiometerError

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_reliability_outputs import blend, one_error_line, run_cli  # noqa: E402,F401  (blend: a fixture)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _state(folder):
    """Every entry of ``folder`` (hidden ones included) with its content's hash."""
    return {name: hashlib.sha1(open(os.path.join(folder, name), "rb").read()).hexdigest()
            if os.path.isfile(os.path.join(folder, name)) else "dir" for name in sorted(os.listdir(folder))}


def _write_set(folder, texts, manifest="m.json"):
    with outputs.FileSet(folder, manifest=manifest, name="set") as stage:
        for name, text in texts.items():
            outputs.write_text(stage.path(name), text)
        outputs.write_text(stage.path(manifest), json.dumps({"files": sorted([*texts, manifest])}))
        return stage.commit()


def test_file_set_replaced_together_and_stale_files_removed(tmp_path):
    _write_set(tmp_path, {"a.png": "old a", "b.csv": "old b", "keep.txt": "old keep"})
    (tmp_path / "user.txt").write_text("not ours")  # never listed: never touched
    done = _write_set(tmp_path, {"a.png": "new a", "keep.txt": "new keep"})
    assert os.path.basename(done[-1]) == "m.json"  # the manifest goes in last
    assert sorted(os.listdir(tmp_path)) == ["a.png", "keep.txt", "m.json", "user.txt"]  # b.csv was the old set's
    assert (tmp_path / "a.png").read_text() == "new a" and (tmp_path / "user.txt").read_text() == "not ours"


def test_file_set_left_without_commit_keeps_the_previous_set_and_no_temporary(tmp_path):
    _write_set(tmp_path, {"a.png": "old a", "b.csv": "old b"})
    before = _state(tmp_path)
    for error in (RadiometerError("cancelled"), KeyboardInterrupt()):
        with pytest.raises(type(error)), outputs.FileSet(tmp_path, manifest="m.json") as stage:
            outputs.write_text(stage.path("a.png"), "half of a new set")
            raise error
        assert _state(tmp_path) == before  # no staging folder, nothing replaced


def test_file_set_refuses_a_link_or_folder_target_before_moving_anything(tmp_path):
    _write_set(tmp_path, {"a.png": "old a", "b.csv": "old b"})
    (tmp_path / "z.html").mkdir()  # sorts last: a check per file while moving would have moved a and b
    before = _state(tmp_path)
    with pytest.raises(RadiometerError, match="z.html.*directory"):
        _write_set(tmp_path, {"a.png": "new a", "b.csv": "new b", "z.html": "new z"})
    assert _state(tmp_path) == before
    with pytest.raises(RadiometerError, match="symbolic link"):
        os.symlink("/etc/hostname", tmp_path / "c.pdf")
        outputs.check_set(str(tmp_path), ["a.png", "c.pdf"])


def test_file_set_finishes_the_renames_when_ctrl_c_arrives_halfway(tmp_path, monkeypatch):
    _write_set(tmp_path, {"a.png": "old a", "b.csv": "old b"})
    real, calls = os.replace, []

    def replace(src, dst):
        if os.path.dirname(dst) == str(tmp_path):  # the commit's renames, not the staged files' writes
            calls.append(dst)
        if len(calls) == 2 and not os.path.exists(dst + ".interrupted"):  # Ctrl-C (a KeyboardInterrupt in an API user's script) between two renames
            open(dst + ".interrupted", "w").close()  # once
            raise KeyboardInterrupt
        return real(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(KeyboardInterrupt):
        _write_set(tmp_path, {"a.png": "new a", "b.csv": "new b"})
    monkeypatch.undo()
    assert (tmp_path / "a.png").read_text() == "new a" and (tmp_path / "b.csv").read_text() == "new b"
    os.unlink(calls[1] + ".interrupted")
    assert sorted(os.listdir(tmp_path)) == ["a.png", "b.csv", "m.json"]


def test_every_exit_removes_staging_folders_and_temporary_files(tmp_path):
    # The CLI's watchdog ends the process with os._exit after remove_private_roots(): a staging folder
    # or a writer's temporary file beside its target (the 0-byte .report.*.tmp.pdf of issue 33) goes too.
    stage = outputs.FileSet(tmp_path, manifest="m.json").__enter__()
    outputs.write_text(stage.path("a.png"), "half")
    with outputs.atomic_output(str(tmp_path / "report.pdf")) as tmp:
        assert os.path.dirname(tmp) == str(tmp_path) and os.path.exists(tmp)
        outputs.remove_private_roots()  # what the watchdog runs, in the middle of a write
        assert os.listdir(tmp_path) == []
        open(tmp, "wb").write(b"%PDF-")  # the writer goes on (it is not told); its file is then put in place
    assert os.listdir(tmp_path) == ["report.pdf"]


def test_written_files_are_recorded_for_the_stop_message(tmp_path):
    from radiometer.commands import _io

    outputs.written.clear()
    assert "no result file was written" in _io.stop_message(signal.SIGINT)
    outputs.write_text(str(tmp_path / "a.csv"), "x\n")
    _write_set(tmp_path / "", {"b.png": "b"})
    line = _io.stop_message(signal.SIGINT)
    assert "wrote" in line and "a.csv" in line and "b.png" in line and "m.json" in line and "\n" not in line
    assert ".set.staging" not in line  # a file in a staging folder is not written yet
    outputs.write_text(os.path.join(outputs.private_temp_root(), "scratch.exr"), "x")
    assert "scratch.exr" not in _io.stop_message(signal.SIGINT)  # removed at exit: not a result
    outputs.written.clear()


def test_no_cancel_is_caught_under_a_broader_radiometer_error():
    # Static: a try whose body passes `cancelled=` on (a measurement that can raise MeasurementCancelled)
    # and catches RadiometerError must let MeasurementCancelled through first (issue 33: the report's
    # picture caught it, so a cancelled report went on and replaced report.html alone).
    found = []
    for root, dirs, files in os.walk(REPO):
        dirs[:] = [d for d in dirs if d not in {"tests", "bench", "tools", "docs", ".venv", ".venv-lts", "__pycache__"}
                   and not d.startswith(".")]
        for name in (f for f in files if f.endswith(".py")):
            path = os.path.join(root, name)
            for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
                if not isinstance(node, ast.Try):
                    continue
                cancellable = any(isinstance(n, ast.keyword) and n.arg == "cancelled" for stmt in node.body
                                  for n in ast.walk(stmt))
                caught = [ast.unparse(h.type) if h.type is not None else "BaseException" for h in node.handlers]
                broad = next((i for i, c in enumerate(caught)
                              if any(w in c for w in ("RadiometerError", "Exception"))), None)
                first_cancel = next((i for i, c in enumerate(caught) if "MeasurementCancelled" in c), None)
                if cancellable and broad is not None and (first_cancel is None or first_cancel > broad):
                    found.append(f"{os.path.relpath(path, REPO)}:{node.lineno}")
    assert not found, f"MeasurementCancelled caught by a broader handler at {found}"


# --- the CLI: implicit outputs and every target checked before the work -----------------------------

def test_png_beside_the_luminance_exr_and_json_of_the_same_name_refused(blend, tmp_path):
    # Issue 33: `glare --luminance-image v.exr --json v.png`: the PNG written beside the EXR and the JSON
    # overwrote each other silently. Now one line, before the scene is rendered.
    started = time.monotonic()
    out = run_cli("glare", blend, "--luminance-image", tmp_path / "v.exr", "--json", tmp_path / "v.png")
    one_error_line(out, "--json and the PNG beside --luminance-image name the same file")
    assert os.listdir(tmp_path) == [] and time.monotonic() - started < 60


@pytest.mark.parametrize("args, line", [
    (["--max-samples", "8"], "--max-samples must be 16-1024 samples per pixel, got 8"),
    (["--time-budget", "0"], "--time-budget must be a number of seconds > 0, got 0"),
    (["--time-budget", "nan"], "--time-budget must be a number of seconds > 0, got nan"),
])
def test_glare_picture_bounds_refused_in_one_line(blend, tmp_path, args, line):
    # Issue 31: the glare picture takes the report's caps (--max-samples, --time-budget); nonsense is one line
    # before any render, and nothing is written.
    out = run_cli("glare", blend, "--luminance-image", tmp_path / "v.exr", *args)
    one_error_line(out, line)
    assert os.listdir(tmp_path) == []


def test_report_targets_checked_before_any_work(blend, tmp_path):
    # Issue 33: a report.html that is a folder (or a symlink) was refused only after 20 s of work and
    # after the PNG/CSV/EXR files had been written. Now one line before the scene is measured, for
    # the fixed files and for the pictures, whose names come from the scene.
    report = tmp_path / "r"
    report.mkdir()
    (report / "report.html").mkdir()
    one_error_line(run_cli("report", blend, "--out", report), "report.html")
    assert os.listdir(report) == ["report.html"]
    (report / "report.html").rmdir()
    os.symlink("/etc/hostname", report / "report.pdf")
    one_error_line(run_cli("report", blend, "--out", report), "symbolic link")
    os.unlink(report / "report.pdf")
    (report / "isolux_work_plane.png").mkdir()  # a picture's name: known once the scene is open
    started = time.monotonic()
    one_error_line(run_cli("report", blend, "--out", report, "--quality", "preview"), "isolux_work_plane.png")
    assert os.listdir(report) == ["isolux_work_plane.png"] and time.monotonic() - started < 60
    one_error_line(run_cli("report", blend, "--out", report, "--json", report / "report.json"), "same file")


def test_signal_after_the_outputs_were_written_names_them(blend, tmp_path):
    # Issue 33: a signal arriving after `annual` wrote its outputs exited 130 "saying nothing was
    # written". Made deterministic: SIGINT is sent by the process to itself right after the grid's
    # first file is complete (inside the run): exit 130, one line naming every file written.
    csv, js = tmp_path / "g.csv", tmp_path / "g.json"
    code = ("import os, signal, sys\n"
            "from radiometer import outputs\n"
            "real = outputs.write_bytes\n"
            "def write_bytes(path, data):\n"
            "    done = real(path, data)\n"
            "    os.kill(os.getpid(), signal.SIGINT)\n"
            "    return done\n"
            "outputs.write_bytes = write_bytes\n"
            "from radiometer.cli import main\n"
            f"sys.exit(main(['grid', {blend!r}, '--plane', 'Work Plane', '--resolution', '3', '3', '--method', "
            f"'analytic', '--csv', {str(csv)!r}, '--json', {str(js)!r}]))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd="/", timeout=300)
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert out.returncode == 130, out.stderr
    assert len(lines) == 1 and "Ctrl-C" in lines[0] and "wrote" in lines[0], out.stderr
    assert csv.exists() and str(csv) in lines[0], out.stderr  # (grid delivers --json before the CSV)
    assert all(str(p) in lines[0] for p in (csv, js) if p.exists()), out.stderr


# --- a real Ctrl-C during `report` -----------------------------------------------------------------

CAMERA = ("cam = bpy.data.objects.new('cam', bpy.data.cameras.new('cam')); cam.location = (0, -3, 1.5); "
          "cam.rotation_euler = (1.1, 0, 0); s.collection.objects.link(cam); s.camera = cam\n"
          "s.render.resolution_x, s.render.resolution_y = 32, 24\n")


@pytest.fixture(scope="module")
def camera_blend(tmp_path_factory):
    pytest.importorskip("bpy")
    from test_reliability_outputs import SCENE

    path = str(tmp_path_factory.mktemp("report_set") / "room.blend")
    code = SCENE.format(path=path, with_map=False).replace("bpy.ops.wm.save_as_mainfile", CAMERA +
                                                           "bpy.ops.wm.save_as_mainfile")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, timeout=300)
    return path


@pytest.mark.slow
def test_ctrl_c_during_report_leaves_the_previous_set_or_the_new_one_whole(camera_blend, tmp_path):
    # Acceptance of issue 33: Ctrl-C at any second of `report` leaves the previous report set intact,
    # or the new one whole, and no temporary file. The runs take ~8-15 s here; SIGINT at 1.5 s
    # (start-up), 4 s and 7 s (measuring, the picture) and 10 s (the client report or after), in
    # parallel processes, each on its own copy of a finished previous set.
    import shutil

    pytest.importorskip("matplotlib")
    first = tmp_path / "first"
    done = run_cli("report", camera_blend, "--out", first, "--quality", "preview", "--no-convergence",
                   "--project", "first")
    assert done.returncode == 0, done.stderr
    previous = _state(first)
    assert json.loads((first / "report.json").read_text())["files"] == sorted(previous)
    env = dict(os.environ, TMPDIR=str(tmp_path))
    runs = {}
    for delay in (1.5, 4.0, 7.0, 10.0):
        folder = tmp_path / f"at{delay}"
        shutil.copytree(first, folder)
        runs[delay] = (folder, subprocess.Popen(
            [sys.executable, "-m", "radiometer", "report", camera_blend, "--out", str(folder), "--quality", "preview",
             "--no-convergence", "--project", "second"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
            cwd="/", env=env))
    started, outcomes = time.monotonic(), []
    for delay, (folder, proc) in sorted(runs.items()):
        time.sleep(max(0.0, started + delay - time.monotonic()))
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
    for delay, (folder, proc) in sorted(runs.items()):
        _, stderr = proc.communicate(timeout=300)
        assert proc.returncode in (0, 130), (delay, proc.returncode, stderr)
        assert "Traceback" not in stderr, stderr
        now = _state(folder)
        assert not [n for n in now if n.startswith(".")], (delay, now)  # no staging folder, no .tmp file
        if now == previous:
            outcomes.append("previous")
            assert proc.returncode == 130 and len([ln for ln in stderr.splitlines() if ln.strip()]) == 1, stderr
            continue
        listed = json.loads((folder / "report.json").read_text())["files"]
        assert listed == sorted(now), (delay, listed, now)  # the new set, whole
        assert all(now[n] != previous[n] for n in ("report.json", "report.html", "report.md")), delay
        outcomes.append("new")
    assert "previous" in outcomes, outcomes  # at least one run was really cut short
    assert not [n for n in os.listdir(tmp_path) if n.startswith(("radiometer-", "blender"))]  # scratch gone


def test_check_plots_targets_checked_before_the_checks(blend, tmp_path):
    # `check --plots DIR` writes a plot per light and law: a target that is a folder was found only
    # after the checks had run and the JSON was written; now one line before, nothing written.
    plots = tmp_path / "plots"
    plots.mkdir()
    (plots / "cosine_lamp.png").mkdir()
    out = run_cli("check", blend, "--plots", plots, "--json", tmp_path / "c.json")
    one_error_line(out, "cosine_lamp.png")
    assert not (tmp_path / "c.json").exists() and os.listdir(plots) == ["cosine_lamp.png"]
    (plots / "cosine_lamp.png").rmdir()
    one_error_line(run_cli("check", blend, "--plots", plots, "--json", plots / "inverse_square_lamp.png"),
                   "same file")


def test_staging_folder_of_a_killed_process_is_removed_by_the_next_set(tmp_path):
    # SIGKILL leaves a staging folder (nothing runs to remove it); the next set into that folder removes
    # it, and leaves a running process's own alone.
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    orphan = tmp_path / f".set.staging-{dead.pid}-abc"
    orphan.mkdir()
    (orphan / "a.png").write_text("half")
    alive = tmp_path / f".set.staging-{os.getppid()}-def"  # pytest's parent: running
    alive.mkdir()
    _write_set(tmp_path, {"a.png": "new"})
    assert sorted(os.listdir(tmp_path)) == sorted(["a.png", "m.json", alive.name])

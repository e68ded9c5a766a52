"""CLI: --help lists subcommands; bad input gives one line and a non-zero exit, no traceback."""

import os
import subprocess
import sys

import pytest


def run_cli(*args, cwd="/"):
    return subprocess.run([sys.executable, "-m", "radiometer", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=300)


def test_help_lists_subcommands():
    out = run_cli("--help")
    assert out.returncode == 0
    for name in ("demo", "measure"):
        assert name in out.stdout


@pytest.mark.parametrize("args, fragment", [
    (("frobnicate",), "invalid choice"),
    (("measure", "/nonexistent/scene.blend"), "no such file"),
    (("measure", "--bogus-option"), "unrecognized arguments"),
])
@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_bad_input_is_one_line_and_nonzero(args, fragment):
    out = run_cli(*args)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    lines = [line for line in out.stderr.splitlines() if line.startswith("radiometer: error")]
    assert len(lines) == 1 and fragment in lines[0], out.stderr


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_not_a_blend_file(tmp_path):
    fake = tmp_path / "scene.blend"
    fake.write_text("this is not a blend file")
    out = run_cli("measure", str(fake))
    assert out.returncode == 2 and "not a .blend file" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_corrupt_blend_file(tmp_path):
    fake = tmp_path / "scene.blend"
    fake.write_bytes(b"BLENDER-v500" + os.urandom(200))
    out = run_cli("measure", str(fake))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert out.stderr.startswith("radiometer: error"), out.stderr


# --- Quiet, robust command line (issue 13) ----------------------------------------------------------

import json  # noqa: E402
import signal  # noqa: E402
import time  # noqa: E402

BLENDER_LOG_FRAGMENTS = ("Info:", "Baking map saved", "Saved:", "Read blend", "CUEW", "Warning:")

_BUILD_SCENE = r"""
import sys, bpy, radiometer
sys.path.insert(0, {tests!r})
from conftest import make_black_world, add_light, add_plane
bpy.ops.wm.read_factory_settings(use_empty=True)
radiometer.register()
s = bpy.context.scene
make_black_world(s)
add_light(s, "AREA", (0, 0, 2), energy=100.0, size=0.5)
add_plane(s, size=4, location=(0, 0, 0), name="Work Plane")
add_plane(s, size=4, location=(0, 0, 3), rotation=(3.14159, 0, 0), name="Ceiling")
bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
bpy.context.active_object.location = (0.3, 0, 0.5)
s.radiometer.method = "render"
bpy.ops.wm.save_as_mainfile(filepath={path!r})
"""


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    """A small lit room whose meter is measured by a Cycles bake (so Blender prints its log lines)."""
    pytest.importorskip("bpy")
    path = str(tmp_path_factory.mktemp("room") / "room.blend")
    tests = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bpy")
    subprocess.run([sys.executable, "-c", _BUILD_SCENE.format(tests=tests, path=path)], check=True,
                   capture_output=True, timeout=300)
    return path


def _one_error_line(out, fragment):
    assert out.returncode == 2, (out.returncode, out.stderr)
    assert "Traceback" not in out.stderr
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("radiometer: error") and fragment in lines[0], out.stderr


def test_version():
    out = run_cli("--version")
    assert out.returncode == 0 and out.stdout.startswith("radiometer ") and out.stdout.split()[1][0].isdigit()


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_stdout_has_results_and_no_blender_log_lines(room, tmp_path):
    out = run_cli("measure", room, "--json", str(tmp_path / "r.json"))
    assert out.returncode == 0, out.stderr
    assert "Illuminance Meter" in out.stdout and " lx " in out.stdout
    for fragment in BLENDER_LOG_FRAGMENTS:
        assert fragment not in out.stdout and fragment not in out.stderr, (fragment, out.stdout, out.stderr)
    assert out.stderr == ""  # not a terminal: no progress line either
    assert json.loads((tmp_path / "r.json").read_text())["meters"][0]["method"] == "render"


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_verbose_shows_blender_log_lines_quiet_shows_nothing(room, tmp_path):
    verbose = run_cli("measure", room, "--verbose")
    assert verbose.returncode == 0
    assert "Baking map saved" in verbose.stdout + verbose.stderr  # the lines exist: the default hides them
    quiet = run_cli("--quiet", "measure", room, "--json", str(tmp_path / "q.json"))
    assert quiet.returncode == 0 and quiet.stdout == "" and quiet.stderr == ""
    assert json.loads((tmp_path / "q.json").read_text())["meters"]
    also = run_cli("measure", room, "-q")  # after the subcommand too
    assert also.returncode == 0 and also.stdout == ""


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_unwritable_json_is_one_line_before_the_run(room, tmp_path):
    _one_error_line(run_cli("measure", room, "--json", str(tmp_path / "missing" / "r.json")), "does not exist")
    _one_error_line(run_cli("measure", room, "--json", str(tmp_path)), "is a directory")
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    _one_error_line(run_cli("measure", room, "--json", str(blocker / "r.json")), "cannot write")


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_full_disk_is_one_line_after_the_results(room):
    # /dev/full accepts open() and fails every write with ENOSPC, like a full disk.
    out = run_cli("measure", room, "--json", "/dev/full")
    _one_error_line(out, "No space left on device")
    assert "Illuminance Meter" in out.stdout  # the results were printed before the file failed


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_unwritable_grid_outputs(room, tmp_path):
    _one_error_line(run_cli("grid", room, "--resolution", "2", "2", "--csv", str(tmp_path / "no" / "g.csv")),
                    "--csv file")
    _one_error_line(run_cli("grid", room, "--resolution", "2", "2", "--png", str(tmp_path)), "is a directory")


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_unwritable_plot_and_out_folders(room, tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    _one_error_line(run_cli("check", room, "--plots", str(blocker)), "--plots folder")
    _one_error_line(run_cli("report", room, "--out", str(blocker / "sub")), "--out folder")
    _one_error_line(run_cli("demo", "--out", str(blocker)), "--out folder")
    assert blocker.read_text() == "x"


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_grid_writes_json_before_csv_and_png(room, tmp_path):
    out = run_cli("grid", room, "--resolution", "3", "3", "--json", str(tmp_path / "g.json"),
                  "--csv", str(tmp_path / "g.csv"), "--png", str(tmp_path / "g.png"))
    assert out.returncode == 0, out.stderr
    data = json.loads((tmp_path / "g.json").read_text())
    assert data["nx"] == 3 and data["csv"] == str(tmp_path / "g.csv") and data["image"] == str(tmp_path / "g.png")
    assert (tmp_path / "g.csv").exists() and (tmp_path / "g.png").exists()


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_brdf_plot_into_a_folder_or_without_extension(tmp_path):
    pytest.importorskip("matplotlib")
    out = run_cli("brdf", "lambert", "--plot", str(tmp_path))
    assert out.returncode == 0, out.stderr
    expected = tmp_path / "brdf_lambert.png"
    assert expected.exists() and f"plot written to {expected}" in out.stdout
    out = run_cli("brdf", "lambert", "--plot", str(tmp_path / "lobe"), "--json", str(tmp_path / "b.json"))
    assert out.returncode == 0 and (tmp_path / "lobe.png").exists() and not (tmp_path / "lobe").exists()
    assert json.loads((tmp_path / "b.json").read_text())["plot"] == str(tmp_path / "lobe.png")


def _interrupt_during(args, tmp_path, wait_for, delay, json_file=True):
    """Start the CLI, wait until ``wait_for`` is printed, let it run ``delay`` s more, send SIGINT."""
    old = tmp_path / "old.json"
    old.write_text("previous result\n")
    extra = ["--json", str(old)] if json_file else []
    proc = subprocess.Popen([sys.executable, "-m", "radiometer", *args, "--verbose", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=str(tmp_path))
    seen = []
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if not line:
            break
        seen.append(line)
        if wait_for in line:
            break
    assert any(wait_for in line for line in seen), "".join(seen)
    time.sleep(delay)
    assert proc.poll() is None, "finished before the interrupt: the test scene is too quick"
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    rest, _ = proc.communicate(timeout=60)
    waited = time.monotonic() - sent
    assert proc.returncode == 130, "".join(seen) + rest
    assert waited < 20, waited
    assert old.read_text() == "previous result\n"  # the JSON file is untouched
    assert "radiometer: interrupted" in rest and "Traceback" not in rest
    return rest


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_ctrl_c_during_a_long_bake_exits_130(room, tmp_path):
    # One time-budgeted round is a single ~60 s bake: Cycles swallows the KeyboardInterrupt inside
    # it, the measurement cannot poll, so the watchdog ends the run a few seconds after Ctrl-C.
    _interrupt_during(["grid", room, "--method", "render", "--resolution", "30", "30", "--target", "0.00001",
                       "--time-budget", "60"], tmp_path, wait_for="Read blend", delay=3.0)


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_ctrl_c_during_the_demo_exits_130(tmp_path):
    # The demo writes demo.json as soon as its meters are measured, then runs the report: whatever
    # the moment of the interrupt, every file there is whole (no half-written JSON, no temp file).
    pytest.importorskip("bpy")
    # Reference quality: the demo got fast (~4 s in all), so it must still be working when the
    # interrupt arrives half a second after its first line.
    _interrupt_during(["demo", "--out", str(tmp_path / "out"), "--quality", "reference"], tmp_path,
                      wait_for="Radiometer demo:", delay=0.5,
                      json_file=False)
    out = tmp_path / "out"
    assert not (out / "report" / "report.md").exists()
    if (out / "demo.json").exists():
        assert json.loads((out / "demo.json").read_text())["meters"]
    assert not [p for p in out.rglob("*.tmp")]


def test_file_stems_are_readable_and_distinct():
    from radiometer import outputs

    names = ["Lamp.1", "Lamp_1", "Lamp 1", "Lampe größer", "灯", "../../etc/passwd", "CON", "", "a" * 300]
    stems = [outputs.file_stem(n) for n in names]
    assert len(set(stems)) == len(names)
    assert stems[1] == "Lamp_1" and stems[0].startswith("Lamp_1-") and stems[3].startswith("Lampe_größer-")
    assert stems[4].startswith("灯") and all("/" not in s and ".." not in s for s in stems)
    assert all(len(s) <= outputs.MAX_STEM + 7 for s in stems)
    stem = outputs.Stems()
    assert stem("Work Plane") == "work_plane" and stem("Lampe größer") == "lampe_größer" and stem("灯") == "灯"
    assert stem("Lamp") == "lamp" and stem("LAMP").startswith("lamp-") and stem("Lamp") == "lamp"
    assert len({stem(n) for n in ("Lamp.1", "Lamp_1", "Lamp 1", "LAMP.1")}) == 4


def test_private_temp_root_is_private_and_unique():
    from radiometer import outputs

    root = outputs.private_temp_root()
    assert os.stat(root).st_mode & 0o777 == 0o700
    assert os.path.basename(root) not in ("radiometer", "radiometer_plots") and root == outputs.private_temp_root()


def test_write_text_is_whole_or_nothing(tmp_path):
    from radiometer import outputs
    from radiometer.errors import RadiometerError

    target = tmp_path / "r.json"
    target.write_text("old")
    with pytest.raises(RadiometerError, match="No space left"):
        outputs.write_text("/dev/full", "x" * 10000)
    outputs.write_text(str(target), "new")
    assert target.read_text() == "new" and [p.name for p in tmp_path.iterdir()] == ["r.json"]


# --- compliance and illuminance-image (issue 34) ------------------------------------------------------

_CAMERA_SCENE = r"""
import json, sys, bpy, radiometer
sys.path.insert(0, {tests!r})
from conftest import make_black_world, add_light, add_plane
bpy.ops.wm.read_factory_settings(use_empty=True)
radiometer.register()
from radiometer import api
s = bpy.context.scene
s.render.engine = "CYCLES"
make_black_world(s)
add_light(s, "AREA", (0, 0, 2), energy=100.0, size=0.5)
add_plane(s, size=4, location=(0, 0, 0), name="Floor", albedo=0.8)
cam = bpy.data.objects.new("Top", bpy.data.cameras.new("Top"))
cam.data.type, cam.data.ortho_scale = "ORTHO", 1.0
cam.location = (0.0, 0.0, 1.0)  # looks down its local -Z: at the floor
s.collection.objects.link(cam)
s.camera = cam
s.render.resolution_x = s.render.resolution_y = 15
bpy.ops.wm.save_as_mainfile(filepath={path!r})
# the closed form averaged over each of the 3 x 3 pixels in the middle (pixels 1/15 m wide; the image's
# pixel filter is a box of one pixel): the mean of 5 x 5 midpoints per pixel
e = lambda x, y: sum(r["illuminance"] for r in api.predict_illuminance((x, y, 0.0), (0, 0, 1), scene=s))
sub = [(k + 0.5) / 5 - 0.5 for k in range(5)]
block = [[sum(e((i + a) / 15, (-j + b) / 15) for a in sub for b in sub) / 25 for i in (-1, 0, 1)] for j in (-1, 0, 1)]
json.dump({{"block_lx": block}}, open({path!r} + ".json", "w"))
"""


@pytest.fixture(scope="module")
def camera_room(tmp_path_factory):
    """A floor under an area light seen straight down by an orthographic camera (15 x 15 px over 1 m);
    no work plane. Beside it the closed-form illuminance at the floor's centre (api.predict_illuminance)."""
    pytest.importorskip("bpy")
    path = str(tmp_path_factory.mktemp("camera_room") / "camera_room.blend")
    tests = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bpy")
    subprocess.run([sys.executable, "-c", _CAMERA_SCENE.format(tests=tests, path=path)], check=True,
                   capture_output=True, timeout=300)
    return path


def test_compliance_and_illuminance_image_help():
    for name, fragment in (("compliance", "--maintained-lx LX"), ("illuminance-image", "--exr FILE")):
        out = run_cli(name, "--help")
        assert out.returncode == 0 and fragment in out.stdout and "lx" in out.stdout, out.stderr
    assert "compliance" in run_cli("--help").stdout and "illuminance-image" in run_cli("--help").stdout


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_compliance_table_with_units_and_json(room, tmp_path):
    """Ēm = MF x the grid's average (the grid in the same JSON), U0 = E_min / Ē; units on the lines."""
    out = run_cli("compliance", room, "--maintained-lx", "50", "--uniformity", "0.1", "--maintenance-factor", "0.7",
                  "--quality", "preview", "--json", str(tmp_path / "c.json"))
    assert out.returncode == 0, out.stderr
    assert "Ēm" in out.stdout and " lx" in out.stdout and "overall:" in out.stdout
    data = json.loads((tmp_path / "c.json").read_text())
    checks = {c["quantity"]: c for c in data["checks"]}
    stats = data["grid"]["stats"]
    assert checks["Ēm"]["unit"] == "lx" and checks["Ēm"]["achieved"] == pytest.approx(0.7 * stats["avg"], rel=1e-9)
    assert checks["U0"]["achieved"] == pytest.approx(stats["min"] / stats["avg"], rel=1e-9)
    assert data["overall"] in ("pass", "fail", "marginal", "not assessed", "error unknown")


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_compliance_bad_input_is_one_line(room, camera_room, tmp_path):
    _one_error_line(run_cli("compliance", room), "give --task KEY")
    _one_error_line(run_cli("compliance", room, "--task", "spaceship"), "unknown task 'spaceship'")
    _one_error_line(run_cli("compliance", room, "--task", "office_writing", "--plane", "Nope"), "no object named 'Nope'")
    _one_error_line(run_cli("compliance", room, "--task", "office_writing", "--maintenance-factor", "1.5"),
                    "--maintenance-factor")
    _one_error_line(run_cli("compliance", camera_room, "--task", "office_writing"), "no work plane")
    _one_error_line(run_cli("compliance", room, "--task", "corridor", "--json", str(tmp_path / "no" / "c.json")),
                    "does not exist")
    assert not (tmp_path / "no").exists()


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_daylight_commands_without_a_work_plane_say_so(camera_room, tmp_path):
    _one_error_line(run_cli("daylight-factor", camera_room, "--quality", "preview"), "no work plane")
    epw = tmp_path / "w.epw"
    from radiometer.radiometry.sun import synthetic_weather

    epw.write_text(synthetic_weather.synthetic_epw_text(), encoding="latin-1")
    _one_error_line(run_cli("annual", camera_room, "--epw", str(epw), "--csv", str(tmp_path / "a.csv")),
                    "no work plane")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.epw"]  # nothing half-written


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_illuminance_image_reads_the_closed_form_at_the_centre(camera_room, tmp_path):
    """The 3 x 3 pixels in the middle see the floor under the light: E from the rendered diffuse passes
    equals the closed form averaged over each pixel (api.predict_illuminance; only direct light reaches
    a lone floor). The pixels' noise is independent: their mean relative departure is within 4 standard
    errors of the mean (from the 9 departures' spread) plus 3e-5 (the 5 x 5 midpoint average of the
    closed form: a 25th of the 2.8e-4 by which a pixel's mean falls below its centre's value). Measured:
    +3e-5 +- 7e-5 with the pixel average; -3.1e-4 against the centres' values (the footprint seen)."""
    import numpy as np
    import OpenEXR

    import bpy

    if bpy.app.version < (5, 0, 0):
        pytest.skip("illuminance images need Blender 5.0's compositor node groups (api.illuminance_image)")
    exr = tmp_path / "e.exr"
    out = run_cli("illuminance-image", camera_room, "--exr", str(exr), "--max-samples", "64", "--json",
                  str(tmp_path / "e.json"))
    assert out.returncode == 0, out.stderr
    assert " lx" in out.stdout and f"wrote {exr}" in out.stdout and (tmp_path / "e.png").exists()
    data = json.loads((tmp_path / "e.json").read_text())
    assert data["resolution"] == [15, 15] and data["paths"]["exr"] == str(exr)
    with OpenEXR.File(str(exr)) as f:
        rgba = f.channels()["RGBA"].pixels
    expected = np.array(json.loads(open(camera_room + ".json").read())["block_lx"])
    assert expected.min() > 10
    departure = (rgba[6:9, 6:9, 0].astype(float) / expected - 1.0).ravel()
    se_mean = float(np.std(departure, ddof=1)) / 3.0
    assert abs(float(np.mean(departure))) <= 4 * se_mean + 3e-5, (departure, se_mean)


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_illuminance_image_bad_input_is_one_line(room, camera_room, tmp_path):
    _one_error_line(run_cli("illuminance-image", room, "--exr", str(tmp_path / "e.exr")), "has no camera")
    _one_error_line(run_cli("illuminance-image", camera_room, "--exr", str(tmp_path / "e.png")), "must name an .exr")
    _one_error_line(run_cli("illuminance-image", camera_room, "--exr", str(tmp_path / "e.exr"), "--camera", "Floor"),
                    "no camera named 'Floor'")
    _one_error_line(run_cli("illuminance-image", camera_room, "--exr", str(tmp_path / "no" / "e.exr")), "--exr file")
    _one_error_line(run_cli("illuminance-image", camera_room, "--exr", str(tmp_path / "e.exr"), "--max-samples", "4"),
                    "--max-samples")
    _one_error_line(run_cli("illuminance-image", camera_room, "--exr", str(tmp_path / "e.exr"), "--range", "5", "1"),
                    "--range")
    assert list(tmp_path.iterdir()) == []  # nothing written, whole or half


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_report_daylight_bad_input_is_one_line(room, camera_room, tmp_path):
    """The report's daylight section (issue 34): a room without a work plane, a weather file with records
    missing their fields, a bad E_v,d: one line each before any measurement, no report file written."""
    out = tmp_path / "rep"
    _one_error_line(run_cli("report", camera_room, "--out", str(out), "--daylight"), "needs a work plane")
    from radiometer.radiometry.sun import synthetic_weather

    lines = synthetic_weather.synthetic_epw_text().splitlines()
    lines[30] = ",".join(lines[30].split(",")[:12])  # line 31: a record cut short before its radiation fields
    bad = tmp_path / "bad.epw"
    bad.write_text("\n".join(lines) + "\n", encoding="latin-1")
    _one_error_line(run_cli("report", room, "--out", str(out), "--daylight", "--epw", str(bad)), "line 31")
    _one_error_line(run_cli("report", room, "--out", str(out), "--daylight", "--median-external-lux", "-5"),
                    "--median-external-lux")
    _one_error_line(run_cli("report", room, "--out", str(out), "--daylight", "--epw", str(tmp_path / "none.epw")),
                    "none.epw")
    assert not out.exists() or list(out.iterdir()) == []

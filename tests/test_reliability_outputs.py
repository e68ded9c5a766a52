"""Issue 21, outputs: nothing lost, nothing half-written, nothing written through a planted link or onto
an input; every refusal is one line on stderr and exit code 2, before any work.

Each test names the finding of issue 21 it reproduces (it failed on the code before the fix).
The scene is tiny (a point light over a 'Work Plane', analytic method): no Cycles render except
the radiance-map test of finding 13 (a 8 x 4 px map).
"""

import contextlib
import glob
import json
import os
import subprocess
import sys

import pytest

SCENE = r"""
import bpy, radiometer
bpy.ops.wm.read_factory_settings(use_empty=True)
radiometer.register()
s = bpy.context.scene
s.render.engine = "CYCLES"
light = bpy.data.lights.new("lamp", "POINT"); light.energy = 100.0; light.shadow_soft_size = 0.0
lo = bpy.data.objects.new("lamp", light); lo.location = (0, 0, 2); s.collection.objects.link(lo)
bpy.ops.mesh.primitive_plane_add(size=1.0); bpy.context.active_object.name = "Work Plane"
if {with_map}:
    bpy.ops.radiometer.add_meter(kind="RADIANCE_MAP")
    bpy.context.active_object.radiometer_meter.map_resolution = 4
    bpy.context.active_object.location = (0, 0, 1)
    s.radiometer.quality = "preview"
bpy.ops.wm.save_as_mainfile(filepath={path!r})
"""


def run_cli(*args, env=None, timeout=300):
    return subprocess.run([sys.executable, "-m", "radiometer", *map(str, args)], capture_output=True, text=True,
                          cwd="/", timeout=timeout, env=env)


def one_error_line(out, fragment=""):
    assert out.returncode == 2, (out.returncode, out.stdout, out.stderr)
    assert "Traceback" not in out.stderr
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("radiometer: error") and fragment in lines[0], out.stderr
    return lines[0]


def _build(tmp_path_factory, name, with_map):
    pytest.importorskip("bpy")
    path = str(tmp_path_factory.mktemp(name) / f"{name}.blend")
    subprocess.run([sys.executable, "-c", SCENE.format(path=path, with_map=with_map)], check=True,
                   capture_output=True, timeout=300)
    return path


@pytest.fixture(scope="module")
def blend(tmp_path_factory):
    return _build(tmp_path_factory, "plane", False)


@pytest.fixture
def scene_copy(blend, tmp_path):
    path = tmp_path / "v.blend"
    path.write_bytes(open(blend, "rb").read())
    return path


# --- finding 1: an output onto the input scene ------------------------------------------------------

@pytest.mark.parametrize("args", [("world", "--json", "{blend}"), ("grid", "--resolution", "2", "2", "--csv", "{blend}"),
                                  ("grid", "--resolution", "2", "2", "--json", "{blend}")])
@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_output_onto_the_input_scene_is_refused(scene_copy, args):
    before = scene_copy.read_bytes()
    argv = [a.format(blend=scene_copy) for a in args]
    out = run_cli(argv[0], scene_copy, *argv[1:])
    one_error_line(out, "input")
    assert out.stdout == ""  # refused before any work
    assert scene_copy.read_bytes() == before


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_output_onto_the_input_by_another_name_is_refused(scene_copy, tmp_path):
    before = scene_copy.read_bytes()
    (tmp_path / "sub").mkdir()
    other_name = tmp_path / "sub" / ".." / "v.blend"
    one_error_line(run_cli("world", scene_copy, "--json", other_name), "input")
    hard = tmp_path / "hard.json"
    os.link(scene_copy, hard)
    one_error_line(run_cli("world", scene_copy, "--json", hard), "input")
    assert scene_copy.read_bytes() == before


def test_luminaire_plot_onto_its_photometric_file_is_refused(tmp_path):
    ies = tmp_path / "lamp.ies"
    ies.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 100\n0 45 90\n0\n100 80 0\n")
    before = ies.read_bytes()
    one_error_line(run_cli("luminaire", ies, "--plot", ies), "input")
    one_error_line(run_cli("luminaire", ies, "--json", ies), "input")
    assert ies.read_bytes() == before


# --- finding 14: two outputs onto one file, empty names, no arguments, long paths -------------------

@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_two_outputs_onto_one_file_are_refused(blend, tmp_path):
    f = tmp_path / "g.out"
    one_error_line(run_cli("grid", blend, "--resolution", "2", "2", "--csv", f, "--json", f), "same file")
    assert not f.exists()


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_empty_json_name_is_an_error(blend):
    one_error_line(run_cli("world", blend, "--json", ""), "--json")


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_json_dash_is_stdout_alone(blend, tmp_path):
    out = subprocess.run([sys.executable, "-m", "radiometer", "world", str(blend), "--json", "-"],
                         capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)  # nothing but the JSON on stdout
    assert data["world"]["illuminance"] == 0.0 and os.listdir(tmp_path) == []  # no file named "-"


def test_no_arguments_prints_usage_on_stderr_exit_2():
    out = run_cli()
    assert out.returncode == 2 and out.stdout == "" and "usage" in out.stderr.lower()


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_a_5000_character_path_is_not_echoed_whole(tmp_path):
    long = "/" + "a" * 5000 + ".blend"
    line = one_error_line(run_cli("measure", long))
    assert len(line) < 400


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_access_based_checks_do_not_pass_a_folder_nobody_can_write_into(blend):
    # /proc passes access(W_OK) for root, but no file can be created there: refused before the run.
    out = run_cli("world", blend, "--json", "/proc/radiometer-test.json")
    one_error_line(out, "/proc/radiometer-test.json")
    assert out.stdout == ""


# --- finding 3: symlinks planted at a destination -----------------------------------------------------

@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
@pytest.mark.parametrize("option", ["--csv", "--png", "--json"])
def test_planted_symlink_is_not_followed(blend, tmp_path, option):
    pytest.importorskip("matplotlib")
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "out.file"
    link.symlink_to(victim)
    one_error_line(run_cli("grid", blend, "--resolution", "2", "2", "--method", "analytic", option, link),
                   "symbolic link")
    assert victim.read_text() == "precious" and os.path.islink(link)


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_brdf_plot_through_a_planted_symlink_is_refused(tmp_path):
    # Finding 2/3: `brdf --plot` wrote its PNG in place (through a link at the destination).
    pytest.importorskip("matplotlib")
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "lobe.png"
    link.symlink_to(victim)
    one_error_line(run_cli("brdf", "lambert", "--plot", link), "symbolic link")
    assert victim.read_text() == "precious"


# --- finding 2: a full disk leaves the old file whole and names the file ------------------------------

@contextlib.contextmanager
def small_tmpfs(tmp_path, size="256k"):
    mount = tmp_path / "tmpfs"
    mount.mkdir()
    ok = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(mount)],
                        capture_output=True).returncode == 0
    if not ok:
        pytest.skip("cannot mount a tmpfs here (covered by /dev/full tests)")
    try:
        yield mount
    finally:
        subprocess.run(["umount", "-l", str(mount)], capture_output=True)


def fill(folder):
    with open(folder / "filler", "wb", buffering=0) as f, contextlib.suppress(OSError):
        while True:
            f.write(b"\0" * 4096)


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
@pytest.mark.parametrize("option, old", [("--csv", "x,y,lux\nold\n"), ("--json", '{"old": true}\n')])
def test_full_disk_keeps_the_old_file_and_names_it(blend, tmp_path, option, old):
    with small_tmpfs(tmp_path) as disk:
        target = disk / ("g.csv" if option == "--csv" else "g.json")
        target.write_text(old)
        fill(disk)
        out = run_cli("grid", blend, "--resolution", "3", "3", "--method", "analytic", option, target)
        line = one_error_line(out)
        assert str(target) in line and "No space left" in line
        assert target.read_text() == old
        assert sorted(p.name for p in disk.iterdir()) == ["filler", target.name]  # no temp file left


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_full_disk_device_is_an_error_naming_it(blend):
    line = one_error_line(run_cli("world", blend, "--json", "/dev/full"), "No space left")
    assert "/dev/full" in line


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_png_onto_a_full_device_is_an_error_and_writes_no_other_file(blend):
    # Finding 14: `--png /dev/full` wrote /dev/full.png and reported success.
    pytest.importorskip("matplotlib")
    line = one_error_line(run_cli("grid", blend, "--resolution", "2", "2", "--method", "analytic",
                                  "--png", "/dev/full"), "No space left")
    assert "/dev/full" in line and not os.path.exists("/dev/full.png")


# --- finding 13: EXR write errors and radiance maps left in a temp folder -------------------------------

@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_irradiance_map_onto_a_full_device_is_an_error(blend):
    pytest.importorskip("OpenEXR")
    out = run_cli("world", blend, "--irradiance-map", "/dev/full", "--resolution", "8", "4")
    one_error_line(out, "/dev/full")


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_irradiance_map_on_a_full_disk_leaves_no_file(blend, tmp_path):
    pytest.importorskip("OpenEXR")
    with small_tmpfs(tmp_path, size="64k") as disk:
        fill(disk)
        out = run_cli("world", blend, "--irradiance-map", disk / "e.exr", "--resolution", "64", "32")
        one_error_line(out, "e.exr")
        assert sorted(p.name for p in disk.iterdir()) == ["filler"]


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_cli_leaves_no_radiance_maps_behind_and_json_points_at_nothing_gone(tmp_path_factory, tmp_path):
    blend = _build(tmp_path_factory, "probe", True)
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    env = dict(os.environ, TMPDIR=str(scratch))
    out = run_cli("measure", blend, "--json", tmp_path / "r.json", env=env)
    assert out.returncode == 0, out.stderr
    meters = json.loads((tmp_path / "r.json").read_text())["meters"]
    paths = [m.get("path") for m in meters]
    assert paths and all(p is None or os.path.isfile(p) for p in paths), paths
    assert glob.glob(str(scratch / "*")) == []  # the private folder is gone

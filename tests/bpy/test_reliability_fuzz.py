"""Issue 21: a bounded fuzz suite over the command line, in-process (``cli.main``), on a tiny scene.

Generated command lines (hypothesis, derandomised, a few dozen examples) combine subcommands with
garbage option values (NaN/inf, huge, negative and empty numbers, text), hostile output names
(newlines, control characters, 5000-character paths, '-', '', folders, devices, planted links,
the input itself) and full-disk outputs. Whatever the line, the CLI answers exit code 0 or 2, never
a traceback; an error is ONE line on stderr; the input .blend is byte-for-byte unchanged; no file
outside the test's folder is created; no temporary file is left beside an output.
"""

import hashlib
import os

import bpy
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from radiometer import cli

NUMBERS = ["nan", "inf", "-inf", "-1", "0", "1e308", "-1e308", "99999999999999999999", "1e-320", "abc", "", "0x10",
           "3", "0.5"]


@pytest.fixture
def scene_file(clean_blender, build, tmp_path):
    s = bpy.context.scene
    build.black_world(s)
    build.light(s, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    build.plane(s, size=1.0, name="Work Plane")
    path = tmp_path / "in.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    return path


def outputs(tmp_path, blend):
    victim = tmp_path / "victim.txt"
    if not victim.exists():
        victim.write_text("precious")
    link = tmp_path / "planted.out"
    if not os.path.lexists(link):
        link.symlink_to(victim)
    return [str(tmp_path / "out.json"), str(tmp_path / "bad\nname.json"), str(tmp_path / "ctl\x01\x1b[2J.csv"),
            str(tmp_path / ("x" * 250)), "/" + "y" * 5000, "-", "", str(tmp_path), "/dev/full", str(link),
            str(blend), str(tmp_path / "missing" / "o.json"), "/proc/radiometer.json", str(tmp_path / "ok.exr")]


def command_lines(tmp_path, blend):
    outs = st.sampled_from(outputs(tmp_path, blend))
    nums = st.sampled_from(NUMBERS)
    world = st.tuples(st.just("world"), st.just(str(blend)),
                      st.lists(st.one_of(st.tuples(st.just("--normal"), nums, nums, nums),
                                         st.tuples(st.just("--irradiance-map"), outs),
                                         st.tuples(st.just("--resolution"), nums, nums),
                                         st.tuples(st.just("--method"), st.sampled_from(["exact", "sh9", "x"])),
                                         st.tuples(st.just("--json"), outs)), max_size=3))
    grid = st.tuples(st.just("grid"), st.just(str(blend)),
                     st.lists(st.one_of(st.tuples(st.just("--resolution"), nums, nums),
                                        st.tuples(st.just("--spacing"), nums),
                                        st.tuples(st.just("--csv"), outs),
                                        st.tuples(st.just("--json"), outs),
                                        st.tuples(st.just("--time-budget"), nums),
                                        st.tuples(st.just("--target"), nums)), max_size=3))
    measure = st.tuples(st.just("measure"), st.sampled_from([str(blend), "/dev/zero", str(tmp_path), "nope.blend"]),
                        st.lists(st.one_of(st.tuples(st.just("--target"), nums),
                                           st.tuples(st.just("--json"), outs)), max_size=2))
    return st.one_of(world, grid, measure)


def flatten(line):
    name, first, options = line
    argv = [name, first]
    for option in options:
        argv += list(option)
    if name == "grid":
        argv += ["--method", "analytic"]
    return argv


def test_cli_fuzz_exit_codes_one_line_and_no_damage(scene_file, tmp_path, capsys):
    blend_hash = hashlib.sha256(scene_file.read_bytes()).hexdigest()
    seen = []

    @settings(max_examples=40, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(line=command_lines(tmp_path, scene_file))
    def run(line):
        argv = flatten(line)
        code = cli.main(argv)
        out, err = capsys.readouterr()
        seen.append((argv, code))
        assert code in (0, 2), (argv, code, err)
        assert "Traceback" not in err and "Traceback" not in out, (argv, err)
        if code == 2:
            lines = [x for x in err.splitlines() if x.strip()]
            assert len(lines) == 1 and lines[0].startswith("radiometer: error"), (argv, err)
            assert len(lines[0]) < 600, argv
        assert hashlib.sha256(scene_file.read_bytes()).hexdigest() == blend_hash, argv
        assert (tmp_path / "victim.txt").read_text() == "precious", argv
        assert not [p for p in os.listdir(tmp_path) if p.startswith(".") and ".tmp" in p], argv

    run()
    assert {code for _argv, code in seen} == {0, 2}  # the fuzz reached both outcomes

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
def test_bad_input_is_one_line_and_nonzero(args, fragment):
    out = run_cli(*args)
    assert out.returncode == 2
    assert "Traceback" not in out.stderr
    lines = [line for line in out.stderr.splitlines() if line.startswith("radiometer: error")]
    assert len(lines) == 1 and fragment in lines[0], out.stderr


def test_not_a_blend_file(tmp_path):
    fake = tmp_path / "scene.blend"
    fake.write_text("this is not a blend file")
    out = run_cli("measure", str(fake))
    assert out.returncode == 2 and "not a .blend file" in out.stderr and "Traceback" not in out.stderr


def test_corrupt_blend_file(tmp_path):
    fake = tmp_path / "scene.blend"
    fake.write_bytes(b"BLENDER-v500" + os.urandom(200))
    out = run_cli("measure", str(fake))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert out.stderr.startswith("radiometer: error"), out.stderr

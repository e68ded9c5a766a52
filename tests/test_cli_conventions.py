"""CLI conventions (no Blender scene needed): every option of every subcommand has help text, `brdf
--list` lists the models, `measure` says which settings it used and the command line wins over the
.blend, `world --calibrate` never overwrites its input."""

import argparse
import json
import subprocess
import sys

import pytest

from radiometer import cli


def _actions(parser, path=()):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _actions(sub, path + (name,))
        else:
            yield path, action


def test_every_option_of_every_subcommand_has_help():
    parser = cli.build_parser()
    missing = [f"{' '.join(path) or '(top)'} {'/'.join(a.option_strings) or a.dest}"
               for path, a in _actions(parser) if not a.help or a.help == argparse.SUPPRESS and a.dest != "help"]
    assert not missing, f"options without help text: {missing}"
    subcommands = {path[0] for path, _a in _actions(parser) if path}
    assert {"measure", "brdf", "world", "grid", "report", "check"} <= subcommands


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_brdf_list_names_every_model_with_its_parameters(tmp_path):
    from radiometer import brdf

    out = tmp_path / "models.json"
    r = subprocess.run([sys.executable, "-m", "radiometer", "brdf", "--list", "--json", str(out)], capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    names = [line.split()[0] for line in r.stdout.splitlines() if line and not line.startswith(" ")]
    assert names == brdf.names()
    models = json.loads(out.read_text())["models"]
    assert [p["name"] for p in models["ggx"]["parameters"]][:1] == ["alpha"]
    r = subprocess.run([sys.executable, "-m", "radiometer", "brdf"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "--list" in r.stderr and r.stderr.count("\n") == 1


def _args(**kw):
    return argparse.Namespace(**{**dict(method=None, quality=None, target=None), **kw})


@pytest.mark.parametrize("given,stored,expected", [
    # --quality reference on a .blend that stores a 2 % target: reference's 0.2 % (the case)
    (dict(quality="reference"), ("auto", "standard", 0.02), ("auto", "reference", 0.002, "quality reference")),
    (dict(), ("auto", "standard", 0.02), ("auto", "standard", 0.02, ".blend")),
    (dict(), ("hybrid", "preview", 0.0), ("hybrid", "preview", 0.05, "quality preview")),
    (dict(target=0.03, quality="reference", method="render"), ("auto", "preview", 0.0),
     ("render", "reference", 0.03, "command line")),
])
def test_command_line_wins_over_the_blend(given, stored, expected):
    from radiometer.commands import measure

    used = measure.used_settings(_args(**given), stored)
    assert (used["method"], used["quality"], used["target_rel_error"], used["source"]["target_rel_error"]) == expected
    line = measure.format_settings(used)
    assert line.startswith("settings: method ") and f"{100 * expected[2]:g} %" in line

"""The math packages never import bpy or mathutils (issue 2): checked in a fresh interpreter."""

import os
import subprocess
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PURE_PACKAGES = ["radiometer", "radiometer.brdf", "radiometer.radiometry", "radiometer.readings",
                 "radiometer.quality"]


@pytest.mark.parametrize("module", PURE_PACKAGES)
def test_pure_module_does_not_import_bpy(module):
    code = (f"import sys, importlib, pkgutil\n"
            f"m = importlib.import_module({module!r})\n"
            f"if hasattr(m, '__path__') and m.__name__ != 'radiometer':\n"
            f"    for info in pkgutil.walk_packages(m.__path__, m.__name__ + '.'):\n"
            f"        if not info.name.split('.')[-1].startswith('plot'):\n"
            f"            importlib.import_module(info.name)\n"
            f"bad = [n for n in ('bpy', 'mathutils', 'bmesh') if n in sys.modules]\n"
            f"assert not bad, bad\n")
    subprocess.run([sys.executable, "-c", code], check=True, cwd="/")


def test_no_pure_source_file_mentions_bpy_import():
    for package in ("brdf", "radiometry"):
        for root, _dirs, files in os.walk(os.path.join(REPO, package)):
            for name in files:
                if name.endswith(".py"):
                    text = open(os.path.join(root, name), encoding="utf-8").read()
                    assert "import bpy" not in text and "import mathutils" not in text, name

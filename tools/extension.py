"""Validate and build the extension with Blender's own tool (``blender_ext.py``, inside the bpy wheel).

    python -m radiometer.tools.extension validate
    python -m radiometer.tools.extension build --out dist
"""

import argparse
import glob
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))


def blender_ext_path():
    """Path of blender_ext.py in the installed bpy, found from bpy's resource path."""
    import importlib.util

    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("bpy is not installed: run `make setup`")
    root = list(spec.submodule_search_locations)[0]
    hits = glob.glob(os.path.join(root, "*", "scripts", "addons_core", "bl_pkg", "cli", "blender_ext.py"))
    if not hits:
        raise FileNotFoundError(f"blender_ext.py not found under {root}")
    return hits[0]


def run_tool(*args):
    return subprocess.run([sys.executable, blender_ext_path(), *args], capture_output=True, text=True)


def validate(source=REPO):
    return run_tool("validate", source)


def build(out_dir, source=REPO):
    os.makedirs(out_dir, exist_ok=True)
    result = run_tool("build", "--source-dir", source, "--output-dir", out_dir)
    zips = sorted(glob.glob(os.path.join(out_dir, "radiometer-*.zip")), key=os.path.getmtime)
    return result, (zips[-1] if zips else None)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m radiometer.tools.extension")
    parser.add_argument("action", choices=("validate", "build"))
    parser.add_argument("--out", default=os.path.join(REPO, "dist"))
    args = parser.parse_args(argv)
    if args.action == "validate":
        result = validate()
    else:
        result, path = build(args.out)
        if path:
            print(path)
    sys.stdout.write(result.stdout)
    sys.stderr.write(result.stderr)
    return result.returncode


if __name__ == "__main__":
    sys.exit(main())

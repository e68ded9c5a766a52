"""Validate and build the extension with Blender's own tool (``blender_ext.py``, inside the bpy wheel).

    python -m radiometer.tools.extension validate
    python -m radiometer.tools.extension fetch             # the bundled wheels of tools/wheels.lock
    python -m radiometer.tools.extension build --out dist  # fetch, then one zip per platform
    python -m radiometer.tools.extension lock              # re-pin the wheels (maintainers)

Bundled wheels: Blender's Python has numpy but not matplotlib, which draws every plot and report
picture. The extension therefore ships matplotlib and its dependencies (numpy excepted) as wheels
for Linux x86-64, Windows x86-64 and macOS arm64/x86-64, Python 3.11 (Blender 4.5 and 5.0). They
are pinned by file name and sha256 in ``tools/wheels.lock``, downloaded once into a cache
(``$RADIOMETER_WHEEL_CACHE`` or ``~/.cache/radiometer/wheels``), checked against the hash, copied
into ``wheels/`` (not committed) and listed in the manifest's ``wheels``; ``build`` makes one zip
per platform with Blender's ``--split-platforms``, each holding only that platform's wheels.
"""

import argparse
import glob
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
LOCK = os.path.join(REPO, "tools", "wheels.lock")
WHEEL_DIR = os.path.join(REPO, "wheels")
MANIFEST = os.path.join(REPO, "blender_manifest.toml")

#: What matplotlib needs at run time besides numpy (Blender ships numpy), pinned to the versions
#: the test suite runs with (requirements.txt and what pip resolved for matplotlib there).
BUNDLED = ("matplotlib==3.11.2", "contourpy==1.3.3", "cycler==0.12.1", "fonttools==4.68.0", "kiwisolver==1.5.1",
           "packaging==26.4", "pillow==13.0.0", "pyparsing==3.3.3", "python-dateutil==4.0.0", "tzdata==2026.6")

#: Blender platform -> pip ``--platform`` tags accepted for it (pip expands macOS versions downwards).
PLATFORMS = {
    "linux-x64": ("manylinux_2_28_x86_64", "manylinux_2_17_x86_64", "manylinux2014_x86_64"),
    "windows-x64": ("win_amd64",),
    "macos-arm64": ("macosx_11_0_arm64",),
    "macos-x64": ("macosx_10_13_x86_64",),
}


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


def build(out_dir, source=REPO, platform=None):
    """Build with ``--split-platforms`` after fetching the locked wheels.

    Returns (CompletedProcess, path of the zip for ``platform``, default this machine's, or None).
    """
    if os.path.realpath(source) == REPO:
        fetch_wheels()
    os.makedirs(out_dir, exist_ok=True)
    result = run_tool("build", "--source-dir", source, "--output-dir", out_dir, "--split-platforms")
    platform = platform or this_platform()
    zips = sorted(glob.glob(os.path.join(out_dir, f"radiometer-*-{platform.replace('-', '_')}.zip")),
                  key=os.path.getmtime)
    return result, (zips[-1] if zips else None)


def this_platform():
    """This machine's Blender platform name (linux-x64, windows-x64, macos-arm64, macos-x64)."""
    import platform as _platform

    machine = {"x86_64": "x64", "amd64": "x64", "arm64": "arm64", "aarch64": "arm64"}[_platform.machine().lower()]
    system = {"linux": "linux", "darwin": "macos", "win32": "windows"}[sys.platform]
    return f"{system}-{machine}"


# ---------------------------------------------------------------------------------------------- wheels

def read_lock(path=LOCK):
    """[(platform, wheel file name, sha256)] from the lock file ('any' = every platform)."""
    rows = []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.split("#", 1)[0].strip()
            if line:
                platform, filename, digest = line.split()
                rows.append((platform, filename, digest))
    return rows


def cache_dir():
    return os.environ.get("RADIOMETER_WHEEL_CACHE") or os.path.join(os.path.expanduser("~"), ".cache", "radiometer",
                                                                       "wheels")


def _sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


class WheelDownloadError(RuntimeError):
    """pip could not download a locked wheel (no network or no index): the build cannot be made."""


def _pip_download(requirement, platform, dest):
    """``pip download`` of one pinned wheel for a Blender platform ('any': pure Python) into ``dest``."""
    cmd = [sys.executable, "-m", "pip", "download", "--quiet", "--disable-pip-version-check", "--no-deps",
           "--only-binary=:all:", "--python-version", "3.11", "--implementation", "cp", "--abi", "cp311",
           "--abi", "abi3", "--abi", "none", "-d", dest, requirement]
    for tag in PLATFORMS.get(platform, ("any",)):
        cmd += ["--platform", tag]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode:
        raise WheelDownloadError(f"pip download {requirement} ({platform}) failed: "
                           + (result.stderr.strip().splitlines() or ["no output"])[-1])


def _requirement(filename):
    """'matplotlib==3.11.2' from a wheel file name (normalised project name, PEP 427)."""
    name, version = filename.split("-")[:2]
    return f"{name.replace('_', '-')}=={version}"


def fetch_wheels(lock=LOCK, dest=WHEEL_DIR):
    """Every locked wheel into ``dest`` (from the cache, downloading what is missing), sha256-checked.

    Returns the list of paths. Raises RuntimeError naming the wheel when a download fails or a file's
    hash differs from the lock (a changed upload is never used silently).
    """
    cache = cache_dir()
    os.makedirs(cache, exist_ok=True)
    os.makedirs(dest, exist_ok=True)
    paths = []
    for platform, filename, digest in read_lock(lock):
        cached = os.path.join(cache, filename)
        if not (os.path.isfile(cached) and _sha256(cached) == digest):
            with tempfile.TemporaryDirectory(dir=cache) as tmp:
                _pip_download(_requirement(filename), platform, tmp)
                got = os.path.join(tmp, filename)
                if not os.path.isfile(got):
                    raise RuntimeError(f"pip did not give the locked wheel {filename} (got {os.listdir(tmp)})")
                if _sha256(got) != digest:
                    raise RuntimeError(f"sha256 of {filename} differs from tools/wheels.lock")
                os.replace(got, cached)
        target = os.path.join(dest, filename)
        if not (os.path.isfile(target) and _sha256(target) == digest):
            shutil.copyfile(cached, target + ".part")
            os.replace(target + ".part", target)
        paths.append(target)
    return paths


def lock_wheels(lock=LOCK):
    """Resolve BUNDLED for every platform, write tools/wheels.lock and the manifest's ``wheels`` list."""
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for platform in PLATFORMS:
            d = os.path.join(tmp, platform)
            os.makedirs(d)
            for req in BUNDLED:
                _pip_download(req, platform, d)
            for filename in sorted(os.listdir(d)):
                kind = "any" if filename.endswith("-none-any.whl") else platform
                rows[(kind, filename)] = _sha256(os.path.join(d, filename))
                os.makedirs(cache_dir(), exist_ok=True)
                shutil.copyfile(os.path.join(d, filename), os.path.join(cache_dir(), filename))
    # A universal2 wheel serves both macOS platforms (Blender's split puts it in both zips): drop the
    # other platform's thin wheel of that project, so no zip holds two copies of one package.
    for kind, filename in [k for k in rows if "universal2" in k[1]]:
        project = filename.split("-")[0]
        for other in [k for k in rows if k[0].startswith("macos") and k[0] != kind and k[1].split("-")[0] == project]:
            del rows[other]
    lines = ["# Bundled run-time wheels (matplotlib and its dependencies, not numpy), Python 3.11.",
             "# Written by `python -m radiometer.tools.extension lock`; fetched and checked by `make zip`.",
             "# blender-platform  wheel  sha256"]
    lines += [f"{p} {f} {h}" for (p, f), h in sorted(rows.items())]
    with open(lock, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    write_manifest_wheels(sorted({f for _p, f in rows}))
    return rows


def write_manifest_wheels(filenames, manifest=MANIFEST):
    """Replace the manifest's ``wheels = [...]`` block with ./wheels/<file> for every file."""
    with open(manifest, encoding="utf-8") as fh:
        text = fh.read()
    block = "wheels = [\n" + "".join(f'  "./wheels/{f}",\n' for f in filenames) + "]"
    text, n = re.subn(r"(?ms)^wheels = \[.*?^\]", lambda _m: block, text)
    if n != 1:
        raise RuntimeError("blender_manifest.toml has no `wheels = [` block to replace")
    with open(manifest, "w", encoding="utf-8") as fh:
        fh.write(text)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m radiometer.tools.extension")
    parser.add_argument("action", choices=("validate", "build", "fetch", "lock"),
                        help="validate the manifest, build the zips, fetch the locked wheels, or re-lock them")
    parser.add_argument("--out", default=os.path.join(REPO, "dist"), help="folder for the zips (build)")
    args = parser.parse_args(argv)
    try:
        if args.action == "fetch":
            print(f"{len(fetch_wheels())} wheels in {WHEEL_DIR}")
            return 0
        if args.action == "lock":
            print(f"{len(lock_wheels())} wheels locked in {LOCK}")
            return 0
        if args.action == "validate":
            result = validate()
        else:
            result, _path = build(args.out)
            for path in sorted(glob.glob(os.path.join(args.out, "radiometer-*.zip"))):
                print(path)
    except (RuntimeError, OSError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    sys.stdout.write(result.stdout)
    sys.stderr.write(result.stderr)
    return result.returncode


if __name__ == "__main__":
    sys.exit(main())

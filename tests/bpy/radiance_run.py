"""Radiance (pyradiance's binaries, test- and bench-only) run on a folder written by ``export-radiance``: the
second opinion of tests/bpy/test_radiance_export.py and bench/radiance_second_opinion.py.

Radiance is run as a path tracer, so that its answer carries a stated standard error rather than the
ambient cache's unstated bias: ``rtrace -I+ -h -ab 32 -aa 0 -ad 1 -as 0 -lw 1e-9 -lr 64 -u+`` (no
ambient cache, one hemisphere ray per input line, uncorrelated sampling, up to 32 bounces with a 1e-9
weight limit), each sensor repeated ``samples`` times in all, split over ``RUNS`` separate rtrace processes;
the mean over all repeats and its standard error from the spread of the processes' means.
lux = 179 x (.265 R + .670 G + .065 B).

Why the spread of separate processes and not the repeats' own standard deviation: the repeats within one
rtrace process are not independent draws. Measured (2026-12-05, side-lit room behind the 6 mm pane, CIE
sky 12, point (1, 1.5, 0.85) m): ten processes of 1 M repeats each had means with a standard deviation of
35.2 lx where each process's repeats stated 17.1 lx (2.1x); the test that used the repeats' error failed
at -3.28 "sigma" in one loaded run of four. rtrace cannot be seeded, but each process draws its own
sequence (its output differs run to run on the same input), so the process means are independent.

The tests' Radiance results are cached (``cached_rtrace_lux``, ``cached_radiance``): Radiance's answer on
byte-identical input files under the same command line, sample counts and Radiance build is one more draw
of the same quantity, so an earlier run's answer, committed under tests/data/radiance_cache/<key>.json, is
used instead of a new run (80-100 s of rtrace in `make test` on 2 cores). The key is the SHA-256 of the
Radiance version (``rtrace -version`` and pyradiance's), the command and its counts, and the SHA-256 of
every input file Radiance reads (the export's files but README.txt and radiance_export.json, which are
documentation; the exports are byte-deterministic). Any change of an exported file changes the key:
Radiance runs again and the test writes the new entry (commit it). An entry is never overwritten: delete it
to replace it. ``RADIOMETER_RADIANCE_RERUN=1`` runs Radiance every time (a fresh draw; the cache is neither
read nor overwritten). The bench (bench/radiance_second_opinion.py) always runs Radiance (``rtrace_lux``)."""

import datetime
import hashlib
import json
import os
import pathlib
import subprocess
import time

import numpy as np

#: Separate rtrace processes per call: the standard error comes from the spread of their means (16: a
#: standard error known to about +-18 %, 1 / sqrt(2 (RUNS - 1))).
RUNS = 16
RTRACE = ["rtrace", "-h", "-I+", "-ab", "32", "-aa", "0", "-ad", "1", "-as", "0", "-lw", "1e-9", "-lr", "64", "-u+"]


def radiance_env(folder):
    """The environment rtrace needs: pyradiance's bin on PATH, the folder and its lib on RAYPATH."""
    import pyradiance

    root = os.path.dirname(pyradiance.__file__)
    return dict(os.environ, PATH=os.path.join(root, "bin") + os.pathsep + os.environ.get("PATH", ""),
                RAYPATH=os.pathsep.join([str(folder), os.path.join(root, "lib")]))


def rtrace_lux(folder, sky, points_file, samples, runs=RUNS):
    """(illuminance lx (N,), its relative standard error (N,)) at the sensors of ``points_file`` from the
    exported scene.rad under ``sky`` (a file of the export, or None for the lights alone): ``samples``
    repeats per sensor in all, over ``runs`` separate rtrace processes (module docstring: why)."""
    return _mean_and_rel(rtrace_means(folder, sky, points_file, samples, runs), runs)


def rtrace_means(folder, sky, points_file, samples, runs=RUNS):
    """The (runs, N) illuminances (lx), one row per rtrace process, of ``rtrace_lux``."""
    env = radiance_env(folder)
    with open(os.path.join(folder, "second_opinion.oct"), "wb") as f:
        subprocess.run(["oconv"] + ([sky] if sky else []) + ["scene.rad"], cwd=folder, env=env, stdout=f, check=True)
    lines = pathlib.Path(folder, points_file).read_text().splitlines()
    per_run = max(1, samples // runs)
    rays = "".join((line + "\n") * per_run for line in lines)
    means = []
    started = None
    for _ in range(runs):
        # rtrace -u+ seeds its random numbers from the clock's second (measured: two processes started in
        # one second returned identical numbers), so each process starts in a new second.
        while started is not None and int(time.time()) == started:
            time.sleep(0.05)
        started = int(time.time())
        out = subprocess.run(RTRACE + ["second_opinion.oct"], cwd=folder, env=env, input=rays, capture_output=True,
                             text=True, check=True)
        rgb = np.array(out.stdout.split(), float).reshape(len(lines), per_run, 3)
        means.append((179.0 * rgb @ np.array([0.265, 0.670, 0.065])).mean(axis=1))
    os.unlink(os.path.join(folder, "second_opinion.oct"))
    means = np.array(means)  # (runs, N)
    if len({row.tobytes() for row in means}) < len(means):
        raise AssertionError("two rtrace processes returned the same numbers: their seeds were not independent")
    return means


def _mean_and_rel(means, runs):
    """The mean over the processes and its relative standard error from their spread."""
    mean = means.mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(mean > 0, means.std(axis=0, ddof=1) / np.sqrt(runs) / mean, 0.0)
    return mean, rel


#: Committed Radiance results of the tests (module docstring).
CACHE = pathlib.Path(__file__).resolve().parent.parent / "data" / "radiance_cache"
RERUN = "RADIOMETER_RADIANCE_RERUN"
#: Files of an export that Radiance never reads (the folder's documentation and manifest).
NOT_READ = ("README.txt", "radiance_export.json")
_version = {}


def radiance_version(env):
    """Radiance's own version line and pyradiance's (the binaries and their lib of .cal files)."""
    if "v" not in _version:
        import pyradiance

        out = subprocess.run(["rtrace", "-version"], env=env, capture_output=True, text=True, check=True)
        _version["v"] = f"{out.stdout.strip()}; pyradiance {pyradiance.__version__}"
    return _version["v"]


def _sha256(data):
    return hashlib.sha256(data).hexdigest()


def cached_radiance(made_by, env, inputs, params, run):
    """``run()`` (a JSON-able result) or the committed result of an earlier run on the same key: Radiance's
    version, ``params`` (the command and its counts) and the SHA-256 of each of ``inputs`` (name -> bytes,
    every file Radiance reads). A new result is written for committing; RADIOMETER_RADIANCE_RERUN=1 always
    runs (module docstring)."""
    meta = {"radiance": radiance_version(env), "params": params,
            "inputs": {name: _sha256(data) for name, data in sorted(inputs.items())}}
    key = _sha256(json.dumps(meta, sort_keys=True).encode())
    path = CACHE / f"{key}.json"
    rerun = os.environ.get(RERUN, "") not in ("", "0")
    if path.exists() and not rerun:
        entry = json.loads(path.read_text(encoding="utf-8"))
        assert entry["key"] == key and entry["meta"] == meta, path  # a hand-edited or misnamed entry
        return entry["result"]
    result = run()
    if not path.exists():
        entry = {"key": key, "made_by": made_by, "made": datetime.datetime.now(datetime.timezone.utc).isoformat(
            timespec="seconds"), "meta": meta, "result": result}
        try:
            CACHE.mkdir(parents=True, exist_ok=True)
            tmp = path.with_name(f".{key}.{os.getpid()}.tmp")
            tmp.write_text(json.dumps(entry, indent=1) + "\n", encoding="utf-8")
            os.replace(tmp, path)
        except OSError:  # a read-only checkout: the test still has its fresh run
            pass
    return result


def cached_rtrace_lux(folder, sky, points_file, samples, runs=RUNS):
    """``rtrace_lux`` with the committed cache (module docstring): the key holds every file of the export
    folder but NOT_READ, the sky and sensor file named, the command and the sample counts."""
    env = radiance_env(folder)
    inputs = {p.name: p.read_bytes() for p in sorted(pathlib.Path(folder).iterdir())
              if p.is_file() and p.name not in NOT_READ + ("second_opinion.oct",)}  # the octree: made here
    per_run = max(1, samples // runs)
    params = {"function": "rtrace_lux", "oconv": ["oconv"] + ([sky] if sky else []) + ["scene.rad"],
              "rtrace": RTRACE + ["second_opinion.oct"], "points_file": points_file, "samples": samples,
              "runs": runs, "per_run": per_run, "lux": [179.0, 0.265, 0.670, 0.065]}

    def run():
        return rtrace_means(folder, sky, points_file, samples, runs).tolist()

    means = np.array(cached_radiance("tests/bpy/radiance_run.py cached_rtrace_lux", env, inputs, params, run), float)
    return _mean_and_rel(means, runs)

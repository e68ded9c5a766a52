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
sequence (its output differs run to run on the same input), so the process means are independent."""

import os
import pathlib
import subprocess

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
    env = radiance_env(folder)
    with open(os.path.join(folder, "second_opinion.oct"), "wb") as f:
        subprocess.run(["oconv"] + ([sky] if sky else []) + ["scene.rad"], cwd=folder, env=env, stdout=f, check=True)
    lines = pathlib.Path(folder, points_file).read_text().splitlines()
    per_run = max(1, samples // runs)
    rays = "".join((line + "\n") * per_run for line in lines)
    means = []
    for _ in range(runs):
        out = subprocess.run(RTRACE + ["second_opinion.oct"], cwd=folder, env=env, input=rays, capture_output=True,
                             text=True, check=True)
        rgb = np.array(out.stdout.split(), float).reshape(len(lines), per_run, 3)
        means.append((179.0 * rgb @ np.array([0.265, 0.670, 0.065])).mean(axis=1))
    os.unlink(os.path.join(folder, "second_opinion.oct"))
    means = np.array(means)  # (runs, N)
    mean = means.mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(mean > 0, means.std(axis=0, ddof=1) / np.sqrt(runs) / mean, 0.0)
    return mean, rel

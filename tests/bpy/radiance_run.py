"""Radiance (pyradiance's binaries, test- and bench-only) run on a folder written by ``export-radiance``: the
second opinion of tests/bpy/test_radiance_export.py and bench/radiance_second_opinion.py.

Radiance is run as a path tracer, so that its answer carries a stated standard error rather than the
ambient cache's unstated bias: ``rtrace -I+ -h -ab 32 -aa 0 -ad 1 -as 0 -lw 1e-9 -lr 64 -u+`` (no
ambient cache, one hemisphere ray per input line, uncorrelated sampling, up to 32 bounces with a 1e-9
weight limit), each sensor repeated ``samples`` times; the mean and the standard error of the mean
over the repeats. lux = 179 x (.265 R + .670 G + .065 B)."""

import os
import pathlib
import subprocess

import numpy as np

RTRACE = ["rtrace", "-h", "-I+", "-ab", "32", "-aa", "0", "-ad", "1", "-as", "0", "-lw", "1e-9", "-lr", "64", "-u+"]


def radiance_env(folder):
    """The environment rtrace needs: pyradiance's bin on PATH, the folder and its lib on RAYPATH."""
    import pyradiance

    root = os.path.dirname(pyradiance.__file__)
    return dict(os.environ, PATH=os.path.join(root, "bin") + os.pathsep + os.environ.get("PATH", ""),
                RAYPATH=os.pathsep.join([str(folder), os.path.join(root, "lib")]))


def rtrace_lux(folder, sky, points_file, samples):
    """(illuminance lx (N,), its relative standard error (N,)) at the sensors of ``points_file`` from the
    exported scene.rad under ``sky`` (a file of the export, or None for the lights alone)."""
    env = radiance_env(folder)
    with open(os.path.join(folder, "second_opinion.oct"), "wb") as f:
        subprocess.run(["oconv"] + ([sky] if sky else []) + ["scene.rad"], cwd=folder, env=env, stdout=f, check=True)
    lines = pathlib.Path(folder, points_file).read_text().splitlines()
    rays = "".join((line + "\n") * samples for line in lines)
    out = subprocess.run(RTRACE + ["second_opinion.oct"], cwd=folder, env=env, input=rays, capture_output=True,
                         text=True, check=True)
    os.unlink(os.path.join(folder, "second_opinion.oct"))
    rgb = np.array(out.stdout.split(), float).reshape(len(lines), samples, 3)
    y = 179.0 * rgb @ np.array([0.265, 0.670, 0.065])
    mean = y.mean(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(mean > 0, y.std(axis=1, ddof=1) / np.sqrt(samples) / mean, 0.0)
    return mean, rel

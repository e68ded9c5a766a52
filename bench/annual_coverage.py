"""Coverage of the annual dome's hourly errors (issue 31) after the 2026-12-07 changes: the patches found by the
paths' own bounces (emission sampling NONE) and 8 x 8-pixel blocks at preview. Three meters of the annual room
(tests/bpy/annual_room.py: near the window facing up, facing the window, deep in the room where the reflected
light dominates), 60 random Perez skies with a sun (hourly sky vectors over the 146 patches).

* Reference: one render at reference quality (1M rays per meter) by a different estimator: the whole light
  rendered (no closed-form direct part), the patches also found by next-event estimation (emission sampling
  AUTO, as before the change), 16 x 16-pixel blocks.
* Under test: ``seeds`` preview renders per configuration, the current one, the one before the change and two
  between them (emission sampling NONE with 16 x 16 and 12 x 12 blocks);
  per meter and sky z = (E - E_ref) / hypot(stated s.e., reference s.e.); acceptance: at least 90 % of 95 %
  intervals hold.
* Independent means: Radiance's two-phase coefficients (``rcontrib -ab 8 -ad 262144 -lw 1e-6``, no ambient
  cache; one run, its error not stated) against the seeds' mean.

    PYTHONPATH=... python bench/annual_coverage.py [--quick]   # writes bench/annual_coverage.{json,md}
"""

import json
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
POINTS = [(2.0, 0.6, 0.85), (1.0, 2.4, 0.85), (3.0, 5.7, 0.85)]
NORMALS = [(0.0, 0.0, 1.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0)]
NAMES = ["near the window, up", "facing the window", "deep in the room, up"]


def sky_vectors(patches, count, seed):
    """``count`` random hourly sky vectors (Perez skies with a sun), as tests/bpy/test_annual.py draws them."""
    from radiometer.radiometry.skies import perez

    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        alt, az = rng.uniform(0.05, 1.4), rng.uniform(0, 2 * np.pi)
        sun = np.array([np.cos(alt) * np.sin(az), np.cos(alt) * np.cos(az), np.sin(alt)])
        out.append(perez.sky_vector(patches, sun, rng.uniform(0, 800), rng.uniform(20, 300), 180)[0])
    return np.array(out)


def _configured(dcm, emission, preview):
    """Patch ``dcm`` for one configuration: the dome material's emission sampling, the preview preset."""
    original = dcm._build_dome.__wrapped__ if hasattr(dcm._build_dome, "__wrapped__") else dcm._build_dome

    def build(*args, **kwargs):
        names, objects = original(*args, **kwargs)
        for ob in objects:
            for mat in ob.data.materials:
                mat.cycles.emission_sampling = emission
        return names, objects

    build.__wrapped__ = original
    dcm._build_dome = build
    dcm.DOME_PRESETS["preview"] = preview


def hourly(c, skies):
    """(E (S, N), s.e. (S, N)) of sky vectors ``skies`` (S, P) from coefficients ``c``."""
    e = skies @ c.dc
    se = np.sqrt(np.maximum(np.einsum("sp,npq,sq->sn", skies, c.covariance, skies), 0.0))
    return e, se


def run(quick=False, seeds=50, skies=60, configs=None, radiance=True):
    import bpy

    import radiometer
    from radiometer.measure.analyses import daylight_coefficients as dcm
    from radiometer.measure.blender import request as request_of
    from radiometer.radiometry.skies import sky_patches
    from scenes import load_test_module

    seeds = 3 if quick else seeds
    room = load_test_module("annual_room")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = bpy.context.scene
    room.room.build_blender(scene, room.quads())
    points, normals = np.array(POINTS), np.array(NORMALS)
    patches = sky_patches.reinhart_patches(1)
    vec = sky_vectors(patches, skies, 2)
    current = dict(dcm.DOME_PRESETS)
    out = {"seeds": seeds, "skies": skies, "load_average_before": os.getloadavg(), "meters": NAMES}
    t0 = time.perf_counter()
    _configured(dcm, "AUTO", (8, 16, 8))
    ref = dcm.render_coefficients(points, normals, request=request_of.build(
        scene, quality="preview" if quick else "reference", seed=999), proven_direct=False)
    out["reference_s"] = time.perf_counter() - t0
    out["reference_rays_per_meter"] = int(ref.samples)
    e_ref, se_ref = hourly(ref, vec)
    configs = configs or {"current": ("NONE", current["preview"]), "before": ("AUTO", (8, 16, 8)),
                          "none16": ("NONE", (8, 16, 8)), "none12": ("NONE", (14, 12, 8))}
    for label, (emission, preview) in configs.items():
        _configured(dcm, emission, preview)
        zs, es, secs = [], [], []
        for k in range(seeds):
            t0 = time.perf_counter()
            c = dcm.render_coefficients(points, normals, request=request_of.build(scene, quality="preview", seed=k))
            secs.append(time.perf_counter() - t0)
            e, se = hourly(c, vec)
            zs.append((e - e_ref) / np.hypot(se, se_ref))
            es.append(e)
        z, es = np.array(zs), np.array(es)  # (seeds, S, N)
        out[label] = {"emission_sampling": emission, "preview": list(preview), "seconds_median": float(np.median(secs)),
                      "coverage": [float(np.mean(np.abs(z[:, :, i]) <= 1.96)) for i in range(len(points))],
                      "z_mean": [float(z[:, :, i].mean()) for i in range(len(points))],
                      "z_sd": [float(z[:, :, i].std()) for i in range(len(points))],
                      "rel_error_median": [float(np.median(np.sqrt(np.mean((es[:, :, i] - e_ref[:, i]) ** 2, axis=0))
                                                           / e_ref[:, i])) for i in range(len(points))],
                      "mean_over_reference": [float(es[:, :, i].mean() / e_ref[:, i].mean()) for i in
                                              range(len(points))],
                      "mean_over_reference_se": [float(es[:, :, i].mean(axis=1).std() / np.sqrt(seeds)
                                                       / e_ref[:, i].mean()) for i in range(len(points))]}
        print(label, {k: v for k, v in out[label].items()}, flush=True)
    dcm.DOME_PRESETS.update(current)
    if not radiance:
        return out
    folder = tempfile.mkdtemp(prefix="radiometer-annual-coverage-")
    epw_path = room.write_epw(os.path.join(folder, "year.epw"))
    t0 = time.perf_counter()
    _e, rad_dc = room.radiance_two_phase(folder, epw_path, points, normals,
                                         ambient_divisions=16384 if quick else 262144)
    out["radiance_s"] = time.perf_counter() - t0
    e_rad = vec @ rad_dc
    out["reference_over_radiance"] = [float(e_ref[:, i].mean() / e_rad[:, i].mean()) for i in range(len(points))]
    out["load_average_after"] = os.getloadavg()
    if not quick:
        with open(os.path.join(HERE, "annual_coverage.json"), "w") as f:
            json.dump(out, f, indent=1)
        write_md()
    return out


def write_md():
    with open(os.path.join(HERE, "annual_coverage.json")) as f:
        d = json.load(f)
    lines = ["## Annual dome: coverage of the hourly errors (issue 31)", "",
             f"`bench/annual_coverage.py`: 3 meters of the annual room, {d['skies']} random Perez skies with a sun, "
             f"{d['seeds']} preview seeds per configuration, one run on the 2-core machine (load average before "
             f"{', '.join(f'{v:.1f}' for v in d['load_average_before'])}). Reference: the whole light rendered at "
             f"{d['reference_rays_per_meter']} rays per meter with next-event estimation on the patches (another "
             "estimator than the one under test); z = (E - E_ref) / hypot(stated s.e., reference s.e.).", "",
             "| meter | configuration | 95 % coverage | z mean | z s.d. | hourly error (median RMS) | "
             "seeds' mean / reference | one preview render (s) |", "|---|---|---|---|---|---|---|---|"]
    for i, name in enumerate(d["meters"]):
        for label, title in (("current", "current: emission sampling NONE, 8x8 px x 32 samples"),
                             ("before", "before: emission sampling AUTO, 16x16 px x 8 samples"),
                             ("none16", "emission sampling NONE, 16x16 px x 8 samples"),
                             ("none12", "emission sampling NONE, 12x12 px x 14 samples")):
            if label not in d:
                continue
            r = d[label]
            lines.append(f"| {name} | {title} | {100 * r['coverage'][i]:.1f} % | {r['z_mean'][i]:+.2f} | "
                         f"{r['z_sd'][i]:.2f} | {100 * r['rel_error_median'][i]:.1f} % | "
                         f"{r['mean_over_reference'][i]:.4f} +- {r['mean_over_reference_se'][i]:.4f} | "
                         f"{r['seconds_median']:.2f} |")
    lines += ["", "The reference against Radiance's two-phase coefficients (`rcontrib -ab 8 -ad 262144 -lw 1e-6`, "
              "one run, its error not stated), mean over the skies: "
              + ", ".join(f"{name} {v:.4f}" for name, v in zip(d["meters"], d["reference_over_radiance"])) + "."]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(HERE, "annual_coverage.md"), "w") as f:
        f.write(text)
    print(text, end="")


if __name__ == "__main__":
    write_md() if sys.argv[1:] == ["md"] else run(quick="--quick" in sys.argv)

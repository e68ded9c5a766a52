"""`make bench`: Radiometer's benchmarks (issue 6), all in one process, results in bench/results.{json,md}.

Speed is only ever reported as a RATIO of two things timed in the same run, interleaved, as the
median of several repetitions: the machine (2 cores) is shared, absolute seconds drift from run to
run. Every goal of the issue is evaluated and written down as met or NOT met.

Usage: ``.venv/bin/python bench/run.py [--quick] [--only NAME ...]``.
"""

import argparse
import contextlib
import datetime
import json
import math
import os
import platform
import resource
import statistics
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import bpy  # noqa: E402

import scenes  # noqa: E402
from radiometer import api  # noqa: E402
from radiometer import quality as quality_presets  # noqa: E402
from radiometer.measure import exr, render_settings, scene_guard, scene_lights, sensors  # noqa: E402
from radiometer.radiometry import lights as light_models  # noqa: E402

QUICK = False


def log(msg):
    print(msg, file=sys.stderr, flush=True)


@contextlib.contextmanager
def quiet_stdout():
    """Silence Cycles' C-level prints ("Baking map saved ...") while benchmarks run."""
    sys.stdout.flush()
    saved = os.dup(1)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    try:
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)
        os.close(devnull)


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def median(xs):
    return float(statistics.median(xs))


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def data_counts():
    return {name: len(getattr(bpy.data, name)) for name in scene_guard._DATA_COLLECTIONS}


class BakeClock:
    """Adds up the time spent inside Cycles' bake operator (wraps ``sensors.run_bake``)."""

    def __init__(self):
        self.seconds = 0.0
        self._original = None

    def __enter__(self):
        self._original = original = sensors.run_bake

        def clocked(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds += time.perf_counter() - t0

        sensors.run_bake = clocked
        return self

    def __exit__(self, *exc):
        sensors.run_bake = self._original
        return False


# --- 1. overhead ------------------------------------------------------------------------------------

def _bare_sensor(scene, point, normal, preset):
    """The same sensor quad + image as Radiometer builds, set up once, plus a bare bake function."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    needs = render_settings.scene_needs(scene, depsgraph)
    render_settings.apply(scene, samples=preset["samples"], bounces=preset["bounces"], needs=needs)
    obj, image, per_row = sensors.build_sensor(scene, np.array([point]), np.array([normal]), preset["texels"])
    obj.name = "bench bare sensor"  # not radiometer_*: Radiometer must not mistake it for its own
    view_layer = bpy.context.view_layer
    res = per_row * preset["texels"]

    def bake():
        for other in view_layer.objects:
            other.select_set(other == obj)
        view_layer.objects.active = obj
        with bpy.context.temp_override(active_object=obj, object=obj, selected_objects=[obj],
                                       selected_editable_objects=[obj]):
            result = bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"}, margin=0,
                                         use_clear=True, target="IMAGE_TEXTURES")
        assert result == {"FINISHED"}
        px = np.empty(res * res * 4, np.float32)
        image.pixels.foreach_get(px)
        return math.pi * float(px.reshape(-1, 4)[:, :3].mean())

    return obj, bake


def bench_overhead():
    reps = 5 if QUICK else 11
    preset = quality_presets.preset("standard")
    rows = []
    for label, build, point in (("delta-lit (point light only)", scenes.delta_lit, (0.3, 0.2, 0.0)),
                                ("interreflecting room", scenes.room, (0.3, 0.2, 0.75))):
        scene = build()
        normal = (0.0, 0.0, 1.0)
        # The bare bake uses exactly the settings Radiometer chose for this scene (e.g. one exact
        # sample per texel when only delta lights shine), read back from a first reading.
        first = api.measure_illuminance(point, normal, method="render", quality="standard")
        used = dict(preset, samples=first.render_settings["samples"])
        used["texels"] = int(round(math.sqrt(first.samples / (used["samples"] * preset["bakes"]))))
        bare_obj, bare = _bare_sensor(scene, point, normal, used)
        t_meter, t_bare, values = [], [], []

        def radiometer_reading():
            bare_obj.hide_render = True  # the bare sensor must not be in Radiometer's bake
            try:
                return api.measure_illuminance(point, normal, method="render", quality="standard").irradiance
            finally:
                bare_obj.hide_render = False

        radiometer_reading(), bare()  # warm-up (kernel load, first sync)
        for k in range(reps):
            order = (radiometer_reading, bare) if k % 2 == 0 else (bare, radiometer_reading)
            for fn in order:
                dt, value = timed(fn)
                (t_meter if fn is radiometer_reading else t_bare).append(dt)
                values.append((fn is radiometer_reading, value))
        ratio = median(t_meter) / median(t_bare)
        rows.append({"scene": label, "reps": reps, "median_reading_s": median(t_meter),
                     "median_bare_bake_s": median(t_bare), "ratio": ratio, "goal": 1.1, "met": ratio <= 1.1,
                     "reading_value": median([v for m, v in values if m]),
                     "bare_value": median([v for m, v in values if not m])})
        log(f"  overhead {label}: {ratio:.3f}")
    return {"rows": rows}


# --- 2. batching ------------------------------------------------------------------------------------

def bench_batching():
    counts = (1, 10, 100) if QUICK else (1, 10, 100, 1000)
    rows = []
    for label, build, z in (("delta-lit", scenes.delta_lit, 0.0), ("interreflecting room", scenes.room, 0.75)):
        build()
        api.measure_illuminance((0.0, 0.0, z), method="render")  # warm-up
        times, bake_share = {}, {}
        reps = {1: 9, 10: 7, 100: 7, 1000: 3}
        for n in counts:
            pts, normals = scenes.meter_points(n, half_width=1.5, z=z, seed=n)
            ts, shares = [], []
            for _ in range(2 if QUICK else reps[n]):
                with BakeClock() as clock:
                    ts.append(timed(lambda: api.measure_illuminance(pts, normals, method="render",
                                                                    quality="standard"))[0])
                shares.append(clock.seconds / ts[-1])
            times[n] = median(ts)
            bake_share[n] = median(shares)
        for n in counts:
            rows.append({"scene": label, "meters": n, "median_s": times[n], "ratio_to_1": times[n] / times[1],
                         "ms_per_meter": 1e3 * times[n] / n,
                         "share_in_cycles_bake": bake_share[n]})
        log(f"  batching {label}: " + ", ".join(f"{n}: {times[n] / times[1]:.2f}x" for n in counts))
    ratios = {r["scene"]: r["ratio_to_1"] for r in rows if r["meters"] == 100}
    return {"rows": rows, "goal": "t(100 meters) <= 3 t(1 meter)",
            "met": {scene: ratio <= 3.0 for scene, ratio in ratios.items()}}


# --- 3. analytic ------------------------------------------------------------------------------------

def bench_analytic():
    scene = scenes.delta_lit()
    specs, _ = scene_lights.light_specs(scene)
    m = 200_000 if QUICK else 1_000_000
    rng = np.random.default_rng(0)
    pts = rng.uniform(-5, 5, (m, 3))
    normals = rng.normal(size=(m, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    light_models.irradiance(specs[0], pts[:1000], normals[:1000])
    t_single = median([timed(lambda: light_models.irradiance(specs[0], pts, normals))[0] for _ in range(5)])
    evals_per_s = m / t_single

    # predict_illuminance with 100 point lights, without and with geometry (occlusion ray casts).
    results = {"points": m, "seconds_per_call": t_single, "point_evals_per_s": evals_per_s,
               "goal_evals_per_s": 1e6, "met": evals_per_s >= 1e6}
    for label, with_room in (("100 lights, no geometry", False), ("100 lights in the closed room", True)):
        scene = scenes.room() if with_room else scenes.fresh()
        for k in range(100):
            x, y = rng.uniform(-1.8, 1.8, 2)
            scenes.light(scene, "POINT", (x, y, 2.5), energy=10.0, shadow_soft_size=0.0)
        if with_room:  # drop the room's own area light so that exactly 100 point lights remain
            bpy.data.objects.remove(bpy.data.objects["bench area"])
        api.predict_illuminance((0.1, 0.2, 0.75))
        t = median([timed(lambda: api.predict_illuminance((0.1, 0.2, 0.75)))[0] for _ in range(5)])
        t_vec = median([timed(lambda: [light_models.irradiance(s, pts[:1], normals[:1])
                                       for s in scene_lights.light_specs(scene)[0]])[0] for _ in range(5)])
        results[label] = {"predict_illuminance_s": t, "model_evaluation_only_s": t_vec,
                          "share_outside_models": 1 - t_vec / t}
        log(f"  analytic {label}: predict {t * 1e3:.1f} ms")
    log(f"  analytic: {evals_per_s:.3g} point-light evaluations/s")
    return results


# --- 4. error vs time -------------------------------------------------------------------------------

def _fit_slope(x, y):
    x, y = np.log(np.asarray(x)), np.log(np.asarray(y))
    return float(np.polyfit(x, y, 1)[0])


def bench_error_vs_time():
    """RMS relative error of N meters vs a reference, per preset, plus a sample sweep for the slope.

    The sweep (``bench_sN``: N samples x 16 texels x 1 bake) uses the reference's bounce limit, so its
    error is Monte Carlo noise only and the fitted slope tests the 1/sqrt(N) law; the presets keep
    their own bounce limits, so their error also contains the bias of truncating interreflection.
    """
    truth_bounces = 64  # albedo 0.7: energy left after 64 bounces ~ 0.7^64 ~ 1e-10
    sweep = (4, 16, 64, 256) if QUICK else (4, 16, 64, 256, 1024)
    out = {"scenes": {}}
    try:
        for label, build, z, truth, meters in (("delta-lit (exact)", scenes.delta_lit, 0.0, "analytic", 60),
                                               ("area-lit (closed form)", scenes.area_lit, 0.0, "analytic", 60),
                                               ("interreflecting room (high-sample reference)", scenes.room, 0.75,
                                                "render", 30)):
            build()
            for s in sweep:
                quality_presets.PRESETS[f"bench_s{s}"] = {"samples": s, "texels": 4, "bakes": 1,
                                                          "bounces": truth_bounces}
            quality_presets.PRESETS["bench_truth"] = {"samples": 512 if QUICK else 2048, "texels": 4, "bakes": 2,
                                                      "bounces": truth_bounces}
            pts, normals = scenes.meter_points(meters, half_width=0.8, z=z, seed=4)
            if truth == "analytic":
                ref = np.array([r.irradiance for r in api.measure_illuminance(pts, normals, method="analytic")])
                ref_var = np.zeros(meters)
                ref_note = "closed form (exact)"
            else:
                t_ref, refs = timed(lambda: api.measure_illuminance(pts, normals, method="render",
                                                                    quality="bench_truth", seed=10_000))
                ref = np.array([r.irradiance for r in refs])
                ref_var = np.array([(r.rel_std_error * r.irradiance) ** 2 for r in refs])
                p = quality_presets.PRESETS["bench_truth"]
                ref_note = (f"render, {p['samples']} samples x 16 texels x {p['bakes']} bakes per meter, "
                            f"{truth_bounces} bounces ({t_ref:.1f} s, stated rel. s.e. "
                            f"{np.sqrt(np.mean(ref_var)) / np.sqrt(np.mean(ref ** 2)):.1e}); its variance is "
                            "subtracted from the squared errors")
            rows = []
            for name in ("preview", "standard", "reference") + tuple(f"bench_s{s}" for s in sweep):
                api.measure_illuminance(pts[:1], normals[:1], method="render", quality=name)  # warm-up
                dt, readings = timed(lambda: api.measure_illuminance(pts, normals, method="render", quality=name,
                                                                     seed=1))
                got = np.array([r.irradiance for r in readings])
                mse = np.mean((got - ref) ** 2 - ref_var) / np.mean(ref ** 2)
                rel_rms = math.sqrt(max(mse, 0.0))
                stated = float(np.sqrt(np.mean([(r.rel_std_error * r.irradiance) ** 2 for r in readings])
                                       / np.mean(ref ** 2)))
                p = quality_presets.PRESETS[name]
                # What the readings actually used (a delta-only scene needs 1 sample per texel).
                rows.append({"preset": name, "samples_per_meter": int(readings[0].samples),
                             "bounces": p["bounces"], "seconds_per_call": dt, "seconds_per_meter": dt / meters,
                             "rel_rms_error": rel_rms, "stated_rel_std_error": stated,
                             "error_over_stated": rel_rms / stated if stated > 0 else None})
            fit_rows = [r for r in rows if r["preset"].startswith("bench_s") and r["rel_rms_error"] > 1e-5]
            entry = {"reference": ref_note, "meters": meters, "rows": rows}
            if len(fit_rows) >= 3:
                entry["slope_error_vs_time"] = _fit_slope([r["seconds_per_call"] for r in fit_rows],
                                                          [r["rel_rms_error"] for r in fit_rows])
                entry["slope_error_vs_samples"] = _fit_slope([r["samples_per_meter"] for r in fit_rows],
                                                             [r["rel_rms_error"] for r in fit_rows])
            else:
                entry["slope_error_vs_time"] = None
                entry["slope_error_vs_samples"] = None
                entry["note"] = ("no Monte Carlo error to fit: every preset is exact to float32 rounding "
                                 "(a delta light is sampled exactly by every path)")
            out["scenes"][label] = entry
            log(f"  error-vs-time {label}: slope {entry['slope_error_vs_time']}")
    finally:
        for key in [k for k in quality_presets.PRESETS if k.startswith("bench_")]:
            del quality_presets.PRESETS[key]
    return out


# --- 5. against the manual way ----------------------------------------------------------------------

def bench_manual():
    """A user renders a full-HD frame of a white card and averages its pixels: E = pi L / albedo."""
    albedo, card, cam_height = 0.8, 0.05, 0.25
    width, height, card_px = 1920, 1080, 400
    scene = scenes.area_lit()
    point = (0.0, 0.0, 0.0)
    exact = api.measure_illuminance(point, method="analytic").irradiance
    # Bias of averaging over the card instead of reading a point: closed form over an 11 x 11 grid.
    g = np.linspace(-card / 2, card / 2, 11)
    grid = np.c_[np.repeat(g, 11), np.tile(g, 11), np.zeros(121)]
    card_mean = float(np.mean([r.irradiance for r in api.measure_illuminance(grid, method="analytic")]))

    # Radiometer's render path (standard preset) on the same scene without the card.
    api.measure_illuminance(point, method="render")
    runs = [timed(lambda: api.measure_illuminance(point, method="render", quality="standard"))
            for _ in range(7)]
    t_meter = median([t for t, _ in runs])
    stated = median([r.rel_std_error for _, r in runs])
    actual = median([abs(r.irradiance / exact - 1) for _, r in runs])

    # The card and the camera (perspective, looking straight down; the card spans card_px pixels).
    quad = [(-card / 2, -card / 2, 0), (card / 2, -card / 2, 0), (card / 2, card / 2, 0), (-card / 2, card / 2, 0)]
    scenes.quad_mesh(scene, "white card", [quad], scenes.diffuse_material("white card", albedo))
    cam_data = bpy.data.cameras.new("manual camera")
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.angle = 2 * math.atan((card / 2) / cam_height * (width / 2) / (card_px / 2))
    cam = bpy.data.objects.new("manual camera", cam_data)
    cam.location = (0.0, 0.0, cam_height)
    scene.collection.objects.link(cam)
    scene.camera = cam
    depsgraph = bpy.context.evaluated_depsgraph_get()
    render_settings.apply(scene, samples=1, bounces=8, needs=render_settings.scene_needs(scene, depsgraph))
    scene.view_settings.view_transform = "Standard"
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    ims = r.image_settings
    if hasattr(ims, "media_type"):
        ims.media_type = "IMAGE"
    ims.file_format, ims.color_depth = "OPEN_EXR", "32"
    folder = tempfile.mkdtemp(prefix="radiometer_bench_")
    margin = 3
    lo_x, hi_x = width // 2 - card_px // 2 + margin, width // 2 + card_px // 2 - margin
    lo_y, hi_y = height // 2 - card_px // 2 + margin, height // 2 + card_px // 2 - margin

    def manual(samples, seed):
        scene.cycles.samples, scene.cycles.seed = samples, seed
        r.filepath = os.path.join(folder, f"frame_{samples}_{seed}")
        assert bpy.ops.render.render(write_still=True) == {"FINISHED"}
        img = exr.read_rgb(r.filepath + ".exr")
        lum = img[lo_y:hi_y, lo_x:hi_x] @ np.array([0.2126, 0.7152, 0.0722])
        e = math.pi * lum / albedo
        return float(e.mean()), float(e.std(ddof=1) / math.sqrt(e.size) / e.mean())

    pilot = {}
    try:
        for samples in (1, 4):
            runs = [timed(lambda s=samples, k=k: manual(s, k)) for k in range(3)]
            pilot[samples] = {"median_s": median([t for t, _ in runs]),
                              "estimates": [v[0] for _, v in runs],
                              "rel_std_error_from_pixels": median([v[1] for _, v in runs])}
    finally:
        for name in os.listdir(folder):
            os.remove(os.path.join(folder, name))
        os.rmdir(folder)
    # Time model t(N) = a + b N from the two pilot sample counts; error follows 1/sqrt(N).
    b = (pilot[4]["median_s"] - pilot[1]["median_s"]) / 3.0
    a = pilot[1]["median_s"] - b
    s1 = pilot[1]["rel_std_error_from_pixels"]
    s1_seeds = float(np.std(pilot[1]["estimates"], ddof=1) / np.mean(pilot[1]["estimates"]))
    needed = s1 ** 2 / stated ** 2
    samples_needed = max(1, math.ceil(needed))
    t_manual = a + b * samples_needed
    return {
        "scene": "1 m square area light 1 m above the point, black world",
        "radiometer_standard_s": t_meter, "radiometer_stated_rel_error": stated,
        "radiometer_actual_rel_error": actual,
        "card": {"albedo": albedo, "side_m": card, "pixels_on_card": (hi_x - lo_x) * (hi_y - lo_y),
                 "frame": f"{width}x{height}", "bias_card_average_vs_point": card_mean / exact - 1},
        "pilot": pilot, "rel_std_error_1spp_pixels": s1, "rel_std_error_1spp_seed_spread_3_renders": s1_seeds,
        "samples_needed_exact": needed, "samples_needed": samples_needed,
        "time_model": {"a_s": a, "b_s_per_sample": b}, "manual_time_s": t_manual,
        "ratio_manual_over_radiometer": t_manual / t_meter,
        "extrapolated": samples_needed > 4,
    }


# --- 6. scene size ----------------------------------------------------------------------------------

def bench_scene_size():
    sizes = (2, 10_000, 100_000) if QUICK else (2, 10_000, 100_000, 1_000_000)
    rows = []
    for count in sizes:
        scene = scenes.delta_lit()
        _obj, tris = scenes.add_triangles(scene, count)
        api.measure_illuminance((0.0, 0.0, 0.0), method="render")  # warm-up
        pts, normals = scenes.meter_points(100, half_width=1.5, seed=6)
        t1 = median([timed(lambda: api.measure_illuminance((0.0, 0.0, 0.0), method="render"))[0]
                     for _ in range(3)])
        t100 = median([timed(lambda: api.measure_illuminance(pts, normals, method="render"))[0]
                       for _ in range(3)])
        rows.append({"triangles": tris, "one_meter_s": t1, "hundred_meters_s": t100,
                     "ms_per_meter_in_100": 1e3 * t100 / 100})
        log(f"  scene size {tris}: 1 meter {t1:.3f} s, 100 meters {t100:.3f} s")
    base = rows[0]["one_meter_s"]
    for row in rows:
        row["one_meter_vs_smallest"] = row["one_meter_s"] / base
        row["sync_cost_s"] = row["one_meter_s"] - base
        row["per_meter_in_100_vs_one_meter"] = row["ms_per_meter_in_100"] / (1e3 * row["one_meter_s"])
    return {"rows": rows, "note": "grid of triangles 0.5 m below the meters (geometry forces 8 bounces); "
                                  "sync cost = t(1 meter) minus t(1 meter, 2 triangles)"}


# --- 7. memory --------------------------------------------------------------------------------------

def bench_memory():
    n = 200 if QUICK else 1000
    scenes.delta_lit()
    rng = np.random.default_rng(7)
    api.measure_illuminance((0.0, 0.0, 0.0), method="render")
    counts_before = data_counts()
    rss = []
    t0 = time.perf_counter()
    for k in range(n):
        p = (rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0)
        api.measure_illuminance(p, method="render", quality="standard", seed=k)
        if k in (9, 99) or (k + 1) % 100 == 0:
            rss.append((k + 1, rss_mb()))
    seconds = time.perf_counter() - t0
    counts_after = data_counts()
    base = dict(rss)[10]
    growth = rss[-1][1] - base
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    return {"readings": n, "rss_mb_after": rss, "growth_mb_from_10th": growth,
            "peak_rss_mb_process": peak, "goal_growth_mb": 50.0, "met": growth < 50.0,
            "data_counts_unchanged": counts_before == counts_after,
            "data_counts": counts_after, "seconds": seconds}


# --- report -----------------------------------------------------------------------------------------

def machine():
    cpu = "unknown"
    with contextlib.suppress(OSError):
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    return {"nproc": os.cpu_count(), "cpu": cpu, "python": platform.python_version(),
            "bpy": bpy.app.version_string, "numpy": np.__version__, "platform": platform.platform(),
            "date_utc": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "load_average_at_start": os.getloadavg()}


def yes(flag):
    return "met" if flag else "**NOT met**"


def markdown(res):
    m = res["machine"]
    out = ["# Radiometer benchmarks", "",
           f"Machine: {m['nproc']} cores ({m['cpu']}), Python {m['python']}, bpy {m['bpy']}, numpy {m['numpy']}; "
           f"{m['date_utc']}; load average at start {', '.join(f'{x:.1f}' for x in m['load_average_at_start'])} "
           "(the machine is shared: only ratios within this run are meaningful).",
           f"Total run time {res['total_seconds']:.0f} s. Generated by `make bench` (bench/run.py); raw numbers in "
           "bench/results.json.", ""]
    if "overhead" in res:
        out += ["## 1. Overhead of a render-based reading", "",
                "Radiometer's `measure_illuminance(method='render', quality='standard')` vs the same sensor quad "
                "and the same `bpy.ops.object.bake` call set up once by hand (same Cycles settings), timed "
                "interleaved, medians. Goal: ratio <= 1.1.", "",
                "| scene | reps | reading (s) | bare bake (s) | ratio | goal |", "|---|---|---|---|---|---|"]
        for r in res["overhead"]["rows"]:
            out.append(f"| {r['scene']} | {r['reps']} | {r['median_reading_s']:.4f} | {r['median_bare_bake_s']:.4f} "
                       f"| {r['ratio']:.3f} | {yes(r['met'])} |")
        out.append("")
    if "batching" in res:
        b = res["batching"]
        out += ["## 2. Batching: N meters in one call (standard preset)", "",
                "Goal: 100 meters <= 3 x one meter.", "",
                "'in Cycles' = share of the call spent inside `bpy.ops.object.bake` (scene sync + path tracing); "
                "the rest is Radiometer's own work (checks, snapshot/restore, sensor mesh, read-back).", "",
                "| scene | meters | median (s) | / one meter | ms per meter | in Cycles |", "|---|---|---|---|---|---|"]
        for r in b["rows"]:
            out.append(f"| {r['scene']} | {r['meters']} | {r['median_s']:.4f} | {r['ratio_to_1']:.2f} | "
                       f"{r['ms_per_meter']:.2f} | {100 * r['share_in_cycles_bake']:.0f} % |")
        out += ["", "Goal: " + "; ".join(f"{s}: {yes(v)}" for s, v in b["met"].items()), ""]
    if "analytic" in res:
        a = res["analytic"]
        out += ["## 3. Analytic path", "",
                f"Vectorised point-light model (`radiometry.lights.irradiance`) at {a['points']:,} receivers in one "
                f"call: {a['seconds_per_call'] * 1e3:.1f} ms, **{a['point_evals_per_s']:.3g} evaluations/s** "
                f"(goal >= 1e6/s: {yes(a['met'])}).", "",
                "| predict_illuminance, one point | time (ms) | of which light models (ms) |", "|---|---|---|"]
        for key in ("100 lights, no geometry", "100 lights in the closed room"):
            v = a[key]
            out.append(f"| {key} | {v['predict_illuminance_s'] * 1e3:.1f} | {v['model_evaluation_only_s'] * 1e3:.1f} |")
        out.append("")
    if "error_vs_time" in res:
        e = res["error_vs_time"]
        out += ["## 4. Error vs time per quality preset", "",
                "Error = RMS over the meters of (reading - reference), relative to the RMS reference; 'stated' = "
                "the RMS of the readings' own standard errors on the same scale (error/stated near 1 means the "
                "stated error is honest). `bench_sN` rows are a sample sweep (N samples x 16 texels x 1 bake, the "
                "reference's bounce limit) used for the fit; the presets keep their own bounce limits. "
                "Expected slope of log(error) vs log(samples): -1/2.", ""]
        for label, entry in e["scenes"].items():
            out += [f"### {label}", "", f"{entry['meters']} meters per call. Reference: {entry['reference']}.", "",
                    "| preset | samples/meter | bounces | s per call | rel. RMS error | stated rel. s.e. | error/stated |",
                    "|---|---|---|---|---|---|---|"]
            for r in entry["rows"]:
                ratio = "" if r["error_over_stated"] is None else f"{r['error_over_stated']:.2f}"
                out.append(f"| {r['preset']} | {r['samples_per_meter']} | {r['bounces']} | "
                           f"{r['seconds_per_call']:.3f} | {r['rel_rms_error']:.3g} | "
                           f"{r['stated_rel_std_error']:.3g} | {ratio} |")
            if entry["slope_error_vs_time"] is not None:
                out += ["", f"Fitted slope (sweep rows): {entry['slope_error_vs_samples']:.3f} vs samples, "
                            f"{entry['slope_error_vs_time']:.3f} vs time (expect -0.5; time includes the fixed "
                            "sync cost, which steepens the slope vs time)."]
            else:
                out += ["", entry["note"] + "."]
            out.append("")
    if "manual" in res:
        mm = res["manual"]
        out += ["## 5. Against the manual way (full-HD frame of a white card)", "",
                f"Scene: {mm['scene']}. Manual: a {mm['card']['side_m']} m card of albedo {mm['card']['albedo']} filling "
                f"{mm['card']['pixels_on_card']:,} pixels of a {mm['card']['frame']} frame, measurement-grade Cycles "
                "settings (the most favourable case for the manual way), 32-bit EXR written and read, "
                "E = pi x mean(L) / albedo.", "",
                "| | value |", "|---|---|",
                f"| Radiometer standard reading (s) | {mm['radiometer_standard_s']:.4f} |",
                f"| its stated rel. s.e. / actual error vs closed form | {mm['radiometer_stated_rel_error']:.2e} / "
                f"{mm['radiometer_actual_rel_error']:.2e} |",
                f"| manual frame, 1 spp (s) | {mm['pilot'][1]['median_s']:.3f} |",
                f"| manual frame, 4 spp (s) | {mm['pilot'][4]['median_s']:.3f} |",
                f"| manual rel. s.e. at 1 spp (pixel spread; 3-seed spread) | {mm['rel_std_error_1spp_pixels']:.2e}; "
                f"{mm['rel_std_error_1spp_seed_spread_3_renders']:.2e} |",
                f"| samples per pixel needed for the same error (1/sqrt(N) law) | {mm['samples_needed_exact']:.3g} -> "
                f"{mm['samples_needed']} |",
                f"| manual time to that error (t = a + b N fitted to 1 and 4 spp) (s) | {mm['manual_time_s']:.3f} |",
                f"| **ratio manual / Radiometer** | **{mm['ratio_manual_over_radiometer']:.1f}** |",
                f"| bias of the card average vs the point value (closed form) | "
                f"{mm['card']['bias_card_average_vs_point']:.2e} |", ""]
        if mm["extrapolated"]:
            out += ["The manual time is EXTRAPOLATED with the fitted t(N) and the measured 1/sqrt(N) law.", ""]
        else:
            out += ["No extrapolation was needed: the manual frame reaches the error within the pilot sample "
                    "counts (its cost is one full-HD render: sync, film and EXR I/O).", ""]
    if "scene_size" in res:
        out += ["## 6. Scene size", "", res["scene_size"]["note"] + ".", "",
                "| triangles | 1 meter (s) | / 2 triangles | sync cost (s) | 100 meters (s) | ms/meter in 100 | "
                "per-meter cost in 100 / one meter |", "|---|---|---|---|---|---|---|"]
        for r in res["scene_size"]["rows"]:
            out.append(f"| {r['triangles']:,} | {r['one_meter_s']:.3f} | {r['one_meter_vs_smallest']:.2f} | "
                       f"{r['sync_cost_s']:.3f} | {r['hundred_meters_s']:.3f} | {r['ms_per_meter_in_100']:.2f} | "
                       f"{r['per_meter_in_100_vs_one_meter']:.3f} |")
        out.append("")
    if "memory" in res:
        mem = res["memory"]
        out += ["## 7. Memory", "",
                f"{mem['readings']} single-meter render readings in a row in one process ({mem['seconds']:.0f} s): "
                f"RSS growth after the 10th reading {mem['growth_mb_from_10th']:.1f} MB (goal < 50 MB: "
                f"{yes(mem['met'])}); peak RSS of the whole bench process so far {mem['peak_rss_mb_process']:.0f} MB; "
                f"bpy.data counts unchanged: {mem['data_counts_unchanged']}.", "",
                "| readings done | RSS (MB) |", "|---|---|"]
        out += [f"| {k} | {v:.1f} |" for k, v in mem["rss_mb_after"]]
        out.append("")
    return "\n".join(out)


BENCHES = {"overhead": bench_overhead, "batching": bench_batching, "analytic": bench_analytic,
           "error_vs_time": bench_error_vs_time, "manual": bench_manual, "scene_size": bench_scene_size,
           "memory": bench_memory}


def main(argv=None):
    global QUICK
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes (a smoke run, not for results)")
    parser.add_argument("--only", nargs="*", choices=list(BENCHES), help="run only these benchmarks")
    parser.add_argument("--out", default=HERE, help="folder for results.json and results.md")
    args = parser.parse_args(argv)
    QUICK = args.quick
    results = {"machine": machine(), "quick": QUICK}
    started = time.perf_counter()
    # Memory first: its RSS curve must not include the large scenes of the other benchmarks.
    order = ["memory"] + [k for k in BENCHES if k != "memory"]
    for name in order:
        if args.only and name not in args.only:
            continue
        log(f"bench: {name} ...")
        with quiet_stdout():
            t, results[name] = timed(BENCHES[name])
        log(f"bench: {name} done in {t:.0f} s")
    results["total_seconds"] = time.perf_counter() - started
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "results.json"), "w", encoding="utf-8") as f:
        json.dump(results, f, indent=2, default=float)
        f.write("\n")
    with open(os.path.join(args.out, "results.md"), "w", encoding="utf-8") as f:
        f.write(markdown(results) + "\n")
    log(f"bench: wrote {args.out}/results.json and results.md ({results['total_seconds']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

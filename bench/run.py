"""`make bench`: Radiometer's benchmarks (issues 6 and 10), one process, results in bench/results.{json,md}.

Speed is only ever reported as a RATIO of two things timed in the same run (interleaved where it
matters, medians of repetitions): the machine (2 cores) is shared and absolute seconds drift from run
to run. Every goal is evaluated and written down as met or NOT met, with a measured breakdown
(scene capture, visibility proofs, Cycles bakes, the rest) where it is not.

Usage: ``.venv/bin/python bench/run.py [--quick] [--only NAME ...]``.
"""

import argparse
import collections
import contextlib
import datetime
import json
import math
import os
import platform
import resource
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import bpy  # noqa: E402

import scenes  # noqa: E402
import speed  # noqa: E402
from radiometer import api  # noqa: E402
from radiometer import quality as quality_presets  # noqa: E402
from radiometer.measure.render import adaptive, render_settings, sensors
from radiometer.measure.capture import capture_cache, scene_capture
from radiometer.measure.meter import point_meter as meter
from radiometer.measure.blender import scene_guard  # noqa: E402
from radiometer.radiometry.sampling import allocation  # noqa: E402

QUICK = False
CORES = os.cpu_count() or 1


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


def as_list(readings):
    return readings if isinstance(readings, list) else [readings]


# --- profiling: where a measurement's time goes ------------------------------------------------------

#: (module, function, phase label). Patched by attribute, so every call site that looks the name up
#: in its module at call time (all of meter/adaptive/allocation do) is timed.
_PHASES = (
    (meter, "capture_model", "scene capture (probe render: sync + triangles to numpy)"),
    (meter, "sensor_points", "sensor placement (surface proximity test)"),
    (meter, "plan", "visibility proofs (scene_model.plan_direct)"),
    (meter, "placement_notes", "placement notes"),
    (meter, "analytic_irradiance", "closed forms"),
    (sensors, "build_sensor", "sensor objects (build_sensor, every round)"),
    (sensors, "run_bake", "Cycles bakes (sync + path tracing)"),
    (sensors, "read_blocks", "read-back of bake images"),
    (adaptive, "render_hybrid", None),
)


class Profile:
    """Times the phases of ``meter.measure_illuminance`` and keeps the last ``render_hybrid`` result."""

    def __init__(self):
        self.seconds = collections.defaultdict(float)
        self.calls = collections.Counter()
        self.durations = collections.defaultdict(list)
        self.runs = []
        self._saved = []

    def __enter__(self):
        for module, name, _label in _PHASES:
            original = getattr(module, name)
            self._saved.append((module, name, original))

            def wrapper(*args, __original=original, __name=name, **kwargs):
                t0 = time.perf_counter()
                try:
                    out = __original(*args, **kwargs)
                finally:
                    dt = time.perf_counter() - t0
                    self.seconds[__name] += dt
                    self.calls[__name] += 1
                    self.durations[__name].append(dt)
                if __name == "render_hybrid":
                    self.runs.append(out)
                return out

            setattr(module, name, wrapper)
        return self

    def __exit__(self, *exc):
        for module, name, original in reversed(self._saved):
            setattr(module, name, original)
        self._saved.clear()
        return False

    def breakdown(self, total):
        """Phase -> seconds (and the rest), for the markdown tables."""
        out = {}
        for _module, name, label in _PHASES:
            if label is not None and self.calls[name]:
                out[name] = {"label": label, "seconds": self.seconds[name], "calls": self.calls[name]}
        hybrid = self.seconds["render_hybrid"]
        inside = sum(self.seconds[n] for n in ("build_sensor", "run_bake", "read_blocks"))
        out["allocation_python"] = {"label": "allocation + light linking + sensor cleanup (Python, rounds)",
                                    "seconds": max(hybrid - inside, 0.0), "calls": self.calls["render_hybrid"]}
        known = sum(v["seconds"] for k, v in out.items())
        out["other"] = {"label": "everything else (inputs, photometry, readings, guard)",
                        "seconds": max(total - known, 0.0), "calls": 1}
        return out

    def rounds(self):
        """Per round of the last run: spp, meters baked, samples, bake seconds."""
        if not self.runs:
            return []
        run = self.runs[-1]
        bakes = self.durations["run_bake"][-len(run["round_log"]):]
        rows = []
        for r, dt in zip(run["round_log"], bakes):
            texels = np.asarray(r["texels"])
            rows.append({"spp": int(r["spp"]), "meters": int((texels > 0).sum()),
                         "samples": float(r["spp"] * texels.sum()), "bake_s": dt})
        return rows


def reading_stats(readings, target):
    rel = np.array([r.rel_std_error for r in readings])
    spent = np.array([r.samples for r in readings], float)
    # Allocation efficiency: samples a meter would have needed to land exactly on the target
    # (1/N law, conservative for Cycles' QMC) over what it got.
    ideal = spent * (rel / target) ** 2 if target else spent
    return {"worst_rel_error": float(rel.max()), "mean_rel_error": float(rel.mean()),
            "all_within_target": bool(np.all(rel <= target)) if target else None,
            "samples_total": float(spent.sum()), "samples_median": float(np.median(spent)),
            "samples_max": float(spent.max()), "samples_min": float(spent.min()),
            "overshoot_samples_over_needed": float(spent.sum() / max(ideal.sum(), 1e-300)),
            "methods": sorted(set(r.method for r in readings))}


def fit_time_model(rounds):
    """t = a + b * samples over rounds (a = a bake's fixed cost, b = seconds per sample)."""
    if len(rounds) < 2:
        return None, None
    s = np.array([r["samples"] for r in rounds])
    t = np.array([r["bake_s"] for r in rounds])
    if np.ptp(s) == 0:
        return None, None
    b, a = np.polyfit(s, t, 1)
    return float(a), float(b)


# --- a bare bake by hand ---------------------------------------------------------------------------

class BareSensor:
    """One sensor patch baked by hand with bpy: one quad, one image, one bake.

    Cycles settings: the ones Radiometer writes (``render_settings.apply`` once, same bounces);
    everything else (quad, UVs, white diffuse material, float image, selection, the bake call) is
    plain bpy. ``bake(total_samples)`` bakes a 4 x 4 image at total/16 samples per texel, so the
    patch gets the same total samples as the reading it is compared with."""

    TEXELS = 4

    def __init__(self, scene, point, normal, bounces, needs):
        render_settings.apply(scene, samples=64, bounces=bounces, needs=needs)
        p, n = np.asarray(point, float), np.asarray(normal, float)
        t = np.cross([1.0, 0.0, 0.0] if abs(n[2]) > 0.9 else [0.0, 0.0, 1.0], n)
        t /= np.linalg.norm(t)
        b = np.cross(n, t)
        h = 1e-5
        p = p + n * 5e-6  # a meter on a surface: lift the patch off it, as Radiometer does
        verts = [tuple(p + h * (su * t + sv * b)) for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        mesh = bpy.data.meshes.new("bench bare patch")
        mesh.from_pydata(verts, [], [(0, 1, 2, 3)])
        uv = mesh.uv_layers.new(name="uv")
        for loop, co in zip(uv.data, ((0, 0), (1, 0), (1, 1), (0, 1))):
            loop.uv = co
        mat = scenes.diffuse_material("bench bare patch", 1.0)
        self.image = bpy.data.images.new("bench bare patch", self.TEXELS, self.TEXELS, alpha=False,
                                         float_buffer=True)
        self.image.colorspace_settings.is_data = True
        tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = self.image
        mat.node_tree.nodes.active = tex
        mesh.materials.append(mat)
        self.obj = obj = bpy.data.objects.new("bench bare patch", mesh)
        scene.collection.objects.link(obj)
        for attr in ("visible_diffuse", "visible_glossy", "visible_transmission", "visible_volume_scatter",
                     "visible_shadow"):
            setattr(obj, attr, False)
        self.scene = scene
        self.seed = 0

    def bake(self, total_samples):
        scene, obj = self.scene, self.obj
        scene.cycles.samples = max(1, int(round(total_samples / self.TEXELS ** 2)))
        scene.cycles.seed = self.seed
        self.seed += 1
        view_layer = bpy.context.view_layer
        for other in view_layer.objects:
            other.select_set(other == obj)
        view_layer.objects.active = obj
        with bpy.context.temp_override(active_object=obj, object=obj, selected_objects=[obj],
                                       selected_editable_objects=[obj]):
            result = bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"}, margin=0,
                                         use_clear=True, target="IMAGE_TEXTURES")
        assert result == {"FINISHED"}
        px = np.empty(self.TEXELS ** 2 * 4, np.float32)
        self.image.pixels.foreach_get(px)
        e = math.pi * px.reshape(-1, 4)[:, :3].astype(float)
        y = e @ np.array([0.2126, 0.7152, 0.0722])
        return float(y.mean()), float(y.std(ddof=1) / math.sqrt(len(y)) / abs(y.mean()))

    def hidden(self):
        """Context: the bare patch must not take part in Radiometer's own measurement."""
        obj = self.obj

        @contextlib.contextmanager
        def cm():
            obj.hide_render = True
            try:
                yield
            finally:
                obj.hide_render = False

        return cm()

    def remove(self):
        mesh = self.obj.data
        bpy.data.objects.remove(self.obj, do_unlink=True)
        bpy.data.meshes.remove(mesh)
        bpy.data.images.remove(self.image)


# --- 1. batching at equal error -------------------------------------------------------------------

TARGET = 0.01


def bench_batching():
    scene, tris = scenes.big_room()
    counts = (1, 10, 100) if QUICK else (1, 10, 100, 1000)
    reps = {1: 3, 10: 2, 100: 2} if QUICK else {1: 9, 10: 5, 100: 5, 1000: 1}
    pts0, nrm0 = scenes.floor_meters(1, seed=11)
    api.measure_illuminance(pts0, nrm0, target_rel_error=TARGET)  # warm-up (kernels, caches)
    rows = []
    for n in counts:
        pts, nrm = scenes.floor_meters(n, seed=100 + n)
        if n == 1:
            pts, nrm = pts0, nrm0
        times, stats, profiles = [], [], []
        for rep in range(reps[n]):
            with Profile() as prof:
                dt, rs = timed(lambda: as_list(api.measure_illuminance(pts, nrm, target_rel_error=TARGET, seed=rep)))
            times.append(dt)
            stats.append(reading_stats(rs, TARGET))
            profiles.append((dt, prof))
        k = int(np.argsort(times)[len(times) // 2])  # the median run's breakdown
        dt, prof = profiles[k]
        rows.append({"meters": n, "reps": reps[n], "median_s": median(times), "times_s": times,
                     "worst_rel_error": max(s["worst_rel_error"] for s in stats),
                     "all_within_target": all(s["all_within_target"] for s in stats),
                     "readings": stats[k], "breakdown": prof.breakdown(dt), "rounds": prof.rounds(),
                     "sensor_groups": prof.runs[-1]["groups"] if prof.runs else None})
        log(f"  batching {n}: {median(times):.3f} s, worst {rows[-1]['worst_rel_error']:.4f}, "
            f"samples {stats[k]['samples_total']:.0f}")
    base = rows[0]
    for row in rows:
        row["ratio_to_1"] = row["median_s"] / base["median_s"]
        row["samples_ratio_to_1"] = row["readings"]["samples_total"] / base["readings"]["samples_total"]
    # How many of the 100 meters see the area light partly hidden (rendered direct light).
    pts, nrm = scenes.floor_meters(100, seed=200)
    model = meter.capture_model(scene, bpy.context.view_layer)
    direct = meter.plan(scene, model, pts + nrm * 5e-6, nrm, "auto")["direct"]
    from radiometer.radiometry.scene import scene_model

    partial = int(np.any(direct.status == scene_model.RENDER, axis=0).sum())
    zero = int(np.any(direct.status == scene_model.ZERO, axis=0).sum())
    row100 = next(r for r in rows if r["meters"] == 100)
    r100 = row100["ratio_to_1"]
    # Sampling-only bound: seconds per sample of the 100-meter run's bakes (fitted over its rounds).
    a, b = fit_time_model(row100["rounds"])
    return {"triangles": tris, "scene": "closed 6 x 5 x 3 m room (subdivided scaled cube, albedo 0.6), 4 furniture "
                                        "boxes, 1.2 m square ceiling area light 300 W, radius-0 point light 60 W; "
                                        "meters lying on the floor",
            "target": TARGET, "rows": rows, "ratio_100": r100, "goal": 1.5, "bar": 3.0,
            "goal_met": r100 <= 1.5, "bar_met": r100 <= 3.0,
            "meters_of_100_with_partly_occluded_light": partial, "meters_of_100_in_full_shadow_of_a_light": zero,
            "bake_time_model_100": {"fixed_s_per_bake": a, "s_per_sample": b}}


# --- 2. overhead ----------------------------------------------------------------------------------

def bench_overhead():
    reps = 3 if QUICK else 9
    rows = []
    for label, build, point in (("130k-triangle room (issue 10)", lambda: scenes.big_room()[0], (-0.8, 0.9, 0.0)),
                                ("small interreflecting room", scenes.room, (0.3, 0.2, 0.75))):
        scene = build()
        normal = (0.0, 0.0, 1.0)
        first = api.measure_illuminance(point, normal, target_rel_error=TARGET)  # warm-up; its samples
        model = meter.capture_model(scene, bpy.context.view_layer)
        bare = BareSensor(scene, point, normal, bounces=quality_presets.PRESETS["standard"]["bounces"],
                          needs=model.needs)
        t_meter, t_bare, t_bare1, samples, bare_err = [], [], [], [], []
        t_same, samples_same = [], []  # issue 17: the same reading again, nothing changed in between
        profiles = []
        edits = {"lights": [], "geometry": []}  # issue 17: right after a lights-only / a geometry edit

        bare.bake(first.samples)
        for k in range(reps):
            for which in (("reading", "bare", "bare1") if k % 2 == 0 else ("bare1", "bare", "reading")):
                if which == "reading":
                    with bare.hidden():
                        with Profile() as prof:
                            dt, r = timed(lambda: api.measure_illuminance(point, normal, target_rel_error=TARGET,
                                                                          seed=len(t_meter)))
                        # The bare bake changed the scene (its settings, the patch's visibility): the
                        # reading above captured it again; this one keeps that capture.
                        dt_same, r_same = timed(lambda: api.measure_illuminance(
                            point, normal, target_rel_error=TARGET, seed=100 + len(t_meter)))
                        for kind in ("lights", "geometry"):  # bench/speed.py edited_reading
                            before = capture_cache.stats()
                            with Profile() as prof_edit:
                                dt_edit, r_edit = speed.edited_reading(kind, scene, point, normal, TARGET,
                                                                       seed=200 + len(t_meter))
                            after = capture_cache.stats()
                            delta = {k: after[k] - before[k] for k in ("light_recaptures", "misses",
                                                                        "partial_captures")}
                            edits[kind].append((dt_edit, r_edit.samples, prof_edit, delta["light_recaptures"],
                                                delta["misses"] - delta["light_recaptures"]
                                                - delta["partial_captures"], delta["partial_captures"]))
                    t_same.append(dt_same)
                    samples_same.append(r_same.samples)
                    t_meter.append(dt)
                    samples.append(r.samples)
                    profiles.append((dt, prof))
                elif which == "bare":
                    # Same total samples as the latest reading (the first one at the start).
                    n = samples[-1] if samples else first.samples
                    dt, (_v, se) = timed(lambda: bare.bake(n))
                    t_bare.append(dt)
                    bare_err.append(se)
                else:
                    t_bare1.append(timed(lambda: bare.bake(16))[0])  # 1 sample per texel: ~ the fixed cost
        ratio = median(t_meter) / median(t_bare)
        dt, prof = sorted(profiles, key=lambda x: x[0])[len(profiles) // 2]  # the median reading
        rows.append({"scene": label, "reps": reps, "median_reading_s": median(t_meter),
                     "median_bare_bake_s": median(t_bare), "median_bare_bake_1spp_s": median(t_bare1),
                     "samples_per_reading": samples, "bare_rel_error_median": median(bare_err),
                     "ratio": ratio, "goal": 1.1, "bar": 1.5, "goal_met": ratio <= 1.1, "bar_met": ratio <= 1.5,
                     "syncs_per_reading": 1 + prof.calls["run_bake"], "breakdown": prof.breakdown(dt),
                     "rounds": prof.rounds(), "median_reading_unchanged_s": median(t_same),
                     "samples_per_reading_unchanged": samples_same, "ratio_unchanged": median(t_same) / median(t_bare)})
        for kind, runs in edits.items():
            dt_e, prof_e = sorted([(x[0], x[2]) for x in runs], key=lambda x: x[0])[len(runs) // 2]
            rows[-1].setdefault("edits", {})[kind] = {
                "reps": len(runs), "median_s": median([x[0] for x in runs]), "samples": [x[1] for x in runs],
                "ratio": median([x[0] for x in runs]) / median(t_bare), "breakdown": prof_e.breakdown(dt_e),
                "light_recaptures": sum(x[3] for x in runs), "full_captures": sum(x[4] for x in runs),
                "partial_captures": sum(x[5] for x in runs)}
        bare.remove()
        log(f"  overhead {label}: {ratio:.2f} (reading {median(t_meter):.3f} s, bare {median(t_bare):.3f} s, "
            f"bare 1 spp {median(t_bare1):.3f} s)")
    return {"rows": rows}


# --- 3. throughput --------------------------------------------------------------------------------

def bench_throughput():
    n = 200 if QUICK else 1000
    scene = scenes.room()
    pts, nrm = scenes.meter_points(n, half_width=1.8, z=0.75, seed=3)
    api.measure_illuminance(pts[:2], nrm[:2], target_rel_error=TARGET)  # warm-up
    with Profile() as prof:
        t_ours, rs = timed(lambda: api.measure_illuminance(pts, nrm, target_rel_error=TARGET, seed=1))
    st = reading_stats(rs, TARGET)
    ours = {"seconds": t_ours, "meters_per_s_per_core": n / t_ours / CORES, **st,
            "breakdown": prof.breakdown(t_ours), "rounds": prof.rounds(),
            "irradiance_W_m2": [r.irradiance for r in rs],  # for the Radiance section's cross-check
            "pooled": sum(r.method.endswith("+pooled") for r in rs)}  # issue 17: the default pools (bench/pooled.py)
    log(f"  throughput ours: {t_ours:.1f} s, {ours['meters_per_s_per_core']:.1f} meters/s/core")

    # Brute force A: one bare bake per meter at the total samples the allocator chose for it
    # (the full light: the bare patch does not know the hybrid split), on a random subset.
    sub = 10 if QUICK else 100
    rng = np.random.default_rng(5)
    pick = rng.choice(n, sub, replace=False)
    model = meter.capture_model(scene, bpy.context.view_layer)
    t_a, errs = 0.0, []
    for k in pick:
        bare = BareSensor(scene, pts[k], nrm[k], bounces=quality_presets.PRESETS["standard"]["bounces"],
                          needs=model.needs)
        dt, (_v, se) = timed(lambda: bare.bake(rs[k].samples))
        t_a += dt
        errs.append(se)
        bare.remove()
    per_meter_a = t_a / sub
    brute_a = {"meters_timed": sub, "seconds_per_meter": per_meter_a, "seconds_for_all": per_meter_a * n,
               "meters_per_s_per_core": 1.0 / per_meter_a / CORES,
               "rel_error_median": median(errs), "rel_error_max": float(max(errs))}
    log(f"  throughput brute A: {per_meter_a * n:.1f} s for {n} (worst error {max(errs):.4f})")

    # Brute force B: the same call with a FIXED sample count per meter, the hardest meter's count.
    fixed = int(st["samples_max"])
    t_b, rb = timed(lambda: api.measure_illuminance(pts, nrm, samples=fixed, seed=2))
    sb = reading_stats(rb, TARGET)
    brute_b = {"samples_per_meter": fixed, "seconds": t_b, "meters_per_s_per_core": n / t_b / CORES,
               "worst_rel_error": sb["worst_rel_error"], "all_within_target": sb["all_within_target"]}
    log(f"  throughput brute B: {t_b:.1f} s at {fixed} samples/meter (worst {sb['worst_rel_error']:.4f})")
    radiance = radiance_status()
    return {"meters": n, "scene": "closed 4 x 4 x 3 m room (albedo 0.7, 6 quads), 1 m square ceiling area light, "
                                  "meters scattered at 0.75 m", "cores": CORES, "ours": ours,
            "brute_one_bake_per_meter": brute_a, "brute_fixed_samples": brute_b,
            "speedup_vs_one_bake_per_meter": per_meter_a * n / t_ours, "speedup_vs_fixed_samples": t_b / t_ours,
            "radiance": radiance}


def radiance_status():
    """Is Radiance (rtrace) here or installable? apt-cache only (no download)."""
    import shutil

    if speed.radiance_bin():
        return {"available": True, "note": "Radiance (rtrace from pyradiance, a bench-only dependency) is compared in "
                                           "the section 'Radiance comparison' below"}
    if shutil.which("rtrace"):
        return {"available": True, "note": "rtrace found on PATH (comparison not implemented in this run)"}
    try:
        out = subprocess.run(["apt-cache", "policy", "radiance"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired) as exc:
        return {"available": False, "note": f"apt-cache not usable ({exc})"}
    candidate = next((line.split(":", 1)[1].strip() for line in out.splitlines() if "Candidate:" in line), "(none)")
    return {"available": False, "apt_candidate": candidate,
            "note": "Radiance is not installed and `apt-cache policy radiance` (after apt-get update) shows "
                    f"candidate {candidate}: no package in this machine's Debian sources, so no rtrace -I comparison"}


# --- 4. hybrid vs full render ---------------------------------------------------------------------

def _demo():
    from radiometer.demo import scene as demo_scene

    scenes.fresh()
    scene = demo_scene.build(bpy.context.scene)
    bpy.context.view_layer.update()
    objs = [ob for ob in scene.objects if ob.radiometer_meter.is_meter and ob.radiometer_meter.kind == "ILLUMINANCE"]
    pts = np.array([np.array(ob.matrix_world.translation) for ob in objs])
    nrm = np.array([np.array(ob.matrix_world.to_3x3().col[2]) for ob in objs])
    return scene, pts, nrm, [ob.name for ob in objs]


def bench_hybrid():
    seeds = 2 if QUICK else 5
    out = {"target": TARGET, "seeds": seeds, "scenes": {}}
    cases = [(label, build, target) for label, build in (
        ("demo room (radiometer.demo.scene)", _demo),
        ("several lights (dark room albedo 0.15: 6 point + 1 spot, radius 0; small area light; table shadow)",
         lambda: (scenes.multi_light(), *scenes.multi_light_meters(), None))) for target in (TARGET, 0.002)]
    for label, build, target in cases:
        scene, pts, nrm, _names = build()
        api.measure_illuminance(pts[:1], nrm[:1], target_rel_error=0.05)  # warm-up
        entry = {"meters": len(pts), "target": target}
        if target == TARGET:
            # Per-sample relative spread of each meter's reading (rel. s.e. x sqrt(samples)) at a fixed
            # 8192 samples: what each method has to average away.
            spread_n = 8192
            entry["per_sample_rel_spread"] = {
                method: [r.rel_std_error * math.sqrt(spread_n) for r in as_list(api.measure_illuminance(
                    pts, nrm, method=method, samples=spread_n, seed=77))] for method in ("hybrid", "render")}
        runs = {"hybrid": [], "render": []}
        for k in range(seeds):
            for method in (("hybrid", "render") if k % 2 == 0 else ("render", "hybrid")):  # interleaved
                dt, rs = timed(lambda: as_list(api.measure_illuminance(pts, nrm, method=method,
                                                                       target_rel_error=target, seed=10 * k)))
                runs[method].append((dt, reading_stats(rs, target),
                                     [(r.irradiance, r.rel_std_error * abs(r.irradiance), r.samples) for r in rs]))
        values = {}
        for method, items in runs.items():
            times = [x[0] for x in items]
            stats = [x[1] for x in items]
            values[method] = np.array([x[2] for x in items])  # (seeds, meters, 3)
            entry[method] = {"median_s": median(times), "samples_total_median": median([s["samples_total"] for s in stats]),
                             "samples_max": max(s["samples_max"] for s in stats),
                             "samples_per_meter_median": np.median(values[method][..., 2], axis=0).tolist(),
                             "worst_rel_error": max(s["worst_rel_error"] for s in stats),
                             "all_within_target": all(s["all_within_target"] for s in stats),
                             "methods": sorted(set(m for s in stats for m in s["methods"]))}
        h, r = values["hybrid"], values["render"]
        diff = (h[..., 0].mean(0) - r[..., 0].mean(0)) / np.sqrt((h[..., 1] ** 2).mean(0) / seeds
                                                                 + (r[..., 1] ** 2).mean(0) / seeds)
        entry["hybrid_minus_render_in_se"] = diff.tolist()
        entry["time_ratio_render_over_hybrid"] = entry["render"]["median_s"] / entry["hybrid"]["median_s"]
        entry["samples_ratio_render_over_hybrid"] = (entry["render"]["samples_total_median"]
                                                     / entry["hybrid"]["samples_total_median"])
        out["scenes"][f"{label}, target {100 * target:g} %"] = entry
        log(f"  hybrid {label} {target}: hybrid {entry['hybrid']['median_s']:.2f} s / {entry['hybrid']['samples_total_median']:.0f}"
            f" samples; render {entry['render']['median_s']:.2f} s / {entry['render']['samples_total_median']:.0f}")
    return out


# --- 5. preset table ------------------------------------------------------------------------------

def _three_points():
    return np.array([[0.0, 0.0, 0.0], [0.6, -0.3, 0.0], [-0.9, 0.7, 0.0], [1.4, 1.1, 0.0], [-1.2, -1.3, 0.0],
                     [0.2, 0.9, 0.0]])


def _delta_scene():
    scene = scenes.fresh()
    for k, loc in enumerate(((0.0, 0.0, 2.0), (1.5, -0.5, 1.5), (-1.0, 1.2, 2.5))):
        scenes.light(scene, "POINT", loc, energy=100.0 - 20 * k, shadow_soft_size=0.0)
    return scene


def bench_presets():
    seeds = 2 if QUICK else 6
    pts = _three_points()
    nrm = np.tile([0.0, 0.0, 1.0], (len(pts), 1))
    room_pts = pts * 1.1 + np.array([0.0, 0.0, 0.75])
    out = {"seeds": seeds, "meters": len(pts), "scenes": {}}
    cases = (("delta-lit (3 radius-0 point lights)", _delta_scene, pts, "render",
              "closed form (exact; `auto` would return it with zero error)"),
             ("area-lit (1 m square, 1 m up)", lambda: scenes.area_lit(), pts * 0.7, "render",
              "closed form (Lambert polygon, exact; `auto` would return it)"),
             ("interreflecting room (4 x 4 x 3 m, albedo 0.7)", scenes.room, room_pts, "auto", None))
    ref_target = 0.002 if QUICK else 0.0005
    for label, build, p, method, ref_note in cases:
        build()
        api.measure_illuminance(p[:1], nrm[:1], method="render", target_rel_error=0.05)  # warm-up
        if ref_note is not None:
            ref = np.array([r.irradiance for r in api.measure_illuminance(p, nrm, method="analytic")])
            ref_var = np.zeros(len(p))
            ref_seconds = 0.0
        else:
            ref_seconds, rr = timed(lambda: api.measure_illuminance(p, nrm, method="render",
                                                                    target_rel_error=ref_target, seed=99_999))
            ref = np.array([r.irradiance for r in rr])
            ref_var = np.array([(r.rel_std_error * r.irradiance) ** 2 for r in rr])
            ref_note = (f"render (method='render', target {100 * ref_target:g} %: reached "
                        f"{100 * max(r.rel_std_error for r in rr):.3g} % worst, {ref_seconds:.0f} s); its "
                        "variance is subtracted from the squared errors")
        rows = []
        for name in ("preview", "standard", "reference"):
            target = quality_presets.PRESETS[name]["target"]
            times, rel_err, stated, spent, over = [], [], [], [], 0
            for s in range(seeds):
                dt, rs = timed(lambda: api.measure_illuminance(p, nrm, method=method, quality=name, seed=1000 * s + 1))
                times.append(dt)
                got = np.array([r.irradiance for r in rs])
                rel_err.append(((got - ref) ** 2 - ref_var) / ref ** 2)
                stated.append([r.rel_std_error for r in rs])
                spent.append([r.samples for r in rs])
                over += sum(1 for r in rs if r.rel_std_error > target)
            mse = float(np.mean(rel_err))
            rows.append({"preset": name, "target": target, "median_s": median(times),
                         "rms_rel_error": math.sqrt(max(mse, 0.0)), "mean_stated_rel_error": float(np.mean(stated)),
                         "max_stated_rel_error": float(np.max(stated)), "readings": seeds * len(p),
                         "readings_over_target": over, "samples_median": float(np.median(spent)),
                         "samples_max": float(np.max(spent)), "methods": sorted(set(r.method for r in rs))})
            log(f"  presets {label} {name}: {median(times):.3f} s, RMS {100 * rows[-1]['rms_rel_error']:.3g} %, "
                f"stated {100 * rows[-1]['mean_stated_rel_error']:.3g} %, over target {over}")
        out["scenes"][label] = {"method": method, "reference": ref_note, "reference_seconds": ref_seconds,
                                "rows": rows}
    return out


# --- 6. analytic, guard, memory -------------------------------------------------------------------

def _specs(scene):
    model = scene_capture.capture(scene, bpy.context.view_layer)
    return [lt.spec for lt in model.lights if lt.spec is not None]


def bench_analytic():
    scene = scenes.delta_lit()
    spec = _specs(scene)[0]
    m = 200_000 if QUICK else 1_000_000
    rng = np.random.default_rng(0)
    pts = rng.uniform(-5, 5, (m, 3))
    normals = rng.normal(size=(m, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    spec.irradiance_at(pts[:1000], normals[:1000])
    t_single = median([timed(lambda: spec.irradiance_at(pts, normals))[0] for _ in range(5)])
    evals_per_s = m / t_single
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
        specs = _specs(scene)
        t_vec = median([timed(lambda: [s.irradiance_at(pts[:1], normals[:1]) for s in specs])[0]
                        for _ in range(5)])
        results[label] = {"predict_illuminance_s": t, "model_evaluation_only_s": t_vec}
        log(f"  analytic {label}: predict {t * 1e3:.1f} ms")
    log(f"  analytic: {evals_per_s:.3g} point-light evaluations/s")
    return results


def bench_guard():
    """Cost of the scene guard (snapshot + restore) and of the scene capture, small vs 130k triangles."""
    rows = []
    for label, build in (("delta-lit (1 light)", scenes.delta_lit), ("130k-triangle room", lambda: scenes.big_room()[0])):
        scene = build()

        def guard():
            with scene_guard.preserved_scene(scene):
                pass

        guard()
        t_guard = median([timed(guard)[0] for _ in range(15)])
        # The capture itself (scene_capture.capture): meter.capture_model would be served from the cache here.
        scene_capture.capture(scene, bpy.context.view_layer)
        t_capture = median([timed(lambda: scene_capture.capture(scene, bpy.context.view_layer))[0] for _ in range(5)])
        rows.append({"scene": label, "guard_s": t_guard, "capture_s": t_capture})
        log(f"  guard {label}: {t_guard * 1e3:.1f} ms, capture {t_capture * 1e3:.1f} ms")
    return {"rows": rows}


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
            "data_counts_unchanged": counts_before == counts_after, "seconds": seconds}


# --- 9. live meter latency ------------------------------------------------------------------------

def _live_change_latency(scene, light, st, live_mod, repeats):
    """Wall time from a light move (depsgraph update) to the updated live reading, with the real
    debounce: the timer function is called as Blender would (every TICK_S) until it has measured."""
    rows = []
    for k in range(repeats):
        before = st.measurements
        light.location.x += 0.05 if k % 2 == 0 else -0.05
        t0 = time.perf_counter()
        bpy.context.view_layer.update()  # fires the depsgraph_update_post handler
        while st.measurements == before and time.perf_counter() - t0 < 30:
            live_mod.tick()
            if st.measurements == before:
                time.sleep(live_mod.TICK_S)
        rows.append((time.perf_counter() - t0, st.preview_seconds))
    return {"change_to_reading_s_median": median([r[0] for r in rows]),
            "measurement_s_median": median([r[1] for r in rows]), "repeats": repeats}


def bench_live():
    """Live mode latency: a change to an exact reading (point lights, nothing else: closed forms) and to
    a preview reading in the demo room, then the refinement to the scene's quality while idle."""
    from radiometer.operators import live as live_mod

    repeats = 2 if QUICK else 4
    out = {"debounce_s": live_mod.DEBOUNCE_S, "tick_s": live_mod.TICK_S, "refine_idle_s": live_mod.REFINE_IDLE_S}
    scene = _delta_scene()
    from radiometer.operators.meter import add_meter

    for p in _three_points():
        add_meter(bpy.context, "ILLUMINANCE", tuple(p))
    light = next(ob for ob in scene.objects if ob.type == "LIGHT")
    scene.radiometer.live = True
    st = live_mod.state(scene)
    live_mod.tick(now=time.perf_counter() + 10)  # first reading of every meter
    exact = _live_change_latency(scene, light, st, live_mod, repeats)
    meters_ = [ob for ob in scene.objects if ob.radiometer_meter.is_meter]
    exact.update(meters=len(meters_), all_exact=all(ob.radiometer_meter.exact for ob in meters_))
    out["exact"] = exact
    log(f"  live exact: {exact['change_to_reading_s_median'] * 1e3:.0f} ms change to reading "
        f"({exact['measurement_s_median'] * 1e3:.1f} ms measuring)")

    scene, _pts, _nrm, _names = _demo()
    scene.radiometer.quality = "standard"
    light = scene.objects["Table Lamp"]
    scene.radiometer.live = True
    st = live_mod.state(scene)
    live_mod.tick(now=time.perf_counter() + 10)  # first preview (warms Cycles up)
    st.refine = []
    preview = _live_change_latency(scene, light, st, live_mod, repeats)
    live_meters = [ob for ob in live_mod._live_meters(scene) if ob.radiometer_meter.kind in live_mod.FAST_KINDS]
    preview.update(meters=len(live_meters), spot_meters_when_idle=len(live_mod._live_meters(scene)) - len(live_meters), exact_readings=sum(ob.radiometer_meter.exact for ob in live_meters),
                   worst_rel_error=max(ob.radiometer_meter.rel_std_error for ob in live_meters))
    t0 = time.perf_counter()
    ticks = 0
    while st.refine and time.perf_counter() - t0 < 60:
        live_mod.tick(now=time.perf_counter() + 10)  # idle long enough: refine one batch per tick
        ticks += 1
    preview["refine_to_standard_s"] = time.perf_counter() - t0
    preview["refine_ticks"] = ticks
    preview["refined_worst_rel_error"] = max(ob.radiometer_meter.rel_std_error for ob in live_mod._live_meters(scene))
    out["demo_preview"] = preview
    scene.radiometer.live = False
    live_mod.tick()
    log(f"  live demo: {preview['change_to_reading_s_median'] * 1e3:.0f} ms change to preview; "
        f"refined to standard in {preview['refine_to_standard_s']:.1f} s ({ticks} ticks)")
    return out


# --- report ---------------------------------------------------------------------------------------

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


def pct(x, digits=3):
    return f"{100 * x:.{digits}g} %"


def _breakdown_table(bd, total):
    out = ["| phase | seconds | share | calls |", "|---|---:|---:|---:|"]
    for key, v in bd.items():
        out.append(f"| {v['label']} | {v['seconds']:.3f} | {100 * v['seconds'] / total:.0f} % | {v['calls']} |")
    return out


def _rounds_table(rounds):
    out = ["| round | spp | meters baked | samples | bake (s) |", "|---:|---:|---:|---:|---:|"]
    for i, r in enumerate(rounds):
        out.append(f"| {i + 1} | {r['spp']} | {r['meters']} | {r['samples']:.0f} | {r['bake_s']:.3f} |")
    return out


def presets_markdown(p):
    out = [f"{p['meters']} meters x {p['seeds']} seeds per preset and scene. Reached error = RMS over meters and "
           "seeds of (reading - reference) / reference; stated = mean of the readings' own `rel_std_error`; "
           "seconds = median of one call for all meters; 'over target' counts readings with "
           "`rel_std_error` > the preset's target.", "",
           "| scene | method | preset (target) | seconds per call | samples/meter (median / max) | reached error "
           "(RMS) | stated (mean / max) | over target |", "|---|---|---|---:|---:|---:|---:|---:|"]
    for label, entry in p["scenes"].items():
        for i, r in enumerate(entry["rows"]):
            out.append(f"| {label if i == 0 else ''} | {entry['method'] if i == 0 else ''} | {r['preset']} "
                       f"({pct(r['target'], 2)}) | {r['median_s']:.3f} | {r['samples_median']:.0f} / "
                       f"{r['samples_max']:.0f} | {pct(r['rms_rel_error'])} | {pct(r['mean_stated_rel_error'])} / "
                       f"{pct(r['max_stated_rel_error'])} | {r['readings_over_target']} of {r['readings']} |")
    out.append("")
    out += [f"- {label}: reference = {entry['reference']}." for label, entry in p["scenes"].items()]
    return out


def markdown(res):
    m = res["machine"]
    out = ["# Radiometer benchmarks", "",
           f"Machine: {m['nproc']} cores ({m['cpu']}), Python {m['python']}, bpy {m['bpy']}, numpy {m['numpy']}; "
           f"{m['date_utc']}; load average at start {', '.join(f'{x:.1f}' for x in m['load_average_at_start'])} "
           "(the machine is shared: only ratios within this run are meaningful).",
           f"Total run time {res['total_seconds']:.0f} s. Generated by `make bench` (bench/run.py); raw numbers in "
           "bench/results.json. All readings use `target_rel_error=0.01` (1-sigma) unless said otherwise.", ""]
    if "batching" in res:
        b = res["batching"]
        out += ["## 1. Batching at equal error (1 %)", "",
                f"Scene: {b['scene']}; {b['triangles']:,} triangles. Meters scattered over the floor; of 100, "
                f"{b['meters_of_100_with_partly_occluded_light']} see the area light partly hidden by furniture "
                f"(its direct light must be rendered) and {b['meters_of_100_in_full_shadow_of_a_light']} are in the "
                "full shadow of a light. `method='auto'` (the hybrid here).", "",
                "| meters | reps | median (s) | / 1 meter | samples (total) | / 1 meter | samples/meter (min / median / "
                "max) | worst reached error | all <= 1 % | sample overshoot |", "|---:|---:|---:|---:|---:|---:|---|---:|---|---:|"]
        for r in b["rows"]:
            s = r["readings"]
            out.append(f"| {r['meters']} | {r['reps']} | {r['median_s']:.3f} | **{r['ratio_to_1']:.2f}** | "
                       f"{s['samples_total']:.0f} | {r['samples_ratio_to_1']:.0f} | {s['samples_min']:.0f} / "
                       f"{s['samples_median']:.0f} / {s['samples_max']:.0f} | {pct(r['worst_rel_error'])} | "
                       f"{r['all_within_target']} | {s['overshoot_samples_over_needed']:.2f} |")
        tm = b["bake_time_model_100"]
        out += ["", f"t(100) / t(1) = **{b['ratio_100']:.2f}**: goal <= 1.5 {yes(b['goal_met'])}; bar <= 3 "
                    f"{yes(b['bar_met'])}. 'Sample overshoot' = samples spent / samples the 1/N law says each meter "
                    "needed to land exactly on 1 % (sum over meters).", ""]
        for r in b["rows"]:
            out += [f"Where the time goes, {r['meters']} meter(s) (median run, {r['median_s']:.3f} s):", ""]
            out += _breakdown_table(r["breakdown"], r["median_s"]) + [""]
            out += _rounds_table(r["rounds"]) + [""]
        if tm["s_per_sample"]:
            out += [f"Bake time model of the 100-meter run's rounds: {tm['fixed_s_per_bake']:.3f} s per bake + "
                    f"{tm['s_per_sample'] * 1e6:.2f} us per sample.", ""]
    if "overhead" in res:
        out += ["## 2. Overhead of a reading (1 meter at 1 %)", "",
                "`measure_illuminance(p, target_rel_error=0.01)` vs a bare bake by hand (one quad, one 4 x 4 float "
                "image, one `bpy.ops.object.bake`, Radiometer's Cycles settings, the same bounce limit) with the "
                "same total samples as the reading used; interleaved, medians. 'bare 1 spp' = the same bare bake "
                "at 1 sample per texel, i.e. a bake's fixed cost (scene sync, kernel setup, image write).", "",
                "| scene | reps | reading (s) | bare bake, same samples (s) | bare 1 spp (s) | syncs per reading | "
                "samples per reading | ratio | goal <= 1.1 | bar <= 1.5 |", "|---|---:|---:|---:|---:|---:|---|---:|---|---|"]
        for r in res["overhead"]["rows"]:
            sp = sorted(set(r["samples_per_reading"]))
            out.append(f"| {r['scene']} | {r['reps']} | {r['median_reading_s']:.4f} | {r['median_bare_bake_s']:.4f} | "
                       f"{r['median_bare_bake_1spp_s']:.4f} | {r['syncs_per_reading']} | "
                       f"{', '.join(str(x) for x in sp)} | **{r['ratio']:.2f}** | {yes(r['goal_met'])} | "
                       f"{yes(r['bar_met'])} |")
        out.append("")
        for r in res["overhead"]["rows"]:
            if "ratio_unchanged" in r:  # issue 17: the capture kept (capture_cache.Watch)
                out.append(f"- {r['scene']}, the same reading again with nothing changed since the previous one (its "
                           f"capture kept): {r['median_reading_unchanged_s']:.4f} s median, samples "
                           f"{', '.join(str(x) for x in sorted(set(r['samples_per_reading_unchanged'])))}: ratio "
                           f"**{r['ratio_unchanged']:.2f}** to the bare bake ({yes(r['ratio_unchanged'] <= 1.5)} "
                           "for <= 1.5).")
        out.append("")
        out += speed.edits_markdown(res["overhead"]["rows"])
        for r in res["overhead"]["rows"]:
            out += [f"Breakdown of one reading, {r['scene']} ({r['median_reading_s']:.3f} s median):", ""]
            out += _breakdown_table(r["breakdown"], sum(v["seconds"] for v in r["breakdown"].values())) + [""]
            for kind, e in r.get("edits", {}).items():
                out += [f"Breakdown of one reading right after a {kind} edit, {r['scene']} (median one):", ""]
                out += _breakdown_table(e["breakdown"], sum(v["seconds"] for v in e["breakdown"].values())) + [""]
    if "throughput" in res:
        t = res["throughput"]
        o, a, bb = t["ours"], t["brute_one_bake_per_meter"], t["brute_fixed_samples"]
        out += ["## 3. Throughput: {:,} meters at 1 %".format(t["meters"]), "",
                f"Scene: {t['scene']}; {t['cores']} cores.", "",
                "| way | seconds | meters / s / core | worst reached error | samples per meter |",
                "|---|---:|---:|---:|---|",
                f"| Radiometer (`auto`: hybrid, one call; {o.get('pooled', 0)} meters pooled) | {o['seconds']:.1f} | "
                f"**{o['meters_per_s_per_core']:.1f}** | {pct(o['worst_rel_error'])} | {o['samples_min']:.0f} / "
                f"{o['samples_median']:.0f} / {o['samples_max']:.0f} (min / median / max) |",
                f"| brute force A: one bare bake per meter at the samples the allocator chose for it "
                f"({a['meters_timed']} meters timed, scaled) | {a['seconds_for_all']:.1f} | "
                f"{a['meters_per_s_per_core']:.1f} | {pct(a['rel_error_max'])} (median {pct(a['rel_error_median'])}) "
                "| as Radiometer |",
                f"| brute force B: one call, fixed samples for every meter = the hardest meter's count | "
                f"{bb['seconds']:.1f} | {bb['meters_per_s_per_core']:.1f} | {pct(bb['worst_rel_error'])} | "
                f"{bb['samples_per_meter']} |", "",
                f"Speed-up: {t['speedup_vs_one_bake_per_meter']:.1f}x over one bake per meter, "
                f"{t['speedup_vs_fixed_samples']:.2f}x over fixed samples. Brute force A renders the full light "
                "(direct + indirect) where Radiometer adds the proven direct light analytically, so its errors "
                "differ at equal samples. Radiance: " + t["radiance"]["note"] + ".", ""]
        out += ["Breakdown of Radiometer's call:", ""] + _breakdown_table(o["breakdown"], o["seconds"]) + [""]
        out += _rounds_table(o["rounds"]) + [""]
    if "hybrid" in res:
        h = res["hybrid"]
        out += ["## 4. Hybrid vs full render", "",
                f"Same meters, same target (1 % and 0.2 %), {h['seeds']} seeds per method, interleaved; medians "
                "over seeds; samples = total over the meters; "
                "'difference' = (mean hybrid - mean render) / combined standard error per meter (unbiasedness "
                "check: |x| < 3 expected).", "",
                "| scene | meters | method | seconds | samples (total) | max samples/meter | worst reached error | "
                "all <= target |", "|---|---:|---|---:|---:|---:|---:|---|"]
        for label, e in h["scenes"].items():
            for i, method in enumerate(("hybrid", "render")):
                x = e[method]
                out.append(f"| {label if i == 0 else ''} | {e['meters'] if i == 0 else ''} | {method} | "
                           f"{x['median_s']:.3f} | {x['samples_total_median']:.0f} | {x['samples_max']:.0f} | "
                           f"{pct(x['worst_rel_error'])} | {x['all_within_target']} |")
        out.append("")
        for label, e in h["scenes"].items():
            out.append(f"- {label}: render / hybrid = {e['time_ratio_render_over_hybrid']:.2f}x time, "
                       f"{e['samples_ratio_render_over_hybrid']:.2f}x samples; samples per meter (median over "
                       "seeds) hybrid " + ", ".join(f"{x:.0f}" for x in e["hybrid"]["samples_per_meter_median"])
                       + " vs render " + ", ".join(f"{x:.0f}" for x in e["render"]["samples_per_meter_median"])
                       + "; difference in s.e. per meter: " + ", ".join(f"{x:+.2f}" for x in e["hybrid_minus_render_in_se"]))
            if "per_sample_rel_spread" in e:
                sp = e["per_sample_rel_spread"]
                out.append("  - per-sample relative spread per meter at 8192 samples (rel. s.e. x sqrt(N)): hybrid "
                           + ", ".join(f"{x:.3f}" for x in sp["hybrid"]) + "; render "
                           + ", ".join(f"{x:.3f}" for x in sp["render"]) + " (samples for 1 % = (spread / 0.01)^2)")
        out.append("")
    if "presets" in res:
        out += ["## 5. Quality presets: time and reached error", ""] + presets_markdown(res["presets"]) + [""]
    if "analytic" in res:
        a = res["analytic"]
        out += ["## 6. Analytic path", "",
                f"Vectorised point-light model (the emitter's `irradiance_at`) at {a['points']:,} receivers in one "
                f"call: {a['seconds_per_call'] * 1e3:.1f} ms, **{a['point_evals_per_s']:.3g} evaluations/s** "
                f"(goal >= 1e6/s: {yes(a['met'])}).", "",
                "| predict_illuminance, one point | time (ms) | of which light models (ms) |", "|---|---:|---:|"]
        for key in ("100 lights, no geometry", "100 lights in the closed room"):
            v = a[key]
            out.append(f"| {key} | {v['predict_illuminance_s'] * 1e3:.1f} | {v['model_evaluation_only_s'] * 1e3:.1f} |")
        out.append("")
    if "guard" in res:
        out += ["## 7. Scene guard and scene capture", "",
                "| scene | guard: snapshot + restore (ms) | scene capture (probe render) (ms) |", "|---|---:|---:|"]
        for r in res["guard"]["rows"]:
            out.append(f"| {r['scene']} | {r['guard_s'] * 1e3:.1f} | {r['capture_s'] * 1e3:.1f} |")
        out.append("")
    if "memory" in res:
        mem = res["memory"]
        out += ["## 8. Memory", "",
                f"{mem['readings']} single-meter render readings in a row in one process ({mem['seconds']:.0f} s): "
                f"RSS growth after the 10th reading {mem['growth_mb_from_10th']:.1f} MB (goal < 50 MB: "
                f"{yes(mem['met'])}); peak RSS of the bench process so far {mem['peak_rss_mb_process']:.0f} MB; "
                f"bpy.data counts unchanged: {mem['data_counts_unchanged']}.", "",
                "| readings done | RSS (MB) |", "|---|---|"]
        out += [f"| {k} | {v:.1f} |" for k, v in mem["rss_mb_after"]]
        out.append("")
    if "live" in res:
        lv = res["live"]
        e, d = lv["exact"], lv["demo_preview"]
        out += ["## 9. Live meter latency", "",
                f"Live mode (`scene.radiometer.live`): a light is moved, the depsgraph handler marks the meters "
                f"stale, the timer (every {lv['tick_s'] * 1e3:.0f} ms) waits {lv['debounce_s'] * 1e3:.0f} ms of "
                f"stillness and measures; medians of {e['repeats']} moves, wall time including the debounce.", "",
                "| scene | meters | change to reading (ms) | of which measuring (ms) | reading |", "|---|---:|---:|---:|---|",
                f"| 3 point lights, nothing else | {e['meters']} | {e['change_to_reading_s_median'] * 1e3:.0f} | "
                f"{e['measurement_s_median'] * 1e3:.1f} | exact: {e['all_exact']} |",
                f"| demo room (preview) | {d['meters']} | {d['change_to_reading_s_median'] * 1e3:.0f} | "
                f"{d['measurement_s_median'] * 1e3:.0f} | {d['exact_readings']} exact, worst "
                f"{100 * d['worst_rel_error']:.2g} % |", "",
                f"The demo room's {d['spot_meters_when_idle']} spot (luminance) meter(s) are measured in the idle "
                "phase (a camera render, ~1 s even at preview). "
                f"Refinement of the demo room's preview to standard (1 %), spot meter included, while idle: "
                f"{d['refine_to_standard_s']:.1f} s in {d['refine_ticks']} ticks (worst "
                f"{100 * d['refined_worst_rel_error']:.2g} %); each tick blocks the UI for its batch.", ""]
    # sections whose own module writes them, in this order
    for key, section in (("capture", speed.capture_markdown), ("live_edits", speed.live_edits_markdown),
                         ("batch_cost", speed.batch_cost_markdown), ("radiance", speed.radiance_markdown),
                         ("allocation_coverage", speed.allocation_coverage_markdown),
                         ("pooled_study", speed.pooled_study_markdown),
                         ("pooled", lambda r: __import__("pooled").markdown(r))):
        if key in res:
            out += section(res[key])
    if "cluster" in res:
        c = res["cluster"]
        out += ["## Scale-out on Dask (issue 20)", "",
                f"A {c['points']}-point x {c['times']}-time sun study: t(1 worker) / t(2 workers) = "
                f"{c['ratio_1_over_2']:.2f} (warm workers; 2 cores); projected annual daylight coefficients "
                f"(1000 points x 8760 h) on 16 / 64 / 256 cores: "
                + " / ".join(f"{r['total_s'] / 60:.1f} min" for r in c["projection"])
                + ". Overheads and the projection's model: bench/cluster.md (bench/cluster.py).", ""]
    for key in ("sun_study", "daylight_factor", "daylight_split", "daylight_furnished", "daylight_gather", "daylight_steps",
                "annual"):  # bench/<key>.py writes its own section
        if key in res:
            out += __import__(key).markdown(res[key])
    return "\n".join(out)


BENCHES = {"batching": bench_batching, "overhead": bench_overhead, "throughput": bench_throughput,
           "hybrid": bench_hybrid, "presets": bench_presets, "analytic": bench_analytic, "guard": bench_guard,
           "memory": bench_memory, "live": bench_live}
# Issue 17 (bench/speed.py): capture reuse; the throughput room against Radiance (after "throughput").
BENCHES["capture"] = lambda: speed.bench_capture(QUICK)
BENCHES["live_edits"] = lambda: speed.bench_live_edits(QUICK)  # issue 17: live meter after edits, 130k triangles
BENCHES["batch_cost"] = lambda: speed.bench_batch_cost(QUICK)
BENCHES["radiance"] = lambda: speed.bench_radiance(_RESULTS.get("throughput"), QUICK)
BENCHES["allocation_coverage"] = lambda: speed.bench_allocation_coverage(QUICK)
BENCHES["pooled_study"] = lambda: speed.bench_pooled_study(QUICK)
BENCHES["pooled"] = lambda: __import__("pooled").bench_pooled(QUICK)  # issue 17: the pooled estimator vs per meter
_RESULTS = {}


# Issue 20 (bench/cluster.py, run as its own process: a LocalCluster's workers are spawned and re-import
# the main script, and this one imports bpy at its top, which breaks bpy in the workers; FACTS.md).
def bench_cluster():
    import tempfile

    out = tempfile.mkdtemp(prefix="radiometer-bench-") if QUICK else HERE  # quick runs never overwrite results
    subprocess.run([sys.executable, os.path.join(HERE, "cluster.py"), "--out", out] + (["--quick"] if QUICK else []),
                   check=True, timeout=3600)
    with open(os.path.join(out, "cluster.json"), encoding="utf-8") as f:
        return json.load(f)


BENCHES["cluster"] = bench_cluster
# Issue 19 (bench/sun_study.py): an hourly sun study's cost per time step.
BENCHES["sun_study"] = lambda: __import__("sun_study").bench_sun_study(QUICK)

# Issue 19 (bench/daylight_factor.py): 100-point daylight-factor grid vs electric-light grid at 1 %.
BENCHES["daylight_factor"] = lambda: __import__("daylight_factor").bench_daylight_factor(QUICK)
# Issue 31 (bench/daylight_split.py): the DF grid with the sky component proven vs rendered whole vs electric.
BENCHES["daylight_split"] = lambda: __import__("daylight_split").bench_daylight_split(4 if QUICK else 10,
                                                                                     0.05 if QUICK else 0.01)

# Issue 31 (bench/daylight_steps.py): a low-sun sun-study step vs a midday one; the glare picture's seconds.
BENCHES["daylight_steps"] = lambda: __import__("daylight_steps").bench_daylight_steps(QUICK)

# Issue 19 (bench/annual.py): annual sDA/ASE vs Radiance on a room that does not saturate; dome vs per-patch cost.
BENCHES["annual"] = lambda: __import__("annual").bench_annual(QUICK)
# Issue 35 (bench/spectral_demo_eye.py): the spectral reading's coverage at the demo camera's eye, 50 seeds a room.
BENCHES["spectral_demo_eye"] = lambda: __import__("spectral_demo_eye").bench_spectral_demo_eye(QUICK)
# Issue 31 (bench/annual_large.py): 1000 points x 146 patches against Radiance, per core.
BENCHES["annual_large"] = lambda: __import__("annual_large").bench_annual_large(QUICK)
# Issue 31 (bench/sun_bounce_coverage.py): the sun's first bounce as emitters against the Sun light, 50 seeds.
BENCHES["sun_bounce_coverage"] = lambda: __import__("sun_bounce_coverage").bench_section(QUICK)
# Issue 31 (bench/annual_coverage.py): the annual dome's hourly errors over 50 seeds, the configuration before beside.
BENCHES["annual_coverage"] = lambda: __import__("annual_coverage").run(quick=QUICK)
# Issue 31 (bench/boxes_room_split.py): the DF grid in a room of separate boxes vs electric and vs rendered whole;
# quick: 3 x 3 at 5 % into a temporary folder (quick runs never overwrite results).
BENCHES["boxes_room_split"] = lambda: __import__("boxes_room_split").run(
    *((3, 0.05, 3, __import__("tempfile").mkdtemp(prefix="radiometer-bench-")) if QUICK else ()))

# Issue 31 (bench/ground_plane_split.py): the DF grid of the side-lit room and the room of boxes on a ground plane vs
# electric, and vs the path before 2026-12-07; quick: 3 x 3 at 5 % into a temporary folder.
BENCHES["ground_plane_split"] = lambda: __import__("ground_plane_split").run(
    *((3, 0.05, 3, __import__("tempfile").mkdtemp(prefix="radiometer-bench-")) if QUICK else ()))


# Issue 31 (bench/daylight_furnished.py): the DF grid in issue 31's room with a cabinet, a column, a window frame and a
# mullion vs electric and vs the gate path; quick: 3 x 3 at 5 % (its result returned, the files left as they are).
BENCHES["daylight_furnished"] = lambda: __import__("daylight_furnished").bench_daylight_furnished(
    *((3, 0.05) if QUICK else ()))


# Issue 31 (bench/daylight_gather.py): the rest of 900 and 100 DF meters gathered from the walls vs rendered per meter;
# quick: one repeat of a 10 x 10 grid.
BENCHES["daylight_gather"] = lambda: __import__("daylight_gather").bench_daylight_gather(
    *((1, (10,)) if QUICK else ()))


# Issue 31 (bench/dark_meters.py): a grid past a lit room's walls, the meters outside proven dark vs sampled to the
# dark floor; quick: the same at 5 % into a temporary folder.
BENCHES["dark_meters"] = lambda: __import__("dark_meters").run(
    *((0.05, __import__("tempfile").mkdtemp(prefix="radiometer-bench-")) if QUICK else ()))


# Issue 18 (bench/coverage_rare_paths_fin.py, its own process): coverage of stated errors in the fin scene
# (50 seeds per meter; the Sobol-Burley rows are an experiment on the sampler); quick: 5 seeds at preview.
def bench_coverage_fin():
    import tempfile

    out = tempfile.mkdtemp(prefix="radiometer-bench-") if QUICK else HERE  # quick runs never overwrite results
    script = [sys.executable, os.path.join(HERE, "coverage_rare_paths_fin.py"), "--out", out]
    runs = [["--seeds", "5"], ["--seeds", "5", "--scene", "hdri"]] if QUICK else [
        ["--pattern", "tabulated", "burley"], ["--quality", "standard", "--pattern", "tabulated", "burley"],
        ["--scene", "hdri", "--quality", "preview", "standard"]]  # the HDRI world with a sun disc
    for args in runs:
        subprocess.run(script + args, check=True, timeout=4 * 3600)
    found = {}
    for scene in ("fin", "hdri"):
        with open(os.path.join(out, f"coverage_rare_paths_{scene}.json"), encoding="utf-8") as f:
            found[scene] = json.load(f)
    return found


BENCHES["coverage_fin"] = bench_coverage_fin


def main(argv=None):
    global QUICK
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes (a smoke run, not for results)")
    parser.add_argument("--only", nargs="*", choices=list(BENCHES), help="run only these benchmarks")
    parser.add_argument("--out", default=HERE, help="folder for results.json and results.md")
    args = parser.parse_args(argv)
    QUICK = args.quick
    results = _RESULTS
    results.update({"machine": machine(), "quick": QUICK})
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
    scenes.write_results(args.out, "results", results, markdown(results))
    if "presets" in results:
        with open(os.path.join(args.out, "presets.md"), "w", encoding="utf-8") as f:
            f.write("# Quality presets, measured\n\nWritten by `make bench` (bench/run.py, section 5 of results.md) "
                    "in the same run as results.md.\n\n" + "\n".join(presets_markdown(results["presets"])) + "\n")
        with open(os.path.join(args.out, "presets.json"), "w", encoding="utf-8") as f:
            json.dump({"machine": results["machine"], **results["presets"]}, f, indent=2, default=float)
            f.write("\n")
    log(f"bench: wrote {args.out}/results.json and results.md ({results['total_seconds']:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

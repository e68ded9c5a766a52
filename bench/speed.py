"""Issue 17's speed sections of `make bench`: capture reuse, and the same room against Radiance.

* ``bench_capture``: what one scene capture costs (a miss: probe render + triangles) against a cache
  hit (nothing changed: a depsgraph evaluation and the key), in the 130k-triangle room; and how many
  captures an inverse-square check makes now (it made 4-5 before the capture was passed down).
* ``bench_radiance``: the interreflecting throughput room (bench/scenes.py ``room``: 4 x 4 x 3 m,
  albedo 0.7, 1 m square 400 W ceiling panel) written as a Radiance scene and measured at the
  throughput section's points with ``rtrace -I`` the way its users run it: Honeybee-like ambient-cache
  detail levels 0 and 1, and as a path tracer (``-aa 0 -ad 1 -u+``, each point traced K times; the
  spread gives the error). Radiance ships with pyradiance, a bench dependency only (never at run time).
  Each renderer's error is against its OWN converged reference on a subset of points (Radiance: a
  path-traced reference with about 8x the samples; Radiometer: its stated 1-sigma error), so the table
  compares time against error at each one's settings; the two references are compared with each
  other as a check that both scenes are the same room.
"""

import math
import os
import shutil
import subprocess
import tempfile
import time

import numpy as np

import bpy

import scenes
from radiometer import api
from radiometer.measure.capture import capture_cache, scene_capture
from radiometer.measure.analyses import law_checks
from radiometer.measure.meter import point_meter as meter

Y = np.array([0.2126, 0.7152, 0.0722])  # Rec.709 Y: grey walls and a white light, all channels equal


def _median(xs):
    return float(np.median(np.asarray(xs, float)))


# --- capture reuse ----------------------------------------------------------------------------------

def bench_capture(quick=False):
    scene, tris = scenes.big_room()
    layer = bpy.context.view_layer
    lamp = next(ob for ob in scene.objects if ob.type == "LIGHT" and ob.data.type == "AREA")
    reps = 3 if quick else 7
    box = _edited_object(scene, "geometry")
    miss, light_miss, hit, full = [], [], [], []
    partial = 0
    meter.capture_model(scene, layer)  # the scene's first capture (whole), which the edits below build on
    for k in range(reps):
        box.location.x += 1e-4 * (1 if k % 2 else -1)  # a geometry edit: the box read again (a partial capture)
        before = capture_cache.stats()["partial_captures"]
        t0 = time.perf_counter()
        meter.capture_model(scene, layer)
        miss.append(time.perf_counter() - t0)
        partial += capture_cache.stats()["partial_captures"] - before
        lamp.data.energy += 1e-3 * (1 if k % 2 else -1)  # a lights-only edit: the lights are read again
        t0 = time.perf_counter()
        meter.capture_model(scene, layer)
        light_miss.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        meter.capture_model(scene, layer)
        hit.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        scene_capture.capture(scene, layer)  # the same scene captured whole (the cache not asked)
        full.append(time.perf_counter() - t0)
    # One meter at 1 %, called again with nothing changed: the second call reuses the first one's capture
    # (capture_cache.Watch), the first pays it (an edit before it).
    point, normal = (-0.8, 0.9, 0.0), (0.0, 0.0, 1.0)
    api.measure_illuminance(point, normal, target_rel_error=0.01)  # warm-up
    after_edit, unchanged = [], []
    for k in range(reps):
        lamp.data.energy += 1e-3 * (1 if k % 2 else -1)
        t0 = time.perf_counter()
        api.measure_illuminance(point, normal, target_rel_error=0.01, seed=2 * k)
        after_edit.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        api.measure_illuminance(point, normal, target_rel_error=0.01, seed=2 * k + 1)
        unchanged.append(time.perf_counter() - t0)
    calls, seconds = [], []
    real = scene_capture.capture
    recaptures = capture_cache.stats()["light_recaptures"]

    def counting(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return real(*args, **kwargs)
        finally:
            calls.append(1)
            seconds.append(time.perf_counter() - t0)

    scene_capture.capture = counting
    try:
        capture_cache.clear()
        t0 = time.perf_counter()
        from radiometer.measure.blender import request as request_of

        law_checks.check_inverse_square(lamp, request=request_of.build(scene, quality="preview"),
                                        distances=[0.5, 1.0, 1.5, 2.0])
        t_check = time.perf_counter() - t0
    finally:
        scene_capture.capture = real
    return {"triangles": tris, "reps": reps, "miss_s": _median(miss), "hit_s": _median(hit),
            "full_s": _median(full), "partial_over_full": _median(miss) / _median(full), "partial_captures": partial,
            "hit_over_miss": _median(hit) / _median(miss), "lights_only_s": _median(light_miss),
            "lights_only_over_miss": _median(light_miss) / _median(miss),
            "inverse_square_light_recaptures": capture_cache.stats()["light_recaptures"] - recaptures,
            "meter_after_edit_s": _median(after_edit), "meter_unchanged_s": _median(unchanged),
            "meter_unchanged_over_after_edit": _median(unchanged) / _median(after_edit),
            "inverse_square_captures": len(calls), "inverse_square_capture_s": float(sum(seconds)),
            "inverse_square_s": t_check, "inverse_square_captures_before": "5 (issue 17: 4-5)"}


def _edited_object(scene, kind):
    """The object an edit of ``kind`` changes: the room's area light ('lights'), else a furniture box of the
    130k room or the small room's only mesh ('geometry')."""
    if kind == "lights":
        return next(ob for ob in scene.objects if ob.type == "LIGHT" and ob.data.type == "AREA")
    meshes = sorted((ob for ob in scene.objects if ob.type == "MESH" and not ob.name.startswith("bench bare")),
                    key=lambda ob: len(ob.data.polygons))
    return meshes[0]


def edited_reading(kind, scene, point, normal, target, seed):
    """(seconds, reading) of one meter at ``target`` called right after an edit of ``kind`` (issue 17):
    'lights' nudges the area light's power by +-1 mW (the capture keeps its geometry), 'geometry' moves the
    smallest mesh by +-0.1 mm (a full capture). The sign alternates with ``seed`` so the scene stays put."""
    obj = _edited_object(scene, kind)
    sign = 1.0 if seed % 2 else -1.0
    if kind == "lights":
        obj.data.energy += sign * 1e-3
    else:
        obj.location.x += sign * 1e-4
    t0 = time.perf_counter()
    reading = api.measure_illuminance(point, normal, target_rel_error=target, seed=seed)
    return time.perf_counter() - t0, reading


def edits_markdown(rows):
    """Lines for the overhead section: one meter after a lights-only edit and after a geometry edit."""
    out = []
    for r in rows:
        for kind, label in (("lights", "a lights-only edit (area light power, the geometry kept)"),
                            ("geometry", "a geometry edit (one mesh moved 0.1 mm: a partial capture transforms "
                                         "it again, keeps the rest)")):
            e = r.get("edits", {}).get(kind)
            if e is None:
                continue
            out.append(f"- {r['scene']}, one meter right after {label}: {e['median_s']:.4f} s median, samples "
                       f"{', '.join(str(x) for x in sorted(set(e['samples'])))}: ratio **{e['ratio']:.2f}** to the "
                       f"bare bake ({'met' if e['ratio'] <= 1.5 else '**NOT met**'} for <= 1.5); light recaptures "
                       f"{e['light_recaptures']}, partial captures {e.get('partial_captures', 0)}, full captures "
                       f"{e['full_captures']} in {e['reps']} readings.")
    return out + [""]


# --- the live meter after an edit, 130k triangles -------------------------------------------------------

def _live_latency(scene, edit, repeats):
    """Wall time from an edit (``edit(k)``) to the next live reading, ticking as Blender's timer would;
    also the measuring part alone (the tick that measured). Returns a dict of medians (s)."""
    from radiometer.operators import live as live_mod

    st = live_mod.state(scene)
    total, measuring, after_debounce = [], [], []
    for k in range(repeats):
        before = st.measurements
        edit(k)
        t0 = time.perf_counter()
        bpy.context.view_layer.update()  # fires the depsgraph_update_post handlers (live, capture cache)
        last_tick = t0
        while st.measurements == before and time.perf_counter() - t0 < 60:
            last_tick = time.perf_counter()
            live_mod.tick()
            if st.measurements == before:
                time.sleep(live_mod.TICK_S)
        done = time.perf_counter()
        total.append(done - t0)
        after_debounce.append(done - last_tick)  # the measuring tick: edit seen, debounce over, to the reading
        measuring.append(st.preview_seconds)
    return {"repeats": repeats, "change_to_reading_s_median": _median(total),
            "measuring_tick_s_median": _median(after_debounce), "measurement_s_median": _median(measuring)}


def bench_live_edits(quick=False):
    """Live meter latency after a light move and after a geometry edit in 130k-triangle scenes (issue 17):
    (a) three radius-0 point lights over a 130k-triangle floor 0.5 m below six meters (every reading a
    closed form, the floor's triangles in every proof), (b) the 130k-triangle room (interreflection:
    preview readings at 5 %)."""
    from radiometer.operators import live as live_mod
    from radiometer.operators.meter import add_meter

    repeats = 2 if quick else 5
    out = {"debounce_s": live_mod.DEBOUNCE_S, "tick_s": live_mod.TICK_S}
    for label, build, points in (
            ("3 point lights over a 130k-triangle floor (exact)", _floor_scene,
             [(0.0, 0.0, 0.0), (0.6, -0.3, 0.0), (-0.9, 0.7, 0.0), (1.4, 1.1, 0.0), (-1.2, -1.3, 0.0), (0.2, 0.9, 0.0)]),
            ("130k-triangle room (preview)", lambda: scenes.big_room()[0],
             [(-0.8, 0.9, 0.0), (1.0, -0.5, 0.0), (0.3, 1.5, 0.0), (-1.5, -1.0, 0.0)])):
        scene = build()
        triangles = sum(len(ob.data.polygons) for ob in scene.objects if ob.type == "MESH")
        for p in points:
            add_meter(bpy.context, "ILLUMINANCE", tuple(p))
        light = next(ob for ob in scene.objects if ob.type == "LIGHT")
        mesh = max((ob for ob in scene.objects if ob.type == "MESH"), key=lambda ob: len(ob.data.polygons))
        scene.radiometer.live = True
        st = live_mod.state(scene)
        live_mod.tick(now=time.perf_counter() + 10)  # first reading of every meter (a full capture)

        def move_light(k):
            light.location.x += 0.05 if k % 2 == 0 else -0.05

        def move_mesh(k):
            mesh.location.z += 1e-4 if k % 2 == 0 else -1e-4

        row = {"scene": label, "triangles": triangles, "meters": len(points)}
        for kind, edit in (("light moved", move_light), ("mesh moved 0.1 mm", move_mesh)):
            before = capture_cache.stats()
            row[kind] = _live_latency(scene, edit, repeats)
            after = capture_cache.stats()
            row[kind]["light_recaptures"] = after["light_recaptures"] - before["light_recaptures"]
            row[kind]["partial_captures"] = after["partial_captures"] - before["partial_captures"]
        meters = [ob for ob in scene.objects if ob.radiometer_meter.is_meter]
        row["exact_readings"] = sum(ob.radiometer_meter.exact for ob in meters)
        scene.radiometer.live = False
        live_mod.tick()
        out.setdefault("rows", []).append(row)
    return out


def _floor_scene():
    scene = scenes.fresh()
    for k, loc in enumerate(((0.0, 0.0, 2.0), (1.5, -0.5, 1.5), (-1.0, 1.2, 2.5))):
        scenes.light(scene, "POINT", loc, energy=100.0 - 20 * k, shadow_soft_size=0.0)
    scenes.add_triangles(scene, 130_000, z=-0.5)
    return scene


def live_edits_markdown(b):
    out = ["## Live meter after an edit, 130k triangles (issue 17)", "",
           f"Live mode as in section 9 (timer every {b['tick_s'] * 1e3:.0f} ms, debounce {b['debounce_s'] * 1e3:.0f} ms: "
           "the scene must be still that long); medians. 'Measuring tick' = from the tick that starts measuring "
           "(edit seen, debounce over) to the reading written: the latency excluding the debounce. A light move "
           "keeps the captured geometry (lights read again); a mesh move is a partial capture (the moved mesh "
           "transformed again from its kept vertices, the rest kept).", "",
           "| scene | triangles | meters | edit | change to reading (ms) | measuring tick (ms) | of which measuring "
           "(ms) | light recaptures | partial captures |", "|---|---:|---:|---|---:|---:|---:|---:|---:|"]
    for r in b["rows"]:
        for kind in ("light moved", "mesh moved 0.1 mm"):
            e = r[kind]
            out.append(f"| {r['scene']} | {r['triangles']:,} | {r['meters']} | {kind} | "
                       f"{e['change_to_reading_s_median'] * 1e3:.0f} | {e['measuring_tick_s_median'] * 1e3:.1f} | "
                       f"{e['measurement_s_median'] * 1e3:.1f} | {e['light_recaptures']} of {e['repeats']} | "
                       f"{e.get('partial_captures', 0)} of {e['repeats']} |")
    out.append("")
    out += [f"- {r['scene']}: {r['exact_readings']} of {r['meters']} readings exact." for r in b["rows"]]
    return out + [""]


# --- per-sample cost of a batch ------------------------------------------------------------------------

def bench_batch_cost(quick=False):
    """Seconds per meter-sample of a 100-meter call against a 1-meter call, both at the same FIXED samples
    per meter (130k-triangle room, floor meters): the whole call, and the bakes alone."""
    from radiometer.measure.render import sensors

    scene, tris = scenes.big_room()
    samples = 1024
    reps = 2 if quick else 3
    pts1, nrm1 = scenes.floor_meters(1, seed=11)
    pts100, nrm100 = scenes.floor_meters(100, seed=200)
    api.measure_illuminance(pts1, nrm1, samples=64)  # warm-up
    real = sensors.run_bake
    bake = []

    def timed_bake(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return real(*args, **kwargs)
        finally:
            bake[-1] += time.perf_counter() - t0

    sensors.run_bake = timed_bake
    rows = {}
    try:
        for n, pts, nrm in ((1, pts1, nrm1), (100, pts100, nrm100)):
            calls, bakes = [], []
            for rep in range(reps):
                bake.append(0.0)
                t0 = time.perf_counter()
                api.measure_illuminance(pts, nrm, samples=samples, seed=rep, method="render")
                calls.append(time.perf_counter() - t0)
                bakes.append(bake[-1])
            rows[n] = {"call_s": _median(calls), "bake_s": _median(bakes)}
    finally:
        sensors.run_bake = real
    per_call = (rows[100]["call_s"] / 100) / rows[1]["call_s"]
    per_bake = (rows[100]["bake_s"] / 100) / rows[1]["bake_s"]
    return {"triangles": tris, "samples_per_meter": samples, "reps": reps, "rows": rows,
            "per_sample_ratio_call": per_call, "per_sample_ratio_bakes": per_bake, "goal": 1.5,
            "goal_met_call": per_call <= 1.5, "goal_met_bakes": per_bake <= 1.5}


def batch_cost_markdown(b):
    rows = {int(k): v for k, v in b["rows"].items()}  # JSON turns the keys into strings
    r1, r100 = rows[1], rows[100]
    return ["## Per-sample cost of a batch (issue 17)", "",
            f"130k-triangle room, {b['samples_per_meter']} samples per meter fixed, `method='render'`, median of "
            f"{b['reps']}: 1 meter {r1['call_s']:.3f} s (bakes {r1['bake_s']:.3f} s), 100 meters "
            f"{r100['call_s']:.3f} s (bakes {r100['bake_s']:.3f} s).",
            f"Per meter-sample, 100 meters / 1 meter: whole call **{b['per_sample_ratio_call']:.2f}**, bakes alone "
            f"**{b['per_sample_ratio_bakes']:.2f}** (goal <= {b['goal']}: "
            f"{'met' if b['goal_met_call'] else 'NOT met'} for the call, "
            f"{'met' if b['goal_met_bakes'] else 'NOT met'} for the bakes).", ""]


# --- Radiance ---------------------------------------------------------------------------------------

def radiance_bin():
    try:
        import pyradiance
    except ImportError:
        return None
    folder = os.path.join(os.path.dirname(pyradiance.__file__), "bin")
    return folder if os.path.exists(os.path.join(folder, "rtrace")) else None


#: Honeybee-like rtrace ambient-cache settings (honeybee-radiance's grid-based detail levels 0, 1).
HONEYBEE = {
    0: "-ab 2 -ad 512 -as 128 -ar 16 -aa 0.25 -dj 0 -ds 0.5 -dt 0.5 -dc 0.25 -dr 0 -dp 64 -st 0.85 -lr 4 -lw 0.05",
    1: "-ab 3 -ad 2048 -as 2048 -ar 64 -aa 0.2 -dj 0.5 -ds 0.25 -dt 0.25 -dc 0.5 -dr 1 -dp 256 -st 0.5 -lr 6 "
       "-lw 0.01",
}
#: Path tracing: no ambient cache, one ambient ray per bounce, Russian roulette by weight, random numbers.
PATH = "-ab 64 -aa 0 -ad 1 -as 0 -lr 0 -lw 1e-6 -dj 1 -ds 0.02 -u+"


def _room_rad(size=(4.0, 4.0, 3.0), albedo=0.7, energy=400.0):
    """bench/scenes.py ``room`` as a Radiance scene: the same quads, a Lambertian 0.7 wall, the panel."""
    h = size[2]
    quads = scenes.room_quads(size)
    radiance = energy / (math.pi * 1.0)  # Blender's area light: L = P / (pi A), W/(m^2 sr) per channel
    z = h - 0.01
    panel = [(-0.5, -0.5, z), (-0.5, 0.5, z), (0.5, 0.5, z), (0.5, -0.5, z)]  # normal -Z, as the light
    lines = [f"void plastic wall 0 0 5 {albedo} {albedo} {albedo} 0 0",
             f"void light panel 0 0 3 {radiance} {radiance} {radiance}"]
    for k, quad in enumerate(quads):
        lines.append(f"wall polygon q{k} 0 0 12 " + " ".join(f"{c:g}" for v in quad for c in v))
    lines.append("panel polygon lamp 0 0 12 " + " ".join(f"{c:g}" for v in panel for c in v))
    return "\n".join(lines) + "\n"


def _rtrace(bindir, octree, options, points, normals, repeat=1):
    rays = np.repeat(np.c_[points, normals], repeat, axis=0)
    text = "\n".join(" ".join(f"{x:.9g}" for x in row) for row in rays) + "\n"
    env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""))
    t0 = time.perf_counter()
    out = subprocess.run([os.path.join(bindir, "rtrace"), "-I", "-h", "-n", "1", *options.split(), octree],
                         input=text, capture_output=True, text=True, env=env, check=True).stdout
    dt = time.perf_counter() - t0
    rgb = np.array([line.split()[:3] for line in out.splitlines() if line.strip()], float)
    return (rgb @ Y).reshape(len(points), repeat), dt


def bench_radiance(throughput=None, quick=False):
    bindir = radiance_bin()
    if bindir is None:
        return {"available": False, "note": "pyradiance (Radiance binaries) is not installed"}
    n = 200 if quick else 1000
    pts, nrm = scenes.meter_points(n, half_width=1.8, z=0.75, seed=3)  # the throughput section's points
    sub = np.random.default_rng(17).choice(n, 20 if quick else 30, replace=False)
    work = tempfile.mkdtemp(prefix="radiometer-bench-radiance-")
    try:
        rad = os.path.join(work, "room.rad")
        with open(rad, "w", encoding="utf-8") as f:
            f.write(_room_rad())
        octree = os.path.join(work, "room.oct")
        with open(octree, "wb") as f:
            subprocess.run([os.path.join(bindir, "oconv"), rad], stdout=f, check=True)
        # Reference: path tracing with many repeats on the subset.
        k_ref = 512 if quick else 2048
        ref_values, t_ref = _rtrace(bindir, octree, PATH, pts[sub], nrm[sub], repeat=k_ref)
        ref = ref_values.mean(axis=1)
        ref_se = ref_values.std(axis=1, ddof=1) / math.sqrt(k_ref) / ref
        rows = []
        for level, options in HONEYBEE.items():
            values, dt = _rtrace(bindir, octree, options, pts, nrm)
            err = values[sub, 0] / ref - 1.0
            rows.append({"setting": f"rtrace -I, Honeybee-like detail level {level} (ambient cache)",
                         "options": options, "points": n, "seconds": dt,
                         "worst_error": float(np.max(np.abs(err))), "rms_error": float(np.sqrt(np.mean(err ** 2))),
                         "error_kind": "against the Radiance reference (subset)"})
        # Path tracing at about 1 % per point: K from the reference's per-path spread.
        spread = float(np.median(ref_values.std(axis=1, ddof=1) / ref))
        k = int(min(4096, max(4, math.ceil((spread / 0.01) ** 2))))
        t0 = time.perf_counter()
        values, dt = _rtrace(bindir, octree, PATH, pts, nrm, repeat=k)
        mean = values.mean(axis=1)
        se = values.std(axis=1, ddof=1) / math.sqrt(k) / mean
        err = mean[sub] / ref - 1.0
        rows.append({"setting": f"rtrace -I as a path tracer, {k} paths per point", "options": PATH, "points": n,
                     "seconds": dt, "paths_per_point": k, "seconds_per_path": dt / (n * k),
                     "worst_error": float(np.max(np.abs(err))), "rms_error": float(np.sqrt(np.mean(err ** 2))),
                     "stated_error_median": float(np.median(se)), "error_kind": "against the Radiance reference "
                     "(subset); its own 1-sigma spread also stated"})
        out = {"available": True, "points": n, "subset": int(len(sub)), "reference_paths": k_ref,
               "reference_seconds": t_ref, "reference_rel_se_max": float(np.max(ref_se)),
               "per_path_spread": spread, "rows": rows, "cores_used_by_rtrace": 1}
        out["semantics"] = light_semantics(pts[sub[:5]], nrm[sub[:5]], ref[:5], ref_se[:5] * ref[:5], quick)
        if throughput is not None:
            ours = throughput["ours"]
            readings = ours.get("irradiance_W_m2")
            out["radiometer"] = {"setting": "Radiometer, 1 % target (throughput section)", "points": n,
                                 "seconds": ours["seconds"], "cores": throughput["cores"],
                                 "worst_error": ours.get("worst_rel_error"), "error_kind": "stated 1-sigma"}
            if readings is not None:
                ours_e = np.array([readings[i] for i in sub])
                out["references_differ_rms"] = float(np.sqrt(np.mean((ours_e / ref - 1.0) ** 2)))
        return out
    finally:
        shutil.rmtree(work, ignore_errors=True)


def light_semantics(points, normals, radiance_ref, radiance_se, quick=False):
    """Why Radiometer reads above Radiance in the throughput room: both against an independent numpy
    tracer (bench/room_reference.py) with the panel transparent to reflected rays (Cycles: a path
    passes through a light) and opaque (Radiance: a ``light`` polygon ends it), at the same points.
    Radiometer at a 0.2 % target; Radiance's values are the path-traced reference of the section."""
    import room_reference

    paths = 10_000 if quick else 40_000
    rows = []
    for k, (p, n) in enumerate(zip(points, normals)):
        direct, ind_t, se_t = room_reference.irradiance(p, n, paths=paths, seed=k)
        _d, ind_o, se_o = room_reference.irradiance(p, n, paths=paths, opaque=True, seed=100 + k)
        rows.append({"point": [float(c) for c in p], "direct": direct, "transparent": direct + ind_t,
                     "transparent_se": se_t, "opaque": direct + ind_o, "opaque_se": se_o,
                     "radiance": float(radiance_ref[k]), "radiance_se": float(radiance_se[k])})
    scenes.room()
    readings = api.measure_illuminance(np.asarray(points), np.asarray(normals), target_rel_error=0.002, seed=7)
    for row, r in zip(rows, readings):
        row["radiometer"], row["radiometer_se"] = r.irradiance, r.rel_std_error * abs(r.irradiance)
    return {"paths": paths, "rows": rows}


def semantics_markdown(sem):
    out = ["### Why Radiometer reads above Radiance here: lights are transparent in Cycles", "",
           "An independent numpy path tracer of the same box (bench/room_reference.py: Lambert's polygon formula "
           "for every vertex's direct light, cosine-sampled bounces, no Cycles, no Radiance) computed with the "
           "panel transparent to reflected rays (a path passes through it to the ceiling, as Cycles treats every "
           "light: docs/FACTS.md) and opaque (the path ends there, as at Radiance's `light` polygon), "
           f"{sem['paths']:,} paths per point. Radiometer at a 0.2 % target; Radiance = the section's path-traced "
           "reference. W/m², ± 1 s.e.; z = difference / combined s.e.", "",
           "| point (m) | direct (closed form) | numpy, transparent panel | Radiometer | z | numpy, opaque panel | "
           "Radiance rtrace | z |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in sem["rows"]:
        z1 = (r["radiometer"] - r["transparent"]) / math.hypot(r["radiometer_se"], r["transparent_se"])
        z2 = (r["radiance"] - r["opaque"]) / math.hypot(r["radiance_se"], r["opaque_se"])
        out.append(f"| ({r['point'][0]:.2f}, {r['point'][1]:.2f}, {r['point'][2]:.2f}) | {r['direct']:.3f} | "
                   f"{r['transparent']:.3f} ± {r['transparent_se']:.3f} | {r['radiometer']:.3f} ± "
                   f"{r['radiometer_se']:.3f} | {z1:+.1f} | {r['opaque']:.3f} ± {r['opaque_se']:.3f} | "
                   f"{r['radiance']:.3f} ± {r['radiance_se']:.3f} | {z2:+.1f} |")
    gap = [r["transparent"] / r["opaque"] - 1 for r in sem["rows"]]
    out += ["", f"Transparent over opaque panel in the independent tracer: +{100 * min(gap):.1f} to "
                f"+{100 * max(gap):.1f} %, the whole Radiometer - Radiance difference. Each renderer agrees with the "
                "independent tracer run with its own semantics, so both are right about their own scene: Cycles lets "
                "reflected light through a light object (the ceiling behind the panel stays lit and seen), Radiance's "
                "`light` material absorbs it (so does an `illum` with a void alternate, for ambient rays: measured by "
                "hand, -0.1 to +0.5 % from `light`). Radiometer measures the scene as Cycles renders it; a physical "
                "luminaire that blocks the ceiling is modelled in Blender with an opaque housing behind the light.", ""]
    return out


# --- coverage of the stated errors (allocation) ----------------------------------------------------------

COVERAGE_POINTS = [(0.0, 0.0, 0.75), (0.9, -0.4, 0.75), (1.6, 1.5, 0.75), (-1.7, 0.2, 0.75), (0.3, 1.2, 0.75)]


def bench_allocation_coverage(quick=False):
    """Issue 17: do 1-sigma errors stated at a 1 % target cover the truth, with the allocation as it is
    (pilot of >= 512 samples, small needs finished at the pilot's spp)? The throughput room, 5 meters,
    ``seeds`` calls with different seeds; truth from the independent numpy tracer (room_reference,
    transparent light as in Cycles). Nominal 95 % intervals; goal >= 90 % of them cover."""
    import room_reference

    seeds = 20 if quick else 60
    paths = 20_000 if quick else 60_000
    truth = []
    for k, p in enumerate(COVERAGE_POINTS):
        direct, indirect, se = room_reference.irradiance(p, paths=paths, seed=k)
        truth.append((direct + indirect, se))
    e, e_se = np.array(truth).T
    scenes.room()
    pts, nrm = np.array(COVERAGE_POINTS), np.tile([0.0, 0.0, 1.0], (len(COVERAGE_POINTS), 1))
    z, rel, samples = [], [], []
    for seed in range(seeds):
        for r, t, ts in zip(api.measure_illuminance(pts, nrm, target_rel_error=0.01, seed=seed), e, e_se):
            z.append((r.irradiance - t) / math.hypot(r.rel_std_error * r.irradiance, ts))
            rel.append(r.rel_std_error)
            samples.append(r.samples)
    z = np.array(z)
    covered = float(np.mean(np.abs(z) < 1.96))
    return {"seeds": seeds, "meters": len(COVERAGE_POINTS), "intervals": int(z.size), "reference_paths": paths,
            "covered_95": covered, "goal": 0.9, "goal_met": covered >= 0.9, "z_mean": float(z.mean()),
            "z_std": float(z.std(ddof=1)), "stated_rel_error_median": float(np.median(rel)),
            "samples_median": float(np.median(samples)), "samples_max": float(np.max(samples)),
            "overshoot_samples_over_needed": float(np.sum(samples) / np.sum(np.array(samples) * (np.array(rel) / 0.01) ** 2))}


def allocation_coverage_markdown(c):
    return ["## Coverage of the stated errors at 1 % (issue 17)", "",
            f"Throughput room, {c['meters']} meters at 0.75 m, {c['seeds']} seeds = {c['intervals']} readings at a 1 % "
            f"target; truth: the independent numpy tracer (bench/room_reference.py, {c['reference_paths']:,} paths per "
            "point, transparent light as in Cycles). z = (reading - truth) / combined 1-sigma.", "",
            f"95 % intervals covering: **{100 * c['covered_95']:.1f} %** (goal >= 90 %: "
            f"{'met' if c['goal_met'] else 'NOT met'}); z mean {c['z_mean']:+.2f}, s.d. {c['z_std']:.2f}; stated "
            f"error median {100 * c['stated_rel_error_median']:.2f} %; samples per meter median "
            f"{c['samples_median']:.0f}, max {c['samples_max']:.0f}; samples spent / needed (1/N law) "
            f"{c['overshoot_samples_over_needed']:.2f}.", ""]


# --- study: pooling neighbouring meters (not in the product) ---------------------------------------------

def bench_pooled_study(quick=False):
    """How far below the per-meter sampling floor could pooling go? The throughput room's 1000 meters
    measured with the pilot's samples only (256 per meter, hybrid: the direct light is exact), the
    rendered (indirect) part fitted by weighted least squares with a polynomial in (x, y) of degree d,
    the fitted field compared at 24 meters with the independent numpy tracer (room_reference). A study
    for the next step (an estimator whose error is checked on held-out sampled meters), NOT a product
    feature: Radiometer does not pool meters."""
    import room_reference

    n = 200 if quick else 1000
    scenes.room()
    pts, nrm = scenes.meter_points(n, half_width=1.8, z=0.75, seed=3)
    t0 = time.perf_counter()
    readings = api.measure_illuminance(pts, nrm, samples=256, seed=1)
    seconds = time.perf_counter() - t0
    e = np.array([r.irradiance for r in readings])
    se = np.array([r.rel_std_error * abs(r.irradiance) for r in readings])
    direct = room_reference.panel_irradiance(pts, nrm, 400.0 / math.pi, room_reference.panel())
    indirect = e - direct
    sub = np.random.default_rng(17).choice(n, 12 if quick else 24, replace=False)
    truth = np.array([room_reference.irradiance(pts[k], paths=5_000 if quick else 20_000, seed=int(k))[1:]
                      for k in sub])

    def basis(p, deg):
        x, y = p[:, 0] / 2.0, p[:, 1] / 2.0
        return np.stack([x ** i * y ** j for i in range(deg + 1) for j in range(deg + 1 - i)], axis=1)

    rows = []
    for deg in (2, 3, 4, 6):
        a, w = basis(pts, deg), 1.0 / se
        beta = np.linalg.lstsq(a * w[:, None], indirect * w, rcond=None)[0]
        cov = np.linalg.inv((a * w[:, None]).T @ (a * w[:, None]))
        b = basis(pts[sub], deg)
        fit, fit_se = b @ beta, np.sqrt(np.einsum("ij,jk,ik->i", b, cov, b))
        total = direct[sub] + truth[:, 0]
        err = (fit - truth[:, 0]) / total
        z = (fit - truth[:, 0]) / np.hypot(fit_se, truth[:, 1])
        rows.append({"degree": deg, "parameters": int(a.shape[1]), "rms_error": float(np.sqrt(np.mean(err ** 2))),
                     "max_error": float(np.max(np.abs(err))), "fit_se_median": float(np.median(fit_se / total)),
                     "z_rms": float(np.sqrt(np.mean(z ** 2))),
                     "reduced_chi2": float(np.sum(((indirect - a @ beta) / se) ** 2) / (n - a.shape[1]))})
    return {"meters": n, "samples_per_meter": 256, "seconds": seconds, "checked": int(len(sub)),
            "per_meter_rel_se_median": float(np.median(se / e)), "rows": rows}


def pooled_study_markdown(p):
    out = ["## Study: pooling neighbouring meters (issue 17's way below the sampling floor; not in the product)", "",
           f"The throughput room's {p['meters']} meters measured with the pilot's samples only ({p['samples_per_meter']} "
           f"per meter, hybrid; {p['seconds']:.1f} s here, each meter's own error {100 * p['per_meter_rel_se_median']:.2f} % "
           "median); the rendered (indirect) part fitted over all meters by weighted least squares, a polynomial in "
           f"(x, y) of degree d; the field checked at {p['checked']} meters against the independent numpy tracer. "
           "'z rms' = RMS of (fit - truth) / (fit's own s.e. (+) truth's s.e.): above 1 the fit's own error does not cover "
           "its model misfit, which an estimator must measure (held-out meters sampled on their own) and add.", "",
           "| degree | parameters | error vs truth, RMS | max | fit's own s.e. (median) | z rms | reduced chi2 |",
           "|---:|---:|---:|---:|---:|---:|---:|"]
    for r in p["rows"]:
        out.append(f"| {r['degree']} | {r['parameters']} | {100 * r['rms_error']:.2f} % | {100 * r['max_error']:.2f} % | "
                   f"{100 * r['fit_se_median']:.2f} % | {r['z_rms']:.2f} | {r['reduced_chi2']:.3f} |")
    return out + [""]


# --- markdown -----------------------------------------------------------------------------------------

def capture_markdown(c):
    return ["## Capture reuse (issue 17)", "",
            f"130k-triangle room ({c['triangles']:,} triangles), median of {c['reps']}: a capture after a geometry "
            f"edit (a furniture box moved 0.1 mm: "
            + (f"a partial capture, {c['partial_captures']} of {c['reps']}) {c['miss_s']:.4f} s against "
               f"{c['full_s']:.4f} s for the same scene captured whole = **{c['partial_over_full']:.2g}**"
               if "full_s" in c else f"everything captured again) {c['miss_s']:.4f} s")
            + (f"; after a lights-only edit (the area light's power: the lights read again by a lights-only probe "
               f"render, the geometry kept) {c['lights_only_s']:.4f} s = **{c['lights_only_over_miss']:.2g}** of it"
               if "lights_only_s" in c else "")
            + f"; the same capture with nothing changed (hit: one depsgraph evaluation and "
            f"the key) {c['hit_s']:.2g} s = **{c['hit_over_miss']:.2g}** of the capture after the geometry edit.",
            *([f"One meter at 1 % in that room, called right after a lights-only edit (the area light's power): "
               f"{c['meter_after_edit_s']:.3f} s; called "
               f"again with nothing changed (the previous call's capture is kept: capture_cache.Watch): "
               f"{c['meter_unchanged_s']:.3f} s = **{c['meter_unchanged_over_after_edit']:.2f}** of it."]
              if "meter_unchanged_s" in c else []),
            f"An inverse-square check of the area light (preview, 4 distances): **{c['inverse_square_captures']}** "
            f"full capture(s) ({c['inverse_square_capture_s']:.3f} s of {c['inverse_square_s']:.2f} s)"
            + (f" and {c['inverse_square_light_recaptures']} lights-only one(s) (the light alone: same geometry)"
               if "inverse_square_light_recaptures" in c else "") + "; before: "
            f"{c['inverse_square_captures_before']} (the whole scene 3 times, then each of the 2 measurements); now the "
            "whole scene once and the light alone once, handed to both measurements. A measurement's own bakes "
            "change the scene and restore it (Blender reports updates); the capture it used stays valid only when "
            "the measurement succeeded, no callback of it changed the scene and the key is unchanged.", ""]


def radiance_markdown(r):
    if not r.get("available"):
        return ["## Radiance comparison", "", r.get("note", "not run"), ""]
    out = ["## Radiance comparison (same room, same points)", "",
           f"The throughput room as a Radiance scene, {r['points']} points; errors against a Radiance path-traced "
           f"reference on {r['subset']} of them ({r['reference_paths']} paths per point, worst 1-sigma "
           f"{100 * r['reference_rel_se_max']:.2f} %). rtrace runs on 1 core (`-n 1`); Radiometer's time is for "
           f"the whole machine ({r.get('radiometer', {}).get('cores', '?')} cores).", "",
           "| renderer, settings | seconds | worst error | RMS error | error is |", "|---|---:|---:|---:|---|"]
    for row in r["rows"]:
        out.append(f"| {row['setting']} | {row['seconds']:.2f} | {100 * row['worst_error']:.2f} % | "
                   f"{100 * row['rms_error']:.2f} % | {row['error_kind']} |")
    ours = r.get("radiometer")
    if ours:
        worst = ours["worst_error"]
        out.append(f"| {ours['setting']} | {ours['seconds']:.2f} | "
                   f"{'' if worst is None else f'{100 * worst:.2f} %'} | | {ours['error_kind']} |")
    path = next((row for row in r["rows"] if "paths_per_point" in row), None)
    if path:
        out += ["", f"Radiance path tracing: {1e6 * path['seconds_per_path']:.0f} µs per path, per-path spread "
                    f"{100 * r['per_path_spread']:.0f} % (so {path['paths_per_point']} paths for 1 %)."]
    if "references_differ_rms" in r:
        out += [f"Radiometer's readings against the Radiance reference: RMS {100 * r['references_differ_rms']:.2f} % "
                "(explained below: Cycles' lights are transparent to reflected rays, Radiance's `light` is opaque).",
                "The ambient-cache levels stop at 2 and 3 ambient bounces (`-ab`): in a closed room of albedo 0.7 "
                "most of the light has bounced more often, hence their large errors."]
    if r.get("semantics"):
        out += [""] + semantics_markdown(r["semantics"])
    return out + [""]

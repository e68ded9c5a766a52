"""Issue 31 acceptance "coverage stays honest": the daylight factor's fast path (``method="auto"``: the openings
as emitters of the CIE overcast sky's radiance, the sky and ground seen straight in closed form where proven,
the rest rendered) against an independent reference, Radiance rtrace used as a path tracer.

Per scene, ``--seeds`` calls of ``api.daylight_factor(points, normals, target_rel_error=..., seed=k)``
(k = 0 .. seeds - 1), each against the same Radiance reference. z = (DF - DF_ref) / hypot(rel_std_error x DF,
s.e._ref); the 95 % interval holds where |z| <= 1.96. Acceptance: at least 90 % of the intervals hold.
The reference's own error is common to every seed, so the bias (mean over seeds of DF - DF_ref) is stated
with the s.e. sqrt(s.d.^2 / seeds + s.e._ref^2).

Scenes (tests/bpy/daylight_room.py: the same quads in Blender and in Radiance):
1. ``open``: the side-lit room (4 x 3 x 2.7 m, a 2 x 1.2 m window), open;
2. ``pane``: the same with the solid 6 mm pane (Glass BSDF, IOR 1.52; Radiance: a ``dielectric`` box), and
   the whole render (``method="render"``: Cycles under the sky, no emitters) on ``--render-seeds`` seeds beside
   it, to tell the emitters from Cycles' glass if the pane room reads off Radiance;
3. ``skylight``: a closed 4 x 4 x 3 m room with a 1 x 1 m opening in its ceiling (``skylight_quads``);
4. ``deep``: the side-lit room 8 m deep, points at its back, where the internally reflected light dominates;
5. ``obstruction``: the open side-lit room facing an opaque block outside (``obstruction_quads``: 10 m wide,
   6 m tall, 1 m thick, its near face 4 m in front of the window wall, reflectance 0.2): nothing may lie in
   front of an opening for the emitters' proof, so ``auto`` takes its other path (the sky past the block's
   silhouette in closed form, the rest through the gate);
6. ``roof``: a closed 4 x 4 m room under a mono-pitch roof tilted 30 deg (3 m high at y = 0), a 1 x 1 m
   opening in the sloped ceiling holding a solid 6 mm pane tilted with it (``roof_quads``, ``roof_pane``);
   against Radiance's ``dielectric`` box and its thin ``glass`` (every glazed scene gets both), and the
   whole render on ``--render-seeds`` seeds;
7. ``pane_obstruction``: the obstruction room with the 6 mm pane in its window (the sky past the block through
   the pane, its T(theta) bounded);
8. ``boxes``: a room built of nine separate boxes that touch (walls, floor and roof 0.2 m thick; no single closed
   surface, so no room's openings): the sky over every direction that meets no surface in closed form
   (``obstructed_aperture.open_directions``), the rest through the gate;
9. ``boxes_pane``: the same with a solid 6 mm pane at the room side of its window;
10. ``ground``: the open side-lit room on a ground plane (reflectance 0.2): the openings emit the sky alone,
   upwards, and the ground plane seen through them is rendered (``Openings.sky_only``).

Radiance: ``radiance_daylight_factor`` (rtrace -I, -aa 0 -ad 1 -as 0 -ab 32: one hemisphere ray per input
line). A pilot process gives each point's per-sample spread; then each point runs alone in at least 4 separate
processes, enough samples in all that its s.e. is ``--ref-fraction`` (0.3) of the mean error Radiometer stated
there. rtrace -u+ seeds from the clock's second, so each process starts in a later second than the last ended,
and the processes' means are checked to differ (distinct means; their spread over their stated errors ~1).

    PYTHONPATH=... python bench/coverage_daylight_emitters.py [--scenes open pane skylight deep obstruction roof
        pane_obstruction boxes boxes_pane ground]
        [--seeds 100]
        [--target 0.02] [--render-seeds 20] [--probe]
Writes bench/coverage_daylight_emitters.{json,md} after every scene (scenes already there are kept).
"""

import argparse
import json
import math
import os
import pathlib
import sys
import tempfile
import time
import types

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
HERE = ROOT / "bench"
sys.path.insert(0, str(HERE))
OUT_JSON = HERE / "coverage_daylight_emitters.json"
OUT_MD = HERE / "coverage_daylight_emitters.md"
Z95 = 1.96
COVERAGE_LIMIT = 0.90

UP = (0.0, 0.0, 1.0)


def _room():
    from scenes import load_test_module

    return load_test_module("daylight_room")


def scene_specs(room):
    """name -> (description, room quads, glass, points (m), normals[, pane: (faces, mid-plane polygon)])."""
    deep = room.quads(D=8.0)
    return {
        "open": ("side-lit room 4 x 3 x 2.7 m, 2 x 1.2 m window, open", room.quads(), False,
                 [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85), (1.2, 0.4, 1.6)],
                 [UP] * 5),
        "pane": ("the same room, a solid 6 mm pane (IOR 1.52) in the window", room.quads(), True,
                 [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85), (1.2, 0.4, 1.6)],
                 [UP] * 5),
        "skylight": ("closed room 4 x 4 x 3 m, a 1 x 1 m opening in the ceiling (x, y 1.5-2.5 m)",
                     room.skylight_quads(), False,
                     [(2.0, 2.0, 0.85), (1.0, 1.0, 0.85), (0.5, 3.5, 0.85), (3.9, 2.0, 1.5)],
                     [UP, UP, UP, (-1.0, 0.0, 0.0)]),
        "deep": ("side-lit room 4 x 8 x 2.7 m (the same window), points at the back", deep, False,
                 [(2.0, 5.0, 0.85), (2.0, 6.5, 0.85), (2.0, 7.5, 0.85), (0.5, 7.5, 0.85)], [UP] * 4),
        # the block's top edge (z = 6 m at y = -4 m) crosses the window at z 1.32, 1.66 and 2.00 m seen from the
        # 1st, 2nd and 5th points (they see sky above it); the 3rd and 4th see only the block through the window
        "obstruction": ("the open side-lit room facing a 10 m wide x 6 m tall x 1 m thick block, its near face 4 m "
                        "in front of the window wall (reflectance 0.2)", room.quads() + room.obstruction_quads(),
                        False,
                        [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85), (1.2, 0.4, 1.6)],
                        [UP] * 5),
        # the same block with a 6 mm pane in the window: the sky past the block through the pane (T(theta) bounded)
        "pane_obstruction": ("the obstruction room with a solid 6 mm pane (IOR 1.52) in the window",
                             room.quads() + room.obstruction_quads(), True,
                             [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85),
                              (1.2, 0.4, 1.6)], [UP] * 5),
        # a room as users build one: nine separate boxes that touch (no single closed surface), thick walls
        "boxes": ("a 4 x 5 x 2.8 m room of nine boxes that touch (walls, floor and roof 0.2 m thick), a 2 x 1.3 m "
                  "window through the wall", room.boxes_quads(room.boxes_room_boxes()), False,
                  [(2.0, 1.0, 0.85), (2.0, 2.5, 0.85), (1.0, 4.0, 0.85), (3.5, 0.5, 1.5), (0.3, 0.3, 0.85)],
                  [UP] * 5),
        "boxes_pane": ("the room of boxes with a solid 6 mm pane (IOR 1.52) at the room side of its window",
                       room.boxes_quads(room.boxes_room_boxes()), True,
                       [(2.0, 1.0, 0.85), (2.0, 2.5, 0.85), (1.0, 4.0, 0.85), (3.5, 0.5, 1.5), (0.3, 0.3, 0.85)],
                       [UP] * 5, room.boxes_pane()),
        # on a ground plane (since 2026-12-07 the openings emit the sky alone, upwards; the ground plane is rendered)
        "ground": ("the open side-lit room on a 64 x 63 m ground plane (reflectance 0.2) 1 cm below its floor",
                   room.quads() + room.ground_quads(), False,
                   [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85), (1.2, 0.4, 1.6),
                    (2.0, 1.0, 1.6)], [UP] * 5 + [(0.0, -1.0, 0.0)]),
        "roof": ("closed room 4 x 4 m under a roof tilted 30 deg (3 m at y = 0, 5.31 m at y = 4 m), a 1 x 1 m "
                 "opening in it (centre (2, 2, 4.15) m) with a solid 6 mm pane (IOR 1.52) tilted with the roof",
                 room.roof_quads(), True,
                 [(2.0, 2.0, 0.85), (1.0, 1.0, 0.85), (0.5, 3.5, 0.85), (3.5, 3.0, 0.85), (3.9, 2.0, 1.5)],
                 [UP] * 4 + [(-1.0, 0.0, 0.0)], room.roof_pane()),
    }


def build(room, quads, glass, pane=None):
    import bpy

    import radiometer
    from radiometer.compat import ensure_node_tree

    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "radiometer"):
        radiometer.register()
    scene = bpy.context.scene
    room.build_blender(scene, quads)
    if glass:
        room.add_pane_blender(scene, None if pane is None else pane[0])
    world = bpy.data.worlds.new("black")  # the user's world; daylight_factor swaps in its sky and restores it
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene


def _next_second():
    """rtrace -u+ seeds from the clock's second: wait until a later second than now."""
    end = int(time.time())
    while int(time.time()) <= end:
        time.sleep(0.02)


def _rtrace(room, quads, glass, points, normals, samples, pane=None):
    """One rtrace process (then wait for a new second): DF (%) and rel. s.e. per point."""
    folder = tempfile.mkdtemp(prefix="radiometer-coverage-rad-")
    extra = {} if pane is None else {"pane": pane}
    m, r = room.radiance_daylight_factor(folder, points, normals=normals, samples=samples, glass=glass,
                                         room_quads=quads, **extra)
    _next_second()
    return m, r


def radiance_reference(room, quads, glass, points, normals, goal_rel, pilot=20_000, min_runs=4, cap=1_000_000,
                       pane=None):
    """Radiance DF (%) per point and its s.e. (%), each point run to its own ``goal_rel`` (relative s.e.).

    A pilot process (all points, ``pilot`` samples each) gives each point's per-sample relative spread s_j;
    then point j runs alone in max(min_runs, N_j / cap) processes of equal size, N_j = (s_j / goal_j)^2
    samples in all (the pilot is not pooled: it only plans). The s.e. is pooled from the processes' own
    per-sample spreads; the processes' means are checked against it (between/stated ~1) and for repeats."""
    t0 = time.perf_counter()
    pm, pr = _rtrace(room, quads, glass, points, normals, pilot, pane)
    spread0 = pr * math.sqrt(pilot)
    out = {"df": [], "se": [], "rel": [], "runs": [], "samples_per_run": [], "distinct_process_means": [],
           "between_over_stated": [], "spread_per_sample": [], "pilot_spread_per_sample": spread0.tolist(),
           "pilot_df": pm.tolist()}
    for j, p in enumerate(points):
        need = (spread0[j] / goal_rel[j]) ** 2
        runs = max(min_runs, math.ceil(need / cap))
        n = max(pilot, math.ceil(need / runs))
        means, rels = [], []
        for _ in range(runs):
            m, r = _rtrace(room, quads, glass, [p], [normals[j]], n, pane)
            means.append(float(m[0]))
            rels.append(float(r[0]))
        means, rels = np.array(means), np.array(rels)
        spread = float(np.sqrt(np.mean(rels ** 2 * n)))
        df = float(means.mean())
        rel = spread / math.sqrt(n * runs)
        chi = (means - df) ** 2 / (rels * means) ** 2  # ~1 per process for independent draws, 0 for repeats
        out["df"].append(df)
        out["rel"].append(rel)
        out["se"].append(rel * df)
        out["runs"].append(runs)
        out["samples_per_run"].append(n)
        out["distinct_process_means"].append(len(set(np.round(means, 12))))
        out["between_over_stated"].append(float(np.sqrt(np.sum(chi) / (runs - 1))))
        out["spread_per_sample"].append(spread)
    out["wall_s"] = time.perf_counter() - t0
    return out


def radiometer_runs(api, scene, points, normals, target, seeds, method="auto", seed0=0):
    rows = []
    for k in range(seed0, seed0 + seeds):
        t0 = time.perf_counter()
        rs = api.daylight_factor(points, normals, scene=scene, target_rel_error=target, seed=k, method=method)
        dt = time.perf_counter() - t0
        rows.append({"seed": k, "s": dt, "df": [r.daylight_factor for r in rs], "rel": [r.rel_std_error for r in rs],
                     "method": [r.method for r in rs], "exact": [r.exact for r in rs],
                     "sc": [r.sky_component for r in rs], "erc": [r.externally_reflected_component for r in rs],
                     "irc": [r.internally_reflected_component for r in rs]})
        if k == seed0:
            rows[-1]["notes"] = [list(r.notes) for r in rs]
    return rows


def coverage(rows, ref):
    """Per point and overall: z mean/s.d., share of 95 % intervals holding, bias and its s.e."""
    df = np.array([r["df"] for r in rows])            # (seeds, points)
    se = np.array([r["rel"] for r in rows]) * df
    ref_df, ref_se = np.array(ref["df"]), np.array(ref["se"])
    z = (df - ref_df) / np.hypot(se, ref_se)
    hold = np.abs(z) <= Z95
    n = df.shape[0]
    diff = df.mean(axis=0) - ref_df
    diff_se = np.sqrt(df.var(axis=0, ddof=1) / n + ref_se ** 2)
    per_point = [{"ref_df": float(ref_df[j]), "ref_se": float(ref_se[j]), "mean_df": float(df[:, j].mean()),
                  "sd_df": float(df[:, j].std(ddof=1)), "mean_stated_se": float(se[:, j].mean()),
                  "mean_rel_std_error": float(np.mean(se[:, j] / df[:, j])),
                  "ref_se_over_stated": float(ref_se[j] / se[:, j].mean()),
                  "z_mean": float(z[:, j].mean()), "z_sd": float(z[:, j].std(ddof=1)),
                  "coverage": float(hold[:, j].mean()), "bias": float(diff[j]), "bias_se": float(diff_se[j]),
                  "bias_over_se": float(diff[j] / diff_se[j]),
                  "scatter_over_stated": float(df[:, j].std(ddof=1) / se[:, j].mean())}
                 for j in range(df.shape[1])]
    return {"seeds": n, "z_mean": float(z.mean()), "z_sd": float(z.std(ddof=1)), "coverage": float(hold.mean()),
            "meets": bool(hold.mean() >= COVERAGE_LIMIT), "worst_abs_z": float(np.abs(z).max()),
            "per_point": per_point, "z": np.round(z, 3).tolist()}


def _components(rows):
    m = sorted({x for r in rows for x in r["method"]})
    sc = np.array([[np.nan if v is None else v for v in r["sc"]] for r in rows], float)
    erc = np.array([[np.nan if v is None else v for v in r["erc"]] for r in rows], float)
    irc = np.array([[np.nan if v is None else v for v in r["irc"]] for r in rows], float)
    return {"methods": m, "sc_proven_share": float(np.mean(np.isfinite(sc))),
            "erc_proven_share": float(np.mean(np.isfinite(erc))),
            "sc": [None if not np.isfinite(v) else float(v) for v in sc[0]],
            "erc": [None if not np.isfinite(v) else float(v) for v in erc[0]],
            "irc_mean": [None if not np.all(np.isfinite(irc[:, j])) else float(irc[:, j].mean())
                         for j in range(irc.shape[1])]}


def run_scene(api, room, name, spec, args):
    desc, quads, glass, points, normals, *pane = spec
    pane = pane[0] if pane else None
    pts, nrm = np.asarray(points, float), np.asarray(normals, float)
    out = {"name": name, "description": desc, "glass": glass, "points": points, "normals": normals,
           "target_rel_error": args.target, "load_before": os.getloadavg()}
    scene = build(room, quads, glass, pane)
    t0 = time.perf_counter()
    warm = api.daylight_factor(pts, nrm, scene=scene, target_rel_error=args.target, seed=10_000)
    out["warmup_s"] = time.perf_counter() - t0
    if args.probe:
        for r in warm:
            print(name, r.location, f"DF {r.daylight_factor:.4f} rel {r.rel_std_error:.4f} {r.method} "
                  f"SC {r.sky_component} ERC {r.externally_reflected_component} "
                  f"IRC {r.internally_reflected_component}")
        print("\n".join(warm[0].notes))
        print(f"{name}: warm-up {out['warmup_s']:.2f} s")
        t0 = time.perf_counter()
        api.daylight_factor(pts, nrm, scene=scene, target_rel_error=args.target, seed=10_001)
        print(f"{name}: second call {time.perf_counter() - t0:.2f} s")
        return None
    rows = radiometer_runs(api, scene, pts, nrm, args.target, args.seeds)
    out["auto"] = {"rows": rows, "s_per_call_mean": float(np.mean([r["s"] for r in rows])),
                   "s_per_call_median": float(np.median([r["s"] for r in rows])), **_components(rows),
                   "notes_seed0": rows[0]["notes"]}
    if glass and args.render_seeds:
        rrows = radiometer_runs(api, scene, pts, nrm, args.target, args.render_seeds, method="render", seed0=5000)
        out["render"] = {"rows": rrows, "s_per_call_mean": float(np.mean([r["s"] for r in rrows])),
                         "methods": sorted({x for r in rrows for x in r["method"]})}
    # the reference's s.e. a fraction of the s.e. Radiometer states at each point (its mean over the seeds)
    stated = np.mean([r["rel"] for r in rows], axis=0)
    out["radiance"] = radiance_reference(room, quads, glass, points, normals, goal_rel=args.ref_fraction * stated,
                                         pane=pane)
    out["radiance"]["ref_fraction"] = args.ref_fraction
    out["auto"]["coverage"] = coverage(rows, out["radiance"])
    if "render" in out:
        out["render"]["coverage"] = coverage(out["render"]["rows"], out["radiance"])
    if glass:  # the thin-pane model Radiometer measures with, beside the dielectric box (see the pane rows)
        out["radiance_thin"] = radiance_reference(room, quads, "thin", points, normals,
                                                  goal_rel=args.ref_fraction * stated, pane=pane)
        out["radiance_thin"]["ref_fraction"] = args.ref_fraction
        out["auto"]["coverage_thin"] = coverage(rows, out["radiance_thin"])
        if "render" in out:
            out["render"]["coverage_thin"] = coverage(out["render"]["rows"], out["radiance_thin"])
        # auto against render: mean over seeds, each with its own spread (no common reference)
        a = np.array([r["df"] for r in rows])
        w = np.array([r["df"] for r in out["render"]["rows"]])
        d = a.mean(axis=0) - w.mean(axis=0)
        dse = np.sqrt(a.var(axis=0, ddof=1) / len(a) + w.var(axis=0, ddof=1) / len(w))
        out["auto_minus_render"] = {"diff": d.tolist(), "se": dse.tolist()}
    out["load_after"] = os.getloadavg()
    return out


PANE_POINTS = [(2.0, 0.4, 0.85), (2.0, 0.75, 0.85), (1.2, 0.4, 1.6)]


def pane_diagnostic(api, room, seeds=10, target=0.0025, goal_rel=0.0025):
    """The pane room with black surfaces and a black ground: only the sky seen straight through the pane is
    left. Radiometer (``auto``: rendered through the emitters) and Radiance against two closed forms
    (``sky_aperture.pane_bounded_illuminance``) of the 6 mm slab's T(theta): the s and p polarisations
    summed separately over the internal reflections (``thin_glass.slab``, Radiometer's model, physical) and
    Fresnel averaged over s and p at each interface before summing, T = (1 - r) / (1 + r), r = (r_s + r_p) / 2
    (what Radiance's ``dielectric`` does: src/rt/dielectric.c halves r_s + r_p per interface)."""
    from radiometer.radiometry.scene import thin_glass
    from radiometer.radiometry.skies import sky_aperture

    x0, x1, z0, z1 = room.WINDOW
    poly = np.array([(x0, 0, z0), (x1, 0, z0), (x1, 0, z1), (x0, 0, z1)], float)
    lz = 100.0 * 9.0 / (7.0 * math.pi)  # DF (%) directly: E_h = 7 pi Lz / 9 = 100

    def t_polarised(c):
        return thin_glass.slab(c, room.IOR, room.PANE)[0][..., 1]

    def t_averaged(c):
        rs, rp = thin_glass.fresnel_dielectric(c, room.IOR)
        r = 0.5 * (rs + rp)
        return (1.0 - r) / (1.0 + r)

    closed = {}
    for name, t in (("polarised", t_polarised), ("averaged", t_averaged)):
        closed[name] = [sky_aperture.pane_bounded_illuminance(poly, p, UP, t, (0.0, 1.0, 0.0), zenith_luminance=lz,
                                                              rel_tol=1e-4)[:2] for p in PANE_POINTS]
    saved = dict(room.RHO)
    try:
        room.RHO.update({k: 0.0 for k in room.RHO})
        scene = build(room, room.quads(), True)
        pts, nrm = np.asarray(PANE_POINTS, float), np.broadcast_to(UP, (len(PANE_POINTS), 3))
        rows = []
        for k in range(seeds):
            t0 = time.perf_counter()
            rs = api.daylight_factor(pts, nrm, scene=scene, target_rel_error=target, seed=k, ground_reflectance=0.0)
            rows.append({"seed": k, "s": time.perf_counter() - t0, "df": [r.daylight_factor for r in rs],
                         "rel": [r.rel_std_error for r in rs], "method": [r.method for r in rs]})
        def black(folder_, points, normals=UP, samples=1, glass=True, room_quads=None):
            return room.radiance_daylight_factor(folder_, points, normals=normals, samples=samples, glass=glass,
                                                 room_quads=room_quads, ground_reflectance=0.0)
        rad, rad_thin = (radiance_reference(types.SimpleNamespace(radiance_daylight_factor=black), room.quads(), g,
                                            PANE_POINTS, [UP] * len(PANE_POINTS),
                                            goal_rel=[goal_rel] * len(PANE_POINTS)) for g in (True, "thin"))
    finally:
        room.RHO.clear()
        room.RHO.update(saved)
    df = np.array([r["df"] for r in rows])
    se = np.array([r["rel"] for r in rows]) * df
    return {"points": PANE_POINTS, "seeds": seeds, "target_rel_error": target,
            "radiometer_mean": df.mean(axis=0).tolist(),
            "radiometer_se": (np.sqrt(np.sum(se ** 2, axis=0)) / len(df)).tolist(),
            "radiometer_scatter_se": (df.std(axis=0, ddof=1) / math.sqrt(len(df))).tolist(),
            "methods": sorted({x for r in rows for x in r["method"]}),
            "s_per_call": float(np.mean([r["s"] for r in rows])),
            "radiance": rad, "radiance_thin": rad_thin,
            "closed_polarised": [list(map(float, v)) for v in closed["polarised"]],
            "closed_averaged": [list(map(float, v)) for v in closed["averaged"]]}


def pane_thin_reference(room, data, ref_fraction):
    """The pane scene's readings (already in ``data``) against a second Radiance reference, its thin ``glass``."""
    s = data["scenes"]["pane"]
    stated = np.mean([r["rel"] for r in s["auto"]["rows"]], axis=0)
    s["radiance_thin"] = radiance_reference(room, room.quads(), "thin", s["points"], s["normals"],
                                            goal_rel=ref_fraction * stated)
    s["radiance_thin"]["ref_fraction"] = ref_fraction
    s["auto"]["coverage_thin"] = coverage(s["auto"]["rows"], s["radiance_thin"])
    if "render" in s:
        s["render"]["coverage_thin"] = coverage(s["render"]["rows"], s["radiance_thin"])


def _f(v, d=3):
    return "-" if v is None else f"{v:.{d}f}"


def markdown(data):
    L = ["## Daylight factor through the openings as emitters: coverage against Radiance (issue 31)", "",
         "`api.daylight_factor(points, normals, target_rel_error=t, seed=k)`, k = 0 .. seeds - 1, method `auto`, "
         "against Radiance rtrace as a path tracer (tests/bpy/daylight_room.py `radiance_daylight_factor`: the same "
         "quads, the sharp-horizon CIE overcast sky, ground reflectance 0.2; the pane as a `dielectric` box, and "
         "Radiance's thin `glass` where a row says so). "
         "z = (DF - DF_ref) / hypot(rel_std_error x DF, s.e._ref); the 95 % interval holds where |z| <= 1.96; "
         f"acceptance: >= {100 * COVERAGE_LIMIT:.0f} % hold. Bias = mean over seeds of DF - DF_ref, its s.e. "
         "sqrt(s.d.^2 / seeds + s.e._ref^2) (the reference's error is common to every seed). Radiance: separate "
         "rtrace processes, each started in a later second than the last ended (-u+ seeds from the clock's "
         "second), its s.e. pooled from the processes' per-sample spread; 'between/stated' is the processes' "
         "means' spread over their stated errors (1 for independent draws). Times: wall seconds per call on a "
         "2-core machine shared with other work.", ""]
    L += ["| scene | points | t | seeds | method(s) taken | SC / ERC proven | s per call | coverage 95 % | "
          "z mean | z s.d. | meets 90 % |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for s in data["scenes"].values():
        a, c = s["auto"], s["auto"]["coverage"]
        L.append(f"| {s['name']} | {len(s['points'])} | {100 * s['target_rel_error']:.3g} % | {c['seeds']} | "
                 f"{', '.join(a['methods'])} | {100 * a['sc_proven_share']:.0f} % / "
                 f"{100 * a['erc_proven_share']:.0f} % "
                 f"| {a['s_per_call_mean']:.2f} | {100 * c['coverage']:.1f} % | {c['z_mean']:+.2f} | "
                 f"{c['z_sd']:.2f} | {'yes' if c['meets'] else '**no**'} |")
        if "coverage_thin" in a:
            c = a["coverage_thin"]
            L.append(f"| {s['name']}, against Radiance's thin `glass` | {len(s['points'])} | "
                     f"{100 * s['target_rel_error']:.3g} % | {c['seeds']} | {', '.join(a['methods'])} | | | "
                     f"{100 * c['coverage']:.1f} % | {c['z_mean']:+.2f} | {c['z_sd']:.2f} | "
                     f"{'yes' if c['meets'] else '**no**'} |")
    L.append("")
    if "pane_diagnostic" in data and "pane" in data["scenes"]:
        d = data["pane_diagnostic"]
        sep = [100 * (cp[0] / ca[0] - 1) for cp, ca in zip(d["closed_polarised"], d["closed_averaged"])]
        own = [100 * (a / cp[0] - 1) for a, cp in zip(d["radiometer_mean"], d["closed_polarised"])]
        diel = [100 * (r / ca[0] - 1) for r, ca in zip(d["radiance"]["df"], d["closed_averaged"])]
        L += ["Reading the pane rows: against Radiance's `dielectric` box the pane room reads high (z mean "
              f"{data['scenes']['pane']['auto']['coverage']['z_mean']:+.2f}), and the whole render "
              "(no emitters) reads the same, so the emitters do not cause it. With only the sky through the pane "
              "(black room, below) Radiometer matches the closed form of a slab whose s and p polarisations are "
              f"followed apart ({', '.join(f'{v:+.2f}' for v in own)} %), as Radiance's thin `glass` does; Radiance's "
              "dielectric averages the Fresnel reflectance over s and p at each interface, which passes less (the "
              f"polarised slab's closed form is {', '.join(f'{v:+.2f}' for v in sep)} % above the averaged one at "
              f"those points), and its solid box reads {', '.join(f'{v:+.2f}' for v in diel)} % against that "
              "averaged closed form (presumably the box's edges and lateral shift, which a thin pane leaves out; "
              "not isolated here). Against Radiance's thin `glass` "
              "the pane room's coverage holds with z mean "
              f"{data['scenes']['pane']['auto'].get('coverage_thin', {}).get('z_mean', float('nan')):+.2f}.", ""]
    if "obstruction" in data["scenes"]:
        o = data["scenes"]["obstruction"]
        op = data["scenes"].get("open")
        ratio = (f" ({o['auto']['s_per_call_mean'] / op['auto']['s_per_call_mean']:.0f}x the open room's "
                 f"{op['auto']['s_per_call_mean']:.2f} s)") if op else ""
        if o["auto"].get("sc_proven_share", 0.0) > 0.0:
            L += ["Reading the obstruction row: the block lies in front of the window, so the openings' emitter proof "
                  "does not apply; `auto` took "
                  f"{', '.join(o['auto']['methods'])}: the sky past the block in closed form, its silhouette clipped "
                  "exactly (radiometry/skies/obstructed_aperture.py; SC stated at "
                  f"{100 * o['auto']['sc_proven_share']:.0f} % of readings, 0 where the block hides all the sky), the "
                  "rest (the block's and the room's reflections, the ground) rendered with the sky's direct emission "
                  f"gated off; ERC not stated. {o['auto']['s_per_call_mean']:.2f} s per call{ratio}; until "
                  "2026-12-07 `auto` rendered the whole here, 3.97 s per call in the run then. Its stated errors are "
                  "checked against Radiance (the block's 5 faces, reflectance 0.2, in both).", ""]
        else:
            L += ["Reading the obstruction row: the block lies in front of the window, so the openings' emitter "
                  "proof does not apply and `auto` took "
                  f"{', '.join(o['auto']['methods'])} at every point (SC and ERC not stated as fields; the notes: "
                  f"'{o['auto']['notes_seed0'][0][-1]}'), {o['auto']['s_per_call_mean']:.2f} s per call{ratio}. Its "
                  "stated errors hold against Radiance (the block's 5 faces, reflectance 0.2, in both).", ""]
    if "pane_obstruction" in data["scenes"] and "coverage_thin" in data["scenes"]["pane_obstruction"]["auto"]:
        po = data["scenes"]["pane_obstruction"]
        obs = data["scenes"].get("obstruction")
        L += ["Reading the pane_obstruction rows: the sky past the block through the pane (each point's core of the "
              "pane and its opening cut past the block's silhouette, the core's pieces weighted by T(theta) with a "
              "hard bound), the rest through the gate; "
              f"{po['auto']['s_per_call_mean']:.2f} s per call"
              + (f" (the open obstruction room's {obs['auto']['s_per_call_mean']:.2f} s)" if obs else "")
              + ". As in the pane rows, Radiometer reads above Radiance's `dielectric` box (z mean "
              f"{po['auto']['coverage']['z_mean']:+.2f}) and holds against its thin `glass` (z mean "
              f"{po['auto']['coverage_thin']['z_mean']:+.2f}, {100 * po['auto']['coverage_thin']['coverage']:.1f} % "
              "of 95 % intervals), the model Radiometer measures with.", ""]
    if "boxes" in data["scenes"]:
        bx = data["scenes"]["boxes"]
        bp = data["scenes"].get("boxes_pane")
        L += ["Reading the boxes rows: the room is nine separate boxes that touch (no single closed surface), so "
              "the closed room's openings are not found; `auto` took "
              f"{', '.join(bx['auto']['methods'])}: the sky over every direction that meets no surface in closed form "
              "(radiometry/skies/obstructed_aperture.py open_directions), the rest through the gate, the window (a "
              "gap in the faces of the scene's bounding box, radiometry/scene/envelope.py) an emitter gated like the "
              "world (since 2026-12-07, sky_component.add_envelope_emitters; before it 95.0 % open, z s.d. 0.99), "
              f"{bx['auto']['s_per_call_mean']:.2f} s per call (such a room was rendered whole before: "
              "bench/boxes_room_split.md)"
              + ("" if not bp or "coverage_thin" not in bp["auto"] else
                 f"; behind the pane {bp['auto']['s_per_call_mean']:.2f} s per call, its directions through the pane "
                 "weighted by T(theta) with a hard bound, the window not made an emitter (a see-through surface stands "
                 "in the scene: with emitters behind the pane, one run of 100 seeds read 85.4 % against the "
                 "`dielectric` box and 90.8 % against thin `glass`, the readings scattering 1.11-1.15x their stated "
                 "error at three of the five points, so the rows here are the run without them, the path taken). "
                 "Unlike the pane room, it holds against Radiance's "
                 f"`dielectric` box too ({100 * bp['auto']['coverage']['coverage']:.1f} %); a likely reason, not "
                 "tested: the pane sits at the room end of a 0.2 m deep opening whose reveals hide the grazing "
                 "directions where the thin-pane model's averaging of s and p differs most from the solid slab")
              + ".", ""]
    if "roof" in data["scenes"] and "coverage_thin" in data["scenes"]["roof"]["auto"]:
        r = data["scenes"]["roof"]
        thin_over = [100 * (t / d - 1) for t, d in zip(r["radiance_thin"]["df"], r["radiance"]["df"])]
        L += ["Reading the roof rows: the pane tilted 30 deg with the roof is recognised (`auto` took "
              f"{', '.join(r['auto']['methods'])}, SC proven through the pane at "
              f"{100 * r['auto']['sc_proven_share']:.0f} % of readings). Radiance's thin `glass` reads "
              f"{', '.join(f'{v:+.2f}' for v in thin_over)} % against its `dielectric` box at the points "
              "(presumably the dielectric's per-interface average over s and p, as for the vertical pane above; "
              "not isolated for this pane). `auto` holds "
              f"against both (z mean {r['auto']['coverage']['z_mean']:+.2f} against the box, "
              f"{r['auto']['coverage_thin']['z_mean']:+.2f} against thin glass)."]
        if "auto_minus_render" in r:
            am = r["auto_minus_render"]
            rm = [p["mean_df"] for p in r["render"]["coverage"]["per_point"]]
            L[-1] += (" Beside the whole render (no emitters) `auto` reads "
                      + ", ".join(f"{100 * d / m:+.2f} % ({d / e:+.1f} s.e.)" for d, e, m in
                                  zip(am["diff"], am["se"], rm))
                      + f" at the points, and the render's z mean against thin glass is "
                      f"{r['render']['coverage_thin']['z_mean']:+.2f}: a small deficit of the emitters under "
                      "the tilted pane, well inside the stated 2 % but of one sign; not isolated here.")
        L.append("")
    for s in data["scenes"].values():
        a, c, rad = s["auto"], s["auto"]["coverage"], s["radiance"]
        L += [f"### {s['name']}: {s['description']}", "",
              f"Radiance (its s.e. aimed at {rad.get('ref_fraction', 0.3):g} x the stated; {rad['wall_s']:.0f} s in "
              "all, a pilot process of "
              f"{data.get('pilot', 20000)} samples per point planning the rest): per point "
              + "; ".join(f"{r} processes x {n} samples, {d} distinct means, between/stated {b:.2f}" for r, n, d, b in
                          zip(rad["runs"], rad["samples_per_run"], rad["distinct_process_means"],
                              rad["between_over_stated"]))
              + ". Load average before "
              f"{', '.join(f'{v:.2f}' for v in s['load_before'])}, after "
              f"{', '.join(f'{v:.2f}' for v in s['load_after'])}; warm-up call {s['warmup_s']:.1f} s.", "",
              "| point (m) | normal | ref DF (%) | ref s.e. (%) | ref s.e. / stated | Radiometer mean DF (%) | "
              "mean stated rel. err. | scatter / stated | SC (%) | ERC (%) | IRC mean (%) | bias (%) | "
              "bias / s.e. | z mean | z s.d. | coverage |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for j, p in enumerate(c["per_point"]):
            L.append(f"| {tuple(s['points'][j])} | {tuple(s['normals'][j])} | {p['ref_df']:.4f} | {p['ref_se']:.4f} | "
                     f"{p['ref_se_over_stated']:.2f} | {p['mean_df']:.4f} | {100 * p['mean_rel_std_error']:.2f} % | "
                     f"{p['scatter_over_stated']:.2f} | {_f(a['sc'][j], 4)} | {_f(a['erc'][j], 4)} | "
                     f"{_f(a['irc_mean'][j], 4)} | {p['bias']:+.4f} | {p['bias_over_se']:+.2f} | {p['z_mean']:+.2f} | "
                     f"{p['z_sd']:.2f} | {100 * p['coverage']:.0f} % |")
        L += ["", "Notes of the first seed's first point:", ""] + [f"- {n}" for n in a["notes_seed0"][0]] + [""]
        if "radiance_thin" in s:
            rt, ct = s["radiance_thin"], a["coverage_thin"]
            L += [f"Against Radiance's thin `glass` (one polygon in the pane's mid-plane, s and p apart: the thin-pane "
                  f"model Radiometer measures with; its s.e. aimed at {rt.get('ref_fraction', 0.3):g} x the stated; "
                  f"{rt['wall_s']:.0f} s, per point "
                  + "; ".join(f"{r} x {n}, {d} distinct, between/stated {b:.2f}" for r, n, d, b in
                              zip(rt["runs"], rt["samples_per_run"], rt["distinct_process_means"],
                                  rt["between_over_stated"]))
                  + f"): `auto` coverage {100 * ct['coverage']:.1f} %, z mean {ct['z_mean']:+.2f}, s.d. "
                  f"{ct['z_sd']:.2f}"
                  + (f"; `render` coverage {100 * s['render']['coverage_thin']['coverage']:.1f} %, z mean "
                     f"{s['render']['coverage_thin']['z_mean']:+.2f}" if "render" in s else "") + ".", "",
                  "| point (m) | Radiance thin DF (%) | s.e. (%) | Radiance dielectric DF (%) | Radiometer mean (%) | "
                  "bias vs thin (%) | bias / s.e. | z mean | coverage |", "|---|---|---|---|---|---|---|---|---|"]
            for j, p in enumerate(ct["per_point"]):
                L.append(f"| {tuple(s['points'][j])} | {p['ref_df']:.4f} | {p['ref_se']:.4f} | "
                         f"{rad['df'][j]:.4f} | {p['mean_df']:.4f} | {p['bias']:+.4f} | {p['bias_over_se']:+.2f} | "
                         f"{p['z_mean']:+.2f} | {100 * p['coverage']:.0f} % |")
            L.append("")
        if "radiance_thin_first" in s:
            rf, cf = s["radiance_thin_first"], a["coverage_thin_first"]
            L += [f"A first thin-`glass` reference, its s.e. aimed at {rf['ref_fraction']:g} x the stated "
                  f"({', '.join(str(r) for r in rf['runs'])} processes per point), gave `auto` coverage "
                  f"{100 * cf['coverage']:.1f} %, z mean {cf['z_mean']:+.2f}; per point DF_ref "
                  + ", ".join(f"{d:.4f} +- {e:.4f}" for d, e in zip(rf["df"], rf["se"]))
                  + " %, bias / s.e. " + ", ".join(f"{p['bias_over_se']:+.2f}" for p in cf["per_point"])
                  + " (the table above is the longer run).", ""]
        if "render" in s:
            r, rc = s["render"], s["render"]["coverage"]
            L += [f"Whole render (`method=\"render\"`: Cycles under the sky, no emitters), {rc['seeds']} seeds, "
                  f"{r['s_per_call_mean']:.2f} s per call, against the same Radiance reference: coverage "
                  f"{100 * rc['coverage']:.1f} %, z mean {rc['z_mean']:+.2f}, s.d. {rc['z_sd']:.2f}.", "",
                  "| point (m) | render mean DF (%) | bias vs Radiance dielectric (%) | bias / s.e. | bias vs "
                  "Radiance thin (%) | bias / s.e. | auto - render (%) | (auto - render) / s.e. (seeds' scatter) |",
                  "|---|---|---|---|---|---|---|---|"]
            thin = r.get("coverage_thin", {}).get("per_point")
            for j, p in enumerate(rc["per_point"]):
                d, e = s["auto_minus_render"]["diff"][j], s["auto_minus_render"]["se"][j]
                t = f"{thin[j]['bias']:+.4f} | {thin[j]['bias_over_se']:+.2f}" if thin else "- | -"
                L.append(f"| {tuple(s['points'][j])} | {p['mean_df']:.4f} | {p['bias']:+.4f} | "
                         f"{p['bias_over_se']:+.2f} | {t} | {d:+.4f} | {d / e:+.2f} |")
            L.append("")
    if "pane_diagnostic" in data:
        d = data["pane_diagnostic"]
        rad = d["radiance"]
        L += ["### The pane alone: black room, black ground (only the sky seen straight through the pane)", "",
              f"Radiometer `auto` ({', '.join(d['methods'])}; through the emitters), {d['seeds']} seeds at "
              f"{100 * d['target_rel_error']:.3g} %, {d['s_per_call']:.2f} s per call, mean and its s.e. (from the "
              f"stated errors; from the seeds' scatter in brackets); Radiance ({', '.join(map(str, rad['runs']))} "
              "processes per point, the dielectric box); closed forms (sky_aperture.pane_bounded_illuminance, "
              "+- its hard bound) of the slab's T(theta) with s and p summed separately over the internal "
              "reflections (thin_glass.slab: Radiometer's model) and with Fresnel averaged over s and p at each "
              "interface, T = (1 - r)/(1 + r) (Radiance's dielectric.c halves r_s + r_p per interface). DF in %.", "",
              "Radiance thin: its `glass` material (one polygon, s and p apart, glass.c).", "",
              "| point (m) | Radiometer | closed form, polarisations separate | Radiance thin `glass` | Radiance "
              "`dielectric` box | closed form, averaged per interface | Radiometer / separate - 1 | "
              "Radiance thin / separate - 1 | Radiance dielectric / averaged - 1 | separate / averaged - 1 |",
              "|---|---|---|---|---|---|---|---|---|---|"]
        for j, p in enumerate(d["points"]):
            a, ase, asc = d["radiometer_mean"][j], d["radiometer_se"][j], d["radiometer_scatter_se"][j]
            cp, ca = d["closed_polarised"][j], d["closed_averaged"][j]
            r, rse = rad["df"][j], rad["se"][j]
            t, tse = d["radiance_thin"]["df"][j], d["radiance_thin"]["se"][j]
            L.append(f"| {tuple(p)} | {a:.4f} +- {ase:.4f} ({asc:.4f}) | {cp[0]:.4f} +- {cp[1]:.4f} | "
                     f"{t:.4f} +- {tse:.4f} | {r:.4f} +- {rse:.4f} | {ca[0]:.4f} +- {ca[1]:.4f} | "
                     f"{100 * (a / cp[0] - 1):+.2f} % | {100 * (t / cp[0] - 1):+.2f} % | "
                     f"{100 * (r / ca[0] - 1):+.2f} % | {100 * (cp[0] / ca[0] - 1):+.2f} % |")
        L.append("")
    return "\n".join(L) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", nargs="+", default=["open", "pane", "skylight", "deep"])
    ap.add_argument("--seeds", type=int, default=100)
    ap.add_argument("--target", type=float, default=0.02)
    ap.add_argument("--render-seeds", type=int, default=20)
    ap.add_argument("--ref-fraction", type=float, default=0.3,
                    help="the reference's s.e. aimed at this fraction of the s.e. Radiometer states")
    ap.add_argument("--probe", action="store_true", help="one call per scene, printed; nothing written")
    ap.add_argument("--md", action="store_true", help="rewrite the .md from the .json only")
    ap.add_argument("--pane-thin-reference", action="store_true",
                    help="the pane scene's readings against Radiance's thin glass as well")
    ap.add_argument("--pane-diagnostic", action="store_true",
                    help="the pane room black (only the sky through the pane) against two closed forms")
    args = ap.parse_args(argv)
    from radiometer import api

    room = _room()
    specs = scene_specs(room)
    data = json.loads(OUT_JSON.read_text()) if OUT_JSON.exists() and not args.probe else {"scenes": {}}
    if args.md:
        OUT_MD.write_text(markdown(data))
        return
    if args.pane_thin_reference:
        pane_thin_reference(room, data, args.ref_fraction)
        OUT_JSON.write_text(json.dumps(data, indent=1))
        OUT_MD.write_text(markdown(data))
        print(markdown(data))
        return
    if args.pane_diagnostic:
        data["pane_diagnostic"] = pane_diagnostic(api, room)
        OUT_JSON.write_text(json.dumps(data, indent=1))
        OUT_MD.write_text(markdown(data))
        print(markdown(data))
        return
    for name in args.scenes:
        t0 = time.perf_counter()
        res = run_scene(api, room, name, specs[name], args)
        if res is None:
            continue
        res["total_s"] = time.perf_counter() - t0
        data["scenes"][name] = res
        OUT_JSON.write_text(json.dumps(data, indent=1))
        OUT_MD.write_text(markdown(data))
        c = res["auto"]["coverage"]
        print(f"{name}: coverage {100 * c['coverage']:.1f} %, z mean {c['z_mean']:+.2f}, s.d. {c['z_sd']:.2f}, "
              f"{res['total_s']:.0f} s", flush=True)


if __name__ == "__main__":
    main()

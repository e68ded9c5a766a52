"""Issue 18 acceptance QA on scenes the corpus does not hold (T8): every case of
tests/bpy/glass_fog_unseen_scenes.py read by ``api.measure_illuminance`` (methods auto and render,
qualities preview and standard, several seeds) against its independent reference: this file's own
Fresnel slab (``fresnel_slab``) for the clear panes under delta lights and a 0.53 degree sun, converged
patch renders (tests/bpy/glass_fog_unseen_references.json, made by make_glass_fog_unseen_references.py)
elsewhere. Writes bench/qa_glass_fog.json and prints the rows of bench/qa_glass_fog.md.

    .venv/bin/python bench/qa_glass_fog.py [--seeds N] [case ...]
    .venv/bin/python bench/qa_glass_fog.py --summary      # the table of qa_glass_fog.md

``--seeds N``: seeds 0..N-1 for every rendered reading (default 3).

The three criteria of issue 18, each on its own (the reference's s.e. in quadrature):
(1) |err| <= max(3 x s.e., 0.5 %); (2) a reading marked exact within 1e-4 of a closed form;
(3) a reading stating < 5 % is off by no more than 5 x what it states.
"""

import json
import math
import pathlib
import sys
import time

import bpy  # noqa: F401  (Blender as a module)

ROOT = pathlib.Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests" / "bpy"
OUT = ROOT / "bench" / "qa_glass_fog.json"


sys.path.insert(0, str(ROOT / "bench"))
from scenes import load_test_module as _load  # noqa: E402


def criteria(reading_lux, stated, exact, ref_lux, ref_se):
    err = reading_lux / ref_lux - 1.0
    combined = math.hypot(stated, ref_se)
    c1 = abs(err) <= max(3.0 * combined, 0.005)
    c2 = (not exact) or (ref_se == 0.0 and abs(err) <= 1e-4)
    c3 = stated >= 0.05 or abs(err) <= max(5.0 * combined, 1e-9)
    z = err / combined if combined > 0 else (0.0 if err == 0 else math.inf)
    return err, z, c1, c2, c3


def _write(rows):
    OUT.write_text("[\n" + ",\n".join(json.dumps(r) for r in rows) + "\n]\n")


def main(only, seeds=3):
    import radiometer
    from radiometer import api

    u = _load("glass_fog_unseen_scenes")
    stored = json.loads((TESTS / "glass_fog_unseen_references.json").read_text())["values"]
    rows = json.loads(OUT.read_text()) if OUT.exists() and only else []
    rows = [r for r in rows if r["case"] not in only]
    plans = []
    for name, (build, expected, kind) in u.CLOSED_FORM.items():
        plans.append((name, build, kind, lambda label, point, normal, f=expected: (f(label), 0.0),
                      [("auto", "preview", 0), ("auto", "standard", 0)]
                      + [("render", q, s) for q in ("preview", "standard") for s in range(seeds)]))
    for name, (build, kind) in u.RENDERED.items():
        def ref(label, point, normal, name=name):
            e = stored[f"{name}/{label}"]
            assert all(abs(a - b) < 1e-12 for a, b in zip(e["point"] + e["normal"], list(point) + list(normal)))
            return u.lux(e["E_rgb"]), e["rel_std_error"]
        plans.append((name, build, kind, ref, [("auto", q, s) for q in ("preview", "standard") for s in range(seeds)]))
    for name, build, kind, ref, runs in plans:
        if only and name not in only:
            continue
        scene, cases = build()
        radiometer.register()
        try:
            for label, point, normal in cases:
                ref_lux, ref_se = ref(label, point, normal)
                for method, quality, seed in runs:
                    t0 = time.perf_counter()
                    r = api.measure_illuminance(point, normal, scene=scene, method=method, quality=quality, seed=seed)
                    seconds = time.perf_counter() - t0
                    row = {"case": name, "kind": kind, "meter": label, "method": method, "got_method": r.method,
                           "quality": quality, "seed": seed, "lux": r.illuminance,
                           "stated": float(r.rel_std_error), "exact": bool(r.exact), "ref_lux": ref_lux,
                           "ref_se": ref_se, "samples": int(r.samples or 0), "seconds": round(seconds, 2),
                           "notes": list(r.notes)}
                    if ref_lux > 0:
                        err, z, c1, c2, c3 = criteria(r.illuminance, row["stated"], row["exact"], ref_lux, ref_se)
                        row.update(err=err, z=z, c1=c1, c2=c2, c3=c3)
                    else:  # a meter in full shade of a black room: the answer is 0
                        row.update(err=r.illuminance, z=None, c1=r.illuminance == 0.0, c2=not r.exact or r.illuminance == 0.0,
                                   c3=True)
                    print(json.dumps({k: v for k, v in row.items() if k != "notes"}), flush=True)
                    if seed and row["c1"] and row["c2"] and row["c3"]:
                        row["notes"] = []  # notes kept for seed 0 and every failing reading (file size)
                    rows.append(row)
                    _write(rows)
        finally:
            radiometer.unregister()


def summary():
    """Markdown rows of bench/qa_glass_fog.md from bench/qa_glass_fog.json: one per case, meter, method
    and quality (seeds pooled)."""
    rows = json.loads(OUT.read_text())
    groups = {}
    for r in rows:
        groups.setdefault((r["case"], r["meter"], r["method"], r["quality"]), []).append(r)
    print("| case | meter | method (ran) | quality | seeds | reading lx (mean; range) | stated (mean) | reference lx +- s.e. "
          "| z (mean; worst) | exact | (1) | (2) | (3) | samples (median) |")
    print("|---|---|---|---|---:|---|---:|---|---|---|---|---|---|---:|")
    for (case, meter, method, quality), g in groups.items():
        lux = [r["lux"] for r in g]
        zs = [r["z"] for r in g if r["z"] is not None]
        ran = "/".join(sorted({r["got_method"] for r in g}))
        z = "—" if not zs else f"{sum(zs) / len(zs):+.2f}; {max(zs, key=abs):+.2f}"
        if all(r["stated"] == 0 and r["ref_se"] == 0 for r in g):
            z = f"— (err {max(abs(r['err']) for r in g):.1e})"
        ref = f"{g[0]['ref_lux']:.6g} +- {100 * g[0]['ref_se']:.2g} %" if g[0]["ref_se"] else f"{g[0]['ref_lux']:.6g} (closed form)"
        stated = sum(r["stated"] for r in g) / len(g)
        exact = sum(r["exact"] for r in g)
        samples = sorted(r["samples"] for r in g)[len(g) // 2]
        print(f"| {case} | {meter} | {method} ({ran}) | {quality} | {len(g)} | {sum(lux) / len(lux):.6g}; "
              f"{min(lux):.6g}–{max(lux):.6g} | {100 * stated:.3g} % | {ref} | {z} | {exact}/{len(g)} | "
              f"{sum(r['c1'] for r in g)}/{len(g)} | {sum(r['c2'] for r in g)}/{len(g)} | {sum(r['c3'] for r in g)}/{len(g)} "
              f"| {samples:,} |")


if __name__ == "__main__":
    args = sys.argv[1:]
    if args == ["--summary"]:
        summary()
        sys.exit(0)
    n_seeds = 3
    if "--seeds" in args:
        k = args.index("--seeds")
        n_seeds = int(args[k + 1])
        del args[k:k + 2]
    main(args, n_seeds)

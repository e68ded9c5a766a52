"""Measure how faithfully Cycles renders each Radiometer BRDF; writes bench/brdf_fidelity.md.

Run: ``.venv/bin/python bench/brdf_fidelity.py`` (bpy as a module, Cycles CPU; about 20 minutes on a
loaded 2-core machine); ``bench/brdf_fidelity.py blinn_phong [...]`` re-runs only those models' rows and
keeps every other row of the existing table (the header says which rows were re-run, and when).
For every library model and method (node group, OSL): the stated fidelity from the numpy fit
(shading.fit: weighted RMS relative difference and directional-albedo difference), then renders of the
realised material at many (theta_i, phi_i, theta_o, phi_o) with one point light (shading.validate),
compared with the library's f (render vs model) and with the closure network (render vs closure).
"""

import itertools
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# a default parameter set per model, plus a second, harder one where it matters
EXTRA = {
    "ggx": [{"alpha": 0.3, "f0": 0.04}, {"alpha_x": 0.1, "alpha_y": 0.5, "f0": [0.95, 0.64, 0.54]}],
    "beckmann": [{"alpha": 0.3, "f0": 0.04}, {"alpha_x": 0.4, "alpha_y": 0.1, "f0": 0.9}],
    "blinn_phong": [{}, {"n": 200.0}],
    "phong": [{}, {"n": 100.0}],
    "oren_nayar": [{}, {"variant": "cycles", "sigma": 0.5}],
}


def configs():
    out = []
    for ti, to, dphi in itertools.product((0, 20, 40, 60, 75), (10, 30, 50, 70), (0, 60, 120, 180)):
        for phi_i in (0, 45):
            out.append((ti, phi_i, to, phi_i + dphi))
    return out


def main(path=os.path.join(HERE, "brdf_fidelity.md"), only=()):
    import bpy

    import radiometer
    from radiometer import brdf
    from radiometer.shading import closures as C
    from radiometer.shading import fit as F
    from radiometer.shading import validate as V
    from radiometer.shading.assign import assign_brdf
    from radiometer.shading.realise import check_params

    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    wi, wo = V.config_directions(configs())
    rows = []
    t0 = time.time()
    for model in brdf.names():
        if only and model not in only:
            continue
        for params in EXTRA.get(model, [{}]):
            for method in ("nodes", "osl"):
                mat = bpy.data.materials.new(f"bench {model}")
                try:
                    fid = assign_brdf(mat, model, method, **params)
                except Exception as exc:  # report, do not hide
                    rows.append((model, params, method, "error", str(exc)) + ("",) * 9)
                    continue
                if any(t.closure == "mirror" for t in fid.terms):
                    rows.append((model, params, method, fid.kind, "delta") + ("",) * 6 + ("n/a (delta lobe)", "", fid.closure))
                    continue
                kwargs = check_params(model, params)
                rendered = V.render_f(mat, wi, wo, osl=(method == "osl"))
                model_f = np.asarray(brdf.evaluate(model, wi, wo, **kwargs), dtype=float) * np.ones(3)
                closure_f = C.evaluate_terms(fid.terms, wi, wo)
                m = model_f > 1e-3 * model_f.max()
                c = closure_f > 1e-3 * closure_f.max()
                vs_model = float(np.max(np.abs(rendered - model_f)[m] / model_f[m]))
                vs_closure = float(np.max(np.abs(rendered - closure_f)[c] / closure_f[c]))
                rms_render = F.rms_rel_diff(rendered, model_f, wi, wo)
                pw = fid.pointwise
                rows.append((model, params, method, fid.kind, f"{100 * fid.rms_rel_diff:.2f} %",
                             f"{100 * pw.rms:.2f} %", f"{pw.median:.3f}", f"{pw.p95:.3f}", f"{pw.max:.3f}",
                             f"{fid.albedo_diff:.4f}", f"{100 * rms_render:.2f} %", f"{100 * vs_model:.2f} %",
                             f"{100 * vs_closure:.3f} %", fid.closure))
                bpy.data.materials.remove(mat)
    radiometer.unregister()
    produced = (f"Produced by `bench/brdf_fidelity.py` (bpy {bpy.app.version_string}, Cycles CPU, "
                f"{len(wi)} direction pairs per row, {time.time() - t0:.0f} s).")
    old_rows = {}
    if only:
        # keep the other models' rows (and the header line of their run) from the existing table
        with open(path, encoding="utf-8") as f:
            old_lines = f.read().splitlines()
        produced = next(x for x in old_lines if x.startswith("Produced by")) + (
            f" Rows of {', '.join(only)} re-run on {time.strftime('%Y-%m-%d')} ({time.time() - t0:.0f} s).")
        for x in old_lines:
            cells = [c.strip() for c in x.strip("|").split("|")]
            if x.startswith("| ") and len(cells) == 14 and cells[0] not in ("model",) + tuple(only):
                old_rows.setdefault(cells[0], []).append(x)
    lines = [
        "# BRDF fidelity: Radiometer numpy models vs their Cycles realisations",
        "",
        produced,
        "",
        "* stated RMS / albedo Δ: the fidelity `assign_brdf` reports (numpy fit, shading/fit.py: "
        "cos-weighted RMS relative difference of f over ~4500 direction pairs up to 80°; max |Δ directional albedo| "
        "at 0/30/60/75°).",
        "* uniform set: the pointwise statistics `assign_brdf` states (shading/fit.py `measure_pointwise`): all "
        "25 600 pairs of 160 directions uniform in solid angle up to 85°, pairs counted where f cos θi >= 1e-3 of "
        "its maximum; RMS as above on this set; median of the ratio q = f_Cycles / f_model; p95 and max of "
        "max(q, 1/q).",
        "* render vs model (RMS): the stated metric, computed from the renders at this row's direction pairs.",
        "* render vs model (max): max relative difference between the rendered f = L_r / E_i (point light, radius 0, "
        "direct light only) and the library's f, over pairs where f > 0.1 % of its maximum.",
        "* render vs closure: the same against the numpy transcription of the Cycles closures (checks the "
        "transcription; it is what the stated fidelity was computed with).",
        "",
        "| model | params | method | fidelity | stated RMS | uniform RMS | median q | p95 ratio | max ratio | albedo Δ "
        "| render vs model (RMS) | render vs model (max) | render vs closure (max) | Cycles closures |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    new_rows = {}
    for r in rows:
        p = ", ".join(f"{k}={v}" for k, v in r[1].items()) or "defaults"
        new_rows.setdefault(r[0], []).append("| " + " | ".join([r[0], p] + [str(x) for x in r[2:]]) + " |")
    for model in brdf.names():  # the library's order
        lines.extend(new_rows.get(model) or old_rows.get(model, []))
    from radiometer.outputs import write_text

    write_text(path, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    sys.exit(main(only=tuple(sys.argv[1:])))

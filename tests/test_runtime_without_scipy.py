"""Run-time code works in a Python without scipy, matplotlib and colour-science (like Blender's).

A fresh interpreter blocks the three imports (``sys.modules[name] = None`` makes ``import name``
raise ImportError) and then runs every model's evaluate/albedo, the Student-t interval, the closure
fits (realise, i.e. shading.fit) and a plot request, which must fail with the clear RadiometerError.
Reference values: the fidelity shading.realise stated with scipy's optimisers (tests/test_shading_optim.py).
"""

import json
import math
import subprocess
import sys
import textwrap

import pytest

SCRIPT = textwrap.dedent("""
    import json, os, sys, tempfile
    for name in ("scipy", "matplotlib", "colour"):
        sys.modules[name] = None
    import numpy as np
    import radiometer.brdf as brdf
    from radiometer.radiometry.sampling import stats
    from radiometer.shading.realise import realise
    from radiometer.errors import RadiometerError

    out = {"albedo": {}, "fidelity": {}}
    wi = np.array([[0.3, 0.1, 0.9], [0.0, 0.0, 1.0]])
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    wo = np.array([[-0.2, -0.1, 0.95], [0.6, 0.0, 0.8]])
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    for model in brdf.names():
        f = np.asarray(brdf.evaluate(model, wi, wo), dtype=float)
        assert np.all(np.isfinite(f)) and np.all(f >= 0), (model, f)
        rho = np.asarray(brdf.albedo(model, np.array([0.0, 0.6, 1.3])), dtype=float)
        assert np.all(np.isfinite(rho)) and np.all(rho <= 1.0 + 1e-3), (model, rho)
        out["albedo"][model] = rho.tolist()
    values = np.array([[1.0, 2.0], [1.5, 2.5], [0.5, 1.5], [1.2, 2.2]])
    out["t_half_width"] = stats.t_half_width_95(values).tolist()
    out["t_quantile_3"] = stats.t_quantile_975(3)
    for model, method in (("ward", "nodes"), ("blinn_phong", "nodes"), ("blinn_phong", "osl")):
        _, fid = realise(model, method)
        out["fidelity"][f"{model} {method}"] = [fid.rms_rel_diff, fid.albedo_diff]
    from radiometer.plots.brdf import write_summary
    try:
        write_summary("ward", os.path.join(tempfile.gettempdir(), "radiometer_no_mpl.png"))
    except RadiometerError as exc:
        out["plot_error"] = str(exc)
    from radiometer import plots
    try:
        plots.pyplot()
    except RadiometerError as exc:
        out["pyplot_error"] = str(exc)
    out["blocked_loaded"] = [n for n in ("scipy", "matplotlib", "colour") if sys.modules.get(n) is not None]
    print("RESULT " + json.dumps(out))
""")


def _run():
    proc = subprocess.run([sys.executable, "-W", "error::RuntimeWarning", "-c", SCRIPT], cwd="/",
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    line = [s for s in proc.stdout.splitlines() if s.startswith("RESULT ")][-1]
    return json.loads(line[len("RESULT "):])


@pytest.mark.slow
def test_runtime_paths_work_without_scipy_matplotlib_colour():
    out = _run()
    assert out["blocked_loaded"] == []
    from radiometer import brdf

    assert sorted(out["albedo"]) == sorted(brdf.names()) and "beckmann" in out["albedo"]
    # Student t(0.975, 3): scipy.stats.t.ppf(0.975, 3) = 3.1824463052837078 (scipy 1.17.1)
    t3 = 3.1824463052837078
    assert abs(out["t_quantile_3"] - t3) < 1e-14 * t3
    se = math.sqrt(0.53 / 3) / 2  # [1, 1.5, 0.5, 1.2]: sum of squared deviations 0.53, 3 dof, 4 batches
    assert all(abs(h - t3 * se) < 1e-13 for h in out["t_half_width"])  # column 2 = column 1 + 1
    # stated fidelity in this (scipy-equipped) process: the numpy-only run must state the same
    from radiometer.shading.realise import realise

    expected = {f"{m} {me}": (realise(m, me)[1].rms_rel_diff, realise(m, me)[1].albedo_diff)
                for m, me in (("ward", "nodes"), ("blinn_phong", "nodes"), ("blinn_phong", "osl"))}
    for key, (rms, alb) in expected.items():
        got_rms, got_alb = out["fidelity"][key]
        assert abs(got_rms - rms) <= 1e-3 * rms and abs(got_alb - alb) <= 1e-3 * alb, (key, got_rms, got_alb)
    for key in ("plot_error", "pyplot_error"):
        assert out[key].startswith("plots need matplotlib, which this Blender's Python lacks: "), out
        assert "pip install matplotlib" in out[key]

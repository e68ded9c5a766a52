"""bpy tier: the add-on works in a Blender whose Python has only numpy (no scipy, matplotlib, colour).

A fresh bpy process blocks the three imports (``sys.modules[name] = None``), registers the add-on,
builds a point light + area light scene and runs a rendered measurement to 1 % (Student-t interval,
radiometry.sampling.stats), a BRDF assignment with a fitted closure (shading.fit: BVLS + Nelder-Mead), a law
check asked for a plot (a one-line error) and without one, the analysis operators (pictures skipped
with a warning) and the report (numbers, CSV, JSON,
report.md without images), and the BRDF plot operator and ``check --plots``, which must say clearly
why they cannot plot. Reference values: the analytic illuminance of the same lights (point: I cos / d^2; disk
formula of tests/bpy/test_meter.py) and the fidelity stated with scipy (tests/test_shading_optim.py).
"""

import json
import os
import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import json, math, os, sys, tempfile
    for name in ("scipy", "matplotlib", "colour"):
        sys.modules[name] = None
    import bpy
    import radiometer
    from radiometer import api
    from radiometer.compat import ensure_node_tree
    from radiometer.errors import RadiometerError

    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world

    def light(kind, location, **props):
        data = bpy.data.lights.new(kind.lower(), kind)
        for k, v in props.items():
            setattr(data, k, v)
        obj = bpy.data.objects.new(data.name, data)
        obj.location = location
        scene.collection.objects.link(obj)
        return obj

    point = light("POINT", (0.5, 0.0, 2.0), energy=100.0, shadow_soft_size=0.0)
    area = light("AREA", (0.0, 0.0, 1.0), energy=50.0, shape="DISK", size=1.0)
    out = {}
    analytic = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), method="analytic")
    rendered = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), method="render", target_rel_error=0.01)
    out["analytic"] = analytic.illuminance
    out["rendered"] = rendered.illuminance
    out["rel_std_error"] = rendered.rel_std_error
    out["method"] = rendered.method

    mesh = bpy.data.meshes.new("m")
    obj = bpy.data.objects.new("o", mesh)
    scene.collection.objects.link(obj)
    mat = bpy.data.materials.new("ward material")
    mesh.materials.append(mat)
    fid = api.assign_brdf(mat, "ward", method="nodes")
    out["ward"] = [fid.kind, fid.rms_rel_diff, fid.albedo_diff]

    plot = os.path.join(tempfile.mkdtemp(), "inverse_square.png")
    try:  # asked for a plot that cannot be drawn: an error, never a silent success
        api.check_inverse_square(point, scene=scene, method="analytic", plot=plot)
        out["law_plot_error"] = None
    except RadiometerError as exc:
        out["law_plot_error"] = str(exc)
    out["law_plot_exists"] = os.path.exists(plot)
    out["law_exponent"] = api.check_inverse_square(point, scene=scene, method="analytic").exponent

    mat.radiometer_brdf.model = "ward"
    try:
        with bpy.context.temp_override(object=obj, material=mat):
            bpy.ops.radiometer.brdf_plot()
        out["operator_error"] = None
    except RuntimeError as exc:
        out["operator_error"] = str(exc)
    try:
        from radiometer.plots.brdf import write_summary
        write_summary("ward", os.path.join(tempfile.mkdtemp(), "ward.png"))
        out["plot_error"] = None
    except RadiometerError as exc:
        out["plot_error"] = str(exc)

    # operators and the report: numbers, CSV, JSON and report.md without images
    from radiometer import cli
    outdir = tempfile.mkdtemp()
    settings = scene.radiometer_analysis
    settings.output_dir = outdir + os.sep
    settings.colour_plane = True  # needs matplotlib's colour map: a warning, the grid stays
    out["op_inverse"] = sorted(bpy.ops.radiometer.check_inverse_square(light="__ALL__"))
    out["op_inverse_exponent"] = settings.laws[point.name].exponent
    out["op_grid"] = sorted(bpy.ops.radiometer.illuminance_grid(create_plane=True))
    out["grid"] = [settings.grid_avg, settings.grid_image, os.path.exists(settings.grid_csv)]
    report = api.export_report(os.path.join(outdir, "report"), scene=scene, convergence=False)
    out["report_errors"] = report["errors"]
    out["report_files"] = sorted(os.listdir(os.path.join(outdir, "report")))
    out["report_exponents"] = [r.get("exponent") for r in report["inverse_square"]]
    out["cli_plots"] = cli._blender_cli(["check", "--light", point.name, "--plots", os.path.join(outdir, "p")])
    out["cli_grid_png"] = cli._blender_cli(["grid", "--png", os.path.join(outdir, "g.png")])
    out["cli_grid_csv"] = cli._blender_cli(["grid", "--csv", os.path.join(outdir, "g.csv")])
    out["blocked_loaded"] = [n for n in ("scipy", "matplotlib", "colour") if sys.modules.get(n) is not None]
    radiometer.unregister()
    print("RESULT " + json.dumps(out), flush=True)
    sys.stderr.flush()
    os._exit(0)  # Blender 4.5's bpy can hang at exit (see tests/bpy/conftest.py)
""")


def test_addon_runs_in_a_numpy_only_python():
    proc = subprocess.run([sys.executable, "-c", SCRIPT], cwd="/", capture_output=True, text=True, timeout=600,
                          env=dict(os.environ))
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    out = json.loads([s for s in proc.stdout.splitlines() if s.startswith("RESULT ")][-1][len("RESULT "):])
    assert out["blocked_loaded"] == []
    # point: I cos / d^2 with I = P / (4 pi) W/sr; disk: pi L r^2 / (r^2 + h^2), L = P / (pi^2 r^2); 683 lm/W
    point = 100.0 / (4 * 3.141592653589793) * (2.0 / 4.25 ** 0.5) / 4.25
    disk = 50.0 / (3.141592653589793 * 0.25) * 0.25 / (0.25 + 1.0)
    assert abs(out["analytic"] - 683.0 * (point + disk)) < 1e-4 * out["analytic"]
    assert out["method"] == "render" and 0 < out["rel_std_error"] < 0.01
    # the 95 % interval (t s.e.) met the 1 % target: the render agrees with the closed form to a few s.e.
    assert abs(out["rendered"] - out["analytic"]) < 4 * out["rel_std_error"] * out["analytic"]
    kind, rms, albedo = out["ward"]
    assert kind == "approximate"
    from radiometer.shading.realise import realise

    ref = realise("ward", "nodes")[1]  # stated in this (scipy-equipped) process
    assert abs(rms - ref.rms_rel_diff) < 1e-3 * ref.rms_rel_diff
    assert abs(albedo - ref.albedo_diff) < 1e-3 * ref.albedo_diff
    # a law check asked for a plot says it cannot draw it (one line); without a plot it gives its numbers
    assert "plots need matplotlib, which this Blender's Python lacks" in out["law_plot_error"]
    assert "\n" not in out["law_plot_error"] and not out["law_plot_exists"]
    assert abs(out["law_exponent"] + 2.0) < 1e-3  # point light: E ~ d^-2 exactly
    assert out["op_inverse"] == ["FINISHED"] and abs(out["op_inverse_exponent"] + 2.0) < 1e-3
    assert out["op_grid"] == ["FINISHED"]
    grid_avg, grid_image, grid_csv_exists = out["grid"]
    assert grid_avg > 0 and grid_image == "" and grid_csv_exists
    assert any(e.startswith("no plots: plots need matplotlib") for e in out["report_errors"]), out["report_errors"]
    files = out["report_files"]
    assert {"report.json", "report.md"} <= set(files) and any(f.endswith(".csv") for f in files)
    assert not any(f.endswith(".png") for f in files)
    assert out["report_exponents"] and all(e is not None for e in out["report_exponents"])
    assert out["cli_plots"] == 2 and out["cli_grid_png"] == 2  # asked for images: one-line error, exit code 2
    assert out["cli_grid_csv"] == 0  # numbers and CSV need no matplotlib
    assert "plots need matplotlib, which this Blender's Python lacks" in proc.stderr
    for key in ("operator_error", "plot_error"):
        assert out[key] and "plots need matplotlib, which this Blender's Python lacks: " in out[key], out
        assert "pip install matplotlib" in out[key]

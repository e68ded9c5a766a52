"""The patch-render cache shared by the reference generators (``make_glass_fog_references.py``,
``make_glass_fog_unseen_references.py``): render ``reference.reference_irradiance`` at every meter of
some scene builders and merge the values into a JSON file, with their provenance. Run by hand, never by
the suite; nothing of Radiometer's measurement code runs here."""

import datetime
import importlib.util
import json
import pathlib

import bpy

HERE = pathlib.Path(__file__).resolve().parent
#: How the harness samples since 2026-12-06 (stored with every value rendered since).
SAMPLER = "TABULATED_SOBOL, each pixel's table rotated by its own uniform shift (scrambling distance 1 - 2^-20)"


def load(name, prefix="_refcache_"):
    """tests/bpy/<name>.py as a module."""
    spec = importlib.util.spec_from_file_location(f"{prefix}{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def render_into(json_path, builds, *, generator, scenes_file, target, seed, max_seconds, lift=lambda point: True,
                error_kind="batch-means standard error"):
    """Render every meter of ``builds`` ({name: builder returning (scene, [(label, point, normal)])}) and
    merge ``{name}/{label}`` entries into ``json_path`` after each one (a cancelled run keeps what it
    finished). ``lift(point)``: whether the patch is lifted off its surface (``reference.lift_off_surface``)."""
    reference = load("reference")
    data = json.loads(json_path.read_text()) if json_path.exists() else {"values": {}}
    data["provenance"] = {
        "harness": "tests/bpy/reference.py reference_irradiance (white Lambertian patch, orthographic Cycles "
                   f"camera, E = pi x pixel, {error_kind})",
        "generator": generator, "scenes": scenes_file,
        "seed": seed, "target_rel_error": target, "max_seconds": max_seconds,
        "blender": bpy.app.version_string, "device": "CPU", "date": datetime.date.today().isoformat(),
        "sampler_note": "values with no 'sampler' key were rendered before 2026-12-06 with Cycles' default "
                        "scrambling distance 1: a fixed Sobol table, biased where light comes by a rare path "
                        "(tests/bpy/reference.py's docstring)"}
    for name, build in builds.items():
        scene, cases = build()
        for label, point, normal in cases:
            at = reference.lift_off_surface(scene, point, normal) if lift(point) else point
            e_rgb, se, info = reference.reference_irradiance(scene, at, normal, target_rel_error=target,
                                                             max_seconds=max_seconds, seed=seed)
            data["values"][f"{name}/{label}"] = {"point": list(point), "normal": list(normal), "E_rgb": list(e_rgb),
                                                 "rel_std_error": se, "samples": info.get("samples"),
                                                 "seconds": round(info["seconds"], 1), "sampler": SAMPLER,
                                                 "date": datetime.date.today().isoformat()}
            print(name, label, e_rgb, se, info.get("samples"), round(info["seconds"], 1), flush=True)
            json_path.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")

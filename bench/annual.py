"""Bench / validation for issue 19 item 6: annual daylight (sDA, ASE, UDI) of the side-lit room of
tests/bpy/daylight_room.py (window facing south) with a synthetic London year, Radiometer against
Radiance's two-phase method (epw2wea, gendaymtx -m 1, rcontrib -I+ over reinhartb.cal bins with a
ground bin, dctimestep). Run by hand (slow: one render per sky patch):
``.venv/bin/python bench/annual.py [--quick]``; writes bench/annual.json.
"""

import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
POINTS = [(1.0, 0.75, 0.85), (3.0, 0.75, 0.85), (1.0, 1.5, 0.85), (3.0, 1.5, 0.85), (1.0, 2.5, 0.85), (3.0, 2.5, 0.85)]


def _room():
    spec = importlib.util.spec_from_file_location("daylight_room", os.path.join(HERE, "..", "tests", "bpy",
                                                                                  "daylight_room.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_year_epw(path, latitude=51.5, longitude=-0.12, seed=11):
    """A synthetic year: pvlib's Ineichen clear sky at the site (standard time UTC+0), each day
    scaled by a random cloudiness (direct x k, diffuse raised), dew point 8 C."""
    import pandas as pd
    import pvlib

    times = pd.date_range("2026-01-01 00:30", periods=8760, freq="1h", tz="Etc/GMT")
    loc = pvlib.location.Location(latitude, longitude, tz="Etc/GMT", altitude=20)
    cs = loc.get_clearsky(times, model="ineichen")
    rng = np.random.default_rng(seed)
    k = np.repeat(rng.uniform(0.0, 1.0, 365), 24)
    dni = np.round(cs["dni"].to_numpy() * k)
    dhi = np.round(cs["dhi"].to_numpy() * (1 + 1.5 * (1 - k)))
    ghi = np.round(dhi + dni * np.maximum(0, np.cos(np.radians(loc.get_solarposition(times)["apparent_zenith"]))))
    head = [f"LOCATION,Synthetic London,ENG,GBR,pvlib Ineichen x random cloudiness,000000,{latitude},{longitude},0.0,20.0",
            "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
            "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0", "COMMENTS 1,bench/annual.py", "COMMENTS 2,",
            "DATA PERIODS,1,1,Data,Thursday, 1/ 1,12/31"]
    rows = []
    for t, g, n, d in zip(times, ghi, dni, dhi):
        f = [2026, t.month, t.day, t.hour + 1, 60, "?9", 12.0, 8.0, 70, 101325, 9999, 9999, 300, int(g), int(n), int(d),
             999999, 999999, 999999, 9999, 180, 3.0, 5, 3, 10.0, 77777, 9, 999999999, 10, 0.1, 0, 88, 0.2, 0, 1]
        rows.append(",".join(str(v) for v in f))
    with open(path, "w", encoding="latin-1") as fh:
        fh.write("\n".join(head + rows) + "\n")
    return path


def radiance_annual(folder, room, epw_path, points, m=1):
    import pyradiance

    from radiometer.radiometry import daylight_metrics, epw

    root = os.path.dirname(pyradiance.__file__)
    env = dict(os.environ, PATH=os.path.join(root, "bin") + os.pathsep + os.environ["PATH"],
               RAYPATH=os.pathsep.join([folder, os.path.join(root, "lib")]))
    lines = ["void glow groundglow\n0\n0\n4 1 1 1 0\n", "groundglow source ground\n0\n0\n4 0 0 -1 180\n",
             "void glow skyglow\n0\n0\n4 1 1 1 0\n", "skyglow source sky\n0\n0\n4 0 0 1 180\n"]
    for name, r in room.RHO.items():
        lines.append(f"void plastic {name}\n0\n0\n5 {r} {r} {r} 0 0\n")
    for k, (name, q) in enumerate(room.quads()):
        lines.append(f"{name} polygon p{k}\n0\n0\n12 " + " ".join(f"{c:g}" for v in q for c in v) + "\n")
    with open(os.path.join(folder, "room.rad"), "w") as f:
        f.write("".join(lines))
    with open(os.path.join(folder, "room.oct"), "wb") as f:
        subprocess.run(["oconv", "room.rad"], cwd=folder, env=env, stdout=f, check=True)
    rays = "".join(f"{x} {y} {z} 0 0 1\n" for x, y, z in points)
    dc = subprocess.run(["rcontrib", "-h", "-I+", "-ab", "8", "-ad", "16384", "-lw", "1e-6", "-faa",
                         "-b", "0", "-bn", "1", "-m", "groundglow",
                         "-e", f"MF:{m}", "-f", "reinhartb.cal", "-b", "rbin", "-bn", "Nrbins", "-m", "skyglow",
                         "room.oct"], cwd=folder, env=env, input=rays, capture_output=True, text=True, check=True).stdout
    dc = np.array(dc.split(), float).reshape(len(points), -1, 3)
    dc_y = 179.0 * (0.265 * dc[..., 0] + 0.670 * dc[..., 1] + 0.065 * dc[..., 2])  # lux per (W/sr/m^2 ~ 179 cd/m^2)
    subprocess.run(["epw2wea", str(epw_path), os.path.join(folder, "y.wea")], env=env, check=True, capture_output=True)
    out = {}
    for key, flags in (("all", []), ("sun", ["-d"])):
        sky = subprocess.run(["gendaymtx", "-h", "-m", str(m), *flags, os.path.join(folder, "y.wea")], env=env,
                             capture_output=True, text=True, check=True).stdout
        s = np.array(sky.split(), float).reshape(dc.shape[1], -1, 3)  # (P, T, 3) radiance
        s_y = 0.265 * s[..., 0] + 0.670 * s[..., 1] + 0.065 * s[..., 2]  # (P, T) in W/sr/m^2 (white)
        out[key] = s_y.T @ dc_y.T  # (T, N) lux: radiance x (lux per unit radiance)
    w = epw.read_epw(epw_path)
    occ = daylight_metrics.occupied_hours(w.midpoint_hours())
    sda, frac = daylight_metrics.sda(out["all"], occ)
    ase, hours = daylight_metrics.ase(out["sun"], occ)
    return {"sda": sda, "sda_point_fraction": frac.tolist(), "ase": ase, "ase_hours": hours.tolist(),
            "udi_useful": daylight_metrics.udi(out["all"], occ)[1].tolist()}


def main(quick=False):
    import bpy

    import radiometer
    from radiometer.measure import annual

    room = _room()
    folder = tempfile.mkdtemp(prefix="radiometer-annual-")
    epw_path = write_year_epw(os.path.join(folder, "year.epw"))
    t0 = time.perf_counter()
    ref = radiance_annual(folder, room, epw_path, POINTS)
    t_rad = time.perf_counter() - t0
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    room.build_blender(scene)
    t0 = time.perf_counter()
    r = annual.annual_daylight(POINTS, (0, 0, 1), epw_path, scene=scene, quality="preview",
                               target_rel_error=0.1 if quick else 0.05)
    t_rm = time.perf_counter() - t0
    result = {"points": len(POINTS), "radiometer": r.to_dict(), "radiance": ref, "seconds_radiometer": t_rm,
              "seconds_radiance": t_rad, "sda_difference_pp": 100 * (r.sda - ref["sda"]),
              "ase_difference_pp": 100 * (r.ase - ref["ase"])}
    with open(os.path.join(HERE, "annual.json"), "w", encoding="utf-8") as f:
        json.dump(result, f, indent=2, default=float)
    print(json.dumps({k: v for k, v in result.items() if k not in ("radiometer", "radiance")}, indent=1))
    print("per-point sDA hour fractions", np.round(r.sda_point_fraction, 3), np.round(ref["sda_point_fraction"], 3))
    print("per-point ASE hours", r.ase_hours, ref["ase_hours"])
    return result


if __name__ == "__main__":
    main("--quick" in sys.argv)

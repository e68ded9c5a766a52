"""Is Radiometer's annual sky matrix right on a VERTICAL plane? Three sources, no rendering.

    PYTHONPATH=... nice -n 19 .venv/bin/python bench/sky_matrix_check.py

For the synthetic London year of the annual tests (``tests/bpy/annual_room.write_epw``) and a few
planes (horizontal, vertical S / E / W / N / SE) the annual sums of plane irradiance (W/m^2 h) and
illuminance (lx h), split sun / sky / ground:

1. Radiometer: ``measure.analyses.annual.sky_matrix`` (Perez 1993 at Tregenza patch centres + the sun in
   its 4 nearest patches) times the plane's exact coefficients c_p = integral over patch p of
   max(0, n . w) dw (no rendering);
2. Radiance: ``gendaymtx -m 1`` of ``epw2wea``'s file (``-d`` sun only, ``-s`` sky only, ``-O1`` W/m^2),
   the same coefficients;
3. independent references (nothing of Radiometer's sky code): the sun E_dn max(0, cos AOI) with pvlib's
   SPA at the record midpoint (apparent position); the sky by pvlib's Perez 1990 transposition
   (``get_total_irradiance(model="perez")``) and by a direct numerical integration of the continuous
   Perez 1993 luminance distribution (normalised to the diffuse horizontal over the continuous
   hemisphere, 64 800 equal-area cells); the ground rho E_gh (1 - cos tilt) / 2.
   Photometric values: irradiances x Perez et al. 1990 efficacies at the EPW dew point (8 deg C).

Diagnostics: Radiometer's sky_vector with gendaymtx's own sun directions (``gendaymtx -n -D``) and with
gendaymtx's fixed 11 deg C dew point, to split the differences into sun position and efficacy.
Writes bench/sky_matrix_check.{json,md}.
"""

import importlib.util
import json
import os
import pathlib
import subprocess
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
PLANES = {"horizontal": (0.0, 0.0, 1.0), "south": (0.0, -1.0, 0.0), "east": (1.0, 0.0, 0.0),
          "west": (-1.0, 0.0, 0.0), "north": (0.0, 1.0, 0.0), "south-east": (0.7071067811865476, -0.7071067811865476, 0.0)}
RHO_G = 0.2


def radiance_env():
    import pyradiance

    root = os.path.dirname(pyradiance.__file__)
    return dict(os.environ, PATH=os.path.join(root, "bin") + os.pathsep + os.environ.get("PATH", ""),
                RAYPATH=os.path.join(root, "lib"))


def _y(a):
    return 0.265 * a[..., 0] + 0.670 * a[..., 1] + 0.065 * a[..., 2]


def plane_coefficients(patches, normal, n_sub=48):
    """(P,) sr: integral of max(0, n . w) over each patch (ground = patch 0, the lower hemisphere);
    midpoint rule on n_sub x n_sub equal-area cells (sin(alt), azimuth) per patch."""
    n = np.asarray(normal, float)
    t = (np.arange(n_sub) + 0.5) / n_sub
    out = np.zeros(patches.count)
    for p in range(patches.count):
        u = np.sin(patches.alt_lo[p]) + t * (np.sin(patches.alt_hi[p]) - np.sin(patches.alt_lo[p]))
        az = patches.az_lo[p] + t * (patches.az_hi[p] - patches.az_lo[p])
        uu, aa = np.meshgrid(u, az, indexing="ij")
        ca = np.sqrt(np.maximum(1 - uu ** 2, 0))
        d = np.stack([ca * np.sin(aa), ca * np.cos(aa), uu], axis=-1)
        out[p] = np.maximum(d @ n, 0).mean() * patches.solid_angle[p]
    return out


def gendaymtx(wea, flags, count, env):
    text = subprocess.run(["gendaymtx", "-h", "-m", "1", *flags, str(wea)], env=env, capture_output=True, text=True,
                          check=True).stdout
    return _y(np.array(text.split(), float).reshape(count, -1, 3)).T  # (T, P) W/sr/m^2 (visible or solar)


def gendaymtx_suns(wea, env, weather):
    """(T, 3) gendaymtx's sun directions (``-n -D -``), zero where it gives none (sun below -0.27 deg)."""
    text = subprocess.run(["gendaymtx", "-n", "-D", "-", str(wea)], env=env, capture_output=True, text=True,
                          check=True).stdout
    out = np.zeros((weather.count, 3))
    toks = text.split()
    minutes = []
    dirs = []
    for i, tok in enumerate(toks):
        if tok == "source":  # "solarNNN source sunNNN 0 0 4 x y z 0.533"
            minutes.append(int(toks[i - 1][len("solar"):]))
            dirs.append([float(v) for v in toks[i + 5:i + 8]])
    # solar_minute(jd, hr) = 1440 (jd - 1) + round(60 hr): record k's midpoint is minute 60 k + 30
    for m, d in zip(minutes, dirs):
        out[(m - 30) // 60] = d
    return out


def perez_continuous(sun_dirs, dni, dhi, doy, n_u=180, n_az=360):
    """(T, n_cells) luminance-relative weights: the continuous Perez 1993 sky normalised to E_dh = 1 over
    the continuous hemisphere; returns (cell directions (C, 3), solid angle per cell, function(t) -> L (C,))."""
    from radiometer.radiometry.skies import perez  # Table 1 coefficients and eqs. 6-8 only

    u = (np.arange(n_u) + 0.5) / n_u
    az = (np.arange(n_az) + 0.5) / n_az * 2 * np.pi
    uu, aa = np.meshgrid(u, az, indexing="ij")
    ca = np.sqrt(1 - uu ** 2)
    d = np.stack([ca * np.sin(aa), ca * np.cos(aa), uu], axis=-1).reshape(-1, 3)
    omega = 2 * np.pi / (n_u * n_az)

    def sky(t):
        s = sun_dirs[t]
        z = float(perez.clamp_zenith(np.arccos(np.clip(s[2], -1, 1))))
        eps = float(perez.clearness(dni[t], dhi[t], z))
        delta = float(perez.brightness(dhi[t], z, doy[t]))
        params = perez.parameters(z, eps, delta)
        # the angle from the sun from its clamped zenith and true azimuth, as the model is defined
        h = np.array([np.sin(z) * s[0] / max(np.hypot(s[0], s[1]), 1e-12),
                      np.sin(z) * s[1] / max(np.hypot(s[0], s[1]), 1e-12), np.cos(z)])
        gamma = np.arccos(np.clip(d @ h, -1, 1))
        lum = perez.relative_luminance(np.arccos(d[:, 2]), gamma, params)
        return lum / (np.sum(lum * d[:, 2]) * omega)  # per unit E_dh

    return d, omega, sky


def main():
    import pandas as pd
    import pvlib

    from radiometer.measure.analyses import annual
    from radiometer.radiometry.skies import perez, sky_patches
    from radiometer.radiometry.sun import epw

    spec = importlib.util.spec_from_file_location("annual_room", ROOT / "tests" / "bpy" / "annual_room.py")
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    env = radiance_env()
    patches = sky_patches.reinhart_patches(1)
    P = patches.count
    coeff = {k: plane_coefficients(patches, n) for k, n in PLANES.items()}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="radiometer-skycheck-") as folder:
        epw_path = room.write_epw(pathlib.Path(folder) / "year.epw")
        weather = epw.read_epw(epw_path)
        wea = pathlib.Path(folder) / "y.wea"
        subprocess.run(["epw2wea", str(epw_path), str(wea)], env=env, check=True, capture_output=True)
        g = {"vis_all": 179.0 * gendaymtx(wea, [], P, env), "vis_sun": 179.0 * gendaymtx(wea, ["-d"], P, env),
             "rad_all": gendaymtx(wea, ["-O1"], P, env), "rad_sun": gendaymtx(wea, ["-O1", "-d"], P, env)}
        g_suns = gendaymtx_suns(wea, env, weather)
    T = weather.count
    # ---- 1. Radiometer: photometric (its own efficacy) and radiometric (lux := W/m^2 passed through)
    sm = annual.sky_matrix(weather, patches, ground_reflectance=RHO_G)
    r = {"vis_all": sm.sky, "vis_sun": sm.sun_patches}
    times = weather.midpoint_datetimes(2026)
    doy = np.array([tt.timetuple().tm_yday for tt in times])
    dni = np.clip(np.nan_to_num(weather.direct_normal_w_m2), 0, None)
    dhi = np.clip(np.nan_to_num(weather.diffuse_horizontal_w_m2), 0, None)
    dew = weather.dew_point_c

    def vectors(sun_dirs, dew_c, radiometric):
        all_, sun = np.zeros((T, P)), np.zeros((T, P))
        for t in range(T):
            kw = dict(direct_normal_lux=dni[t], diffuse_horizontal_lux=dhi[t]) if radiometric else {}
            all_[t], _ = perez.sky_vector(patches, sun_dirs[t], dni[t], dhi[t], doy[t], dew_c[t], RHO_G, **kw)
            sun[t], _ = perez.sky_vector(patches, sun_dirs[t], dni[t], dhi[t], doy[t], dew_c[t], 0.0,
                                         include_sky=False, **kw)
        return all_, sun

    r["rad_all"], r["rad_sun"] = vectors(sm.sun_direction, dew, True)
    # diagnostics: Radiometer's sky_vector with gendaymtx's sun, and with its 11 deg C dew point
    gsun = np.where(np.linalg.norm(g_suns, axis=1)[:, None] > 0, g_suns, sm.sun_direction)
    diag = {}
    diag["radiometer_gendaymtx_sun_rad"] = vectors(gsun, dew, True)
    diag["radiometer_gendaymtx_sun_vis"] = vectors(gsun, dew, False)
    diag["radiometer_dew11_vis"] = vectors(sm.sun_direction, np.full(T, 11.0), False)
    diag["radiometer_gendaymtx_sun_dew11_vis"] = vectors(gsun, np.full(T, 11.0), False)

    # ---- 3. references: pvlib SPA sun, pvlib Perez 1990 transposition, continuous Perez 1993 integral
    idx = pd.DatetimeIndex([pd.Timestamp(tt).tz_convert("UTC") for tt in times])
    sp = pvlib.solarposition.get_solarposition(idx, weather.latitude_deg, weather.longitude_deg,
                                               altitude=weather.elevation_m, method="nrel_numpy")
    zen = np.radians(sp["apparent_zenith"].to_numpy())
    azi = np.radians(sp["azimuth"].to_numpy())
    s_ref = np.stack([np.sin(zen) * np.sin(azi), np.sin(zen) * np.cos(azi), np.cos(zen)], axis=-1)
    # the sun counts as the two matrices count it: centre above -0.27 deg and irradiance given
    up = (s_ref[:, 2] > -np.sin(np.radians(0.2665))) & (dni + dhi > 1e-4)
    ghi = dhi + dni * np.maximum(s_ref[:, 2], 0)
    dni_extra = pvlib.irradiance.get_extra_radiation(idx).to_numpy()
    airmass = pvlib.atmosphere.get_relative_airmass(np.degrees(zen), model="kastenyoung1989")
    z_cl = perez.clamp_zenith(zen)
    eps = perez.clearness(dni, dhi, z_cl)
    delta = perez.brightness(dhi, z_cl, doy)
    k_dif, k_dir = perez.efficacy(eps, delta, z_cl, dew)
    k_dif, k_dir = np.where(up, k_dif, 0), np.where(up, k_dir, 0)
    cells, omega, sky_fn = perez_continuous(s_ref, dni, dhi, doy)
    ref = {}
    day = np.flatnonzero(up)
    cont = {k: np.zeros(T) for k in PLANES}
    cos_cells = np.stack([np.maximum(cells @ np.asarray(n), 0) for n in PLANES.values()], axis=1) * omega
    for t in day:
        if dhi[t] <= 0:
            continue
        e = (sky_fn(t) * dhi[t]) @ cos_cells  # W/sr/m^2 (radiometric Perez sky) -> W/m^2 per plane
        for j, k in enumerate(PLANES):
            cont[k][t] = e[j]
    for k, n in PLANES.items():
        n = np.asarray(n, float)
        tilt = np.degrees(np.arccos(n[2]))
        surf_az = np.degrees(np.arctan2(n[0], n[1])) % 360
        cos_aoi = np.where(up, np.maximum(s_ref @ n, 0), 0)
        pv = pvlib.irradiance.get_total_irradiance(tilt, surf_az, np.degrees(zen), np.degrees(azi), dni, ghi, dhi,
                                                   dni_extra=dni_extra, airmass=airmass, albedo=RHO_G, model="perez")
        pv_sky = np.where(up, np.nan_to_num(pv["poa_sky_diffuse"]), 0)
        ground_rad = np.where(up, RHO_G * ghi * (1 - n[2]) / 2, 0)
        sun_rad = dni * cos_aoi
        ref[k] = {"sun_rad": sun_rad, "sky_rad_pvlib1990": pv_sky, "sky_rad_perez1993": cont[k],
                  "ground_rad": ground_rad, "sun_vis": sun_rad * k_dir, "sky_vis_perez1993": cont[k] * k_dif,
                  "sky_vis_pvlib1990": pv_sky * k_dif,
                  "ground_vis": np.where(up, RHO_G * (dhi * k_dif + dni * k_dir * np.maximum(s_ref[:, 2], 0))
                                         * (1 - n[2]) / 2, 0)}

    def split(all_, sun, c):
        """(sun, sky, ground) hourly plane values from a (T, P) matrix and coefficients."""
        sky = all_ - sun
        return sun @ c, sky[:, 1:] @ c[1:], sky[:, 0] * c[0]

    results, hourly = {}, {}
    for k in PLANES:
        c = coeff[k]
        row = {"coefficients_sum_sr": float(c.sum()), "ground_coefficient_sr": float(c[0])}
        for unit, scale in (("rad", 1e-3), ("vis", 1e-6)):  # kWh/m^2, Mlx h
            rs, rk, rg = split(r[f"{unit}_all"], r[f"{unit}_sun"], c)
            gs, gk, gg = split(g[f"{unit}_all"], g[f"{unit}_sun"], c)
            e = ref[k]
            sky_ref = e[f"sky_{unit}_perez1993"]
            row[unit] = {
                "radiometer": {"sun": rs.sum() * scale, "sky": rk.sum() * scale, "ground": rg.sum() * scale},
                "gendaymtx": {"sun": gs.sum() * scale, "sky": gk.sum() * scale, "ground": gg.sum() * scale},
                "reference": {"sun": e[f"sun_{unit}"].sum() * scale, "sky": sky_ref.sum() * scale,
                              "sky_pvlib_perez1990": e[f"sky_{unit}_pvlib1990"].sum() * scale,
                              "ground": e[f"ground_{unit}"].sum() * scale}}
            for name, (a_all, a_sun) in diag.items():
                if name.endswith(unit):
                    ds, dk, dg = split(a_all, a_sun, c)
                    row[unit][name] = {"sun": ds.sum() * scale, "sky": dk.sum() * scale, "ground": dg.sum() * scale}
            if unit == "vis":
                hourly[k] = {"radiometer_sun": rs, "gendaymtx_sun": gs, "reference_sun": e["sun_vis"],
                             "radiometer_sky": rk, "gendaymtx_sky": gk, "reference_sky": sky_ref}
        results[k] = row
    # per-hour spread of the sun and sky ratios (hours where the reference is >= 1 klx on the plane)
    per_hour = {}
    for k, h in hourly.items():
        row = {}
        for part in ("sun", "sky"):
            m = h[f"reference_{part}"] > 1000.0
            for src in ("radiometer", "gendaymtx"):
                q = h[f"{src}_{part}"][m] / h[f"reference_{part}"][m]
                row[f"{src}_{part}_over_reference"] = {"hours": int(m.sum()), "median": float(np.median(q)),
                                                       "p05": float(np.percentile(q, 5)),
                                                       "p95": float(np.percentile(q, 95))}
        per_hour[k] = row
    # sun position: angle between the three suns at hours with the sun up
    ang = lambda a, b: np.degrees(np.arccos(np.clip(np.sum(a * b, axis=1), -1, 1)))
    both = up & (np.linalg.norm(g_suns, axis=1) > 0)
    sun_pos = {"hours": int(both.sum()),
               "radiometer_vs_pvlib_deg_max": float(ang(sm.sun_direction[both], s_ref[both]).max()),
               "gendaymtx_vs_pvlib_deg_median": float(np.median(ang(g_suns[both], s_ref[both]))),
               "gendaymtx_vs_pvlib_deg_max": float(ang(g_suns[both], s_ref[both]).max()),
               "gendaymtx_minus_pvlib_altitude_deg_mean": float(np.degrees(
                   np.mean(np.arcsin(g_suns[both, 2]) - np.arcsin(s_ref[both, 2]))))}
    # the eyes of tests/bpy/annual_dgp_reference.json: Radiance's rendered coefficients (mean of its 2 runs)
    from radiometer.radiometry.metrics import daylight_metrics

    dgp_ref = json.loads((ROOT / "tests" / "bpy" / "annual_dgp_reference.json").read_text(encoding="utf-8"))
    occ = daylight_metrics.occupied_hours(weather.midpoint_hours())
    eyes = []
    sources = {"radiometer": (r["vis_all"], r["vis_sun"]), "gendaymtx": (g["vis_all"], g["vis_sun"]),
               **{k[:-4]: v for k, v in diag.items() if k.endswith("_vis")}}
    for k, view in enumerate(dgp_ref["views"]):
        dc = np.mean([np.asarray(run["dc_lux_per_cd_m2"][k]) for run in dgp_ref["runs"]], axis=0)
        row = {"eye": dgp_ref["eyes"][k], "view": view}
        for name, (a_all, a_sun) in sources.items():
            sun_e, rest_e = a_sun[occ] @ dc, (a_all - a_sun)[occ] @ dc
            row[name] = {"sun": float(sun_e.sum() * 1e-6), "sky_and_ground": float(rest_e.sum() * 1e-6)}
        eyes.append(row)
    out = {"weather": "tests/bpy/annual_room.write_epw (synthetic London, 51.5 N 0.12 W, UTC+0, dew point 8 C)",
           "units": {"rad": "kWh/m^2 per year (annual sum of hourly W/m^2)", "vis": "Mlx h per year"},
           "planes": {k: list(v) for k, v in PLANES.items()}, "ground_reflectance": RHO_G,
           "annual": results, "eyes_occupied_mlxh": eyes, "per_hour_ratios_vis": per_hour, "sun_position": sun_pos,
           "seconds": time.perf_counter() - t0}
    (HERE / "sky_matrix_check.json").write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    write_md(out)
    print(json.dumps({k: v["vis"] for k, v in results.items()}, indent=1))
    print(json.dumps(sun_pos, indent=1))


def write_md(out):
    lines = ["# Sky matrix check: Radiometer vs gendaymtx vs independent references", "",
             f"Weather: {out['weather']}; ground reflectance {out['ground_reflectance']}. Generated by "
             "`bench/sky_matrix_check.py` (no rendering: exact cosine-weighted patch coefficients).", ""]
    for unit, label in (("vis", "illuminance, Mlx h / year"), ("rad", "irradiance, kWh/m^2 / year")):
        lines += [f"## Annual sums, {label}", "",
                  "| plane | part | Radiometer | gendaymtx | reference | Radiometer / ref | gendaymtx / ref | pvlib Perez 1990 |",
                  "|---|---|---|---|---|---|---|---|"]
        for k, row in out["annual"].items():
            v = row[unit]
            for part in ("sun", "sky", "ground"):
                a, b, c = v["radiometer"][part], v["gendaymtx"][part], v["reference"][part]
                pv = f"{v['reference']['sky_pvlib_perez1990']:.4g}" if part == "sky" else ""
                ra = f"{a / c:.4f}" if c > 0 else "-"
                rb = f"{b / c:.4f}" if c > 0 else "-"
                lines.append(f"| {k} | {part} | {a:.4g} | {b:.4g} | {c:.4g} | {ra} | {rb} | {pv} |")
        lines.append("")
    lines += ["## Diagnostics (illuminance, Mlx h / year): Radiometer's sky_vector with gendaymtx's inputs", "",
              "Radiometer's sky vector with gendaymtx's sun directions (`gendaymtx -n -D`) and / or its fixed 11 C "
              "dew point. The sky here has Radiometer's exact cosine-weighted normalisation, 0.55 % above gendaymtx's "
              "(docs/daylight-sky.md), so '+ both' equals gendaymtx on the sun and the ground and is 0.55 % above it on "
              "the sky; with gendaymtx's normalisation '+ both' reproduced gendaymtx to 0.02 % in every cell.", "",
              "| plane | part | Radiometer | + gendaymtx sun | + dew 11 C | + both | gendaymtx |", "|---|---|---|---|---|---|---|"]
    for k, row in out["annual"].items():
        v = row["vis"]
        for part in ("sun", "sky", "ground"):
            lines.append(f"| {k} | {part} | {v['radiometer'][part]:.4g} | {v['radiometer_gendaymtx_sun_vis'][part]:.4g} "
                         f"| {v['radiometer_dew11_vis'][part]:.4g} | {v['radiometer_gendaymtx_sun_dew11_vis'][part]:.4g} "
                         f"| {v['gendaymtx'][part]:.4g} |")
    lines += ["", "## Per hour (illuminance; hours with the reference part >= 1 klx on the plane): ratio to the reference", "",
              "| plane | source / part | hours | median | 5 % | 95 % |", "|---|---|---|---|---|---|"]
    for k, row in out["per_hour_ratios_vis"].items():
        for name, q in row.items():
            lines.append(f"| {k} | {name} | {q['hours']} | {q['median']:.4f} | {q['p05']:.4f} | {q['p95']:.4f} |")
    lines += ["", "## Eyes of tests/bpy/annual_dgp_reference.json (Radiance's rendered coefficients), occupied hours, Mlx h",
              "", "| eye / view | part | Radiometer | + gendaymtx sun | + dew 11 C | + both | gendaymtx | gendaymtx / Radiometer |",
              "|---|---|---|---|---|---|---|---|"]
    for e in out["eyes_occupied_mlxh"]:
        for part in ("sun", "sky_and_ground"):
            v = [e[n][part] for n in ("radiometer", "radiometer_gendaymtx_sun", "radiometer_dew11",
                                     "radiometer_gendaymtx_sun_dew11", "gendaymtx")]
            lines.append(f"| {e['eye']} {e['view']} | {part} | " + " | ".join(f"{x:.4g}" for x in v)
                         + f" | {v[4] / v[0]:.4f} |")
    sp = out["sun_position"]
    lines += ["", f"Sun position over {sp['hours']} hours: Radiometer vs pvlib SPA max {sp['radiometer_vs_pvlib_deg_max']:.4f} deg; "
              f"gendaymtx vs pvlib median {sp['gendaymtx_vs_pvlib_deg_median']:.3f} deg, max {sp['gendaymtx_vs_pvlib_deg_max']:.3f} deg, "
              f"mean altitude difference {sp['gendaymtx_minus_pvlib_altitude_deg_mean']:+.3f} deg.", ""]
    (HERE / "sky_matrix_check.md").write_text("\n".join(lines), encoding="utf-8")


if __name__ == "__main__":
    main()

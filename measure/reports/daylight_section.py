"""The report's daylight section (issue 34): measured when the scene has a sky (a sun or an emitting
world) and the caller asks for it (``report --daylight``; the CLI asks by itself when the scene has one).

Per work plane: the daylight factor grid (CIE overcast sky, the average by BS 8206-2) and its map;
with a weather file (EPW) the annual metrics (sDA300/50%, ASE1000/250h, UDI 100-2000 lx) on the same
points, the weather file's name and period, and the sDA map; the sunlight hours on the reference day
(21 March of the weather file's year, at its site, every ``SUN_STEP_MIN`` minutes) and their map;
daylight glare (DGP) at the scene camera, and with a weather file its annual DGP there (imageless:
``daylight_glare.annual_dgp``); and the EN 17037 table (``radiometry.metrics.en17037``): daylight provision
from the annual hours (else the DF method with the site's E_v,d when given), exposure to sunlight at the
plane's sunniest point (the standard assesses a point on the window: noted), protection from glare from
the camera's annual DGP over the occupied hours (not assessed without a weather file or a camera).

Everything lands in ``report["daylight"]`` (numbers with units in the keys, map file names) and the
maps in the report's folder; a part that fails is one line in ``errors`` and the rest goes on.
"""

import datetime as _dt
import os

import numpy as np

from ...errors import MeasurementCancelled, RadiometerError

#: Minutes between the sun study's times on the reference day.
SUN_STEP_MIN = 30
#: A seated eye over the work plane (m): EN 17037's 1.2 m over the floor less its 0.85 m reference plane;
#: the view out is judged from the plane's points raised by this much along the plane's normal.
EYE_ABOVE_WORK_PLANE_M = 0.35
#: at most this many of the plane's points (evenly spread) are view-out eyes: rays cost triangles x rays
VIEW_OUT_MAX_EYES = 36
#: The DGP fisheye's side in pixels in the report (preview-sized: a picture of the camera's view).
DGP_RESOLUTION = 64


def map_files(plane_stems, annual=False, sun=False):
    """The map file names the section may write for the planes' stems (checked before any work)."""
    names = []
    for stem in plane_stems:
        names.append(f"daylight_factor_{stem}.png")
        names += [f"sda_{stem}.png"] if annual else []
        names += [f"sunlight_hours_{stem}.png"] if sun else []
    return names


def sky_words(scene):
    """What makes ``scene`` daylit: its suns and an emitting world, in words ("" when none)."""
    from ..blender.request import view_layer_of
    from ..meter import point_meter as meter

    model = meter.capture_model(scene, view_layer_of(scene))
    suns = [lt.name for lt in model.lights if lt.spec is not None and not lt.spec.has_position]
    parts = ([f"sun(s) {', '.join(repr(n) for n in suns)}"] if suns else []) + \
        (["an emitting world"] if model.world_emits else [])
    return " and ".join(parts)


def _camera_view(scene):
    cam = scene.camera
    if cam is None:
        return None
    m = cam.matrix_world
    direction = m.to_3x3() @ __import__("mathutils").Vector((0.0, 0.0, -1.0))
    return tuple(m.translation), tuple(direction.normalized())


def measure_daylight(request, planes, out_dir, stems, *, epw_path=None, median_external_illuminance_lux=None,
                     resolution=None, draw=True):
    """Measure the daylight section (module docstring) into a dict; maps written into ``out_dir``. The
    request (``measure.blender.request``) gives the scene, the daylight factor's ``quality`` (None:
    "preview"; the annual, sun, glare and view parts run at preview) and cancel."""
    from ...radiometry.metrics import en17037
    from ..analyses import annual as annual_mod
    from ..analyses import daylight_factor, daylight_glare, sun_study
    from . import daylight_maps

    scene, quality = request.scene, request.quality or "preview"
    # each part at its own quality, seed 0, no budget of the report's (as the section has always measured)
    request = request.but(quality=quality, target_rel_error=None, samples=None, time_budget_s=None,
                          target_abs_error=None, seed=0, progress=None, client=None)
    preview = request.but(quality="preview")

    section = {"sky": sky_words(scene), "quality": quality, "planes": [], "dgp": None, "annual_dgp": None,
               "weather": None, "en17037": [], "images": [], "errors": []}
    weather = None
    if epw_path:
        from ...radiometry.sun import epw

        try:
            weather = epw.read_epw(epw_path)
        except (OSError, ValueError) as exc:
            raise RadiometerError(f"weather file: {exc}") from None
        import re

        section["weather"] = {"file": os.path.basename(epw_path), "site": f"{weather.city}, {weather.country}",
                              "latitude_deg": weather.latitude_deg, "longitude_deg": weather.longitude_deg,
                              "period": re.sub(r" \(line \d+\)", "", weather.period),
                              "whole_year": bool(weather.is_full_year)}

    def failed(what, exc):
        section["errors"].append(f"{what}: {exc}")

    def drawn(result, name, caption, **how):
        """The plan-view map of ``result`` written as ``name`` in the report folder, with its caption."""
        daylight_maps.daylight_map(result, os.path.join(out_dir, name), scene=request, **how)
        section["images"].append((caption, name))

    view = _camera_view(scene)
    glare_row = None
    if weather is not None and view is not None:
        try:
            a = daylight_glare.annual_dgp(view[0], view[1], epw_path, request=preview,
                                          partial_period=not weather.is_full_year)
            glare_row = en17037.glare_protection(a.occupied_dgp())
            glare_row.note = "annual DGP at the camera"
            section["annual_dgp"] = {
                "camera": scene.camera.name, "observer": list(a.observer), "direction": list(a.view_direction),
                "occupied_hours": int(a.occupied.sum()), "sun_in_view_hours": int((a.sun_seen & a.occupied).sum()),
                "hours_at_or_above": {f"{k:.2f}": v for k, v in a.hours_above.items()},
                "hours_at_or_above_within_2se": {f"{k:.2f}": list(v) for k, v in a.hours_above_range.items()},
                "en17037_level": glare_row.level, "summary": a.summary(), "notes": list(a.notes)}
        except MeasurementCancelled:
            raise
        except (RadiometerError, ValueError) as exc:
            failed("annual daylight glare at the camera", exc)
    for plane in planes:
        stem = stems(plane.name)
        entry = {"plane": plane.name}
        section["planes"].append(entry)
        try:
            g = daylight_factor.daylight_factor_grid(plane, resolution=resolution, request=request,
                                                     median_external_illuminance_lux=median_external_illuminance_lux)
        except MeasurementCancelled:
            raise
        except (RadiometerError, ValueError) as exc:
            failed(f"daylight factor on {plane.name}", exc)
            continue
        s = g.stats
        entry["daylight_factor"] = {
            "points": int(g.nx * g.ny), "grid": [int(g.nx), int(g.ny)], "average_percent": s["average"],
            "minimum_percent": s["minimum"], "maximum_percent": s["maximum"], "median_percent": s["median"],
            "uniformity": s["uniformity"], "worst_rel_std_error": float(np.max(g.rel_std_error)),
            "method": (f"CIE standard overcast sky, ground reflectance 0.2, electric lights off; {g.method}; "
                       "average by BS 8206-2 (mean of the grid)")}
        df_values = np.asarray(g.daylight_factor, float).ravel()
        if draw:
            try:
                drawn(g, f"daylight_factor_{stem}.png", f"Daylight factor on {plane.name} (%, CIE overcast sky): "
                      f"average {s['average']:.2g} %, minimum {s['minimum']:.2g} %")
            except (RadiometerError, OSError) as exc:
                failed(f"daylight factor map of {plane.name}", exc)
        locations = np.asarray(g.points, float).reshape(-1, 3)
        normals = np.broadcast_to(np.asarray(g.normal, float), locations.shape)
        provision = None
        if weather is not None:
            try:
                r = annual_mod.annual_daylight(locations, normals, epw_path, request=preview,
                                               partial_period=not weather.is_full_year)
                entry["annual"] = {"sDA_300_50_percent": 100 * r.sda,
                                   "sDA_range_2se_percent": [100 * v for v in r.sda_range],
                                   "ASE_1000_250h_percent": 100 * r.ase,
                                   "UDI_100_2000_mean_percent": 100 * float(np.mean(r.udi[1])),
                                   "occupied_hours": int(np.sum(r.occupied)),
                                   "worst_hourly_rel_std_error": r.max_rel_std_error,
                                   "period": r.weather_period or section["weather"]["period"], "notes": list(r.notes)}
                daylight_hours = np.asarray(weather.global_horizontal_w_m2, float) > 0
                if np.asarray(r.illuminance).shape[0] == daylight_hours.shape[0]:
                    provision = en17037.daylight_provision_illuminance(r.illuminance, daylight_hours)
                if draw:
                    drawn(r, f"sda_{stem}.png", f"Spatial daylight autonomy on {plane.name}: share of occupied "
                          f"hours at 300 lx or more (%); sDA300/50% {100 * r.sda:.0f} %", metric="sda")
            except MeasurementCancelled:
                raise
            except (RadiometerError, ValueError, OSError) as exc:
                failed(f"annual daylight on {plane.name}", exc)
        if provision is None and median_external_illuminance_lux:
            provision = en17037.daylight_provision_daylight_factor(df_values, median_external_illuminance_lux)
        sunlight = None
        if weather is not None:
            try:
                tz = _dt.timezone(_dt.timedelta(hours=float(weather.time_zone_h)))
                year = int(weather.data["year"][0]) if "year" in weather.data else 2026
                start = _dt.datetime(year, 3, 21, 0, 0, tzinfo=tz)
                times = [start + _dt.timedelta(minutes=SUN_STEP_MIN * k) for k in range(24 * 60 // SUN_STEP_MIN)]
                st = sun_study.sun_study(locations, normals, times, latitude_deg=weather.latitude_deg,
                                         longitude_deg=weather.longitude_deg, elevation_m=weather.elevation_m,
                                         request=preview)
                h = np.asarray(st.sunlight_hours, float)
                entry["sunlight_hours"] = {"day": start.date().isoformat(), "step_min": SUN_STEP_MIN,
                                           "minimum_h": float(h.min()), "mean_h": float(h.mean()),
                                           "maximum_h": float(h.max())}
                sunlight = en17037.sunlight_exposure(float(h.max()))
                sunlight.note = "at the plane's sunniest point, not on the window"
                if draw:
                    drawn(st, f"sunlight_hours_{stem}.png", f"Sunlight hours on {plane.name} on "
                          f"{start.date().isoformat()} (h; every {SUN_STEP_MIN} min): maximum {h.max():.1f} h")
            except MeasurementCancelled:
                raise
            except (RadiometerError, ValueError, OSError) as exc:
                failed(f"sunlight hours on {plane.name}", exc)
        import dataclasses

        view_row = None
        try:
            eyes = locations + np.asarray(g.normal, float) * (EYE_ABOVE_WORK_PLANE_M / request.scale_length)
            eyes = eyes[np.unique(np.linspace(0, len(eyes) - 1, min(len(eyes), VIEW_OUT_MAX_EYES)).round().astype(int))]
            vo = daylight_glare.view_out(eyes, request=request)
            entry["view_out"] = {"eyes": int(len(eyes)), "eye_above_plane_m": EYE_ABOVE_WORK_PLANE_M,
                                 "level": vo.en17037["level"], "values": vo.en17037["values"],
                                 "note": vo.en17037.get("note", ""), "openings": vo.openings, "notes": vo.notes}
            view_row = en17037.Criterion(**vo.en17037)   # assessed or not, the row with its note
        except MeasurementCancelled:
            raise
        except (RadiometerError, ValueError) as exc:
            failed(f"view out on {plane.name}", exc)
        rows = en17037.table(provision=provision, sunlight=sunlight, glare=glare_row, view=view_row)
        entry["en17037"] = [dataclasses.asdict(row) for row in rows]
    if view is not None:
        try:
            d = daylight_glare.glare_dgp(view[0], view[1], request=preview, resolution=DGP_RESOLUTION)
            section["dgp"] = {"camera": scene.camera.name, "observer": [float(v) for v in view[0]],
                              "direction": [float(v) for v in view[1]], "dgp": float(d.dgp),
                              "dgp_std_error": float(d.dgp_std_error), "class": d.dgp_class,
                              "vertical_illuminance_lx": float(d.vertical_illuminance), "sources": len(d.sources),
                              "summary": d.summary()}
        except MeasurementCancelled:
            raise
        except (RadiometerError, ValueError) as exc:
            failed("daylight glare at the camera", exc)
    return section


def _g(value, digits=2):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return "n/a"
    return "n/a" if not np.isfinite(v) else f"{v:.{digits}g}"


def _plain(value, digits=3):
    """``value`` to ``digits`` significant digits without an exponent: 1909.7 -> '1910'."""
    return f"{float(f'{float(value):.{digits}g}'):g}" if abs(float(value)) < 10 ** digits else \
        f"{float(f'{float(value):.{digits}g}'):.0f}"


def daylight_tables(section):
    """(title, header, rows) of the daylight section, shared by the markdown, HTML and PDF reports; []
    without a section. Titles short (they are one line on an A4 page), the how in the first table."""
    if not section:
        return []
    tables = []
    weather = section.get("weather")
    how = [["daylit by", section.get("sky") or "no sun or emitting world in the scene (asked for)"],
           ["quality", str(section.get("quality"))],
           ["daylight factor", "CIE standard overcast sky, ground reflectance 0.2, lights off"],
           ["its average", "BS 8206-2: the mean of the grid"]]
    if weather:
        how += [["weather file", f"{weather['file']}: {weather['site']}"], ["period", weather["period"]],
                ["sunlight hours", f"21 March at the weather file's site, the sun every {SUN_STEP_MIN} min"]]
    else:
        how += [["weather file", "none given: no annual metrics, no sunlight hours"]]
    tables.append(("Daylight: how it was measured", ["item", "value"], how))
    for entry in section.get("planes", []):
        name = entry["plane"]
        df = entry.get("daylight_factor")
        if df:
            tables.append((f"Daylight factor on {name}", ["average", "minimum", "median", "maximum", "U0 min/avg",
                                                          "points", "worst 1 s.e."],
                           [[f"{_g(df['average_percent'])} %", f"{_g(df['minimum_percent'])} %",
                             f"{_g(df['median_percent'])} %", f"{_g(df['maximum_percent'])} %", _g(df["uniformity"]),
                             f"{df['grid'][0]} x {df['grid'][1]}", f"{100 * df['worst_rel_std_error']:.2g} % rel."]]))
        a = entry.get("annual")
        if a:
            tables.append((f"Annual daylight on {name}", ["sDA300/50%", "sDA within 2 s.e.", "ASE1000/250h",
                                                          "mean UDI 100-2000 lx", "occupied hours",
                                                          "worst hourly 1 s.e."],
                           [[f"{a['sDA_300_50_percent']:.0f} %",
                             f"{a['sDA_range_2se_percent'][0]:.0f}-{a['sDA_range_2se_percent'][1]:.0f} %",
                             f"{a['ASE_1000_250h_percent']:.0f} %", f"{a['UDI_100_2000_mean_percent']:.0f} %",
                             f"{a['occupied_hours']} h", f"{100 * a['worst_hourly_rel_std_error']:.2g} % rel."]]))
        h = entry.get("sunlight_hours")
        if h:
            tables.append((f"Sunlight hours on {name}, {h['day']}", ["minimum", "mean", "maximum"],
                           [[f"{h['minimum_h']:.1f} h", f"{h['mean_h']:.1f} h", f"{h['maximum_h']:.1f} h"]]))
        rows = []
        for row in entry.get("en17037", []):
            assessed = row["level"] != "not assessed"
            method, note = row.get("method") or "", row.get("note") or ""
            basis = f"{method}; {note}" if method and note and len(method) + len(note) < 62 else note or method
            rows.append([row["criterion"], row["level"] + (" (indicative)" if row.get("indicative") and assessed
                                                           else ""), basis or "-"])
        if rows:
            tables.append((f"EN 17037 on {name} (2018+A1:2021)", ["criterion", "level", "how"], rows))
    d = section.get("dgp")
    if d:
        tables.append((f"Daylight glare (DGP) at the camera {d['camera']}",
                       ["eye (m)", "view", "DGP", "class", "E_v at the eye", "sources"],
                       [[", ".join(f"{v:.2f}" for v in d["observer"]), ", ".join(f"{v:.2f}" for v in d["direction"]),
                         f"{d['dgp']:.2f} ± {d['dgp_std_error']:.1g}", d["class"],
                         f"{_plain(d['vertical_illuminance_lx'])} lx", str(d["sources"])]]))
        how += [["daylight glare", "DGP (Wienold & Christoffersen 2006), 180 deg fisheye at the camera"],
                ["DGP classes", "imperceptible < 0.35 <= perceptible < 0.40 <= disturbing < 0.45"]]
    a = section.get("annual_dgp")
    if a:
        def hours(k):
            lo, hi = a["hours_at_or_above_within_2se"][k]
            return f"{a['hours_at_or_above'][k]} h" + (f" ({lo}-{hi})" if lo != hi else "")

        tables.append((f"Annual daylight glare at the camera {a['camera']}",
                       ["occupied hours", "sun in view", "DGP >= 0.35", "DGP >= 0.40", "DGP >= 0.45", "EN 17037"],
                       [[f"{a['occupied_hours']} h", f"{a['sun_in_view_hours']} h", hours("0.35"), hours("0.40"),
                         hours("0.45"), a["en17037_level"]]]))
        how += [["annual glare", "the sun's disc as source where seen, else DGPs (a lower envelope); Wienold 2009"]]
    return tables


def markdown_lines(section):
    """The daylight section of report.md: its tables and maps (relative links)."""
    if not section:
        return []
    md = ["## Daylight\n"]
    for title, header, rows in daylight_tables(section):
        md.append(f"**{title}**\n")
        md.append("| " + " | ".join(header) + " |\n|" + "---|" * len(header))
        for row in rows:
            md.append("| " + " | ".join(str(c).replace("|", "/") for c in row) + " |")
        md.append("")
    for caption, name in section.get("images", []):
        md.append(f"![{caption}]({name})\n\n*{caption}*\n")
    for error in section.get("errors", []):
        md.append(f"- not measured: {error}")
    return md

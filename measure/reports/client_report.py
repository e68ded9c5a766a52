"""The client's report (issue 23): HTML and PDF with the project and room data, the luminaire schedule,
the EN 12464-1 compliance table, false-colour and isolux pictures, the meter readings with their
uncertainty, and the law checks in an engineering appendix.

Built on the analysis report's results (``measure.reports.report``): this module adds the schedule, the
compliance checks (UGR at the given observers), a false-colour luminance image of the scene camera,
and writes ``report.html`` (pictures linked by relative file names) and ``report.pdf`` (matplotlib's
PDF backend, pictures embedded). Paths shown are file names only (no absolute paths). Numbers carry
the digits their standard error supports and their units.

How to add a section (``REPORT_SECTIONS``: one function plus one mapping entry, as colour-science adds a
method):

1. measure what it needs in ``report._report_parts`` as one part (a ``yield step(label)``, its weight in
   ``parts``, any files it writes in the planned set before the first measurement), into
   ``report[name]`` as plain numbers with their units in the keys (it is written to report.json);
2. write ``_name_section(report, client)`` returning its tables as (title, header, rows), every number
   with its unit and the digits its error supports, and add it to ``REPORT_SECTIONS`` where it belongs
   in the page order;
3. pictures: (caption, file name) in ``client["section_images"][name]``, laid out two to a page under
   the section's heading (``write_pdf``), inline in the HTML;
4. a markdown form for report.md (as ``daylight_section.markdown_lines``) and a test that reads the
   section's numbers back from report.json and its heading from the HTML.
"""

import datetime
import html
import math
import os

import bpy
import numpy as np

from ... import outputs
from ...errors import MeasurementCancelled, RadiometerError
from ...readings import format_error, format_melanopic, format_quantity, format_value, photographic_text


#: Samples per pixel per render (cap) of the report's false-colour picture, by the report's quality.
PICTURE_SPP = {"preview": 16, "standard": 64, "reference": 256}
#: Pixels on the longer side of the report's false-colour picture (the camera's aspect kept).
PICTURE_LONGEST_PX = 240


def _num(value, rel_se=0.0, exact=False):
    try:
        return format_value(float(value), rel_se or 0.0, exact)
    except (TypeError, ValueError):
        return "n/a"


# --- the luminaire schedule ----------------------------------------------------------------------

def daylight_words(scene):
    """A warning for the compliance notes when the report's grids were measured with daylight on (a sun or
    an emitting world): EN 12464-1 rates the electric lighting (``api.en12464_compliance`` switches
    daylight off; the report's grids are measured with the scene as it is)."""
    from ..meter import point_meter as meter
    from ..analyses.analysis_common import view_layer_of

    model = meter.capture_model(scene, view_layer_of(scene))
    suns = [lt.name for lt in model.lights if lt.spec is not None and not lt.spec.has_position]
    parts = ([f"sun(s) {', '.join(repr(n) for n in suns)}"] if suns else []) + \
        (["an emitting world"] if model.world_emits else [])
    if not parts:
        return ""
    return (f"DAYLIGHT INCLUDED ({' and '.join(parts)} on while the grid was measured): not the electric "
            "lighting alone; use api.en12464_compliance, which switches daylight off")


def luminaire_schedule(scene):
    """Rows per luminaire type: type, file (name only), count, flux per luminaire (lm), power (W),
    efficacy (lm/W). IES/EULUMDAT lights: the file's flux and input watts; Blender lights: the emitted
    flux K x Y x P (the light's power is radiant, so no electrical power and no efficacy). ``scene``: a
    request (``measure.blender.request``: its efficacy), a scene or None."""
    from ..authoring import light_power
    from ..blender import request as request_of
    from ..capture import luminaires

    request = request_of.of(scene)
    scene = request.scene
    groups = {}
    for obj in scene.objects:
        if obj.type != "LIGHT" or obj.hide_render:
            continue
        data = obj.data
        source = data.get(luminaires.PROP_SOURCE) if hasattr(data, "get") else None
        if source:
            key = ("file", os.path.basename(source))
            if key not in groups:
                flux = data.get(luminaires.PROP_LUMENS)
                watts = None
                try:
                    watts = luminaires.photometry_of_light(obj).input_watts
                except RadiometerError:
                    pass
                groups[key] = {"type": data.name.split(".")[0], "file": os.path.basename(source), "count": 0,
                               "flux_lm": float(flux) if flux else math.nan,
                               "power_w": float(watts) if watts else math.nan}
        else:
            shape = ""
            if data.type == "AREA":
                two = data.shape in ("RECTANGLE", "ELLIPSE")
                shape = f" {data.shape.lower()} {data.size:.3g}" + (f" x {data.size_y:.3g}" if two else "") + " m"
            power = float(data.energy) * 2.0 ** float(getattr(data, "exposure", 0.0))
            # The light's one home for flux (its emitter: colour x temperature colour, exposure, normalize),
            # as the photometric-power dialog reads it; a sun has an illuminance, not a flux.
            flux = math.nan if data.type == "SUN" else light_power.photometric_power(obj, "LUMEN", request)
            key = ("blender", data.type, shape, round(power, 6), round(flux, 3) if math.isfinite(flux) else None)
            if key not in groups:
                groups[key] = {"type": f"Blender {data.type.lower()} light{shape}, {power:.4g} W radiant",
                               "file": "", "count": 0, "flux_lm": flux, "power_w": math.nan}
        groups[key]["count"] += 1
    rows = list(groups.values())
    for r in rows:
        r["efficacy_lm_w"] = r["flux_lm"] / r["power_w"] if r["power_w"] and r["power_w"] > 0 else math.nan
    return rows


# --- writing ---------------------------------------------------------------------------------------

def _law_sentence(r, kind):
    """An engineer's sentence for a law check (no FLAGGED: the near field is physics, not a failure)."""
    if "error" in r:
        return f"not checked: {r['error']}"
    if kind == "inverse_square":
        limit = r.get("near_field_limit")
        se = r["exponent_se"] if r["exponent_se"] >= 5e-7 else 0.0  # an exact fit's error is rounding noise
        fit = f"exponent {r['exponent']:.3f} ± {se:.1g} (ideal -2)"
        if r.get("departure"):
            what = f"{r['departure']}: physics, not a fault"
        elif limit is None or not math.isfinite(limit):
            what = ("its far field lies beyond the free space checked, so at every distance the light is an extended "
                    "source (near field) and departs from I/d² as expected; this is physics, not a fault")
        elif limit > 0:
            what = (f"within {limit:.2g} m the light is an extended source (near field) and departs from I/d² as "
                    f"expected; beyond it, it {'follows' if r.get('passed') else 'does not follow'} the law")
        else:
            what = f"it {'follows' if r.get('passed') else 'does not follow'} the law at every distance checked"
        return (f"{what}; {fit}; the room's interreflections add up to "
                f"{100 * r.get('max_scene_share', 0.0):.2g} % of a reading")
    dev = 100 * r["max_rel_deviation"]
    where = f"cosine law at {tuple(round(v, 2) for v in r['location'])} m"
    if r.get("departure"):
        what = f"{r['departure']}: physics, not a fault"
    else:
        dev_text = "0 %" if abs(dev) < 5e-5 else f"{dev:.2g} %"  # rounding noise of a closed form: 0
        what = (f"largest deviation {dev_text} at {r['max_at_deg']:g}° ({'within' if r.get('passed') else 'outside'} "
                "the tolerance)")
    return f"{where}: {what}; the room adds up to {100 * r.get('max_scene_share', 0.0):.2g} %"


def _meter_rows(report):
    rows = []
    for r in report.get("meters", []):
        lum = r.get("quantity") == "luminance"
        value = r["luminance"] if lum else r["illuminance"]
        rows.append({"name": r["name"], "reading": format_quantity(value, "cd/m²" if lum else "lx",
                                                                   r.get("rel_std_error") or 0.0, r.get("exact")),
                     "photo": photographic_text("luminance" if lum else "illuminance", value,
                                                r.get("radiance_rgb") if lum else r.get("irradiance_rgb"),
                                                r.get("colour_space", "")),
                     "method": r.get("method", ""), "melanopic": format_melanopic(r.get("melanopic"))})
    return rows


def _html_table(header, rows):
    out = ["<table><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>"]
    for row in rows:
        out.append("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>")
    return "\n".join(out) + "</table>"


def _project_section(report, client):
    return [("Project", ["item", "value"], [[k, v] for k, v in client["project"].items()])]


def _work_planes_section(report, client):
    rooms = [[g["target"], f"{g['size'][0]:.3g} m x {g['size'][1]:.3g} m", f"{g['nx']} x {g['ny']}",
              f"{g['spacing'][0]:.2g} m"] for g in report.get("grids", []) if "error" not in g]
    return [("Work planes", ["work plane", "size", "grid points", "cell"], rooms)] if rooms else []


def _luminaires_section(report, client):
    return [("Luminaire schedule", ["type", "file", "count", "flux per luminaire", "power", "efficacy"],
             [[s["type"], s["file"] or "-", s["count"],
               "n/a" if not math.isfinite(s["flux_lm"]) else f"{_plain(s['flux_lm'])} lm",
               "n/a" if not math.isfinite(s["power_w"]) else f"{_plain(s['power_w'])} W",
               "n/a" if not math.isfinite(s["efficacy_lm_w"]) else f"{s['efficacy_lm_w']:.3g} lm/W"]
              for s in client["schedule"]])]


def _compliance_section(report, client):
    tables = []
    for comp in client["compliance"]:
        req = comp["requirement"]
        rows = []
        for c in comp["checks"]:
            achieved = c["achieved"]
            known = c.get("std_error") is None or math.isfinite(c["std_error"])
            if c["unit"] == "lx":
                shown = (f"{_num(achieved, c['std_error'] / achieved if achieved else 0)} lx" if known
                         else f"{_num(achieved, 0.01)} lx (error unknown)")
            elif isinstance(achieved, float) and not math.isfinite(achieved):
                shown = "n/a" if math.isnan(achieved) else "no glare source"
            elif c["quantity"] == "U0":
                shown = f"{achieved:.2f}"
            elif c["quantity"] == "Ra":
                shown = f"{achieved:g}"
            else:  # UGR: one decimal, with its standard error
                shown = f"{achieved:.1f}" + ((f" ± {c['std_error']:.2g}" if c.get("std_error") else "") if known
                                             else " (error unknown)")
            margin = c["margin"]
            if not math.isfinite(margin):
                mtext = "n/a"
            elif c["unit"] == "lx":
                mtext = f"{'+' if margin >= 0 else '−'}{_plain(abs(margin), 3)} lx"
            else:
                mtext = f"{margin:+.2f}" if c["quantity"] == "U0" else f"{margin:+.1f}"
            rows.append([c["quantity"], c["required"], shown, c["status"], mtext, c["note"]])
        source = req["source"] + (", indicative values: check them against the standard or give your own"
                                  if req.get("indicative") else "")
        tables.append((f"EN 12464-1 compliance: {comp['plane']} ({req['task']}; {source}; maintenance "
                       f"factor {comp['maintenance_factor']:g}) - overall: {comp['overall']}",
                       ["quantity", "required", "achieved", "result", "margin", "how"], rows))
    return tables


def _meters_section(report, client):
    meters = _meter_rows(report)
    return [("Meter readings (± 1 standard error)", ["meter", "reading", "photographic", "method",
                                                     "mel-EDI, direct light"],
             [[m["name"], m["reading"], m["photo"] or "-", m["method"], m["melanopic"]] for m in meters])] if meters else []


def _glare_section(report, client):
    tables = []
    for g in client["glare"]:
        tables.append((f"Glare at {g['label']} (CIE 117 UGR {g['ugr_text']}, background {g['lb_text']})",
                       ["source", "luminance", "solid angle", "position index"],
                       [[s["name"], f"{_plain(s['luminance'], 4)} cd/m²", f"{s['solid_angle']:.3g} sr",
                         f"{s['position_index']:.3g}"] for s in g["sources"]]))
        if g["left_out"]:
            tables.append((f"Lights not rated at {g['label']} (CIE 117 counts only sources in its field)",
                           ["light", "why"], [[d["name"], d["reason"]] for d in g["left_out"]]))
    return tables


def _daylight_section(report, client):
    from .daylight_section import daylight_tables

    return daylight_tables(report.get("daylight"))


#: The client report's sections in page order: name -> ``f(report, client)`` returning its tables, each
#: (title, header, rows), shared by the HTML and the PDF (pictures are ``client["images"]``, a section's
#: own under ``client["section_images"][name]``). How to add a section (module docstring):
#: one function here and one entry below.
REPORT_SECTIONS = {
    "project": _project_section,
    "work planes": _work_planes_section,
    "luminaire schedule": _luminaires_section,
    "compliance": _compliance_section,
    "meter readings": _meters_section,
    "glare": _glare_section,
    "daylight": _daylight_section,
}


def _tables(report, client):
    """(title, header, rows) of every table, shared by HTML and PDF: the sections of ``REPORT_SECTIONS``."""
    return [table for section in REPORT_SECTIONS.values() for table in section(report, client)]


def _appendix(report):
    lines = []
    types = report.get("law_types") or {}

    def who(name):
        others = types.get(name) or []
        return f"{name} (and {len(others)} more of its type)" if others else name

    for r in report.get("inverse_square", []):
        lines.append((f"{who(r['light'])}: inverse square", _law_sentence(r, "inverse_square"), r.get("plot")))
    for r in report.get("cosine", []):
        lines.append((f"{who(r['light'])}: cosine law", _law_sentence(r, "cosine"), r.get("plot")))
    c = report.get("convergence")
    if c and "error" not in c:
        from ...plots.convergence import fit_in_words

        words = fit_in_words(c["fit"]["slope"], "samples") or "no convergence measured"
        lines.append((f"Convergence ({c['target']})", f"{words}; {100 * c['target_error']:g} % needs about "
                      f"{_plain(c['samples_for_target'], 2)} samples per reading", c.get("plot")))
    return lines


def write_html(path, report, client):
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
             f"<title>{html.escape(client['title'])}</title>",
             "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto;color:#222}"
             "table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #bbb;padding:3px 8px;"
             "text-align:left;font-size:90%}th{background:#eee}img{max-width:100%;margin:0.5em 0}"
             "h2{border-bottom:1px solid #ccc}</style></head><body>",
             f"<h1>{html.escape(client['title'])}</h1>",
             f"<p>{html.escape(client['subtitle'])}</p>"]
    for title, header, rows in _tables(report, client):
        parts.append(f"<h2>{html.escape(title)}</h2>")
        parts.append(_html_table(header, rows))
    if client["images"]:
        parts.append("<h2>Pictures</h2>")
        for caption, name in client["images"]:
            parts.append(f"<figure><img src='{html.escape(name)}' alt='{html.escape(caption)}'>"
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    for section, pictures in client.get("section_images", {}).items():
        if pictures:
            parts.append(f"<h2>{html.escape(section.capitalize())}: maps</h2>")
            for caption, name in pictures:
                parts.append(f"<figure><img src='{html.escape(name)}' alt='{html.escape(caption)}' "
                             f"style='max-width:48%'><figcaption>{html.escape(caption)}</figcaption></figure>")
    appendix = _appendix(report)
    if appendix:
        parts.append("<h2>Engineering appendix: the physics checks</h2>")
        for title, sentence, plot in appendix:
            parts.append(f"<h3>{html.escape(title)}</h3><p>{html.escape(sentence)}.</p>")
            if plot:
                parts.append(f"<img src='{html.escape(os.path.basename(plot))}' alt='{html.escape(title)}'>")
    parts.append(f"<p><small>{html.escape(client['conventions'])}</small></p></body></html>")
    outputs.write_text(path, "\n".join(parts) + "\n")
    return path


def write_pdf(path, out_dir, report, client):
    """A4 pages: tables first, then one picture per page, then the appendix (plots embedded)."""
    from ... import plots

    plt = plots.pyplot()
    from matplotlib.backends.backend_pdf import PdfPages

    a4 = (8.27, 11.69)

    def table_page(pdf, blocks, heading=None):
        fig = plt.figure(figsize=a4)
        y = 0.95
        if heading:
            fig.text(0.07, y, heading[0], fontsize=15, weight="bold")
            fig.text(0.07, y - 0.018, "\n".join(_wrap(heading[1], 120)), fontsize=8, va="top")
            y -= 0.07
        for title, header, rows in blocks:
            lines = _wrap(title, 95)
            fig.text(0.07, y, "\n".join(lines), fontsize=10, weight="bold", va="top")
            y -= 0.012 + 0.014 * len(lines)
            cells = [[_short(str(c), 70) for c in row] for row in rows] or [["-"] * len(header)]
            h = 0.018 * (len(cells) + 1)
            ax = fig.add_axes((0.07, y - h, 0.86, h))
            ax.axis("off")
            t = ax.table(cellText=cells, colLabels=header, cellLoc="left", bbox=(0, 0, 1, 1))
            t.auto_set_font_size(False)
            t.set_fontsize(7)
            t.auto_set_column_width(list(range(len(header))))
            y -= h + 0.03
        pdf.savefig(fig)
        plt.close(fig)

    def image_pages(pdf, pictures, heading=None):
        """Pictures from the top of the page down, each with its caption right below it, as many
        per page as fit (a picture page used to float one small image in the middle of A4)."""
        fig, y = None, 0.0
        for caption, file_name in pictures:
            img = plt.imread(os.path.join(out_dir, file_name))
            lines = _wrap(caption, 110)
            height = 0.88 * a4[0] * img.shape[0] / img.shape[1] / a4[1]  # page fraction at 88 % of the width
            # two pictures to a page with captions of up to 2 lines: 0.915 - 2 x (0.36 + 0.046) - 0.025 > 0.04
            height = min(height, 0.36)
            need = height + 0.02 + 0.013 * len(lines)
            if fig is None or y - need < 0.04:
                if fig is not None:
                    pdf.savefig(fig)
                    plt.close(fig)
                fig, y = plt.figure(figsize=a4), 0.95
                if heading:
                    fig.text(0.07, y, heading, fontsize=12, weight="bold", va="top")
                    y -= 0.035
            ax = fig.add_axes((0.06, y - height, 0.88, height))
            ax.imshow(img)
            ax.axis("off")
            fig.text(0.5, y - height - 0.008, "\n".join(lines), ha="center", va="top", fontsize=8)
            y -= need + 0.025
        if fig is not None:
            pdf.savefig(fig)
            plt.close(fig)

    with outputs.atomic_output(path) as tmp, PdfPages(tmp) as pdf:
        tables = _tables(report, client)
        # at most ~28 rows per page
        page, rows_on_page, first = [], 0, True
        for block in tables:
            n = len(block[2]) + 3
            if page and rows_on_page + n > 40:
                table_page(pdf, page, (client["title"], client["subtitle"]) if first else None)
                page, rows_on_page, first = [], 0, False
            page.append(block)
            rows_on_page += n
        if page:
            table_page(pdf, page, (client["title"], client["subtitle"]) if first else None)
        image_pages(pdf, client["images"], "Pictures")
        for section, pictures in client.get("section_images", {}).items():
            image_pages(pdf, pictures, f"{section.capitalize()}: maps")
        image_pages(pdf, [(f"{title}: {sentence}.", os.path.basename(plot)) for title, sentence, plot in _appendix(report)
                          if plot and os.path.exists(plot)], "Engineering appendix: the physics checks")
    return path


def _wrap(text, width):
    import textwrap

    return textwrap.wrap(text, width) or [""]


def _picture_size(scene, longest=None):
    """The camera's aspect at ``longest`` pixels (default PICTURE_LONGEST_PX) on the longer side."""
    longest = PICTURE_LONGEST_PX if longest is None else longest
    r = scene.render
    w, h = max(r.resolution_x, 1), max(r.resolution_y, 1)
    k = longest / max(w, h)
    return max(1, round(w * k)), max(1, round(h * k))


def _plain(value, digits=4):
    """``value`` to ``digits`` significant digits without scientific notation: 10240 -> '10240';
    "n/a" for a missing or non-finite number (an exact scene's convergence fit has no samples figure)."""
    if value is None or not math.isfinite(float(value)):
        return "n/a"
    v = float(f"{float(value):.{digits}g}")
    return f"{v:.0f}" if abs(v) >= 10 ** (digits - 1) else f"{v:g}"


def _short(text, n):
    return text if len(text) <= n else text[: n - 1] + "…"


def client_report(report, out_dir, *, request, project=None, task=None, maintenance_factor=0.8, observers=(),
                  ra=None, camera_image=True):
    """Add the client's parts to ``report`` (the analysis report dict) and write report.html and
    report.pdf into ``out_dir``. ``project``: dict of project data (name, client, designer, ...);
    ``task``: an EN 12464-1 task key (``radiometry.metrics.compliance.TASKS``) or a dict of requirement values
    (maintained_lx, uniformity, ugr_limit, ra_required), None: each work plane's custom property
    ``radiometer_task`` or no compliance table; ``observers``: ((x, y, z), (dx, dy, dz)) eye positions
    for UGR. The request (``measure.blender.request``) gives the scene, the report's ``quality`` (None:
    "standard": UGR's background and the picture's cap) and cancel. Returns the client dict (also stored
    as ``report["client"]``)."""
    from ... import plots
    from ...radiometry.metrics import compliance
    from ..analyses import glare as glare_mod
    from ..analyses.grid import work_planes

    scene, quality, cancelled = request.scene, request.quality or "standard", request.cancelled
    # UGR and the picture at the report's quality, seed 0, no budget or progress of the report's parts
    request = request.but(quality=quality, target_rel_error=None, samples=None, time_budget_s=None,
                          target_abs_error=None, seed=0, progress=None, client=None)
    blend = os.path.basename(bpy.data.filepath) if bpy.data.filepath else "(unsaved file)"
    project = dict(project or {})
    name = project.pop("name", None) or scene.get("radiometer_project") or \
        (os.path.splitext(blend)[0] if bpy.data.filepath else scene.name)
    info = {"project": name}
    info.update({k: str(v) for k, v in project.items()})
    info.update({"Blender file": blend, "scene": scene.name,
                 "date": datetime.date.today().isoformat(),
                 "quality": str(report.get("quality"))})
    client = {"title": f"Lighting report: {name}", "project": info, "schedule": luminaire_schedule(request),
              "compliance": [], "glare": [], "images": [],
              "subtitle": "Illuminance, uniformity, glare and luminance computed with Radiometer from the Blender "
                          "scene as Cycles renders it; every reading with its standard error.",
              "conventions": "Units: lx, cd/m², m, W, lm. Readings show the digits their 1-sigma standard error "
                             "supports. Luminous efficacy K = 683 lm/W unless the scene says otherwise. "
                             "UGR by CIE 117-1995; requirements from EN 12464-1 as cited."}
    glare_results = []
    for k, obs in enumerate(observers or ()):
        if cancelled is not None and cancelled():
            raise MeasurementCancelled("report cancelled; the previous report is as it was")
        (p, d) = obs
        try:
            g = glare_mod.glare_ugr(p, d, request=request)
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report.setdefault("errors", []).append(f"glare at observer {k + 1}: {exc}")
            continue
        glare_results.append((f"observer {k + 1}", g))
        client["glare"].append({"label": f"observer {k + 1} {tuple(round(float(v), 2) for v in p)} m",
                                "ugr": g.ugr, "ugr_text": f"not measurable: {g.not_measurable}" if g.not_measurable
                                else f"{g.ugr:.1f} {g.error_text()}" if math.isfinite(g.ugr)
                                else "no source in the field",
                                "lb_text": g.background_text(),
                                "sources": g.sources, "left_out": g.left_out})
    planes = {p.name: p for p in work_planes(scene)}
    daylight = daylight_words(scene)
    for grid in report.get("grids", []):
        if "error" in grid:
            continue
        plane = planes.get(grid["target"])
        key = task if task is not None else (plane.get("radiometer_task") if plane is not None else None)
        if key is None:
            continue
        try:
            req = compliance.requirement(**key) if isinstance(key, dict) else compliance.requirement(str(key))
        except (TypeError, ValueError) as exc:
            raise RadiometerError(f"compliance task: {exc}") from None
        lux = np.asarray(grid["lux"], float)
        se = np.asarray(grid["rel_std_error"], float)
        rows = compliance.assess(req, average_lx=grid["stats"]["avg"], minimum_lx=grid["stats"]["min"],
                                 maintenance_factor=maintenance_factor,
                                 average_rel_se=float(np.sqrt(np.sum((lux * se) ** 2)) / max(lux.sum(), 1e-300)),
                                 minimum_rel_se=float(se.ravel()[int(np.argmin(lux))]),
                                 ugr=[(label, g.ugr, g.ugr_std_error, g.error_unknown or g.not_measurable)
                                      for label, g in glare_results], ra=ra, lighting=daylight)
        import dataclasses

        client["compliance"].append({"plane": grid["target"], "requirement": dataclasses.asdict(req),
                                     "maintenance_factor": float(maintenance_factor),
                                     "checks": [dataclasses.asdict(r) for r in rows],
                                     "overall": compliance.overall(rows)})
    draw = plots.matplotlib_available()
    if draw and camera_image and scene.camera is not None:
        from ..analyses import luminance_image

        try:
            # A picture, not a measurement: preview target, at most PICTURE_SPP samples per pixel per render
            # (measured: in an office of 6 IES luminaires a round of 8 renders at 64 spp took 246 s where one
            # at 16 spp took 53 s and already had 97 % of the pixels within 5 %; bench/report_cost.md).
            img = luminance_image.luminance_image(os.path.join(out_dir, "luminance.exr"),
                                                  request=request.but(quality="preview"),
                                                  resolution=_picture_size(scene), max_spp=PICTURE_SPP.get(quality, 64))
            client["images"].append((f"False-colour luminance seen by the camera {scene.camera.name} (cd/m², log "
                                     f"scale; {100 * img.share_on_target:.0f} % of the pixels within "
                                     f"{100 * img.target_rel_error:g} %)", "luminance.png"))
        except MeasurementCancelled:  # a cancel is no failed picture: the report stops (issue 33)
            raise
        except RadiometerError as exc:
            report.setdefault("errors", []).append(f"luminance image: {exc}")
    for grid in report.get("grids", []):
        if grid.get("image"):
            s = grid["stats"]
            client["images"].append((f"Isolux lines on {grid['target']} (lx): Ē {_plain(s['avg'], 3)} lx, E_min "
                                     f"{_plain(s['min'], 3)} lx, U0 {s['u0']:.2f}", os.path.basename(grid["image"])))
    if report.get("daylight"):
        client["section_images"] = {"daylight": [tuple(p) for p in report["daylight"].get("images", [])]}
        client["subtitle"] += (" Daylight: the daylight factor under the CIE overcast sky, the annual metrics "
                               "from the weather file named, sunlight hours and daylight glare (DGP).")
    report["client"] = client
    html_path = os.path.join(out_dir, "report.html")
    write_html(html_path, report, client)
    paths = {"html": html_path}
    if draw:
        paths["pdf"] = write_pdf(os.path.join(out_dir, "report.pdf"), out_dir, report, client)
    client["paths"] = paths
    return client

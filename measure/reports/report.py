"""A full analysis report of a scene: meters, law checks per light, work-plane grids, convergence.

``export_report(out_dir)`` writes ``report.json`` (everything, SI units), ``report.md`` (readable
tables linking the PNG plots) and the plots/CSV files next to them. Every part runs on its own: an
item that cannot be analysed (a sun for inverse square, an empty plane) is recorded with the reason
and the rest continues. Work planes: mesh objects whose name contains "work plane" (any case) or
that carry the custom property ``radiometer_work_plane``.

File names follow the object names readably and uniquely (``outputs.Stems``: "Lamp.1" and
"Lamp_1" get different files, letters of any script are kept). The text writers take any missing
or non-finite number (NaN, None) and show "n/a". ``cancelled()`` is polled by every measurement;
a cancelled report raises MeasurementCancelled and writes nothing.
"""

import json
import math
import os
import time
import unicodedata

import bpy

from ... import outputs, plots
from ...errors import MeasurementCancelled, RadiometerError
from ..analyses import analysis
from ..meter import meter_objects
from ..blender import request as request_of
from ..analyses.analysis_common import plain
from .report_files import planned_files
from ..analyses.grid import work_planes  # noqa: F401 - report.work_planes: the planes the report grids


#: The report's law checks are its engineering appendix, not the full study (that is ``check``'s job):
#: a few distances and tilts per light, and at preview a fixed number of samples per reading instead
#: of a target error (a tilted meter's tiny reading could otherwise take millions of samples). Closed
#: forms, exact where proven, cost nothing either way; each reading still states its own error.
REPORT_LAW_DISTANCES = 6
REPORT_LAW_ANGLES_DEG = (0.0, 30.0, 60.0, 75.0, 85.0, 89.0)
PREVIEW_LAW_SAMPLES = 1024


def law_check_budget(budget, quality):
    """The budget keywords of the report's law checks: the report's own, or at preview (and without a
    time budget of the user's) a fixed ``PREVIEW_LAW_SAMPLES`` per reading."""
    if quality == "preview" and budget.get("time_budget_s") is None:
        return {"quality": quality, "samples": PREVIEW_LAW_SAMPLES}
    return dict(budget)


_TYPE_ATTRIBUTES = ("type", "energy", "exposure", "use_temperature", "temperature", "normalize", "use_soft_falloff",
                    "shadow_soft_size", "spot_size", "spot_blend", "shape", "size", "size_y", "spread", "angle")


def _light_type_key(obj):
    """What makes two light objects the same luminaire for the law checks: the light's settings, its
    colour, its photometric file and the object's scale (rotation and position do not change a light's
    own law). A light with its own node tree and no photometric file is a type of its own."""
    data = obj.data
    source = data.get("radiometer_photometric_file") if hasattr(data, "get") else None
    if getattr(data, "node_tree", None) is not None and getattr(data, "use_nodes", True) and not source:
        return ("own", obj.name)
    values = []
    for name in _TYPE_ATTRIBUTES:
        v = getattr(data, name, None)
        values.append(round(float(v), 9) if isinstance(v, (int, float)) and not isinstance(v, bool) else v)
    return (tuple(values), tuple(round(c, 6) for c in data.color), source,
            tuple(round(v, 6) for v in obj.matrix_world.to_scale()))


def light_types(lights):
    """[(representative, [the others of its type])], in the order of ``lights``: the report checks
    each type's laws once (a light's own inverse-square and cosine behaviour belongs to its type)."""
    groups = {}
    for ob in lights:
        groups.setdefault(_light_type_key(ob), []).append(ob)
    return [(members[0], members[1:]) for members in groups.values()]


def plot_stem(name, among=()):
    """A readable file-name stem for an object name, unique among the names ``among`` (``outputs.Stems``):
    how the report and the analysis operators name an object's plot files."""
    return outputs.Stems(sorted(set(among) | {name}))(name)


class _Missing(float):
    """A missing number (None or NaN in a result): formats as "n/a", is falsy, absorbs arithmetic."""

    def __new__(cls):
        return float.__new__(cls, "nan")

    def __format__(self, spec):
        return "n/a"

    def __str__(self):
        return "n/a"

    __repr__ = __str__

    def __bool__(self):
        return False

    def _same(self, *_args):
        return self

    __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = __truediv__ = __rtruediv__ = _same
    __neg__ = __pos__ = __abs__ = __round__ = __pow__ = __rpow__ = _same


MISSING = _Missing()


def _text(value):
    # Object names may hold newlines, control characters or "|": one table cell, one line.
    cleaned = "".join(" " if unicodedata.category(ch) in ("Cc", "Zl", "Zp") else ch for ch in value)
    return cleaned.replace("|", "\\|")


def _robust(value):
    """A copy of a result dict for the text writers: None and NaN numbers become MISSING, strings
    lose control characters (a name with a newline must not break a table)."""
    if value is None or isinstance(value, _Missing):
        return MISSING
    if isinstance(value, str):
        return _text(value)
    if isinstance(value, float) and math.isnan(value):
        return MISSING
    if isinstance(value, dict):
        return {k: _robust(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_robust(v) for v in value]
    return value


def _given(value):
    return value is not None and not isinstance(value, _Missing)


def _fmt(value, spec=".4g"):
    if not _given(value) or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a" if not _given(value) or math.isnan(value) else "∞"
    return format(value, spec)


def export_report(out_dir, **kwargs):
    """Analyse the scene and write report.json, report.md and PNG plots into ``out_dir`` (blocking).

    Keywords as :func:`iter_report`; returns the report dict.
    """
    parts = iter_report(out_dir, **kwargs)
    try:
        while True:
            next(parts)
    except StopIteration as done:
        return done.value


def iter_report(out_dir, *, request, method=None, convergence=True, convergence_samples=(4, 16, 64), phase=None,
                client=True, project=None, task=None, maintenance_factor=0.8, observers=(), ra=None, meters=(),
                settings=None, daylight=False, epw=None, median_external_illuminance_lux=None,
                daylight_resolution=None):
    """The report as a generator of parts, for modal operators: one ``next()`` measures one part.

    The first ``next()`` measures nothing and yields the plan, a list of (label, weight); every
    further ``next()`` measures one part and yields its label; the last one writes the files and
    ends the generator with the report dict (``StopIteration.value``). ``export_report`` runs it.

    The request (``measure.blender.request``) gives the scene; its ``quality`` (target 1-sigma relative
    error per reading: preview 5 %, standard 1 %, reference 0.2 %) and ``target_rel_error`` (fraction), like
    ``method``, override ``settings`` (the scene's Radiometer settings, read by the api: a dict of "method",
    "quality", "target_rel_error"; None: auto, standard, the preset's) where given; its ``time_budget_s`` (s)
    bounds each measurement of the report (a meter batch, a law check, a grid). ``meters``: the scene's meters
    (``measure.meter.meter_objects.Meter``, the api's). Every analysis measures with the meter's per-meter
    allocation. Returns the report dict (also written as report.json) with ``paths`` and ``summary`` (the
    text table).

    The request's ``progress(done, total, seconds_left)``: done/total in thousandths of the whole report, ETA
    in s or None; ``phase(label)``: the part being measured ("meters", "laws Lamp", ...); the request's
    ``cancelled()``: polled by every measurement, True raises MeasurementCancelled (nothing written).

    The files are one set, replaced together or not at all (``outputs.FileSet``): every file is
    written into a hidden staging folder inside ``out_dir``, and only when all are complete are they
    renamed into place, report.json (the manifest: its ``"files"`` lists the set) last; files of the
    previous report that the new one lacks are removed then. An error, a cancel or Ctrl-C at any
    moment before leaves the previous set as it was and no temporary file. Every target (a link, a
    folder) is checked before the first measurement.

    ``client``: also write the client's report.html and report.pdf (``measure.reports.client_report``: project
    data ``project`` (dict), luminaire schedule, EN 12464-1 compliance for ``task`` with
    ``maintenance_factor``, UGR at ``observers`` ((x, y, z), (dx, dy, dz)), the luminaires' rated
    ``ra``, a false-colour luminance image of the scene camera, the isolux plots, the readings, and the
    law checks as an engineering appendix).

    ``daylight``: True adds the daylight section (``measure.reports.daylight_section``: daylight factor,
    with the weather file ``epw`` sDA/ASE/UDI and sunlight hours, DGP at the camera, the EN 17037 table
    and the maps; ``median_external_illuminance_lux`` the site's E_v,d for the DF method;
    ``daylight_resolution`` (nx, ny) the grids, default EN 12464-1's spacing); "auto": when the scene has
    a sky (a sun or an emitting world); False (default): none.
    """
    out = os.path.abspath(out_dir)
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as exc:
        raise RadiometerError(f"cannot create report folder {out}: {exc.strerror}") from None
    with outputs.FileSet(out, manifest="report.json", name="report") as stage:
        return (yield from _report_parts(stage, request=request, method=method,
                                         convergence=convergence, convergence_samples=convergence_samples,
                                         phase=phase, client=client,
                                         project=project, task=task, maintenance_factor=maintenance_factor,
                                         observers=observers, ra=ra, meters=meters, settings=settings,
                                         daylight=daylight, epw=epw,
                                         median_external_illuminance_lux=median_external_illuminance_lux,
                                         daylight_resolution=daylight_resolution))


def _report_parts(stage, *, request, method, convergence, convergence_samples, phase, client, project, task,
                  maintenance_factor, observers, ra, meters, settings, daylight=False, epw=None,
                  median_external_illuminance_lux=None, daylight_resolution=None):
    """:func:`iter_report`'s parts, written into ``stage`` (an ``outputs.FileSet``) and committed at the end."""
    scene, progress, cancelled = request.scene, request.progress, request.cancelled
    time_budget_s = request.time_budget_s
    from ..meter.point_meter import capture_model

    capture_model(scene, request.view_layer)  # bad input (a light of non-finite power) is one error, as for `measure`
    out = stage.target
    settings = dict(settings or {"method": "auto", "quality": "standard", "target_rel_error": None})
    if request.quality:
        settings["quality"] = request.quality
    if method:
        settings["method"] = method
    if request.target_rel_error is not None:
        settings["target_rel_error"] = float(request.target_rel_error)
    q, m, goal = settings["quality"], settings["method"], settings["target_rel_error"]
    # the report's budget for every part (each part passes its own progress)
    base = request.but(quality=q, target_rel_error=goal, progress=None, samples=None, target_abs_error=None, seed=0)
    started = time.perf_counter()
    report = {"scene": scene.name, "file": bpy.data.filepath, "quality": q, "method": m, "law_types": {},
              "target_rel_error": goal, "time_budget_s": time_budget_s,
              "meters": [], "inverse_square": [], "cosine": [], "grids": [], "convergence": None, "errors": []}

    objs = list(meters)
    types = light_types(analysis.scene_lights_to_check(scene))
    lights = [representative for representative, _same in types]  # one law check per luminaire type
    report["law_types"] = {rep.name: [ob.name for ob in same] for rep, same in types if same}
    planes = work_planes(scene)
    conv_target = None
    if convergence:
        conv_target = next((m.obj for m in objs if m.kind == "ILLUMINANCE"), None)
        conv_target = conv_target or next(iter(planes), None)
    if daylight == "auto":
        from .daylight_section import sky_words

        daylight = bool(sky_words(scene))
    if daylight and not planes:
        raise RadiometerError("the report's daylight section needs a work plane: add a mesh named 'Work Plane'")
    if daylight and epw:
        from ...radiometry.sun import epw as epw_mod

        try:  # a bad weather file is one line before any measurement, not after the grids
            epw_mod.read_epw(epw)
        except (OSError, ValueError) as exc:
            raise RadiometerError(f"weather file: {exc}") from None
    # Rough relative costs for one progress bar: a law check ~ 2 measurements, a grid ~ 3, a study ~ 4,
    # the daylight section ~ 8 per plane.
    parts = [1.0] * bool(objs) + [2.0] * len(lights) + [3.0] * len(planes) + [4.0] * (conv_target is not None) \
        + [8.0] * bool(daylight)
    bounds = [0.0]
    for w in parts:
        bounds.append(bounds[-1] + w / max(sum(parts), 1e-12))
    state = {"part": -1}

    def _overall(fraction):
        if progress is None:
            return
        elapsed = time.perf_counter() - started
        eta = elapsed * (1 - fraction) / fraction if fraction > 0.02 else None
        from ...progress import reporter  # one adapter for both callback forms

        reporter(progress)(int(round(1000 * fraction)), 1000, eta)

    def part_progress(done, total, *_rest):
        k = state["part"]
        lo, hi = bounds[k], bounds[k + 1]
        _overall(lo + (hi - lo) * (min(max(done / total, 0.0), 1.0) if total else 0.0))

    labels = (["meters"] * bool(objs) + [f"laws {light.name}" for light in lights]
              + [f"grid {plane.name}" for plane in planes] + ["convergence"] * (conv_target is not None)
              + ["daylight"] * bool(daylight))
    plan = list(zip(labels, parts))

    def step(label):
        # What the generator yields before measuring a part: the plan first, then the part's label.
        if cancelled is not None and cancelled():
            raise MeasurementCancelled("report cancelled; the scene was restored, the previous report is as it was")
        state["part"] += 1
        if phase is not None:
            phase(label)
        _overall(bounds[state["part"]])
        return plan if state["part"] == 0 else label

    stems = outputs.Stems(sorted({ob.name for ob in lights} | {ob.name for ob in planes}))
    watched = base.but(progress=part_progress)
    draw = plots.matplotlib_available()  # without matplotlib: the numbers, no plot paths asked for
    if not draw:
        report["errors"].append("no plots: " + plots.missing_message())
    # Every target before any work (issue 33: a report.html that is a folder was refused after 20 s).
    planned = planned_files([stems(ob.name) for ob in lights], [stems(ob.name) for ob in planes], draw,
                            conv_target is not None, client)
    if daylight and draw:
        from .daylight_section import map_files

        planned += map_files([stems(ob.name) for ob in planes], annual=bool(epw), sun=bool(epw))
    outputs.check_set(out, planned, "report file")
    out, final = stage.folder, stage.target  # written into the staging folder, moved into `final` at the end
    # Meters (readings are not written to the objects: a report leaves the scene as it was).
    if objs:
        yield step("meters")
        try:
            steps = [st for st in meter_objects.plan_steps(objs) if st[0] != "RADIANCE_MAP"]  # maps: images
            tracker = meter_objects.StepProgress(steps, lambda f, eta: part_progress(f, 1.0))
            for i, st in enumerate(steps):
                tracker.start(i)
                for obj, reading in meter_objects.run_step(base.but(progress=tracker), st, method=m):
                    entry = dict(name=obj.name, **reading.to_dict())
                    if reading.quantity == "illuminance":
                        entry["melanopic"] = _melanopic(base, obj)
                    report["meters"].append(entry)
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report["errors"].append(f"meters: {exc}")
    # Law checks per light.
    law = law_check_budget(base.budget(), q)  # a whole budget: the fields it leaves out are None
    law_budget = watched.but(**{name: law.get(name) for name in request_of.BUDGET_FIELDS})
    for light in lights:
        yield step(f"laws {light.name}")
        slug = stems(light.name)
        try:
            r = analysis.check_inverse_square(light, request=law_budget, method=m, points=REPORT_LAW_DISTANCES,
                                              plot=os.path.join(out, f"inverse_square_{slug}.png") if draw else None)
            report["inverse_square"].append(r.to_dict())
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report["inverse_square"].append({"light": light.name, "kind": light.data.type, "error": str(exc)})
        try:
            where = {}
            if light.data.type == "SUN":
                # a sun's cosine check means something only where the sun shines in the room: at the centre
                # of the first work plane (else the first illuminance meter), never at the origin
                spot = _room_point(planes, objs)
                if spot is None:
                    raise RadiometerError("a sun's cosine check needs a point in the room: add a work plane or an "
                                          "illuminance meter")
                where = {"location": spot}
            r = analysis.check_cosine_law(light, request=law_budget, method=m, **where,
                                          angles_deg=REPORT_LAW_ANGLES_DEG,
                                          plot=os.path.join(out, f"cosine_{slug}.png") if draw else None)
            report["cosine"].append(r.to_dict())
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report["cosine"].append({"light": light.name, "kind": light.data.type, "error": str(exc)})
    # Grids on work planes.
    for plane in planes:
        yield step(f"grid {plane.name}")
        slug = stems(plane.name)
        try:
            g = analysis.illuminance_grid(plane, request=watched, method=m,
                                          png=os.path.join(out, f"isolux_{slug}.png") if draw else None,
                                          csv_path=os.path.join(out, f"grid_{slug}.csv"))
            report["grids"].append(g.to_dict())
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report["grids"].append({"target": plane.name, "error": str(exc)})
    # A short convergence study on the first illuminance meter (else the first work plane).
    if conv_target is not None:
        target = conv_target
        yield step("convergence")
        try:
            c = analysis.convergence_study(target, request=base, samples=convergence_samples,
                                           meter_kind=next((m.kind for m in objs if m.obj == target), None),
                                           plot=os.path.join(out, "convergence.png") if draw else None)
            report["convergence"] = c.to_dict()
        except MeasurementCancelled:
            raise
        except RadiometerError as exc:
            report["convergence"] = {"target": target.name, "error": str(exc)}
    if daylight:
        yield step("daylight")
        from .daylight_section import measure_daylight

        report["daylight"] = measure_daylight(base, planes, out, stems, epw_path=epw,
                                              median_external_illuminance_lux=median_external_illuminance_lux,
                                              resolution=daylight_resolution, draw=draw)
        report["errors"] += [f"daylight: {e}" for e in report["daylight"]["errors"]]
    if client:
        from . import client_report

        client_report.client_report(report, out, request=base, project=project, task=task,
                                    maintenance_factor=maintenance_factor, observers=observers, ra=ra)
    if cancelled is not None and cancelled():
        raise MeasurementCancelled("report cancelled; the scene was restored, the previous report is as it was")
    _overall(1.0)
    report["seconds"] = time.perf_counter() - started
    report["paths"] = {"json": os.path.join(out, "report.json"), "markdown": os.path.join(out, "report.md")}
    report["paths"].update(report.get("client", {}).get("paths", {}))
    report = outputs.relocated(report, out, final)  # the paths the files will have once in place
    report["summary"] = summary_table(report)
    report["files"] = sorted(set(stage.files()) | {"report.json", "report.md"})  # the set (the manifest)
    # Markdown first, JSON last: report.json is the manifest, renamed into place last too.
    outputs.write_text(stage.path("report.md"), markdown(report))
    outputs.write_text(stage.path("report.json"), json.dumps(plain(report), indent=2) + "\n")
    stage.commit()
    return report


def _room_point(planes, meters):
    """Scene coordinates of the first work plane's centre, else of the first illuminance meter, else None."""
    for plane in planes:
        if plane.type == "MESH" and len(plane.data.vertices):
            import numpy as np

            co = np.array([v.co[:] for v in plane.data.vertices])
            centre = (co.min(axis=0) + co.max(axis=0)) / 2
            return tuple(plane.matrix_world @ __import__("mathutils").Vector(centre))
    for m in meters:
        if m.kind == "ILLUMINANCE":
            return tuple(m.obj.matrix_world.translation)
    return None


def summary_table(report):
    """Plain-text summary: one line per meter, light check and grid (missing numbers: "n/a")."""
    report = _robust(report)
    lines = []
    if report["meters"]:
        lines.append(f"{'meter':<24} {'reading':>12} {'unit':<6} {'± 1 s.e.':>9}  method")
        for r in report["meters"]:
            value, unit, error = _meter_cells(r)
            lines.append(f"{r['name']:<24} {value:>12} {unit:<6} {error:>9}  {r['method']}")
        lines.append("")
    lines.append(f"{'light':<18} {'kind':<6} {'1/d² exponent':>16} {'near field (m)':>15} {'1/d²':>11} "
                 f"{'scene':>7} {'cos max dev':>12} {'cos':>11} {'scene':>7}")
    cos_by = {c["light"]: c for c in report["cosine"]}
    for r in report["inverse_square"]:
        c = cos_by.get(r["light"], {})
        if "error" in r:
            inv = f"{'n/a':>16} {'n/a':>15} {'--':>11} {'':>7}"
        else:
            limit = _near_field_text(r)
            # an exact fit's standard error is rounding noise (4e-16): 0
            se = r["exponent_se"] if not _given(r["exponent_se"]) or r["exponent_se"] >= 5e-7 else 0.0
            inv = (f"{_fmt(r['exponent'], '.3f'):>9} ± {_fmt(se, '.1g'):<5}"
                   f"{limit:>15} {verdict(r):>11} {_share(r):>7}")
        cos = (f"{'n/a':>12} {'--':>11} {'':>7}" if "error" in c or not c else
               f"{_pct(c['max_rel_deviation']).lstrip('+'):>12} {verdict(c):>11} {_share(c):>7}")
        lines.append(f"{r['light']:<18} {r['kind']:<6} {inv} {cos}")
    if report["inverse_square"]:
        import textwrap

        lines += textwrap.wrap("(each light alone, judged on its own direct light. 'near field': the light is not a "
                               "point at these distances or from this spot (an extended source, Blender's soft "
                               "falloff) and departs from the law exactly as the closed form of its shape predicts: "
                               "physics, not a fault; 'departs': a departure its shape does not explain (see the "
                               "causes); 'scene': the largest share of a reading the room adds by interreflection)",
                               108)
        lines += [f"{name}: also stands for {_same_type_text(others)} (same luminaire type: its laws checked once)"
                  for name, others in (report.get("law_types") or {}).items()]
    for g in report["grids"]:
        lines.append("")
        if "error" in g:
            lines.append(f"grid {g['target']}: {g['error']}")
        else:
            lines.append(f"grid {g['target']} ({g['nx']} x {g['ny']}): {_grid_stats_text(g)}  [{g['method']}]")
    c = report.get("convergence")
    if c and "error" not in c:
        lines.append("")
        from ...plots.convergence import fit_in_words

        slope = c["fit"]["slope"]
        words = fit_in_words(slope) if _given(slope) else ""
        lines.append(f"convergence ({c['target']}): {words or 'no convergence measured'} (error ∝ N^{_fmt(slope, '.2f')});"
                     f" {100 * c['target_error']:g} % needs about {_fmt(c['samples_for_target'], '.2g')} samples per "
                     f"reading, {_fmt(c['seconds_for_target'], '.2g')} s")
        t = c.get("targeted")
        if t:
            lines.append(f"  error-targeted reading: {_fmt(t['samples'], '.3g')} samples, {t['seconds']:.3g} s, "
                         f"stated {100 * t['rel_std_error']:.3g} %, RMS error {100 * t['rms_error']:.3g} %")
    return "\n".join(lines)


def _law_opening(md, result, near_field, departs):
    """Append one light's law-check section head to ``md`` ('### light (kind)', then why it was not checked, or
    its expected departure); return None where it was not checked, else the heading of its verdict: 'Follows
    the law', ``near_field`` (departs as its shape predicts) or ``departs``."""
    md.append(f"### {result['light']} ({result['kind']})\n")
    if "error" in result:
        md.append(f"Not checked: {result['error']}\n")
        return None
    if result.get("departure"):
        md.append(f"**As expected:** {result['departure']}.\n")
    return "Follows the law" if result["passed"] else near_field if result.get("expected_departure") else departs


def _meter_cells(result):
    """A meter's reading, its unit ('lx' or 'cd/m²') and its error: the digits the error supports, as the
    CLI's measure and the sidebar show them."""
    from ...readings import format_error, format_value

    lum = result.get("quantity") == "luminance"
    value = result["luminance"] if lum else result["illuminance"]
    se = result["rel_std_error"] if _given(result["rel_std_error"]) else None
    return (format_value(value, se, result["exact"]), "cd/m²" if lum else "lx", format_error(se, result["exact"]))


def _melanopic(request, obj):
    """The direct light's melanopic reading at an illuminance meter (``spectra.spectral_reading``: closed forms
    per light and each light's spectrum), as the report keeps it; {"error": ...} when a spectrum is refused."""
    from ..meter import meter_objects

    try:
        r = meter_objects.direct_spectral_reading(obj, request)
    except RadiometerError as exc:
        return {"error": str(exc)}
    return {"mel_edi_lx": float(r["mel_edi_lx"]), "mel_der": r["mel_der"], "exact": bool(r["exact"]),
            "complete": bool(r["complete"]), "notes": list(r["notes"])}


def _melanopic_text(result):
    from ...readings import format_melanopic

    return format_melanopic(result.get("melanopic"))


def _who_broke(result):
    """'light', 'scene', ...: with the light's near field named as such when its shape explains it."""
    who = str(result.get("broken_by") or "")
    return who.replace("light", "the light's near field") if result.get("expected_departure") else who


def _grid_stats_text(grid):
    """'E_avg 277 lx ±0.4 %, E_min 180 lx, E_max 457 lx, U0 0.65': the digits each error supports (E_avg's
    error from the points' errors, as the grid CLI says it; E_min/E_max their own point's)."""
    from ...readings import format_quantity, format_value

    s = grid["stats"]
    try:
        import numpy as np

        lux = np.asarray(grid["lux"], float).ravel()
        se = np.asarray(grid["rel_std_error"], float).ravel()
        avg_se = float(np.sqrt(np.sum((lux * se) ** 2)) / max(float(np.sum(lux)), 1e-300))
        exact = bool(grid.get("exact"))
        return (f"E_avg {format_quantity(s['avg'], 'lx', avg_se, exact)}, E_min "
                f"{format_value(s['min'], float(se[np.argmin(lux)]), exact)} lx, E_max "
                f"{format_value(s['max'], float(se[np.argmax(lux)]), exact)} lx, U0 {s['u0']:.2f}")
    except (KeyError, TypeError, ValueError):  # a result without its points: the plain numbers
        return f"E_avg {_fmt(s['avg'])} lx, E_min {_fmt(s['min'])} lx, E_max {_fmt(s['max'])} lx, U0 {_fmt(s['u0'], '.2f')}"


def _same_type_text(names, most=4):
    """'Lamp 2, Lamp 3' or 'Lamp 2, Lamp 3, Lamp 4, Lamp 5 and 3 more'."""
    names = list(names)
    shown = ", ".join(names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")


def _pct(value):
    """A signed relative deviation in %: '+1.2 %', and '0 %' for rounding noise (|x| < 5e-7, e.g. 3e-16)."""
    if not _given(value) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return "n/a"
    return "0 %" if abs(value) < 5e-7 else f"{100 * value:+.3g} %"


def _row_mark(row, result):
    """'✓', 'near field' (closer than the near-field limit: an extended source, as expected) or '✗'."""
    if row["ok"]:
        return "✓"
    limit = result.get("near_field_limit")
    if _given(limit) and isinstance(limit, float) and math.isfinite(limit) and row["distance"] < limit:
        return "near field"
    if result.get("expected_departure"):
        return "near field"
    return "✗"


def _near_field_text(result):
    """Near-field limit in m: '0' (a point everywhere), '0.52', or '> 1.8' (beyond the distances checked)."""
    limit = result.get("near_field_limit")
    if _given(limit) and isinstance(limit, (int, float)) and math.isfinite(limit):
        return _fmt(limit, ".3g")
    rows = result.get("rows") or []
    last = rows[-1].get("distance") if rows and isinstance(rows[-1], dict) else None
    return f"> {_fmt(last, '.2g')}" if _given(last) else "not reached"


def verdict(result):
    """'ok', 'ok(scene)' (the light obeys; the room's light on top does not), 'near field' (the light
    departs exactly as the closed form of its shape predicts: physics) or 'departs' (unexplained)."""
    if result.get("passed"):
        return "ok" if result.get("total_passed", True) else "ok(scene)"
    if result.get("expected_departure"):
        return "near field"
    broken = result.get("broken_by", "light")
    return "departs(light)" if "light" in (broken if isinstance(broken, str) else "light") else "departs"


def _share(result):
    share = result.get("max_scene_share")
    return f"+{100 * share:.3g} %" if share else "0"


def _img(path):
    if not path or not isinstance(path, str):
        return ""
    # A link target with spaces or brackets needs <...> in CommonMark.
    return f"![{os.path.basename(path)}](<{os.path.basename(path)}>)\n\n"


def markdown(report):
    """report.md: tables of every result with the plots inline (relative links); missing numbers "n/a"."""
    report = _robust(report)
    md = [f"# Radiometer analysis report: {report['scene']}\n",
          f"File `{os.path.basename(report['file']) if report['file'] else '(unsaved)'}`; quality `{report['quality']}`, method `{report['method']}`; "
          f"{report['seconds']:.1f} s. Units: lux, W/m², m, deg.\n",
          "```\n" + report["summary"] + "\n```\n"]
    if report["errors"]:
        md.append("**Errors:** " + "; ".join(report["errors"]) + "\n")
    if report["meters"]:
        md.append("## Meters\n\n| meter | value | unit | ± 1 s.e. | method | mel-EDI of the direct light |\n"
                  "|---|---:|---|---:|---|---:|")
        for r in report["meters"]:
            value, unit, error = _meter_cells(r)
            md.append(f"| {r['name']} | {value} | {unit} | {error} | {r['method']} | {_melanopic_text(r)} |")
        md.append("\nmel-EDI: melanopic equivalent daylight illuminance (CIE S 026) of the lights' direct light, "
                  "from each light's spectrum; the reflected light and the world are not in it (docs/spectral.md); "
                  "'>=' where a light without a spectrum is left out.")
        md.append("")
    md.append("## Inverse-square law\n")
    for name, others in (report.get("law_types") or {}).items():
        md.append(f"- {name} also stands for {_same_type_text(others, 50)}: the same luminaire type (settings, colour, "
                  "photometric file, scale), whose own laws are checked once.")
    md.append("")
    for r in report["inverse_square"]:
        heading = _law_opening(md, r, "Near field, as its shape predicts", "Departs from I/d² (see causes)")
        if heading is None:
            continue
        md.append(f"{heading}: exponent {_fmt(r['exponent'], '.4f')} ± "
                  f"{_fmt(r['exponent_se'], '.2g')} (fit from {_fmt(r['fit_from'], '.3g')} m), near-field limit "
                  f"{_near_field_text(r).replace('>', 'beyond').replace('not reached', 'beyond the sweep')} m, source size {r['source_size']:.3g} m (five-times rule "
                  f"{r['five_times']['rule_distance']:.3g} m: {'holds' if r['five_times']['rule_holds'] else 'does not hold'}"
                  f"), measured by {r['method']}. Judged on the light's own direct light "
                  f"({r.get('direct_method') or r['method']}); the room adds up to {100 * r.get('max_scene_share', 0):.3g} % "
                  f"of a reading; the total {'also follows' if r.get('total_passed', True) else 'does not follow'} "
                  f"the law{' (broken by: ' + _who_broke(r) + ')' if r.get('broken_by') else ''}.\n")
        for cause in r["causes"]:
            md.append(f"- cause: {cause}")
        for note in r["notes"]:
            md.append(f"- note: {note}")
        # lux where the scene gives an efficacy (the user's unit), else W/m² (CIE Y weighted)
        k = r.get("efficacy") if _given(r.get("efficacy")) and r.get("efficacy", 0) > 0 else 1.0
        unit = "lx" if k != 1.0 else "W/m²"
        md.append(f"\n| d (m) | E total ({unit}) | E direct ({unit}) | I/d² ({unit}) | direct dev. | total dev. | "
                  "scene share | rel. s.e. | light's model dev. | ok |\n"
                  "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        for row in r["rows"]:
            md.append(f"| {row['distance']:.4g} | {k * row['measured']:.5g} | {k * row.get('direct', row['measured']):.5g} | "
                      f"{k * row['predicted']:.5g} | {_pct(row.get('direct_deviation', row['rel_deviation']))} | "
                      f"{_pct(row['rel_deviation'])} | {100 * row.get('scene_share', 0):.3g} % | "
                      f"{100 * row['rel_std_error']:.2g} % | {_pct(row['model_deviation'])} | "
                      f"{_row_mark(row, r)} |")
        md.append("")
        md.append(_img(r.get("plot")))
    md.append("## Cosine law\n")
    for c in report["cosine"]:
        heading = _law_opening(md, c, "Extended source, as its shape predicts", "Departs from cos θ (see causes)")
        if heading is None:
            continue
        md.append(f"{heading} at {tuple(round(v, 3) for v in c['location'])}: max "
                  f"deviation {100 * c['max_rel_deviation']:.3g} % at {c['max_at_deg']:g} deg; onset "
                  f"{_fmt(c['onset_deg'], 'g')} deg; source reaches the horizon at {c['horizon_onset_deg']:.3g} deg. "
                  f"Judged on the light's own direct light; with the room's light the total deviates up to "
                  f"{100 * c.get('total_max_rel_deviation', c['max_rel_deviation']):.3g} % (the room adds up to "
                  f"{100 * c.get('max_scene_share', 0):.3g} % of a reading).\n")
        for cause in c["causes"]:
            md.append(f"- cause: {cause}")
        md.append("\n| θ (deg) | direct E(θ)/E(0) | total E(θ)/E(0) | cos θ | direct dev. | total dev. | scene share "
                  "| rel. s.e. | ok |\n|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        for row in c["rows"]:
            md.append(f"| {row['angle']:g} | {row.get('direct_ratio', row['ratio']):.5g} | {row['ratio']:.5g} | "
                      f"{row['predicted']:.5g} | {_pct(row.get('direct_deviation', row['rel_deviation']))} | "
                      f"{_pct(row['rel_deviation'])} | {100 * row.get('scene_share', 0):.3g} % | "
                      f"{100 * row['ratio_rel_se']:.2g} % | {'✓' if row['ok'] else ('near field' if c.get('expected_departure') else '✗')} |")
        md.append("")
        md.append(_img(c.get("plot")))
    if report["grids"]:
        md.append("## Work-plane grids\n")
        for g in report["grids"]:
            md.append(f"### {g['target']}\n")
            if "error" in g:
                md.append(f"Not measured: {g['error']}\n")
                continue
            s = g["stats"]
            md.append(f"{g['nx']} x {g['ny']} points ({g['spacing'][0]:.3g} x {g['spacing'][1]:.3g} m cells"
                      f"{'; ' + g['spacing_rule'] if g['spacing_rule'] else ''}), {g['method']}.\n\n"
                      f"| E_avg (lx) | E_min (lx) | E_max (lx) | U0 |\n|---:|---:|---:|---:|\n"
                      f"| {s['avg']:.4g} | {s['min']:.4g} | {s['max']:.4g} | {s['u0']:.3f} |\n")
            md.append(_img(g.get("image")))
            if g.get("csv"):
                md.append(f"Data: [{os.path.basename(g['csv'])}]({os.path.basename(g['csv'])})\n")
    from .daylight_section import markdown_lines

    md += markdown_lines(report.get("daylight"))
    c = report.get("convergence")
    if c:
        md.append("## Convergence\n")
        if "error" in c:
            md.append(f"Not run: {c['error']}\n")
        else:
            md.append(f"Target {c['target']}; reference {c['reference_kind']}. Fit: error ∝ N^{c['fit']['slope']:.3f} ± "
                      f"{c['fit']['slope_se']:.2g} (ideal -0.5), error ∝ t^{c['fit']['time_slope']:.3f} ± "
                      f"{c['fit']['time_slope_se']:.2g} against the wall time of one reading of the target alone; "
                      f"{100 * c['target_error']:g} % needs {c['samples_for_target']:.3g} samples per reading, "
                      f"{_fmt(c['seconds_for_target'], '.3g')} s (t0 + c N; the time fit alone says "
                      f"{_fmt(c.get('seconds_for_target_by_time_fit'), '.3g')} s).\n\n"
                      "| samples/texel | samples/reading | seconds | RMS error | stated s.e. |\n|---:|---:|---:|---:|---:|")
            for row in c["rows"]:
                md.append(f"| {row['samples_per_texel']} | {row['samples']} | {row['seconds']:.3g} | "
                          f"{100 * row['rms_error']:.3g} % | {100 * row['std_error']:.3g} % |")
            md.append("")
            t = c.get("targeted")
            if t:
                md.append(f"Error-targeted reading (the meter's per-meter allocation, target "
                          f"{_fmt(t['target_rel_error'] and 100 * t['target_rel_error'], '.3g')} %): "
                          f"{_fmt(t['samples'], '.3g')} samples, {t['seconds']:.3g} s, stated error "
                          f"{100 * t['rel_std_error']:.3g} %, RMS error against the reference {100 * t['rms_error']:.3g} %"
                          f"{'' if t['reached'] else ' (target NOT reached)'}.\n")
            md.append(_img(c.get("plot")))
    return "\n".join(md) + "\n"

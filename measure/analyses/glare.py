"""Discomfort glare at an observer (host side): CIE 117 UGR from the scene as Cycles renders it.

Sources: area lights (Lambertian or with spread; luminance towards the eye from their radiant intensity,
exact solid angle of their rectangle / ellipse) and photometric (IES/EULUMDAT) point lights whose file
gives a flat luminous opening (luminance = I / projected area, solid angle = projected area / d², as
CIE 117 defines them). Left out, and said so: delta lights without a luminous area (point, spot,
sphere lights: their luminance is not defined by the file), suns (daylight glare is DGP's field, not
UGR's), the sky seen through windows, sources outside CIE 117's field.

Emissive meshes (an Emission shader of plain strength and colour: ``radiometry.emitters.EmissiveMesh``)
count: Cycles' emission is Lambertian, so each triangle's luminance towards the eye is K x Y of its
radiance (strength x colour, SI), whatever the direction; its solid angle is exact (Van Oosterom &
Strackee); each triangle counts for the part the eye sees. The object is one source: omega the sum, L
such that L^2 omega is the sum of the triangles' L^2 omega, p at the centre of the luminous area seen.
Left out, and said so: emission the capture cannot read (a texture, a node chain), meshes invisible to
camera rays, and meshes of more than :data:`MAX_SOURCE_TRIANGLES` triangles.

Visibility (issue 32), for every source alike (an area light's outline, an IES opening, a mesh's
triangles): proven in full view, proven hidden (left out, with the occluder's name) or cut to the part
in view with proven bounds (``radiometry.scene.source_visibility``: the meter's separating-axis proof, a
coplanar-patch proof of hiding, subdivision between).

Background: Lb = E_ind / pi, E_ind = the vertical illuminance at the eye minus its direct part (both
measured by the meter: closed forms where proven, Cycles with lights transparent to rays otherwise),
with the quality's target on E_ind itself; an error that is not known is "error unknown" with the
cause (``GlareResult.error_unknown``), never a number.
"""

import dataclasses
import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry.metrics import glare as glare_math
from ...radiometry.scene import scene_model
from ...radiometry.scene import source_visibility
from ...radiometry.emitters import RayVisibility
from ...radiometry.emitters.photometric import opening_outline


MAX_SOURCE_TRIANGLES = 20000  #: an emitting mesh with more triangles is left out (said so), not rated
OUTLINE_SIDES = 64  #: sides of the polygon circumscribing a round luminous area in the visibility proofs


@dataclasses.dataclass
class GlareResult:
    """CIE 117 UGR at one observer. Luminances cd/m², solid angles sr, illuminances lx."""

    ugr: float
    ugr_std_error: float            #: 1 s.e. of UGR from E_ind's (both readings): 8 / ln 10 x rel. s.e.; nan unknown
    background_luminance: float     #: Lb = E_ind / pi, cd/m²
    indirect_illuminance: float     #: E_ind on the vertical plane at the eye, lx
    total_illuminance: float        #: vertical illuminance at the eye, lx
    background_rel_std_error: float
    sources: list                   #: dicts: name, luminance, solid_angle (of the part seen), position_index,
    #: sigma_deg, tau_deg, visible_fraction, visible_fraction_bounds, solid_angle_bounds, visibility (words)
    left_out: list                  #: dicts: name, reason
    observer: tuple
    view_direction: tuple
    notes: list
    error_unknown: str = ""         #: why the standard error is unknown ("" when it is known)
    not_measurable: str = ""        #: why UGR cannot be measured here (ugr is nan), "" otherwise
    #: (UGR, UGR) with every partly hidden source at its proven smallest / largest visible solid angle;
    #: None when every rated source is proven in full view
    ugr_visibility_range: tuple = None
    background_target_rel_error: float = None  #: the target put on E_ind (1 s.e., relative)

    def to_dict(self):
        d = dataclasses.asdict(self)
        for k in ("ugr", "ugr_std_error", "background_rel_std_error"):
            if d[k] is None or not math.isfinite(d[k]):
                d[k] = None
        if d["ugr_visibility_range"] is not None:
            d["ugr_visibility_range"] = [v if math.isfinite(v) else None for v in d["ugr_visibility_range"]]
        return d

    def error_text(self):
        """'±0.1', or 'error unknown (cause)' (never ±inf or ±nan)."""
        if self.error_unknown or not math.isfinite(self.ugr_std_error):
            return f"error unknown ({self.error_unknown or 'no standard error'})"
        return f"±{self.ugr_std_error:.2g}"  # 2 significant digits: a small error never prints as ±0.0

    def background_text(self):
        from ...readings import format_value

        lb = format_value(self.background_luminance, self.background_rel_std_error)
        known = math.isfinite(self.background_rel_std_error) and not self.error_unknown
        return f"{lb} cd/m²" + ("" if known else " (error unknown)")

    def summary(self):
        if self.not_measurable:
            return f"UGR not measurable: {self.not_measurable}"
        hidden = sum("hidden from the eye" in d["reason"] for d in self.left_out)
        tail = f"; {hidden} hidden from the eye, left out" if hidden else ""
        if not math.isfinite(self.ugr):
            return f"UGR: no glare source in the field (Lb {self.background_text()}{tail})"
        span = ""
        if self.ugr_visibility_range is not None:
            lo, hi = self.ugr_visibility_range
            span = f", visibility bounds {lo:.1f}..{hi:.1f}" if math.isfinite(lo) else f", visibility bound <= {hi:.1f}"
        return (f"UGR {self.ugr:.1f} {self.error_text()} ({len(self.sources)} sources{span}, Lb "
                f"{self.background_text()}{tail})")


def _opening_outline(spec, opening):
    """World vertices (K, 3) m of a flat IES luminous opening at the light's photometric centre, facing
    its emission direction (``radiometry.emitters.photometric.opening_outline``)."""
    return opening_outline(spec.axes, spec.position, opening, OUTLINE_SIDES)


def _rate(sources, left_out, name, geometry, view, eye, up, seen=None):
    """Add one source seen from ``eye`` to ``sources`` when it is in CIE 117's field, else to ``left_out``.

    ``geometry``: (luminance cd/m², solid angle sr of what the eye sees, centre m); ``seen``: the visible
    part's record (fraction and proven bounds, equivalent solid-angle bounds, words), None when whole."""
    luminance, omega, centre = geometry[:3]
    sigma, tau, elevation = glare_math.view_angles(view, centre - eye, up)
    if not glare_math.in_field(sigma, elevation):
        why = "below the line of sight" if elevation <= 0 else "behind the eye (90 deg or more off the view)"
        left_out.append({"name": name, "reason": f"outside CIE 117's field: {why}"})
        return
    entry = {"name": name, "luminance": float(luminance), "solid_angle": float(omega),
             "position_index": float(glare_math.position_index(sigma, tau)),
             "sigma_deg": float(sigma), "tau_deg": float(tau),
             "visible_fraction": 1.0, "visible_fraction_bounds": (1.0, 1.0),
             "solid_angle_bounds": (float(omega), float(omega)), "visibility": "proven in full view"}
    if seen is not None:
        entry.update(seen)
    sources.append(entry)


def _hidden_reason(part):
    return (f"hidden from the eye by {', '.join(repr(b) for b in part.blockers)} (proven: every line of sight "
            "to it crosses an opaque surface)")


def _seen_words(part, term_bounds=None):
    """The visible part's record for a source entry (see ``_rate``)."""
    if part.status == source_visibility.CLEAR:
        words = "proven in full view"
    else:
        by = ", ".join(repr(b) for b in part.blockers) or "an occluder"
        words = (f"partly hidden by {by}: {100 * part.fraction:.1f} % of its solid angle in view (proven "
                 f"{100 * part.lower:.1f}-{100 * part.upper:.1f} %"
                 + (f"; {part.unresolved} small cell(s) on the edge of the shadow counted by the ray to their "
                    "centre" if part.unresolved else "") + ")")
    if part.see_through:
        words += (f"; seen through non-opaque {', '.join(repr(b) for b in part.see_through)}, rated without "
                  "its transmittance (an upper bound)")
    return {"visible_fraction": float(part.fraction), "visible_fraction_bounds": (float(part.lower), float(part.upper)),
            "visibility": words}


def _light_part(name, geometry, eye, model):
    """(geometry cut to what the eye sees, seen record) of a light, or (None, reason) when it is hidden."""
    luminance, omega, _centre, outline = geometry
    tol = scene_model.length_tolerance(np.vstack([eye[None], outline]))
    part = source_visibility.seen_part(eye, source_visibility.polygon_cells(outline), model.geometry, tol)
    if part.status == source_visibility.HIDDEN:
        return None, _hidden_reason(part)
    seen = _seen_words(part)
    seen["solid_angle_bounds"] = (float(omega * part.lower), float(omega * part.upper))
    centre = part.centre_seen[0] if part.area_seen[0] > 0 else geometry[2]
    return (luminance, omega * part.fraction, centre), seen


def _mesh_source(mesh, eye, efficacy, weights, model):
    """((luminance cd/m², solid angle sr, centre) of what the eye sees of an emitting mesh, seen record),
    or (None, reason)."""
    if mesh.radiance is None:
        return None, "emissive surface whose emission the capture cannot read (a texture or node chain): not rated"
    if not mesh.visibility & RayVisibility.CAMERA:
        return None, "emissive surface invisible to camera rays: the eye does not see it"
    tris = np.asarray(mesh.triangles, float)
    if len(tris) > MAX_SOURCE_TRIANGLES:
        return None, f"emissive mesh of {len(tris)} triangles (more than {MAX_SOURCE_TRIANGLES}): not rated"
    luminance = efficacy * (np.asarray(mesh.radiance, float) @ weights)
    lit = luminance > 0
    if not lit.any():
        return None, "no emitting triangle (unlit)"
    tol = scene_model.length_tolerance(np.vstack([eye[None], tris[lit].reshape(-1, 3)]))
    # Both sides emit: every lit triangle is a cell, its visible part proven or bounded from the eye.
    part = source_visibility.seen_part(eye, list(tris[lit]), model.geometry, tol)
    if part.status == source_visibility.HIDDEN:
        return None, _hidden_reason(part)
    lum_lit = luminance[lit]
    seen = part.omega_seen > 0
    if not seen.any():
        return None, "no emitting triangle in the eye's view (the rays to every part left undecided are blocked)"
    lum, total, centre = glare_math.patches_as_one_source(part.centre_seen[seen], part.area_seen[seen],
                                                          lum_lit[seen], part.omega_seen[seen])
    record = _seen_words(part)
    # Bounds of L^2 omega as solid angles at the source's one luminance L (exact for a uniform mesh).
    lo = float(lum_lit ** 2 @ part.omega_clear) / lum ** 2
    hi = float(lum_lit ** 2 @ (part.omega - part.omega_hidden)) / lum ** 2
    record["solid_angle_bounds"] = (min(lo, total), max(hi, total))
    return (lum, total, centre), record


def observer_and_view(observer, view_direction, up=(0.0, 0.0, 1.0)):
    """(eye (3,) scene coordinates, unit view (3,)) checked: one-line RadiometerError for anything that is
    not 3 finite numbers each, a zero view, or a view along ``up`` (no vertical plane for P)."""
    try:
        eye_scene = np.asarray(observer, float).reshape(3)
        view = np.asarray(view_direction, float).reshape(3)
    except (TypeError, ValueError):
        raise RadiometerError("observer and view_direction need 3 numbers each") from None
    if not (np.all(np.isfinite(eye_scene)) and np.all(np.isfinite(view)) and np.linalg.norm(view) > 0):
        raise RadiometerError(f"observer and view_direction must be finite and the view non-zero, got "
                              f"{tuple(eye_scene)}, {tuple(view)}")
    view = view / np.linalg.norm(view)
    try:
        glare_math.view_frame(view, up)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    return eye_scene, view


def glare_ugr(observer, view_direction, *, request, up=(0.0, 0.0, 1.0)):
    """CIE 117 UGR for an eye at ``observer`` (scene coordinates) looking along ``view_direction``.

    The request (``measure.blender.request``) gives the scene, its photometry and the background's
    ``quality`` (None: "standard"). Returns :class:`GlareResult`. See the module docstring for what counts
    as a source.
    """
    from ..meter import point_meter as meter

    eye_scene, view = observer_and_view(observer, view_direction, up)
    eye = request.to_metres(eye_scene)
    model = meter.capture_model(request.scene, request.view_layer)
    space, weights, efficacy = request.photometry

    sources, left_out = [], []
    candidates = [(light, None) for light in model.lights] + [(None, mesh) for mesh in
                                                             getattr(model, "emissive_meshes", [])]
    for light, mesh in candidates:
        if mesh is not None:
            name = mesh.name or "emissive surface"
            geometry, seen = _mesh_source(mesh, eye, efficacy, weights, model)
            if geometry is None:
                left_out.append({"name": name, "reason": seen})
                continue
            _rate(sources, left_out, name, geometry, view, eye, up, seen)
            continue
        if light.spec is None:
            left_out.append({"name": light.name, "reason": f"not modelled ({light.uncovered})"})
            continue
        if light.portal:
            continue
        geometry, reason = light.spec.luminous_area_seen(eye, efficacy, weights, OUTLINE_SIDES)
        if geometry is None:
            left_out.append({"name": light.name, "reason": reason})
            continue
        sigma, _tau, elevation = glare_math.view_angles(view, geometry[2] - eye, up)
        if not glare_math.in_field(sigma, elevation):
            _rate(sources, left_out, light.name, geometry, view, eye, up)  # left out: outside the field
            continue
        cut, seen = _light_part(light.name, geometry, eye, model)
        if cut is None:
            left_out.append({"name": light.name, "reason": seen})
            continue
        _rate(sources, left_out, light.name, cut, view, eye, up, seen)
    notes = []
    if np.any(model.geometry.emissive) and not getattr(model, "emissive_meshes", None):
        notes.append("emissive surfaces are not rated as glare sources (their light counts in the background)")
    if model.world_emits:
        notes.append("the world (sky through windows) is not rated as a glare source; its light counts in the "
                     "background")
    notes.append("visibility: every source's luminous area is proven in view, proven hidden (left out) or cut to "
                 "the part the eye sees, among the scene's shadow-casting surfaces (radiometry.scene.source_visibility)")
    partly = [s["name"] for s in sources if s["visible_fraction_bounds"] != (1.0, 1.0)]
    if partly:
        notes.append(f"partly hidden, rated for the part in view: {', '.join(partly)} (see each source's "
                     "'visibility'; ugr_visibility_range gives UGR at their proven bounds)")
    lo, hi = glare_math.OMEGA_RANGE_SR
    odd = [s["name"] for s in sources if not lo <= s["solid_angle"] <= hi]
    if odd:
        notes.append(f"outside CIE 117's range of source sizes ({lo:g}-{hi:g} sr): {', '.join(odd)}; UGR is given "
                     "but CIE 147 treats such sources separately")
    background = _background(eye_scene, view, request, meter, model)
    notes += background["notes"]
    e_ind, rel, lb = background["e_ind"], background["rel"], background["e_ind"] / math.pi
    args = ([s["luminance"] for s in sources], [s["position_index"] for s in sources])
    unknown, not_measurable, value, span = background["unknown"], "", -math.inf, None
    if sources and not e_ind > 0:
        not_measurable = (f"no indirect light reaches the eye (E_ind {e_ind:.3g} lx): UGR needs a background "
                          "luminance (a room with reflecting surfaces)")
        value = math.nan
    elif sources:
        value = glare_math.ugr(lb, args[0], [s["solid_angle"] for s in sources], args[1])
        if partly:
            span = tuple(glare_math.ugr(lb, args[0], [s["solid_angle_bounds"][k] for s in sources], args[1])
                         for k in (0, 1))
    if not math.isfinite(value):
        se = math.nan
    elif unknown:
        se = math.nan
    else:
        se = 8 / math.log(10) * rel
    return GlareResult(ugr=value, ugr_std_error=se, background_luminance=lb, indirect_illuminance=e_ind,
                       total_illuminance=background["e_total"], background_rel_std_error=rel, sources=sources,
                       left_out=left_out, observer=tuple(map(float, eye_scene)), view_direction=tuple(map(float, view)),
                       notes=notes, error_unknown=unknown, not_measurable=not_measurable, ugr_visibility_range=span,
                       background_target_rel_error=background["target"])


def _unknown_cause(reading, which):
    """Why ``reading`` states no finite error: its own note saying so, else a plain sentence."""
    said = [n for n in reading.notes if "unknown" in n or "infinite" in n]
    return f"the {which} reading: " + (said[0] if said else "it states no finite standard error")


def _background(eye_scene, view, request, meter, model=None):
    """E_ind = E_vertical - E_direct at the eye with its own target (the request's quality preset's, on E_ind:
    both readings share the allowed variance; a pilot at the preset decides the targets, independent readings
    (seed 1) are kept). Returns a dict: e_total, e_ind (lx), rel (1 s.e. of E_ind, relative; nan when
    unknown), unknown (the cause, or ""), target, notes."""
    target = float(request.preset()["target"])

    def read(seed, t_total=None, t_direct=None):
        # One meter run for both parts: one capture, one visibility proof (meter.measure_parts says why
        # each part that needs Cycles still has its own bakes). "direct": light straight from every
        # source, emitting surfaces included (rendered at 0 bounces).
        got = meter.measure_illuminance(eye_scene, view, request.but(
            seed=seed, target_rel_error={"total": t_total, "direct": t_direct}, samples=None, time_budget_s=None,
            target_abs_error=None), parts=("total", "direct"), model=model)
        return got["total"], got["direct"]

    def combine(total, direct):
        e_total, e_direct = float(total.illuminance), float(direct.illuminance)
        # a reading of 0 states its error as 0 (exact) or infinite (unknown): keep which
        s_total = abs(e_total) * total.rel_std_error if e_total else (0.0 if total.rel_std_error == 0 else math.inf)
        s_direct = abs(e_direct) * direct.rel_std_error if e_direct else (0.0 if direct.rel_std_error == 0 else math.inf)
        return e_total, e_direct, s_total, s_direct

    total, direct = read(0)
    e_total, e_direct, s_total, s_direct = combine(total, direct)
    e_ind = e_total - e_direct
    notes = []
    causes = [_unknown_cause(r, w) for r, s, w in ((total, s_total, "vertical illuminance"),
                                                    (direct, s_direct, "direct-only")) if not math.isfinite(s)]
    if not causes and e_ind > 0 and math.hypot(s_total, s_direct) > target * e_ind:
        # Split the allowed variance (target x E_ind)^2 between the readings in proportion to their
        # pilot errors (an exact reading, s.e. 0, takes none of it).
        allowed = target * e_ind
        share = allowed / math.hypot(s_total, s_direct)
        t_total = max(share * s_total / abs(e_total), 1e-4) if s_total else None
        t_direct = max(share * s_direct / abs(e_direct), 1e-4) if s_direct else None
        total, direct = read(1, t_total, t_direct)
        e_total, e_direct, s_total, s_direct = combine(total, direct)
        e_ind = e_total - e_direct
        notes.append(f"background: E_ind's own target {100 * target:g} % (1 s.e.): a pilot set the targets "
                     f"of E_vertical ({'exact' if t_total is None else f'{100 * t_total:.3g} %'}) and E_direct "
                     f"({'exact' if t_direct is None else f'{100 * t_direct:.3g} %'}); the readings kept are "
                     "independent of it (seed 1)")
        causes = [_unknown_cause(r, w) for r, s, w in ((total, s_total, "vertical illuminance"),
                                                        (direct, s_direct, "direct-only")) if not math.isfinite(s)]
    unknown = "; ".join(causes)
    rendered = not (total.exact and direct.exact)
    se = math.hypot(s_total, s_direct)
    if not unknown and rendered and se == 0 and e_ind != 0:
        unknown = "a rendered reading stated a standard error of 0"
    rel = math.nan if unknown or not e_ind > 0 else se / e_ind
    notes.append("Lb = (E_vertical - E_direct) / pi at the eye (CIE 117); lights are transparent to rays as "
                 "Cycles renders them")
    if unknown:
        notes.append(f"UGR and Lb: error unknown ({unknown})")
    return {"e_total": e_total, "e_ind": e_ind, "rel": rel, "unknown": unknown, "target": target, "notes": notes}

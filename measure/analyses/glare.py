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
Strackee); only triangles whose centre the eye sees (nothing of the scene in between, the mesh's own
far side included) count, each whole. The object is one source: omega the sum, L such that L^2 omega
is the sum of the triangles' L^2 omega, p at the centre of the luminous area seen. Left out, and said
so: emission the capture cannot read (a texture, a node chain), meshes invisible to camera rays, and
meshes of more than :data:`MAX_SOURCE_TRIANGLES` triangles.

Background: Lb = E_ind / pi, E_ind = the vertical illuminance at the eye minus its direct part (both
measured by the meter: closed forms where proven, Cycles with lights transparent to rays otherwise).
"""

import dataclasses
import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry.metrics import glare as glare_math


MAX_SOURCE_TRIANGLES = 20000  #: an emitting mesh with more triangles is left out (said so), not rated


@dataclasses.dataclass
class GlareResult:
    """CIE 117 UGR at one observer. Luminances cd/m², solid angles sr, illuminances lx."""

    ugr: float
    ugr_std_error: float            #: 1 s.e. of UGR from the background's standard error (8 / ln 10 x rel. s.e.)
    background_luminance: float     #: Lb = E_ind / pi, cd/m²
    indirect_illuminance: float     #: E_ind on the vertical plane at the eye, lx
    total_illuminance: float        #: vertical illuminance at the eye, lx
    background_rel_std_error: float
    sources: list                   #: dicts: name, luminance, solid_angle, position_index, sigma_deg, tau_deg
    left_out: list                  #: dicts: name, reason
    observer: tuple
    view_direction: tuple
    notes: list

    def to_dict(self):
        d = dataclasses.asdict(self)
        for k in ("ugr", "ugr_std_error"):
            if not math.isfinite(d[k]):
                d[k] = None
        return d

    def summary(self):
        from ...readings import format_value

        if not math.isfinite(self.ugr):
            return f"UGR: no glare source in the field (Lb {format_value(self.background_luminance, 0.01)} cd/m²)"
        return (f"UGR {self.ugr:.1f} ±{self.ugr_std_error:.1f} ({len(self.sources)} sources, Lb "
                f"{format_value(self.background_luminance, self.background_rel_std_error)} cd/m²)")


def _source_geometry(spec, eye, efficacy, weights, photometry_for):
    """(luminance cd/m², solid angle sr, centre) of one light seen from ``eye``, or (None, reason)."""
    centre = np.asarray(spec.position, float)
    to_eye = eye - centre
    dist = float(np.linalg.norm(to_eye))
    if dist == 0:
        return None, "the observer is inside the light"
    d = to_eye / dist
    if spec.kind == "AREA":
        if getattr(spec, "is_sheared", False):
            return None, "a sheared area light (Cycles samples another shape): not modelled"
        eu, ev = (np.asarray(e, float) for e in spec.edges)
        round_shape = spec.shape in ("DISK", "ELLIPSE")
        area = float(spec.area_m2)  # the emitter's area (its one home); not sheared here, so |eu x ev| (x pi/4)
        cos_l = float(d @ spec.emission_direction)
        if cos_l <= 0:
            return None, "seen from behind: it emits nothing towards the eye"
        intensity = float(spec.intensity_towards(d) @ weights) * efficacy  # cd
        luminance = intensity / (area * cos_l)
        if round_shape:
            poly = glare_math.disk_polygon(centre, eu, ev)
        else:
            poly = centre + np.array([[-.5, -.5], [.5, -.5], [.5, .5], [-.5, .5]]) @ np.array([eu, ev])
        return (luminance, glare_math.polygon_solid_angle(eye, poly), centre), None
    if spec.kind == "POINT" and spec.intensity_table is not None:
        photometry = photometry_for()
        if photometry is None:
            return None, "photometric light whose file is not at hand: no luminous area to rate"
        opening = glare_math.luminous_opening_m(photometry.metadata)
        if opening is None:
            return None, "its photometric file gives no luminous opening (a point source): no luminance to rate"
        gamma = math.degrees(math.acos(float(np.clip(d @ spec.emission_direction, -1.0, 1.0))))
        projected = glare_math.projected_opening_area(*opening, gamma)
        if projected is None:
            return None, "a luminous opening with height or of another shape: not modelled (flat ones only)"
        if projected <= 0:
            return None, "seen from above its luminous opening"
        intensity = float(spec.intensity_towards(d) @ weights) * efficacy
        return (intensity / projected, projected / dist**2, centre), None
    if spec.kind == "SUN":
        return None, "a sun: daylight glare is not rated by UGR (CIE 117 is for luminaires)"
    return None, f"a {spec.kind.lower()} light without a luminous area: its luminance is not defined"


def _rate(sources, left_out, name, geometry, view, eye, up):
    """Add one source seen from ``eye`` to ``sources`` when it is in CIE 117's field, else to ``left_out``."""
    luminance, omega, centre = geometry
    sigma, tau, elevation = glare_math.view_angles(view, centre - eye, up)
    if not glare_math.in_field(sigma, elevation):
        why = "below the line of sight" if elevation <= 0 else "behind the eye (90 deg or more off the view)"
        left_out.append({"name": name, "reason": f"outside CIE 117's field: {why}"})
        return
    sources.append({"name": name, "luminance": float(luminance), "solid_angle": float(omega),
                    "position_index": float(glare_math.position_index(sigma, tau)),
                    "sigma_deg": float(sigma), "tau_deg": float(tau)})


def _mesh_source(mesh, eye, efficacy, weights, model):
    """(luminance cd/m², solid angle sr, centre) of an emitting mesh seen from ``eye``, or (None, reason)."""
    from ...radiometry.scene import visibility
    from ...radiometry.emitters import RayVisibility

    if mesh.radiance is None:
        return None, "emissive surface whose emission the capture cannot read (a texture or node chain): not rated"
    if not mesh.visibility & RayVisibility.CAMERA:
        return None, "emissive surface invisible to camera rays: the eye does not see it"
    tris = np.asarray(mesh.triangles, float)
    if len(tris) > MAX_SOURCE_TRIANGLES:
        return None, f"emissive mesh of {len(tris)} triangles (more than {MAX_SOURCE_TRIANGLES}): not rated"
    luminance = efficacy * (np.asarray(mesh.radiance, float) @ weights)
    lit = luminance > 0
    centres = tris.mean(axis=1)
    to = centres - eye
    dist = np.linalg.norm(to, axis=1)
    dirs = to / np.where(dist > 0, dist, 1.0)[:, None]
    # Both sides emit: every lit triangle whose centre the eye sees (nothing nearer on the ray) counts.
    hit, _index, _facing = visibility.first_hits(eye, dirs[lit], model.geometry.triangles)
    seen = np.zeros(len(tris), bool)
    seen[lit] = hit >= dist[lit] * (1.0 - 1e-6) - 1e-6
    if not seen.any():
        return None, "no emitting triangle in the eye's view (hidden or unlit)"
    omega = glare_math.triangle_solid_angles(eye, tris[seen])
    areas = 0.5 * np.linalg.norm(np.cross(tris[seen, 1] - tris[seen, 0], tris[seen, 2] - tris[seen, 0]), axis=1)
    lum, total, centre = glare_math.patches_as_one_source(centres[seen], areas, luminance[seen], omega)
    return (lum, total, centre), None


def glare_ugr(observer, view_direction, *, scene=None, quality="standard", up=(0.0, 0.0, 1.0)):
    """CIE 117 UGR for an eye at ``observer`` (scene coordinates) looking along ``view_direction``.

    Returns :class:`GlareResult`. See the module docstring for what counts as a source.
    """
    import bpy

    from ..meter import point_meter as meter

    scene = scene or bpy.context.scene
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
    scale = scene.unit_settings.scale_length
    eye = eye_scene * scale
    view_layer = bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]
    model = meter.capture_model(scene, view_layer)
    space, weights, efficacy = meter.scene_photometry(scene)

    sources, left_out = [], []
    candidates = [(light, None) for light in model.lights] + [(None, mesh) for mesh in
                                                             getattr(model, "emissive_meshes", [])]
    for light, mesh in candidates:
        if mesh is not None:
            name = mesh.name or "emissive surface"
            geometry, reason = _mesh_source(mesh, eye, efficacy, weights, model)
            if geometry is None:
                left_out.append({"name": name, "reason": reason})
                continue
            _rate(sources, left_out, name, geometry, view, eye, up)
            continue
        if light.spec is None:
            left_out.append({"name": light.name, "reason": f"not modelled ({light.uncovered})"})
            continue
        if light.portal:
            continue

        def photometry_for(light=light):
            from ..capture import luminaires, scene_capture

            # the light's own object by identity (SourceId), never by name
            obj = next(iter(scene_capture.source_objects([light.source_id]).values()), None)
            try:
                return luminaires.photometry_of_light(obj) if obj is not None else None
            except RadiometerError:
                return None

        geometry, reason = _source_geometry(light.spec, eye, efficacy, weights, photometry_for)
        if geometry is None:
            left_out.append({"name": light.name, "reason": reason})
            continue
        _rate(sources, left_out, light.name, geometry, view, eye, up)
    notes = []
    if np.any(model.geometry.emissive) and not getattr(model, "emissive_meshes", None):
        notes.append("emissive surfaces are not rated as glare sources (their light counts in the background)")
    elif getattr(model, "emissive_meshes", None):
        notes.append("emissive meshes are rated from their triangles the eye sees, each triangle counted whole "
                     "(partly hidden triangles are not cut)")
    if model.world_emits:
        notes.append("the world (sky through windows) is not rated as a glare source; its light counts in the "
                     "background")
    lo, hi = glare_math.OMEGA_RANGE_SR
    odd = [s["name"] for s in sources if not lo <= s["solid_angle"] <= hi]
    if odd:
        notes.append(f"outside CIE 117's range of source sizes ({lo:g}-{hi:g} sr): {', '.join(odd)}; UGR is given "
                     "but CIE 147 treats such sources separately")

    total = meter.measure_illuminance(eye_scene, view, scene=scene, quality=quality)
    # direct_only: light straight from every source, emitting surfaces included (rendered at 0 bounces)
    direct = meter.measure_illuminance(eye_scene, view, scene=scene, quality=quality, direct_only=True)
    e_total, e_direct = float(total.illuminance), float(direct.illuminance)
    e_ind = e_total - e_direct
    se_abs = math.hypot(e_total * total.rel_std_error, e_direct * direct.rel_std_error)
    if not e_ind > 0:
        raise RadiometerError(f"no indirect light reaches the eye at {tuple(eye_scene)} (E_ind {e_ind:.3g} lx): "
                              "UGR needs a background luminance (a room with reflecting surfaces)")
    rel = se_abs / e_ind
    lb = e_ind / math.pi
    value = glare_math.ugr(lb, [s["luminance"] for s in sources], [s["solid_angle"] for s in sources],
                           [s["position_index"] for s in sources])
    notes.append("Lb = (E_vertical - E_direct) / pi at the eye (CIE 117); lights are transparent to rays as "
                 "Cycles renders them")
    return GlareResult(ugr=value, ugr_std_error=8 / math.log(10) * rel if math.isfinite(value) else math.nan,
                       background_luminance=lb, indirect_illuminance=e_ind, total_illuminance=e_total,
                       background_rel_std_error=rel, sources=sources, left_out=left_out,
                       observer=tuple(map(float, eye_scene)), view_direction=tuple(map(float, view)), notes=notes)

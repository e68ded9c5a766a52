"""Daylight glare probability at an observer (host side): DGP from a rendered angular fisheye.

Method: an angular (equidistant) 180 deg fisheye is rendered from the eye along the line of sight
(a temporary Cycles panoramic camera, ``FISHEYE_EQUIDISTANT``, removed afterwards) with the
luminance-image method (``measure.analyses.luminance_image.render_luminance``: independent renders, per-pixel
error by batch means); its pixels' directions and solid angles are ``radiometry.glare_dgp``'s
``angular_fisheye`` (Radiance's ``-vta``), so the same picture, written as a Radiance HDR, reads the
same in evalglare. Glare sources are found as evalglare finds them, on the picture: the sun's disc
seen through a pane, the sky through openings, luminaires and bright surfaces alike.

E_v: the meter's vertical illuminance at the eye (closed forms where proven, rendered otherwise, with
its standard error), which the DGP uses; the picture's own E_v (the sum of L cos(theta) omega) is
reported beside it as a check of the picture. The DGP's standard error combines E_v's and the
sources' luminance errors (first order); pixelation is stated apart: a source's border pixels are
partly covered (a pixel's mean luminance), so half their solid angle is counted as uncertain
(``radiometry.glare_dgp``'s ``dgp_pixel_error``); it shrinks as 1 / resolution. Delta lights (point/spot of radius 0, sun of angle 0) are not
seen by camera rays: they light the eye (E_v) but are no glare source (a note says so).

:func:`annual_dgp` (below): the hourly DGP at one eye over a weather file, imageless, from the daylight
coefficients (DGP with the sun's disc where it is seen, the simplified DGPs elsewhere; Wienold 2009).
"""

import dataclasses
import math

import numpy as np

from ...errors import RadiometerError
from ...readings import AsDict
from ...radiometry.metrics import glare_dgp as dgp_math
from ...radiometry.metrics.glare import view_frame

MAX_RESOLUTION = 512   #: px a side of the fisheye; preview-sized pictures are the point (128 by default)
#: cap on the samples per pixel of one fisheye render, per quality: DGP needs the bright pixels, which
#: converge first (the side-lit room at 128 px: DGP 0.216 ±0.001 at 64 and at 256 spp, 21 s vs 103 s)
MAX_SPP = {"preview": 64, "standard": 256, "reference": 1024}


@dataclasses.dataclass
class DaylightGlareResult(AsDict):
    """DGP at one observer. Luminances cd/m², solid angles sr, illuminances lx."""

    dgp: float
    dgp_std_error: float                 #: 1 s.e. from the render noise (E_v and the sources' pixels)
    dgp_resolution_error: float          #: from the sources' partly covered border pixels (pixelation)
    dgp_class: str
    vertical_illuminance: float          #: the meter's E_v at the eye (used in the DGP), lx
    vertical_illuminance_rel_std_error: float
    picture_vertical_illuminance: float  #: E_v summed over the fisheye picture, lx
    threshold_cd_m2: float
    sources: list                        #: dicts: luminance, solid_angle, position_index, direction, ...
    low_light_correction: bool
    observer: tuple
    view_direction: tuple
    resolution: int
    notes: list
    paths: dict = dataclasses.field(default_factory=dict)

    def summary(self):
        return (f"DGP {self.dgp:.3f} ±{self.dgp_std_error:.3f} (noise) ±{self.dgp_resolution_error:.3f} (pixels) "
                f"({self.dgp_class}; {len(self.sources)} glare sources, E_v {self.vertical_illuminance:.0f} lx)")


def _fisheye_camera(scene, eye_scene, view, up):
    """A temporary angular-fisheye camera (180 deg) at ``eye_scene`` looking along ``view``, ``up`` up."""
    import bpy
    from mathutils import Matrix

    f, u, r = view_frame(view, up)
    data = bpy.data.cameras.new("radiometer_dgp_fisheye")
    data.type = "PANO"
    if hasattr(data, "panorama_type"):
        data.panorama_type = "FISHEYE_EQUIDISTANT"
        data.fisheye_fov = math.pi
    else:  # Blender < 4: the panorama settings live on data.cycles
        data.cycles.panorama_type = "FISHEYE_EQUIDISTANT"
        data.cycles.fisheye_fov = math.pi
    data.clip_start, data.clip_end = 1e-4, 1e12
    cam = bpy.data.objects.new("radiometer_dgp_fisheye", data)
    cam.location = tuple(map(float, eye_scene))
    # a camera looks along its local -Z with +Y up: columns (right, up, -forward)
    cam.rotation_mode = "QUATERNION"
    cam.rotation_quaternion = Matrix(np.column_stack([r, u, -f]).tolist()).to_quaternion()
    scene.collection.objects.link(cam)
    return cam


def _dgp_std_error(ev, ev_rel, sources, rel_errors, low_light):
    """First-order 1 s.e. of DGP from E_v's relative error and each source's luminance error."""
    terms = np.array([s["luminance"] ** 2 * s["solid_angle"] / s["position_index"] ** 2 for s in sources])
    x = float(terms.sum()) / ev ** dgp_math.EV_EXPONENT if len(terms) else 0.0
    k = dgp_math.C_LOG / math.log(10) * x / (1 + x)                  # d DGP / d ln(sum)
    d_ln_sum = math.sqrt(sum((2 * e * t) ** 2 for e, t in zip(rel_errors, terms))) / terms.sum() if x else 0.0
    d_ev = (dgp_math.C_EV * ev - k * dgp_math.EV_EXPONENT) * ev_rel   # d DGP / d ln(E_v) x its rel. s.e.
    se = math.hypot(k * d_ln_sum, d_ev)
    return se * float(dgp_math.low_light_factor(ev)) if low_light else se


def glare_dgp(observer, view_direction, *, request, resolution=128, up=(0.0, 0.0, 1.0),
              threshold_cd_m2=dgp_math.THRESHOLD_CD_M2, threshold_factor=None, low_light_correction=False,
              hdr_path=None, max_spp=None):
    """DGP for an eye at ``observer`` (scene coordinates) looking along ``view_direction``. The request
    (``measure.blender.request``) gives the scene and ``quality`` (None: "preview") of the picture and E_v.

    ``resolution``: the fisheye's side in px (16..512). ``threshold_cd_m2`` / ``threshold_factor``:
    glare-source detection (``radiometry.glare_dgp.find_glare_sources``). ``hdr_path``: also write
    the fisheye as a Radiance HDR (angular fisheye, luminance / 179 in R, G and B, its VIEW in the
    header) for evalglare. ``max_spp``: cap on the samples per pixel of one render (None: :data:`MAX_SPP`
    for the quality). Returns :class:`DaylightGlareResult`.
    """
    from . import glare, luminance_image
    from ..meter import point_meter as meter
    from ..blender import scene_guard

    quality = request.quality or "preview"
    request = request.but(quality=quality, target_rel_error=None, samples=None, time_budget_s=None,
                          target_abs_error=None, seed=0)
    scene = request.scene
    eye_scene, view = glare.observer_and_view(observer, view_direction, up)
    try:
        n = int(resolution)
    except (TypeError, ValueError):
        raise RadiometerError(f"resolution must be an integer number of pixels, got {resolution!r}") from None
    if not 16 <= n <= MAX_RESOLUTION:
        raise RadiometerError(f"resolution must be 16 to {MAX_RESOLUTION} px, got {n}")
    if threshold_factor is None and not (float(threshold_cd_m2) > 0):
        raise RadiometerError(f"threshold_cd_m2 must be > 0 cd/m², got {threshold_cd_m2!r}")
    if threshold_factor is not None and not (float(threshold_factor) > 0):
        raise RadiometerError(f"threshold_factor must be > 0, got {threshold_factor!r}")
    if hdr_path is not None:
        from ... import outputs

        outputs.check_writable(hdr_path, "HDR file")
    with scene_guard.preserved_scene(scene):
        cam = _fisheye_camera(scene, eye_scene, view, up)
        img = luminance_image.render_luminance(request=request, camera=cam, resolution=(n, n),
                                               max_spp=max_spp or MAX_SPP.get(quality, 256))
    dirs, omega, valid = dgp_math.angular_fisheye(n, n, view, up)
    lum = np.where(valid, img.luminance, 0.0)
    if not np.all(np.isfinite(lum)):
        raise RadiometerError("the fisheye picture has NaN or infinite pixels (a light's power, a texture or the "
                              "world is not finite): no DGP")
    ev_meter = meter.measure_illuminance(eye_scene, view, request)
    ev, ev_rel = float(ev_meter.illuminance), float(ev_meter.rel_std_error)
    try:
        result = dgp_math.dgp_from_picture(lum, dirs, omega, valid, view, up, vertical_illuminance=ev,
                                           low_light_correction=low_light_correction,
                                           threshold_cd_m2=threshold_cd_m2, threshold_factor=threshold_factor)
    except ValueError as exc:
        raise RadiometerError(f"DGP at {tuple(map(float, eye_scene))}: {exc}") from None
    picture_ev = float(np.sum((lum * np.clip(dirs @ view, 0, 1) * omega)[valid]))
    rel_px = np.nan_to_num(img.rel_std_error, nan=0.0)
    rel_errors = []
    for s in result.sources:   # a source's mean luminance: s.e. from its pixels' independent errors
        sel = valid & (lum > result.threshold_cd_m2) & (dirs @ np.asarray(s["direction"]) > math.cos(0.35))
        lw = lum[sel] * omega[sel]
        rel_errors.append(float(np.sqrt(np.sum((lw * rel_px[sel]) ** 2)) / lw.sum()) if lw.sum() > 0 else 0.0)
    se = _dgp_std_error(ev, ev_rel, result.sources, rel_errors, low_light_correction)
    notes = list(result.notes) + [
        f"angular fisheye {n} x {n} px, {img.samples} samples per pixel; glare sources as evalglare finds them "
        f"(threshold {result.threshold_cd_m2:.0f} cd/m²)",
        f"E_v from the meter {ev:.0f} lx (±{100 * ev_rel:.1f} %); the picture's own E_v {picture_ev:.0f} lx",
        "delta lights (radius 0, sun of angle 0) light the eye but are not seen as glare sources"]
    paths = {}
    if hdr_path is not None:
        paths["hdr"] = write_angular_hdr(hdr_path, lum, view, up, eye_scene)
    return DaylightGlareResult(dgp=result.dgp, dgp_std_error=se, dgp_resolution_error=result.dgp_pixel_error,
                               dgp_class=result.dgp_class, vertical_illuminance=ev,
                               vertical_illuminance_rel_std_error=ev_rel, picture_vertical_illuminance=picture_ev,
                               threshold_cd_m2=result.threshold_cd_m2, sources=result.sources,
                               low_light_correction=bool(low_light_correction),
                               observer=tuple(map(float, eye_scene)), view_direction=tuple(map(float, view)),
                               resolution=n, notes=notes, paths=paths)


def write_angular_hdr(path, luminance, view, up, eye):
    """Write ``luminance`` (H, W) cd/m² as a Radiance angular-fisheye picture (``radiometry.glare_dgp.
    radiance_picture``), whole or not at all. Returns the path."""
    from ... import outputs

    outputs.write_bytes(path, dgp_math.radiance_picture(luminance, view, up, eye))
    return str(path)


# --- annual DGP at one eye, imageless, from the daylight coefficients (issue 34) ---------------------------------
#
# The way Radiance's and Honeybee's imageless annual glare go (Wienold 2009, "Dynamic daylight glare
# evaluation", Building Simulation 2009, Glasgow, 944-951), with the sun's disc added where it is seen:
#
# 1. E_v per hour: the daylight coefficients of ONE meter at the eye whose normal is the line of sight
#    (``measure.analyses.annual.annual_daylight``, the same renders, sky matrix and hourly standard
#    error as for points), sky + ground + sun (the sun spread over its 4 nearest patches: two-phase).
# 2. The sun as a glare source: at the hours where it stands in the view's front hemisphere AND its
#    centre ray reaches the eye (``annual.direct_sun`` with the eye's normal: 0 when an opaque triangle
#    blocks it, the panes' luminance-weighted transmittance through glass), its disc (0.533 deg,
#    omega = 6.80e-5 sr) has the luminance E_dn / omega x (what reaches the eye); its position index
#    at the disc's centre (``radiometry.metrics.glare_dgp.position_index_dgp``); full DGP
#    (Wienold & Christoffersen 2006) with that one source and E_v.
# 3. Every other hour: the simplified DGPs = 6.22e-5 E_v + 0.184 (Wienold 2007). DGPs has no contrast
#    term: a bright sky or pane seen from the eye is not a glare source there, so where no sun is seen
#    it is the lower envelope of DGP (a window of bright overcast sky beside a dark wall rates higher
#    in a rendered picture: :func:`glare_dgp` above).
#
# The DGP's standard error is first order from E_v's (the coefficients' covariance); the sun's
# luminance is a closed form (no render noise). Counts over the occupied hours: hours at or above 0.35 /
# 0.40 / 0.45 (perceptible / disturbing / intolerable), with the hours whose class changes within 2
# standard errors counted apart; EN 17037's protection-from-glare row from the occupied hours' DGP.

#: the class limits counted (perceptible, disturbing, intolerable from these up)
LIMITS = (0.35, 0.40, 0.45)


@dataclasses.dataclass
class AnnualDGPResult:
    """Hourly DGP at one eye. Arrays are (T,) over the weather file's records; illuminances lx,
    luminances cd/m^2. ``hours_above`` {limit: occupied hours with DGP >= limit}, ``hours_above_range``
    {limit: (hours with every DGP 2 s.e. lower, 2 s.e. higher)}, ``share_above`` {limit: share of the
    occupied hours}, ``en17037`` the protection-from-glare row (dict)."""

    observer: tuple
    view_direction: tuple
    dgp: np.ndarray
    dgp_std_error: np.ndarray
    vertical_illuminance: np.ndarray
    vertical_illuminance_std_error: np.ndarray
    sun_seen: np.ndarray
    sun_luminance: np.ndarray
    sun_position_index: np.ndarray
    occupied: np.ndarray
    hours: np.ndarray
    hours_above: dict
    hours_above_range: dict
    share_above: dict
    en17037: dict
    low_light_correction: bool
    notes: list
    weather_period: str = ""
    whole_year: bool = True

    def occupied_dgp(self):
        """The occupied hours' DGP (what ``api.en17037_table(dgp=...)`` takes)."""
        return self.dgp[self.occupied]

    def summary(self):
        n = int(self.occupied.sum())
        parts = [f"DGP >= {lim:.2f}: {self.hours_above[lim]} h ({100 * self.share_above[lim]:.1f} %"
                 + (f", {self.hours_above_range[lim][0]}-{self.hours_above_range[lim][1]} h within 2 s.e."
                    if self.hours_above_range[lim][0] != self.hours_above_range[lim][1] else "") + ")"
                 for lim in LIMITS]
        return (f"annual DGP over {n} occupied hours ({int((self.sun_seen & self.occupied).sum())} with the sun "
                f"in view): " + "; ".join(parts) + f"; EN 17037 glare protection: {self.en17037['level']}")

    def to_dict(self):
        def arr(a):
            return [None if not np.isfinite(v) else float(v) for v in np.asarray(a, float)]

        return {"observer": list(self.observer), "view_direction": list(self.view_direction),
                "occupied_hours": int(self.occupied.sum()),
                "sun_in_view_occupied_hours": int((self.sun_seen & self.occupied).sum()),
                "hours_above": {f"{k:.2f}": v for k, v in self.hours_above.items()},
                "hours_above_within_2_std_error": {f"{k:.2f}": list(v) for k, v in self.hours_above_range.items()},
                "share_of_occupied_hours_above": {f"{k:.2f}": v for k, v in self.share_above.items()},
                "en17037_glare_protection": self.en17037, "low_light_correction": self.low_light_correction,
                "weather_period": self.weather_period, "whole_year": self.whole_year, "notes": list(self.notes),
                "hourly": {"hour": arr(self.hours), "occupied": [bool(v) for v in self.occupied],
                           "dgp": arr(self.dgp), "dgp_std_error": arr(self.dgp_std_error),
                           "vertical_illuminance_lux": arr(self.vertical_illuminance),
                           "vertical_illuminance_std_error_lux": arr(self.vertical_illuminance_std_error),
                           "sun_in_view": [bool(v) for v in self.sun_seen],
                           "sun_luminance_cd_m2": arr(self.sun_luminance)}}

    def csv_text(self):
        lines = ["record,local_hour,occupied,dgp,dgp_std_error,vertical_illuminance_lux,"
                 "vertical_illuminance_std_error_lux,sun_in_view,sun_luminance_cd_m2"]
        for t in range(len(self.dgp)):
            lines.append(f"{t},{self.hours[t]:.2f},{int(self.occupied[t])},{self.dgp[t]:.4f},"
                         f"{self.dgp_std_error[t]:.2g},{self.vertical_illuminance[t]:.6g},"
                         f"{self.vertical_illuminance_std_error[t]:.3g},{int(self.sun_seen[t])},"
                         f"{self.sun_luminance[t]:.4g}")
        return "\n".join(lines) + "\n"


def class_counts(dgp, std_error, occupied):
    """({limit: hours >= limit}, {limit: (hours with DGP - 2 s.e., with DGP + 2 s.e.)}, {limit: share})
    over the occupied hours."""
    d, se = np.asarray(dgp, float)[occupied], np.asarray(std_error, float)[occupied]
    n = max(len(d), 1)
    above = {lim: int(np.sum(d >= lim)) for lim in LIMITS}
    rng = {lim: (int(np.sum(d - 2 * se >= lim)), int(np.sum(d + 2 * se >= lim))) for lim in LIMITS}
    return above, rng, {lim: above[lim] / n for lim in LIMITS}


def annual_dgp(observer, view_direction, epw_path=None, *, request, m=1, ground_reflectance=0.2,
               north_offset_deg=0.0, occupied_from=8.0, occupied_to=18.0, low_light_correction=False,
               up=(0.0, 0.0, 1.0), method="dome", partial_period=False):
    """Hourly DGP for an eye at ``observer`` (scene coordinates) looking along ``view_direction`` (module
    docstring); the request as ``annual.annual_daylight`` takes it. Returns :class:`AnnualDGPResult`."""
    from ..meter import point_meter as meter
    from . import annual, glare
    from ...radiometry.metrics import en17037

    if not isinstance(low_light_correction, (bool, np.bool_)):
        raise RadiometerError(f"low_light_correction must be True or False, got {low_light_correction!r}")
    eye, view = glare.observer_and_view(observer, view_direction, up)
    r = annual.annual_daylight([eye], [view], epw_path, request=request, m=m, ground_reflectance=ground_reflectance,
                               north_offset_deg=north_offset_deg, occupied_from=occupied_from,
                               occupied_to=occupied_to, method=method, partial_period=partial_period)
    ev = r.illuminance[:, 0]
    se_ev = r.illuminance_std_error[:, 0]  # stated at the occupied hours (0 elsewhere), as annual states it
    e_sun = r.sun_illuminance[:, 0]
    seen, lum, p = dgp_math.sun_glare_source(view, r.sun_direction, r.direct_normal_lux, np.nan_to_num(e_sun), up)
    value, se = dgp_math.hourly_dgp(ev, lum, p, vertical_illuminance_std_error=se_ev,
                                    low_light_correction=bool(low_light_correction))
    occupied = r.occupied & np.isfinite(value)
    if not occupied.any():
        raise RadiometerError("annual DGP: no occupied hour with a usable weather record")
    above, rng, share = class_counts(value, se, occupied)
    row = dataclasses.asdict(en17037.glare_protection(value[occupied]))
    model = meter.capture_model(request.scene, request.view_layer)
    n_sun = int((seen & occupied).sum())
    notes = [f"eye at ({eye[0]:g}, {eye[1]:g}, {eye[2]:g}) looking ({view[0]:.3g}, {view[1]:.3g}, {view[2]:.3g}); "
             "E_v from the daylight coefficients of a meter at the eye facing the line of sight"]
    notes += [n for n in r.notes if not n.startswith("ASE") and "sDA verdict" not in n]  # the points' metrics
    notes.append(f"DGP (Wienold & Christoffersen 2006) with the sun's disc as the one glare source at the "
                 f"{n_sun} occupied hours the sun is in the view's hemisphere and its centre ray reaches the eye "
                 f"(L = E_dn / {dgp_math.SUN_SOLID_ANGLE_SR:.3g} sr x the panes' transmittance); the simplified "
                 "DGPs = 6.22e-5 E_v + 0.184 at the other hours (Wienold 2009, imageless as Radiance/Honeybee)")
    notes.append("DGPs ignores the contrast of the sky or a bright pane seen from the eye: where no sun is seen it "
                 "is the lower envelope of DGP (a rendered view, glare --index dgp, rates such hours in full)")
    notes.append("E_v holds the sun spread over its 4 nearest sky patches (two-phase), not the disc's exact "
                 "direct part; the sun's luminance and position are exact (the SPA sun, centre ray)")
    if model.refractors:
        notes.append("transmitting objects that are not thin panes let the sun through unchanged in the sun's "
                     "glare term: " + ", ".join(name for name, _why in model.refractors))
    dim = int(np.sum(occupied & (ev < 380.0)))
    if dim:
        notes.append(f"{dim} occupied hours have E_v below 380 lx, where DGP was not fitted (it may underestimate "
                     "glare there)" + ("; the low-light correction applies" if low_light_correction else ""))
    return AnnualDGPResult(observer=tuple(map(float, eye)), view_direction=tuple(map(float, view)), dgp=value,
                           dgp_std_error=se, vertical_illuminance=ev, vertical_illuminance_std_error=se_ev,
                           sun_seen=seen, sun_luminance=lum, sun_position_index=p, occupied=occupied,
                           hours=np.asarray(r.hours, float), hours_above=above,
                           hours_above_range=rng, share_above=share, en17037=row,
                           low_light_correction=bool(low_light_correction), notes=notes,
                           weather_period=r.weather_period, whole_year=r.whole_year)



# --- View out (EN 17037): what the eyes see through the openings, from the geometry -----------------------

@dataclasses.dataclass
class ViewOutResult(AsDict):
    """EN 17037's view out from eyes (``radiometry.scene.view_out``): per eye (metres) the horizontal sight
    angle (deg), the outside distance (m; inf where nothing modelled stands in front) and the layers seen;
    ``en17037``: the criterion's row (dict; "not assessed" with its note where the geometry cannot tell);
    ``openings``: how many were found in the opaque surfaces."""

    eyes: np.ndarray
    horizontal_sight_angle_deg: np.ndarray
    outside_distance_m: np.ndarray
    layers: list
    en17037: dict
    openings: int
    notes: list


def view_out(eyes, *, request, model=None):
    """EN 17037 view out from ``eyes`` (3 numbers or (N, 3), scene coordinates; the assessed points of the
    utilised area at eye height). Geometry only: nothing is rendered. Returns :class:`ViewOutResult`."""
    from ...radiometry.metrics import en17037
    from ...radiometry.scene import view_out as geometry_view
    from ...radiometry.scene import scene_model
    from ...radiometry.skies import sky_aperture
    from ..meter import point_meter as meter
    from .sky_component import opaque_mask

    pts = np.atleast_2d(np.asarray(eyes, float))
    if pts.ndim != 2 or pts.shape[1] != 3 or not len(pts) or not np.all(np.isfinite(pts)):
        raise RadiometerError(f"view out needs eyes as 3 finite numbers or (N, 3), got shape {pts.shape}")
    model = model or meter.capture_model(request.scene, request.view_layer)
    eyes_m = request.to_metres(pts)
    g = model.geometry
    tris = g.triangles[opaque_mask(model)] if g.count else np.zeros((0, 3, 3))
    lo, hi = g.bounds() if g.count else (np.zeros(3), np.zeros(3))
    tol = 10.0 * scene_model.length_tolerance(np.r_[lo, hi, eyes_m.ravel()])
    openings = [poly for poly, _n in sky_aperture.find_apertures(tris, tol)]
    parts = geometry_view.scene_parts(tris, openings, tol)     # the triangles' parts, once for both below
    views = geometry_view.eye_views(eyes_m, openings, tris, tol=tol, parts=parts)
    notes = [f"{len(openings)} opening(s) in the opaque surfaces; rays every {geometry_view.STEP_DEG:g} deg in "
             f"azimuth, {geometry_view.ROWS} rows in elevation; see-through surfaces (panes) are looked through"]
    why = ""
    if g.unmodelled:
        why = f"geometry without triangles ({', '.join(g.unmodelled[:3])}) may hide or open the view"
    elif not geometry_view.surroundings_modelled(tris, openings, any("landscape" in v.layers for v in views), tol,
                                                 parts=parts):
        why = ("the scene models nothing outside its openings but flat ground: no building, terrain or tree to "
               "judge the landscape layer and the outside distance against")
    if why:
        row = dataclasses.asdict(en17037.not_assessed("view out", why))
        notes.append("view out not assessed: " + why)
    else:
        row = dataclasses.asdict(en17037.view_out_over_points([v.horizontal_sight_angle_deg for v in views],
                                                              [v.outside_distance_m for v in views],
                                                              [v.layer_score() for v in views]))
        blind = sum(1 for v in views if not v.rays_out)
        if blind:
            notes.append(f"{blind} of {len(views)} eyes see no opening")
    return ViewOutResult(eyes=eyes_m, horizontal_sight_angle_deg=np.array([v.horizontal_sight_angle_deg for v in views]),
                         outside_distance_m=np.array([v.outside_distance_m for v in views]),
                         layers=[list(v.layers) for v in views], en17037=row, openings=len(openings), notes=notes)

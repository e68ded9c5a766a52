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


def glare_dgp(observer, view_direction, *, scene=None, quality="preview", resolution=128, up=(0.0, 0.0, 1.0),
              threshold_cd_m2=dgp_math.THRESHOLD_CD_M2, threshold_factor=None, low_light_correction=False,
              hdr_path=None, max_spp=None):
    """DGP for an eye at ``observer`` (scene coordinates) looking along ``view_direction``.

    ``resolution``: the fisheye's side in px (16..512). ``threshold_cd_m2`` / ``threshold_factor``:
    glare-source detection (``radiometry.glare_dgp.find_glare_sources``). ``hdr_path``: also write
    the fisheye as a Radiance HDR (angular fisheye, luminance / 179 in R, G and B, its VIEW in the
    header) for evalglare. ``max_spp``: cap on the samples per pixel of one render (None: :data:`MAX_SPP`
    for the quality). Returns :class:`DaylightGlareResult`.
    """
    import bpy

    from . import glare, luminance_image
    from ..meter import point_meter as meter
    from ..blender import scene_guard

    scene = scene or bpy.context.scene
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
        img = luminance_image.render_luminance(scene=scene, camera=cam, resolution=(n, n), quality=quality,
                                               max_spp=max_spp or MAX_SPP.get(quality, 256))
    dirs, omega, valid = dgp_math.angular_fisheye(n, n, view, up)
    lum = np.where(valid, img.luminance, 0.0)
    if not np.all(np.isfinite(lum)):
        raise RadiometerError("the fisheye picture has NaN or infinite pixels (a light's power, a texture or the "
                              "world is not finite): no DGP")
    ev_meter = meter.measure_illuminance(eye_scene, view, scene=scene, quality=quality)
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

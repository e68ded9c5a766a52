"""Camera-based readings: the spot luminance meter and the panoramic radiance map.

Both render with a temporary camera inside ``scene_guard.preserved_scene`` (the user's camera,
settings and data-blocks come back afterwards) and read 32-bit EXR (never half floats, which
overflow at 65504). Delta lights (point/spot of radius 0, sun of angle 0) are invisible to camera
rays: a camera reading sees surfaces and extended lights only, as a real luminance meter would.
"""

import dataclasses
import math
import os
import shutil
import time

import bpy
import numpy as np

from ...radiometry.skies import environment
from ...errors import RadiometerError
from ...radiometry.sampling import allocation
from ...readings import LuminanceReading
from ..blender import exr, scene_guard
from . import point_meter as meter
from ..render import render_settings
from ..render.rounds import RenderRounds
from ..blender.temporary_scene import scratch_folder

# Panorama orientation: local +Y (image up) -> world +Z, local +Z (image centre) -> world -Y.
_PANO_EULER = (math.pi / 2, 0.0, 0.0)
_PANO_ROTATION = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


@dataclasses.dataclass
class RadianceMap:
    path: str
    width: int
    height: int
    irradiance_rgb: tuple  # for the +Z normal, W/m^2
    irradiance: float
    illuminance: float
    efficacy: float
    colour_space: str
    rel_std_error: float = math.nan
    method: str = "render"
    samples: int = 0
    seconds: float = 0.0
    exact: bool = False
    notes: list = dataclasses.field(default_factory=list)
    quantity: str = "radiance_map"

    def to_dict(self):
        return dataclasses.asdict(self)

    def irradiance_for(self, normal):
        """E (W/m^2, RGB) on a surface facing ``normal`` (world), from the stored map."""
        return environment.irradiance(exr.read_rgb(self.path), normal, _PANO_ROTATION)[0]


def default_map_path(name):
    """Where a meter's radiance map goes: the extension's user folder, else a private (0700)
    temporary folder of this process; the file name is readable and distinct per meter name."""
    from ... import outputs

    return os.path.join(outputs.user_folder("radiance_maps"), f"{outputs.file_stem(name)}.exr")


def _temp_camera(scene, location_scene, rotation_quat=None, euler=None):
    cam_data = bpy.data.cameras.new("radiometer_camera")
    cam = bpy.data.objects.new("radiometer_camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = tuple(location_scene)
    if rotation_quat is not None:
        cam.rotation_mode = "QUATERNION"
        cam.rotation_quaternion = rotation_quat
    else:
        cam.rotation_euler = euler
    scene.camera = cam
    cam_data.clip_start = 1e-6
    cam_data.clip_end = 1e12
    return cam


def render_exr(scene, folder, name, width, height, *, compositing=False):
    """Render ``scene`` from its camera at ``width`` x ``height`` px into ``folder``/``name``.exr (32-bit
    float RGBA: never half floats, which overflow at 65504) and read it back as (H, W, 3), top row first.
    ``compositing``: write the compositor's output (``luminance_image``'s light passes) instead of the
    render layer. The one temporary render set-up of every camera reading; call it inside the caller's
    ``scene_guard.preserved_scene``, which restores the render settings it changes."""
    return exr.read_rgb(_render_file(scene, folder, name, width, height, compositing=compositing))


def render_multilayer_exr(scene, folder, name, width, height):
    """As :func:`render_exr`, but every pass of the view layer (light groups included) goes into one multilayer
    EXR, parts named "<view layer>.<pass>", channels "<part>.R" ...; returns its path (the caller reads it)."""
    return _render_file(scene, folder, name, width, height, multilayer=True)


def _render_file(scene, folder, name, width, height, *, compositing=False, multilayer=False):
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = int(width), int(height), 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.use_compositing = bool(compositing)
    r.use_sequencer = False
    r.use_single_layer = True
    r.use_file_extension = True
    ims = r.image_settings
    if hasattr(ims, "media_type"):
        ims.media_type = "MULTI_LAYER_IMAGE" if multilayer else "IMAGE"
    ims.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    ims.color_depth = "32"
    if multilayer:
        ims.exr_codec = "ZIP"
    else:
        ims.color_mode = "RGBA"
    path = os.path.join(folder, name)
    r.filepath = path
    result = bpy.ops.render.render(write_still=True, scene=scene.name)
    if result != {"FINISHED"}:
        raise RadiometerError(f"Cycles render did not finish ({result})")
    return path + ".exr"


#: Largest radiance-map height (px; the width is twice it): 4096 x 8192 float RGBA is 512 MB.
MAX_MAP_HEIGHT = 4096

#: Independent renders per round of a luminance reading (batch means need a few).
RENDERS_PER_ROUND = 4


def prepare_render(scene, preset, snapshot):
    """Settings and visibility for a camera reading of ``scene`` (restored by ``snapshot``); the record."""
    # Blender hides lights from camera rays by default (visible_camera False). A luminance meter
    # or a radiance probe must see the light sources' surfaces, so they are shown for the render
    # and restored afterwards by the snapshot: every light OBJECT that renders, including those
    # only seen through collection instances or geometry nodes (their source objects).
    from . import point_meter as meter
    from ..capture import scene_capture

    model = meter.capture_model(scene)
    found = scene_capture.source_objects(light.source_id for light in model.lights)  # by identity, not name
    for obj in sorted(found.values(), key=lambda ob: ob.name):
        if obj.type == "LIGHT" and not obj.visible_camera:
            snapshot.remember(obj, "visible_camera")
            obj.visible_camera = True
    record = render_settings.apply(scene, samples=preset["samples"], bounces=preset["bounces"], needs=model.needs,
                                   snapshot=snapshot)
    if model.needs.get("thin_panes"):  # issue 18: planar panes render as thin glass (sun patches converge)
        from ..capture import glass

        record = dict(record, thin_panes=glass.swap_panes(snapshot, model.needs["thin_panes"]))
    return record


def measure_luminance(location, direction, *, request, acceptance_deg=1.0, resolution=24, max_renders=64):
    """Average radiance in a cone of full angle ``acceptance_deg`` around ``direction``. The request
    (``measure.blender.request``): the scene, ``quality`` (None: "standard"), ``target_rel_error``,
    progress, cancel and ``seed`` (the first render's Cycles seed: render k takes seed + k)."""
    from mathutils import Vector

    scene, target_rel_error, seed = request.scene, request.target_rel_error, request.seed
    progress, cancelled = request.progress, request.cancelled
    points, _ = meter.as_points(location)
    d = meter.as_directions(direction, 1, name="direction")[0]
    acceptance_deg = float(acceptance_deg)
    if not (0.0 < acceptance_deg < 120.0) or not math.isfinite(acceptance_deg):
        raise RadiometerError(f"acceptance angle must be in (0, 120) degrees, got {acceptance_deg}")
    preset = request.preset()
    space, weights, efficacy = request.photometry
    half = math.radians(acceptance_deg) / 2
    # Pixel weights: a perspective pixel subtends a solid angle proportional to cos^3 of its
    # angle from the axis; pixels outside the acceptance cone get weight 0.
    t = (np.arange(resolution) + 0.5) / resolution * 2 - 1
    x, y = np.meshgrid(t, t)
    off_axis = np.arctan(np.hypot(x, y) * math.tan(half))
    w = np.where(off_axis <= half, np.cos(off_axis) ** 3, 0.0)
    w /= w.sum()
    unit_area = request.unit_area  # Cycles renders per scene-unit^2
    folder = scratch_folder()
    started = time.perf_counter()
    target = float(target_rel_error) if target_rel_error is not None else float(preset["target"])
    # Rounds of RENDERS_PER_ROUND independent renders (new seeds) at one spp each; the spp grows
    # from round to round as the error estimate asks (capped at 1024: float32 accumulation), and
    # rounds combine weighted by their samples, each with its own batch-means variance
    # (radiometry.sampling.allocation.MeterTally: Cycles' QMC converges faster than 1/N, so per-sample
    # variances are not pooled across spp).
    tally = allocation.MeterTally(1)
    spp, record = 64, None
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            record = prepare_render(scene, dict(preset, samples=spp), snapshot)
            cam = _temp_camera(scene, points[0], rotation_quat=Vector(d).to_track_quat("-Z", "Y"))
            cam.data.type = "PERSP"
            cam.data.sensor_fit = "HORIZONTAL"
            cam.data.angle = 2 * half
            shown = None if progress is None else (lambda done, total: progress(min(done, total), total))
            rounds = RenderRounds(scene, cancelled=cancelled, progress=shown, total_of=lambda _done: max_renders,
                                  seed_of=lambda k: int(seed) + k)

            def render(k):
                img = render_exr(scene, folder, f"lum{k}", resolution, resolution) / unit_area
                return np.einsum("hw,hwc->c", w, img)

            while True:
                batch = rounds.round(RENDERS_PER_ROUND, spp, render)
                k = rounds.renders
                tally.add(np.zeros(len(batch), int), spp, batch @ weights, batch)
                rel = float(tally.rel_std_error()[0])
                if rel <= target or k >= max_renders:
                    break
                # Texel-variance model with the Monte Carlo rate (conservative for QMC).
                spp = int(min(1024, max(spp, spp * (rel / target) ** 2 * 1.3)))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    mean = tally.mean_rgb[0]
    radiance = float(tally.mean[0])
    # A rendered value is known no better than Cycles' float32 rounding (meter.FLOAT32_FLOOR; issue 32:
    # identical renders of a uniform emitter gave s.e. 0).
    se = math.hypot(float(tally.std_error[0]), meter.FLOAT32_FLOOR * abs(radiance))
    notes = [f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}",
             f"perspective camera, cone {acceptance_deg:g} deg full angle, cos^3 pixel weights, "
             f"{k} independent renders in {len(tally.rounds)} round(s) (batch means), target {100 * target:g} %",
             "delta lights (radius 0) are invisible to camera rays and cannot be seen by a luminance meter",
             "light objects are made visible to camera rays during the render (Blender hides them by default)"]
    if se > target * abs(radiance):
        notes.append(f"target {100 * target:g} % NOT reached in {max_renders} renders")
    return LuminanceReading(
        radiance_rgb=tuple(map(float, mean)), radiance=radiance, luminance=efficacy * radiance,
        rel_std_error=(se / abs(radiance)) if radiance else (0.0 if se == 0 else math.inf),
        method="render", samples=int(tally.n[0]), seconds=time.perf_counter() - started,
        efficacy=efficacy, colour_space=space, acceptance_deg=acceptance_deg, location=tuple(points[0]),
        direction=tuple(d), notes=notes, render_settings=record, target_rel_error=target,
        std_error_rgb=tuple(float(math.hypot(e, meter.FLOAT32_FLOOR * abs(m)))
                            for e, m in zip(tally.std_error_rgb[0], mean)))


def capture_radiance_map(location, path, *, request, resolution=128):
    """Render a 32-bit equirectangular EXR (width = 2 x ``resolution``) of incident radiance at the
    request's scene and ``quality`` (None: "standard")."""
    scene = request.scene
    points, _ = meter.as_points(location)
    resolution = int(resolution)
    if not 4 <= resolution <= MAX_MAP_HEIGHT:  # 10**9 would render for ever and ignore Ctrl-C
        raise RadiometerError(f"radiance map height must be 4 to {MAX_MAP_HEIGHT} px, got {resolution}")
    if not str(path).strip():
        raise RadiometerError("radiance map path is empty: name an .exr file")
    path = os.path.abspath(bpy.path.abspath(path) if path.startswith("//") else path)
    if not os.path.isdir(os.path.dirname(path)):
        raise RadiometerError(f"cannot write {path}: its folder does not exist")
    preset = request.preset()
    space, weights, efficacy = request.photometry
    folder = scratch_folder()
    started = time.perf_counter()
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            record = prepare_render(scene, preset, snapshot)
            cam = _temp_camera(scene, points[0], euler=_PANO_EULER)
            cam.data.type = "PANO"
            cam.data.panorama_type = "EQUIRECTANGULAR"
            img = render_exr(scene, folder, "map", 2 * resolution, resolution)
            img /= request.unit_area  # the file keeps Cycles' own values
        path = path if path.endswith(".exr") else path + ".exr"
        if not np.all(np.isfinite(img)):
            raise RadiometerError("the radiance map has NaN or infinite pixels (a light's power, a texture or the "
                                  "world of the scene is not finite); no map written")
        from ...outputs import atomic_output

        with atomic_output(path) as tmp:  # whole or not at all, never through a planted link
            shutil.copyfile(os.path.join(folder, "map.exr"), tmp)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    e_rgb = environment.irradiance(img, (0.0, 0.0, 1.0), _PANO_ROTATION)[0]  # exact for the pixels
    e = float(e_rgb @ weights)
    notes = [f"equirectangular {2 * resolution}x{resolution} px, 32-bit EXR at {path}",
             "irradiance for +Z integrates L cos(theta) d omega over the map (the lecture's irradiance map)",
             "CANNOT see delta lights (point/spot of radius 0, sun of angle 0): camera rays never hit them",
             f"render settings: {record['samples']} samples/pixel, no error estimate for single maps"]
    return RadianceMap(path=path, width=2 * resolution, height=resolution, irradiance_rgb=tuple(map(float, e_rgb)),
                       irradiance=e, illuminance=efficacy * e, efficacy=efficacy, colour_space=space,
                       samples=int(preset["samples"]), seconds=time.perf_counter() - started, notes=notes)

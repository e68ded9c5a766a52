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
import tempfile
import time

import bpy
import numpy as np

from .. import envmap
from .. import quality as quality_presets
from ..errors import MeasurementCancelled, RadiometerError
from ..radiometry import stats
from ..readings import LuminanceReading
from . import exr, meter, render_settings, scene_guard

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
        return envmap.irradiance_from_map(exr.read_rgb(self.path), normal, _PANO_ROTATION)


def default_map_path(name):
    folder = os.path.join(tempfile.gettempdir(), "radiometer")
    try:
        folder = bpy.utils.extension_path_user(__package__.rsplit(".", 1)[0], path="radiance_maps", create=True)
    except (ValueError, AttributeError, RuntimeError):
        os.makedirs(folder, exist_ok=True)
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in name)
    return os.path.join(folder, f"{safe}.exr")


def _scratch_folder():
    try:
        return tempfile.mkdtemp(prefix="radiometer_")
    except OSError as exc:
        raise RadiometerError(f"cannot create a temporary folder for the render ({exc.strerror}: "
                              f"{tempfile.gettempdir()}); set TMPDIR to a writable folder") from None


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


def _render_exr(scene, folder, name, width, height):
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = int(width), int(height), 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.use_compositing = False
    r.use_sequencer = False
    r.use_single_layer = True
    r.use_file_extension = True
    ims = r.image_settings
    if hasattr(ims, "media_type"):
        ims.media_type = "IMAGE"
    ims.file_format = "OPEN_EXR"
    ims.color_depth = "32"
    ims.color_mode = "RGBA"
    path = os.path.join(folder, name)
    r.filepath = path
    result = bpy.ops.render.render(write_still=True, scene=scene.name)
    if result != {"FINISHED"}:
        raise RadiometerError(f"Cycles render did not finish ({result})")
    return exr.read_rgb(path + ".exr")


def _prepare(scene, preset, snapshot):
    # Blender hides lights from camera rays by default (visible_camera False). A luminance meter
    # or a radiance probe must see the light sources' surfaces, so they are shown for the render
    # and restored afterwards by the snapshot.
    for obj in scene.objects:
        if obj.type == "LIGHT" and not obj.visible_camera:
            snapshot.remember(obj, "visible_camera")
            obj.visible_camera = True
    depsgraph = bpy.context.evaluated_depsgraph_get()
    needs = render_settings.scene_needs(scene, depsgraph)
    return render_settings.apply(scene, samples=preset["samples"], bounces=preset["bounces"], needs=needs,
                                 snapshot=snapshot)


def measure_luminance(location, direction, *, acceptance_deg=1.0, scene=None, quality="standard",
                      target_rel_error=None, progress=None, cancelled=None, resolution=24, max_renders=64):
    """Average radiance in a cone of full angle ``acceptance_deg`` around ``direction``."""
    from mathutils import Vector

    scene = scene or bpy.context.scene
    points, _ = meter.as_points(location)
    d = meter.as_directions(direction, 1, name="direction")[0]
    acceptance_deg = float(acceptance_deg)
    if not (0.0 < acceptance_deg < 120.0) or not math.isfinite(acceptance_deg):
        raise RadiometerError(f"acceptance angle must be in (0, 120) degrees, got {acceptance_deg}")
    preset = quality_presets.preset(quality)
    space, weights, efficacy = meter.scene_photometry(scene)
    half = math.radians(acceptance_deg) / 2
    # Pixel weights: a perspective pixel subtends a solid angle proportional to cos^3 of its
    # angle from the axis; pixels outside the acceptance cone get weight 0.
    t = (np.arange(resolution) + 0.5) / resolution * 2 - 1
    x, y = np.meshgrid(t, t)
    off_axis = np.arctan(np.hypot(x, y) * math.tan(half))
    w = np.where(off_axis <= half, np.cos(off_axis) ** 3, 0.0)
    w /= w.sum()
    unit_area = scene.unit_settings.scale_length ** 2  # Cycles renders per scene-unit^2
    folder = _scratch_folder()
    started = time.perf_counter()
    renders = max(4, preset["bakes"] * 4)
    # A camera pixel averages many paths already: a quarter of the sensor budget per render.
    samples_each = max(1, preset["samples"] * preset["texels"] ** 2 // 16)
    estimates = []
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            record = _prepare(scene, dict(preset, samples=samples_each), snapshot)
            cam = _temp_camera(scene, points[0], rotation_quat=Vector(d).to_track_quat("-Z", "Y"))
            cam.data.type = "PERSP"
            cam.data.sensor_fit = "HORIZONTAL"
            cam.data.angle = 2 * half
            k = 0
            while True:
                if cancelled is not None and cancelled():
                    raise MeasurementCancelled("measurement cancelled; the scene was restored")
                scene.cycles.seed = k
                img = _render_exr(scene, folder, f"lum{k}", resolution, resolution) / unit_area
                estimates.append(np.einsum("hw,hwc->c", w, img))
                k += 1
                if progress is not None:
                    progress(k, renders)
                if k < renders:
                    continue
                if target_rel_error is None or k >= max_renders:
                    break
                y_est = np.array(estimates) @ weights
                if stats.t_half_width_95(y_est) <= target_rel_error * abs(y_est.mean()):
                    break
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    est = np.array(estimates)
    mean = est.mean(axis=0)
    y = est @ weights
    radiance = float(mean @ weights)
    se = float(stats.batch_mean(y)[1])
    notes = [f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}",
             f"perspective camera, cone {acceptance_deg:g} deg full angle, cos^3 pixel weights, "
             f"{len(y)} independent renders (batch means)",
             "delta lights (radius 0) are invisible to camera rays and cannot be seen by a luminance meter",
             "light objects are made visible to camera rays during the render (Blender hides them by default)"]
    return LuminanceReading(
        radiance_rgb=tuple(map(float, mean)), radiance=radiance, luminance=efficacy * radiance,
        rel_std_error=(se / abs(radiance)) if radiance else (0.0 if se == 0 else math.inf),
        method="render", samples=int(samples_each * len(y)), seconds=time.perf_counter() - started,
        efficacy=efficacy, colour_space=space, acceptance_deg=acceptance_deg, location=tuple(points[0]),
        direction=tuple(d), notes=notes, render_settings=record)


def capture_radiance_map(location, path, *, resolution=128, scene=None, quality="standard"):
    """Render a 32-bit equirectangular EXR (width = 2 x ``resolution``) of incident radiance."""
    scene = scene or bpy.context.scene
    points, _ = meter.as_points(location)
    resolution = int(resolution)
    if resolution < 4:
        raise RadiometerError(f"radiance map height must be at least 4 px, got {resolution}")
    path = os.path.abspath(bpy.path.abspath(path) if path.startswith("//") else path)
    if not os.path.isdir(os.path.dirname(path)):
        raise RadiometerError(f"cannot write {path}: its folder does not exist")
    preset = quality_presets.preset(quality)
    space, weights, efficacy = meter.scene_photometry(scene)
    folder = _scratch_folder()
    started = time.perf_counter()
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            record = _prepare(scene, preset, snapshot)
            cam = _temp_camera(scene, points[0], euler=_PANO_EULER)
            cam.data.type = "PANO"
            cam.data.panorama_type = "EQUIRECTANGULAR"
            img = _render_exr(scene, folder, "map", 2 * resolution, resolution)
            img /= scene.unit_settings.scale_length ** 2  # the file keeps Cycles' own values
        shutil.copyfile(os.path.join(folder, "map.exr"), path if path.endswith(".exr") else path + ".exr")
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    path = path if path.endswith(".exr") else path + ".exr"
    e_rgb = envmap.irradiance_from_map(img, (0.0, 0.0, 1.0), _PANO_ROTATION)
    e = float(e_rgb @ weights)
    notes = [f"equirectangular {2 * resolution}x{resolution} px, 32-bit EXR at {path}",
             "irradiance for +Z integrates L cos(theta) d omega over the map (the lecture's irradiance map)",
             "CANNOT see delta lights (point/spot of radius 0, sun of angle 0): camera rays never hit them",
             f"render settings: {record['samples']} samples/pixel, no error estimate for single maps"]
    return RadianceMap(path=path, width=2 * resolution, height=resolution, irradiance_rgb=tuple(map(float, e_rgb)),
                       irradiance=e, illuminance=efficacy * e, efficacy=efficacy, colour_space=space,
                       samples=int(preset["samples"]), seconds=time.perf_counter() - started, notes=notes)

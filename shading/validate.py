"""Check a realised BRDF by rendering it: the reflection equation with one point light.

A flat patch (normal +Z, tangent +X, so world = BRDF local frame) is seen by an orthographic camera
from direction wo and lit by a point light of radius 0 and power P at distance d in direction wi.
The light's radiant intensity is I = P / (4 pi) W/sr (measured, docs/FACTS.md), so the patch
receives E_i = I cos(theta_i) / d^2 W/m^2, and with direct light only the rendered radiance is

    L_r = f(wi, wo) E_i     (lecture: L_r = L_i f cos(theta_i) d omega_i, for a delta source),

so f_rendered = L_r / E_i in 1/sr. Everything happens in a scratch scene that is removed afterwards
together with every data-block created here; the user's scenes are never touched.

References
----------
Nicodemus et al. (1977), NBS Monograph 160: BRDF definition f = dL_r / dE_i.
Hanrahan, CS348B lecture 10 (2009): reflection equation (shared/seed/radiometry-lecture.md).
"""

import math
import os
import tempfile
from dataclasses import dataclass

import numpy as np

PATCH_HALF_SIZE = 0.01  # m
LIGHT_DISTANCE = 10.0  # m; the patch subtends 1e-3 rad, so wi is constant across it
CAMERA_DISTANCE = 1.0  # m
ORTHO_SCALE = 1e-4  # m; the camera sees only the middle of the patch even at 80 deg
RESOLUTION = 4  # pixels per side


@dataclass
class RenderComparison:
    wi: np.ndarray  # (N, 3)
    wo: np.ndarray  # (N, 3)
    rendered: np.ndarray  # (N, 3) f from the render, 1/sr
    expected: np.ndarray  # (N, 3) f from the numpy model, 1/sr

    @property
    def rel_diff(self):
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(self.rendered - self.expected) / np.abs(self.expected)

    @property
    def max_rel_diff(self):
        mask = np.abs(self.expected) > 1e-6 * np.max(np.abs(self.expected))
        return float(np.max(self.rel_diff[mask])) if mask.any() else 0.0

    def to_dict(self):
        return {"wi": self.wi.tolist(), "wo": self.wo.tolist(), "rendered": self.rendered.tolist(),
                "expected": self.expected.tolist(), "max_rel_diff": self.max_rel_diff}


def direction(theta, phi):
    """Unit vector (local frame) at polar angle theta and azimuth phi, both in radians."""
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)])


def _read_exr(path):
    import OpenEXR

    with OpenEXR.File(path) as f:
        channels = f.channels()
        key = "RGBA" if "RGBA" in channels else ("RGB" if "RGB" in channels else None)
        if key is not None:
            px = np.array(channels[key].pixels, dtype=np.float64)[..., :3]
        else:
            px = np.stack([np.array(channels[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)
    return px


def render_f(material, wi, wo, *, osl=False, samples=2, light_power=None):
    """Render ``material`` once per direction pair; return f = L_r / E_i in 1/sr, shape (N, 3).

    Parameters
    ----------
    material : bpy.types.Material
    wi, wo : array_like (N, 3)
        Unit directions (local frame = world frame of the patch) to the light and to the camera.
    osl : bool
        Render with Open Shading Language (needed for Script nodes), in the scratch scene only.
    samples : int
        Samples per pixel; a delta light with direct lighting only is noise-free at 1.
    """
    import bpy
    from mathutils import Vector

    wi = np.atleast_2d(np.asarray(wi, dtype=float))
    wo = np.atleast_2d(np.asarray(wo, dtype=float))
    power = light_power if light_power is not None else 4.0 * math.pi * LIGHT_DISTANCE ** 2  # I = d^2 W/sr
    intensity = power / (4.0 * math.pi)

    had_render_result = "Render Result" in bpy.data.images
    created = []
    scene = bpy.data.scenes.new("Radiometer BRDF validation")
    tmpdir = tempfile.mkdtemp(prefix="radiometer_brdf_")
    try:
        h = PATCH_HALF_SIZE
        mesh = bpy.data.meshes.new("Radiometer validation patch")
        created.append(mesh)
        mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(material)
        patch = bpy.data.objects.new("Radiometer validation patch", mesh)
        created.append(patch)
        scene.collection.objects.link(patch)

        cam_data = bpy.data.cameras.new("Radiometer validation camera")
        created.append(cam_data)
        cam_data.type = "ORTHO"
        cam_data.ortho_scale = ORTHO_SCALE
        cam_data.clip_start = 0.1 * CAMERA_DISTANCE
        cam_data.clip_end = 10.0 * CAMERA_DISTANCE
        cam = bpy.data.objects.new("Radiometer validation camera", cam_data)
        created.append(cam)
        scene.collection.objects.link(cam)
        scene.camera = cam

        light_data = bpy.data.lights.new("Radiometer validation light", "POINT")
        created.append(light_data)
        light_data.energy = power
        light_data.color = (1.0, 1.0, 1.0)
        light_data.shadow_soft_size = 0.0
        light = bpy.data.objects.new("Radiometer validation light", light_data)
        created.append(light)
        scene.collection.objects.link(light)

        r = scene.render
        r.engine = "CYCLES"
        r.resolution_x = r.resolution_y = RESOLUTION
        r.resolution_percentage = 100
        r.film_transparent = False
        r.filter_size = 0.01
        r.use_persistent_data = False
        r.image_settings.file_format = "OPEN_EXR"
        r.image_settings.color_depth = "32"
        scene.view_settings.view_transform = "Standard"
        scene.view_settings.look = "None"
        scene.view_settings.exposure = 0.0
        scene.view_settings.gamma = 1.0
        c = scene.cycles
        c.device = "CPU"
        c.shading_system = bool(osl)
        c.samples = samples
        c.use_adaptive_sampling = False
        c.use_denoising = False
        c.max_bounces = 0  # direct light only: the reflection equation with one delta source
        c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.volume_bounces = 0
        c.transparent_max_bounces = 0
        c.light_sampling_threshold = 0.0
        c.sample_clamp_direct = 0.0
        c.sample_clamp_indirect = 0.0
        c.blur_glossy = 0.0
        c.caustics_reflective = True
        c.caustics_refractive = True
        c.filter_width = 0.01
        c.film_exposure = 1.0
        c.seed = 0
        scene.world = None  # black background, no environment light

        out = np.zeros((len(wi), 3))
        for i, (a, b) in enumerate(zip(wi, wo)):
            cam.location = Vector(tuple(b * CAMERA_DISTANCE))
            up = "Y" if abs(b[2]) < 0.999 or True else "X"
            cam.rotation_euler = (-Vector(tuple(b))).to_track_quat("-Z", up).to_euler()
            light.location = Vector(tuple(a * LIGHT_DISTANCE))
            path = os.path.join(tmpdir, f"sample_{i}.exr")
            r.filepath = path
            bpy.ops.render.render(write_still=True, scene=scene.name)
            radiance = _read_exr(path).reshape(-1, 3).mean(axis=0)  # W/(m^2 sr)
            irradiance = intensity * a[2] / LIGHT_DISTANCE ** 2  # W/m^2
            out[i] = radiance / irradiance
        return out
    finally:
        bpy.data.scenes.remove(scene)
        for block in reversed(created):
            collection = {
                bpy.types.Object: bpy.data.objects, bpy.types.Mesh: bpy.data.meshes,
                bpy.types.Camera: bpy.data.cameras, bpy.types.PointLight: bpy.data.lights,
            }.get(type(block))
            if collection is None:
                collection = bpy.data.lights if isinstance(block, bpy.types.Light) else None
            if collection is not None:
                collection.remove(block)
        if not had_render_result and "Render Result" in bpy.data.images:
            bpy.data.images.remove(bpy.data.images["Render Result"])
        for name in os.listdir(tmpdir):
            os.remove(os.path.join(tmpdir, name))
        os.rmdir(tmpdir)


DEFAULT_CONFIGS = [  # (theta_i, phi_i, theta_o, phi_o) in degrees
    (0, 0, 0, 0),
    (30, 0, 30, 180),
    (45, 0, 45, 180),
    (45, 0, 30, 90),
    (60, 0, 20, 200),
    (20, 0, 60, 150),
    (70, 0, 70, 180),
    (40, 90, 40, 270),
]


def config_directions(configs=DEFAULT_CONFIGS):
    """(wi, wo) arrays (N, 3) from (theta_i, phi_i, theta_o, phi_o) tuples in degrees."""
    rad = np.radians(np.asarray(configs, dtype=float))
    wi = np.array([direction(t, p) for t, p in rad[:, :2]])
    wo = np.array([direction(t, p) for t, p in rad[:, 2:]])
    return wi, wo


def validate_material(material, expected_f, configs=DEFAULT_CONFIGS, *, osl=False, samples=2):
    """Render ``material`` at ``configs`` and compare with ``expected_f(wi, wo)`` -> (N, 3) 1/sr."""
    wi, wo = config_directions(configs)
    rendered = render_f(material, wi, wo, osl=osl, samples=samples)
    return RenderComparison(wi, wo, rendered, np.asarray(expected_f(wi, wo), dtype=float))

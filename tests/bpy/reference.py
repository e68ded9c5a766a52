"""Independent reference irradiance for tests: render a tiny white Lambertian patch with Cycles.

This file deliberately imports nothing from Radiometer (no ``radiometer.measure``, no
``radiometer.api``, not even ``radiometer.compat``): it is the yardstick the meter is checked against,
so it must not share the meter's code or its bugs.

Method (the project's agreed reference, see docs/FACTS.md):

* A sensor of size ``s`` (about 1e-4 of the scene's extent; one triangle that contains the square
  [-s/2, s/2]^2 around ``point``, see ``_add_patch`` for why not a quad) is placed at ``point`` with
  its front side facing ``normal``. Its material is a Diffuse BSDF of colour 1 and roughness 0 (pure
  Lambert, albedo 1), so the radiance it reflects towards any direction is L = E / pi, where E is the
  irradiance on its front side.
* The patch is visible to CAMERA rays only (``visible_diffuse/glossy/transmission/volume_scatter/
  shadow = False``): no other ray can hit it, so it neither casts shadows nor reflects light into the
  scene. The scene is measured as it is.
* An ORTHOGRAPHIC camera looks straight down -normal at the patch from a tiny distance in front of it,
  with ``ortho_scale == s`` so every pixel centre lies on the patch, and the box pixel filter is tiny
  so every camera ray goes through its pixel centre.
* Cycles CPU renders it; E = pi * mean pixel value (RGB, W per scene-unit^2). Cycles ignores
  ``scene.unit_settings.scale_length`` (FACTS.md), so the SI value is E / scale_length^2.

The patch's normal is stored as a Blender 5 "free" custom normal (float vector attribute
``custom_normal``) with smooth shading: Cycles would otherwise derive the shading normal from the
float32 corner positions, which a few metres from the origin are quantised to ~2e-7 m, i.e. a normal
error of ~1e-3 rad for a 2e-4 m patch (a 1e-3 relative error at 45 degrees incidence).

Uncertainty: the TABULATED_SOBOL pattern with its scrambling distance just below 1 gives every pixel the
render's table shifted by its own uniform Cranley-Patterson rotation, so the pixel means of one render are
independent, identically distributed and unbiased estimates of the same number (all pixels see the same
irradiance up to the patch's tiny size). The standard error is the batch-means estimate std(pixel means)
/ sqrt(number of pixels), pooled over renders with independent seeds. Cycles' default (distance 1) is
NOT that: each pixel then draws one of the table's fixed patterns, and the mean over any number of pixels
converges to those patterns' mean, not to the integral; where light comes by a rare path the difference
shows (2026-12-06, the rare-hit bench's spot on a rough metal floor: 657.8 lx +- 0.1 % with distance 1 for
seeds 7 and 11 alike, 653.4 lx +- 0.1 % rotated, 653.0 lx +- 0.1 % with the BLUE_NOISE pattern, a
different sampler; bench/coverage_rare_hits.md). (The blue-noise patterns correlate neighbouring pixels,
which would make the batch-means estimate wrong, so they serve only as that cross-check.)

Light linking and per-light settings are the user's. Note that the sensor is a new object in no
linking collection, so it receives what an unlinked object receives (a light whose receiver
collection INCLUDEs only certain objects does not light it).

Everything added (camera, mesh, material, images, temp files) is removed in ``finally`` and every
scene setting that is changed is put back.
"""

import math
import os
import tempfile
import time

import numpy as np

import bpy
import OpenEXR
from mathutils import Matrix, Vector

from radiometer.compat import ensure_node_tree  # the product's 4.5/5.0 layer

# Rec.709 / sRGB luminance weights (ITU-R BT.709-6, item 3.3), used only to turn the RGB result into
# one scalar for the relative-error stopping rule and for lux in the baseline (K = 683 lm/W).
REC709_Y = (0.2126, 0.7152, 0.0722)
K_M = 683.0

_PATCH_NAME = "__reference_patch__"
_CAMERA_NAME = "__reference_camera__"


class _Settings:
    """Set attributes and remember the old values, so they can be restored in reverse order."""

    def __init__(self):
        self._saved = []

    def set(self, owner, attr, value):
        if not hasattr(owner, attr):
            return
        self._saved.append((owner, attr, getattr(owner, attr)))
        setattr(owner, attr, value)

    def restore(self):
        for owner, attr, value in reversed(self._saved):
            try:
                setattr(owner, attr, value)
            except Exception:  # pragma: no cover - a property that refuses its own old value
                pass
        self._saved.clear()


def _scene_extent(scene, depsgraph, point):
    """Largest distance from ``point`` to any evaluated mesh bounding-box corner or light, at least 1e-3."""
    p = Vector(point)
    far = 0.0
    for inst in depsgraph.object_instances:
        ob = inst.object
        mw = inst.matrix_world
        if ob.type == "LIGHT":
            far = max(far, (mw.translation - p).length)
        elif ob.type in {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME"}:
            for corner in ob.bound_box:
                far = max(far, (mw @ Vector(corner) - p).length)
    return max(far, 1e-3 * max(p.length, 1.0), 1e-3)


def _free_distance(scene, depsgraph, point, normal, limit):
    """Distance from ``point`` along ``normal`` to the first geometry (``limit`` if none)."""
    hit, location, *_ = scene.ray_cast(depsgraph, Vector(point), Vector(normal), distance=limit)
    return (location - Vector(point)).length if hit else limit


def _orthonormal_frame(n):
    n = Vector(n).normalized()
    helper = Vector((1.0, 0.0, 0.0)) if abs(n.x) < 0.9 else Vector((0.0, 1.0, 0.0))
    t = n.cross(helper).normalized()
    b = n.cross(t)
    return n, t, b


def _add_patch(scene, point, normal, size):
    """White Lambertian sensor, world-space vertices (identity transform), exact custom normal.

    The sensor is ONE triangle that contains the camera's square frame [-size/2, size/2]^2 with a
    20 % margin. A two-triangle quad was tried first: about one camera ray in 10^4 that landed on
    the shared diagonal returned zero (measured: single samples of 0 in an otherwise noiseless
    point-light render of a tilted patch, a -6e-5 bias of the mean). A single triangle has no
    interior edge for a ray to slip through."""
    n, t, b = _orthonormal_frame(normal)
    p = Vector(point)
    a = 0.6 * size  # legs of the right triangle: (-a,-a), (3a,-a), (-a,3a); hypotenuse x + y = 2a
    # Counter-clockwise seen from the front (+n): (t, b, n) is right-handed, so the face normal is +n.
    verts = [p - a * t - a * b, p + 3 * a * t - a * b, p - a * t + 3 * a * b]
    mesh = bpy.data.meshes.new(_PATCH_NAME)
    mesh.from_pydata([tuple(v) for v in verts], [], [(0, 1, 2)])
    mesh.update()
    attr = mesh.attributes.new("custom_normal", "FLOAT_VECTOR", "POINT")
    attr.data.foreach_set("vector", [c for _ in range(3) for c in n])
    mesh.shade_smooth()
    mat = bpy.data.materials.new(_PATCH_NAME)
    tree = ensure_node_tree(mat)  # Blender 4.5 gives a new material no tree until use_nodes is set
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    out.target = "ALL"
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0  # pure Lambert (roughness > 0 is Oren-Nayar)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(_PATCH_NAME, mesh)
    # Camera rays only: nothing else in the scene can see (or be shadowed by) the patch.
    for a in ("visible_diffuse", "visible_glossy", "visible_transmission", "visible_volume_scatter",
              "visible_shadow"):
        setattr(obj, a, False)
    obj.visible_camera = True
    obj.is_holdout = False
    obj.is_shadow_catcher = False
    obj.hide_render = False
    scene.collection.objects.link(obj)
    return obj, mesh, mat


def _add_camera(scene, point, normal, size, distance):
    n = Vector(normal).normalized()
    cam_data = bpy.data.cameras.new(_CAMERA_NAME)
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = size          # the patch fills the (square) frame exactly
    cam_data.shift_x = cam_data.shift_y = 0.0
    cam_data.clip_start = 0.1 * distance  # rays start just in front of the camera...
    cam_data.clip_end = 2.0 * distance    # ...and end just behind the patch: nothing else can be seen
    cam_data.dof.use_dof = False
    cam = bpy.data.objects.new(_CAMERA_NAME, cam_data)
    cam.location = Vector(point) + distance * n
    _, t, b = _orthonormal_frame(n)
    # Camera looks along its local -Z (= -n); its local X, Y are the sensor's t, b, so the frame is
    # the square [-size/2, size/2]^2 in the sensor's own coordinates.
    rot = Matrix((t, b, n)).transposed()
    cam.rotation_euler = rot.to_euler()
    scene.collection.objects.link(cam)
    return cam, cam_data


def _measurement_settings(scene, view_layer, settings, res, spp, seed, path, engine_only=False):
    s = settings.set
    r, c = scene.render, scene.cycles
    if not engine_only:
        s(r, "engine", "CYCLES")
        s(c, "device", "CPU")
        # --- settings that change only noise or truncation, never the converged answer ---
        s(c, "use_adaptive_sampling", False)  # fixed spp: every pixel is an identical estimator
        s(c, "use_denoising", False)          # denoising is biased
        s(c, "time_limit", 0.0)               # a user time limit would cut samples
        s(c, "sampling_pattern", "TABULATED_SOBOL")  # each pixel's table rotated by its own uniform shift:
        s(c, "scrambling_distance", 1.0 - 2.0 ** -20)  # pixels independent and unbiased (module docstring)
        s(c, "auto_scrambling_distance", False)
        s(c, "sample_offset", 0)
        s(c, "use_animated_seed", False)
        s(c, "light_sampling_threshold", 0.0)  # the default 0.01 culls dim lights (biased)
        s(c, "sample_clamp_direct", 0.0)       # clamping is biased
        s(c, "sample_clamp_indirect", 0.0)
        s(c, "blur_glossy", 0.0)               # filter glossy (default 1) is biased
        # Bounce limits: high enough that truncation is negligible; Russian roulette (unbiased)
        # ends paths long before. Lights are transparent to rays (FACTS.md), so the transparent
        # limit matters too (0 would make every light opaque).
        for attr in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                     "volume_bounces", "transparent_max_bounces"):
            s(c, attr, 1024)
        # --- Cycles defaults for things that change the converged answer (a user's file may differ) ---
        s(c, "caustics_reflective", True)
        s(c, "caustics_refractive", True)
        s(c, "use_fast_gi", False)   # AO approximation of GI
        s(r, "use_simplify", False)  # simplify changes geometry and AO bounces
        s(c, "film_exposure", 1.0)
        s(r, "use_motion_blur", False)  # measure the current frame's state
        s(r, "use_compositing", False)  # a compositor tree would alter the pixels
        s(r, "use_sequencer", False)
        s(r, "use_freestyle", False)
        s(r, "use_border", False)
        s(r, "use_multiview", False)
        s(r, "use_persistent_data", True)  # keeps the synced scene between seeds (speed only)
        s(r, "resolution_percentage", 100)
        s(r, "pixel_aspect_x", 1.0)
        s(r, "pixel_aspect_y", 1.0)
        s(c, "pixel_filter_type", "BOX")
        s(c, "filter_width", 0.01)  # every camera ray through its pixel centre, on the patch
        s(r, "film_transparent", False)
        s(r, "use_single_layer", True)
        s(scene.view_settings, "view_transform", "Standard")
        s(scene.view_settings, "look", "None")
        s(scene.view_settings, "exposure", 0.0)
        s(scene.view_settings, "gamma", 1.0)
        s(scene.view_settings, "use_curve_mapping", False)
        s(view_layer, "material_override", None)  # would replace the patch's white material
        s(view_layer, "samples", 0)               # a per-layer sample override
        s(view_layer, "use", True)
        s(view_layer.cycles, "use_denoising", False) if hasattr(view_layer, "cycles") else None
        im = r.image_settings
        if hasattr(im, "media_type"):
            s(im, "media_type", "IMAGE")
        s(im, "file_format", "OPEN_EXR")
        s(im, "color_depth", "32")  # float32: half floats overflow at 65504
        s(im, "color_mode", "RGBA")
        s(im, "exr_codec", "ZIP")
        s(r, "use_file_extension", True)
        s(r, "filepath", path)
    s(r, "resolution_x", res)
    s(r, "resolution_y", res)
    s(c, "samples", spp)
    s(c, "seed", seed)


def _render_pixels(scene, view_layer, path):
    """One render; returns (res*res, 3) float64 pixel values (radiance, W / (scene unit^2 sr))."""
    bpy.ops.render.render(write_still=True, scene=scene.name, layer=view_layer.name)
    with OpenEXR.File(path) as f:
        channels = f.channels()
        if "RGBA" in channels:
            px = np.array(channels["RGBA"].pixels, dtype=np.float64)  # copy inside the with
        else:
            px = np.stack([np.array(channels[k].pixels, dtype=np.float64) for k in "RGB"], axis=-1)
    os.remove(path)
    return px.reshape(-1, px.shape[-1])[:, :3]


def on_surface_point(scene, origin, direction, *, depsgraph=None):
    """First hit of a ray from ``origin`` along ``direction``: (location, face normal) or None.

    Use it to put a meter exactly on a surface (the corpus does this for desk and wall meters)."""
    if depsgraph is None:
        depsgraph = _depsgraph(scene, None)
    hit, location, normal, *_ = scene.ray_cast(depsgraph, Vector(origin), Vector(direction).normalized())
    return (tuple(location), tuple(normal)) if hit else None


def lift_off_surface(scene, point, normal, gap_m=1e-6, min_ulps=32):
    """``point`` moved off its surface along ``normal`` by max(``gap_m`` metres in scene units,
    ``min_ulps`` float32 ulps of the point's largest coordinate).

    The reference patch must sit in free space, never inside or level with a surface (a ray from the
    patch must not be able to hit the surface it lies on). The lift biases the reading by about
    2 * gap / d for a source at distance d (inverse square): measured on desk_only (spot lamp 0.4 m
    above the desk), a 1e-5 m lift read 4.3e-5 high against Radiometer's closed form on the surface,
    as predicted (5e-5); a 1 mm lift would be 0.5 %. With the default (1e-6 m, or ~4e-6 m a couple of
    metres from the origin, where 32 float32 ulps are larger) the bias is < 2e-5 for d >= 0.4 m."""
    scale = scene.unit_settings.scale_length or 1.0
    p = Vector(point)
    n = Vector(normal).normalized()
    ulp = float(np.spacing(np.float32(max(abs(c) for c in p) or 1e-30)))
    gap = max(gap_m / scale, min_ulps * ulp)
    return tuple(p + gap * n)


def _depsgraph(scene, view_layer):
    view_layer = view_layer or (bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0])
    dg = view_layer.depsgraph
    dg.update()
    return dg


def reference_irradiance(scene, point, normal, *, target_rel_error=1e-3, max_seconds=120.0, seed=0,
                         view_layer=None, resolution=32, patch_size=None, verbose=False):
    """Reference irradiance on the front side of an ideal sensor at ``point`` facing ``normal``.

    Parameters: ``point``, ``normal`` in scene coordinates (``point`` must be in free space: use
    ``lift_off_surface`` for a point on a surface); ``target_rel_error``: stop when the relative
    standard error of the Rec.709-luminance-weighted irradiance is at most this; ``max_seconds``:
    stop anyway after this much rendering time; ``seed``: first Cycles seed (render k uses
    seed + k + 1, the pilot uses seed). ``view_layer``: defaults to the context view layer for the
    context scene, else the scene's first view layer. ``patch_size``: in scene units (default 1e-4 of
    the scene extent seen from ``point``).

    Returns ``(E_rgb, rel_std_error, info)``: E_rgb is a tuple of 3 floats in SI W/m^2 (scene value /
    scale_length^2); rel_std_error is the standard error over E's luminance-weighted scalar (0 when
    all pixels agree exactly, e.g. one delta light and no geometry); info a dict (samples, renders,
    seconds, patch_size, camera_distance, spp, E_Y).
    """
    t_start = time.perf_counter()
    if view_layer is None:
        view_layer = bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]
    n = Vector(normal)
    if n.length == 0:
        raise ValueError("normal must be non-zero")
    n.normalize()
    depsgraph = _depsgraph(scene, view_layer)
    extent = _scene_extent(scene, depsgraph, point)
    if patch_size is None:
        # 1e-4 of the scene: the mean irradiance over a patch of size s at distance d from a source
        # differs from the point value by O((s/d)^2); and far above float32 resolution of |point|.
        ulp = np.spacing(np.float32(max(Vector(point).length, extent)))
        patch_size = max(1e-4 * extent, 2000.0 * float(ulp))
    # Camera distance: small against the patch's distance to anything in front of it.
    free = _free_distance(scene, depsgraph, point, n, limit=extent)
    cam_dist = min(10.0 * patch_size, 0.25 * free)
    cam_dist = max(cam_dist, 50.0 * float(np.spacing(np.float32(max(Vector(point).length, 1.0)))))

    settings = _Settings()
    added = []
    had_render_result = "Render Result" in bpy.data.images
    old_camera = scene.camera
    tmpdir = tempfile.mkdtemp(prefix="radiometer_ref_")
    path = os.path.join(tmpdir, "ref.exr")
    try:
        patch, mesh, mat = _add_patch(scene, point, n, patch_size)
        added += [("objects", patch), ("meshes", mesh), ("materials", mat)]
        cam, cam_data = _add_camera(scene, point, n, patch_size, cam_dist)
        added += [("objects", cam), ("cameras", cam_data)]
        scene.camera = cam

        # Pilot: few samples, estimate the per-sample variance to size the main renders.
        pilot_res, pilot_spp = 16, 16
        _measurement_settings(scene, view_layer, settings, pilot_res, pilot_spp, seed, path)
        px = _render_pixels(scene, view_layer, path)
        y = px @ np.asarray(REC709_Y)
        mean_y, sd_y = float(y.mean()), float(y.std(ddof=1))
        renders, samples = 1, px.shape[0] * pilot_spp
        if sd_y == 0.0:
            # All pixels equal. Either the answer is noiseless (one delta light, nothing to bounce)
            # or every sample missed a rarely picked light: measured in transformed_lights, a meter
            # outside a spot's cone read exactly 0 in 4096 samples although three far area lights
            # give 4.6e-5 W/m^2 (the light tree picks them with tiny probability). Confirm with a
            # full-size render (64x more samples, new seed) before calling it exact.
            pilot_res, pilot_spp = resolution, 256
            _measurement_settings(scene, view_layer, settings, pilot_res, pilot_spp, seed + 10 ** 6, path,
                                  engine_only=True)
            px2 = _render_pixels(scene, view_layer, path)
            renders += 1
            if np.all(px2 == px2[0]) and np.allclose(px2[0], px[0], rtol=1e-6, atol=0.0):
                px, sd_y = px2, 0.0
            else:
                px = px2
                y = px @ np.asarray(REC709_Y)
                mean_y, sd_y = float(y.mean()), float(y.std(ddof=1))
                if sd_y == 0.0:  # equal pixels, but not the pilot's value: not trustworthy as exact
                    sd_y = abs(mean_y - float(np.asarray(REC709_Y) @ px[0])) or 1e-30
            samples += px2.shape[0] * pilot_spp
        if sd_y == 0.0 or mean_y == 0.0:
            # Every pixel identical (delta lights only, nothing to bounce): no noise at all.
            rgb = px.mean(axis=0)
            rel = 0.0 if sd_y == 0.0 else math.inf
            spp = pilot_spp
        else:
            per_sample_rel_var = (sd_y / mean_y) ** 2 * pilot_spp
            needed = per_sample_rel_var / target_rel_error ** 2  # total samples for the target
            spp = int(min(1024, max(16, math.ceil(needed / resolution ** 2))))  # <= 1024: float32 film
            all_px = []
            k = 0
            while True:
                k += 1
                _measurement_settings(scene, view_layer, settings, resolution, spp, seed + k, path,
                                      engine_only=True)
                all_px.append(_render_pixels(scene, view_layer, path))
                renders += 1
                pool = np.concatenate(all_px)
                y = pool @ np.asarray(REC709_Y)
                mean_y = float(y.mean())
                rel = float(y.std(ddof=1) / math.sqrt(len(y)) / abs(mean_y)) if mean_y != 0 else math.inf
                if verbose:
                    print(f"  render {k}: spp {spp}, E_Y {math.pi * mean_y:.6g}, rel se {rel:.2e}")
                if rel <= target_rel_error or time.perf_counter() - t_start > max_seconds:
                    break
            rgb = pool.mean(axis=0)
            samples = pool.shape[0] * spp
        scale = scene.unit_settings.scale_length or 1.0
        e_rgb = tuple(float(math.pi * v / scale ** 2) for v in rgb)
        info = {"samples": samples, "renders": renders, "seconds": time.perf_counter() - t_start,
                "patch_size": patch_size, "camera_distance": cam_dist, "spp": spp,
                "E_Y": sum(w * v for w, v in zip(REC709_Y, e_rgb))}
        return e_rgb, rel, info
    finally:
        settings.restore()
        scene.camera = old_camera
        for kind, block in reversed(added):
            try:
                getattr(bpy.data, kind).remove(block)
            except Exception:  # pragma: no cover
                pass
        if not had_render_result and "Render Result" in bpy.data.images:
            bpy.data.images.remove(bpy.data.images["Render Result"])
        for name in os.listdir(tmpdir):
            os.remove(os.path.join(tmpdir, name))
        os.rmdir(tmpdir)


def luminance(e_rgb):
    """Rec.709 Y of an RGB irradiance (W/m^2), and illuminance in lux with K = 683 lm/W."""
    y = sum(w * v for w, v in zip(REC709_Y, e_rgb))
    return y, K_M * y

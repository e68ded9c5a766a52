"""Daylight coefficients of every sky patch at every meter from ONE Cycles render (issue 19).

Radiance's ``rcontrib`` traces paths from each sensor and adds each path's contribution to the bin of
the sky patch where it escapes. Cycles does the same with three of its own features:

* **a patch dome**: the world is replaced by a sphere of emitting triangles around the scene, one
  object per sky patch (``radiometry.skies.sky_patches.dome_mesh``: the radial projections of its
  triangles are the patches, crack-free; patch 0 the ground), each emitting white radiance 1, each
  in its own **light group**. A light group's pass holds exactly the light that left that group's
  emitters, after any number of bounces: one render gives every patch's contribution at once.
* **a custom OSL camera** (Cycles' ``CUSTOM`` lens, no OSL shading needed): the image is a grid of
  B x B pixel blocks, one per meter. A pixel sample at (u, v) inside meter k's block starts a ray at
  the meter (lifted ``EPS`` of the scene's size along its normal) in the direction that the
  concentric (Shirley-Chiu) map sends (u, v) to on the cosine-weighted hemisphere about the meter's
  normal (Malley's method). With a one-pixel box filter the samples are uniform over the block, so
  the block's mean radiance times pi is the irradiance: E_k,p = pi mean(L_p), exactly the diffuse
  sensor's estimator, for every patch p.
* **the render saved as one multilayer EXR** holds every light-group pass (parts "<view layer>.Combined_<group>").
  Until 2026-12-07 the compositor's File Output node wrote them: building its 146 (MF:2: 578) inputs cost
  0.4 s (9.3 s) per render set-up, the render itself no less.

DC[p, k] = pi Y_p,k (lux per cd/m^2: a patch of luminance L_v gives L_v DC lux): the patches emit
white radiance 1 and Y weighs the pass with the scene's luminance weights, so coloured surfaces
count as they do for the meter. Ray visibility: the first ray leaves from the meter like the
sensor's diffuse ray, so for that render every object's camera visibility is set to its diffuse
visibility (restored after). Lights are hidden (light groups would exclude them anyway; hidden,
they cost no samples) and the world is black.

Error: the render is repeated in ``rounds`` with different seeds; each pixel is a stratum of the
hemisphere, so the variance of a block mean is the sum over its pixels of the between-round variance
of the pixel's mean over rounds, divided by the pixel count squared (stratified sampling: no
correlation between pixels is assumed beyond that of Cycles' per-pixel scrambling, which the
measurement settings keep at full distance). The same pixel data give the full covariance of the
coefficients of one meter (patches share paths), which ``covariance`` returns so that hourly
illuminance errors are propagated with it (``measure.analyses.annual``).

The dome is centred on the bounding box of the scene's render-visible triangles and the meters, with
radius ``DOME_SCALE`` times its half-diagonal: a meter at distance d from the centre sees a patch
edge displaced by at most d / R < 1 / DOME_SCALE rad (1e-5 rad: at 1e-3 a 12 deg patch's coefficient
moved by ~1 %).
"""

from __future__ import annotations

import dataclasses
import math
import os
import shutil
import tempfile

import numpy as np

from ...errors import MeasurementCancelled, RadiometerError

#: Dome radius over the scene's half-diagonal (the largest patch-edge displacement seen from a
#: meter is 1 / DOME_SCALE rad).
DOME_SCALE = 1e5
#: Ray lift off the meter along its normal, relative to the scene's half-diagonal (a meter on a
#: floor must not see the floor's back face).
EPS = 1e-6
#: Samples per pixel, pixels per block side, rounds per quality (``render_irradiance``: the world as it is).
PRESETS = {"preview": (8, 16, 8), "standard": (32, 24, 8), "reference": (128, 32, 8)}
#: The same for the patch dome (``render_coefficients``): as many rays per meter, in 4x fewer pixels. Every pixel
#: carries all 146 light-group passes to the EXR and back, so pixels cost more than samples
#: there. Measured (the annual room, 200 points, preview, one run each): 16 x 16 px x 8 samples took 16.5 s for
#: the coefficients, 8 x 8 x 32 8.8 s, with the same hourly errors (median 4.9 % / 4.8 %, 95th percentile
#: 14.1 % / 14.0 %). A block's pixels still give its variance 64 x 7 degrees of freedom per hourly sum.
DOME_PRESETS = {"preview": (32, 8, 8), "standard": (128, 12, 8), "reference": (512, 16, 8)}
LIGHTGROUP = "radiometer_patch_{:04d}"


@dataclasses.dataclass
class Coefficients:
    """``dc`` (P, N) lux per cd/m^2, ``std_error`` (P, N), ``covariance`` (N, P, P) of the
    coefficients of each meter, ``samples`` rays per meter, ``seconds``, ``notes``; ``direct`` (P, N): the part
    of ``dc`` that is the patches' proven direct light in closed form (exact: the errors are the rest's), or
    None where it was rendered."""

    dc: np.ndarray
    std_error: np.ndarray
    covariance: np.ndarray
    samples: int
    seconds: float
    notes: list
    direct: object = None


def _frame(n):
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(n, helper)
    t /= np.linalg.norm(t)
    return t, np.cross(n, t)


def camera_source(origins, normals, block, columns):
    """OSL source of the meter camera: meter k's block is column k % columns, row k // columns.

    Positions and directions go out in Cycles' camera space (+Z forward, +Y up), which for a camera
    object at the origin without rotation is world (x, y, -z).
    """
    n = len(origins)
    rows = -(-n // columns)
    table = []
    def xyz(v):  # full-precision Python floats (numpy 2 writes np.float64(...) as repr)
        return ", ".join(repr(float(c)) for c in v)

    for k, (o, d) in enumerate(zip(origins, normals)):
        t, b = _frame(np.asarray(d, float))
        table.append(f"    if (k == {k}) {{ O = point({xyz(o)}); Nn = vector({xyz(d)}); T = vector({xyz(t)}); "
                     f"Bt = vector({xyz(b)}); }}")
    # A binary search over k keeps the per-ray cost logarithmic in the meter count.
    body = _dispatch(table, 0, n)
    return f"""// Radiometer meter camera (generated): one block of {block} x {block} pixels per meter.
shader radiometer_meters(output point position = point(0, 0, 0), output vector direction = vector(0, 0, 1),
                         output color throughput = color(1, 1, 1))
{{
    point rp = camera_shader_raster_position();
    float px = rp[0] * {columns * block}.0 / {block}.0;
    float py = rp[1] * {rows * block}.0 / {block}.0;
    int cx = (int)floor(px);
    int cy = (int)floor(py);
    int k = cy * {columns} + cx;
    // The pixel from the raster position, the place inside the pixel from the camera's own random
    // pair: Cycles' box filter spreads samples over ~0.96 of a pixel (measured: Var 0.077, not 1/12),
    // which left the block's outer ring (grazing directions) under-sampled.
    vector xi = camera_shader_random_sample();
    float su = clamp((floor(rp[0] * {columns * block}.0) - cx * {block}.0 + xi[0]) / {block}.0, 0.0, 1.0);
    float sv = clamp((floor(rp[1] * {rows * block}.0) - cy * {block}.0 + xi[1]) / {block}.0, 0.0, 1.0);
    point O = point(0, 0, 0);
    vector Nn = vector(0, 0, 1), T = vector(1, 0, 0), Bt = vector(0, 1, 0);
    if (k < 0 || k >= {n}) {{ throughput = color(0, 0, 0); return; }}
{body}
    float a = 2 * su - 1, b = 2 * sv - 1, r = 0, phi = 0;
    if (a != 0 || b != 0) {{
        if (abs(a) > abs(b)) {{ r = a; phi = M_PI / 4 * (b / a); }}
        else {{ r = b; phi = M_PI / 2 - M_PI / 4 * (a / b); }}
    }}
    float dx = r * cos(phi), dy = r * sin(phi);
    vector d = dx * T + dy * Bt + sqrt(max(0.0, 1 - dx * dx - dy * dy)) * Nn;
    position = point(O[0], O[1], -O[2]);
    direction = vector(d[0], d[1], -d[2]);
    throughput = color(1, 1, 1);
}}
"""


def _dispatch(table, lo, hi):
    if hi - lo <= 4:
        return "\n".join(table[lo:hi])
    mid = (lo + hi) // 2
    left = _dispatch(table, lo, mid).replace("\n", "\n    ")
    right = _dispatch(table, mid, hi).replace("\n", "\n    ")
    return f"    if (k < {mid}) {{\n    {left}\n    }} else {{\n    {right}\n    }}"


def _block_layout(n, block):
    columns = max(1, int(math.ceil(math.sqrt(n))))
    return columns, -(-n // columns)


def _compile_camera(source):
    import bpy

    from ...shading.osl import ensure_oslquery

    ensure_oslquery()
    from cycles import osl as cycles_osl  # Blender's Cycles add-on, present with bpy

    text = bpy.data.texts.new("radiometer_meter_camera.osl")
    text.write(source)
    cam_data = bpy.data.cameras.new("radiometer_meter_camera")
    cam_data.type = "CUSTOM"
    cam_data.custom_mode = "INTERNAL"
    cam_data.custom_shader = text
    cam_data.clip_start = 1e-9
    cam_data.clip_end = 1e30
    messages = []
    cycles_osl.update_custom_camera_shader(cam_data, lambda kind, msg: messages.append((set(kind), msg)))
    if not cam_data.custom_bytecode:
        raise RadiometerError("the meter camera (OSL) did not compile: " + "; ".join(m for _k, m in messages))
    return cam_data


def _build_dome(scene, view_layer, patches, centre, radius):
    """One emitting object per patch, each in its own light group; returns the group names and the objects."""
    import bpy

    from ...radiometry.skies import sky_patches

    from ..blender.materials import shader_material

    mat, _emission = shader_material("radiometer_patch_emission", "ShaderNodeEmission",
                                     {"Color": (1.0, 1.0, 1.0, 1.0), "Strength": 1.0})
    # Found by the paths' own bounces only, not by next-event estimation: from inside a room nearly every shadow
    # ray to a patch of the far dome ends on a wall, and the light tree cannot know which patches the openings
    # show. Measured (the annual room, 200 points, preview, one run each): the render 3.3x faster, the hourly
    # errors 1.16x larger (median 4.9 % against 4.2 %): 1 / (time x variance) 2.5x higher.
    mat.cycles.emission_sampling = "NONE"
    names, objects = [], []
    for p, (verts, faces) in enumerate(sky_patches.dome_mesh(patches)):
        name = LIGHTGROUP.format(p)
        me = bpy.data.meshes.new(name)
        me.from_pydata((np.asarray(centre) + radius * verts).tolist(), [], faces.tolist())
        me.materials.append(mat)
        ob = bpy.data.objects.new(name, me)
        scene.collection.objects.link(ob)
        ob.visible_shadow = True
        if view_layer.lightgroups.get(name) is None:
            view_layer.lightgroups.add(name=name)
        ob.lightgroup = name
        names.append(name)
        objects.append(ob)
    return names, objects


def _read_passes(path, names, weights):
    """(P, H, W) luminance-weighted light-group passes (top row first) from the render's multilayer EXR
    (parts "<view layer>.Combined_<group>"; ``measure.blender.exr.read_parts``); the file is removed."""
    from ..blender import exr

    parts = exr.read_parts(path, lambda part: part.rpartition(".Combined_")[2] if ".Combined_" in part else None)
    out = None
    for i, name in enumerate(names):
        ch = parts.get(name)
        if ch is None:
            raise RadiometerError(f"the render has no pass for sky patch {i}")
        y = sum(w * np.asarray(ch[c], np.float64) for w, c in zip(weights, "RGB"))
        if out is None:
            out = np.empty((len(names),) + y.shape)
        out[i] = y
    os.remove(path)
    return out


def _blocks(img, n, block, columns):
    """(P, H, W) -> (n, P, block * block): each meter's pixels. The camera's raster y runs from the
    bottom of the image, the EXR's rows from the top."""
    p, h, w = img.shape
    img = img[:, ::-1, :]
    rows = -(-n // columns)
    cells = img[:, :rows * block, :columns * block].reshape(p, rows, block, columns, block)
    cells = cells.transpose(1, 3, 0, 2, 4).reshape(rows * columns, p, block * block)
    return cells[:n]


def supported(scene):
    """Whether this Blender has what the dome needs: custom (OSL) cameras and a multilayer save that holds the
    light-group passes (Blender 5.0, told by its image settings' ``media_type``; measured: 4.5's saved render
    holds no light-group part)."""
    import bpy

    return hasattr(scene.render.image_settings, "media_type") and "CUSTOM" in \
        bpy.types.Camera.bl_rna.properties["type"].enum_items.keys()


def require_dome(scene):
    """Raise one RadiometerError where this Blender cannot render the dome (:func:`supported`). Measured on
    Blender 4.5 (the annual test room, 2 spp): falling back silently to one render per patch gave per-point
    sDA bounds that missed Radiance's by up to 57 points, so the dome is refused and per_patch stays an
    explicit choice (with target_rel_error, which takes the meter's sample floor)."""
    if not supported(scene):
        raise RadiometerError("the one-render sky-patch dome needs Blender 5.0 (custom cameras, light-group passes in a "
                              "saved render); on this Blender "
                              "ask for method='per_patch' with target_rel_error "
                              "(one adaptive measurement per sky patch: far slower)")


def scene_extent(model, points_scene, scale):
    """(centre, half-diagonal) of the render-visible triangles and the points, scene units."""
    pts = [np.asarray(points_scene, float)]
    if model.geometry.count:
        pts.append(model.geometry.triangles.reshape(-1, 3) / scale)
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    return (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1.0)


def _meter_camera(request, snapshot, model, points, normals, half, *, blk, spp):
    """Inside the caller's guard: every object's camera visibility = its diffuse visibility (the first
    ray is the sensor's diffuse ray), the meter camera, measurement settings (the request's quality preset's
    bounces, its seed), thin panes as the meter reads them, a one-pixel box filter. Returns (the settings'
    record, (width, height) of the image)."""
    import bpy

    from ..render import render_settings

    scene = request.scene
    for ob in scene.objects:
        if ob.type != "LIGHT" and ob.visible_camera != ob.visible_diffuse:
            snapshot.remember(ob, "visible_camera")
            ob.visible_camera = ob.visible_diffuse
    columns, rows = _block_layout(len(points), blk)
    cam_data = _compile_camera(camera_source(points + EPS * half * normals, normals, blk, columns))
    cam = bpy.data.objects.new("radiometer_meter_camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    record = render_settings.apply(scene, samples=spp, bounces=request.preset()["bounces"], needs=model.needs,
                                   seed=request.seed, snapshot=snapshot, custom_camera=True)
    if model.needs.get("thin_panes"):  # panes read as thin glass, as the meter reads them
        from ..capture import glass

        glass.swap_panes(snapshot, model.needs["thin_panes"])
    scene.cycles.filter_width = 1.0  # box of one pixel: samples stay inside their block
    return record, (columns * blk, rows * blk)


def _rounds(request, folder, size, nrounds, label, read, multilayer=False):
    """Render ``nrounds`` times (seeds ``seed * 7919 + k``, the request's seed; ``measure.meter.camera.render_exr``);
    ``read(image)`` -> (N, C, npix) after each (``multilayer``: ``read(path)`` of the render's multilayer EXR,
    ``render_multilayer_exr``); the request's cancel before and progress after each. Returns the per-pixel sums
    over rounds and the sum over rounds and pixels of x x^T (N, C, C)."""
    from ..meter.camera import render_exr, render_multilayer_exr

    scene, seed, cancelled, progress = request.scene, request.seed, request.cancelled, request.progress
    render = render_multilayer_exr if multilayer else render_exr
    total = cross = None
    for k in range(nrounds):
        if cancelled is not None and cancelled():
            raise MeasurementCancelled(f"{label} cancelled")
        scene.cycles.seed = int(seed) * 7919 + k
        x = read(render(scene, folder, "combined", size[0], size[1]))
        total = x if total is None else total + x
        cross = np.matmul(x, np.swapaxes(x, 1, 2)) + (0.0 if cross is None else cross)  # BLAS, not einsum: 4x
        if progress is not None:
            progress(k + 1, nrounds, None)
    return total, cross


def _stratified(total, cross, nrounds):
    """(mean (N, C), covariance (N, C, C)) of the block means: Var(block mean) = sum over pixels of
    Var(pixel's round mean) / npix^2, each from R rounds; sum_i sum_r (x_ri - m_i)(x_ri - m_i)^T =
    sum_r sum_i x x^T - R sum_i m_i m_i^T (streamed: the rounds are never all in memory)."""
    npix = total.shape[-1]
    mean = total.sum(axis=2) / (nrounds * npix)
    cov = (cross - np.einsum("npi,nqi->npq", total, total) / nrounds) / ((nrounds - 1) * nrounds * npix ** 2)
    return mean, cov


def render_irradiance(points_scene, normals, *, request, block=None, rounds=None):
    """Irradiance at the meters from the scene AS IT IS (world and lights as the caller left them),
    through the meter camera (module docstring; no dome, no light groups): (E_rgb (N, 3) W/m^2 per
    scene unit^2 as Cycles renders, covariance (N, 3, 3), record). The scene is as before afterwards.
    The request gives the scene, ``quality`` (None: "standard") and ``samples``, the seed, progress and cancel."""
    from ..meter import point_meter as meter
    from ..blender import scene_guard

    scene, quality = request.scene, request.quality or "standard"
    spp, blk, nrounds = _settings(quality, request.samples, block, rounds)
    points = np.asarray(points_scene, float).reshape(-1, 3)
    normals = np.asarray(normals, float).reshape(-1, 3)
    n = len(points)
    columns, _rows = _block_layout(n, blk)
    folder = tempfile.mkdtemp(prefix="radiometer_cam_")
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            model = meter.capture_model(scene, request.view_layer)
            _centre, half = scene_extent(model, points, request.scale_length)
            record, size = _meter_camera(request.but(quality=quality), snapshot, model, points, normals, half,
                                         blk=blk, spp=spp)
            total, cross = _rounds(request, folder, size, nrounds, "meter camera",
                                   lambda img: np.pi * _blocks(np.moveaxis(img, -1, 0), n, blk, columns))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    mean, cov = _stratified(total, cross, nrounds)
    return mean, cov, dict(record, rays_per_meter=nrounds * spp * blk * blk)


def _settings(quality, samples, block, rounds, presets=PRESETS):
    from ... import quality as quality_presets

    if quality not in presets:
        quality_presets.preset(quality)  # the one-line error for an unknown name
    spp, blk, nrounds = presets[quality]
    spp, blk, nrounds = int(samples or spp), int(block or blk), int(rounds or nrounds)
    if spp < 1 or blk < 2 or nrounds < 2:
        raise RadiometerError("the meter camera needs samples >= 1, block >= 2 and rounds >= 2")
    return spp, blk, nrounds


#: Relative width of a pane's T(theta) bound per piece of a patch (``patch_aperture.pane_patch_coefficients``):
#: measured in the annual room behind a 6 mm pane (256 points, preview, one run each), 1e-3 took 10.3 s of
#: subdivision beside a 31 s render, for bounds of 0.02-0.15 % of the direct light; 5e-3 5.8 s, bounds up to 0.34 %,
#: where the render's hourly errors are ~4 %.
PANE_REL_TOL = 5e-3


def _slots(pieces):
    """Per-point lists of convex polygons as ``patch_aperture`` openings: slot j holds each point's j-th polygon,
    ((N, K, 3) padded by repeating the last vertex, counts (N,), 0 where a point has fewer)."""
    width = max((len(q) for ps in pieces for q in ps), default=3)
    slots = []
    for j in range(max((len(ps) for ps in pieces), default=0)):
        polys, counts = np.zeros((len(pieces), width, 3)), np.zeros(len(pieces), int)
        for i, ps in enumerate(pieces):
            if j < len(ps):
                q = ps[j]
                polys[i] = np.concatenate([q, np.repeat(q[-1:], width - len(q), axis=0)])
                counts[i] = len(q)
        slots.append((polys, counts))
    return slots


def _direct_part(views, points_m, normals, patches):
    """(direct (N, P), its hard bound (N, P)) through the openings ``sky_component.openings_seen_whole`` found."""
    from ...radiometry.skies import patch_aperture

    dome = patch_aperture.dome_triangles(patches)
    direct, bound = np.zeros((len(points_m), patches.count)), np.zeros((len(points_m), patches.count))
    for view in views:
        if view.get("pieces") is not None:  # past obstructions: each point's pieces of the opening
            direct += patch_aperture.patch_coefficients(_slots(view["pieces"]), points_m, normals, patches, dome=dome)
            continue
        if view["pane"] is None:
            direct += patch_aperture.patch_coefficients([view["opening"]], points_m, normals, patches, dome=dome)
            continue
        pane = view["pane"]
        past = view.get("core_pieces") is not None  # opaque obstructions beyond the pane: each point's pieces
        est, half = patch_aperture.pane_patch_coefficients(
            _slots(view["opening_pieces"]) if past else view["opening"],
            _slots(view["core_pieces"]) if past else view["cores"], points_m, normals, patches,
            lambda c: pane.optics(np.asarray(c, float))[0][..., 1], pane.geometry.normal, dome=dome,
            rel_tol=PANE_REL_TOL)
        direct += est
        bound += half
    return direct, bound


def render_coefficients(points_scene, normals, *, request, m=1, block=None, rounds=None, proven_direct=True):
    """Daylight coefficients of every Reinhart MF:m patch (patch 0 the ground) at every meter, from
    ``rounds`` renders of one dome (module docstring). The scene is as before afterwards. The request
    gives the scene, ``quality`` (None: "preview") and ``samples``, the seed, progress and cancel.
    ``proven_direct``: where every meter sees the world through openings proven clear, open or glazed with a
    recognised thin pane (``sky_component.openings_seen_whole``), the patches' direct light in closed form
    (``radiometry.skies.patch_aperture``, ``Coefficients.direct``) and only the rest rendered; False renders
    everything."""
    import time

    import bpy

    from ...radiometry.skies import sky_patches
    from ..meter import point_meter as meter
    from ..blender import scene_guard
    from . import sky_component

    scene, quality = request.scene, request.quality or "preview"
    require_dome(scene)
    spp, blk, nrounds = _settings(quality, request.samples, block, rounds, DOME_PRESETS)
    start = time.perf_counter()
    points = np.asarray(points_scene, float).reshape(-1, 3)
    normals = np.asarray(normals, float).reshape(-1, 3)
    n = len(points)
    patches = sky_patches.reinhart_patches(m)
    columns, _rows = _block_layout(n, blk)
    folder = tempfile.mkdtemp(prefix="radiometer_dc_")
    view_layer = request.view_layer
    added_groups = []
    active_group = view_layer.active_lightgroup_index
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            model = meter.capture_model(scene, view_layer)
            scale = request.scale_length
            from .light_isolation import rendering_light_objects

            for ob in rendering_light_objects(scene, model):
                snapshot.remember(ob, "hide_render")
                ob.hide_render = True
            scene.world = bpy.data.worlds.new("radiometer black world")
            from ...compat import ensure_node_tree

            tree = ensure_node_tree(scene.world)
            bg = next((nd for nd in tree.nodes if nd.type == "BACKGROUND"), None)
            if bg is not None:
                bg.inputs["Strength"].default_value = 0.0
            centre, half = scene_extent(model, points, scale)
            # Issue 31: where every meter sees the world through openings proven clear (open, or glazed with a
            # recognised thin pane), the patches' direct light is a closed form; the dome is then hidden from the
            # first ray (camera rays) and Cycles renders only what the room reflects.
            points_m = points * scale
            seen = sky_component.openings_seen_whole(model, points_m, normals) if proven_direct else "not asked"
            direct, bound = (None, None) if isinstance(seen, str) else _direct_part(seen, points_m, normals, patches)
            before = {g.name for g in view_layer.lightgroups}
            names, dome = _build_dome(scene, view_layer, patches, centre, DOME_SCALE * half)
            added_groups = [g for g in names if g not in before]
            record, size = _meter_camera(request.but(quality=quality), snapshot, model, points, normals, half,
                                         blk=blk, spp=spp)
            if direct is not None:
                for ob in dome:  # new objects, removed with the dome
                    ob.visible_camera = False
            weights = request.weights
            total, cross = _rounds(request, folder, size, nrounds, "daylight coefficients",
                                   lambda path: np.pi * _blocks(_read_passes(path, names, weights), n, blk, columns),
                                   multilayer=True)
    finally:
        for g in added_groups:
            lg = view_layer.lightgroups.get(g)
            if lg is not None:
                view_layer.lightgroups.remove(lg)
        if view_layer.active_lightgroup_index != active_group:  # adding and removing groups moved it
            view_layer.active_lightgroup_index = active_group
        shutil.rmtree(folder, ignore_errors=True)
    mean, cov = _stratified(total, cross, nrounds)
    dc = mean.T  # (P, N) irradiance per unit radiance
    se = np.sqrt(np.maximum(np.einsum("npp->pn", cov), 0.0))
    notes = [f"daylight coefficients of {patches.count} patches (Reinhart MF:{m}) from {nrounds} renders of a "
             f"patch dome with one light group per patch: {spp} samples x {blk}x{blk} pixels per meter per "
             f"render ({nrounds * spp * blk * blk} rays per meter), {record.get('engine', 'Cycles')}"]
    if record.get("device_note"):
        notes.append(record["device_note"])
    if direct is not None:
        dc = dc + direct.T
        glazed = sum(v["pane"] is not None for v in seen)
        clipped = sum(v.get("pieces") is not None or v.get("core_pieces") is not None for v in seen)
        if glazed:
            # the panes' T(theta) bound (hard), counted as one sigma and as fully correlated over patches (an hour's
            # sum of patches adds the bounds up)
            cov = cov + np.einsum("np,nq->npq", bound, bound)
            se = np.sqrt(np.maximum(np.einsum("npp->pn", cov), 0.0))
        closed_form = ("in closed form (radiometry/skies/patch_aperture.py: each patch's triangles of the dome clipped "
                       "to the {}, Lambert's formula{}); the dome was hidden from the meters' first rays, so Cycles "
                       "rendered only the light the surfaces reflect")
        if seen[0]["opening"] is None:  # no closed room: every direction that meets no surface
            notes.append("the patches' direct light over every direction from each meter that meets no surface at all "
                         f"({seen[0]['no_room']}; each meter's "
                         "open directions as convex pieces on the "
                         "faces of a cube round it, radiometry/skies/obstructed_aperture.py open_directions), "
                         + closed_form.format("pieces", ""))
        else:
            notes.append(f"the patches' direct light through {len(seen)} opening(s) ({glazed} glazed with a recognised "
                         "thin pane), proven from every meter (sky and ground: "
                         + (f"only opaque obstructions in the way through {clipped} of them, the world past their "
                            "silhouettes clipped exactly, radiometry/skies/obstructed_aperture.py" if clipped else
                            "nothing inside or outside in the way") + "), "
                         + closed_form.format("openings", "; a pane's T(theta) bounded per piece, the bound counted in "
                                                          "the errors" if glazed else ""))
    elif proven_direct:
        notes.append(f"the patches' direct light rendered with the rest ({seen})")
    return Coefficients(dc, se, cov, nrounds * spp * blk * blk, time.perf_counter() - start, notes,
                        None if direct is None else direct.T)

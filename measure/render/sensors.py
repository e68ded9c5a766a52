"""Irradiance at many points from one Cycles bake ("tiled sensors").

Every meter becomes a tiny white Lambertian quad at its location facing its normal, all in ONE
mesh. Its UVs give each quad a block of ``texels x texels`` pixels of a float image, and one
``bpy.ops.object.bake(type='DIFFUSE', pass_filter={'DIRECT', 'INDIRECT'})`` fills them all with
one scene sync. Baking DIFFUSE without COLOR stores the light a diffuse BSDF receives divided by its
albedo, i.e. E / pi for a Lambertian sensor, so E = pi * pixel.

Each texel of a block is an independent estimate (Cycles decorrelates pixels by per-pixel
scrambling), so one bake already gives ``texels**2`` batches for a batch-means standard error;
further bakes with new seeds add batches. The quads are invisible to every ray type but camera
(Cycles bakes only objects visible to camera rays), so meters never shadow each other or the scene.

Caller's duty: run inside ``scene_guard.preserved_scene`` (this creates and selects data-blocks).
"""

import math
import time

import bpy
import numpy as np

from ...errors import MeasurementCancelled, RadiometerError
from ..blender.materials import shader_material

SENSOR_NAME = "radiometer_sensor"


def _orthonormal_tangents(normals):
    """Two unit tangents per normal (any orthonormal completion; the quad is tiny)."""
    helper = np.where(np.abs(normals[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    t = np.cross(helper, normals)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(normals, t)
    return t, b


def _nearest_light_distance(scene, points):
    """Distance (scene units) from each point to the nearest light origin (inf without lights)."""
    origins = [np.array(ob.matrix_world.translation) for ob in scene.objects
               if ob.type == "LIGHT" and ob.data.type != "SUN"]
    if not origins:
        return np.full(len(points), np.inf)
    d = np.linalg.norm(points[:, None, :] - np.array(origins)[None, :, :], axis=2)
    return d.min(axis=1)


def build_sensor(scene, points, normals, texels):
    """Create the sensor object (linked to the scene collection) and its bake image."""
    n = len(points)
    blocks_per_row = int(math.ceil(math.sqrt(n)))
    res = blocks_per_row * texels
    # Half-size: tiny against the distance to the nearest light. Texels sample different points of
    # the quad: the mean's error is second order, (half / distance)^2, but the SPREAD between texels
    # is first order (~2 half / distance) and would read as noise that no sample count removes
    # (measured: 1e-4 x distance made a 2e-4 target take 800 x the samples it needs). So 2e-6 x
    # distance, floored at 8 float32 steps of the coordinates (6e-8 relative each): enough for a
    # valid quad (its normal comes from the custom normals, not from the vertices).
    radius = np.linalg.norm(points, axis=1)
    nearest = _nearest_light_distance(scene, points)
    half = np.maximum(np.minimum(2e-6 * nearest, 2e-6 * np.maximum(radius, 1.0)), 5e-7 * np.maximum(radius, 1e-3))
    t, b = _orthonormal_tangents(normals)
    corners = np.stack([-t - b, t - b, t + b, -t + b], axis=1) * half[:, None, None] + points[:, None, :]
    verts = corners.reshape(-1, 3)
    faces = np.arange(4 * n).reshape(n, 4)

    mesh = bpy.data.meshes.new(SENSOR_NAME)
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.astype(np.float32).ravel())
    mesh.loops.add(4 * n)
    mesh.loops.foreach_set("vertex_index", faces.ravel().astype(np.int32))
    mesh.polygons.add(n)
    mesh.polygons.foreach_set("loop_start", (np.arange(n) * 4).astype(np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(n, 4, np.int32))
    mesh.update()
    mesh.validate()
    # Exact normals: a face normal computed by Cycles from float32 corners that are 2e-5 m apart
    # is off by ~1e-3 rad a few metres from the origin. Blender 5 "free" custom normals (a float
    # vector attribute named custom_normal) carry the meter's normal at full float32 precision,
    # and smooth shading makes Cycles use them.
    free = mesh.attributes.new("custom_normal", "FLOAT_VECTOR", "POINT")
    free.data.foreach_set("vector", np.repeat(normals, 4, axis=0).astype(np.float32).ravel())
    mesh.shade_smooth()

    # UV block per quad; the quad spans its whole block so every texel centre lies inside.
    ix, iy = np.arange(n) % blocks_per_row, np.arange(n) // blocks_per_row
    u0, v0 = ix * texels / res, iy * texels / res
    du = texels / res
    uv = np.stack([np.c_[u0, v0], np.c_[u0 + du, v0], np.c_[u0 + du, v0 + du], np.c_[u0, v0 + du]], axis=1)
    layer = mesh.uv_layers.new(name="sensor")
    layer.data.foreach_set("uv", uv.reshape(-1).astype(np.float32))

    material, bsdf = shader_material(SENSOR_NAME, "ShaderNodeBsdfDiffuse",
                                     {"Color": (1.0, 1.0, 1.0, 1.0), "Roughness": 0.0})
    tree = material.node_tree
    image = bpy.data.images.new(SENSOR_NAME, res, res, alpha=False, float_buffer=True)
    image.colorspace_settings.is_data = True  # store raw linear values, no view transform
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tree.nodes.active = tex
    mesh.materials.append(material)

    obj = bpy.data.objects.new(SENSOR_NAME, mesh)
    scene.collection.objects.link(obj)
    for attr in ("visible_diffuse", "visible_glossy", "visible_transmission", "visible_volume_scatter", "visible_shadow"):
        setattr(obj, attr, False)
    obj.visible_camera = True  # Cycles skips objects invisible to camera rays when baking
    return obj, image, blocks_per_row


def select_only(view_layer, objs):
    """Select exactly ``objs`` (one object or a list), the first one active."""
    objs = list(objs) if isinstance(objs, (list, tuple)) else [objs]
    for other in view_layer.objects:
        if other.select_get(view_layer=view_layer):
            other.select_set(False, view_layer=view_layer)
    for obj in objs:
        obj.select_set(True, view_layer=view_layer)
    view_layer.objects.active = objs[0]



def read_blocks(image, per_row, texels, count):
    """Irradiance E = pi x texel of the first ``count`` blocks of a bake image, (count, texels^2, 3),
    blocks laid out row by row, ``per_row`` to a row (as ``build_sensor`` lays them)."""
    res = per_row * texels
    pixels = np.empty(res * res * 4, np.float32)
    image.pixels.foreach_get(pixels)
    blocks = pixels.reshape(per_row, texels, per_row, texels, 4)[..., :3].astype(np.float64)
    b = np.arange(count)
    return math.pi * blocks[b // per_row, :, b % per_row, :, :].reshape(count, texels * texels, 3)


def run_bake(scene, view_layer, obj):
    """One Cycles bake of the sensor object(s) (a function of its own so tests can make it fail).

    ``obj``: one sensor object or a list of them; all are baked in one call, each into its own
    image (one scene sync).

    Every operator option is passed explicitly: an option left out is taken from the scene's bake
    settings, so a user's "Selected to Active" (measured: "No valid selected objects"), cage, ray
    distance, external saving or split materials would change what is baked. View-layer material
    and world overrides and holdout/indirect-only collections are switched off around the bake
    (a world override changed a reading by +2 %) and restored afterwards.
    """
    from . import render_settings
    from ..blender.op_reports import operator_reports_dropped

    objs = list(obj) if isinstance(obj, (list, tuple)) else [obj]
    obj = objs[0]
    active_uv = obj.data.uv_layers.active
    uv_layer = active_uv.name if active_uv is not None else ""  # "": the operator's own choice (and error)
    with render_settings.layer_overrides_suspended(scene), operator_reports_dropped(), \
            bpy.context.temp_override(scene=scene, view_layer=view_layer, active_object=obj,
                                      object=obj, selected_objects=objs, selected_editable_objects=objs):
        return bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"}, margin=0,
                                   margin_type="EXTEND", use_clear=True, target="IMAGE_TEXTURES",
                                   save_mode="INTERNAL", use_selected_to_active=False, use_cage=False,
                                   cage_extrusion=0.0, max_ray_distance=0.0, normal_space="TANGENT",
                                   use_split_materials=False, use_automatic_name=False, uv_layer=uv_layer)


def bake_irradiance(scene, view_layer, points, normals, *, samples, texels=4, bakes=1, progress=None,
                    cancelled=None, seed0=0):
    """Bake irradiance E (W/m^2 in the render's units, RGB) at ``points`` facing ``normals``, a fixed
    budget (the convergence study and the settings tests; error-targeted readings use
    ``measure.render.adaptive``).

    Returns ``(estimates, info)`` where ``estimates`` has shape (batches, N, 3): one independent
    estimate per texel per bake, all with the same sample count.
    """
    points = np.asarray(points, float)
    normals = np.asarray(normals, float)
    obj, image, per_row = build_sensor(scene, points, normals, texels)
    select_only(view_layer, obj)
    n = len(points)
    started = time.perf_counter()
    bake_seconds = 0.0
    samples = int(samples)
    estimates = []
    for k in range(bakes):
        if cancelled is not None and cancelled():
            raise MeasurementCancelled("measurement cancelled; the scene was restored")
        scene.cycles.seed = seed0 + k
        scene.cycles.samples = samples
        t0 = time.perf_counter()
        result = run_bake(scene, view_layer, obj)
        bake_seconds += time.perf_counter() - t0
        if result != {"FINISHED"}:
            raise RadiometerError(f"the Cycles bake did not finish ({', '.join(sorted(result))}); "
                                  "the scene was restored")
        estimates.append(read_blocks(image, per_row, texels, n).transpose(1, 0, 2))  # (t*t, n, 3)
        if progress is not None:
            progress(k + 1, bakes)
    estimates = np.concatenate(estimates, axis=0)
    info = {
        "bakes": bakes,
        "total_bakes": bakes,
        "texels_per_meter": texels * texels,
        "samples_per_texel": samples,
        "bake_seconds": bake_seconds,
        "seconds": time.perf_counter() - started,
    }
    return estimates, info

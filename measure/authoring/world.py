"""World photometry, measured: illuminance from the world alone, its brightest direction,
calibration of the Background strength, irradiance environment maps and the mirror-ball probe.

How the world is read as data (what is modelled in closed form, what is rendered) lives in
``measure/capture/world_capture.py``; this module measures with it and, where the world is not modelled,
with the meter.
"""

import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry.skies import environment
from ..capture.world_capture import read_world

# --- photometry -------------------------------------------------------------------------------------

def _scene(scene):
    import bpy

    return scene or bpy.context.scene


def world_illuminance(scene=None, normal=(0.0, 0.0, 1.0)):
    """Illuminance (lux) on a surface facing ``normal`` from the world alone (nothing blocking it).
    ``scene``: a request (``measure.blender.request``), a scene or None (the context's).

    Returns a dict: illuminance, irradiance (W/m^2, CIE-Y weighted), irradiance_rgb, method
    ("analytic" or "render"), exact, rel_error_bound, brightest_direction, brightest_radiance_rgb,
    brightest_luminance (cd/m^2), notes.
    """
    from ..blender import request as request_of
    from ..meter import point_meter as meter

    request = request_of.of(scene)
    scene = request.scene
    n = meter.as_directions(normal, 1)[0]
    space, weights, efficacy = request.photometry
    unit = request.unit_area  # world radiance is per scene unit^2 (Conventions)
    world = read_world(scene)
    notes = [f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}"] + list(world.notes)
    if world.modelled:
        e_rgb, err = world.irradiance(n)
        e_rgb, err = e_rgb / unit, err / unit
        d, value = world.brightest(weights)
        e = float(e_rgb @ weights)
        bound = float(np.abs(err) @ np.abs(weights))
        notes.append(f"world {world.kind}: E = integral of L cos(theta) d omega computed from the "
                     + ("image's pixels" if world.kind == "equirect" else "closed form") + "; nothing rendered")
        return {"illuminance": efficacy * e, "irradiance": e, "irradiance_rgb": tuple(map(float, e_rgb)),
                "method": "analytic", "exact": bool(world.exact), "rel_error_bound": bound / abs(e) if e else 0.0,
                "brightest_direction": tuple(map(float, d)), "brightest_radiance_rgb": tuple(map(float, value / unit)),
                "brightest_luminance": float(efficacy * (value / unit) @ weights), "kind": world.kind,
                "strength": world.strength, "notes": notes}
    reading = _render_world_alone(request, n)
    notes += [f"world not modelled ({world.reason}): rendered alone (no lights, no geometry)"]
    return {"illuminance": reading.illuminance, "irradiance": reading.irradiance,
            "irradiance_rgb": reading.irradiance_rgb, "method": "render", "exact": False,
            "rel_error_bound": reading.rel_std_error, "brightest_direction": None, "brightest_radiance_rgb": None,
            "brightest_luminance": None, "kind": None, "strength": world.strength, "notes": notes}


def _render_world_alone(request, n):
    """Render the world's light on a sensor in a temporary empty scene that shares the world (at the
    "standard" quality, seed 0: the request's photometry, not its budget)."""
    from ..meter import point_meter as meter
    from ..blender.temporary_scene import temporary_scene

    with temporary_scene("radiometer_world_alone", like=request.scene) as rig:
        alone = request.but(scene=rig.scene, quality="standard", target_rel_error=None, samples=None,
                            time_budget_s=None, target_abs_error=None, seed=0, progress=None, cancelled=None)
        return meter.measure_illuminance((0.0, 0.0, 0.0), tuple(n), alone, method="render")


def calibrate_world(scene=None, illuminance_lux=None, normal=(0.0, 0.0, 1.0)):
    """Set the Background strength so that the world alone gives ``illuminance_lux`` on ``normal``.

    The world's light is linear in the Background strength. Returns a dict with the old and new
    strength, the illuminance before and after, and notes. The operator wraps it in an undo step.
    ``scene``: a request, a scene or None (the context's).
    """
    from ..blender import request as request_of

    request = request_of.of(scene)
    scene = request.scene
    try:
        target = float(illuminance_lux)
    except (TypeError, ValueError):
        raise RadiometerError(f"illuminance must be a number of lux, got {illuminance_lux!r}") from None
    if not (target > 0 and math.isfinite(target)):
        raise RadiometerError(f"illuminance must be > 0 lux, got {illuminance_lux!r}")
    world = read_world(scene)
    tree = scene.world.node_tree if scene.world is not None else None
    node = tree.nodes.get(world.node) if (tree is not None and world.node) else None
    if node is None or node.bl_idname != "ShaderNodeBackground" or node.inputs["Strength"].is_linked:
        raise RadiometerError("cannot calibrate: the world needs a Background node with an unlinked Strength "
                              f"({world.reason or 'no Background node'})")
    before = world_illuminance(request, normal)
    if not before["illuminance"] > 0:
        raise RadiometerError("cannot calibrate a black world (it gives 0 lux at any strength)")
    old = float(node.inputs["Strength"].default_value)
    new = old * target / before["illuminance"]
    node.inputs["Strength"].default_value = new
    after = world_illuminance(request, normal)
    return {"old_strength": old, "new_strength": new, "illuminance_before": before["illuminance"],
            "illuminance_after": after["illuminance"], "target": target, "method": after["method"],
            "notes": [f"Background {node.name!r} strength {old:g} -> {new:g} so the world alone gives "
                      f"{target:g} lx on a surface facing {tuple(np.round(normal, 6))} ({after['method']})"]}


# --- irradiance environment maps -----------------------------------------------------------------

def irradiance_environment_map(source, path, *, method="exact", resolution=(64, 32), scene=None):
    """Write the irradiance environment map of ``source`` (EXR path, RadianceMap, or "world"/a
    scene) to ``path`` (32-bit EXR, W/m^2 per pixel = E for the pixel's direction as normal);
    returns a dict with path, coefficients (9 x RGB), sh9 error and bound, notes."""
    import os

    from ..blender import exr

    rotation, notes = None, []
    unit = 1.0
    if isinstance(source, str) and source != "world":
        lmap, rotation = exr.read_rgb(os.path.abspath(source)), environment.RADIANCE_MAP_ROTATION
        notes.append(f"source: radiance map {source} (capture_radiance_map orientation)")
    elif hasattr(source, "path") and hasattr(source, "irradiance_for"):
        lmap, rotation = exr.read_rgb(source.path), environment.RADIANCE_MAP_ROTATION
        notes.append(f"source: radiance map {source.path}")
    else:
        import bpy

        from ..blender import request as request_of

        request = request_of.of(source if isinstance(source, bpy.types.Scene) else scene)
        scene = request.scene
        world = read_world(scene)
        if not world.modelled:
            raise RadiometerError(f"the world is not modelled ({world.reason}); capture a radiance map "
                                  "(capture_radiance_map) and pass it instead")
        lmap, rotation = world.as_map()
        if world.kind == "equirect":
            lmap = world.sampled_map()
        unit = request.unit_area
        notes.append(f"source: the world of scene {scene.name!r} ({world.kind}); output in the Environment "
                     "Texture orientation, so it can be used as one")
    width, height = (int(v) for v in resolution)
    if width < 1 or height < 1:
        raise RadiometerError(f"resolution must be two positive integers, got {resolution}")
    if method not in ("exact", "sh9"):
        raise RadiometerError(f"method must be 'exact' or 'sh9', got {method!r}")
    out = environment.irradiance_map(lmap / unit, rotation, resolution=(width, height), method=method)
    path = os.path.abspath(path)
    if not os.path.isdir(os.path.dirname(path)):
        raise RadiometerError(f"cannot write {path}: its folder does not exist")
    write_exr(path, out["map"])
    coeffs = out["coefficients"]
    notes.append(f"SH9 bound |E9 - E| <= 3/32 x integral of L = {out['sh9_bound'].max():.6g} W/m^2 "
                 "(Ramamoorthi & Hanrahan 2001; 9.4 % of a point source's peak)")
    if "sh9_error" in out:
        notes.append(f"SH9 measured max |E9 - E_exact| = {out['sh9_error'].max():.6g} W/m^2 over the output pixels")
    return {"path": path, "method": method, "resolution": (width, height),
            "coefficients": {name: tuple(map(float, coeffs[i])) for i, name in enumerate(environment.SH9_NAMES)},
            "sh9_error": None if "sh9_error" not in out else tuple(map(float, out["sh9_error"])),
            "sh9_bound": tuple(map(float, out["sh9_bound"])), "max_irradiance": float(np.max(out["map"])),
            "notes": notes}


def write_exr(path, rgb):
    """32-bit float RGBA EXR (OpenEXR module), top row first."""
    try:
        import OpenEXR
    except ImportError:
        raise RadiometerError("writing EXR needs the OpenEXR module (pip install OpenEXR)") from None
    rgb = np.asarray(rgb, np.float32)
    rgba = np.concatenate([rgb, np.ones(rgb.shape[:2] + (1,), np.float32)], axis=-1)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    from ...outputs import atomic_output, shown

    # Whole or not at all (issue 21): a temp file beside it, renamed; a full disk is an error.
    with atomic_output(path) as tmp:
        try:
            with OpenEXR.File(header, {"RGBA": rgba}) as f:
                f.write(tmp)
        except Exception as exc:  # noqa: BLE001 - one line for the user
            raise RadiometerError(f"cannot write {shown(path)}: {str(exc).splitlines()[0] if str(exc) else exc}") from None
    return path


# --- the mirror-sphere light probe ----------------------------------------------------------------

def render_mirror_ball(scene=None, *, size=128, samples=16, view=(0.0, -1.0, 0.0)):
    """Render the classic light probe: an ideal chrome ball (Glossy BSDF, roughness 0, colour 1: no
    Fresnel) lit by the scene's world alone, seen by an orthographic camera looking along ``view``
    from outside, framed to the ball. Returns (probe (size, size, 3) radiance, camera rotation (3, 3)
    camera local -> world). Everything is built in a temporary scene that shares the world."""
    import bmesh
    import bpy
    from mathutils import Vector

    from ...compat import ensure_node_tree
    from ..meter.camera import render_exr
    from ..blender.temporary_scene import temporary_scene

    scene = _scene(scene)
    with temporary_scene("radiometer_probe") as rig:
        temp = rig.scene
        temp.world = scene.world
        temp.cycles.device = "CPU"
        temp.cycles.samples = int(samples)
        temp.cycles.use_denoising = False
        temp.cycles.use_adaptive_sampling = False
        temp.cycles.sample_clamp_direct = temp.cycles.sample_clamp_indirect = 0.0
        temp.cycles.blur_glossy = 0.0
        temp.cycles.max_bounces = temp.cycles.glossy_bounces = 1
        temp.cycles.pixel_filter_type = "BOX"
        temp.cycles.filter_width = 0.01
        temp.view_settings.view_transform = "Standard"
        mesh = rig.keep(bpy.data.meshes.new("radiometer_probe_ball"))
        bm = bmesh.new()
        bmesh.ops.create_uvsphere(bm, u_segments=256, v_segments=128, radius=1.0)
        for f in bm.faces:
            f.smooth = True
        bm.to_mesh(mesh)
        bm.free()
        mat = rig.keep(bpy.data.materials.new("radiometer_probe_chrome"))
        tree = ensure_node_tree(mat)
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
        glossy.inputs["Roughness"].default_value = 0.0
        glossy.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        tree.links.new(glossy.outputs["BSDF"], out.inputs["Surface"])
        mesh.materials.append(mat)
        rig.link(bpy.data.objects.new("radiometer_probe_ball", mesh))
        cam_data = rig.keep(bpy.data.cameras.new("radiometer_probe_camera"))
        cam_data.type = "ORTHO"
        cam_data.ortho_scale = 2.0
        cam_data.clip_start, cam_data.clip_end = 1e-3, 100.0
        cam = rig.link(bpy.data.objects.new("radiometer_probe_camera", cam_data))
        v = Vector(view).normalized()
        cam.location = -10.0 * v
        cam.rotation_mode = "QUATERNION"
        cam.rotation_quaternion = v.to_track_quat("-Z", "Z" if abs(v.z) < 0.99 else "Y")
        temp.camera = cam
        probe = render_exr(temp, rig.scratch(), "probe", int(size), int(size))
        rotation = np.array(cam.rotation_quaternion.to_matrix(), float)
        return probe, rotation

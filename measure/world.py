"""The scene's world as Cycles renders it, as pure data (``radiometry.environment.WorldLight``), and
world photometry: illuminance from the world alone, its brightest direction, calibration.

Modelled (closed form, nothing rendered):
* a Background node with unlinked Color and Strength: radiance = strength x colour everywhere;
* Background <- Environment Texture (equirectangular) of an image, optionally through a Mapping
  node (rotation; uniform scale; no translation) fed by Texture Coordinate > Generated: the
  image's pixels x strength, oriented as Cycles looks them up (``environment.BLENDER_WORLD_ROTATION``,
  measured by rendering in tests/bpy/test_world.py);
* no world, a black Background, or a world invisible to diffuse rays: black.
Anything else (Sky Texture, gradients and other node chains, mirror-ball projection, cubic
interpolation, colour spaces other than the working space / Non-Color / 8-bit sRGB, volumes) is
"not modelled" with the reason, and is rendered.
"""

import math

import numpy as np

from ..errors import RadiometerError
from ..radiometry import environment

#: Above this many supersampled pixels, 'Linear' interpolation is integrated on the pixels alone.
MAX_SUPERSAMPLED_PIXELS = 8_000_000


def _follow(socket):
    """The node feeding ``socket`` (through reroutes), or None; raises for muted links."""
    if not socket.is_linked:
        return None, None
    link = socket.links[0]
    if getattr(link, "is_muted", False) or not getattr(link, "is_valid", True):
        return "muted", None
    node = link.from_node
    while node.bl_idname == "NodeReroute":
        if not node.inputs[0].is_linked:
            return None, None
        link = node.inputs[0].links[0]
        node = link.from_node
    return node, link.from_socket


def _not_modelled(reason, node="", strength=1.0):
    return environment.WorldLight(None, reason=reason, node=node, strength=strength)


def _mapping_rotation(node):
    """Orthogonal A with texture direction t ~ A d for world direction d, or a reason string."""
    from mathutils import Euler

    for name in ("Location", "Rotation", "Scale"):
        sock = node.inputs.get(name)
        if sock is not None and sock.is_linked:
            return f"the Mapping node's {name} is linked"
    kind = node.vector_type
    rot = np.array(Euler(tuple(node.inputs["Rotation"].default_value), "XYZ").to_matrix(), float)
    scale = np.array(node.inputs["Scale"].default_value, float)
    loc = np.array(node.inputs["Location"].default_value, float) if "Location" in node.inputs else np.zeros(3)
    if not (np.all(scale == scale[0]) and scale[0] != 0.0):
        return f"the Mapping node's scale {tuple(scale)} is not uniform (it distorts directions)"
    if kind in ("POINT", "TEXTURE") and np.any(loc != 0.0):
        return "the Mapping node translates the direction (Location is not 0)"
    sign = math.copysign(1.0, scale[0])
    if kind == "TEXTURE":
        return sign * rot.T
    return sign * rot  # POINT, VECTOR, NORMAL (normalised afterwards): t ~ R (s d)


def _image_pixels(image):
    """(H, W, 4) float64, top row first, or a reason string."""
    if image is None:
        # Measuring Cycles' magenta stand-in would be a wrong number without an error (issue 21).
        raise RadiometerError("the world's Environment Texture has no image (Cycles renders it magenta): "
                              "open an image in it or remove the node")
    w, h = image.size[:]
    if not image.has_data:
        try:
            image.pixels[0]  # loads the file
        except Exception:  # noqa: BLE001 - any failure means Cycles cannot read it either
            pass
        w, h = image.size[:]
    if w == 0 or h == 0:
        from ..outputs import shown

        raise RadiometerError(f"the world's image {image.name!r} cannot be loaded "
                              f"({shown(image.filepath) if image.filepath else 'no file'}: missing, unreadable or "
                              "empty); Cycles would render a magenta placeholder, so it is not measured")
    px = np.empty(w * h * image.channels, np.float32)
    image.pixels.foreach_get(px)
    px = px.reshape(h, w, image.channels)[::-1].astype(np.float64)
    if image.channels == 1:
        px = np.concatenate([np.repeat(px, 3, axis=2), np.ones((h, w, 1))], axis=2)
    elif image.channels == 3:
        px = np.concatenate([px, np.ones((h, w, 1))], axis=2)
    return px


def _srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _image_radiance(image, working_space):
    """(H, W, 3) linear RGB in the working space as Cycles reads it, or a reason string."""
    px = _image_pixels(image)
    if isinstance(px, str):
        return px
    space = image.colorspace_settings.name
    rgb = px[..., :3]
    if not np.all(np.isfinite(rgb)):
        bad = int(np.count_nonzero(~np.isfinite(rgb).all(axis=-1)))
        raise RadiometerError(f"the world's image {image.name!r} has {bad} pixel(s) that are NaN or infinite: "
                              "no finite reading exists; fix or clamp the image")
    if space in ("Non-Color", working_space):
        pass
    elif space == "sRGB" and working_space == "Linear Rec.709" and not image.is_float:
        rgb = _srgb_to_linear(rgb)
    else:
        return f"the image's colour space {space!r} is not modelled (working space {working_space!r})"
    if image.alpha_mode not in ("NONE", "CHANNEL_PACKED") and np.any(px[..., 3] < 1.0):
        return f"the image {image.name!r} has alpha < 1 (Cycles' alpha handling is not modelled)"
    return rgb


def read_world(scene):
    """The world of ``scene`` as a ``WorldLight`` (see the module docstring)."""
    from ..compat import active_node_tree

    world = scene.world
    if world is None:
        return environment.WorldLight("black", np.zeros(3), reason="no world")
    vis = getattr(world, "cycles_visibility", None)
    if vis is not None and not getattr(vis, "diffuse", True):
        return environment.WorldLight("black", np.zeros(3), notes=["world invisible to diffuse rays: no light on a diffuse sensor"])
    tree = active_node_tree(world)
    if "radiometer_cie_sky" in world.keys():  # a Radiometer CIE sky (measure/sky.py): exact while unedited
        from . import sky

        found = sky.read_sky_world(world, tree)
        return _not_modelled(found) if isinstance(found, str) else found
    if tree is None:
        return environment.WorldLight("constant", np.array(world.color[:3], float), node="")
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    output = next((n for n in outputs if n.is_active_output and getattr(n, "target", "ALL") in ("ALL", "CYCLES")), None)
    output = output or (outputs[0] if outputs else None)
    if output is None:
        return environment.WorldLight("black", np.zeros(3), reason="the world has no World Output")
    if output.inputs["Volume"].is_linked:
        return _not_modelled("the world has a volume")
    src, _sock = _follow(output.inputs["Surface"])
    if src is None:
        return environment.WorldLight("black", np.zeros(3), reason="nothing linked to the World Output")
    if src == "muted" or src.mute:
        return _not_modelled("a muted node or link feeds the World Output")
    if src.bl_idname != "ShaderNodeBackground":
        return _not_modelled(f"the world's surface is a {src.bl_label!r} node, not a Background")
    colour, strength_in = src.inputs["Color"], src.inputs["Strength"]
    if strength_in.is_linked:
        return _not_modelled("the Background's Strength is linked", node=src.name)
    strength = float(strength_in.default_value)
    if not math.isfinite(strength):
        raise RadiometerError(f"the world's Background strength is not finite ({strength}): give it a real value")
    feed, feed_socket = _follow(colour)
    if feed is None:
        value = np.array(colour.default_value[:3], float)
        return environment.WorldLight("constant", strength * value, node=src.name, strength=strength)
    if feed == "muted" or feed.mute:
        return _not_modelled("a muted node or link feeds the Background colour", src.name, strength)
    if feed.bl_idname == "ShaderNodeTexSky":
        return _not_modelled("Sky Texture: its sky and sun are computed inside Cycles; rendered", src.name, strength)
    if feed.bl_idname != "ShaderNodeTexEnvironment" or feed_socket.name != "Color":
        return _not_modelled(f"the Background colour comes from a {feed.bl_label!r} node", src.name, strength)
    if feed.projection != "EQUIRECTANGULAR":
        return _not_modelled(f"Environment Texture projection {feed.projection} is not modelled", src.name, strength)
    if feed.interpolation not in ("Closest", "Linear"):
        return _not_modelled(f"Environment Texture interpolation {feed.interpolation!r} is not modelled "
                             "(Closest and Linear are)", src.name, strength)
    rotation = np.eye(3)
    notes = []
    vec, _vs = _follow(feed.inputs["Vector"])
    if vec == "muted":
        return _not_modelled("a muted link feeds the Environment Texture vector", src.name, strength)
    if vec is not None:
        if vec.bl_idname != "ShaderNodeMapping":
            return _not_modelled(f"the Environment Texture vector comes from a {vec.bl_label!r} node", src.name, strength)
        a = _mapping_rotation(vec)
        if isinstance(a, str):
            return _not_modelled(a, src.name, strength)
        coord, coord_sock = _follow(vec.inputs["Vector"])
        if coord is None or coord == "muted" or coord.bl_idname != "ShaderNodeTexCoord" or coord_sock.name != "Generated":
            return _not_modelled("the Mapping node is not fed by Texture Coordinate > Generated", src.name, strength)
        rotation = a
        notes.append(f"Mapping node {vec.name!r} ({vec.vector_type}) rotates the image")
    working = bpy_working_space()
    radiance = _image_radiance(feed.image, working)
    if isinstance(radiance, str):
        return _not_modelled(radiance, src.name, strength)
    h, w = radiance.shape[:2]
    # t = A d  =>  d = A^T t, and t = BLENDER_WORLD_ROTATION @ local.
    total = rotation.T @ environment.BLENDER_WORLD_ROTATION
    factor = 1
    if feed.interpolation == "Linear":
        factor = next((f for f in (4, 2) if f * f * h * w <= MAX_SUPERSAMPLED_PIXELS), 1)
        notes.append("Linear interpolation: the integral of Cycles' bilinear interpolant, by the midpoint rule on "
                     f"{factor} x {factor} sub-pixels (error estimated by Richardson, factor {factor // 2} vs {factor})"
                     if factor > 1 else
                     f"Linear interpolation on a {w}x{h} image: the pixel sum is used (differs from the bilinear "
                     f"interpolant by O((pi/{h})^2))")
    return environment.WorldLight("equirect", radiance * strength, total, exact=feed.interpolation == "Closest",
                                  notes=notes, strength=strength, node=src.name, interpolation=feed.interpolation,
                                  image=feed.image.name, supersample=factor)


def bpy_working_space():
    from ..compat import working_colour_space  # one home for the scene's colour space

    return working_colour_space()


# --- photometry -------------------------------------------------------------------------------------

def _scene(scene):
    import bpy

    return scene or bpy.context.scene


def world_illuminance(scene=None, normal=(0.0, 0.0, 1.0)):
    """Illuminance (lux) on a surface facing ``normal`` from the world alone (nothing blocking it).

    Returns a dict: illuminance, irradiance (W/m^2, CIE-Y weighted), irradiance_rgb, method
    ("analytic" or "render"), exact, rel_error_bound, brightest_direction, brightest_radiance_rgb,
    brightest_luminance (cd/m^2), notes.
    """
    from . import meter

    scene = _scene(scene)
    n = meter.as_directions(normal, 1)[0]
    space, weights, efficacy = meter.scene_photometry(scene)
    unit = scene.unit_settings.scale_length ** 2  # world radiance is per scene unit^2 (Conventions)
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
    reading = _render_world_alone(scene, n)
    notes += [f"world not modelled ({world.reason}): rendered alone (no lights, no geometry)"]
    return {"illuminance": reading.illuminance, "irradiance": reading.irradiance,
            "irradiance_rgb": reading.irradiance_rgb, "method": "render", "exact": False,
            "rel_error_bound": reading.rel_std_error, "brightest_direction": None, "brightest_radiance_rgb": None,
            "brightest_luminance": None, "kind": None, "strength": world.strength, "notes": notes}


def _render_world_alone(scene, n, quality="standard"):
    """Render the world's light on a sensor in a temporary empty scene that shares the world."""
    import bpy

    from . import meter

    temp = bpy.data.scenes.new("radiometer_world_alone")
    try:
        temp.world = scene.world
        temp.render.engine = "CYCLES"
        temp.unit_settings.scale_length = scene.unit_settings.scale_length
        src, dst = getattr(scene, "radiometer", None), getattr(temp, "radiometer", None)
        if src is not None and dst is not None:
            dst.efficacy_convention = src.efficacy_convention
            dst.efficacy = src.efficacy
        return meter.measure_illuminance((0.0, 0.0, 0.0), tuple(n), scene=temp, method="render", quality=quality)
    finally:
        bpy.data.scenes.remove(temp)


def calibrate_world(scene=None, illuminance_lux=None, normal=(0.0, 0.0, 1.0)):
    """Set the Background strength so that the world alone gives ``illuminance_lux`` on ``normal``.

    The world's light is linear in the Background strength. Returns a dict with the old and new
    strength, the illuminance before and after, and notes. The operator wraps it in an undo step.
    """
    scene = _scene(scene)
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
    before = world_illuminance(scene, normal)
    if not before["illuminance"] > 0:
        raise RadiometerError("cannot calibrate a black world (it gives 0 lux at any strength)")
    old = float(node.inputs["Strength"].default_value)
    new = old * target / before["illuminance"]
    node.inputs["Strength"].default_value = new
    after = world_illuminance(scene, normal)
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

    from . import exr

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

        scene = source if isinstance(source, bpy.types.Scene) else _scene(scene)
        world = read_world(scene)
        if not world.modelled:
            raise RadiometerError(f"the world is not modelled ({world.reason}); capture a radiance map "
                                  "(capture_radiance_map) and pass it instead")
        lmap, rotation = world.as_map()
        if world.kind == "equirect":
            lmap = world.sampled_map()
        unit = scene.unit_settings.scale_length ** 2
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
    from ..outputs import atomic_output, shown

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
    import os
    import shutil
    import tempfile

    import bpy
    from mathutils import Vector

    from . import exr

    scene = _scene(scene)
    temp = bpy.data.scenes.new("radiometer_probe")
    created = []
    folder = tempfile.mkdtemp(prefix="radiometer_probe_")
    try:
        temp.world = scene.world
        temp.render.engine = "CYCLES"
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
        mesh = bpy.data.meshes.new("radiometer_probe_ball")
        created.append(mesh)
        import bmesh

        bm = bmesh.new()
        bmesh.ops.create_uvsphere(bm, u_segments=256, v_segments=128, radius=1.0)
        for f in bm.faces:
            f.smooth = True
        bm.to_mesh(mesh)
        bm.free()
        mat = bpy.data.materials.new("radiometer_probe_chrome")
        created.append(mat)
        from ..compat import ensure_node_tree

        tree = ensure_node_tree(mat)
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
        glossy.inputs["Roughness"].default_value = 0.0
        glossy.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        tree.links.new(glossy.outputs["BSDF"], out.inputs["Surface"])
        mesh.materials.append(mat)
        ball = bpy.data.objects.new("radiometer_probe_ball", mesh)
        created.append(ball)
        temp.collection.objects.link(ball)
        cam_data = bpy.data.cameras.new("radiometer_probe_camera")
        created.append(cam_data)
        cam_data.type = "ORTHO"
        cam_data.ortho_scale = 2.0
        cam_data.clip_start, cam_data.clip_end = 1e-3, 100.0
        cam = bpy.data.objects.new("radiometer_probe_camera", cam_data)
        created.append(cam)
        temp.collection.objects.link(cam)
        v = Vector(view).normalized()
        cam.location = -10.0 * v
        cam.rotation_mode = "QUATERNION"
        cam.rotation_quaternion = v.to_track_quat("-Z", "Z" if abs(v.z) < 0.99 else "Y")
        temp.camera = cam
        r = temp.render
        r.resolution_x = r.resolution_y = int(size)
        r.resolution_percentage = 100
        r.image_settings.file_format = "OPEN_EXR"
        r.image_settings.color_depth = "32"
        r.filepath = os.path.join(folder, "probe")
        r.use_file_extension = True
        bpy.ops.render.render(write_still=True, scene=temp.name)
        probe = exr.read_rgb(os.path.join(folder, "probe.exr"))
        rotation = np.array(cam.rotation_quaternion.to_matrix(), float)
        return probe, rotation
    finally:
        bpy.data.scenes.remove(temp)
        for block in reversed(created):
            collection = {bpy.types.Object: bpy.data.objects, bpy.types.Mesh: bpy.data.meshes,
                          bpy.types.Material: bpy.data.materials, bpy.types.Camera: bpy.data.cameras}[type(block)]
            collection.remove(block)
        shutil.rmtree(folder, ignore_errors=True)

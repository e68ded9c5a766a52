"""The scene's world read as pure data (``radiometry.skies.environment.WorldLight``, or
``radiometry.skies.cie_sky.CIESkyWorld`` for a Radiometer CIE sky): what the scene capture needs, and
nothing that measures (``measure/authoring/world.py`` measures the world with the meter; ``measure/authoring/sky.py``
builds CIE sky worlds). Host code: reads node trees and images through bpy, renders nothing.

Modelled (closed form, nothing rendered):
* a Background node with unlinked Color and Strength: radiance = strength x colour everywhere;
* Background <- Environment Texture (equirectangular) of an image, optionally through a Mapping
  node (rotation; uniform scale; no translation) fed by Texture Coordinate > Generated: the
  image's pixels x strength, oriented as Cycles looks them up (``environment.BLENDER_WORLD_ROTATION``,
  measured by rendering in tests/bpy/test_world.py);
* a CIE sky world built by ``measure.authoring.sky.set_cie_sky`` whose nodes are as built (tag + fingerprint);
* no world, a black Background, or a world invisible to diffuse rays: black.
Anything else (Sky Texture, gradients and other node chains, mirror-ball projection, cubic
interpolation, colour spaces other than the working space / Non-Color / 8-bit sRGB, volumes) is
"not modelled" with the reason, and is rendered.
"""

import hashlib
import json
import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry.skies import environment, sky_models

#: The custom property on a World that ``measure.authoring.sky.set_cie_sky`` writes (JSON parameters + fingerprint).
CIE_SKY_TAG = "radiometer_cie_sky"
CIE_SKY_SCHEMA = 1

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
        from ...outputs import shown

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
    from ...compat import active_node_tree

    world = scene.world
    if world is None:
        return environment.WorldLight("black", np.zeros(3), reason="no world")
    vis = getattr(world, "cycles_visibility", None)
    if vis is not None and not getattr(vis, "diffuse", True):
        return environment.WorldLight("black", np.zeros(3), notes=["world invisible to diffuse rays: no light on a diffuse sensor"])
    tree = active_node_tree(world)
    if CIE_SKY_TAG in world.keys():  # a Radiometer CIE sky (measure/authoring/sky.py made it): exact while unedited
        found = read_sky_world(world, tree)
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
    from ...compat import working_colour_space  # one home for the scene's colour space

    return working_colour_space()



# --- Radiometer CIE sky worlds -------------------------------------------------------------------

def sky_fingerprint(tree):
    """A hash of every node (type, operation, mute, unlinked input values) and link of ``tree``."""
    items = []
    for node in sorted(tree.nodes, key=lambda n: n.name):
        entry = [node.name, node.bl_idname, getattr(node, "operation", ""), bool(node.mute),
                 getattr(node, "is_active_output", None), getattr(node, "target", None),
                 bool(getattr(node, "use_clamp", False))]
        for sock in node.inputs:
            value = getattr(sock, "default_value", None)
            if value is not None and not sock.is_linked:
                value = [round(float(v), 12) for v in value] if hasattr(value, "__len__") else round(float(value), 12)
            entry.append((sock.identifier, sock.is_linked, value, bool(getattr(sock, "enabled", True))))
        items.append(entry)
    for link in tree.links:
        items.append(("link", link.from_node.name, link.from_socket.identifier, link.to_node.name,
                      link.to_socket.identifier, bool(getattr(link, "is_muted", False))))
    items[len(tree.nodes):] = sorted(items[len(tree.nodes):], key=repr)
    return hashlib.sha256(repr(items).encode()).hexdigest()


def read_sky_world(world, tree):
    """The exact ``cie_sky.CIESkyWorld`` of a Radiometer CIE sky world, or a reason string when the
    tag is broken or the nodes were edited (then the world is rendered like any other)."""
    try:
        info = json.loads(world[CIE_SKY_TAG])
        if info.get("schema") != CIE_SKY_SCHEMA:
            return f"the CIE sky tag has schema {info.get('schema')!r}, not {CIE_SKY_SCHEMA}"
        fingerprint = info["fingerprint"]
        model = sky_models.sky_model(info["sky_type"])
        sky = model.world(np.array(info["sun_direction"], float), info["zenith_radiance"], info["ground_radiance"],
                          node="")
    except (KeyError, TypeError, ValueError) as exc:
        return f"the world's CIE sky tag cannot be read ({exc})"
    if tree is None or sky_fingerprint(tree) != fingerprint:
        return "the CIE sky world's nodes were edited after it was made (set the sky again to read it exactly)"
    bg = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeBackground"), None)
    sky.node = bg.name if bg is not None else ""
    sky.notes.append(f"{model.label}, E_h {info['horizontal_illuminance_lux']:g} lx, ground rho {info['ground_reflectance']:g}: "
                     "integrated exactly (radiometry/skies/cie_sky.py)")
    return sky

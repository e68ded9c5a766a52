"""CIE sky worlds: build a World whose shader evaluates the ISO 15469 / CIE overcast luminance formula
on the ray direction (``radiometry.skies.cie_sky``), and mark it so that the meter recognises it.

The world's node tree: Texture Coordinate > Generated (the ray direction in world shaders) >
Normalize > math nodes computing the sky luminance (as radiance, W/(m^2 sr) per scene unit^2:
luminance / luminous efficacy x scale_length^2) above the horizon and the uniform ground radiance
below a sharp horizon (cos Z > 0), into a Background's Strength with a white colour. The parameters
are stored on the world as the custom property ``radiometer_cie_sky`` (JSON) with a fingerprint of
the node tree: ``read_sky_world`` returns the exact ``cie_sky.CIESkyWorld`` only while the tree is
exactly as built, and "not modelled" (rendered) once the user has edited it. Reading such a world
(``read_sky_world``, the tag and the fingerprint) lives in ``measure/capture/world_capture.py``.
"""

import json
import math

from ...errors import RadiometerError
from ...radiometry.skies import cie_sky, sky_models
from ..capture.world_capture import CIE_SKY_SCHEMA, CIE_SKY_TAG, sky_fingerprint


def math_socket(tree, op, a=None, b=None, c=None, x=0):
    """A Math node ``op`` in ``tree`` on up to three inputs (numbers, or sockets linked in; None left as is);
    returns its output socket (its node: ``.node``)."""
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = op
    node.location = (x, -60 * len(tree.nodes))
    for i, v in enumerate((a, b, c)):
        if v is None:
            continue
        if isinstance(v, (int, float)):
            node.inputs[i].default_value = float(v)
        else:
            tree.links.new(v, node.inputs[i])
    return node.outputs[0]


def sky_radiance(tree, direction, sky_type, sun, zenith_radiance, ground_radiance):
    """Nodes in ``tree`` giving the sky's radiance for the ``direction`` socket (any length; normalised
    here): zenith_radiance x L/Lz above the horizon, ground_radiance below. Returns (the radiance socket,
    the unit direction socket, its z socket: the cosine of the zenith angle). Shared by the world (``build_sky_tree``) and the openings' emitters
    (``opening_emitter_material``) so that both evaluate one formula; the world's nodes come out as
    before (names, order and links: its fingerprint, measured equal for overcast and types 1, 5, 12, 15)."""
    norm = tree.nodes.new("ShaderNodeVectorMath")
    norm.operation = "NORMALIZE"
    norm.location = (-700, 0)
    tree.links.new(direction, norm.inputs[0])
    sep = tree.nodes.new("ShaderNodeSeparateXYZ")
    sep.location = (-500, 0)
    tree.links.new(norm.outputs["Vector"], sep.inputs[0])
    direction, cos_z = norm.outputs["Vector"], sep.outputs["Z"]
    params = cie_sky.parameters(sky_type)
    if params is None:  # traditional overcast: Lz (1 + 2 cos Z) / 3
        sky = math_socket(tree, "MULTIPLY_ADD", cos_z, 2.0 * zenith_radiance / 3.0, zenith_radiance / 3.0)
    else:
        a, b, c, d, e = params
        zeta = float(cie_sky.zenith_shape(cie_sky.parse_sky_type(sky_type), sun))
        k = zenith_radiance / zeta
        cz = math_socket(tree, "MAXIMUM", cos_z, 1e-6)
        phi = math_socket(tree, "MULTIPLY_ADD",
                          math_socket(tree, "EXPONENT", math_socket(tree, "DIVIDE", b, cz)), a, 1.0)
        if c == 0.0 and e == 0.0:
            sky = math_socket(tree, "MULTIPLY", phi, k)
        else:
            dot = tree.nodes.new("ShaderNodeVectorMath")
            dot.operation = "DOT_PRODUCT"
            dot.location = (-500, -300)
            tree.links.new(direction, dot.inputs[0])
            dot.inputs[1].default_value = tuple(float(v) for v in sun)
            cos_chi = math_socket(tree, "MAXIMUM", math_socket(tree, "MINIMUM", dot.outputs["Value"], 1.0), -1.0)
            chi = math_socket(tree, "ARCCOSINE", cos_chi)
            ind = math_socket(tree, "MULTIPLY_ADD",
                              math_socket(tree, "EXPONENT", math_socket(tree, "MULTIPLY", chi, d)), c,
                              1.0 - c * math.exp(d * math.pi / 2))
            f = math_socket(tree, "MULTIPLY_ADD", math_socket(tree, "MULTIPLY", cos_chi, cos_chi), e, ind)
            sky = math_socket(tree, "MULTIPLY", math_socket(tree, "MULTIPLY", f, phi), k)
    above = math_socket(tree, "GREATER_THAN", cos_z, 0.0)
    value = math_socket(tree, "MULTIPLY_ADD", above, math_socket(tree, "SUBTRACT", sky, ground_radiance),
                        ground_radiance)
    return value, direction, cos_z


def build_sky_tree(tree, sky_type, sun, zenith_radiance, ground_radiance):
    """Fill ``tree`` (cleared) with the sky: radiance zenith_radiance x L/Lz above, ground_radiance below."""
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputWorld")
    out.location = (900, 0)
    bg = tree.nodes.new("ShaderNodeBackground")
    bg.location = (700, 0)
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(bg.outputs["Background"], out.inputs["Surface"])
    coord = tree.nodes.new("ShaderNodeTexCoord")
    coord.location = (-900, 0)
    value, _unit, _cos_z = sky_radiance(tree, coord.outputs["Generated"], sky_type, sun, zenith_radiance,
                                        ground_radiance)
    tree.links.new(value, bg.inputs["Strength"])
    return bg


def opening_emitter_material(name, info, outward, sky_only=False):
    """A new material that emits, towards the room, the radiance of the CIE sky ``info`` (the world's
    tag as ``set_cie_sky`` wrote it) that a ray leaving through an opening would meet: the sky above the
    horizon, the ground below, in the ray's direction (-Incoming, world space; the same formula as the
    world, ``sky_radiance``), and nothing for rays arriving from outside (``outward``: the opening's
    outward unit normal). Issue 31: an opening becomes a light source whose light Cycles samples by
    next-event estimation, as Radiance's mkillum does for windows.

    ``sky_only``: where a ground plane (or anything else below the opening) lies in front of it, only a ray leaving
    upwards meets the sky alone: the material emits the sky to those rays and stops them, and lets every other ray
    through (a Transparent BSDF): downwards to the ground plane, and inwards from outside."""
    import bpy

    from ...compat import ensure_node_tree

    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(emission.outputs["Emission"], out.inputs["Surface"])
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    leaving = tree.nodes.new("ShaderNodeVectorMath")
    leaving.operation = "SCALE"
    leaving.inputs["Scale"].default_value = -1.0
    tree.links.new(geometry.outputs["Incoming"], leaving.inputs[0])
    value, unit, cos_z = sky_radiance(tree, leaving.outputs["Vector"], info["sky_type"],
                                      [float(v) for v in info["sun_direction"]], info["zenith_radiance"],
                                      info["ground_radiance"])
    facing = tree.nodes.new("ShaderNodeVectorMath")
    facing.operation = "DOT_PRODUCT"
    tree.links.new(unit, facing.inputs[0])
    facing.inputs[1].default_value = tuple(float(v) for v in outward)
    leaves = math_socket(tree, "GREATER_THAN", facing.outputs["Value"], 0.0)  # rays from inside only
    if sky_only:
        leaves = math_socket(tree, "MULTIPLY", leaves, math_socket(tree, "GREATER_THAN", cos_z, 0.0))
        mix = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(leaves, mix.inputs["Fac"])
        tree.links.new(tree.nodes.new("ShaderNodeBsdfTransparent").outputs[0], mix.inputs[1])
        tree.links.new(emission.outputs["Emission"], mix.inputs[2])
        tree.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    tree.links.new(math_socket(tree, "MULTIPLY", value, leaves), emission.inputs["Strength"])
    return mat


def set_cie_sky(scene, sky_type, *, horizontal_illuminance_lux=None, sun_direction=None, ground_reflectance=0.2,
                world=None):
    """Make ``scene.world`` the CIE sky (a new world, or ``world`` rebuilt); returns a dict of what was set.
    ``scene``: a request (``measure.blender.request``: its scene, efficacy and unit scale), a scene or None.

    The unobstructed horizontal illuminance from the sky is ``horizontal_illuminance_lux`` (default
    ``cie_sky.TYPICAL_HORIZONTAL_ILLUMINANCE``); the ground below the sharp horizon has luminance
    rho_g E_h / pi. Luminance is converted to radiance with the scene's luminous efficacy (Radiometer
    settings, 683 lm/W by default) and scene units (radiance per scene unit^2).
    """
    import bpy

    from ...compat import ensure_node_tree
    from ..blender import request as request_of

    request = request_of.of(scene)
    scene = request.scene
    try:
        model = sky_models.sky_model(sky_type)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    t = model.sky_type
    e_h = cie_sky.TYPICAL_HORIZONTAL_ILLUMINANCE if horizontal_illuminance_lux is None else horizontal_illuminance_lux
    try:
        e_h = float(e_h)
        rho = float(ground_reflectance)
    except (TypeError, ValueError):
        raise RadiometerError(f"horizontal illuminance and ground reflectance must be numbers, got "
                              f"{horizontal_illuminance_lux!r}, {ground_reflectance!r}") from None
    if not (math.isfinite(e_h) and e_h > 0):
        raise RadiometerError(f"horizontal_illuminance_lux must be a finite number > 0, got {horizontal_illuminance_lux!r}")
    if not (math.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise RadiometerError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    try:
        sun = cie_sky.sun_for_sky(t, sun_direction)
        lz = e_h / float(model.sky_integral([0.0, 0.0, 1.0], sun)[0])  # Lz for E_h, any model
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    efficacy, unit = request.efficacy, request.unit_area
    lg = float(cie_sky.ground_luminance(e_h, rho))
    zr, gr = lz / efficacy * unit, lg / efficacy * unit
    name = model.label
    if world is None:
        world = bpy.data.worlds.new(name)
    tree = ensure_node_tree(world)
    build_sky_tree(tree, t, sun, zr, gr)
    info = {"schema": CIE_SKY_SCHEMA, "sky_type": t, "sun_direction": [float(v) for v in sun],
            "horizontal_illuminance_lux": e_h, "ground_reflectance": rho, "zenith_luminance": lz,
            "ground_luminance": lg, "efficacy": efficacy, "scale_length": request.scale_length,
            "zenith_radiance": zr, "ground_radiance": gr, "fingerprint": sky_fingerprint(tree)}
    world[CIE_SKY_TAG] = json.dumps(info)
    scene.world = world
    return dict(info, world=world.name, notes=[
        f"{name}: Lz = {lz:.6g} cd/m^2 for E_h = {e_h:g} lx (exact integration, radiometry/skies/cie_sky.py), "
        f"ground {lg:.6g} cd/m^2 (rho_g = {rho:g}) below a sharp horizon; luminous efficacy {efficacy:g} lm/W"])

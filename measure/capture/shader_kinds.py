"""Shader kinds: which node types make a material or world glossy, transmissive, emitting or a volume.

Read from Blender node trees (looking inside groups) by ``measure.capture.scene_capture`` to decide what the
scene needs rendered (``SceneModel.needs``) and by the render settings through it.
"""

from ...compat import active_node_tree

GLOSSY_NODES = {
    "ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfMetallic", "ShaderNodeBsdfGlass",
    "ShaderNodeBsdfRefraction", "ShaderNodeBsdfPrincipled", "ShaderNodeBsdfHairPrincipled",
    "ShaderNodeBsdfToon", "ShaderNodeBsdfSheen", "ShaderNodeScript", "ShaderNodeBsdfHair",
}
TRANSMISSIVE_NODES = {
    "ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction", "ShaderNodeBsdfTranslucent",
    "ShaderNodeBsdfTransparent", "ShaderNodeScript", "ShaderNodeBsdfRayPortal", "ShaderNodeBsdfHair",
    "ShaderNodeBsdfHairPrincipled",
}
#: A Background shader on a surface emits as Emission does (the old "shadeless" trick).
EMISSIVE_NODES = {"ShaderNodeEmission", "ShaderNodeScript", "ShaderNodeBackground"}
#: Shader nodes through which no light passes (issue 31, sealed shells): a material whose shader nodes are all
#: of these (a Principled BSDF without alpha, transmission or subsurface) stops every ray; any other shader node,
#: known or new, proves nothing (a whitelist: Ray Portal, Hair, Holdout, Subsurface, Script, ...).
SEALING_SHADERS = {
    "ShaderNodeBsdfDiffuse", "ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfMetallic",
    "ShaderNodeBsdfPrincipled", "ShaderNodeBsdfSheen", "ShaderNodeBsdfToon", "ShaderNodeEmission",
    "ShaderNodeMixShader", "ShaderNodeAddShader",
}
_SHADER_NODES = {"ShaderNodeBackground", "ShaderNodeHoldout", "ShaderNodeSubsurfaceScattering", "ShaderNodeScript",
                 "ShaderNodeEeveeSpecular", "ShaderNodeShaderToRGB"}


def is_shader_node(bl_idname):
    """True for a node that makes or combines a closure (a BSDF, emission, volume, holdout, ...)."""
    return (bl_idname.startswith(("ShaderNodeBsdf", "ShaderNodeVolume")) or bl_idname in _SHADER_NODES
            or bl_idname in SEALING_SHADERS)


def seals(types):
    """True when node types ``types`` (``node_types``) make a surface that stops every ray."""
    shaders = {t for t in types if is_shader_node(t)}
    return shaders <= SEALING_SHADERS and not types & TRANSMISSIVE_NODES
GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME", "GREASEPENCIL"}


def node_types(tree, seen=None):
    """All node type identifiers in a node tree, looking inside node groups."""
    seen = set() if seen is None else seen
    if tree is None or tree.as_pointer() in seen:
        return set()
    seen.add(tree.as_pointer())
    types = set()
    for node in tree.nodes:
        types.add(node.bl_idname)
        if node.bl_idname == "ShaderNodeGroup":
            types |= node_types(node.node_tree, seen)
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            inp = node.inputs.get("Emission Strength")
            if inp is not None and not inp.is_linked and inp.default_value > 0:
                types.add("ShaderNodeEmission")
            elif inp is not None and inp.is_linked:
                types.add("ShaderNodeEmission")
            # a Principled BSDF passes light where its alpha or transmission says so, and scatters it under the
            # surface with subsurface weight: read as those closures, inside groups too
            if _set(node, "Alpha", 1.0) or _set(node, "Transmission Weight", 0.0):
                types.add("ShaderNodeBsdfTransparent")
            if _set(node, "Subsurface Weight", 0.0):
                types.add("ShaderNodeSubsurfaceScattering")
    return types


def _set(node, name, default):
    """True when the node's input ``name`` is linked or differs from ``default``."""
    socket = node.inputs.get(name)
    return socket is not None and (socket.is_linked or socket.default_value != default)


def uses_volume(tree):
    if tree is None:
        return False
    for node in tree.nodes:
        if node.bl_idname in {"ShaderNodeOutputMaterial", "ShaderNodeOutputWorld"}:
            vol = node.inputs.get("Volume")
            if vol is not None and vol.is_linked:
                return True
    return False


def world_emits(world):
    """True unless the world is provably black (no world, or a Background of zero strength/colour)."""
    if world is None:
        return False
    tree = active_node_tree(world)
    if tree is None:  # Blender 4.x without world nodes renders the plain World.color
        return max(world.color[:3]) > 0.0
    output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld" and n.is_active_output), None)
    if output is None:
        output = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"), None)
    if output is None or not output.inputs["Surface"].is_linked:
        return False
    src = output.inputs["Surface"].links[0].from_node
    if src.bl_idname == "ShaderNodeBackground":
        colour, strength = src.inputs["Color"], src.inputs["Strength"]
        if not strength.is_linked and strength.default_value == 0.0:
            return False
        if not colour.is_linked and max(colour.default_value[:3]) == 0.0:
            return False
    return True


#: Cycles' surface for an object without a material: a Diffuse BSDF of grey 0.8.
DEFAULT_ALBEDO = (0.8, 0.8, 0.8)


def lambertian_albedo(material):
    """(albedo RGB, "") when ``material`` renders in Cycles as a Lambertian surface of one colour: its active
    output's Surface is a Diffuse BSDF straight, with an unlinked colour within 0..1, roughness 0 (Lambert:
    above 0 it is Oren-Nayar) and no normal map, or a Principled BSDF with nothing but its diffuse base
    (``PRINCIPLED_DIFFUSE_ONLY``: Specular IOR Level 0, ...), and nothing on Volume or Displacement; else (None, why).
    Issue 31: only then does the sun's light leave a sunlit surface as a Lambertian emitter's."""
    if material is None:
        return DEFAULT_ALBEDO, ""
    tree = active_node_tree(material)
    if tree is None:
        return None, f"material {material.name!r} renders without nodes"
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
               and getattr(n, "target", "ALL") in ("ALL", "CYCLES")]
    active = [n for n in outputs if getattr(n, "is_active_output", False)] or outputs[:1]
    if not active:
        return None, f"material {material.name!r} has no material output"
    out = active[0]
    for name in ("Volume", "Displacement"):
        sock = out.inputs.get(name)
        if sock is not None and sock.is_linked:
            return None, f"material {material.name!r} has a {name.lower()}"
    surface = out.inputs.get("Surface")
    if surface is None or not surface.is_linked or len(surface.links) != 1:
        return None, f"material {material.name!r}: its surface is not one shader"
    node = surface.links[0].from_node
    if node.bl_idname == "ShaderNodeBsdfPrincipled":
        return _principled_albedo(material, node)
    if node.bl_idname != "ShaderNodeBsdfDiffuse":
        return None, f"material {material.name!r} is not a Diffuse BSDF ({node.bl_idname})"
    rough = node.inputs.get("Roughness")
    if rough is not None and (rough.is_linked or float(rough.default_value) != 0.0):
        return None, f"material {material.name!r}: diffuse roughness is not 0 (Oren-Nayar, not Lambert)"
    return _one_colour(material, node, "Color", "diffuse colour")


def _one_colour(material, node, colour_name, what):
    """(RGB, "") of a BSDF node's unlinked colour ``colour_name`` within 0..1 with an unlinked normal; else
    (None, why)."""
    colour, normal = node.inputs[colour_name], node.inputs.get("Normal")
    if colour.is_linked or (normal is not None and normal.is_linked):
        return None, f"material {material.name!r}: its {what} or normal is linked (a texture, a map)"
    rgb = tuple(float(c) for c in colour.default_value[:3])
    if not all(0.0 <= c <= 1.0 for c in rgb):
        return None, f"material {material.name!r}: {what} outside 0..1"
    return rgb, ""


#: A Principled BSDF's inputs that add a layer or a lobe to its diffuse base, with the values that leave it out.
#: Specular IOR Level 0 scales the dielectric's F0 to 0, so its IOR becomes 1 and it reflects at no angle
#: (Cycles' principled closure; measured in 5.0: a plane under a Sun light renders as the Diffuse BSDF of the same
#: colour to 5 digits at 10-85 deg of sun and 0-70 deg of view, where level 0.5 differs by up to 12x).
PRINCIPLED_DIFFUSE_ONLY = (("Specular IOR Level", 0.0), ("Metallic", 0.0), ("Transmission Weight", 0.0),
                           ("Subsurface Weight", 0.0), ("Coat Weight", 0.0), ("Sheen Weight", 0.0), ("Alpha", 1.0),
                           ("Emission Strength", 0.0), ("Diffuse Roughness", 0.0), ("Thin Film Thickness", 0.0))


def _principled_albedo(material, node):
    """``lambertian_albedo`` for a Principled BSDF: Lambertian with its base colour when every extra layer is
    off (``PRINCIPLED_DIFFUSE_ONLY``, unlinked) and its base colour and normal are unlinked."""
    for name, value in PRINCIPLED_DIFFUSE_ONLY:
        if _set(node, name, value):
            sock = node.inputs[name]
            shown = "linked" if sock.is_linked else f"{float(sock.default_value):g}"
            return None, (f"material {material.name!r}: its Principled BSDF has {name} {shown} (only a Principled "
                          f"BSDF with {name} {value:g} is Lambertian)")
    return _one_colour(material, node, "Base Color", "base colour")

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
    "ShaderNodeBsdfTransparent", "ShaderNodeScript",
}
EMISSIVE_NODES = {"ShaderNodeEmission", "ShaderNodeScript"}
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
    return types


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

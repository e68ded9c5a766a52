"""Measurement-grade Cycles settings, enabling only the render features the scene needs.

``scene_needs(scene)`` inspects the scene (world, materials, volumes) and ``apply(scene, ...)``
writes the settings; callers run inside ``scene_guard.preserved_scene`` so the user's settings come
back afterwards. The returned dict records what was enabled and why (it goes into readings' notes).
"""

import bpy

from ..compat import active_node_tree

_GLOSSY_NODES = {
    "ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfMetallic", "ShaderNodeBsdfGlass",
    "ShaderNodeBsdfRefraction", "ShaderNodeBsdfPrincipled", "ShaderNodeBsdfHairPrincipled",
    "ShaderNodeBsdfToon", "ShaderNodeBsdfSheen", "ShaderNodeScript", "ShaderNodeBsdfHair",
}
_TRANSMISSIVE_NODES = {
    "ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction", "ShaderNodeBsdfTranslucent",
    "ShaderNodeBsdfTransparent", "ShaderNodeScript",
}
_EMISSIVE_NODES = {"ShaderNodeEmission", "ShaderNodeScript"}
_GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME", "GREASEPENCIL"}


def _node_types(tree, seen=None):
    """All node type identifiers in a node tree, looking inside node groups."""
    seen = set() if seen is None else seen
    if tree is None or tree.as_pointer() in seen:
        return set()
    seen.add(tree.as_pointer())
    types = set()
    for node in tree.nodes:
        types.add(node.bl_idname)
        if node.bl_idname == "ShaderNodeGroup":
            types |= _node_types(node.node_tree, seen)
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            inp = node.inputs.get("Emission Strength")
            if inp is not None and not inp.is_linked and inp.default_value > 0:
                types.add("ShaderNodeEmission")
            elif inp is not None and inp.is_linked:
                types.add("ShaderNodeEmission")
    return types


def _uses_volume(tree):
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


def scene_needs(scene, depsgraph=None, exclude=()):
    """What the scene contains that light transport must simulate. ``exclude``: object names."""
    needs = {"geometry": False, "glossy": False, "transmission": False, "volume": False, "emissive_surfaces": False}
    needs["world_emits"] = world_emits(scene.world)
    needs["volume"] = _uses_volume(active_node_tree(scene.world) if scene.world else None)
    for ob in scene.objects:
        if ob.name in exclude or ob.type not in _GEOMETRY_TYPES or ob.hide_render:
            continue
        if not (ob.visible_diffuse or ob.visible_glossy or ob.visible_transmission or ob.visible_shadow):
            continue
        needs["geometry"] = True
        if ob.type == "VOLUME":
            needs["volume"] = True
        materials = [slot.material for slot in ob.material_slots if slot.material]
        if not materials:
            continue
        for mat in materials:
            tree = active_node_tree(mat)
            types = _node_types(tree)
            needs["glossy"] |= bool(types & _GLOSSY_NODES)
            needs["transmission"] |= bool(types & _TRANSMISSIVE_NODES)
            needs["emissive_surfaces"] |= bool(types & _EMISSIVE_NODES)
            needs["volume"] |= _uses_volume(tree)
    return needs


def apply(scene, *, samples, bounces, needs, seed=0):
    """Write measurement-grade settings; return the record of what was enabled and why."""
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = int(samples)
    cy.use_adaptive_sampling = False  # a noise threshold would stop early with a biased error estimate
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.light_sampling_threshold = 0.0  # the default 0.01 culls dim lights
    cy.seed = int(seed)
    cy.use_animated_seed = False
    scene.render.use_persistent_data = False
    scene.render.film_transparent = False
    scene.render.filter_size = 0.01  # pixel filter width (px): we want each pixel's own value
    interreflection = bounces if needs["geometry"] else 0
    cy.diffuse_bounces = interreflection
    cy.glossy_bounces = interreflection if needs["glossy"] else 0
    cy.transmission_bounces = interreflection if needs["transmission"] else 0
    cy.volume_bounces = interreflection if needs["volume"] else 0
    cy.transparent_max_bounces = 8 if needs["transmission"] else 0
    cy.max_bounces = interreflection * (1 + needs["glossy"] + needs["transmission"]) if interreflection else 0
    cy.caustics_reflective = bool(needs["glossy"])
    cy.caustics_refractive = bool(needs["transmission"])
    return {
        "engine": "CYCLES (CPU)",
        "samples": int(samples),
        "max_bounces": cy.max_bounces,
        "diffuse_bounces": cy.diffuse_bounces,
        "glossy_bounces": cy.glossy_bounces,
        "transmission_bounces": cy.transmission_bounces,
        "volume_bounces": cy.volume_bounces,
        "caustics": bool(needs["glossy"] or needs["transmission"]),
        "denoising": False,
        "clamping": False,
        "filter_glossy": 0.0,
        "light_threshold": 0.0,
        "scene_has": {k: bool(v) for k, v in needs.items()},
    }

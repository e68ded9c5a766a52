"""Reading a scene's participating media for the meter (issue 18): a homogeneous world volume.

Host code: inspects the world's node tree only (nothing is changed). The maths is in
``radiometry/scene/media.py``.
"""

from ...radiometry.scene import media

_NODES = {"ShaderNodeVolumeScatter": "scatter", "ShaderNodeVolumeAbsorption": "absorption"}


def world_medium(scene):
    """The world's volume as a :class:`~radiometer.radiometry.scene.media.HomogeneousMedium`, or None when
    there is none or it is not provably homogeneous: the active World Output's Volume must come
    straight from one Volume Scatter or Volume Absorption node whose Density and Color are plain
    values (no texture, attribute or driver-fed link)."""
    from ...compat import active_node_tree

    world = scene.world
    tree = active_node_tree(world) if world is not None else None
    if tree is None:
        return None
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    output = next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)
    socket = output.inputs.get("Volume") if output is not None else None
    if socket is None or not socket.is_linked or len(socket.links) != 1:
        return None
    link = socket.links[0]
    node = link.from_node
    kind = _NODES.get(node.bl_idname)
    if kind is None or not link.is_valid or getattr(link, "is_muted", False) or node.mute:
        return None
    density, colour = node.inputs.get("Density"), node.inputs.get("Color")
    if density is None or colour is None or density.is_linked or colour.is_linked:
        return None
    if any(s.is_linked for s in node.inputs if s.name in ("Weight",)):
        return None
    sigma = media.extinction(kind, density.default_value, tuple(colour.default_value)[:3],
                             scene.unit_settings.scale_length)
    label = "Volume Scatter" if kind == "scatter" else "Volume Absorption"
    return media.HomogeneousMedium(f"the world's volume ({label}, density {density.default_value:g})", sigma)

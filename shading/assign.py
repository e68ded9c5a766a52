"""Assign a Radiometer BRDF to a Blender material (node group or OSL Script node), re-editably.

What happens to the material's existing nodes: nothing is deleted. Radiometer adds ONE node (a
group node named ``Radiometer BRDF`` or a Script node named ``Radiometer BRDF (OSL)``) and links it
to the Material Output's Surface. A user node that was linked there is only disconnected (it stays
in the tree, moved 300 px up-left so it does not sit under Radiometer's node, and its name is
reported in ``Fidelity.notes``). Switching methods removes only
Radiometer's own previous node (and its node group when nothing else uses it).
"""

from . import nodes as N
from . import osl as O
from .realise import realise
from ..compat import ensure_node_tree
from ..errors import RadiometerError

GROUP_NODE_NAME = "Radiometer BRDF"
OSL_NODE_NAME = O.NODE_NAME
OWNER_KEY = "radiometer_owner"  # custom property marking data-blocks/nodes created by Radiometer


def _output_node(tree):
    out = tree.get_output_node("CYCLES") or tree.get_output_node("ALL")
    if out is None:
        out = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"), None)
    if out is None:
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        out.location = (300, 0)
    return out


def _remove_group_node(tree):
    node = tree.nodes.get(GROUP_NODE_NAME)
    if node is None:
        return
    group = node.node_tree
    tree.nodes.remove(node)
    import bpy

    if group is not None and group.users == 0 and group.get(OWNER_KEY):
        bpy.data.node_groups.remove(group)


def _remove_osl_node(tree):
    node = tree.nodes.get(OSL_NODE_NAME)
    if node is not None:
        tree.nodes.remove(node)


def assign_brdf(material, model, method="nodes", **params):
    """Realise ``model`` with ``params`` on ``material``; return its ``Fidelity``.

    Parameters
    ----------
    material : bpy.types.Material
    model : str
        One of ``radiometer.brdf.names()``.
    method : {'nodes', 'osl'}
        'nodes' builds a node group (Cycles any device, EEVEE); 'osl' a Script node (Cycles CPU,
        needs Scene > Render > Open Shading Language, which Radiometer never switches on itself).
    **params
        Model parameters (see ``radiometer.brdf.describe(model)``), SI units / radians.

    Raises
    ------
    RadiometerError
        Bad model, method or parameter; the material is then left unchanged.
    """
    import bpy

    if material is None:
        raise RadiometerError("no material to assign the BRDF to")
    terms, fidelity = realise(model, method, **params)  # validates before anything changes
    tree = ensure_node_tree(material)
    out = _output_node(tree)
    notes = []
    surface = out.inputs["Surface"]
    previous = [l.from_node for l in surface.links if l.from_node.name not in (GROUP_NODE_NAME, OSL_NODE_NAME)]

    settings = getattr(material, "radiometer_brdf", None)
    if method == "nodes":
        _remove_osl_node(tree)
        node = tree.nodes.get(GROUP_NODE_NAME)
        group = node.node_tree if node is not None else None
        if group is not None and (not group.get(OWNER_KEY) or group.users > 1):
            group = None  # never rebuild a group that is not ours alone
        if group is None:
            group = N.build_group(terms, f"Radiometer {model}")
            group[OWNER_KEY] = True
        else:
            N.build_group(terms, group.name, group)
            group.name = f"Radiometer {model}"
        if node is None:
            node = tree.nodes.new("ShaderNodeGroup")
            node.name = node.label = GROUP_NODE_NAME
            node.location = (out.location.x - 250, out.location.y)
        old_group = node.node_tree
        node.node_tree = group
        if old_group is not None and old_group != group and old_group.users == 0 and old_group.get(OWNER_KEY):
            bpy.data.node_groups.remove(old_group)
        out_socket = node.outputs[N.GROUP_OUTPUT_SOCKET]
    else:
        _remove_group_node(tree)
        node = tree.nodes.get(OSL_NODE_NAME)
        text = O.source_text()
        if node is None or node.script != text or "BSDF" not in node.outputs:
            if node is None:
                node = tree.nodes.new("ShaderNodeScript")
                node.name = node.label = OSL_NODE_NAME
                node.location = (out.location.x - 250, out.location.y)
            node.mode = "INTERNAL"
            node.script = text
            try:
                O.compile_node(node)
            except RuntimeError as exc:
                tree.nodes.remove(node)
                raise RadiometerError(str(exc)) from None
        O.set_inputs(node, terms)
        out_socket = node.outputs["BSDF"]
        scene = bpy.context.scene
        if scene is not None and not scene.cycles.shading_system:
            notes.append("render with Cycles on the CPU with Open Shading Language enabled (Render Properties)")

    for node_prev in previous:
        # out of the way of Radiometer's node, never deleted
        node_prev.location = (node_prev.location.x - 300, node_prev.location.y + 300)
        notes.append(f"previous surface node '{node_prev.name}' disconnected and moved up-left (kept in the tree)")
    if not surface.links or surface.links[0].from_socket != out_socket:
        tree.links.new(out_socket, surface)

    if notes:
        fidelity = _with_notes(fidelity, notes)
    if settings is not None:
        from ..props.brdf import store_assignment

        store_assignment(material, model, method, params, fidelity)
    return fidelity


def _with_notes(fidelity, notes):
    from dataclasses import replace

    joined = "; ".join([n for n in [fidelity.notes] + notes if n])
    return replace(fidelity, notes=joined)

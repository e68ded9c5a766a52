"""Assign a Radiometer BRDF to a Blender material as an editable node group, updated in place.

What happens to the material's nodes: nothing of the user's is deleted. Radiometer adds ONE group
node named ``Radiometer BRDF`` (its group holds either Cycles closure nodes or, for method 'osl', one
Script node) and links it to the Material Output's Surface. The group node has one input per model
parameter plus ``Normal`` (and ``Tangent``), so textures and bump maps can be linked into it; the
values Radiometer writes are the inputs' default values, which never disturb such links. A user node
that was linked to the Surface is only disconnected (moved 300 px up-left, reported in the notes).
Re-assigning updates the same group and node in place; switching model or method rebuilds the
group's inner nodes and removes what Radiometer created and no longer needs (its tangent node, the
OSL text block).

For an anisotropic model the Tangent input is fed from a Tangent node on a chosen UV map
(``tangent_source='UV'``), or left unlinked: the group then uses the object's +X axis (+Y where +X
is parallel to the normal).

Callers that keep a record of the assignment (``props.brdf``) register a callback in
``ASSIGNED_HOOKS``: this module imports nothing from the UI layer.
"""

import json

from . import laws as L
from . import nodes as N
from . import osl as O
from .realise import check_params, param_specs, realise
from ..compat import ensure_node_tree
from ..errors import RadiometerError

GROUP_NODE_NAME = "Radiometer BRDF"
TANGENT_NODE_NAME = "Radiometer Tangent"
OSL_NODE_NAME = O.NODE_NAME
OWNER_KEY = "radiometer_owner"  # custom property marking data-blocks/nodes created by Radiometer
TANGENT_SOURCES = ("OBJECT", "UV")

#: callables (material, model, method, params, fidelity) run after every successful assignment
ASSIGNED_HOOKS = []


def _output_node(tree):
    out = tree.get_output_node("CYCLES") or tree.get_output_node("ALL")
    if out is None:
        out = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"), None)
    if out is None:
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        out.location = (300, 0)
    return out


def check_editable(material):
    """Raise RadiometerError when ``material`` cannot be edited (library-linked data)."""
    if material is None:
        raise RadiometerError("no material to assign the BRDF to")
    lib = getattr(material, "library", None)
    if lib is not None:
        raise RadiometerError(f"material '{material.name}' is linked from {lib.filepath}: make it local "
                              "(Object > Relations > Make Local) or use a library override to edit it")


def _text_in_use(text):
    import bpy

    for g in bpy.data.node_groups:
        for n in g.nodes:
            if n.bl_idname == "ShaderNodeScript" and n.script == text:
                return True
    for m in bpy.data.materials:
        if m.node_tree is not None:
            for n in m.node_tree.nodes:
                if n.bl_idname == "ShaderNodeScript" and n.script == text:
                    return True
    return False


def _cleanup_osl_text():
    import bpy

    text = bpy.data.texts.get(O.TEXT_NAME)
    if text is not None and text.get(OWNER_KEY) and not _text_in_use(text):
        bpy.data.texts.remove(text)


def _remove_group_node(tree):
    import bpy

    node = tree.nodes.get(GROUP_NODE_NAME)
    if node is None:
        return
    group = node.node_tree
    tree.nodes.remove(node)
    if group is not None and group.users == 0 and group.get(OWNER_KEY):
        bpy.data.node_groups.remove(group)


def remove_brdf(material):
    """Remove what Radiometer added to ``material`` (group node, its group, tangent node, OSL text)."""
    tree = material.node_tree
    if tree is None:
        return
    _remove_group_node(tree)
    for name in (TANGENT_NODE_NAME, OSL_NODE_NAME):
        node = tree.nodes.get(name)
        if node is not None:
            tree.nodes.remove(node)
    _cleanup_osl_text()


def _set_inputs(node, inputs):
    for name, value in inputs.items():
        sock = node.inputs.get(name)
        if sock is None:
            continue
        if sock.type == "RGBA":
            v = list(value) if hasattr(value, "__len__") else [value] * 3
            sock.default_value = (float(v[0]), float(v[1]), float(v[2]), 1.0)
        else:
            sock.default_value = float(value)


def node_params(node):
    """The model parameters as the group node's inputs hold them now ({name: value}), plus the
    model, method, structure and coefficients the group was built with."""
    group = node.node_tree
    sig = json.loads(group["radiometer_signature"])
    coef = json.loads(group.get("radiometer_coefficients", "{}"))
    model, structure = sig["model"], sig["structure"]
    params = {}
    for name in L.input_names(model, structure):
        sock = node.inputs[name]
        v = sock.default_value
        params[name] = [float(c) for c in v[:3]] if sock.type == "RGBA" else float(v)
    if structure.get("variant"):
        params["variant"] = structure["variant"]
    return model, sig["method"], structure, coef, params


def current_fidelity(material):
    """Fidelity of what the material's group node renders now (after direct edits of its inputs)."""
    node = material.node_tree.nodes.get(GROUP_NODE_NAME) if material.node_tree else None
    if node is None or node.node_tree is None or "radiometer_signature" not in node.node_tree:
        return None
    model, method, _, coef, params = node_params(node)
    return realise(model, method, coefficients=coef or None, **params)[1]


def _ensure_tangent(tree, node, source, uv_map):
    sock = node.inputs.get("Tangent")
    ours = tree.nodes.get(TANGENT_NODE_NAME)
    if sock is None or source != "UV":
        if ours is not None:
            tree.nodes.remove(ours)
        return
    if sock.is_linked and sock.links[0].from_node != ours:
        return  # the user's own tangent: leave it
    if ours is None:
        ours = tree.nodes.new("ShaderNodeTangent")
        ours.name = ours.label = TANGENT_NODE_NAME
        ours.location = (node.location.x - 250, node.location.y - 300)
    ours.direction_type = "UV_MAP"
    ours.uv_map = uv_map or ""
    if not sock.is_linked:
        tree.links.new(ours.outputs["Tangent"], sock)


def assign_brdf(material, model, method="nodes", tangent_source="OBJECT", uv_map="", **params):
    """Realise ``model`` with ``params`` on ``material``; return its ``Fidelity``.

    Parameters
    ----------
    material : bpy.types.Material
    model : str
        One of ``radiometer.brdf.names()``.
    method : {'nodes', 'osl'}
        'nodes': Cycles closure nodes (Cycles any device, EEVEE); 'osl': a Script node inside the
        group (Cycles CPU with Open Shading Language on; the notes say when it is off).
    tangent_source : {'OBJECT', 'UV'}
        Anisotropy frame: the object's +X axis, or the tangent of UV map ``uv_map`` ('' = active).
    **params
        Model parameters (see ``radiometer.brdf.describe(model)``), SI units / radians.

    Raises
    ------
    RadiometerError
        Bad model, method or parameter, a library-linked material, or OSL not available; the
        material is then left unchanged.
    """
    import bpy

    check_editable(material)
    if tangent_source not in TANGENT_SOURCES:
        raise RadiometerError(f"tangent_source must be one of {TANGENT_SOURCES}, got {tangent_source!r}")
    terms, fidelity = realise(model, method, **params)  # validates before anything changes
    script = None
    if method == "osl":
        O.ensure_oslquery()
        try:
            import oslquery  # noqa: F401
        except ImportError:
            raise RadiometerError("OSL scripts cannot be compiled here: Blender's oslquery module is missing") from None
        script = O.source_text()
        script[OWNER_KEY] = True
    tree = ensure_node_tree(material)
    out = _output_node(tree)
    notes = []
    surface = out.inputs["Surface"]
    legacy = tree.nodes.get(OSL_NODE_NAME)  # a Script node of an older Radiometer version
    previous = [l.from_node for l in surface.links if l.from_node.name not in (GROUP_NODE_NAME, OSL_NODE_NAME)]

    node = tree.nodes.get(GROUP_NODE_NAME)
    group = node.node_tree if node is not None else None
    if group is not None and (not group.get(OWNER_KEY) or group.users > 1):
        group = None  # never rebuild a group that is not ours alone
    old_group = group
    # Links the user made into the group node (textures, bump): a rebuild of the group's interface
    # (another model, an option that adds or removes inputs) drops them, so they are put back on
    # the inputs of the same name. Radiometer's own tangent node is managed by _ensure_tangent.
    user_links = [] if node is None else [
        (sock.name, link.from_socket) for sock in node.inputs if sock.is_linked for link in sock.links
        if link.from_node.name != TANGENT_NODE_NAME]
    specs = param_specs(model)
    try:
        group = N.build_group(model, method, fidelity.structure, fidelity.coefficients, specs,
                              f"Radiometer {model}", group, script=script)
    except RuntimeError as exc:  # OSL compilation
        raise RadiometerError(str(exc)) from None
    group[OWNER_KEY] = True
    if group.name != f"Radiometer {model}" and not group.name.startswith(f"Radiometer {model}"):
        group.name = f"Radiometer {model}"
    if node is None:
        node = tree.nodes.new("ShaderNodeGroup")
        node.name = node.label = GROUP_NODE_NAME
        node.location = (out.location.x - 250, out.location.y)
    prev_tree = node.node_tree
    node.node_tree = group
    node.width = 220
    if prev_tree is not None and prev_tree not in (group, old_group) and prev_tree.users == 0 \
            and prev_tree.get(OWNER_KEY):
        bpy.data.node_groups.remove(prev_tree)
    _set_inputs(node, fidelity.inputs)
    for name, from_socket in user_links:
        sock = node.inputs.get(name)
        if sock is not None and not sock.is_linked:
            tree.links.new(from_socket, sock)
    _ensure_tangent(tree, node, tangent_source if fidelity.structure.get("aniso") else "OBJECT", uv_map)
    if legacy is not None:
        tree.nodes.remove(legacy)
    if method != "osl":
        _cleanup_osl_text()
    else:
        problems = O.osl_problems(bpy.context.scene)
        if problems:
            notes.append("this OSL material renders black until fixed: " + "; ".join(problems))
    out_socket = node.outputs[N.GROUP_OUTPUT_SOCKET]
    for node_prev in previous:
        # out of the way of Radiometer's node, never deleted
        node_prev.location = (node_prev.location.x - 300, node_prev.location.y + 300)
        notes.append(f"previous surface node '{node_prev.name}' disconnected and moved up-left (kept in the tree)")
    if not surface.links or surface.links[0].from_socket != out_socket:
        tree.links.new(out_socket, surface)

    if notes:
        fidelity = _with_notes(fidelity, notes)
    for hook in list(ASSIGNED_HOOKS):
        hook(material, model, method, check_params(model, params), fidelity)
    return fidelity


def _with_notes(fidelity, notes):
    from dataclasses import replace

    joined = "; ".join([n for n in [fidelity.notes] + notes if n])
    return replace(fidelity, notes=joined)

"""Materials Radiometer builds for its own renders and scenes (sensors, sky patches, demo rooms)."""


def shader_material(name, shader, inputs):
    """A new material whose surface is one ``shader`` node (e.g. "ShaderNodeEmission") with ``inputs``
    (socket name -> default value) set, linked to the surface output. Returns the material and the shader
    node (its tree takes more nodes)."""
    import bpy

    from ...compat import ensure_node_tree

    material = bpy.data.materials.new(name)
    tree = ensure_node_tree(material)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    node = tree.nodes.new(shader)
    for socket, value in inputs.items():
        node.inputs[socket].default_value = value
    tree.links.new(node.outputs[0], out.inputs["Surface"])
    return material, node

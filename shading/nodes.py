"""Build Blender shader node networks from closure terms (``shading.closures.Term``).

Conventions measured/read from the Cycles 5.0 kernel (``svm/closure.h``), re-checked by rendering:

* Glossy / Metallic / Diffuse roughness r gives alpha = r ** 2 (``sqr(saturatef(param1))``).
* Glossy anisotropy a in (-0.99, 0.99): a > 0 gives alpha_x = alpha (1 - a), alpha_y = alpha / (1 - a);
  a < 0 gives alpha_x = alpha / (1 + a), alpha_y = alpha (1 + a); alpha_x alpha_y = alpha ** 2.
* Metallic anisotropy a in [0, 1]: aspect = sqrt(1 - 0.9 a), alpha_x = alpha / aspect,
  alpha_y = alpha aspect, so alpha_y / alpha_x >= 0.1; rotation 0.25 swaps the axes.
* Metallic with Fresnel 'F82' and a white edge tint is exactly Schlick's Fresnel with F0 = base colour.
* Anisotropy only acts when the Tangent socket is linked; we link the object's +X axis in world space.
"""

import math

NODE_PREFIX = "Radiometer"
GROUP_OUTPUT_SOCKET = "BSDF"


def glossy_roughness_anisotropy(alpha_x, alpha_y):
    """(roughness, anisotropy) of a Glossy BSDF that gives alpha_x, alpha_y (dimensionless)."""
    alpha = math.sqrt(alpha_x * alpha_y)
    if alpha_x < alpha_y:
        aniso = 1.0 - math.sqrt(alpha_x / alpha_y)
    else:
        aniso = math.sqrt(alpha_y / alpha_x) - 1.0
    return math.sqrt(alpha), max(-0.99, min(0.99, aniso))


def metallic_roughness_anisotropy_rotation(alpha_x, alpha_y):
    """(roughness, anisotropy, rotation) of a Metallic BSDF that gives alpha_x, alpha_y."""
    alpha = math.sqrt(alpha_x * alpha_y)
    lo, hi = min(alpha_x, alpha_y), max(alpha_x, alpha_y)
    aniso = (1.0 - lo / hi) / 0.9 if hi > 0 else 0.0
    rotation = 0.0 if alpha_x >= alpha_y else 0.25
    return math.sqrt(alpha), max(0.0, min(1.0, aniso)), rotation


def _tangent_socket(nodes, links, x, y):
    vt = nodes.new("ShaderNodeVectorTransform")
    vt.name = vt.label = "Tangent (object +X)"
    vt.vector_type = "VECTOR"
    vt.convert_from = "OBJECT"
    vt.convert_to = "WORLD"
    vt.inputs["Vector"].default_value = (1.0, 0.0, 0.0)
    vt.location = (x, y)
    return vt.outputs["Vector"]


def _rgba(c):
    return (float(c[0]), float(c[1]), float(c[2]), 1.0)


def _term_node(nodes, links, term, x, y):
    """Create the node(s) for one term; return its shader output socket."""
    c = term.closure
    aniso = c in ("microfacet", "ashikhmin_shirley") and abs(term.alpha_x - term.alpha_y) > 1e-9 * max(
        term.alpha_x, term.alpha_y, 1e-30)
    if c in ("diffuse", "oren_nayar"):
        n = nodes.new("ShaderNodeBsdfDiffuse")
        n.inputs["Color"].default_value = _rgba(term.color)
        n.inputs["Roughness"].default_value = float(term.roughness) if c == "oren_nayar" else 0.0
    elif c == "phong_ramp":
        raise ValueError("the Phong lobe exists only as an OSL closure (phong_ramp); use method='osl'")
    elif c in ("microfacet", "mirror") and term.fresnel in ("schlick", "conductor"):
        n = nodes.new("ShaderNodeBsdfMetallic")
        n.distribution = "BECKMANN" if term.distribution == "beckmann" else "GGX"
        if term.fresnel == "schlick":
            n.fresnel_type = "F82"
            n.inputs["Base Color"].default_value = _rgba(term.f0)
            n.inputs["Edge Tint"].default_value = (1.0, 1.0, 1.0, 1.0)  # white tint = pure Schlick
        else:
            n.fresnel_type = "PHYSICAL_CONDUCTOR"
            n.inputs["IOR"].default_value = tuple(float(v) for v in term.ior)
            n.inputs["Extinction"].default_value = tuple(float(v) for v in term.k)
        if c == "mirror":
            n.inputs["Roughness"].default_value = 0.0
        else:
            r, a, rot = metallic_roughness_anisotropy_rotation(term.alpha_x, term.alpha_y)
            n.inputs["Roughness"].default_value = r
            n.inputs["Anisotropy"].default_value = a if aniso else 0.0
            n.inputs["Rotation"].default_value = rot if aniso else 0.0
            if aniso:
                links.new(_tangent_socket(nodes, links, x - 220, y - 250), n.inputs["Tangent"])
        weight = sum(term.color) / 3.0
        if abs(weight - 1.0) > 1e-9:
            # Metallic has no colour weight: scale it with a Mix Shader against "no closure".
            mix = nodes.new("ShaderNodeMixShader")
            mix.inputs["Fac"].default_value = weight
            mix.location = (x + 200, y)
            links.new(n.outputs[0], mix.inputs[2])
            n.location = (x, y)
            return mix.outputs[0]
    else:  # microfacet / ashikhmin_shirley / mirror with F = 1
        n = nodes.new("ShaderNodeBsdfGlossy")
        n.distribution = {"beckmann": "BECKMANN", "ggx": "GGX"}.get(term.distribution, "GGX")
        if c == "ashikhmin_shirley":
            n.distribution = "ASHIKHMIN_SHIRLEY"
        n.inputs["Color"].default_value = _rgba(term.color)
        if c == "mirror":
            n.inputs["Roughness"].default_value = 0.0
        else:
            r, a = glossy_roughness_anisotropy(term.alpha_x, term.alpha_y)
            n.inputs["Roughness"].default_value = r
            n.inputs["Anisotropy"].default_value = a if aniso else 0.0
            if aniso:
                links.new(_tangent_socket(nodes, links, x - 220, y - 250), n.inputs["Tangent"])
    n.location = (x, y)
    return n.outputs[0]


def build_group(terms, name, group=None):
    """Create (or rebuild in place) a shader node group whose output 'BSDF' is the sum of ``terms``.

    Returns the ``bpy.types.ShaderNodeTree``. Rebuilding keeps the data-block (and so every
    material using it) and replaces only its inner nodes, which belong to Radiometer.
    """
    import bpy

    if group is None:
        group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    if not any(s.in_out == "OUTPUT" and s.name == GROUP_OUTPUT_SOCKET for s in group.interface.items_tree
               if getattr(s, "item_type", "SOCKET") == "SOCKET"):
        group.interface.new_socket(GROUP_OUTPUT_SOCKET, in_out="OUTPUT", socket_type="NodeSocketShader")
    nodes, links = group.nodes, group.links
    nodes.clear()
    out = nodes.new("NodeGroupOutput")
    out.location = (400 + 200 * len(terms), 0)
    sockets = [_term_node(nodes, links, t, 0, -320 * i) for i, t in enumerate(terms)]
    if not sockets:
        return group
    acc = sockets[0]
    for i, s in enumerate(sockets[1:]):
        add = nodes.new("ShaderNodeAddShader")
        add.location = (400 + 200 * i, -160 * i)
        links.new(acc, add.inputs[0])
        links.new(s, add.inputs[1])
        acc = add.outputs[0]
    links.new(acc, out.inputs[GROUP_OUTPUT_SOCKET])
    return group

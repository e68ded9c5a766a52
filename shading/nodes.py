"""Build Blender shader node networks from closure terms (``shading.closures.Term``).

Conventions measured/read from the Cycles 5.0 kernel (``svm/closure.h``), re-checked by rendering:

* Glossy / Metallic / Diffuse roughness r gives alpha = r ** 2 (``sqr(saturatef(param1))``).
* Glossy anisotropy a in (-0.99, 0.99): a > 0 gives alpha_x = alpha (1 - a), alpha_y = alpha / (1 - a);
  a < 0 gives alpha_x = alpha / (1 + a), alpha_y = alpha (1 + a); alpha_x alpha_y = alpha ** 2.
* Metallic anisotropy a in [0, 1]: aspect = sqrt(1 - 0.9 a), alpha_x = alpha / aspect,
  alpha_y = alpha aspect, so alpha_y / alpha_x >= 0.1; rotation 0.25 swaps the axes.
* Metallic with Fresnel 'F82' and a white edge tint is exactly Schlick's Fresnel with F0 = base colour.
* Anisotropy only acts when the Tangent socket is linked. The group's Tangent input (a UV map's tangent
  from a Tangent node, linked by ``shading.assign``) is used when linked; otherwise the object's +X axis
  in world space. Either is made orthogonal to the normal inside the group, and where it is (nearly)
  parallel to the normal the object's +Y axis is used instead, so the frame is never degenerate.

The group (``build_group``) has one input per model parameter (``shading.laws.input_names``) plus
``Normal`` (and ``Tangent`` for anisotropic models); Math nodes inside compute the closure controls
from them with exactly the law the numpy replica (``shading.laws.numeric_terms``) uses.
"""

import json
import math

import numpy as np


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



def _is_socket(v):
    return hasattr(v, "is_linked") and hasattr(v, "node")


class NodeOps:
    """The law algebra of ``shading.laws`` evaluated by creating Math nodes in a node tree."""

    def __init__(self, tree, x0=-900, y0=600):
        self.tree = tree
        self.nodes, self.links = tree.nodes, tree.links
        self._x, self._y = x0, y0

    def _place(self, node):
        node.location = (self._x, self._y)
        self._y -= 40
        node.hide = True
        return node

    def set(self, socket, value):
        if _is_socket(value):
            self.links.new(value, socket)
            return
        if socket.type == "RGBA":
            c = np.broadcast_to(np.asarray(value, dtype=float), (3,))
            socket.default_value = (float(c[0]), float(c[1]), float(c[2]), 1.0)
        elif socket.type == "VECTOR":
            c = np.broadcast_to(np.asarray(value, dtype=float), (3,))
            socket.default_value = tuple(float(v) for v in c)
        elif socket.type == "INT":
            socket.default_value = int(round(float(np.asarray(value))))
        else:
            socket.default_value = float(np.asarray(value))

    def _math(self, op, *args):
        if not any(_is_socket(a) for a in args):  # constant folding keeps the group small
            from .laws import NumpyOps

            return float(getattr(NumpyOps, op)(*args))
        n = self._place(self.nodes.new("ShaderNodeMath"))
        n.operation = {"add": "ADD", "sub": "SUBTRACT", "mul": "MULTIPLY", "div": "DIVIDE", "sqrt": "SQRT",
                       "minimum": "MINIMUM", "maximum": "MAXIMUM", "less": "LESS_THAN", "pow": "POWER",
                       "cos": "COSINE"}[op]
        for k, a in enumerate(args):
            self.set(n.inputs[k], a)
        return n.outputs[0]

    def add(self, a, b):
        return self._math("add", a, b)

    def sub(self, a, b):
        return self._math("sub", a, b)

    def mul(self, a, b):
        return self._math("mul", a, b)

    def div(self, a, b):
        return self._math("div", a, b)

    def sqrt(self, a):
        if not _is_socket(a):
            return float(np.sqrt(max(float(a), 0.0)))
        return self._math("sqrt", self._math("maximum", a, 0.0))

    def minimum(self, a, b):
        return self._math("minimum", a, b)

    def maximum(self, a, b):
        return self._math("maximum", a, b)

    def less(self, a, b):
        return self._math("less", a, b)

    def pow(self, a, b):
        return self._math("pow", a, b)

    def cos(self, a):
        return self._math("cos", a)

    def select(self, cond, a, b):
        if not _is_socket(cond):
            return a if float(cond) > 0.5 else b
        return self.add(self.mul(cond, a), self.mul(self.sub(1.0, cond), b))

    def _vec(self, op, a, b=None, scale=None):
        if not _is_socket(a) and not _is_socket(b) and not _is_socket(scale):
            from .laws import NumpyOps

            if op == "SCALE":
                return NumpyOps.cscale(a, scale)
            return NumpyOps.cmul(a, b) if op == "MULTIPLY" else np.subtract(a, b)
        n = self._place(self.nodes.new("ShaderNodeVectorMath"))
        n.operation = op
        self.set(n.inputs[0], a)
        if op == "SCALE":
            self.set(n.inputs["Scale"], scale)
        else:
            self.set(n.inputs[1], b)
        return n.outputs["Vector"]

    def cscale(self, c, s):
        return self._vec("SCALE", c, scale=s)

    def cmul(self, a, b):
        return self._vec("MULTIPLY", a, b)

    def cone_minus(self, c):
        return self._vec("SUBTRACT", (1.0, 1.0, 1.0), c)

    def rgb_from_scalar(self, s):
        if not _is_socket(s):
            return (float(s),) * 3
        n = self._place(self.nodes.new("ShaderNodeCombineXYZ"))
        for k in range(3):
            self.links.new(s, n.inputs[k])
        return n.outputs[0]


def _socket_type(spec, name, model, structure):
    """(socket type, subtype) of a parameter input: colour, angle (radians), factor ([0, 1]) or plain."""
    if spec.get("kind") == "color":
        return "NodeSocketColor", None
    if spec.get("unit") == "rad" and structure.get("variant") != "cycles":
        return "NodeSocketFloat", "ANGLE"
    lo, hi = spec.get("min"), spec.get("max")
    if lo is not None and hi is not None and lo >= 0 and hi <= 1:
        return "NodeSocketFloat", "FACTOR"
    return "NodeSocketFloat", None


def _frame_sockets(ops, group_in, aniso):
    """(normal, tangent) sockets: the inputs when linked (non-zero), else the shading normal / object +X."""
    nodes, links = ops.nodes, ops.links
    geo = ops._place(nodes.new("ShaderNodeNewGeometry"))
    geo.name = geo.label = "Geometry"

    def vmath(op, a, b=None, scale=None):
        return _vmath(ops, op, a, b, scale)

    def choose(use_a, a, b):  # vector a where use_a (0/1), else b
        mix = ops._place(nodes.new("ShaderNodeMix"))
        mix.data_type = "VECTOR"
        ops.set(mix.inputs["Factor"], use_a)
        links.new(b, mix.inputs[4])  # A (factor 0)
        links.new(a, mix.inputs[5])  # B (factor 1)
        return mix.outputs[1]

    n_in = group_in.outputs["Normal"]
    has_n = ops.less(1e-6, vmath("LENGTH", n_in))
    normal = vmath("NORMALIZE", choose(has_n, n_in, geo.outputs["Normal"]))
    tangent = None
    if aniso:
        def obj_axis(v, label):
            vt = ops._place(nodes.new("ShaderNodeVectorTransform"))
            vt.name = vt.label = label
            vt.vector_type = "VECTOR"
            vt.convert_from = "OBJECT"
            vt.convert_to = "WORLD"
            vt.inputs["Vector"].default_value = v
            return vt.outputs["Vector"]

        def perp(t):  # t - (t.n) n
            return vmath("SUBTRACT", t, vmath("SCALE", normal, scale=vmath("DOT_PRODUCT", t, normal)))

        t_in = group_in.outputs["Tangent"]
        has_t = ops.less(1e-6, vmath("LENGTH", t_in))
        t = perp(choose(has_t, t_in, obj_axis((1.0, 0.0, 0.0), "Tangent (object +X)")))
        # degenerate where the tangent is (nearly) parallel to the normal: use the object's +Y axis
        ok = ops.less(0.1, vmath("LENGTH", t))
        t = choose(ok, t, perp(obj_axis((0.0, 1.0, 0.0), "Tangent fallback (object +Y)")))
        tangent = vmath("NORMALIZE", t)
    cos_o = ops.maximum(vmath("DOT_PRODUCT", geo.outputs["Incoming"], normal), 0.0)
    return normal, tangent, cos_o


def _view_weight(ops, view, cos_o):
    w = 1.0
    for f in view:
        if f[0] == "pow":
            w = ops.mul(w, ops.pow(cos_o, float(f[1])))
        elif f[0] == "as_diffuse":
            w = ops.mul(w, ops.sub(1.0, ops.pow(ops.sub(1.0, ops.mul(0.5, cos_o)), 5.0)))
    return w


def _weighted(ops, color, view, cos_o):
    if not view:
        return color
    return ops.cscale(color, _view_weight(ops, view, cos_o))


def _ior_value(ops, v):
    if isinstance(v, tuple) and len(v) == 2 and v[0] == "rgb":
        return ops.rgb_from_scalar(v[1])
    return v


def _vmath(ops, op, a, b=None, scale=None):
    n = ops._place(ops.nodes.new("ShaderNodeVectorMath"))
    n.operation = op
    ops.set(n.inputs[0], a)
    if b is not None:
        ops.set(n.inputs[1], b)
    if scale is not None:
        ops.set(n.inputs["Scale"], scale)
    return n.outputs["Value"] if op in ("DOT_PRODUCT", "LENGTH") else n.outputs["Vector"]


def _tilted_normal(ops, normal, cos_o, tilt):
    """The normal leaning towards the viewer, N' = normalize(N + tilt (I - cos_o N) / max(cos_o, m)), as
    ``closures.tilted_normal`` models it (I: Geometry > Incoming); one per tilt value in a group."""
    from .closures import TILT_MIN_COS

    cache = ops.__dict__.setdefault("_tilted", {})
    key = (tilt.node.name, tilt.identifier) if _is_socket(tilt) else float(tilt)
    if key not in cache:
        geo = ops._place(ops.nodes.new("ShaderNodeNewGeometry"))
        geo.label = "Geometry (view for the tilted normal)"
        incoming = geo.outputs["Incoming"]
        along = _vmath(ops, "SUBTRACT", incoming, _vmath(ops, "SCALE", normal, scale=cos_o))
        lean = _vmath(ops, "SCALE", along, scale=ops.div(tilt, ops.maximum(cos_o, TILT_MIN_COS)))
        cache[key] = _vmath(ops, "NORMALIZE", _vmath(ops, "ADD", normal, lean))
    return cache[key]


def _closure_node(ops, term, normal, tangent, cos_o, x, y):
    """Shader nodes for one symbolic term (fields: numbers or sockets); returns its shader output."""
    from . import laws as L

    nodes, links = ops.nodes, ops.links
    c = term.closure
    color = _weighted(ops, term.color, term.view, cos_o)
    if _is_socket(term.tilt) or float(term.tilt) != 0.0:
        normal = _tilted_normal(ops, normal, cos_o, term.tilt)
    if c == "toon":
        n = nodes.new("ShaderNodeBsdfToon")
        n.component = "GLOSSY"
        ops.set(n.inputs["Color"], color)
        ops.set(n.inputs["Size"], term.size)
        ops.set(n.inputs["Smooth"], term.smooth)
    elif c in ("diffuse", "oren_nayar"):
        n = nodes.new("ShaderNodeBsdfDiffuse")
        ops.set(n.inputs["Color"], color)
        ops.set(n.inputs["Roughness"], term.roughness if c == "oren_nayar" else 0.0)
    elif c == "phong_ramp":
        raise ValueError("the Phong lobe exists only as an OSL closure (phong_ramp); use method='osl'")
    elif term.fresnel in ("schlick", "conductor"):
        n = nodes.new("ShaderNodeBsdfMetallic")
        n.distribution = "BECKMANN" if term.distribution == "beckmann" else "GGX"
        if term.fresnel == "schlick":
            n.fresnel_type = "F82"
            ops.set(n.inputs["Base Color"], term.f0)
            n.inputs["Edge Tint"].default_value = (1.0, 1.0, 1.0, 1.0)  # white tint = pure Schlick
        else:
            n.fresnel_type = "PHYSICAL_CONDUCTOR"
            ops.set(n.inputs["IOR"], _ior_value(ops, term.ior))
            ops.set(n.inputs["Extinction"], term.k)
        if c == "mirror":
            n.inputs["Roughness"].default_value = 0.0
        else:
            r, a, rot = L.metallic_controls(ops, term.alpha_x, term.alpha_y)
            ops.set(n.inputs["Roughness"], r)
            if tangent is not None:
                ops.set(n.inputs["Anisotropy"], a)
                ops.set(n.inputs["Rotation"], rot)
                links.new(tangent, n.inputs["Tangent"])
        links.new(normal, n.inputs["Normal"])
        weight = term.color[0] if isinstance(term.color, tuple) else 1.0
        if abs(float(weight) - 1.0) > 1e-9 or term.view:
            # Metallic has no colour weight: scale it with a Mix Shader against "no closure".
            mix = nodes.new("ShaderNodeMixShader")
            ops.set(mix.inputs["Fac"], ops.mul(weight, _view_weight(ops, term.view, cos_o)))
            mix.location = (x + 200, y)
            links.new(n.outputs[0], mix.inputs[2])
            n.location = (x, y)
            return mix.outputs[0]
    else:  # microfacet / mirror with F = 1
        n = nodes.new("ShaderNodeBsdfGlossy")
        n.distribution = {"beckmann": "BECKMANN", "ggx": "GGX"}.get(term.distribution, "GGX")
        if c == "ashikhmin_shirley":
            n.distribution = "ASHIKHMIN_SHIRLEY"
        ops.set(n.inputs["Color"], color)
        if c == "mirror":
            n.inputs["Roughness"].default_value = 0.0
        else:
            r, a = L.glossy_controls(ops, term.alpha_x, term.alpha_y)
            ops.set(n.inputs["Roughness"], r)
            if tangent is not None:
                ops.set(n.inputs["Anisotropy"], a)
                links.new(tangent, n.inputs["Tangent"])
    if "Normal" in n.inputs and not n.inputs["Normal"].is_linked:
        links.new(normal, n.inputs["Normal"])
    n.location = (x, y)
    return n.outputs[0]


def _osl_node(ops, terms, normal, tangent, cos_o, script):
    """One Script node (``shading/osl/radiometer_brdf.osl``) wired to the symbolic terms."""
    from . import osl as O

    node = ops.nodes.new("ShaderNodeScript")
    node.name = node.label = O.NODE_NAME
    node.mode = "INTERNAL"
    node.script = script
    O.compile_node(node)
    inp = node.inputs
    ops.set(inp["DiffuseColor"], (0.0, 0.0, 0.0))
    ops.set(inp["SpecularKind"], O.KIND_NONE)
    ops.links.new(normal, inp["Normal"])
    if tangent is not None:
        ops.links.new(tangent, inp["Tangent"])
    for t in terms:
        c = t.closure
        color = _weighted(ops, t.color, t.view, cos_o)
        if c in ("diffuse", "oren_nayar"):
            ops.set(inp["DiffuseColor"], color)
            ops.set(inp["DiffuseRoughness"], t.roughness if c == "oren_nayar" else 0.0)
            continue
        ops.set(inp["SpecularColor"], color)
        if _is_socket(t.tilt) or float(t.tilt) != 0.0:  # the lobe's own normal, leaning towards the view
            ops.links.new(_tilted_normal(ops, normal, cos_o, t.tilt), inp["SpecularNormal"])
        ops.set(inp["AlphaX"], t.alpha_x)
        ops.set(inp["AlphaY"], t.alpha_y)
        ops.set(inp["Beckmann"], int(t.distribution == "beckmann"))
        if c == "phong_ramp":
            ops.set(inp["SpecularKind"], O.KIND_PHONG)
            ops.set(inp["PhongExponent"], t.exponent)
        elif c == "mirror" and t.fresnel == "none":
            ops.set(inp["SpecularKind"], O.KIND_MIRROR)
        else:
            if c == "mirror":
                ops.set(inp["AlphaX"], 0.0)
                ops.set(inp["AlphaY"], 0.0)
            kind = {"none": O.KIND_MICROFACET, "schlick": O.KIND_SCHLICK, "conductor": O.KIND_CONDUCTOR}[t.fresnel]
            ops.set(inp["SpecularKind"], kind)
            ops.set(inp["F0"], t.f0)
            ops.set(inp["IOR"], _ior_value(ops, t.ior))
            ops.set(inp["Extinction"], t.k)
    node.location = (300, 0)
    return node.outputs["BSDF"]


def group_signature(model, method, structure):
    return json.dumps({"model": model, "method": method, "structure": structure}, sort_keys=True)


def _ensure_interface(group, model, structure, specs):
    """Inputs: the model's parameters, Normal (and Tangent); output BSDF. Kept when already right."""
    from . import laws as L

    names = L.input_names(model, structure) + ["Normal"] + (["Tangent"] if structure.get("aniso") else [])
    items = [s for s in group.interface.items_tree if getattr(s, "item_type", "SOCKET") == "SOCKET"]
    have = [s.name for s in items if s.in_out == "INPUT"]
    if have != names:
        for s in items:
            if s.in_out == "INPUT":
                group.interface.remove(s)
        for name in names:
            if name in ("Normal", "Tangent"):
                sock = group.interface.new_socket(name, in_out="INPUT", socket_type="NodeSocketVector")
                sock.hide_value = True
                sock.description = ("Shading normal (unlinked: the surface's own)" if name == "Normal" else
                                    "Tangent of the anisotropy frame, world space (unlinked: the object's +X "
                                    "axis, +Y where +X is parallel to the normal)")
                continue
            spec = specs[name]
            stype, subtype = _socket_type(spec, name, model, structure)
            sock = group.interface.new_socket(name, in_out="INPUT", socket_type=stype)
            if subtype:
                sock.subtype = subtype
            unit = f" [{spec['unit']}]" if spec.get("unit") not in (None, "", "1") else ""
            sock.description = (spec.get("description") or "") + unit
            if stype != "NodeSocketColor":
                if spec.get("min") is not None:
                    sock.min_value = float(spec["min"])
                if spec.get("max") is not None:
                    sock.max_value = float(spec["max"])
    if not any(s.in_out == "OUTPUT" and s.name == GROUP_OUTPUT_SOCKET for s in items):
        group.interface.new_socket(GROUP_OUTPUT_SOCKET, in_out="OUTPUT", socket_type="NodeSocketShader")
    return names


def build_group(model, method, structure, coefficients, specs, name, group=None, script=None):
    """Create (or rebuild in place) the node group realising ``model``; return the ShaderNodeTree.

    The interface is kept when it already has the right inputs (links from the user's nodes into
    the group node survive); the inner nodes belong to Radiometer and are rebuilt. ``script`` is the
    OSL text block for method 'osl'.
    """
    import bpy

    from . import laws as L

    if group is None:
        group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    _ensure_interface(group, model, structure, specs)
    group.nodes.clear()
    gin = group.nodes.new("NodeGroupInput")
    gin.location = (-1200, 0)
    out = group.nodes.new("NodeGroupOutput")
    out.location = (700, 0)
    ops = NodeOps(group)
    normal, tangent, cos_o = _frame_sockets(ops, gin, structure.get("aniso"))
    x = {n: gin.outputs[n] for n in L.input_names(model, structure)}
    terms = L.law(ops, model, method, structure, x, coefficients)
    if method == "osl":
        acc = _osl_node(ops, terms, normal, tangent, cos_o, script)
    else:
        sockets = [_closure_node(ops, t, normal, tangent, cos_o, 0, -320 * i) for i, t in enumerate(terms)]
        acc = sockets[0]
        for i, s in enumerate(sockets[1:]):
            add = group.nodes.new("ShaderNodeAddShader")
            add.location = (400 + 200 * i, -160 * i)
            group.links.new(acc, add.inputs[0])
            group.links.new(s, add.inputs[1])
            acc = add.outputs[0]
    group.links.new(acc, out.inputs[GROUP_OUTPUT_SOCKET])
    group["radiometer_signature"] = group_signature(model, method, structure)
    group["radiometer_coefficients"] = json.dumps(coefficients, sort_keys=True)
    return group


def build_terms_group(terms, name, group=None):
    """A plain group whose output is the sum of numeric ``terms`` (closure checks in the tests)."""
    import bpy

    if group is None:
        group = bpy.data.node_groups.new(name, "ShaderNodeTree")
    if not any(s.in_out == "OUTPUT" for s in group.interface.items_tree if getattr(s, "item_type", "") == "SOCKET"):
        group.interface.new_socket(GROUP_OUTPUT_SOCKET, in_out="OUTPUT", socket_type="NodeSocketShader")
    group.interface.new_socket("Normal", in_out="INPUT", socket_type="NodeSocketVector").hide_value = True
    aniso = any(t.closure in ("microfacet", "ashikhmin_shirley") and abs(t.alpha_x - t.alpha_y) > 1e-9 for t in terms)
    if aniso:
        group.interface.new_socket("Tangent", in_out="INPUT", socket_type="NodeSocketVector").hide_value = True
    group.nodes.clear()
    gin = group.nodes.new("NodeGroupInput")
    out = group.nodes.new("NodeGroupOutput")
    ops = NodeOps(group)
    normal, tangent, cos_o = _frame_sockets(ops, gin, aniso)
    sockets = [_closure_node(ops, t, normal, tangent, cos_o, 0, -320 * i) for i, t in enumerate(terms)]
    acc = sockets[0]
    for s in sockets[1:]:
        add = group.nodes.new("ShaderNodeAddShader")
        group.links.new(acc, add.inputs[0])
        group.links.new(s, add.inputs[1])
        acc = add.outputs[0]
    group.links.new(acc, out.inputs[GROUP_OUTPUT_SOCKET])
    return group

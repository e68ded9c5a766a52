"""Thin glass in the scene (issue 18): which materials are window panes, and the thin-pane shader
that a measurement renders in their place.

``pane_optics(material)`` reads a material as a pane when its surface is one of

* a Glass BSDF of roughness 0 (IOR and Color from the node; Color tints every crossing and every
  reflection, as Cycles weights the closure),
* a Principled BSDF that is all transmission (Transmission Weight 1, Metallic 0, Roughness 0, Alpha 1,
  no coat, sheen, subsurface, emission or thin film; Base Color tints transmission, Specular Tint the
  reflection, the IOR from the node; Specular IOR Level 0.5),
* the archviz trick: a Mix Shader whose factor is Light Path > Is Shadow Ray, with a white Transparent
  BSDF for shadow rays and one of the above for the rest. It is read as the real pane it depicts:
  Cycles would count the light twice there (shadow ray through the transparent part + refraction).

with every input unlinked, and no Volume or a plain Volume Absorption (absorption coefficient
density x (1 - Color) per scene unit, Cycles' definition) along the refracted path. Anything else that
transmits (a rough "frosted" pane, a textured one) stays rendered as it is, and the reason is kept for
the notes.

``thin_pane_material(pane)`` builds the material a measurement swaps in (restored by the scene
guard): per shading point, the incidence cosine |N . I| from the geometry drives exact Fresnel (math
nodes, both polarisations), and the whole pane's T goes to a Transparent BSDF and its R to a sharp
Glossy BSDF (no Fresnel in Cycles 4+), on the faces hit from the front; back faces of a slab are
fully transparent (the front face already stands for the pane), so a ray through the slab keeps
T(theta) of the closed form and a shadow ray through it converges like direct light. Reflection is
seen only by rays that were not already reflected by a glossy surface (Light Path > Is Glossy Ray).
Multiple glazing (parallel panes of one outline, a shallow gap: ``stand_in_stacks``) is rendered as ONE
stand-in pane carrying the whole unit's T and R by the adding formula, the other panes clear, so the
light bouncing between the panes is rendered too (issue 18, F5).
"""

import bpy

from ...compat import ensure_node_tree

#: Largest Glass/Principled roughness read as a smooth pane.
SMOOTH = 0.0


def _unlinked(node, *names):
    return all(node.inputs.get(n) is None or not node.inputs[n].is_linked for n in names)


def _value(node, name, default=None):
    socket = node.inputs.get(name)
    return default if socket is None else socket.default_value


def _surface_node(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    active = [n for n in outputs if n.is_active_output and getattr(n, "target", "ALL") in ("ALL", "CYCLES")]
    out = (active or [n for n in outputs if getattr(n, "target", "ALL") in ("ALL", "CYCLES")] or [None])[0]
    if out is None:
        return None, None
    surface = out.inputs["Surface"]
    if not surface.is_linked:
        return None, None
    return surface.links[0].from_node, None


def _absorption(tree):
    """(sigma_a per scene unit (3,), "") of the material's Volume: nothing, or one Volume Absorption
    with unlinked inputs (Cycles: sigma_a = density (1 - Color)); else (None, reason)."""
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    active = [n for n in outputs if n.is_active_output] or outputs
    volume = active[0].inputs["Volume"] if active else None
    if volume is None or not volume.is_linked:
        return (0.0, 0.0, 0.0), ""
    node = volume.links[0].from_node
    if node.bl_idname != "ShaderNodeVolumeAbsorption" or not _unlinked(node, "Color", "Density"):
        return None, "a Volume other than a plain Volume Absorption inside the pane: rendered"
    density = float(_value(node, "Density", 1.0))
    return tuple(density * (1.0 - float(c)) for c in _value(node, "Color")[:3]), ""


def _node_optics(node):
    """(optics dict, reason) of a shader node read as a pane, or (None, reason)."""
    kind = node.bl_idname
    if kind == "ShaderNodeBsdfGlass":
        if not _unlinked(node, "Color", "Roughness", "IOR", "Normal"):
            return None, "Glass BSDF with linked inputs"
        rough = float(_value(node, "Roughness", 0.0))
        if rough > SMOOTH:
            return None, f"frosted Glass BSDF (roughness {rough:g}): rendered"
        colour = tuple(float(c) for c in _value(node, "Color")[:3])
        return {"ior": float(_value(node, "IOR", 1.5)), "tint_t": colour, "tint_r": colour,
                "model": "Glass BSDF"}, ""
    if kind == "ShaderNodeBsdfPrincipled":
        zero = ("Metallic", "Roughness", "Coat Weight", "Sheen Weight", "Subsurface Weight", "Emission Strength",
                "Thin Film Thickness")
        if not _unlinked(node, *(zero + ("Base Color", "IOR", "Transmission Weight", "Alpha", "Specular Tint",
                                        "Specular IOR Level", "Normal"))):
            return None, "Principled BSDF with linked inputs"
        if float(_value(node, "Transmission Weight", 0.0)) != 1.0:
            return None, "Principled BSDF not fully transmissive"
        for name in zero:
            if float(_value(node, name, 0.0)) != 0.0:
                return None, f"Principled BSDF glass with {name} {float(_value(node, name)):g}: rendered"
        if float(_value(node, "Alpha", 1.0)) != 1.0 or abs(float(_value(node, "Specular IOR Level", 0.5)) - 0.5) > 1e-9:
            return None, "Principled BSDF glass with alpha or a specular level: rendered"
        return {"ior": float(_value(node, "IOR", 1.5)),
                "tint_t": tuple(float(c) for c in _value(node, "Base Color")[:3]),
                "tint_r": tuple(float(c) for c in _value(node, "Specular Tint", (1, 1, 1, 1))[:3]),
                "model": "Principled BSDF (transmission 1)"}, ""
    if kind == "ShaderNodeMixShader":
        fac = node.inputs[0]
        if not fac.is_linked:
            return None, "Mix Shader"
        link = fac.links[0]
        shadow, other = node.inputs[2], node.inputs[1]
        if (link.from_node.bl_idname != "ShaderNodeLightPath" or link.from_socket.name != "Is Shadow Ray"
                or not shadow.is_linked or not other.is_linked):
            return None, "Mix Shader"
        transparent = shadow.links[0].from_node
        if transparent.bl_idname != "ShaderNodeBsdfTransparent" or not _unlinked(transparent, "Color") \
                or tuple(_value(transparent, "Color")[:3]) != (1.0, 1.0, 1.0):
            return None, "Is Shadow Ray mix without a white Transparent BSDF"
        optics, why = _node_optics(other.links[0].from_node)
        if optics is None:
            return None, why
        return dict(optics, model=optics["model"] + " with the 'Is Shadow Ray -> Transparent' trick", trick=True), ""
    return None, ""


def pane_optics(material):
    """(optics dict or None, reason): the material read as a thin pane (module docstring)."""
    if material is None:
        return None, ""
    from ...compat import active_node_tree

    tree = active_node_tree(material)
    if tree is None:
        return None, ""
    node, why = _surface_node(tree)
    if node is None:
        return None, why or ""
    optics, why = _node_optics(node)
    if optics is None:
        return None, why
    sigma, why = _absorption(tree)
    if sigma is None:
        return None, why
    if any(sigma):
        optics = dict(optics, absorption=sigma, model=optics["model"] + " with a Volume Absorption inside")
    return optics, ""


# --- the thin-pane shader swapped in for a measurement ----------------------------------------------

class _Math:
    """Tiny expression builder over Math nodes (scalars)."""

    def __init__(self, tree):
        self.tree = tree

    def op(self, operation, a, b=None):
        node = self.tree.nodes.new("ShaderNodeMath")
        node.operation = operation
        node.use_clamp = False
        for k, x in enumerate((a, b)):
            if x is None:
                continue
            if isinstance(x, (int, float)):
                node.inputs[k].default_value = float(x)
            else:
                self.tree.links.new(x, node.inputs[k])
        return node.outputs[0]

    def add(self, a, b): return self.op("ADD", a, b)  # noqa: E704
    def sub(self, a, b): return self.op("SUBTRACT", a, b)  # noqa: E704
    def mul(self, a, b): return self.op("MULTIPLY", a, b)  # noqa: E704
    def div(self, a, b): return self.op("DIVIDE", a, b)  # noqa: E704
    def sqrt(self, a): return self.op("SQRT", a)  # noqa: E704
    def exp(self, a): return self.op("EXPONENT", a)  # noqa: E704
    def max(self, a, b): return self.op("MAXIMUM", a, b)  # noqa: E704


def _pane_channels(m, pane, cos_i):
    """Per channel (T sockets (3,), R sockets (3,)) of ``pane``'s closed form at the incidence cosine
    socket ``cos_i``: exact Fresnel, both polarisations averaged, internal reflections, absorption."""
    n = float(pane.ior)
    sin_t2 = m.div(m.sub(1.0, m.mul(cos_i, cos_i)), n * n)
    cos_t = m.sqrt(m.max(m.sub(1.0, sin_t2), 0.0))
    n_ct = m.mul(cos_t, n)
    n_ci = m.mul(cos_i, n)
    rs = m.op("POWER", m.div(m.sub(cos_i, n_ct), m.add(cos_i, n_ct)), 2.0)
    rp = m.op("POWER", m.div(m.sub(n_ci, cos_t), m.add(n_ci, cos_t)), 2.0)
    channels_t, channels_r = [], []
    for ch in range(3):
        sigma = float(pane.absorption[ch]) * float(pane.thickness)
        a = m.exp(m.div(-sigma, m.max(cos_t, 1e-6))) if sigma > 0 else 1.0
        t, cr = float(pane.tint_t[ch]), float(pane.tint_r[ch])
        T_sum, R_sum = None, None
        for r in (rs, rp):
            one_r = m.sub(1.0, r)
            ra = m.mul(r, a) if not isinstance(a, float) else r
            denom = m.sub(1.0, m.mul(m.mul(ra, ra), cr * cr))
            top = m.mul(m.mul(one_r, one_r), t * t)
            top = m.mul(top, a) if not isinstance(a, float) else top
            T_pol = m.div(top, denom)
            a2 = m.mul(a, a) if not isinstance(a, float) else 1.0
            R_pol = m.add(m.mul(r, cr), m.div(m.mul(m.mul(m.mul(m.mul(one_r, one_r), r), a2), t * t * cr), denom))
            T_sum = T_pol if T_sum is None else m.add(T_sum, T_pol)
            R_sum = R_pol if R_sum is None else m.add(R_sum, R_pol)
        channels_t.append(m.mul(T_sum, 0.5))
        channels_r.append(m.mul(R_sum, 0.5))
    return channels_t, channels_r


def _stack_channels(m, layers):
    """(T, R) sockets per channel of parallel panes met in order (``layers``: their ``_pane_channels``),
    by the adding formula of ``thin_glass.stack``."""
    T, R = list(layers[0][0]), list(layers[0][1])
    for t, r in layers[1:]:
        for ch in range(3):
            denom = m.sub(1.0, m.mul(R[ch], r[ch]))
            T[ch], R[ch] = (m.div(m.mul(T[ch], t[ch]), denom),
                            m.add(R[ch], m.div(m.mul(m.mul(T[ch], T[ch]), r[ch]), denom)))
    return T, R


def thin_pane_material(pane, name, stack=None):
    """A new material (removed by the scene guard with every data-block a measurement creates) that
    renders ``pane`` (``radiometry.scene.thin_glass.Pane``) as thin glass with the closed form's T and R.
    ``stack``: all the panes of a multiple glazing unit ``pane`` stands in for (issue 18, F5), in order
    along ``pane.geometry.normal``: T and R of the whole stack by the adding formula (R from the side the
    ray comes from), so the light bouncing between the panes is rendered; the others are clear."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    m = _Math(tree)
    geo = tree.nodes.new("ShaderNodeNewGeometry")
    dot = tree.nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    tree.links.new(geo.outputs["True Normal"], dot.inputs[0])
    tree.links.new(geo.outputs["Incoming"], dot.inputs[1])
    cos_i = m.op("ABSOLUTE", dot.outputs["Value"])
    cos_i = m.op("MINIMUM", m.max(cos_i, 1e-6), 1.0)
    if not stack or len(stack) < 2:
        channels_t, channels_r = _pane_channels(m, pane, cos_i)
    else:
        layers = [_pane_channels(m, p, cos_i) for p in stack]
        channels_t, r_up = _stack_channels(m, layers)          # met from the lowest offset up
        _t, r_down = _stack_channels(m, layers[::-1])         # met from the highest offset down
        side = tree.nodes.new("ShaderNodeVectorMath")
        side.operation = "DOT_PRODUCT"
        tree.links.new(geo.outputs["Incoming"], side.inputs[0])  # Incoming points back along the ray
        side.inputs[1].default_value = tuple(float(x) for x in pane.geometry.normal)
        from_above = m.op("GREATER_THAN", side.outputs["Value"], 0.0)
        channels_r = [m.add(r_up[ch], m.mul(from_above, m.sub(r_down[ch], r_up[ch]))) for ch in range(3)]

    def combine(channels):
        node = tree.nodes.new("ShaderNodeCombineColor")
        for k, s in enumerate(channels):
            tree.links.new(s, node.inputs[k])
        return node.outputs[0]

    transparent = tree.nodes.new("ShaderNodeBsdfTransparent")
    tree.links.new(combine(channels_t), transparent.inputs["Color"])
    glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
    glossy.inputs["Roughness"].default_value = 0.0
    tree.links.new(combine(channels_r), glossy.inputs["Color"])
    # the mirror is the pane's plane, whatever the mesh's smooth shading: a smoothed normal would tilt it at the
    # pane's edges (the closed forms and the dark-meter proof, radiometry/scene/sealed.py, take the plane)
    tree.links.new(geo.outputs["True Normal"], glossy.inputs["Normal"])
    add = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(transparent.outputs[0], add.inputs[0])
    tree.links.new(glossy.outputs[0], add.inputs[1])
    path = tree.nodes.new("ShaderNodeLightPath")
    # Rays already reflected by a glossy surface see the pane's transmission only (module docstring).
    no_mirror = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(path.outputs["Is Glossy Ray"], no_mirror.inputs[0])
    tree.links.new(add.outputs[0], no_mirror.inputs[1])
    transparent_only = tree.nodes.new("ShaderNodeBsdfTransparent")
    tree.links.new(combine(channels_t), transparent_only.inputs["Color"])
    tree.links.new(transparent_only.outputs[0], no_mirror.inputs[2])
    shader = no_mirror
    if pane.thickness > 0.0:
        # A slab: the face a ray enters by stands for the whole pane, the face it leaves by is clear.
        clear = tree.nodes.new("ShaderNodeBsdfTransparent")
        back = tree.nodes.new("ShaderNodeMixShader")
        tree.links.new(geo.outputs["Backfacing"], back.inputs[0])
        tree.links.new(no_mirror.outputs[0], back.inputs[1])
        tree.links.new(clear.outputs[0], back.inputs[2])
        shader = back
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(shader.outputs[0], out.inputs["Surface"])
    return mat


def _clear_material(name):
    """A new material that lets every ray through unchanged (a pane of a stack whose stand-in carries it)."""
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    clear = tree.nodes.new("ShaderNodeBsdfTransparent")
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(clear.outputs[0], out.inputs["Surface"])
    return mat


#: Largest depth of a stack of panes (outermost face planes), as a fraction of its outline's smallest width,
#: rendered as one stand-in: a ray entering the gap from the side meets one pane only, a share of the
#: light crossing the unit of at most about depth / width x tan(theta) (2 % for double glazing 24 mm deep
#: and 1.2 m wide at 45 deg); deeper stacks keep a thin pane each.
STACK_DEPTH = 0.05


def stand_in_stacks(panes, objects=None):
    """Stacks of parallel panes (``thin_glass.parallel_stacks``) rendered as ONE stand-in pane (issue 18,
    F5): (the stand-in, the Panes in order along its normal), for stacks whose panes
    have the same outline (a ray crossing one crosses all) and each its own object (one material per
    object); other stacks keep a thin pane each (their inter-pane light is not rendered)."""
    import numpy as np

    from ...radiometry.scene import thin_glass

    panes = panes or {}
    objects = pane_objects(panes) if objects is None else objects
    alone = {id(own[0]) for own in objects.values() if len(own) == 1}
    out = []
    for keys in thin_glass.parallel_stacks(panes):
        group = [panes[k] for k in keys]
        first = group[0].geometry
        if not all(id(p) in alone for p in group) or not all(_same_outline(first, p.geometry) for p in group[1:]):
            continue
        if _stack_depth(group) > STACK_DEPTH * float(np.min(np.ptp(first.hull, axis=0))):
            continue  # rays entering the gap from the side would meet one pane only
        order = np.argsort([float(np.mean(p.geometry.heights)) * float(np.sign(p.geometry.normal @ first.normal))
                            for p in group])
        out.append((group[0], [group[k] for k in order]))
    return out


def _stacks(panes):
    """(stack, rendered as one stand-in) for every stack of parallel panes in ``panes`` (each stack the
    Panes in ``thin_glass.parallel_stacks`` order)."""
    from ...radiometry.scene import thin_glass

    panes = panes or {}
    modelled = {frozenset(id(p) for p in group) for _lead, group in stand_in_stacks(panes)}
    return [([panes[k] for k in keys], frozenset(id(panes[k]) for k in keys) in modelled)
            for keys in thin_glass.parallel_stacks(panes)]


def stacks_rendered_whole(panes):
    """True when every stack of parallel panes in ``panes`` is rendered as one stand-in
    (``stand_in_stacks``), so every render holds the light bouncing between their panes."""
    return all(whole for _stack, whole in _stacks(panes))


def _stack_depth(group):
    """Distance in m between the outermost face planes of parallel panes (their normals may point either way)."""
    import numpy as np

    n = group[0].geometry.normal
    offsets = [h * float(np.sign(p.geometry.normal @ n)) for p in group for h in p.geometry.heights]
    return float(max(offsets) - min(offsets))


def _same_outline(a, b):
    """True when pane geometry ``b``'s outline, seen along ``a``'s normal, has ``a``'s corners."""
    import numpy as np

    corners = b.origin + b.hull[:, :1] * b.u + b.hull[:, 1:] * b.v
    flat = np.stack([(corners - a.origin) @ a.u, (corners - a.origin) @ a.v], axis=1)
    tol = 1e-6 * max(1.0, float(np.abs(a.hull).max()), float(np.abs(a.origin).max()))
    if len(flat) != len(a.hull):
        return False
    return all(np.min(np.linalg.norm(a.hull - x, axis=1)) <= tol for x in flat)


def pane_objects(panes):
    """{object: [panes]}: the Blender object behind every pane, found by the capture's identity
    (``Pane.source_id``: session uid and library, ``measure.blender.identity``), never by name, so a pane
    renamed after its capture (a cached capture) is still found. A pane built without a capture
    (no ``source_id``) is found by its name."""
    from ..blender.identity import source_objects

    panes = list((panes or {}).values())
    found = source_objects(p.source_id for p in panes)
    out = {}
    for pane in panes:
        if pane.source_id is not None:
            obj = found.get(tuple(pane.source_id[:2]))
        else:
            obj = bpy.data.objects.get(pane.source)
        if obj is not None:
            out.setdefault(obj, []).append(pane)
    return out


def swap_panes(snapshot, panes):
    """Give every thin pane's object the thin-pane material for the measurement (the old slot links
    and materials are remembered by ``snapshot``, a ``scene_guard.SceneSnapshot``, and come back on
    exit; the new materials are removed with every data-block the measurement created). The objects
    are found by identity (``pane_objects``), and the material is linked to the OBJECT, not to its
    mesh: two objects sharing one mesh (a linked duplicate) may be different panes (another scale,
    another thickness), and the mesh, which other objects may use, is never changed. Every instance
    of one object gets the material of its first pane. Returns the names of the objects swapped."""
    done = []
    objects = pane_objects(panes)
    role = {}  # id(pane): the stack it stands in for, or () for a clear pane of a stack (issue 18, F5)
    for lead, group in stand_in_stacks(panes, objects):
        role.update((id(p), ()) for p in group)
        role[id(lead)] = group
    for obj, own in objects.items():
        pane = own[0]
        if not obj.material_slots:
            continue
        stack = role.get(id(pane))
        if stack is not None and not len(stack):
            mat = _clear_material(f"radiometer clear pane {obj.name}")
        else:
            mat = thin_pane_material(pane, f"radiometer thin pane {obj.name}", stack=stack)
        for j, slot in enumerate(obj.material_slots):
            if pane.slots and j not in pane.slots:
                continue  # a window frame in the same mesh keeps its material
            if slot.link != "OBJECT":
                snapshot.remember(slot, "link")
                slot.link = "OBJECT"
            snapshot.remember(slot, "material")  # the object-level one: restored before the link
            slot.material = mat
        done.append(obj.name)
    return sorted(done)


# --- rough refraction: light sampling finds small lights (issue 18) -----------------------------------

#: Smallest roughness (Cycles' roughness r, GGX alpha = r^2) of every refracting closure of a material at
#: which a small light (sun disc, point, spot) seen through it is found by Cycles' light sampling at the
#: refraction vertex within the samples a measurement spends, so the rendered reading's stochastic error
#: covers it. Measured against converged patch renders (docs/glass-and-fog.md, "Frosted panes are no
#: caustic"): at r = 0.3, 42/44 preview readings of a point light and the 0.53 degree sun within 1.96
#: s.e.; at r = 0.2 a point light's mean sits 1.5 % low over 22 seeds; at r = 0.1 the lobe (about 0.6
#: degrees) is hit by a few in 10^4 of a meter's rays.
ROUGH_REFRACTION = 0.3

_REFRACTING_NODES = ("ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction")


def closure_nodes(material, node_types, principled_input):
    """(nodes, hidden) of ``material``'s active node tree: its unmuted nodes of ``node_types``, and its
    Principled BSDFs whose ``principled_input`` (e.g. "Transmission Weight", "Metallic") is linked or
    not 0; ``hidden`` is True when a node group or script could hold more. ((), False) without a tree."""
    from ...compat import active_node_tree

    tree = active_node_tree(material) if material is not None else None
    if tree is None:
        return (), False
    nodes, hidden = [], False
    for node in tree.nodes:
        if node.mute:
            continue
        if node.bl_idname in ("ShaderNodeGroup", "ShaderNodeScript"):
            hidden = True
        elif node.bl_idname == "ShaderNodeBsdfPrincipled":
            gate = node.inputs.get(principled_input)
            if gate is not None and (gate.is_linked or float(gate.default_value) != 0.0):
                nodes.append(node)
        elif node.bl_idname in node_types:
            nodes.append(node)
    return nodes, hidden


def rough_refraction(material):
    """True when every node of ``material`` that refracts (a Glass or Refraction BSDF, a Principled BSDF
    with transmission) has an unlinked roughness of at least ROUGH_REFRACTION, and nothing else in it
    (a node group, a script) could refract sharply: such a material is no caustic for small lights."""
    nodes, hidden = closure_nodes(material, _REFRACTING_NODES, "Transmission Weight")
    if hidden or not nodes:
        return False
    for node in nodes:
        rough = node.inputs.get("Roughness")
        if rough is None or rough.is_linked or float(rough.default_value) < ROUGH_REFRACTION:
            return False
    return True


# --- sharp mirrors (issue 18) ---------------------------------------------------------------------------

#: Largest roughness read as a sharp mirror: Cycles' alpha = r^2 = 0.01 is a lobe of about half a
#: degree, whose image of a small light a path tracer finds about as rarely as a refracted one.
SHARP_ROUGHNESS = 0.1

_REFLECTING_NODES = ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic", "ShaderNodeBsdfMetallic",
                     "ShaderNodeBsdfPrincipled", "ShaderNodeBsdfGlass")


def _sharp(node, roughness="Roughness"):
    socket = node.inputs.get(roughness)
    return socket is not None and (socket.is_linked or float(socket.default_value) <= SHARP_ROUGHNESS)


def sharp_mirror(material):
    """True when ``material`` may reflect like a sharp mirror: a Glossy, Metallic, Glass or Principled
    BSDF (its specular layer, or a coat) whose roughness is at most SHARP_ROUGHNESS or fed by a link
    (a texture may be sharp somewhere). Every node of the tree counts (conservative)."""
    from ...compat import active_node_tree

    tree = active_node_tree(material) if material is not None else None
    if tree is None:
        return False
    for node in tree.nodes:
        if node.bl_idname not in _REFLECTING_NODES or node.mute:
            continue
        if _sharp(node):
            return True
        coat = node.inputs.get("Coat Weight")
        if coat is not None and (coat.is_linked or float(coat.default_value) > 0.0) and _sharp(node, "Coat Roughness"):
            return True
    return False


def mirror_triangles(model):
    """((T, 3, 3) triangles in m, (T,) object names) of the render-visible objects that have a
    sharp-mirror material (``sharp_mirror``) and are visible to glossy rays; panes count (their
    thin-glass stand-in reflects sharply). Objects are found by the capture's identity
    (``SceneGeometry.object_ids``)."""
    import numpy as np

    from ..blender.identity import geometry_objects

    g = model.geometry
    keep = np.array([obj is not None and obj.visible_glossy
                     and any(sharp_mirror(slot.material) for slot in obj.material_slots)
                     for obj in geometry_objects(g)], bool)
    if not keep.any():
        return np.zeros((0, 3, 3)), np.zeros(0, dtype=object)
    index = np.asarray(g.object_index, int)
    chosen = keep[index] & ~_pane_edges(model)
    return np.asarray(g.triangles, float)[chosen], np.asarray(g.object_names, dtype=object)[index[chosen]]


def _pane_edges(model):
    """(T,) True for a thin pane's triangles that lie in neither of its face planes (a slab's edge faces;
    issue 18, F4): the thin-glass model has none, and light reaches their outside only through the slab,
    so they give no mirror image of a light. A frame in the pane's object is not a pane triangle: kept."""
    import numpy as np

    g = model.geometry
    edges = np.zeros(g.count, bool)
    pane_of = np.asarray(g.pane_of, int) if g.pane_of is not None else np.full(g.count, -1)
    for k, pane in model.panes.items():
        geom = getattr(pane, "geometry", None)
        mine = np.flatnonzero(pane_of == k)
        if geom is None or not mine.size:
            continue
        tris = np.asarray(g.triangles, float)[mine]
        tol = geom.tol or 1e-6 * max(1.0, float(np.abs(tris).max()))  # the tolerance it was recognised with
        h = tris @ np.asarray(geom.normal, float)  # (M, 3) vertex offsets along the pane's normal
        in_plane = np.zeros(mine.size, bool)
        for height in geom.heights:
            in_plane |= np.all(np.abs(h - height) <= tol, axis=1)
        edges[mine[~in_plane]] = True
    return edges


def stack_notes(model):
    """Notes on multiple glazing (issue 18, F5). A stack rendered as one stand-in (``stand_in_stacks``)
    renders the light bouncing between its panes; any other stack of parallel panes is rendered a thin
    pane each, so that light is missing from everything rendered through it (reflected light, the world,
    lights not read in closed form): the note gives its size at normal and 60 deg incidence
    (``thin_glass.interpane_share``). A meter's own closed-form direct light includes it."""
    import numpy as np

    from ...radiometry.scene import thin_glass

    notes = []
    for panes, whole in _stacks(model.panes):
        names = ", ".join(repr(p.name) for p in panes)
        if whole:
            depth = _stack_depth(panes)
            width = float(min(np.ptp(panes[0].geometry.hull, axis=0)))
            notes.append(f"multiple glazing ({names}): rendered as one stand-in pane with the whole unit's T and R "
                         "(adding formula; the other panes clear), so the light bouncing between the panes is "
                         f"rendered; the unit is {1000 * depth:.3g} mm deep on a {width:.3g} m outline: rays that "
                         f"enter the gap from the side (about {100 * depth / width:.2g} % of the light crossing at "
                         "45 deg) are not modelled")
            continue
        at_0, at_60 = (thin_glass.interpane_share(panes, c) for c in (1.0, 0.5))
        notes.append(f"multiple glazing ({names}): rendered as separate thin panes, so the light bouncing between "
                     f"them is missing from rendered light that crossed them: {100 * at_0:.2g} % of it at normal "
                     f"incidence, {100 * at_60:.2g} % at 60 deg; rendered readings may be that much low (not in "
                     "their stated error; a meter's closed-form direct light includes or bounds it)")
    return notes

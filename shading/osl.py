"""OSL realisation: one Script node running ``shading/osl/radiometer_brdf.osl`` (Cycles CPU only).

Rendering it needs ``scene.cycles.shading_system = True`` (Open Shading Language) and the CPU device;
Radiometer switches it on in a user's scene only when asked (``radiometer.enable_osl``, an undoable
operator the panel offers); ``shading.validate`` turns it on only in its own scratch scene.
"""

import os
import sys

TEXT_NAME = "radiometer_brdf.osl"
NODE_NAME = "Radiometer BRDF (OSL)"
SOURCE_PATH = os.path.join(os.path.dirname(__file__), "osl", "radiometer_brdf.osl")

# SpecularKind values of the shader (see the .osl file header).
KIND_NONE, KIND_MICROFACET, KIND_SCHLICK, KIND_CONDUCTOR, KIND_AS, KIND_PHONG, KIND_MIRROR = range(7)


def ensure_oslquery():
    """Put Blender's bundled ``oslquery`` module on sys.path (missing when bpy is a Python module)."""
    try:
        import oslquery  # noqa: F401
        return
    except ImportError:
        pass
    import bpy

    ver = f"python{sys.version_info.major}.{sys.version_info.minor}"
    path = os.path.join(bpy.utils.resource_path("LOCAL"), "python", "lib", ver, "site-packages")
    if os.path.isdir(path) and path not in sys.path:
        sys.path.append(path)


def source_text():
    import bpy

    with open(SOURCE_PATH, encoding="utf-8") as f:
        source = f.read()
    text = bpy.data.texts.get(TEXT_NAME)
    if text is None:
        text = bpy.data.texts.new(TEXT_NAME)
    if text.as_string() != source:
        text.clear()
        text.write(source)
    return text


def compile_node(node):
    """Compile the node's internal script and create its sockets; raise RuntimeError on failure."""
    ensure_oslquery()
    from cycles import osl as cycles_osl  # Blender's Cycles add-on, always present with bpy

    messages = []

    def report(kind, message):
        messages.append((set(kind), message))

    cycles_osl.update_script_node(node, report)
    errors = [m for k, m in messages if "ERROR" in k]
    if errors or "BSDF" not in node.outputs:
        raise RuntimeError("OSL compilation failed: " + "; ".join(errors or [m for _, m in messages]))


def set_inputs(node, terms):
    """Write the parameters of ``terms`` (at most one diffuse + one specular term) to the node."""
    inp = node.inputs

    def rgba(c):
        return (float(c[0]), float(c[1]), float(c[2]), 1.0)

    inp["DiffuseColor"].default_value = (0.0, 0.0, 0.0, 1.0)
    inp["DiffuseRoughness"].default_value = 0.0
    inp["Tangent"].default_value = (1.0, 0.0, 0.0)  # world +X (the validation patch is not rotated)
    inp["SpecularKind"].default_value = KIND_NONE
    for t in terms:
        c = t.closure
        if c in ("diffuse", "oren_nayar"):
            inp["DiffuseColor"].default_value = rgba(t.color)
            inp["DiffuseRoughness"].default_value = float(t.roughness) if c == "oren_nayar" else 0.0
            continue
        if float(getattr(t, "tilt", 0.0)) != 0.0:
            raise ValueError("a tilted specular normal varies with the view: build the term with "
                             "shading.nodes (it feeds SpecularNormal), not as constant inputs")
        inp["SpecularColor"].default_value = rgba(t.color)
        inp["AlphaX"].default_value = float(t.alpha_x)
        inp["AlphaY"].default_value = float(t.alpha_y)
        inp["Beckmann"].default_value = int(t.distribution == "beckmann")
        if c == "phong_ramp":
            inp["SpecularKind"].default_value = KIND_PHONG
            inp["PhongExponent"].default_value = float(t.exponent)
        elif c == "ashikhmin_shirley":
            inp["SpecularKind"].default_value = KIND_AS
        elif c == "mirror" and t.fresnel == "none":
            inp["SpecularKind"].default_value = KIND_MIRROR
        else:
            if c == "mirror":
                inp["AlphaX"].default_value = inp["AlphaY"].default_value = 0.0
            kind = {"none": KIND_MICROFACET, "schlick": KIND_SCHLICK, "conductor": KIND_CONDUCTOR}[t.fresnel]
            inp["SpecularKind"].default_value = kind
            inp["F0"].default_value = rgba(t.f0)
            inp["IOR"].default_value = rgba(t.ior)
            inp["Extinction"].default_value = rgba(t.k)


def osl_problems(scene):
    """Why OSL will not render in ``scene`` (list of sentences; empty when it will)."""
    if scene is None:
        return []
    out = []
    engine = scene.render.engine
    if engine != "CYCLES":
        out.append(f"the render engine is {engine.replace('BLENDER_', '').title()}: OSL runs only in Cycles")
    cycles = getattr(scene, "cycles", None)
    if cycles is not None:
        if not cycles.shading_system:
            out.append("Open Shading Language is off (Render Properties > Open Shading Language)")
        if getattr(cycles, "device", "CPU") != "CPU":
            out.append("the Cycles device is the GPU: OSL renders on the CPU only")
    return out

"""assign_brdf, Material.radiometer_brdf re-editing, operators: what they do to a material.

Reference values: the Cycles node conventions read from the kernel (roughness r -> alpha = r^2),
and the parameters passed in.
"""

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer.compat import ensure_node_tree  # noqa: E402


@pytest.fixture
def lib(clean_blender):
    try:
        from radiometer import brdf

        brdf.names()
    except (ImportError, AttributeError):
        pytest.skip("radiometer.brdf is not available yet")
    return brdf


def _inner(node, bl_idname):
    return [n for n in node.node_tree.nodes if n.bl_idname == bl_idname]


def test_assign_builds_group_keeps_user_nodes(lib):
    from radiometer.shading.assign import GROUP_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    tree = ensure_node_tree(mat)
    out = tree.get_output_node("ALL")
    user = out.inputs["Surface"].links[0].from_node  # the default Principled BSDF
    fid = assign_brdf(mat, "ggx", alpha=0.36, f0=0.04)
    assert fid.kind == "exact" and fid.rms_rel_diff < 1e-3
    node = tree.nodes[GROUP_NODE_NAME]
    assert out.inputs["Surface"].links[0].from_node == node
    assert user.name in tree.nodes  # kept, only disconnected
    assert user.name in fid.notes
    metallic = _inner(node, "ShaderNodeBsdfMetallic")[0]
    assert math.isclose(node.inputs["alpha"].default_value, 0.36, rel_tol=1e-6)  # the group's own input
    assert metallic.inputs["Roughness"].is_linked  # driven from the input by Math nodes
    assert {"alpha", "f0", "Normal"} <= set(node.inputs.keys())
    assert metallic.fresnel_type == "F82"
    assert tuple(metallic.inputs["Edge Tint"].default_value)[:3] == (1.0, 1.0, 1.0)
    s = mat.radiometer_brdf
    assert s.model == "ggx" and s.applied and s.fidelity_kind == "exact"


def test_reedit_parameter_updates_material(lib):
    from radiometer.shading.assign import GROUP_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    assign_brdf(mat, "ggx", alpha=0.25, f0=0.04)
    group = mat.node_tree.nodes[GROUP_NODE_NAME].node_tree
    item = next(p for p in mat.radiometer_brdf.params if p.name == "alpha")
    item.value = 0.64  # update callback re-applies
    node = mat.node_tree.nodes[GROUP_NODE_NAME]
    assert node.node_tree == group  # rebuilt in place, same data-block
    assert math.isclose(node.inputs["alpha"].default_value, 0.64, rel_tol=1e-6)
    assert len([g for g in bpy.data.node_groups if g.name.startswith("Radiometer")]) == 1


def test_bad_parameters_raise_and_leave_material_unchanged(lib):
    from radiometer.errors import RadiometerError
    from radiometer.shading.assign import GROUP_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    assign_brdf(mat, "ggx", alpha=0.25, f0=0.04)
    n_nodes = len(mat.node_tree.nodes)
    for bad in ({"alpha": float("nan")}, {"alpha": -0.1}, {"nonsense": 1.0}):
        with pytest.raises(RadiometerError):
            assign_brdf(mat, "ggx", **bad)
    with pytest.raises(RadiometerError):
        assign_brdf(mat, "no_such_model")
    assert len(mat.node_tree.nodes) == n_nodes
    node = mat.node_tree.nodes[GROUP_NODE_NAME]
    assert math.isclose(node.inputs["alpha"].default_value, 0.25, rel_tol=1e-6)
    # through the property: error stored, material unchanged
    item = next(p for p in mat.radiometer_brdf.params if p.name == "alpha")
    item.value = -1.0
    assert mat.radiometer_brdf.error
    assert math.isclose(node.inputs["alpha"].default_value, 0.25, rel_tol=1e-6)


def test_switch_to_osl_and_back_removes_only_our_nodes(lib):
    from radiometer.shading.assign import GROUP_NODE_NAME, OSL_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    assign_brdf(mat, "lambert")
    assign_brdf(mat, "phong", method="osl", n=20.0)
    node = mat.node_tree.nodes[GROUP_NODE_NAME]
    assert _inner(node, "ShaderNodeScript")  # the Script node lives inside the group
    assert len([g for g in bpy.data.node_groups if g.name.startswith("Radiometer")]) == 1
    assert "radiometer_brdf.osl" in bpy.data.texts
    fid = assign_brdf(mat, "lambert")
    assert fid.kind == "exact"
    assert not _inner(mat.node_tree.nodes[GROUP_NODE_NAME], "ShaderNodeScript")
    assert "radiometer_brdf.osl" not in bpy.data.texts  # the add-on's text block is cleaned up
    assert not bpy.context.scene.cycles.shading_system  # never switched on in the user's scene


def test_operator_poll_and_execute(lib):
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("m")
    obj = bpy.data.objects.new("o", mesh)
    scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    assert not bpy.ops.radiometer.assign_brdf.poll()  # no material yet
    mat = bpy.data.materials.new("m")
    mesh.materials.append(mat)
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf.poll()
        mat.radiometer_brdf.model = "ward"
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    s = mat.radiometer_brdf
    assert s.applied and s.fidelity_kind == "approximate" and s.fidelity_rms > 0
    assert "RMS" in s.fidelity_summary
    from radiometer.operators.brdf import RADIOMETER_OT_assign_brdf

    assert {"REGISTER", "UNDO"} <= RADIOMETER_OT_assign_brdf.bl_options


def test_plot_operator_writes_and_loads_image_or_says_why(lib, tmp_path):
    import importlib.util

    mesh = bpy.data.meshes.new("m")
    obj = bpy.data.objects.new("o", mesh)
    bpy.context.scene.collection.objects.link(obj)
    mat = bpy.data.materials.new("m")
    mesh.materials.append(mat)
    mat.radiometer_brdf.model = "ggx"
    has_plots = importlib.util.find_spec("radiometer.brdf.plots") is not None
    with bpy.context.temp_override(object=obj, material=mat):
        if has_plots:
            assert bpy.ops.radiometer.brdf_plot() == {"FINISHED"}
            assert any(img.name.startswith("brdf_ggx") for img in bpy.data.images)
        else:
            with pytest.raises(RuntimeError, match="not available"):
                bpy.ops.radiometer.brdf_plot()


def test_panel_fidelity_text(lib):
    from radiometer.panels.brdf import format_fidelity
    from radiometer.shading.assign import assign_brdf

    mat = bpy.data.materials.new("m")
    assert format_fidelity(mat.radiometer_brdf) == ""
    assign_brdf(mat, "ward")
    text = format_fidelity(mat.radiometer_brdf)
    assert text.startswith("approximate: RMS ") and "albedo" in text
    assign_brdf(mat, "lambert")
    assert format_fidelity(mat.radiometer_brdf) == "exact"


def test_user_links_into_group_inputs_survive_reassign(lib):
    from radiometer.shading.assign import GROUP_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    assign_brdf(mat, "ggx", alpha=0.3, f0=0.04)
    tree = mat.node_tree
    tex = tree.nodes.new("ShaderNodeTexNoise")
    node = tree.nodes[GROUP_NODE_NAME]
    tree.links.new(tex.outputs["Fac"], node.inputs["alpha"])
    assign_brdf(mat, "ggx", alpha=0.5, f0=0.9)
    node = tree.nodes[GROUP_NODE_NAME]
    assert node.inputs["alpha"].is_linked and node.inputs["alpha"].links[0].from_node == tex
    assert tex.name in tree.nodes


def test_anisotropic_tangent_from_uv_map(lib):
    from radiometer.shading.assign import GROUP_NODE_NAME, TANGENT_NODE_NAME, assign_brdf

    mat = bpy.data.materials.new("m")
    assign_brdf(mat, "ward", tangent_source="UV", uv_map="UVMap")
    tangent = mat.node_tree.nodes[TANGENT_NODE_NAME]
    assert tangent.direction_type == "UV_MAP" and tangent.uv_map == "UVMap"
    assert mat.node_tree.nodes[GROUP_NODE_NAME].inputs["Tangent"].links[0].from_node == tangent
    assign_brdf(mat, "ward")  # back to the object axis: the add-on's tangent node goes
    assert TANGENT_NODE_NAME not in mat.node_tree.nodes


def test_osl_assign_says_when_osl_is_off(lib):
    from radiometer.shading.assign import assign_brdf

    mat = bpy.data.materials.new("m")
    fid = assign_brdf(mat, "phong", method="osl")
    assert "Open Shading Language is off" in fid.notes
    assert not bpy.context.scene.cycles.shading_system


def test_enable_osl_operator_is_undoable_and_reported(lib):
    from radiometer.operators.brdf import RADIOMETER_OT_enable_osl

    scene = bpy.context.scene
    assert not scene.cycles.shading_system
    assert {"REGISTER", "UNDO"} <= RADIOMETER_OT_enable_osl.bl_options
    assert bpy.ops.radiometer.enable_osl() == {"FINISHED"}
    assert scene.cycles.shading_system and scene.render.engine == "CYCLES"
    from radiometer.shading.osl import osl_problems

    assert osl_problems(scene) == []


def test_assign_keeps_user_links_when_the_group_interface_changes(clean_blender):
    """A bump node linked into Normal survives re-assigning with an option that rebuilds the group's
    inputs (GGX with an IOR) and a change of model, through the API itself."""
    from radiometer import api
    from radiometer.shading.assign import GROUP_NODE_NAME

    mat = bpy.data.materials.new("user")
    api.assign_brdf(mat, "ggx", alpha=0.3, f0=0.04)
    tree = mat.node_tree
    bump = tree.nodes.new("ShaderNodeBump")
    tree.links.new(bump.outputs["Normal"], tree.nodes[GROUP_NODE_NAME].inputs["Normal"])
    api.assign_brdf(mat, "ggx", alpha=0.3, ior=1.5)
    api.assign_brdf(mat, "beckmann", alpha=0.2, f0=0.04)
    sock = mat.node_tree.nodes[GROUP_NODE_NAME].inputs["Normal"]
    assert sock.is_linked and sock.links[0].from_node == bump

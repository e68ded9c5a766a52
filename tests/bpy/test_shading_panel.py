"""Material Properties > Radiometer BRDF drawn headless with a recording layout: what it shows before
and after Apply, that it edits the group node's inputs in place (user nodes around the group survive),
presets, the tangent frame, the fidelity numbers, the OSL hint and the model-vs-Cycles lobe plot."""

import types

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")


class FakeLayout:
    """Records every prop/operator/label call of a panel's draw (shared log across sub-layouts)."""

    def __init__(self, log=None):
        self.log = [] if log is None else log
        self.enabled = True
        self.use_property_split = False
        self.use_property_decorate = True

    def _sub(self, *args, **kwargs):
        return FakeLayout(self.log)

    row = column = box = split = _sub

    def prop(self, data, prop, text=None, **kwargs):
        self.log.append(("prop", data, prop, text))

    def prop_search(self, data, prop, search_data, search_prop, **kwargs):
        self.log.append(("prop_search", data, prop, search_prop))

    def prop_enum(self, data, prop, value, text=None, **kwargs):
        self.log.append(("prop_enum", data, prop, value))

    def label(self, text="", **kwargs):
        self.log.append(("label", text))

    def operator(self, idname, text=None, **kwargs):
        props = types.SimpleNamespace()
        self.log.append(("operator", idname, text, props))
        return props

    def operator_menu_enum(self, idname, prop, text=None, **kwargs):
        self.log.append(("menu_enum", idname, prop))

    def menu(self, *args, **kwargs):
        self.log.append(("menu",) + args)


def draw(mat, obj=None):
    from radiometer.panels.brdf import RADIOMETER_PT_brdf

    layout = FakeLayout()
    context = types.SimpleNamespace(material=mat, object=obj, scene=bpy.context.scene)
    assert RADIOMETER_PT_brdf.poll(context)
    RADIOMETER_PT_brdf.draw(types.SimpleNamespace(layout=layout), context)
    return layout.log


def labels(log):
    return [e[1] for e in log if e[0] == "label"]


def props(log):
    return [e for e in log if e[0] == "prop"]


@pytest.fixture
def plane(clean_blender):
    mesh = bpy.data.meshes.new("m")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    mesh.uv_layers.new(name="UVMap")
    mesh.uv_layers.new(name="Detail")
    obj = bpy.data.objects.new("o", mesh)
    bpy.context.scene.collection.objects.link(obj)
    mat = bpy.data.materials.new("m")
    mesh.materials.append(mat)
    bpy.context.view_layer.objects.active = obj
    return obj, mat


def test_parameters_visible_before_apply_with_labels_and_variant_enum(plane):
    obj, mat = plane
    mat.radiometer_brdf.model = "oren_nayar"
    log = draw(mat, obj)
    drawn = {(e[2], e[3]) for e in props(log)}
    assert ("angle", "Roughness \u03c3") in drawn  # radians shown as an angle (degrees)
    assert ("color", "Albedo \u03c1") in drawn
    assert ("option", "Variant") in drawn  # an enum, not free text
    assert not any(e[2] == "text" for e in props(log))
    item = mat.radiometer_brdf.params["variant"]
    item.option = "cycles"
    assert item.text == "cycles" and item.option == "cycles"
    with pytest.raises(TypeError):
        item.option = "no such variant"
    ops = [e[1] for e in log if e[0] == "operator"]
    assert "radiometer.assign_brdf" in ops and "radiometer.brdf_plot" in ops
    assert "radiometer.brdf_param_info" in ops  # per-parameter tooltip button


def test_param_info_tooltip_is_the_library_description(plane):
    obj, mat = plane
    mat.radiometer_brdf.model = "ggx"
    rna = bpy.ops.radiometer.brdf_param_info.get_rna_type()
    assert rna.description
    from radiometer.operators.brdf import RADIOMETER_OT_brdf_param_info as Info

    context = types.SimpleNamespace(material=mat, object=obj)
    text = Info.description(context, types.SimpleNamespace(param="alpha"))
    assert "alpha" in text and "slope" in text.lower()


def test_after_apply_rows_are_the_group_node_inputs_and_user_nodes_survive(plane):
    from radiometer.shading.assign import GROUP_NODE_NAME

    obj, mat = plane
    s = mat.radiometer_brdf
    s.model = "ggx"
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    tree = mat.node_tree
    node = tree.nodes[GROUP_NODE_NAME]
    # the artist adds a texture into f0 and a bump into Normal
    tex = tree.nodes.new("ShaderNodeTexNoise")
    tex.name = "my noise"
    bump = tree.nodes.new("ShaderNodeBump")
    bump.name = "my bump"
    tree.links.new(tex.outputs["Color"], node.inputs["f0"])
    tree.links.new(bump.outputs["Normal"], node.inputs["Normal"])
    log = draw(mat, obj)
    socket_rows = [e for e in props(log) if e[2] == "default_value"]
    assert any(e[1] == node.inputs["alpha"] for e in socket_rows)  # the node's own input is drawn
    assert any("from my noise" in t for t in labels(log))
    assert any("Normal: from my bump" in t for t in labels(log))
    # editing through the drawn row edits the node in place
    row = next(e for e in socket_rows if e[1] == node.inputs["alpha"])
    setattr(row[1], row[2], 0.35)
    assert node.inputs["alpha"].default_value == pytest.approx(0.35)
    # Update (Apply again) keeps the edit and the user's nodes and links
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    node = tree.nodes[GROUP_NODE_NAME]
    assert node.inputs["alpha"].default_value == pytest.approx(0.35)
    assert s.params["alpha"].value == pytest.approx(0.35)
    assert "my noise" in tree.nodes and "my bump" in tree.nodes
    assert node.inputs["f0"].is_linked and node.inputs["f0"].links[0].from_node.name == "my noise"
    assert node.inputs["Normal"].is_linked and node.inputs["Normal"].links[0].from_node.name == "my bump"
    # a structural change (live update) also keeps them
    s.params["ior"].use = True
    node = tree.nodes[GROUP_NODE_NAME]
    assert "my noise" in tree.nodes and "my bump" in tree.nodes
    assert node.inputs["Normal"].is_linked


@pytest.mark.parametrize("preset", ["GOLD", "SILVER", "GLASS", "DIAMOND"])
def test_preset_sets_f0_before_and_after_apply(plane, preset):
    from radiometer.brdf.fresnel import PRESETS
    from radiometer.shading.assign import GROUP_NODE_NAME

    obj, mat = plane
    s = mat.radiometer_brdf
    s.model = "ggx"
    f0 = PRESETS[preset.lower()]["f0"]
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.brdf_preset(preset=preset) == {"FINISHED"}
        assert tuple(s.params["f0"].color) == pytest.approx((f0,) * 3)
        s.params["f0"].color = (0.5, 0.5, 0.5)
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
        s.params["ior"].use = True  # a preset switches exact-Fresnel overrides off again
        assert bpy.ops.radiometer.brdf_preset(preset=preset) == {"FINISHED"}
    node = mat.node_tree.nodes[GROUP_NODE_NAME]
    assert not s.params["ior"].use
    assert tuple(node.inputs["f0"].default_value)[:3] == pytest.approx((f0,) * 3, abs=1e-6)
    assert tuple(s.params["f0"].color) == pytest.approx((f0,) * 3)


def test_preset_on_a_model_without_f0_is_refused(plane):
    obj, mat = plane
    mat.radiometer_brdf.model = "lambert"
    with bpy.context.temp_override(object=obj, material=mat):
        with pytest.raises(RuntimeError, match="no f0"):
            bpy.ops.radiometer.brdf_preset(preset="GOLD")


def test_tangent_source_and_uv_map_in_the_ui_and_applied(plane):
    from radiometer.shading.assign import TANGENT_NODE_NAME

    obj, mat = plane
    s = mat.radiometer_brdf
    s.model = "ward"
    log = draw(mat, obj)
    assert any(e[2] == "tangent_source" for e in props(log))
    s.tangent_source = "UV"
    log = draw(mat, obj)
    assert any(e[0] == "prop_search" and e[2] == "uv_map" and e[3] == "uv_layers" for e in log)
    s.uv_map = "Detail"
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    tan = mat.node_tree.nodes[TANGENT_NODE_NAME]
    assert tan.direction_type == "UV_MAP" and tan.uv_map == "Detail"
    s.tangent_source = "OBJECT"  # live update removes the add-on's tangent node
    assert TANGENT_NODE_NAME not in mat.node_tree.nodes


def test_fidelity_numbers_and_osl_hint_for_a_poor_node_mapping(plane):
    from radiometer.panels.brdf import needs_osl_hint

    obj, mat = plane
    s = mat.radiometer_brdf
    s.model = "phong"
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    assert s.fidelity_has_pointwise and s.fidelity_p95 >= s.fidelity_median > 0
    log = draw(mat, obj)
    text = " | ".join(labels(log))
    assert "RMS" in text and "median" in text and "95 %" in text and "max" in text
    if needs_osl_hint(s):
        assert "OSL" in text
        assert any(e[0] == "prop_enum" and e[3] == "osl" for e in log)
    s.model = "lambert"
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.assign_brdf() == {"FINISHED"}
    assert not needs_osl_hint(s)
    assert "exact" in " | ".join(labels(draw(mat, obj)))


def test_lobe_data_model_vs_closure_follows_the_node_input(plane):
    from radiometer.operators.brdf import lobe_data
    from radiometer.shading.assign import GROUP_NODE_NAME

    obj, mat = plane
    s = mat.radiometer_brdf
    s.model = "ggx"
    with bpy.context.temp_override(object=obj, material=mat):
        bpy.ops.radiometer.assign_brdf()
    mat.node_tree.nodes[GROUP_NODE_NAME].inputs["alpha"].default_value = 0.4
    model, fid, lobes = lobe_data(mat)
    assert model == "ggx" and fid.kind == "exact"
    for _, _, fm, fc in lobes:
        mask = fm > 1e-3 * fm.max()
        assert np.allclose(fc[mask], fm[mask], rtol=5e-3)
    # the plotted model is the node's alpha, not the stored one
    _, _, again = lobe_data(mat)
    from radiometer import brdf

    ti, to, fm, _ = again[1]
    t, o = np.radians(ti), np.radians(to[45])
    f = brdf.evaluate("ggx", np.array([[np.sin(t), 0, np.cos(t)]]), np.array([[-np.sin(o), 0, np.cos(o)]]),
                      alpha=0.4)
    assert np.asarray(f, dtype=float).reshape(-1)[0] == pytest.approx(fm[45, 0], rel=1e-5)  # float32 socket


def test_plot_operator_writes_the_lobe_plot(plane):
    pytest.importorskip("matplotlib")
    obj, mat = plane
    mat.radiometer_brdf.model = "ggx"
    with bpy.context.temp_override(object=obj, material=mat):
        assert bpy.ops.radiometer.brdf_plot(kind="LOBE") == {"FINISHED"}
    assert any(img.name.startswith("brdf_ggx_lobe") for img in bpy.data.images)


def test_linked_material_gives_a_message(plane):
    obj, mat = plane
    log = draw(mat, obj)
    assert log  # local: draws
    # a library-linked material cannot be faked without a file: check the branch through a stand-in
    from radiometer.panels.brdf import RADIOMETER_PT_brdf

    fake = types.SimpleNamespace(library=types.SimpleNamespace(filepath="//lib.blend"),
                                 radiometer_brdf=mat.radiometer_brdf, node_tree=None)
    layout = FakeLayout()
    RADIOMETER_PT_brdf.draw(types.SimpleNamespace(layout=layout),
                            types.SimpleNamespace(material=fake, object=obj, scene=bpy.context.scene))
    assert any("make the material local" in t for t in labels(layout.log))

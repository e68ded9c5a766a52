"""Acceptance: every model and method as an editable group node, rendered after editing an input.

For each (model, method) the BRDF is assigned with parameters A, then ONE input of the group node is
changed by hand to a value B (what an artist does in the node editor), and a point-lit plane is rendered
at several (wi, wo). Reference values: ``radiometer.brdf.evaluate`` at B (the lecture's reflection
equation L_r = f E_i with a radius-0 point light, shading.validate), and the numpy replica of the group's
Math nodes (``realise(..., coefficients=<the group's>, **B)``). Exact mappings must agree with the library
within 0.5 %; approximate ones must render their replica within 0.5 % and lie inside the ratio range
[q_lo, q_hi] that the stated pointwise fidelity gives for B on the uniform direction set.
"""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from radiometer.shading import closures as C  # noqa: E402
from radiometer.shading import validate as V  # noqa: E402

# (model, params A, (input, value B)); configs chosen inside every lobe's significant region
CASES = [
    ("lambert", {"albedo": 0.5}, ("albedo", [0.9, 0.4, 0.1])),
    ("oren_nayar", {"variant": "cycles", "sigma": 0.3}, ("sigma", 0.8)),
    ("oren_nayar", {"sigma": 0.3}, ("sigma", 0.5)),
    ("ggx", {"alpha": 0.3, "f0": 0.04}, ("alpha", 0.15)),
    ("ggx", {"alpha_x": 0.1, "alpha_y": 0.4, "f0": 0.9}, ("alpha_y", 0.25)),
    ("ggx", {"alpha": 0.2, "eta": [0.2, 0.9, 1.5], "k": [3.0, 2.5, 2.0]}, ("k", [1.0, 2.0, 3.0])),
    ("ggx", {"alpha": 0.2, "ior": 1.5}, ("ior", 2.4)),
    ("beckmann", {"alpha": 0.3, "f0": 0.5}, ("f0", [0.95, 0.64, 0.54])),
    ("torrance_sparrow", {"alpha": 0.2}, ("alpha", 0.3)),
    ("phong", {"n": 20.0}, ("n", 40.0)),
    ("blinn_phong", {"n": 50.0}, ("n", 80.0)),
    ("ward", {}, ("alpha_x", 0.25)),
    ("ashikhmin_shirley", {}, ("Rs", 0.3)),
]
CONFIGS = [(0, 0, 0, 0), (30, 0, 30, 180), (45, 0, 30, 200), (20, 90, 40, 250)]


@pytest.mark.parametrize("method", ["nodes", "osl"])
@pytest.mark.parametrize("model,params,edit", CASES, ids=[f"{c[0]}-{c[2][0]}" for c in CASES])
def test_group_input_edit_renders_as_predicted(clean_blender, model, params, edit, method):
    from radiometer import brdf
    from radiometer.shading.assign import GROUP_NODE_NAME, assign_brdf, current_fidelity, node_params

    mat = bpy.data.materials.new(model)
    assign_brdf(mat, model, method, **params)
    node = mat.node_tree.nodes[GROUP_NODE_NAME]
    name, value = edit
    sock = node.inputs[name]
    if sock.type == "RGBA":
        rgb = value if isinstance(value, list) else [value] * 3
        sock.default_value = (*rgb, 1.0)
    else:
        sock.default_value = value
    _, _, _, _, now = node_params(node)
    fid = current_fidelity(mat)
    wi, wo = V.config_directions(CONFIGS)
    rendered = V.render_f(mat, wi, wo, osl=(method == "osl"), samples=1)
    replica = C.evaluate_terms(fid.terms, wi, wo)
    model_f = np.asarray(brdf.evaluate(model, wi, wo, **now), dtype=float)
    m = replica > 1e-6 * replica.max()
    assert np.max(np.abs(rendered[m] / replica[m] - 1)) < 5e-3, (rendered, replica)
    if fid.kind == "exact":
        assert np.max(np.abs(rendered / model_f - 1)) < 5e-3, (rendered, model_f)
    else:
        q = rendered / model_f
        pw = fid.pointwise
        assert np.all(q >= pw.q_lo * (1 - 5e-3)) and np.all(q <= pw.q_hi * (1 + 5e-3)), (q, pw)
    # the edit moved the render: it is not what parameters A give
    before = C.evaluate_terms(assign_brdf(bpy.data.materials.new("a"), model, method, **params).terms, wi, wo)
    assert np.max(np.abs(rendered / before - 1)) > 1e-2

"""Light through fog and thin glass (issue 18), each against an independent reference: a converged
render of a tiny white patch (tests/bpy/reference.py, cached in glass_fog_references.json by
make_glass_fog_references.py) or the slab's closed form."""

import importlib.util
import json
import math
import pathlib

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

HERE = pathlib.Path(__file__).resolve().parent
REC709_Y = np.array([0.2126, 0.7152, 0.0722])  # the default scene's working space, Linear Rec.709


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_tgf_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


scenes = _load("glass_fog_scenes")
STORED = json.loads((HERE / "glass_fog_references.json").read_text())["values"]


def _stored(key, point, normal):
    entry = STORED[key]
    assert np.allclose(entry["point"], point) and np.allclose(entry["normal"], normal), "stale reference: re-run make_glass_fog_references.py"
    return 683.0 * float(np.dot(entry["E_rgb"], REC709_Y)), float(entry["rel_std_error"])


#: Issue 18's window and fog corpus: every kind its list names, each checked by ``_check`` against an
#: independent reference (test_the_corpus_covers_issue_18s_list: none may go missing).
CORPUS = ("plain glass", "single-face glass", "Principled glass", "trick glass", "tinted glass", "double glazing",
          "frosted pane", "absorbing pane", "sun and sky, sun patch", "sun and sky, shade", "fog point", "fog spot",
          "fog area", "glossy floor")
#: kind -> [(relative error, stated s.e., reference s.e., exact)] of every reading ``_check`` saw.
CHECKED = {}


def _check(reading, ref_lux, ref_se, kind):
    """Issue 18's acceptance, each criterion asserted on its own (the reference's own standard error
    ``ref_se`` added in quadrature; 0 for a closed form):

    1. within max(3 x the stated standard error, 0.5 %) of the reference;
    2. a reading marked exact within 1e-4 of its reference, which must then be a closed form (a
       rendered reference cannot show 1e-4);
    3. a reading stating less than 5 % is never off by more than 5 x what it states."""
    assert kind in CORPUS, kind
    err = abs(reading.illuminance / ref_lux - 1.0)
    se = float(reading.rel_std_error)
    CHECKED.setdefault(kind, []).append((err, se, ref_se, bool(reading.exact)))
    combined = math.hypot(se, ref_se)
    assert err <= max(3.0 * combined, 0.005), ("criterion 1", kind, reading.illuminance, ref_lux, err, se,
                                               reading.notes)
    if reading.exact:
        assert ref_se == 0.0 and err <= 1e-4, ("criterion 2", kind, reading.illuminance, ref_lux, err)
    if se < 0.05:
        # (1e-9: float rounding of a closed form that states 0)
        assert err <= max(5.0 * combined, 1e-9) or (reading.exact and err <= 1e-4), ("criterion 3", kind, err, se)


@pytest.mark.parametrize("kind", ["POINT", "SPOT", "AREA"])
def test_fog_removes_exact_and_the_render_matches_a_patch_render(clean_blender, kind):
    from radiometer import api

    scene, [(label, point, normal)] = scenes.fog(kind)
    ref_lux, ref_se = _stored(f"fog_{kind.lower()}/{label}", point, normal)
    rows = api.predict_illuminance(point, normal, scene=scene)
    assert rows[0]["status"] == "render" and "world's volume" in rows[0]["reason"]
    # The medium changes the light measurably (FACTS.md): a closed form that ignored it would fail.
    assert abs(rows[0]["illuminance"] / ref_lux - 1.0) > 0.01
    for method in ("auto", "hybrid"):
        r = api.measure_illuminance(point, normal, scene=scene, method=method, quality="standard")
        assert not r.exact and r.rel_std_error > 0.0
        assert any("volume" in note for note in r.notes)
        if kind == "AREA":  # an extended light: the path length through the fog varies, rendered whole
            assert r.method == "render"
        else:  # a delta light: closed form x exp(-sigma_t d), the in-scattered light rendered
            assert r.method == "hybrid" and r.parts["analytic"] == [kind.lower()]
            assert any("exp(-sigma_t d)" in note and "0.04, 0.04, 0.04 1/m" in note for note in r.notes)
        _check(r, ref_lux, ref_se, f"fog {kind.lower()}")


# --- thin glass ---------------------------------------------------------------------------------------

def _slab_reference(name, cosine):
    """The windows' transmittance from the slab's closed form (``thin_glass.slab``, property-tested
    against Fresnel's normal-incidence form and Radiance's glass in tests/test_thin_glass*.py), and
    the adding formula for two panes."""
    from radiometer.radiometry.scene import thin_glass

    kind, ior, colour, panes = scenes.WINDOWS[name]
    # The shader node stores its inputs in float32 (an IOR of 1.52 is 1.5199999809...).
    ior, colour = float(np.float32(ior)), tuple(float(np.float32(c)) for c in colour)
    tint_r = (1.0, 1.0, 1.0) if kind == "principled" else colour
    layers = [thin_glass.slab(cosine, ior, t, tint_t=colour, tint_r=tint_r)[:2] for _z, t in panes]
    return thin_glass.stack(layers)[0]


WINDOW_KINDS = {"plain": "plain glass", "single_face": "single-face glass", "principled": "Principled glass",
                "trick": "trick glass", "tinted": "tinted glass", "double_glazing": "double glazing"}


def _window_closed_form(name, light):
    """(lux, cosine) under ``scenes.window(name, light)``: the unobstructed light's closed form times
    the slab's T (``_slab_reference``) at its incidence angle."""
    from radiometer.radiometry.photometry import efficacy as photometry  # the scene's Y weights (checked against colour-science)

    if light == "SUN":
        cosine = math.cos(math.radians(30.0))
        e_open = 100.0 * cosine  # W/m^2; the 0.53 degree cap differs from cos by < 1e-5 here
    else:
        d = np.array([0.0, 0.5, 3.0])
        cosine = 3.0 / np.linalg.norm(d)
        e_open = 1000.0 / (4 * math.pi) * cosine / (d @ d)
    weights = np.asarray(photometry.luminance_weights("Linear Rec.709"), float)
    return 683.0 * e_open * float(_slab_reference(name, cosine) @ weights), 683.0 * e_open * float(np.sum(weights))


@pytest.mark.parametrize("name", list(scenes.WINDOWS))
def test_small_lights_through_thin_glass_are_closed_forms(clean_blender, name):
    from radiometer import api

    for light in ("SUN", "POINT"):
        scene, [(_label, point, normal)] = scenes.window(name, light=light)
        expected, open_lux = _window_closed_form(name, light)
        rows = api.predict_illuminance(point, normal, scene=scene)
        assert rows[0]["status"] in ("exact", "bounded") and "thin glass" in rows[0]["reason"], rows[0]
        assert "Pane 1" in rows[0]["reason"]
        if name == "trick":  # read as the real pane it depicts, not transmittance 1
            assert rows[0]["illuminance"] < 0.93 * open_lux
        r = api.measure_illuminance(point, normal, scene=scene, method="analytic")
        tol = 1e-4 if light == "SUN" else 1e-9  # the sun's 0.53 degree disc vs its centre's cosine
        assert r.illuminance == pytest.approx(expected, rel=tol)
        assert r.rel_error_bound <= (2e-4 if light == "SUN" else 1e-12)
        _check(r, expected, 0.0, WINDOW_KINDS[name])


@pytest.mark.parametrize("name", ["plain", "trick", "tinted", "double_glazing"])
def test_rendering_thin_glass_converges_like_direct_light(clean_blender, name):
    """A Glass BSDF turns the sun into a caustic (docs/FACTS.md); the measurement renders the pane
    as thin glass instead, so the rendered sun through it converges to the slab's closed form."""
    from radiometer import api

    scene, [(_label, point, normal)] = scenes.window(name, light="SUN")
    materials = [slot.material.name for ob in scene.objects for slot in ob.material_slots]
    expected, _open = _window_closed_form(name, "SUN")
    for method in ("render", "auto"):
        r = api.measure_illuminance(point, normal, scene=scene, method=method, quality="standard")
        assert r.rel_std_error > 0.0 or r.method == "hybrid"
        _check(r, expected, 0.0, WINDOW_KINDS[name])
    # The user's materials are back on the panes.
    assert [slot.material.name for ob in scene.objects for slot in ob.material_slots] == materials
    assert not any(m.name.startswith("radiometer thin pane") for m in bpy.data.materials)


def test_frosted_and_curved_glass_stay_rendered(clean_blender):
    """Refractors that are not thin panes are rendered as they are. A small light seen only through
    a sharp refractor (a glass ball) or a barely frosted pane (roughness below
    glass.ROUGH_REFRACTION) is a caustic: the reading says so and counts the light's unoccluded
    closed form as its error bound. A pane frosted at ROUGH_REFRACTION or more is no caustic (light
    sampling at the pane finds the lamp): no bound, a stochastic error (against a converged patch
    render in test_frosted_pane_against_a_patch_render)."""
    from radiometer import api
    from radiometer.measure.capture import glass

    caustic = "caustic light may be missing"
    scene, [(_label, point, normal)] = scenes.frosted_window("POINT", roughness=0.1)
    assert 0.1 < glass.ROUGH_REFRACTION <= 0.3
    rows = api.predict_illuminance(point, normal, scene=scene)
    assert rows[0]["status"] == "render"
    r = api.measure_illuminance(point, normal, scene=scene, method="analytic")
    assert any("frosted" in note for note in r.notes), r.notes
    # 1024 samples: the bound's statement does not depend on how long the render ran.
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", samples=1024)
    assert any(caustic in note for note in r.notes), r.notes
    assert r.rel_std_error >= 0.5 and r.rel_error_bound >= 0.5
    pane = bpy.data.objects["Pane 1"]
    pane.data.materials[0] = scenes.glass_material("frosted enough", roughness=glass.ROUGH_REFRACTION)
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", samples=1024)
    assert not any(caustic in note for note in r.notes), r.notes
    assert any("no caustic bound" in note for note in r.notes) and r.rel_error_bound == 0.0
    # So is a frosted Principled BSDF pane (transmission 1); its roughness fed by a texture is not.
    pane.data.materials[0] = scenes.glass_material("frosted principled", "principled", 1.45, roughness=0.4)
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", samples=1024)
    assert not any(caustic in note for note in r.notes) and r.rel_error_bound == 0.0, r.notes
    tree = pane.data.materials[0].node_tree
    noise = tree.nodes.new("ShaderNodeTexNoise")
    tree.links.new(noise.outputs["Fac"], tree.nodes["Principled BSDF"].inputs["Roughness"])
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", samples=1024)
    assert any(caustic in note for note in r.notes), r.notes
    # A curved refractor (a glass ball) is not a pane either; a sharp one is a caustic for the lamp.
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.2, location=(0.0, 0.25, 1.5))
    ball = bpy.context.object
    ball.data.materials.append(scenes.glass_material("ball glass"))
    pane.data.materials[0] = scenes.glass_material("clear")
    r = api.measure_illuminance(point, normal, scene=scene, method="analytic")
    assert any("curved or thick refractor" in note for note in r.notes), r.notes
    r = api.measure_illuminance(point, normal, scene=scene, method="auto", samples=1024)
    assert any(caustic in note for note in r.notes), r.notes


@pytest.mark.parametrize("light", ["POINT", "SUN"])
def test_frosted_pane_against_a_patch_render(clean_blender, light):
    """A pane frosted at roughness 0.3 is rendered as it is; Cycles' light sampling at the rough
    refraction finds the point light and the 0.53 degree sun, so the reading states a stochastic
    error that covers a converged patch render of the same scene (cached)."""
    from radiometer import api

    scene, [(label, point, normal)] = scenes.frosted_window(light, roughness=0.3)
    ref_lux, ref_se = _stored(f"frosted_{light.lower()}_0.3/{label}", point, normal)
    r = api.measure_illuminance(point, normal, scene=scene, quality="preview")
    assert r.method == "render" and not r.exact and r.rel_error_bound == 0.0
    assert not any("caustic light may be missing" in note for note in r.notes), r.notes
    assert any("no caustic bound" in note for note in r.notes), r.notes
    _check(r, ref_lux, ref_se, "frosted pane")


@pytest.mark.parametrize("case", [0, 1])
def test_skylight_room_against_sun_and_sky_references(clean_blender, case):
    """A room lit by the sun and a uniform sky through a 6 mm glass skylight; meters on the floor in
    the sun patch and in the shade. Reference: the sun's part rendered with the pane as thin glass at
    the sun's angle (T, R from the slab's closed form) plus the sky's part rendered through the real
    Glass BSDF (a large source: Cycles converges through refraction), each a patch render."""
    from radiometer import api

    scene, cases = scenes.window_room()
    label, point, normal = cases[case]
    parts = [_stored(f"window_room_{part}/{label}", point, normal) for part in ("sun", "sky")]
    ref_lux = sum(lux for lux, _se in parts)
    ref_se = math.hypot(*(lux * se for lux, se in parts)) / ref_lux
    r = api.measure_illuminance(point, normal, scene=scene, quality="standard" if case == 0 else "preview")
    assert r.method == "hybrid" if case == 0 else r.method in ("render", "hybrid")
    assert any("thin glass 'Skylight'" in note for note in r.notes)
    _check(r, ref_lux, ref_se, f"sun and sky, {'sun patch' if case == 0 else 'shade'}")


@pytest.mark.parametrize("case", [0, 1])
def test_glossy_floor_reflection_against_a_patch_render(clean_blender, case):
    """All of the meter's light arrives by a metal floor's glossy reflection (issue 18 measured
    z = -3.0 and -2.5 there at `standard`; bench/coverage_rare_paths.py measures the coverage)."""
    from radiometer import api

    scene, cases = scenes.glossy_floor()
    label, point, normal = cases[case]
    ref_lux, ref_se = _stored(f"glossy_floor/{label}", point, normal)
    r = api.measure_illuminance(point, normal, scene=scene, quality="preview")
    assert r.render_settings["filter_glossy"] == 0.0 and scene.cycles.blur_glossy == 1.0  # the user's, restored
    _check(r, ref_lux, ref_se, "glossy floor")


def test_volume_absorption_inside_a_pane(clean_blender):
    """A Volume Absorption inside a solid pane is absorption along the refracted path (Cycles:
    sigma_a = density (1 - Color) per scene unit). Under a uniform sky the reference is a patch
    render through the real Glass BSDF with its volume (a large source: it converges); the slab's
    closed form integrated over the pane agrees with it, and so does the meter."""
    from radiometer import api
    from radiometer.radiometry.photometry import efficacy as photometry
    from radiometer.radiometry.scene import thin_glass

    scene, [(label, point, normal)] = scenes.absorbing_pane_sky()
    ref_lux, ref_se = _stored(f"absorbing_pane_sky/{label}", point, normal)
    # Closed form: the world lies all round, so the pane passes T of the sky above and reflects R of
    # the sky below: E = pi L - L * integral over the pane of A(theta) cos(theta) d omega, A = 1 - T - R.
    sigma = np.array([scenes.ABSORBER["density"] * (1.0 - float(np.float32(c))) for c in scenes.ABSORBER["colour"]])
    x, w = np.polynomial.legendre.leggauss(96)
    gx, gy = np.meshgrid(x, x)  # the 2 x 2 m pane at 1 m: x, y in [-1, 1]
    r2 = gx ** 2 + gy ** 2 + 1.0
    A = thin_glass.slab(1.0 / np.sqrt(r2), float(np.float32(1.52)), 0.006, sigma)[2]
    lost = np.einsum("ij,ij,ijc->c", np.outer(w, w), 1.0 / r2 ** 2, A)
    weights = np.asarray(photometry.luminance_weights("Linear Rec.709"), float)
    closed_lux = 683.0 * float((math.pi - lost) @ weights)
    assert abs(closed_lux / ref_lux - 1.0) <= max(3 * ref_se, 0.005), (closed_lux, ref_lux)
    r = api.measure_illuminance(point, normal, scene=scene, quality="standard")
    assert any("Volume Absorption inside" in note for note in r.notes), r.notes
    assert not r.exact  # the sky through the pane is rendered (through the thin-pane shader)
    _check(r, ref_lux, ref_se, "absorbing pane")


def test_luminance_of_a_sun_patch_behind_glass(clean_blender):
    """A luminance meter sees the floor's sun patch under the skylight (camera renders swap the panes
    for thin glass too; through the real Glass BSDF the patch would be a caustic, nearly black)."""
    from radiometer import api

    scene, cases = scenes.window_room()
    label, point, normal = cases[0]
    e_lux = sum(_stored(f"window_room_{part}/{label}", point, normal)[0] for part in ("sun", "sky"))
    r = api.measure_luminance((point[0], point[1], 1.0), (0.0, 0.0, -1.0), acceptance_deg=2.0, quality="preview")
    expected = 0.5 * e_lux / math.pi  # the floor is Lambertian, albedo 0.5: L = rho E / pi
    assert abs(r.luminance / expected - 1.0) <= max(3 * r.rel_std_error, 0.01), (r.luminance, expected)
    assert not any(m.name.startswith("radiometer thin pane") for m in bpy.data.materials)


def test_window_with_its_frame_in_one_mesh(clean_blender):
    """Archviz windows are often one object: an opaque frame and the glass as two material slots.
    The glass slot is the pane, the frame stays an occluder, and only the glass is swapped."""
    from radiometer import api

    scene, [(_label, point, normal)] = scenes.window("single_face", light="POINT")
    pane = bpy.data.objects["Pane 1"]
    frame_mat = scenes._diffuse("frame", 0.3)
    mesh = pane.data
    # A 0.5 m wide frame around the 2 x 2 m pane, in its plane, as a second slot of the same mesh.
    ring = [[(-1.5, -1.5), (1.5, -1.5), (1.5, -1.0), (-1.5, -1.0)], [(-1.5, 1.0), (1.5, 1.0), (1.5, 1.5), (-1.5, 1.5)],
            [(-1.5, -1.0), (-1.0, -1.0), (-1.0, 1.0), (-1.5, 1.0)], [(1.0, -1.0), (1.5, -1.0), (1.5, 1.0), (1.0, 1.0)]]
    verts = [tuple(v.co) for v in mesh.vertices]
    faces = [tuple(p.vertices) for p in mesh.polygons]
    for quad in ring:
        faces.append(tuple(range(len(verts), len(verts) + 4)))
        verts.extend((x, y, 1.0) for x, y in quad)
    new = bpy.data.meshes.new("framed window")
    new.from_pydata(verts, [], faces)
    new.materials.append(mesh.materials[0])
    new.materials.append(frame_mat)
    for k, poly in enumerate(new.polygons):
        poly.material_index = 0 if k == 0 else 1
    pane.data = new
    rows = api.predict_illuminance(point, normal, scene=scene)
    assert rows[0]["status"] == "exact" and "thin glass" in rows[0]["reason"], rows[0]
    d = np.array([0.0, 0.5, 3.0])
    from radiometer.radiometry.photometry import efficacy as photometry

    weights = np.asarray(photometry.luminance_weights("Linear Rec.709"), float)
    expected = 683.0 * 1000.0 / (4 * math.pi) * (3.0 / np.linalg.norm(d)) / (d @ d) * float(
        _slab_reference("single_face", 3.0 / np.linalg.norm(d)) @ weights)
    assert rows[0]["illuminance"] == pytest.approx(expected, rel=1e-9)
    # Under the frame: the lamp is blocked by the opaque frame.
    blocked = api.predict_illuminance((0.0, -2.1, 0.0), normal, scene=scene)
    assert blocked[0]["status"] == "zero" and blocked[0]["illuminance"] == 0.0, blocked[0]
    r = api.measure_illuminance(point, normal, scene=scene, method="render", quality="preview")
    _check(r, expected, 0.0, "single-face glass")
    assert [m.name for m in pane.data.materials] == [mesh.materials[0].name, "frame"]


@pytest.mark.slow
def test_fog_that_varies_in_space_stays_rendered(clean_blender):
    """Only a provably homogeneous world volume gets exp(-sigma_t d): a density fed by a texture is
    rendered whole."""
    from radiometer import api
    from radiometer.measure.capture import media

    scene, [(_label, point, normal)] = scenes.fog("POINT")
    assert media.world_medium(scene).sigma_t == pytest.approx((0.04,) * 3)
    tree = scene.world.node_tree
    noise = tree.nodes.new("ShaderNodeTexNoise")
    tree.links.new(noise.outputs["Fac"], tree.nodes["Volume Scatter"].inputs["Density"])
    assert media.world_medium(scene) is None
    r = api.measure_illuminance(point, normal, scene=scene, quality="preview")
    assert r.method == "render" and not any("exp(-sigma_t d)" in note for note in r.notes)


def test_panes_found_by_identity_renamed_and_linked_duplicate(clean_blender):
    """The measurement finds every pane's object by the capture's identity (session uid), not by
    name: a pane renamed after its capture (a cached capture) is still swapped. A linked duplicate
    (another object sharing the mesh) scaled to twice the thickness is its own pane: each object gets
    its own thin-pane material (linked to the object, the shared mesh is never changed) with its own
    absorption path, and everything is put back."""
    from radiometer.measure.capture import glass, scene_capture
    from radiometer.measure.blender import scene_guard

    scene, _cases = scenes.absorbing_pane_sky()
    first = bpy.data.objects["Pane 1"]
    twin = first.copy()  # Alt+D: a new object, the same mesh
    twin.scale = (1.0, 1.0, 2.0)  # the slab at z 2 m, 12 mm thick
    scene.collection.objects.link(twin)
    user_material = first.data.materials[0]
    panes = scene_capture.capture(scene).needs["thin_panes"]
    assert sorted(round(p.thickness, 6) for p in panes.values()) == [0.006, 0.012]
    first.name = "Renamed after the capture"
    with scene_guard.preserved_scene(scene) as snapshot:
        swapped = glass.swap_panes(snapshot, panes)
        assert swapped == sorted([first.name, twin.name])
        mats = [ob.material_slots[0].material for ob in (first, twin)]
        assert all(m.name.startswith("radiometer thin pane") for m in mats) and mats[0] != mats[1]
        assert first.data.materials[0] == user_material  # the shared mesh keeps the user's material

        def optical_depths(mat):  # -sigma_a d per channel, fed to exp(. / cos theta_t)
            return sorted(-n.inputs[0].default_value for n in mat.node_tree.nodes
                          if n.bl_idname == "ShaderNodeMath" and n.operation == "DIVIDE"
                          and not n.inputs[0].is_linked and n.inputs[0].default_value < 0)

        depth_first, depth_twin = optical_depths(mats[0]), optical_depths(mats[1])
        assert len(depth_first) == 3 and np.allclose(depth_twin, 2.0 * np.asarray(depth_first))
    for ob in (first, twin):
        assert ob.material_slots[0].link == "DATA" and ob.material_slots[0].material == user_material
    assert not any(m.name.startswith("radiometer thin pane") for m in bpy.data.materials)


def test_the_corpus_covers_issue_18s_list(request):
    """Every kind of issue 18's window and fog corpus was checked against its independent reference
    by ``_check`` (the three acceptance criteria, asserted there for every reading) in this run. Runs
    last in this file; a run of selected tests (-k, a node id) cannot tell, so it skips."""
    opts = request.config.option
    if getattr(opts, "keyword", "") or any("::" in str(a) for a in request.config.args):
        pytest.skip("a selection of this file's tests ran: the corpus is judged on the whole file")
    missing = [kind for kind in CORPUS if kind not in CHECKED]
    assert not missing, f"corpus kinds with no reading checked: {missing}"


def test_sharp_mirrors_found_by_identity(clean_blender):
    """The sharp-mirror bound finds its mirrors by the capture's identity: a mirror renamed after its
    capture (a cached capture) still counts, and the name it had then finds nothing."""
    from radiometer.measure.capture import glass, scene_capture

    scene, _cases = scenes.glossy_floor(roughness=0.0)
    model = scene_capture.capture(scene)
    floor = bpy.data.objects["Floor"]
    floor.name = "Renamed mirror"
    tris, owners = glass.mirror_triangles(model)
    assert len(tris) == 2 and set(owners) == {"Floor"}  # the capture's names, found by identity
    floor.data.materials[0].node_tree.nodes["Glossy BSDF"].inputs["Roughness"].default_value = 0.5
    assert len(glass.mirror_triangles(model)[0]) == 0  # the same object, now rough: no mirror


def test_a_pane_that_mirrors_nothing_leaves_the_closed_form_exact(clean_blender):
    """A pane reflects only light from the meter's side of it. With the lamp beyond every pane and
    nothing else that reflects, nothing is left to render: ``auto`` reads the slab's closed form,
    exact (it stated ±0 as a hybrid before, a rendered reading with a zero error). A lamp on the
    meter's side is mirrored by the pane, and the reading is not exact."""
    from radiometer import api

    for name in ("plain", "double_glazing"):
        scene, [(_label, point, normal)] = scenes.window(name, light="POINT")
        expected, _open = _window_closed_form(name, "POINT")
        r = api.measure_illuminance(point, normal, scene=scene, quality="preview")
        assert r.exact and r.method == "analytic", (name, r.method, r.notes)
        assert r.illuminance == pytest.approx(expected, rel=1e-9)
    scene, [(_label, point, normal)] = scenes.window("plain", light="POINT")
    lamp = next(ob for ob in scene.objects if ob.type == "LIGHT")
    lamp.location.z = 0.5  # between the meter (z = 0) and the pane (z = 1)
    r = api.measure_illuminance(point, normal, scene=scene, quality="preview")
    assert not r.exact and r.rel_std_error > 0.0

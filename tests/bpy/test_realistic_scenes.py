"""Issue 9 acceptance: the meter on realistic scenes against an independent reference.

Every corpus case (``corpus.py``) is measured with ``method="auto"`` (and, where relevant, "render",
"hybrid", "analytic") and compared with the independent reference of ``reference.py`` (a tiny white
Lambertian patch seen by an orthographic Cycles camera, E = pi x pixel), or a closed form:

    |reading / reference - 1| <= max(3 * hypot(reading s.e., reference s.e.), 0.5 %)

and every reading marked ``exact`` must be within 1e-4 of a closed form (or of a reference converged
below 3e-5). Nothing real may be refused. The bugs listed in issue 9 each have a regression test below.

Cost: each corpus scene is built ONCE (``_scene_results``: references and readings are computed on
first use and kept as plain numbers, so later tests need no live scene). References are rendered to
1e-3 relative (far below the 0.5 % tolerance). The slow ones (> a few seconds) are precomputed into
``reference_values.json`` by ``make_reference_values.py`` (provenance inside); a stored value is used
only while its case point/normal still match the corpus, else it is recomputed live. Everything else
(the representative subset: rooms, sphere, desk, instances, transformed, stacked, two scenes, unit
scales) is rendered live on every run.

Known Cycles behaviours that make the full-scene render a wrong yardstick (measured, corpus docstrings):
* ``transformed_lights`` "squashed spot, 0.9 m along x": the (1, 2, 1)-scaled spot biases Cycles'
  light-tree sampling of the OTHER lights at that point (full render 6.37e-5 +- 0.9 % vs 4.62e-5 for
  the lights rendered one at a time, +37 %). There every reading is compared with the sum of the
  single-light renders ("singles"), and method="render" (which renders the full scene, so inherits
  the bias) is not asserted at that point.
* ``transformed_lights`` (MIS on) under the sheared light: MIS mixes Cycles' light sampling and its
  BSDF-hit geometry, which disagree for a sheared light, so the converged value depends on the other
  lights (full 2.744, singles 2.840). method="render" renders the same full scene as the reference and
  is compared with the full render; auto/hybrid renders the sheared light's share with the other
  lights linked out of the sensor (light linking), so it is compared with the singles sum.

Set RADIOMETER_CORPUS_TABLE=path.json to dump every comparison (for reports).
"""

import importlib.util
import json
import math
import os
import pathlib
import time

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytest.importorskip("OpenEXR")

import radiometer  # noqa: E402
from radiometer import api  # noqa: E402
from radiometer.errors import RadiometerError  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent


def _load(name):
    spec = importlib.util.spec_from_file_location(f"_rs_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


reference = _load("reference")
corpus = _load("corpus")
refvals = _load("make_reference_values")

REF_TARGET = 1e-3      # reference relative s.e. (the tolerance floor is 0.5 %)
TOL_FLOOR = 0.005
EXACT_TOL = 1e-4
QUALITY = "standard"   # Radiometer: 1 % target 1-sigma

# ------------------------------------------------------------------ what is measured how

#: method="render" is also checked at these (scene, case); "*" = every case of the scene.
RENDER_TOO = {
    "stacked_lights": "*", "two_scenes": "*", "desk_only": "*",
    "transformed_lights": "*", "transformed_lights_sheared_mis_off": "*",
    "instanced_empties": ("behind occluder", "under luminaire"), "instanced_geonodes": ("behind occluder",),
    "closed_room": ("desk top",), "integrating_sphere": ("equator",), "hidden_lights": ("facing wall",),
}
#: method="analytic" (direct light only) is meaningful only where nothing can reflect: no geometry.
ANALYTIC_TOO = {"stacked_lights": "*", "two_scenes": "*", "transformed_lights": "*",
                "transformed_lights_sheared_mis_off": "*"}
#: Tighter Radiometer targets where the standard 1 % is too coarse for the comparison. hidden_lights
#: "facing wall": at 1 % (seed 0) the reading was +2.09 % with s.e. 0.67 % (3.1 sigma); seeds 1..5 read
#: +0.86, -0.16, -0.05, +0.40, -0.42 % (s.e. 0.5..0.75 %): no bias, one 3-sigma draw among ~120
#: comparisons, so this case is measured to 0.3 %.
TARGETS = {("hidden_lights", "facing wall"): 0.003}
HYBRID_TOO = {"stacked_lights": "*", "two_scenes": "*", "desk_only": "*"}

#: Cases whose full-scene Cycles render is a biased yardstick (see the module docstring): compare with
#: the sum of single-light renders; methods listed map to the reference kind used.
SQUASHED_X = "squashed spot, 0.9 m along x"
SINGLES_FOR = {
    ("transformed_lights", SQUASHED_X): {"auto": "singles", "hybrid": "singles", "analytic": "singles",
                                         "render": None},
    ("transformed_lights_sheared_mis_off", SQUASHED_X): {"auto": "singles", "hybrid": "singles",
                                                         "analytic": "singles", "render": None},
    # Measured (make_reference_values.py, 1e-3 targets): the full-scene render under the
    # visible_diffuse=False light reads 0.6634 +- 0.09 %, the five lights rendered one at a time sum to
    # 0.6560 +- 0.05 % (-1.1 %, 7 sigma; seeds 0/1000/2000 agree on the full value). Pairs are additive
    # (ViewportHidden + NoDiffuse: 0.4795 vs 0.4808 alone; + Portal: identical), so Cycles' full-scene
    # estimate there is not the sum of its lights: compare with the sum of single-light renders.
    ("hidden_lights", "under no-diffuse"): {"auto": "singles", "hybrid": "singles", "analytic": "singles",
                                            "render": "singles"},
    ("transformed_lights", "under sheared"): {"auto": "singles", "hybrid": "singles", "analytic": "singles",
                                              "render": "full"},
    ("transformed_lights", "under sheared, tilted"): {"auto": "singles", "hybrid": "singles",
                                                      "analytic": "singles", "render": "full"},
}


def _wants(table, scene, label):
    sel = table.get(scene)
    return sel == "*" or (sel is not None and label in sel)


def _methods_for(scene, label):
    out = ["auto"]
    if _wants(RENDER_TOO, scene, label):
        out.append("render")
    if _wants(HYBRID_TOO, scene, label):
        out.append("hybrid")
    if _wants(ANALYTIC_TOO, scene, label):
        out.append("analytic")
    return out


# ------------------------------------------------------------------ closed forms

def _projected_solid_angle(polygon, point, normal):
    """Lambert's polygon formula (the exact contour integral) for a polygon fully above the horizon."""
    p, n = np.asarray(point, float), np.asarray(normal, float)
    v = [np.asarray(c, float) - p for c in polygon]
    total = 0.0
    for i in range(len(v)):
        a, b = v[i] / np.linalg.norm(v[i]), v[(i + 1) % len(v)] / np.linalg.norm(v[(i + 1) % len(v)])
        cross = np.cross(a, b)
        total += math.atan2(np.linalg.norm(cross), float(a @ b)) * float(cross / np.linalg.norm(cross) @ n)
    return 0.5 * abs(total)


def _square(h, side=1.0, centre=(0.0, 0.0)):
    s = side / 2
    cx, cy = centre
    return [(cx - s, cy - s, h), (cx + s, cy - s, h), (cx + s, cy + s, h), (cx - s, cy + s, h)]


def _point_light(power, light, point, normal):
    d = np.asarray(light, float) - np.asarray(point, float)
    r = np.linalg.norm(d)
    return power / (4 * math.pi) * max(0.0, float(d @ np.asarray(normal, float)) / r) / r ** 2


#: Closed forms (W/m^2) for corpus cases where one exists: exact readings are held to 1e-4 of these.
CLOSED_FORMS = {
    ("stacked_lights", "on axis"): sum(50.0 / math.pi * _projected_solid_angle(_square(h), (0, 0, 0), (0, 0, 1))
                                       for h in (1.0, 2.0)),
    ("two_scenes", "active scene"): 100.0 / (4 * math.pi * 4.0),
    ("two_scenes", "other scene"): 100.0 / math.pi * _projected_solid_angle(_square(1.0), (0, 0, 0), (0, 0, 1)),
}


# ------------------------------------------------------------------ per-scene results (built once)

_RESULTS = {}
_TABLE = []
_STORED = None


def _stored():
    global _STORED
    if _STORED is None:
        path = refvals.JSON_PATH
        data = json.loads(path.read_text()) if path.exists() else {"values": []}
        _STORED = {(e["scene"], e["case"]): e for e in data["values"]}
    return _STORED


def _stored_entry(scene_name, case, kind):
    e = _stored().get((scene_name, case.label))
    if e is None or kind not in e:
        return None
    if not (np.allclose(e["point"], case.point, atol=1e-9) and np.allclose(e["normal"], case.normal, atol=1e-9)):
        return None  # the corpus moved the case: stale, recompute live
    return e[kind]["E"], e[kind]["rel_std_error"], "stored"


def _reading_record(r):
    return {"E": r.irradiance, "se": r.rel_std_error, "exact": r.exact, "method": r.method, "notes": list(r.notes),
            "bound": r.rel_error_bound, "parts": r.parts}


def _scene_results(name):
    """Build corpus scene ``name`` once; references and readings of every case as plain data."""
    if name in _RESULTS:
        return _RESULTS[name]
    t0 = time.perf_counter()
    built = corpus.BUILDERS[name]()
    radiometer.register()
    out = {}
    try:
        for case in built["cases"]:
            scene = refvals.case_scene(built, case)
            refs = {}
            kinds = {"full"}
            special = SINGLES_FOR.get((name, case.label))
            if special:
                kinds = {k for k in special.values() if k}
            for kind in kinds:
                got = _stored_entry(name, case, kind)
                if got is None:
                    if kind == "full":
                        y, rel, _s = refvals.full_reference(scene, case, target=REF_TARGET)
                    else:
                        y, rel, _s, _parts = refvals.singles_reference(scene, case, target=REF_TARGET)
                    got = (y, rel, "live")
                refs[kind] = got
            readings = {}
            for method in _methods_for(name, case.label):
                try:
                    r = api.measure_illuminance(case.point, case.normal, scene=scene, method=method, quality=QUALITY,
                                                target_rel_error=TARGETS.get((name, case.label)))
                    readings[method] = _reading_record(r)
                except RadiometerError as exc:  # recorded; the test fails on it (nothing real is refused)
                    readings[method] = {"error": f"RadiometerError: {exc}"}
            out[case.label] = {"case": case, "refs": refs, "readings": readings}
    finally:
        radiometer.unregister()
    out["_seconds"] = time.perf_counter() - t0
    out["_extra"] = {k: v for k, v in built.items() if k not in ("scene", "objects", "cases", "other")}
    _RESULTS[name] = out
    return out


def _all_comparisons():
    """(scene, case label, method) for every planned comparison (static: no bpy needed)."""
    labels = {
        "closed_room": ["floor centre", "desk top", "wall", "under desk"],
        "room_scale_0.001": ["floor centre", "desk top", "wall", "under desk"],
        "room_scale_1000": ["floor centre", "desk top", "wall", "under desk"],
        "integrating_sphere": ["equator", "mid latitude", "near pole"],
        "desk_only": ["desk top under lamp", "desk top off axis"],
        "instanced_empties": ["under luminaire", "between luminaires", "behind occluder", "facing up at 1 m"],
        "instanced_geonodes": ["under luminaire", "between luminaires", "behind occluder", "facing up at 1 m"],
        "instanced_real": ["under luminaire", "between luminaires", "behind occluder", "facing up at 1 m"],
        "window_room": ["floor in sun patch", "floor in shade", "back wall", "window facing out"],
        "hidden_lights": ["floor centre", "facing wall", "near negative", "under no-diffuse"],
        "transformed_lights": ["under scaled parent", "under sheared", "under sheared, tilted", "under mirrored",
                               "squashed spot, on axis", "squashed spot, 0.9 m along y", SQUASHED_X],
        "transformed_lights_sheared_mis_off": ["under scaled parent", "under sheared", "under sheared, tilted",
                                               "under mirrored", "squashed spot, on axis",
                                               "squashed spot, 0.9 m along y", SQUASHED_X],
        "two_scenes": ["active scene", "other scene"],
        "stacked_lights": ["on axis"],
    }
    assert set(labels) == set(corpus.BUILDERS), "a corpus scene is not covered by the acceptance test"
    for scene, cases in labels.items():
        for label in cases:
            for method in _methods_for(scene, label):
                special = SINGLES_FOR.get((scene, label))
                if special is not None and special.get(method) is None:
                    continue  # full-scene Cycles is biased there and this method renders the full scene
                yield scene, label, method


def _tolerance(reading_se, ref_se):
    return max(3.0 * math.hypot(reading_se, ref_se), TOL_FLOOR)


@pytest.fixture(scope="module", autouse=True)
def _dump_table():
    yield
    path = os.environ.get("RADIOMETER_CORPUS_TABLE")
    if path:
        with open(path, "w") as f:
            json.dump(_TABLE, f, indent=1, default=str)


@pytest.mark.parametrize("scene_name,label,method", list(_all_comparisons()))
def test_corpus_case_matches_independent_reference(scene_name, label, method):
    res = _scene_results(scene_name)
    entry = res[label]
    r = entry["readings"][method]
    assert "error" not in r, f"{scene_name} / {label} [{method}]: refused: {r.get('error')}"
    special = SINGLES_FOR.get((scene_name, label))
    kind = special[method] if special else "full"
    ref, ref_se, origin = entry["refs"][kind]
    dev = r["E"] / ref - 1.0
    tol = _tolerance(r["se"], ref_se)
    _TABLE.append({"scene": scene_name, "case": label, "method": method, "reference": ref, "reference_kind": kind,
                   "reference_se": ref_se, "reference_origin": origin, "reading": r["E"], "reading_se": r["se"],
                   "exact": r["exact"], "method_used": r["method"], "deviation": dev, "tolerance": tol,
                   "passed": abs(dev) <= tol})
    what = (f"{scene_name} / {label} [{method} -> {r['method']}]: reading {r['E']:.6g} (s.e. {r['se']:.2e}, "
            f"exact={r['exact']}) vs {kind} reference {ref:.6g} (s.e. {ref_se:.2e}, {origin}): "
            f"{100 * dev:+.3f} % > tolerance {100 * tol:.3f} %; notes: {r['notes'][1:]}")
    assert abs(dev) <= tol, what
    closed = CLOSED_FORMS.get((scene_name, label))
    if r["exact"]:
        if closed is not None:
            assert abs(r["E"] / closed - 1) <= EXACT_TOL, f"{what}: marked exact but {r['E']} vs closed form {closed}"
        else:
            # An exact reading needs a yardstick converged below the 1e-4 it claims.
            assert ref_se <= 3e-5, f"{scene_name} / {label}: exact reading but no closed form and a noisy reference"
            assert abs(dev) <= EXACT_TOL + 3 * ref_se, f"{what}: marked exact"
    else:
        assert r["se"] > 0, f"{scene_name} / {label}: not exact but stated error 0 (give an honest bound)"
    if closed is not None:
        assert abs(r["E"] / closed - 1) <= _tolerance(r["se"], 0.0), f"{what}: vs closed form {closed}"


def test_integrating_sphere_against_its_closed_form():
    """E = P / (A (1 - rho)) on the wall (all bounces), polygon-corrected as in test_reference_harness:
    the exact direct term at the (lifted) facet centre plus rho P / ((1 - rho) A_poly)."""
    res = _scene_results("integrating_sphere")
    x = res["_extra"]
    rho, power, a_poly = x["rho"], x["power"], x["area_poly"]
    for label in ("equator", "mid latitude", "near pole"):
        case = res[label]["case"]
        c = np.asarray(case.point)
        direct = power / (4 * math.pi) * float(np.dot(-c / np.linalg.norm(c), case.normal)) / float(c @ c)
        closed = direct + rho * power / ((1 - rho) * a_poly)
        assert abs(closed / x["closed_form_true_sphere"] - 1) < 3e-3
        r = res[label]["readings"]["auto"]
        assert not r["exact"]
        assert abs(r["E"] / closed - 1) <= _tolerance(r["se"], 0.0), (label, r["E"], closed, r["se"])


# ------------------------------------------------------------------ notes the issue asks for

def test_meter_on_a_surface_says_so():
    res = _scene_results("closed_room")
    notes = res["desk top"]["readings"]["auto"]["notes"]
    assert any("on the surface of 'DeskTop'" in n for n in notes), notes
    notes = res["floor centre"]["readings"]["auto"]["notes"]
    assert any("on the surface of 'Room'" in n for n in notes), notes
    # a meter in free space has no such note
    notes = _scene_results("instanced_empties")["facing up at 1 m"]["readings"]["auto"]["notes"]
    assert not any("on the surface" in n for n in notes), notes


def test_negative_light_energy_has_a_note():
    notes = _scene_results("hidden_lights")["near negative"]["readings"]["auto"]["notes"]
    assert any("'Negative'" in n and "negative" in n for n in notes), notes


@pytest.fixture
def fresh():
    """An empty factory scene with a black world and Radiometer registered (as conftest's clean_blender)."""
    scene = corpus.reset()
    corpus.black_world(scene)
    radiometer.register()
    try:
        yield scene
    finally:
        radiometer.unregister()


def test_negative_light_alone_reads_minus_its_closed_form(fresh):
    corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.0), name="Minus", energy=-50.0)
    r = api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    expected = -50.0 / (4 * math.pi * 4.0)
    assert abs(r.irradiance / expected - 1) <= EXACT_TOL, (r.irradiance, expected)
    assert any("'Minus'" in n and "negative" in n for n in r.notes), r.notes


@pytest.mark.parametrize("attr,value", [("energy", float("nan")), ("energy", float("inf")),
                                        ("color", (float("nan"), 1.0, 1.0))])
def test_non_finite_light_is_a_one_line_error_naming_it(fresh, attr, value):
    corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.0), name="Good", energy=10.0)
    bad = corpus.add_light(fresh, "POINT", (1.0, 0.0, 2.0), name="BadLamp", energy=10.0)
    setattr(bad.data, attr, value)
    for method in ("auto", "render"):
        with pytest.raises(RadiometerError) as err:
            api.measure_illuminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), method=method)
        msg = str(err.value)
        assert "BadLamp" in msg and "\n" not in msg, msg


def test_meter_inside_a_closed_mesh_reads_zero_with_a_note():
    corpus.closed_room()
    radiometer.register()
    try:
        # inside the desk slab (a closed box 0.72 .. 0.75 m): no light reaches it
        r = api.measure_illuminance((1.0, 0.5, 0.735), (0.0, 0.0, 1.0))
    finally:
        radiometer.unregister()
    assert abs(r.irradiance) <= 1e-9, r.irradiance
    assert any("inside the closed mesh 'DeskTop'" in n for n in r.notes), r.notes


def test_many_meters_in_a_closed_room_are_not_refused(fresh):
    """The closed-mesh rule applies to every point, not only the first 1000: 1001 meters in a room made
    as a scaled cube (outward normals) lit by a point light; the last one reads like a single meter."""
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.35))
    room = bpy.context.active_object
    room.scale = (2.0, 1.5, 1.35)
    corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.5), name="Lamp", energy=100.0)
    rng = np.random.default_rng(9)
    pts = np.column_stack([rng.uniform(-1.9, 1.9, 1001), rng.uniform(-1.4, 1.4, 1001), rng.uniform(0.1, 2.4, 1001)])
    many = api.measure_illuminance(pts, (0.0, 0.0, 1.0), method="analytic")
    one = api.measure_illuminance(pts[1000], (0.0, 0.0, 1.0), method="analytic")
    assert len(many) == 1001
    assert many[1000].irradiance == pytest.approx(one.irradiance, rel=1e-9)
    direct = [_point_light(100.0, (0, 0, 2.5), p, (0, 0, 1)) for p in pts]
    assert np.allclose([x.irradiance for x in many], direct, rtol=1e-6)


# ------------------------------------------------------------------ the lights the meter sees

def test_render_visibility_rules_for_lights(fresh):
    """Viewport-hidden lights render (count); hide_render collections and hidden instancers do not."""
    lv = corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.0), name="ViewportHidden", energy=50.0)
    lv.hide_viewport = True
    hidden = bpy.data.collections.new("HiddenColl")
    fresh.collection.children.link(hidden)
    hidden.hide_render = True
    corpus.add_light(fresh, "POINT", (0.5, 0.0, 2.0), name="InHiddenColl", collection=hidden, energy=500.0)
    inst = bpy.data.collections.new("InstancedLight")
    corpus.add_light(None, "POINT", (0.0, 0.0, 0.0), name="InstancedPoint", collection=inst, energy=500.0)
    e = bpy.data.objects.new("HiddenInstancer", None)
    e.instance_type, e.instance_collection = "COLLECTION", inst
    e.location = (-0.5, 0.0, 2.0)
    e.hide_render = True
    fresh.collection.objects.link(e)
    expected = 50.0 / (4 * math.pi * 4.0)
    names = [row["light"] for row in api.predict_illuminance((0, 0, 0), (0, 0, 1))]
    assert names == ["ViewportHidden"], names
    auto = api.measure_illuminance((0, 0, 0), (0, 0, 1))
    assert abs(auto.irradiance / expected - 1) <= EXACT_TOL, auto.irradiance
    rendered = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="render")
    assert abs(rendered.irradiance / expected - 1) <= _tolerance(rendered.rel_std_error, 0.0), rendered.irradiance


def test_no_diffuse_and_portal_lights_give_no_direct_light(fresh):
    corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.0), name="Lamp", energy=100.0)
    nd = corpus.add_light(fresh, "AREA", (0.3, 0.0, 1.0), name="NoDiffuse", energy=200.0, size=0.5)
    nd.visible_diffuse = False
    portal = corpus.add_light(fresh, "AREA", (-0.3, 0.0, 1.0), name="Portal", energy=1000.0, size=1.0)
    portal.data.cycles.is_portal = True
    expected = 100.0 / (4 * math.pi * 4.0)
    rows = {row["light"]: row for row in api.predict_illuminance((0, 0, 0), (0, 0, 1))}
    assert rows["NoDiffuse"]["irradiance"] == 0.0 and rows["Portal"]["irradiance"] == 0.0, rows
    for method in ("auto", "analytic", "render"):
        r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method=method)
        tol = EXACT_TOL if r.exact else _tolerance(r.rel_std_error, 0.0)
        assert abs(r.irradiance / expected - 1) <= tol, (method, r.irradiance, expected, r.notes)


def test_light_without_shadow_shines_through_a_wall(fresh):
    """use_shadow=False: analytic 0 was the bug (Cycles 7.92). A wall (opaque quad) between light and meter."""
    corpus.add_light(fresh, "POINT", (0.0, 2.0, 1.0), name="NoShadow", energy=100.0, use_shadow=False)
    corpus.add_quad(fresh, "Wall", [(-3, 1.0, 0), (3, 1.0, 0), (3, 1.0, 2.5), (-3, 1.0, 2.5)], corpus.diffuse("w", 0.0))
    point, normal = (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)
    expected = _point_light(100.0, (0.0, 2.0, 1.0), point, normal)
    assert abs(api.predict_illuminance(point, normal)[0]["irradiance"] / expected - 1) <= EXACT_TOL
    for method in ("auto", "render"):
        r = api.measure_illuminance(point, normal, method=method)
        tol = EXACT_TOL if r.exact else _tolerance(r.rel_std_error, 0.0)
        assert abs(r.irradiance / expected - 1) <= tol, (method, r.irradiance, expected)


def _occluder_collection():
    coll = bpy.data.collections.new("Occluder")
    corpus.add_box(None, "OccluderBox", (-0.2, -0.2, -0.01), (0.2, 0.2, 0.01), corpus.diffuse("occ", 0.0),
                   collection=coll)
    return coll


@pytest.mark.parametrize("mode", ["collection", "geonodes"])
def test_instanced_occluders_block(fresh, mode):
    """An occluder that exists only as an instance shadows the meter (bug: 60.39 lx marked exact, Cycles 0)."""
    corpus.add_light(fresh, "POINT", (0.0, 0.0, 2.0), name="Lamp", energy=100.0)
    coll = _occluder_collection()
    if mode == "collection":
        e = bpy.data.objects.new("OccluderInstance", None)
        e.instance_type, e.instance_collection = "COLLECTION", coll
        e.location = (0.0, 0.0, 1.0)
        fresh.collection.objects.link(e)
    else:
        mesh = bpy.data.meshes.new("OccPoints")
        mesh.from_pydata([(0.0, 0.0, 1.0)], [], [])
        obj = bpy.data.objects.new("OccArray", mesh)
        fresh.collection.objects.link(obj)
        tree = bpy.data.node_groups.new("OccArray", "GeometryNodeTree")
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        gin, gout = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
        info = tree.nodes.new("GeometryNodeCollectionInfo")
        info.inputs["Collection"].default_value = coll
        info.transform_space = "ORIGINAL"
        iop = tree.nodes.new("GeometryNodeInstanceOnPoints")
        tree.links.new(gin.outputs[0], iop.inputs["Points"])
        tree.links.new(info.outputs[0], iop.inputs["Instance"])
        tree.links.new(iop.outputs["Instances"], gout.inputs[0])
        obj.modifiers.new("OccArray", "NODES").node_group = tree
    unblocked = 100.0 / (4 * math.pi * 4.0)
    rows = api.predict_illuminance((0, 0, 0), (0, 0, 1))
    assert rows[0]["irradiance"] == 0.0, rows
    for method in ("auto", "render"):
        r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method=method)
        assert abs(r.irradiance) <= 1e-6 * unblocked, (method, r.irradiance, r.exact, r.notes)
    # and just beside the occluder's shadow the light is back, unblocked
    r = api.measure_illuminance((0.6, 0.0, 0.0), (0, 0, 1))
    assert abs(r.irradiance / _point_light(100.0, (0, 0, 2), (0.6, 0, 0), (0, 0, 1)) - 1) <= \
        (EXACT_TOL if r.exact else _tolerance(r.rel_std_error, 0.0))


def test_scene_argument_is_honoured_for_a_non_active_scene():
    """Bug: the analytic path read the context scene's lights (1.989 expected, 23.946 read)."""
    built = corpus.two_scenes()
    radiometer.register()
    try:
        other = built["other"]
        assert bpy.context.scene.name == "Scene"
        names = [row["light"] for row in api.predict_illuminance((0, 0, 0), (0, 0, 1), scene=other)]
        assert names == ["OtherArea"], names
        for method in ("auto", "analytic", "render"):
            r = api.measure_illuminance((0, 0, 0), (0, 0, 1), scene=other, method=method)
            expected = CLOSED_FORMS[("two_scenes", "other scene")]
            tol = EXACT_TOL if r.exact else _tolerance(r.rel_std_error, 0.0)
            assert abs(r.irradiance / expected - 1) <= tol, (method, r.irradiance)
            a = api.measure_illuminance((0, 0, 0), (0, 0, 1), method=method)  # the active scene
            expected = CLOSED_FORMS[("two_scenes", "active scene")]
            tol = EXACT_TOL if a.exact else _tolerance(a.rel_std_error, 0.0)
            assert abs(a.irradiance / expected - 1) <= tol, (method, a.irradiance)
    finally:
        radiometer.unregister()


# ------------------------------------------------------------------ "exact" that was not exact

def test_three_delta_lights_in_the_render_path(fresh):
    """Cycles samples one light per estimate: the old one-sample shortcut read +13 % with three lights."""
    lights = [((0.0, 0.0, 2.0), 100.0), ((1.0, 0.5, 1.5), 40.0), ((-1.0, -0.5, 2.5), 250.0)]
    for i, (loc, p) in enumerate(lights):
        corpus.add_light(fresh, "POINT", loc, name=f"P{i}", energy=p)
    expected = sum(_point_light(p, loc, (0, 0, 0), (0, 0, 1)) for loc, p in lights)
    r = api.measure_illuminance((0, 0, 0), (0, 0, 1), method="render")
    assert not r.exact
    assert abs(r.irradiance / expected - 1) <= _tolerance(r.rel_std_error, 0.0), (r.irradiance, expected, r.notes)
    a = api.measure_illuminance((0, 0, 0), (0, 0, 1))
    assert a.exact and abs(a.irradiance / expected - 1) <= EXACT_TOL, (a.irradiance, expected)


def _spot_with_radius_scene():
    scene = corpus.reset()
    corpus.black_world(scene)
    # radius 0.25 m, 1 m above the floor level, cone 20 deg (half 10 deg) narrower than the light's
    # cap seen from the meters, hard edge
    corpus.add_light(scene, "SPOT", (0.0, 0.0, 1.0), name="WideSpot", energy=50.0, shadow_soft_size=0.25,
                     spot_size=math.radians(20.0), spot_blend=0.0)
    return scene


SPOT_POINTS = [("on axis", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
               ("near the cone edge", (0.15, 0.0, 0.0), (0.0, 0.0, 1.0)),
               ("outside the cone axis-cone", (0.3, 0.0, 0.0), (0.0, 0.0, 1.0)),
               ("tilted meter", (0.1, 0.05, 0.0), (0.3, 0.0, 0.9539392)),
               ("inside the light's sphere", (0.0, 0.0, 0.9), (0.0, 0.0, 1.0))]


def test_spot_with_radius_narrower_than_its_cap():
    """Bug: the quadrature missed the cone edge (-0.7 % to -2.6 %, note claimed ~1e-3); a meter inside
    the spot's sphere read 0.91 x the Cycles value."""
    scene = _spot_with_radius_scene()
    radiometer.register()
    failures = []
    try:
        for label, p, n in SPOT_POINTS:
            e, ref_se, _ = reference.reference_irradiance(scene, p, n, target_rel_error=REF_TARGET, max_seconds=30)
            ref = reference.luminance(e)[0]
            r = api.measure_illuminance(p, n)
            if ref == 0.0:
                ok = abs(r.irradiance) <= 1e-9
            else:
                ok = abs(r.irradiance / ref - 1) <= _tolerance(r.rel_std_error, ref_se) and (r.exact or r.rel_std_error > 0)
            if not ok or (r.exact and ref and abs(r.irradiance / ref - 1) > EXACT_TOL + 3 * ref_se):
                failures.append(f"{label}: reading {r.irradiance:.6g} (s.e. {r.rel_std_error:.2e}, exact {r.exact}, "
                                f"{r.method}) vs reference {ref:.6g} (s.e. {ref_se:.2e})")
    finally:
        radiometer.unregister()
    assert not failures, failures


# ------------------------------------------------------------------ lights behind lights (camera paths)

def test_stacked_lights_seen_by_luminance_meter_and_radiance_map(tmp_path):
    """Lights are transparent to rays: a luminance meter looking up through the lower panel sees both
    (L = 2 x 50 / pi); a radiance map at the meter integrates to the stacked closed form (bug: -19 %)."""
    corpus.stacked_lights()
    radiometer.register()
    try:
        lum = api.measure_luminance((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), acceptance_deg=1.0)
        m = api.capture_radiance_map((0.0, 0.0, 0.0), str(tmp_path / "stacked.exr"), resolution=128)
    finally:
        radiometer.unregister()
    expected_l = 2 * 50.0 / math.pi
    assert abs(lum.radiance / expected_l - 1) <= _tolerance(lum.rel_std_error, 0.0), (lum.radiance, expected_l)
    expected_e = CLOSED_FORMS[("stacked_lights", "on axis")]
    se = m.rel_std_error if math.isfinite(m.rel_std_error) else 0.0
    # the map's pixels integrate the radiance; at 128 x 64 the square's edges are resolved to ~1 %
    assert abs(m.irradiance / expected_e - 1) <= max(3 * se, 0.01), (m.irradiance, expected_e, m.notes)
    # one panel alone would give only ~72 % of this (the lower one) -- the old opaque-light bug
    lower = 50.0 / math.pi * _projected_solid_angle(_square(1.0), (0, 0, 0), (0, 0, 1))
    assert m.irradiance > 1.1 * lower


# ------------------------------------------------------------------ small API promises

def test_grid_points_lie_on_the_plane_and_law_rows_unpack(fresh):
    lamp = corpus.add_light(fresh, "POINT", (0.2, 0.1, 2.0), name="Lamp", energy=100.0)
    mesh = bpy.data.meshes.new("WorkPlane")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    plane = bpy.data.objects.new("WorkPlane", mesh)
    plane.location = (0.0, 0.0, 0.75)
    fresh.collection.objects.link(plane)
    g = api.illuminance_grid(plane, resolution=(4, 3))
    assert g.points.shape == (3, 4, 3)
    assert np.all(g.points[..., 2] == pytest.approx(0.75, abs=1e-9)), g.points[..., 2]
    to_light = np.array([0.2, 0.1, 2.0]) - g.points
    r = np.linalg.norm(to_light, axis=-1)
    expected = 683.0 * 100 / (4 * math.pi) * to_light[..., 2] / r ** 3
    assert np.max(np.abs(g.lux / expected - 1)) <= max(3 * float(np.max(g.rel_std_error)), 1e-4)
    inv = api.check_inverse_square(lamp, distances=[0.5, 1.0, 1.5], method="analytic")
    for row in inv.rows:
        distance, measured, predicted, *rest = row
        assert isinstance(row, tuple) and distance == row.distance and measured == row.measured
        assert predicted == row.predicted and rest
    cos = api.check_cosine_law(lamp, angles_deg=[0.0, 30.0, 60.0], method="analytic")
    for row in cos.rows:
        angle, measured, predicted, *rest = row
        assert isinstance(row, tuple) and angle == row[0] and measured == row[1] and predicted == row[2]

"""Physical properties of every BRDF model: reciprocity, energy, isotropy, shapes, robustness."""

import importlib.util
import math
import pathlib
import warnings

import numpy as np
import pytest

import radiometer.brdf as brdf

_spec = importlib.util.spec_from_file_location("brdf_cases", pathlib.Path(__file__).with_name("brdf_cases.py"))
cases = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cases)
MODEL_PARAMS, ENERGY_CASES = cases.MODEL_PARAMS, cases.ENERGY_CASES

IDS = [f"{n}-{i}" for i, (n, _) in enumerate(MODEL_PARAMS)]


def random_upper(rng, n):
    w = rng.normal(size=(n, 3))
    w[:, 2] = np.abs(w[:, 2]) + 1e-3
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


def test_names_are_exactly_the_required_models():
    assert brdf.names() == ["lambert", "oren_nayar", "phong", "blinn_phong", "torrance_sparrow",
                            "ggx", "beckmann", "ward", "ashikhmin_shirley", "mirror"]


@pytest.mark.parametrize("name,params", MODEL_PARAMS, ids=IDS)
def test_reciprocity(name, params):
    # Every model in the library is documented reciprocal: f(wi, wo) = f(wo, wi) to 1e-6 relative.
    rng = np.random.default_rng(1)
    wi, wo = random_upper(rng, 2000), random_upper(rng, 2000)
    assert brdf.describe(name)["reciprocal"]
    a = brdf.evaluate(name, wi, wo, **params)
    b = brdf.evaluate(name, wo, wi, **params)
    np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-12)


@pytest.mark.parametrize("name,params", MODEL_PARAMS, ids=IDS)
def test_isotropy_or_anisotropy(name, params):
    rng = np.random.default_rng(2)
    wi, wo = random_upper(rng, 500), random_upper(rng, 500)
    phi = 0.7
    rot = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0], [0, 0, 1]])
    a = brdf.evaluate(name, wi, wo, **params)
    b = brdf.evaluate(name, wi @ rot.T, wo @ rot.T, **params)
    anisotropic = name in ("ward", "ashikhmin_shirley") or params.get("alpha_x", 0) != params.get("alpha_y", 0)
    if anisotropic:
        # Demonstrably anisotropic: rotating both directions about the normal changes f a lot.
        assert np.max(np.abs(a - b) / (np.abs(a) + 1e-12)) > 0.1
    else:
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)


# Quadrature accuracy of brdf.albedo (4096 points, 3-strategy MIS) measured against 65536-point and
# 4000x4000-grid references: |error| <= 2.6e-4 over these cases; the tolerance is 5e-4.
ALBEDO_TOL = 5e-4


@pytest.mark.parametrize("name,params", ENERGY_CASES, ids=[f"{n}-{i}" for i, (n, _) in enumerate(ENERGY_CASES)])
def test_energy_conservation(name, params):
    theta = np.radians(np.linspace(0.0, 89.5, 12))
    a = brdf.albedo(name, theta, **params)
    assert a.shape == (12, 3)
    assert np.all(np.isfinite(a)) and np.all(a >= 0)
    assert np.max(a) <= 1.0 + ALBEDO_TOL


def test_lambert_white_furnace():
    a = brdf.albedo("lambert", np.radians([0, 20, 45, 70, 89]), albedo=(1.0, 0.5, 0.25))
    np.testing.assert_allclose(a, np.broadcast_to([1.0, 0.5, 0.25], a.shape), atol=1e-6)


def test_oren_nayar_cycles_white_furnace():
    # Cycles' energy-preserving Oren-Nayar is designed to pass the white furnace test at albedo 1
    # (OpenPBR EON construction): ∫ f cos = E(wi) + (1 - E(wi)) = 1 for any roughness.
    a = brdf.albedo("oren_nayar", np.radians([0, 30, 60, 85]), albedo=1.0, sigma=1.0, variant="cycles")
    np.testing.assert_allclose(a, 1.0, atol=1e-4)


SHAPES = [(3,), (6, 3), (2, 3, 3)]


@pytest.mark.parametrize("name,params", MODEL_PARAMS, ids=IDS)
def test_nd_shapes_consistent(name, params):
    rng = np.random.default_rng(3)
    wi_flat, wo_flat = random_upper(rng, 18), random_upper(rng, 18)
    ref = brdf.evaluate(name, wi_flat, wo_flat, **params)
    for shape in SHAPES:
        n = int(np.prod(shape[:-1]))
        out = brdf.evaluate(name, wi_flat[:n].reshape(shape), wo_flat[:n].reshape(shape), **params)
        assert out.shape == shape[:-1] + (3,)
        np.testing.assert_allclose(out.reshape(-1, 3), ref[:n], rtol=1e-12, atol=1e-300)  # SIMD order may differ by an ulp
    # Broadcasting one wi against many wo.
    out = brdf.evaluate(name, wi_flat[0], wo_flat.reshape(6, 3, 3), **params)
    np.testing.assert_allclose(out.reshape(-1, 3), brdf.evaluate(name, np.tile(wi_flat[0], (18, 1)), wo_flat, **params), rtol=1e-12)
    a = brdf.albedo(name, np.full((2, 3), 0.4), **params)
    assert a.shape == (2, 3, 3) and np.all(a == a[0, 0])


SPECIAL = [-1.0, 0.0, 1.0, -np.inf, np.inf, np.nan]


def _special_dirs():
    grid = np.array(np.meshgrid(SPECIAL, SPECIAL, SPECIAL, indexing="ij")).reshape(3, -1).T
    return grid  # 216 directions, all combinations


@pytest.mark.parametrize("name,params", MODEL_PARAMS, ids=IDS)
def test_nan_inf_inputs(name, params):
    d = _special_dirs()
    wi = np.repeat(d, len(d), axis=0)
    wo = np.tile(d, (len(d), 1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = brdf.evaluate(name, wi, wo, **params)
    has_nan = np.isnan(wi).any(-1) | np.isnan(wo).any(-1)
    # NaN in -> NaN out for that element only; everything else finite and non-negative.
    assert np.all(np.isnan(f[has_nan]))
    assert np.all(np.isfinite(f[~has_nan])) and np.all(f[~has_nan] >= 0)
    if brdf.describe(name)["samplable"]:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            p = brdf.pdf(name, wi, wo, **params)
            ws, ps = brdf.sample(name, d, np.full((len(d), 2), 0.3), **params)
        assert np.all(np.isnan(p[has_nan])) and np.all(np.isfinite(p[~has_nan])) and np.all(p[~has_nan] >= 0)
        bad = np.isnan(d).any(-1)
        assert np.all(np.isfinite(ws[~bad])) and np.all(np.isfinite(ps[~bad])) and np.all(np.isnan(ps[bad]))


EXTREME_PARAMS = [
    ("ggx", {"alpha": 1e-4}), ("ggx", {"alpha": 1.0}), ("beckmann", {"alpha": 1e-4}),
    ("torrance_sparrow", {"alpha": 1e-4}), ("ggx", {"alpha_x": 1e-4, "alpha_y": 1.0}),
    ("phong", {"kd": 0.0, "ks": 1.0, "n": 1e6}), ("blinn_phong", {"ks": 1.0, "n": 1e6}),
    ("ward", {"kd": 0.0, "ks": 1.0, "alpha_x": 1e-4, "alpha_y": 1e-4}),
    ("ashikhmin_shirley", {"n_u": 1e6, "n_v": 1e6}), ("ashikhmin_shirley", {"n_u": 0.0, "n_v": 1e6}),
    ("oren_nayar", {"sigma": math.pi / 2}), ("oren_nayar", {"sigma": 1.0, "variant": "cycles"}),
    ("lambert", {}), ("mirror", {"eta": 0.2, "k": 3.0}),
]


@pytest.mark.parametrize("name,params", EXTREME_PARAMS, ids=[f"{n}-{i}" for i, (n, _) in enumerate(EXTREME_PARAMS)])
def test_extremes_finite(name, params):
    g = 1e-8  # cos θ = 1e-8: grazing
    s = math.sqrt(1 - g * g)
    dirs = np.array([[s, 0, g], [0, s, g], [-s, 0, g], [0, 0, 1], [s / 2, s * math.sqrt(3) / 2, g],
                     [0.6, 0, 0.8], [-0.6, 0, 0.8], [1e-300, 0, 1], [1e300, 1e300, 1e300], [0, 0, 0]])
    wi = np.repeat(dirs, len(dirs), axis=0)
    wo = np.tile(dirs, (len(dirs), 1))
    wi = np.concatenate([wi, dirs, dirs])
    wo = np.concatenate([wo, dirs, -dirs])  # wi == wo and wi == -wo
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f = brdf.evaluate(name, wi, wo, **params)
        a = brdf.albedo(name, np.array([0.0, 1.5707, math.pi / 2 - 1e-8]), **params)
        if brdf.describe(name)["samplable"]:
            u = np.random.default_rng(4).random((len(wo), 2))
            ws, ps = brdf.sample(name, wo, u, **params)
            pp = brdf.pdf(name, wi, wo, **params)
            assert np.all(np.isfinite(ws)) and np.all(np.isfinite(ps)) and np.all(ps >= 0)
            assert np.all(np.isfinite(pp)) and np.all(pp >= 0)
    assert np.all(np.isfinite(f)) and np.all(f >= 0)
    assert np.all(np.isfinite(a)) and np.all(a >= 0) and np.all(a <= 1 + ALBEDO_TOL)
    assert np.all(f[-len(dirs):] == 0)  # wi == -wo: one of them is below the horizon


def test_below_horizon_is_zero():
    wi = np.array([[0.3, 0.1, -0.5], [0.3, 0.1, 0.5], [0.3, 0.1, 0.0]])
    wo = np.array([[0.0, 0.0, 1.0], [0.1, 0.2, -0.1], [0.0, 0.0, 1.0]])
    for name, params in MODEL_PARAMS:
        assert np.all(brdf.evaluate(name, wi, wo, **params) == 0)


def test_unnormalised_inputs_are_normalised():
    rng = np.random.default_rng(5)
    wi, wo = random_upper(rng, 50), random_upper(rng, 50)
    for name, params in MODEL_PARAMS:
        np.testing.assert_allclose(brdf.evaluate(name, 7.5 * wi, 0.01 * wo, **params),
                                   brdf.evaluate(name, wi, wo, **params), rtol=1e-12)


@pytest.mark.parametrize("name,bad", [
    ("lambert", {"albedo": -0.1}), ("lambert", {"albedo": float("nan")}), ("lambert", {"albedo": (0.5, 1.2, 0.1)}),
    ("ggx", {"alpha": 0.0}), ("ggx", {"alpha": 2.0}), ("ggx", {"alpha": float("nan")}),
    ("ggx", {"f0": 0.5, "ior": 1.5}), ("ggx", {"eta": 1.0}), ("ggx", {"ior": -1.0}),
    ("phong", {"n": -1.0}), ("phong", {"kd": 0.6, "ks": 0.6}), ("ward", {"alpha_x": 0.0}),
    ("ashikhmin_shirley", {"n_u": 2e6}), ("oren_nayar", {"sigma": 1.2, "variant": "cycles"}),
    ("oren_nayar", {"variant": "fancy"}), ("lambert", {"roughness": 0.5}), ("nope", {}),
])
def test_invalid_parameters_raise(name, bad):
    with pytest.raises(ValueError) as err:
        brdf.evaluate(name, [0, 0, 1], [0, 0, 1], **bad)
    key = next(iter(bad), None)
    if key and name != "nope" and not (name == "ggx" and "f0" in bad) and key != "eta":
        assert key in str(err.value)


def test_describe_complete_and_stable():
    for name in brdf.names():
        d = brdf.describe(name)
        assert d["name"] == name and d["doc"] and d["references"]
        assert d["units"]["f"] == "1/sr"
        for q in d["parameters"]:
            assert set(q) >= {"name", "default", "min", "max", "kind", "unit", "description"}
            assert q["kind"] in ("float", "color") and q["min"] <= q["max"] and q["description"]
            if not q["optional"]:
                assert q["min"] <= np.min(q["default"]) and np.max(q["default"]) <= q["max"]
        # Defaults alone must be a valid parameter set.
        f = brdf.evaluate(name, [0.3, 0.0, 0.9], [-0.2, 0.1, 0.9])
        assert f.shape == (3,) and np.all(np.isfinite(f))
    assert brdf.describe("oren_nayar")["options"]["variant"]["values"] == ["classic", "cycles"]


def test_no_blender_imports():
    import re
    import sys
    import radiometer.brdf.plots  # noqa: F401  (plots must import without matplotlib/bpy at module level)
    for mod in list(sys.modules):
        if mod.startswith("radiometer.brdf"):
            src = pathlib.Path(sys.modules[mod].__file__).read_text()
            assert not re.search(r"^\s*(import|from)\s+(bpy|mathutils)\b", src, re.M), mod
            assert "matplotlib" not in sys.modules or mod.endswith("plots") or "import matplotlib" not in src

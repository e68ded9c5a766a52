"""Shared parameter tables for the tests/test_brdf_*.py files (not a test module)."""

import math

# Representative parameters per model (every model appears; several sets where behaviour differs).
MODEL_PARAMS = [
    ("lambert", {"albedo": (0.9, 0.5, 0.1)}),
    ("oren_nayar", {"albedo": 0.8, "sigma": 0.5}),
    ("oren_nayar", {"albedo": (1.0, 0.6, 0.2), "sigma": 0.7, "variant": "cycles"}),
    ("phong", {"kd": 0.3, "ks": 0.6, "n": 30.0}),
    ("blinn_phong", {"kd": 0.2, "ks": 0.7, "n": 40.0}),
    ("torrance_sparrow", {"alpha": 0.3, "ior": 1.5}),
    ("ggx", {"alpha": 0.3, "f0": (0.95, 0.64, 0.54)}),
    ("ggx", {"alpha_x": 0.1, "alpha_y": 0.4, "eta": (0.2, 0.9, 1.1), "k": (3.9, 2.4, 2.2)}),
    ("beckmann", {"alpha": 0.25}),
    ("ward", {"kd": 0.2, "ks": 0.6, "alpha_x": 0.1, "alpha_y": 0.4}),
    ("ashikhmin_shirley", {"n_u": 200.0, "n_v": 10.0, "Rs": 0.4, "Rd": 0.5}),
    ("mirror", {"f0": 0.82}),
]

SAMPLED = [(n, p) for n, p in MODEL_PARAMS if n != "mirror"]

# Parameter ranges for the energy-conservation scan (white, no Fresnel loss: worst case).
ENERGY_CASES = (
    [(m, {"alpha": a}) for m in ("ggx", "beckmann", "torrance_sparrow") for a in (1e-4, 0.05, 0.3, 1.0)]
    + [("ggx", {"alpha_x": 0.05, "alpha_y": 0.8})]
    + [(m, {"kd": 0.0, "ks": 1.0, "n": n}) for m in ("phong", "blinn_phong") for n in (0.0, 1.0, 50.0, 1e6)]
    + [("phong", {"kd": 0.5, "ks": 0.5, "n": 5.0})]
    + [("ward", {"kd": 0.0, "ks": 1.0, "alpha_x": ax, "alpha_y": ay}) for ax, ay in ((1e-4, 1e-4), (0.1, 0.5), (1.0, 1.0))]
    + [("ashikhmin_shirley", {"n_u": nu, "n_v": nv, "Rs": rs, "Rd": 1.0})
       for nu, nv in ((0.0, 0.0), (20.0, 10.0), (1e6, 1e6)) for rs in (0.0, 1.0)]
    + [("oren_nayar", {"albedo": 1.0, "sigma": s}) for s in (0.0, 0.5, math.pi / 2)]
    + [("oren_nayar", {"albedo": 1.0, "sigma": s, "variant": "cycles"}) for s in (0.01, 0.5, 1.0)]
    + [("lambert", {"albedo": 1.0}), ("mirror", {}), ("mirror", {"ior": 1.5})]
)

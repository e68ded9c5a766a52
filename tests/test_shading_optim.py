"""radiometer.shading.optim (numpy only) against scipy.optimize, and the fit that uses it.

Reference values: scipy.optimize.lsq_linear(method="bvls") and scipy.optimize.minimize(method=
"Nelder-Mead") (scipy 1.17); the KKT conditions of bounded least squares (Stark & Parker 1995,
eq. 2), which hold exactly at the solution; the Rosenbrock minimum (1, ..., 1) and the minimum of a
convex quadratic (closed form); and the fidelity numbers that shading.realise stated with the scipy
optimisers before they were replaced (commit dd21e8e, bench/brdf_fidelity.md).
"""

import numpy as np
import pytest

from radiometer.shading import fit as F
from radiometer.shading import optim
from radiometer.shading.realise import realise

scipy_optimize = pytest.importorskip("scipy.optimize")


def _kkt_scale(A, b, x):
    return np.linalg.norm(A) * (np.linalg.norm(b) + np.linalg.norm(A) * np.linalg.norm(x))


def _random_problem(rng, kind):
    m, n = int(rng.integers(2, 80)), int(rng.integers(1, 8))
    A = rng.normal(size=(m, n)) * rng.uniform(0.01, 10.0, size=n)  # column scales over 3 decades
    if kind == "collinear" and n >= 2:
        A[:, 1] = A[:, 0] * 2.0 + 1e-6 * rng.normal(size=m)  # condition number ~1e6
    b = rng.normal(size=m) * 3.0
    if kind == "unit_box":
        lo, hi = np.zeros(n), np.ones(n)
    else:
        lo = rng.uniform(-1.0, 0.5, size=n)
        hi = lo + rng.uniform(0.01, 2.0, size=n)
    return A, b, lo, hi


@pytest.mark.parametrize("kind", ["unit_box", "general", "collinear"])
def test_bvls_matches_scipy_and_satisfies_kkt(kind):
    rng = np.random.default_rng({"unit_box": 1, "general": 2, "collinear": 3}[kind])
    for _ in range(300):
        A, b, lo, hi = _random_problem(rng, kind)
        ours = optim.bvls(A, b, lo, hi)
        assert ours.status == 0
        assert np.all(ours.x >= lo) and np.all(ours.x <= hi)
        assert optim.kkt_violation(A, b, ours.x, lo, hi) <= 1e-13 * _kkt_scale(A, b, ours.x)
        if A.shape[0] >= A.shape[1]:
            ref = scipy_optimize.lsq_linear(A, b, bounds=(lo, hi), method="bvls")
            assert ours.fun <= ref.cost * (1 + 1e-12) + 1e-300
            if kind != "collinear":  # well conditioned: the minimiser itself is well determined
                np.testing.assert_allclose(ours.x, ref.x, rtol=0, atol=1e-8)


def test_bvls_edge_cases():
    rng = np.random.default_rng(4)
    A, b = rng.normal(size=(20, 3)), rng.normal(size=20)
    # unbounded = ordinary least squares
    free = optim.bvls(A, b, -np.inf, np.inf)
    np.testing.assert_allclose(free.x, np.linalg.lstsq(A, b, rcond=None)[0], rtol=1e-12, atol=1e-14)
    # a fixed variable (lower == upper) stays where it is
    fixed = optim.bvls(A, b, [0.0, 0.25, 0.0], [1.0, 0.25, 1.0])
    assert fixed.x[1] == 0.25 and fixed.status == 0
    # exact duplicate columns: the solution is not unique, the objective is
    dup = np.c_[A[:, :1], A[:, :1], A[:, 1:]]
    ours = optim.bvls(dup, b, 0.0, 1.0)
    ref = scipy_optimize.lsq_linear(dup, b, bounds=(0.0, 1.0), method="bvls")
    assert ours.fun == pytest.approx(ref.cost, rel=1e-10)
    # fewer rows than columns
    wide = optim.bvls(A[:2], b[:2], 0.0, 1.0)
    assert optim.kkt_violation(A[:2], b[:2], wide.x, 0.0, 1.0) <= 1e-12
    # zero matrix: any x is optimal, the start (lower bounds) is returned
    assert optim.bvls(np.zeros((4, 2)), np.ones(4), 0.0, 1.0).x.tolist() == [0.0, 0.0]
    with pytest.raises(ValueError):
        optim.bvls(A, b, 1.0, 0.0)
    with pytest.raises(ValueError):
        optim.bvls(A, np.r_[b[:-1], np.nan], 0.0, 1.0)


def test_bvls_on_the_fit_matrices_matches_scipy(monkeypatch):
    """The least-squares problems the BRDF fit really solves (ward: diffuse + anisotropic lobe)."""
    seen = []

    def recording_bvls(A, b, lo, hi):
        seen.append((A, b))
        return optim.bvls(A, b, lo, hi)

    monkeypatch.setattr(F, "bvls", recording_bvls)
    from radiometer.shading.realise import _microfacet_candidates

    wi, wo = F.direction_set(0.2)
    f_model = realise.__globals__["_f_model"]("ward", {})
    cand = _microfacet_candidates([0.2, 0.2], aniso=True, distributions=("beckmann",))[0]
    F.fit_candidate(cand, f_model, wi[::9], wo[::9])
    assert len(seen) > 10
    for A, b in seen[::5]:
        ours = optim.bvls(A, b, 0.0, 1.0)
        ref = scipy_optimize.lsq_linear(A, b, bounds=(0.0, 1.0), method="bvls")
        np.testing.assert_allclose(ours.x, ref.x, rtol=0, atol=1e-8)
        assert optim.kkt_violation(A, b, ours.x, 0.0, 1.0) <= 1e-13 * _kkt_scale(A, b, ours.x)


def _rosenbrock(x):
    return float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1.0 - x[:-1]) ** 2))


@pytest.mark.parametrize("x0", [[-1.2, 1.0], [0.0, 0.0, 0.0], [1.3, 0.7, 0.8, 1.9, 1.2]])
@pytest.mark.parametrize("opts", [{"xatol": 1e-8, "fatol": 1e-10, "maxiter": 5000},
                                  {"xatol": 1e-3, "fatol": 1e-5}])
def test_nelder_mead_follows_scipy_step_by_step(x0, opts):
    opts = dict(opts, maxiter=opts.get("maxiter", 120 * len(x0)))  # as shading.fit calls it
    ref = scipy_optimize.minimize(_rosenbrock, x0, method="Nelder-Mead", options=opts)
    ours = optim.nelder_mead(_rosenbrock, x0, **opts)
    np.testing.assert_allclose(ours.x, ref.x, rtol=0, atol=1e-12)
    assert (ours.nfev, ours.nit, ours.status) == (ref.nfev, ref.nit, ref.status)
    if opts["xatol"] < 1e-6 and len(x0) < 5:
        np.testing.assert_allclose(ours.x, np.ones(len(x0)), atol=1e-6)  # the Rosenbrock minimum


def test_nelder_mead_quadratic_limits_and_adaptive():
    H = np.array([[3.0, 1.0, 0.0], [1.0, 2.0, 0.5], [0.0, 0.5, 1.0]])
    g = np.array([1.0, -2.0, 0.5])
    quad = lambda x: 0.5 * x @ H @ x - g @ x  # noqa: E731 - minimum at H^-1 g
    best = np.linalg.solve(H, g)
    res = optim.nelder_mead(quad, np.zeros(3), xatol=1e-10, fatol=1e-14, maxiter=10000)
    assert res.status == 0 and np.allclose(res.x, best, atol=1e-8)
    for adaptive in (False, True):
        ref = scipy_optimize.minimize(quad, np.zeros(3), method="Nelder-Mead",
                                      options={"xatol": 1e-10, "fatol": 1e-14, "adaptive": adaptive})
        ours = optim.nelder_mead(quad, np.zeros(3), xatol=1e-10, fatol=1e-14, adaptive=adaptive)
        assert ours.nfev == ref.nfev and np.allclose(ours.x, ref.x, atol=1e-12)
    capped = optim.nelder_mead(quad, np.zeros(3), xatol=1e-12, fatol=1e-16, maxiter=10)
    assert capped.status == 2 and capped.nit == 10
    capped = optim.nelder_mead(quad, np.zeros(3), xatol=1e-12, fatol=1e-16, maxfev=17)
    assert capped.status == 1 and capped.nfev == 17
    with pytest.raises(ValueError):
        optim.nelder_mead(lambda x: x, np.zeros(2))  # the objective must be scalar


# Stated fidelity with scipy's lsq_linear / Nelder-Mead (before this module; bench/brdf_fidelity.md
# prints them rounded): (model, method, params) -> (rms_rel_diff, albedo_diff, a fitted parameter).
SCIPY_ERA = [
    ("beckmann", "nodes", {"alpha_x": 0.4, "alpha_y": 0.1, "f0": 0.9}, 0.0025063891381439905,
     0.002571637697147411, None),
]


@pytest.mark.parametrize("model,method,params,rms,albedo,fitted", SCIPY_ERA, ids=[r[0] for r in SCIPY_ERA])
def test_stated_fidelity_unchanged_by_the_numpy_optimisers(model, method, params, rms, albedo, fitted):
    _, fid = realise(model, method, **params)
    assert fid.rms_rel_diff == pytest.approx(rms, rel=1e-3)
    assert fid.albedo_diff == pytest.approx(albedo, rel=1e-3)
    if fitted:
        assert fid.fitted[fitted[0]] == pytest.approx(fitted[1], rel=1e-3)

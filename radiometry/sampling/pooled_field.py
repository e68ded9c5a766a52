"""Pooled estimate of the rendered light at many meters on one plane (pure numpy, no bpy; issue 17).

Below the per-meter sampling floor: the rendered part of a reading (reflected light, whatever no
closed form gives) is smooth across neighbouring meters, so a field fitted over many meters' few
samples each is more precise than any one meter's own samples. Its honesty rests on two measured
errors, never on the field's form being right:

1. **the fit's own standard error**: least squares (weighted by each meter's samples, fixed before
   sampling: ``fit_blocks``) of a polynomial in the plane's
   coordinates (Legendre products of total degree d; d chosen by leave-one-out cross-validation on
   the fitted meters alone), its covariance by the sandwich formula from every meter's own batch-means
   variance (so no weight is a noisy estimate correlated with the value it weighs);
2. **the misfit**: what the polynomial cannot follow. It is measured on HELD-OUT meters: a random
   sample of the same meters, left out of the fit and sampled on their own to the target. Their
   residuals r_h = y_h - f(x_h) have variance v_h + tau^2 (v_h: their own s.e.^2 plus the fit's
   s.e.^2 there; tau^2: the mean squared misfit over the meters). The statement uses a one-sided
   ``CONFIDENCE`` upper bound on tau^2 (the Q-profile bound: the tau^2 at which
   Q(tau^2) = sum r_h^2 / (v_h + tau^2) falls to the chi-square(H) lower quantile; Viechtbauer 2007,
   Stat. Med. 26:37), so few held-out meters state a larger misfit, not a smaller one.

The fitted meters take samples in proportion to the field's leverage at them (``fit_blocks``: more at
the plane's edges and corners, where a polynomial leans on few meters), a design fixed by the meters'
places alone. A pooled reading's 1-sigma error = sqrt(fit s.e.^2 + tau_ub^2). The group falls back to per-meter
sampling when there are too few held-out meters, or one of them departs from the field beyond its
own noise and the bounded misfit (a Bonferroni test at ``OUTLIER_LEVEL``: a sharp feature the field
cannot follow); a meter whose pooled error misses the target falls back on its own. tau^2 is a mean
over the meters as they are spread (held-out meters are drawn from them at random): a meter in a
corner where the field bends most may be off by more than its stated error, one in the middle by
less (measured coverage: bench/speed-results.md, 'Pooled estimator').

Only the rendered part is pooled: closed-form (direct) parts stay per meter and are added by the
caller. Pooled readings are never exact.
"""

from dataclasses import dataclass, field
from statistics import NormalDist

import numpy as np

from . import allocation

__all__ = ["POOL_MIN_METERS", "plane_groups", "plane_coordinates", "polynomial_basis",
           "fit_blocks", "FieldFit", "fit_field", "misfit_upper_bound", "HoldoutCheck", "check_held_out",
           "choose_held_out", "local_misfit", "pooled_estimate", "allocate_pooled"]

#: Fewest meters on one plane (same normal, same exclusions) for pooling: 10 % of them are held out
#: (at least ``MIN_HOLDOUT``) and the rest must carry a polynomial of up to ``MAX_DEGREE``.
POOL_MIN_METERS = 300
#: The fitted meters' samples: ``FIT_SPP`` per texel, ``FIT_MIN_BLOCKS`` to ``FIT_MAX_BLOCKS`` blocks
#: of 16 texels each (128 to 1024 samples), in proportion to the field's leverage at the meter
#: (``fit_blocks``). Measured in the throughput room (bench/speed-results.md, 'Pooled estimator', 4
#: seeds): 256 each (8 spp, 2 blocks) spent 0.37-0.39 M samples on 1000 meters; by leverage at 4 spp,
#: 0.30-0.32 M with as many meters pooled and held-out misfits as small (0-0.07 W/m^2). One block a
#: meter is too few: by leverage at 8 spp (1 block in the middle) the held-out misfit estimate rose
#: to 0.04-0.14 W/m^2 and one seed of 4 was refused (a meter's variance from 16 texels understates
#: what its mean varies by: the check saw it, the cost followed), so at least 2 blocks (32 texels).
#: At 4 spp the pilot of the meters read on their own (8 spp) no longer rides in this bake: one bake
#: more (~10 ms in that room).
FIT_SPP = 4
FIT_MIN_BLOCKS = allocation.MIN_BLOCKS
FIT_MAX_BLOCKS = 16
#: A group's fitted meters take at least about this many blocks in all at the median leverage (the
#: fit's error grows as sqrt(1 / (meters x samples))): a group of 900 fitted meters takes 2 blocks (128
#: samples) at its median meter, one of 160 (tests/bpy/test_pooled_meters.py) 6.
FIT_GROUP_BLOCKS = 960
#: Degree of the polynomial whose leverages set the fitted meters' blocks (the throughput room's fits
#: choose 4-5).
LEVERAGE_DEGREE = 4
#: Share of a group held out, and the bounds on their number.
HOLDOUT_FRACTION = 0.1
MIN_HOLDOUT = 40
MAX_HOLDOUT = 150
#: Highest polynomial degree tried, and at least this many fitted meters per coefficient.
MAX_DEGREE = 6
METERS_PER_PARAMETER = 8
#: Fewest fitted meters with smooth light (not dark, not lit by rare paths) for a field: a degree-4 one.
MIN_FITTED = 15 * METERS_PER_PARAMETER
#: Per-sample relative variance of a fitted meter's pilot (texel variance x spp / mean^2) from which its
#: light counts as coming by rare paths (a path found in fewer than about 1 sample in 10: Bernoulli
#: (1 - p) / p >= 10): such a meter is not pooled (the throughput room's meters: ~0.08). Stricter than
#: ``allocation.HEAVY_TAIL`` (where a meter read on its own starts stating the sampler table's floor):
#: a field averages one bake's texels, and only 256 samples per meter judge the spread.
RARE_PATH_SPREAD = 10.0
#: Fitted meters in the neighbourhood of the local check (``local_misfit``).
LOCAL_NEIGHBOURS = 16
#: One-sided confidence of the misfit's upper bound.
CONFIDENCE = 0.95
#: Family-wise level of the held-out outlier test (a sharp feature the field cannot follow).
OUTLIER_LEVEL = 0.01
#: Meters share a plane when their normals agree to this (unit vectors) and their distance along it
#: to PLANE_TOLERANCE_M (sensors on surfaces sit a few micrometres above them).
NORMAL_TOLERANCE = 1e-6
PLANE_TOLERANCE_M = 1e-3


# --- domain ---------------------------------------------------------------------------------------

def plane_groups(points_m, normals, keys=None, eligible=None, min_meters=POOL_MIN_METERS):
    """Index arrays of the meters that can be pooled together: the same normal, the same plane and
    the same ``keys`` entry (e.g. the set of lights added in closed form, which changes what is
    rendered), only ``eligible`` ones, groups of at least ``min_meters``."""
    points_m = np.asarray(points_m, float)
    normals = np.asarray(normals, float)
    n = len(points_m)
    eligible = np.ones(n, bool) if eligible is None else np.asarray(eligible, bool)
    keys = [None] * n if keys is None else list(keys)
    buckets = {}
    for k in np.flatnonzero(eligible):
        nk = tuple(np.round(normals[k] / NORMAL_TOLERANCE).astype(np.int64))
        buckets.setdefault((nk, keys[k]), []).append(k)
    groups = []
    for members in buckets.values():
        members = np.asarray(members)
        # Along the normal: split into runs of distance within the tolerance of each other.
        d = points_m[members] @ normals[members[0]]
        order = np.argsort(d, kind="stable")
        breaks = np.flatnonzero(np.diff(d[order]) > PLANE_TOLERANCE_M) + 1
        for part in np.split(members[order], breaks):
            if len(part) >= min_meters:
                groups.append(np.sort(part))
    return groups


def plane_coordinates(points_m, normal):
    """(N, 2) coordinates of ``points_m`` in the plane normal to ``normal``, each axis mapped to
    [-1, 1] over the points' extent (the Legendre basis is well conditioned there)."""
    points_m = np.asarray(points_m, float)
    nrm = np.asarray(normal, float) / np.linalg.norm(normal)
    helper = np.array([1.0, 0.0, 0.0]) if abs(nrm[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t = np.cross(nrm, helper)
    t /= np.linalg.norm(t)
    b = np.cross(nrm, t)
    uv = np.stack([points_m @ t, points_m @ b], axis=1)
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    half = np.where(hi > lo, 0.5 * (hi - lo), 1.0)
    return (uv - 0.5 * (hi + lo)) / half, (lo, hi, t, b)


def to_plane(points_m, frame):
    """Coordinates of more points in the frame ``plane_coordinates`` returned (may fall outside [-1, 1])."""
    lo, hi, t, b = frame
    uv = np.stack([np.asarray(points_m, float) @ t, np.asarray(points_m, float) @ b], axis=1)
    half = np.where(hi > lo, 0.5 * (hi - lo), 1.0)
    return (uv - 0.5 * (hi + lo)) / half


def polynomial_basis(uv, degree):
    """(N, P): Legendre products P_i(u) P_j(v), i + j <= ``degree`` (P = (d + 1)(d + 2) / 2)."""
    from numpy.polynomial import legendre

    lu = legendre.legvander(uv[:, 0], degree)
    lv = legendre.legvander(uv[:, 1], degree)
    return np.stack([lu[:, i] * lv[:, j] for i in range(degree + 1) for j in range(degree + 1 - i)], axis=1)


# --- the fit --------------------------------------------------------------------------------------

@dataclass
class FieldFit:
    """A fitted field: coefficients (P, C) for C value columns and their covariance (C, P, P)."""
    degree: int
    coef: np.ndarray
    cov: np.ndarray
    loo_rms: float          #: leave-one-out RMS residual of column 0 (units of the values)
    meters: int

    def predict(self, uv):
        """(mean (M, C), standard error (M, C)) of the field at plane coordinates ``uv``."""
        a = polynomial_basis(np.asarray(uv, float), self.degree)
        mean = a @ self.coef
        var = np.einsum("mp,cpq,mq->mc", a, self.cov, a)
        return mean, np.sqrt(np.maximum(var, 0.0))


def fit_field(uv, values, variances, max_degree=MAX_DEGREE, weights=None):
    """Least-squares polynomial field of ``values`` (N, C) at plane coordinates ``uv`` (N, 2).

    ``variances`` (N, C): each meter's own variance of each value (its s.e.^2). The degree is the one
    of 0..``max_degree`` (at most N / ``METERS_PER_PARAMETER`` coefficients) with the smallest
    leave-one-out error of column 0 (the hat-matrix shortcut e_i / (1 - h_ii)); coefficients by
    ordinary least squares, their covariance (A'A)^-1 A' diag(v) A (A'A)^-1 per column.
    ``weights`` (N,): known constants fixed before sampling (a meter's samples: ``fit_blocks``), never
    estimates; then weighted least squares, (A'WA)^-1 A'W y, with covariance
    (A'WA)^-1 A'W diag(v) W A (A'WA)^-1 (still each meter's own variance: right whatever the weights).
    """
    uv = np.asarray(uv, float)
    values = np.asarray(values, float).reshape(len(uv), -1)
    variances = np.asarray(variances, float).reshape(values.shape)
    root_w = np.ones(len(uv)) if weights is None else np.sqrt(np.asarray(weights, float))
    best = None
    for degree in range(max_degree + 1):
        p = (degree + 1) * (degree + 2) // 2
        if p * METERS_PER_PARAMETER > len(uv) and degree > 0:
            break
        a = polynomial_basis(uv, degree)
        q, r = np.linalg.qr(a * root_w[:, None])
        coef = np.linalg.solve(r, q.T @ (values * root_w[:, None]))
        h = np.einsum("np,np->n", q, q)
        resid = values[:, 0] - a @ coef[:, 0]
        loo = float(np.sqrt(np.mean((resid / np.maximum(1.0 - h, 1e-9)) ** 2)))
        if best is None or loo < best[0]:
            best = (loo, degree, a, r, coef)
    loo, degree, a, r, coef = best
    r_inv = np.linalg.inv(r)
    bread = r_inv @ r_inv.T                                  # (A'WA)^-1
    aw = a * root_w[:, None] ** 2
    meat = np.einsum("np,nc,nq->cpq", aw, variances, aw)     # A'W diag(v_c) W A
    cov = np.einsum("pq,cqr,rs->cps", bread, meat, bread)
    return FieldFit(degree=degree, coef=coef, cov=cov, loo_rms=loo, meters=len(uv))


# --- the held-out check ---------------------------------------------------------------------------

def _chi2_quantile(p, dof):
    """Chi-square quantile (Wilson-Hilferty: within ~1 % of the exact one for dof >= 10)."""
    z = NormalDist().inv_cdf(p)
    c = 2.0 / (9.0 * dof)
    return dof * max(1.0 - c + z * np.sqrt(c), 0.0) ** 3


def _solve_q(residuals, variances, level):
    """The tau^2 >= 0 where sum r^2 / (v + tau^2) = ``level`` (0 when already below it)."""
    r2 = np.asarray(residuals, float) ** 2
    v = np.asarray(variances, float)

    def q(t2):
        return float(np.sum(r2 / (v + t2)))

    if q(0.0) <= level:
        return 0.0
    lo, hi = 0.0, max(float(np.max(r2)), 1e-300)
    while q(hi) > level:
        hi *= 4.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if q(mid) > level else (lo, mid)
    return hi


def misfit_upper_bound(residuals, variances, confidence=CONFIDENCE):
    """(tau^2 estimate, tau^2 one-sided upper bound at ``confidence``) of the extra variance of the
    held-out ``residuals`` beyond their known ``variances``: the method-of-moments estimate (Q = H) and
    the Q-profile bound (Q = the chi-square(H) quantile at 1 - ``confidence``)."""
    h = len(residuals)
    estimate = _solve_q(residuals, variances, float(h))
    upper = _solve_q(residuals, variances, _chi2_quantile(1.0 - confidence, h))
    return estimate, upper


@dataclass
class HoldoutCheck:
    """The misfit measured on held-out meters, and whether the field may be used."""
    held_out: int
    misfit: float             #: tau, estimate (units of the values)
    misfit_upper: float       #: tau, upper bound at CONFIDENCE
    z_max: float              #: largest |residual| / sqrt(v + tau_ub^2)
    z_limit: float            #: the outlier test's limit for that
    passed: bool
    reason: str = ""
    flagged: int = 0          #: fitted meters left out where the field does not follow them (local check)


def check_held_out(residuals, variances, min_held_out=MIN_HOLDOUT, confidence=CONFIDENCE, level=OUTLIER_LEVEL):
    """Misfit of a field from held-out meters' ``residuals`` (their own reading - the field) and
    ``variances`` (own s.e.^2 + the field's s.e.^2 there). Fails with too few finite ones, or when
    one departs beyond its noise and the misfit's upper bound (Bonferroni, family-wise ``level``)."""
    residuals = np.asarray(residuals, float)
    variances = np.asarray(variances, float)
    ok = np.isfinite(residuals) & np.isfinite(variances)
    residuals, variances = residuals[ok], variances[ok]
    h = len(residuals)
    if h < min_held_out:
        return HoldoutCheck(h, np.nan, np.nan, np.nan, np.nan, False,
                            f"{h} held-out meters, fewer than the {min_held_out} a misfit bound needs")
    t2, t2_ub = misfit_upper_bound(residuals, variances, confidence)
    z = np.abs(residuals) / np.sqrt(variances + t2_ub)
    z_max = float(np.max(z)) if h else 0.0
    limit = NormalDist().inv_cdf(1.0 - level / (2.0 * h))
    if z_max > limit:
        return HoldoutCheck(h, float(np.sqrt(t2)), float(np.sqrt(t2_ub)), z_max, limit, False,
                            f"a held-out meter departs from the field by {z_max:.1f} sigma (limit {limit:.1f}): "
                            "a feature the smooth field cannot follow")
    return HoldoutCheck(h, float(np.sqrt(t2)), float(np.sqrt(t2_ub)), z_max, limit, True)


def choose_held_out(count, seed=0):
    """Sorted indices (of ``count`` meters) to hold out: ``HOLDOUT_FRACTION`` of them within
    [MIN_HOLDOUT, MAX_HOLDOUT], drawn at random (seeded), so their misfit is the meters' mean one."""
    h = int(np.clip(np.ceil(HOLDOUT_FRACTION * count), MIN_HOLDOUT, MAX_HOLDOUT))
    h = min(h, count)
    return np.sort(np.random.default_rng(1_000_003 + int(seed)).choice(count, h, replace=False))


def fit_blocks(points_m, normals, groups, count):
    """(count,) blocks (at ``FIT_SPP``) each group's fitted meters take: proportional to their leverage
    h_i in a degree-``LEVERAGE_DEGREE`` fit over the group's fitted meters (the diagonal of the hat
    matrix; max(``FIT_MIN_BLOCKS``, ``FIT_GROUP_BLOCKS`` / fitted meters) blocks at the median h),
    rounded, within [``FIT_MIN_BLOCKS``, ``FIT_MAX_BLOCKS``].

    Why: a fitted value's variance is about h_i x its meter's own variance, and h_i is 5-7x the median
    near a group's edges and corners (a polynomial leans on few meters there); samples in proportion
    to h_i even the field's error out, so edge meters are not the ones that miss the target and are
    read again. Small groups take more at every meter (``FIT_GROUP_BLOCKS``). The design depends on
    the meters' places only, never on their values: the fit weighs each meter by its samples, known
    before sampling (``fit_field``'s weights), and its covariance uses each meter's own variance."""
    blocks = np.zeros(count, int)
    for g in groups:
        uv, _frame = plane_coordinates(points_m[g.fitted], normals[g.fitted[0]])
        degree = LEVERAGE_DEGREE
        while degree > 0 and (degree + 1) * (degree + 2) // 2 * METERS_PER_PARAMETER > len(uv):
            degree -= 1
        q, _r = np.linalg.qr(polynomial_basis(uv, degree))
        h = np.einsum("np,np->n", q, q)
        ratio = h / np.median(h) if degree > 0 else np.ones(len(h))
        base = max(float(FIT_MIN_BLOCKS), FIT_GROUP_BLOCKS / len(uv))
        blocks[g.fitted] = np.clip(np.round(base * ratio), FIT_MIN_BLOCKS, FIT_MAX_BLOCKS)
    return blocks


@dataclass
class PooledGroup:
    """One pooled plane: which meters were fitted and held out, the fit and the check."""
    fitted: np.ndarray
    held_out: np.ndarray
    fit: FieldFit = None
    check: HoldoutCheck = None
    pooled: np.ndarray = None     #: of ``fitted``, those whose pooled error meets the target


def local_misfit(uv, z2, neighbours=LOCAL_NEIGHBOURS, level=OUTLIER_LEVEL):
    """Where the field does not follow the fitted meters themselves: (flagged (N,) bool, radius (N,)).

    ``z2`` (N,): each fitted meter's squared standardised leave-one-out residual. Around every meter,
    Q = the sum of z2 over its ``neighbours`` nearest fitted meters (itself included) is chi-square
    with that many degrees of freedom where the field is right; it is flagged above the chi-square
    quantile at 1 - ``level`` / N (Bonferroni over the meters). ``radius``: the distance to its
    farthest neighbour (the flagged region is the union of those discs)."""
    n = len(uv)
    k = min(neighbours, n)
    z2 = np.asarray(z2, float)
    q, radius = np.empty(n), np.empty(n)
    for lo in range(0, n, _CHUNK):  # rows of the distance matrix a chunk at a time (memory ~ _CHUNK x N)
        d = np.linalg.norm(uv[lo:lo + _CHUNK, None, :] - uv[None, :, :], axis=2)
        near = np.argpartition(d, k - 1, axis=1)[:, :k]
        q[lo:lo + _CHUNK] = np.sum(z2[near], axis=1)
        radius[lo:lo + _CHUNK] = np.take_along_axis(d, near, axis=1).max(axis=1)
    return q > _chi2_quantile(1.0 - level / n, k), radius


#: Rows of a distance matrix computed at once (512 x 10,000 meters: 40 MB).
_CHUNK = 512


def _in_region(uv_query, uv, flagged, radius):
    """(M,) bool: query points inside a flagged meter's disc."""
    out = np.zeros(len(uv_query), bool)
    if not np.any(flagged):
        return out
    centres, radii = uv[flagged], radius[flagged]
    for lo in range(0, len(uv_query), _CHUNK):
        d = np.linalg.norm(uv_query[lo:lo + _CHUNK, None, :] - centres[None, :, :], axis=2)
        out[lo:lo + _CHUNK] = np.any(d <= radii[None, :], axis=1)
    return out


def _standardised_loo(fit, uv, values, variances, weights=None):
    """Squared leave-one-out residuals of column 0 over their variance (v / (1 - h); h of the weighted
    fit ``fit_field`` made)."""
    a = polynomial_basis(uv, fit.degree)
    q, _r = np.linalg.qr(a if weights is None else a * np.sqrt(np.asarray(weights, float))[:, None])
    h = np.minimum(np.einsum("np,np->n", q, q), 1.0 - 1e-9)
    e = (values[:, 0] - a @ fit.coef[:, 0]) / (1.0 - h)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(variances[:, 0] > 0, e ** 2 * (1.0 - h) / variances[:, 0], 0.0)


def pooled_estimate(points_m, normal, fit_values, fit_variances, held_points_m, held_values, held_variances,
                    max_degree=MAX_DEGREE, fit_weights=None):
    """The field over the fitted meters, its local check on them and its misfit on the held-out ones.

    ``fit_values`` / ``fit_variances`` (N, C) at ``points_m``; ``held_values`` / ``held_variances``
    (H, C) at ``held_points_m`` (sampled independently of the fitted meters). Column 0 is the one
    whose misfit is measured (the scalar reading). The field is fitted once; where its own meters
    depart from it beyond their noise (``local_misfit``: a sharp feature) that region is left out,
    the field fitted again without it and held-out meters inside it are not used. Returns (fit,
    check, usable (N,) bool: outside the flagged region, mean (N, C), se (N, C)) where the pooled
    standard error includes the misfit's upper bound (column c's misfit scaled by |mean_c| / |mean_0|:
    the colour of the light does not change within the field's misfit).
    """
    fit_values = np.asarray(fit_values, float).reshape(len(points_m), -1)
    fit_variances = np.asarray(fit_variances, float).reshape(fit_values.shape)
    uv, frame = plane_coordinates(points_m, normal)
    w = None if fit_weights is None else np.asarray(fit_weights, float)
    fit = fit_field(uv, fit_values, fit_variances, max_degree, w)
    flagged, radius = local_misfit(uv, _standardised_loo(fit, uv, fit_values, fit_variances, w))
    usable = ~_in_region(uv, uv, flagged, radius)
    if not usable.all() and usable.sum() >= METERS_PER_PARAMETER:
        fit = fit_field(uv[usable], fit_values[usable], fit_variances[usable], max_degree,
                        None if w is None else w[usable])
    mean, se = fit.predict(uv)
    held_uv = to_plane(held_points_m, frame)
    held_mean, held_se = fit.predict(held_uv)
    held_values = np.asarray(held_values, float).reshape(len(held_mean), -1)
    held_variances = np.asarray(held_variances, float).reshape(held_values.shape)
    outside = ~_in_region(held_uv, uv, flagged, radius)
    check = check_held_out((held_values[:, 0] - held_mean[:, 0])[outside],
                           (held_variances[:, 0] + held_se[:, 0] ** 2)[outside])
    check.flagged = int(np.count_nonzero(~usable))
    tau = check.misfit_upper if np.isfinite(check.misfit_upper) else np.inf
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(mean[:, :1] != 0, np.abs(mean) / np.abs(mean[:, :1]), 1.0)
    total_se = np.sqrt(se ** 2 + (tau * share) ** 2)
    return fit, check, usable, mean, total_se


# --- the measurement ------------------------------------------------------------------------------

@dataclass
class PooledTally:
    """What ``measure.render.adaptive`` reads of an allocation's tally, for a pooled measurement."""
    count: int
    mean: np.ndarray
    std_error: np.ndarray
    mean_rgb: np.ndarray
    std_error_rgb: np.ndarray
    rounds: list = field(default_factory=list)


@dataclass
class PooledResult:
    """An ``allocation.AllocationResult`` look-alike, with the pooled meters and the groups' checks."""
    tally: PooledTally
    rounds: int
    seconds: float
    reached: bool
    stopped: str
    samples: np.ndarray
    pooled: np.ndarray                 #: (N,) bool: the reading is the fitted field's
    groups: list = field(default_factory=list)


def _subset_bake(bake, count, idx, rider=None, ready=None):
    """``bake`` restricted to the meters ``idx``: blocks and the returned meter indices in their numbering.

    ``rider``: (other meters, their blocks, spp, a dict): a bake at that spp bakes those blocks too, in
    the same Cycles bake (one scene sync fewer), and leaves their texels in the dict. ``ready``: such a
    dict; the first call asking for exactly its spp and blocks gets its texels instead of a bake."""
    local = np.full(count, -1)
    local[idx] = np.arange(len(idx))

    def sub(spp, blocks):
        if ready and ready["spp"] == spp and np.array_equal(ready["blocks"], blocks):
            texels = ready.pop("texels")
            ready.clear()
            return texels
        full = np.zeros(count, int)
        full[idx] = blocks
        riding = rider is not None and rider[2] == spp and "texels" not in rider[3]
        if riding:
            full[rider[0]] = rider[1]
        meter, scalar, rgb = bake(spp, full)
        meter = np.asarray(meter, int)
        if riding:
            theirs = np.full(count, -1)
            theirs[rider[0]] = np.arange(len(rider[0]))
            out = theirs[meter] >= 0
            rider[3].update(spp=spp, blocks=np.asarray(rider[1]).copy(),
                            texels=(theirs[meter[out]], np.asarray(scalar)[out], np.asarray(rgb)[out]))
            meter, scalar, rgb = meter[~out], np.asarray(scalar)[~out], np.asarray(rgb)[~out]
        return local[meter], scalar, rgb

    return sub


def _pick(value, idx):
    if value is None or np.ndim(value) == 0:
        return value
    return np.asarray(value)[idx]


def allocate_pooled(bake, count, *, points_m, normals, target, keys=None, offset=0.0, seed=0,
                    min_meters=None, progress=None, may_be_lit=None, min_samples=None,
                    max_samples=allocation.MAX_SAMPLES_PER_METER, clock=None, table_patterns=0, target_abs=None, stop_dark=False):
    """``allocation.allocate`` in target mode for many meters, pooling the rendered part of groups
    of at least ``min_meters`` (None: ``POOL_MIN_METERS``) meters on one plane (``plane_groups``;
    ``keys`` per meter: what is rendered there, e.g. the lights excluded from its sensor; meters with
    ``min_samples`` > 0 are not pooled: their light comes by rare paths).

    Stages, each through ``bake`` restricted to its meters: (1) the fitted meters, ``fit_blocks`` each at
    ``FIT_SPP`` (128-1024 samples), one bake; (2) the held-out meters and every
    meter not pooled, each to ``target`` on its own; (3) per group the field and its held-out check
    (``pooled_estimate``); (4) the fitted meters whose pooled error misses the target (or the whole
    group, when its check fails) sampled on their own to ``target``. Returns a :class:`PooledResult`.
    ``target_abs`` (N,) or None: the absolute error floor of the meters read on their own
    (``allocation.allocate``); the pooled field keeps the relative target.
    """
    import time

    clock = clock or time.perf_counter
    started = clock()
    min_meters = POOL_MIN_METERS if min_meters is None else min_meters
    points_m = np.asarray(points_m, float)
    normals = np.asarray(normals, float)
    offset = np.broadcast_to(np.asarray(offset, float), (count,)).copy()
    floors = np.zeros(count) if min_samples is None else np.asarray(min_samples, float)
    groups = [PooledGroup(fitted=g[np.setdiff1d(np.arange(len(g)), h)], held_out=g[h])
              for g, h in ((g, choose_held_out(len(g), seed + i))
                           for i, g in enumerate(plane_groups(points_m, normals, keys, floors <= 0, min_meters)))]
    fitted = np.sort(np.concatenate([g.fitted for g in groups])) if groups else np.zeros(0, int)
    own = np.setdiff1d(np.arange(count), fitted)
    mean4 = np.zeros((count, 4))
    se4 = np.zeros((count, 4))
    samples = np.zeros(count)
    pooled = np.zeros(count, bool)
    rounds = []
    stopped = []

    def stage(idx, lo, hi, rider=None, ready=None, **kwargs):
        def report(fraction, seconds_left):
            if progress is not None:
                progress(lo + (hi - lo) * fraction, seconds_left)

        result = allocation.allocate(_subset_bake(bake, count, idx, rider, ready), len(idx), progress=report,
                                     max_samples=max_samples, **kwargs)
        tally_into(idx, result.tally, result.stopped)
        return result

    def tally_into(idx, t, stop):
        """A stage's tally ``t`` over the meters ``idx``, into the whole measurement's arrays and round log."""
        mean4[idx, 0], mean4[idx, 1:] = t.mean, t.mean_rgb
        se4[idx, 0], se4[idx, 1:] = t.std_error, t.std_error_rgb
        samples[idx] = t.n
        for r in t.rounds:
            texels = np.zeros(count, int)
            texels[idx] = r["texels"]
            rounds.append({"spp": r["spp"], "texels": texels})
        stopped.append(stop)

    def fitted_stage(idx, blocks, lo, hi, rider=None):
        """The fitted meters' samples: ``blocks`` (len(idx),) each at ``FIT_SPP``, one bake (allocation's
        fixed budget, but a number of blocks per meter: ``fit_blocks``)."""
        if progress is not None:
            progress(lo, 0.0)
        meter, scalar, rgb = _subset_bake(bake, count, idx, rider)(FIT_SPP, np.asarray(blocks, int))
        t = allocation.MeterTally(len(idx))
        t.add(meter, FIT_SPP, scalar, rgb)
        tally_into(idx, t, "fixed budget")
        if progress is not None:
            progress(hi, 0.0)
        return FIT_SPP

    def per_meter(idx, lo, hi, ready=None):
        return stage(idx, lo, hi, ready=ready, target=target, offset=offset[idx],
                     may_be_lit=_pick(may_be_lit, idx), min_samples=None if min_samples is None else floors[idx],
                     table_patterns=table_patterns, target_abs=_pick(target_abs, idx), stop_dark=stop_dark)  # meters read on their own: allocation.TABLE_PATTERNS

    # The pilot of the meters read on their own (held out, or in no group) rides in the fitted meters' bake
    # when it is that bake's spp (allocate's first round: PILOT_SPP, pilot_blocks each); else it is baked apart.
    pilot = {}
    rider = (own, np.full(len(own), allocation.pilot_blocks(len(own))), allocation.PILOT_SPP, pilot)
    pilot_spp = 0
    if fitted.size:
        pilot_spp = fitted_stage(fitted, fit_blocks(points_m, normals, groups, count)[fitted], 0.0, 0.25,
                                 rider=rider if own.size else None)
    reached = True
    if own.size:
        reached = per_meter(own, 0.25, 0.75, ready=pilot).reached
    fallback = []
    for g in groups:
        values, variances = mean4[g.fitted], se4[g.fitted] ** 2
        dark = allocation.dark_meters(PooledTally(len(g.fitted), values[:, 0], np.sqrt(variances[:, 0]),
                                                  values[:, 1:], np.sqrt(variances[:, 1:])),
                                      _pick(may_be_lit, g.fitted))
        # Per-sample relative variance of the pilot: light by rare paths is neither smooth from meter to
        # meter nor safely averaged over one bake's texels (Cycles' sampler table: allocation.py).
        with np.errstate(divide="ignore", invalid="ignore"):
            spread = variances[:, 0] * samples[g.fitted] / values[:, 0] ** 2
        keep = ~dark & ~(spread >= RARE_PATH_SPREAD)  # a pilot that found no light says nothing of the field
        use = g.fitted[keep]
        # Held-out meters lit by rare paths (their own reading's spread) check nothing the field is used for.
        with np.errstate(divide="ignore", invalid="ignore"):
            held_spread = se4[g.held_out, 0] ** 2 * samples[g.held_out] / mean4[g.held_out, 0] ** 2
        held = g.held_out[~(held_spread >= RARE_PATH_SPREAD) & (mean4[g.held_out, 0] != 0)]
        if len(use) < MIN_FITTED:
            g.check = HoldoutCheck(len(held), np.nan, np.nan, np.nan, np.nan, False,
                                   f"{len(use)} fitted meters with smooth light, fewer than the {MIN_FITTED} a "
                                   "field needs")
            g.pooled = np.zeros(0, int)
            fallback.append(g.fitted)
            continue
        g.fit, g.check, usable, mean, se = pooled_estimate(
            points_m[use], normals[g.fitted[0]], values[keep], variances[keep], points_m[held],
            mean4[held], se4[held] ** 2, fit_weights=samples[use])  # weights: the design's samples
        if table_patterns:
            # The field averages texels of one bake, so it converges to the mean of Cycles' sampler table,
            # not below that table's floor (allocation.MeterTally.table_floor): sqrt(per-sample variance /
            # (table size x patterns)), each meter's own pilot, at the Monte Carlo rate (QMC: less).
            floor = np.sqrt(variances[keep] * samples[use][:, None]
                            / (allocation.table_size(pilot_spp) * table_patterns))
            se = np.sqrt(se ** 2 + floor ** 2)
        total = np.abs(mean[:, 0] + offset[use])
        ok = g.check.passed & usable & np.isfinite(se[:, 0]) & (se[:, 0] <= target * total)
        g.pooled = use[ok]
        mean4[g.pooled], se4[g.pooled] = mean[ok], se[ok]
        pooled[g.pooled] = True
        fallback.append(np.setdiff1d(g.fitted, g.pooled))
    fallback = np.sort(np.concatenate(fallback)) if fallback else np.zeros(0, int)
    if fallback.size:
        reached = per_meter(fallback, 0.75, 1.0).reached and reached
    if progress is not None:
        progress(1.0, 0.0)
    tally = PooledTally(count, mean4[:, 0], se4[:, 0], mean4[:, 1:], se4[:, 1:], rounds)
    return PooledResult(tally=tally, rounds=len(rounds), seconds=clock() - started, reached=bool(reached),
                        stopped="target reached" if reached else "; ".join(s for s in stopped if s != "target reached"),
                        samples=samples, pooled=pooled, groups=groups)

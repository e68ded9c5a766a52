"""Monte Carlo error statistics for rendered measurements (batch means, Student-t intervals).

References
----------
- G. S. Fishman, *Monte Carlo: Concepts, Algorithms, and Applications* (1996), sec. 6.6 batch means.
- W. S. Gosset ("Student"), "The probable error of a mean", Biometrika 6 (1908).
- M. Abramowitz, I. A. Stegun, *Handbook of Mathematical Functions* (1964), 26.7.3-26.7.5 (Student-t
  distribution as finite sums; Cornish-Fisher expansion of its quantile).
- W. T. Shaw, "Sampling Student's T distribution - use of the inverse cumulative distribution
  function", J. Computational Finance 9(4) (2006), sec. 3 (closed-form quantiles for 1, 2, 4 degrees
  of freedom).
"""

import functools
import math

import numpy as np

from ..units import as_finite_array, check_positive

__all__ = ["batch_mean", "relative_standard_error", "t_half_width_95", "samples_for_target", "t_quantile_975"]

# Phi^{-1}(0.975), the standard normal 97.5 % quantile (A&S table 26.5; 16 significant digits).
_Z975 = 1.959963984540054
_LARGE_DF = 2000  # from here on the Cornish-Fisher series (error < 1e-16 relative) replaces Newton


def _t_abs_cdf(t, df):
    """P(|T| <= t) for Student's T with integer ``df`` >= 1, t >= 0 (A&S 26.7.3, 26.7.4; exact sums)."""
    theta = math.atan(t / math.sqrt(df))
    s, c = math.sin(theta), math.cos(theta)
    c2 = c * c
    if df % 2 == 0:
        # sin(theta) (1 + 1/2 c^2 + 1*3/(2*4) c^4 + ... + 1*3...(df-3)/(2*4...(df-2)) c^(df-2))
        term, total = 1.0, 1.0
        for k in range(1, df // 2):
            term *= c2 * (2 * k - 1) / (2 * k)
            total += term
        return s * total
    # 2/pi (theta + sin(theta) (c + 2/3 c^3 + ... + 2*4...(df-3)/(1*3...(df-2)) c^(df-2)))
    if df == 1:
        return 2.0 / math.pi * theta
    term, total = c, c
    for k in range(1, (df - 1) // 2):
        term *= c2 * (2 * k) / (2 * k + 1)
        total += term
    return 2.0 / math.pi * (theta + s * total)


def _t_pdf(t, df):
    """Student-t density at t (only Newton's step size uses it)."""
    log_c = math.lgamma((df + 1) / 2) - math.lgamma(df / 2) - 0.5 * math.log(df * math.pi)
    return math.exp(log_c - (df + 1) / 2 * math.log1p(t * t / df))


def _cornish_fisher_975(df):
    """t_{0.975, df} ~ z + g1/df + ... + g4/df^4 (A&S 26.7.5), z the normal quantile."""
    z = _Z975
    g1 = (z ** 3 + z) / 4
    g2 = (5 * z ** 5 + 16 * z ** 3 + 3 * z) / 96
    g3 = (3 * z ** 7 + 19 * z ** 5 + 17 * z ** 3 - 15 * z) / 384
    g4 = (79 * z ** 9 + 776 * z ** 7 + 1482 * z ** 5 - 1920 * z ** 3 - 945 * z) / 92160
    v = float(df)
    return z + (g1 + (g2 + (g3 + g4 / v) / v) / v) / v


@functools.lru_cache(maxsize=1024)
def t_quantile_975(df):
    """t_{0.975, df}: the 97.5 % quantile of Student's t with ``df`` degrees of freedom (dimensionless).

    The half-width of the two-sided 95 % confidence interval of a mean is t_{0.975, K-1} s / sqrt(K).
    Exact closed forms for df = 1, 2, 4 (Shaw 2006); Newton's method with bisection safeguard on the
    exact finite-sum CDF (A&S 26.7.3/26.7.4) for other df < 2000; the Cornish-Fisher series in 1/df to
    4th order (A&S 26.7.5) from 2000 on (truncation < 1e-16 relative there). Measured relative
    difference from scipy.stats.t.ppf: < 2e-14 for df = 1..2000, 1e3, 1e6 (tests/test_radiometry_stats.py).

    Parameters
    ----------
    df : int
        Degrees of freedom, an integer >= 1.

    Raises
    ------
    ValueError
        df is not an integer >= 1.

    References
    ----------
    A&S (1964) 26.7.3-26.7.5; Shaw (2006) sec. 3 (module docstring).
    """
    if isinstance(df, bool) or not float(df).is_integer() or df < 1:
        raise ValueError(f"degrees of freedom must be an integer >= 1, got {df!r}")
    df = int(df)
    p = 0.975
    if df == 1:  # Cauchy: tan(pi (p - 1/2))
        return math.tan(math.pi * (p - 0.5))
    if df == 2:  # (2p - 1) / sqrt(2 p (1 - p))
        return (2 * p - 1) / math.sqrt(2 * p * (1 - p))
    if df == 4:  # 2 sqrt(q - 1), q = cos(arccos(sqrt(a)) / 3) / sqrt(a), a = 4 p (1 - p)
        a = 4 * p * (1 - p)
        q = math.cos(math.acos(math.sqrt(a)) / 3) / math.sqrt(a)
        return 2 * math.sqrt(q - 1)
    if df >= _LARGE_DF:
        return _cornish_fisher_975(df)
    # P(|T| <= t) = 0.95 has its root in [z, t_{0.975, 2}] for df >= 3; safeguarded Newton
    lo, hi = _Z975, 4.31
    t = min(max(_cornish_fisher_975(df), lo), hi)
    for _ in range(100):
        g = _t_abs_cdf(t, df) - 0.95
        if g > 0:
            hi = t
        else:
            lo = t
        step = g / (2.0 * _t_pdf(t, df))
        t_new = t - step
        if not lo < t_new < hi:
            t_new = 0.5 * (lo + hi)
        if abs(t_new - t) <= 4e-16 * t:
            return t_new
        t = t_new
    return t


def batch_mean(values, axis=0):
    """Mean and standard error of the mean from K >= 2 independent estimates along ``axis``.

    Returns (mean, std_error) with std_error = s / sqrt(K), s the unbiased sample deviation.
    """
    v = as_finite_array(values, "values")
    k = v.shape[axis]
    if k < 2:
        raise ValueError("batch_mean needs at least 2 independent estimates")
    return np.mean(v, axis=axis), np.std(v, axis=axis, ddof=1) / np.sqrt(k)


def relative_standard_error(values, axis=0):
    """std_error / |mean| (inf where the mean is 0)."""
    mean, se = batch_mean(values, axis)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(mean != 0.0, se / np.abs(mean), np.inf)


def t_half_width_95(values, axis=0):
    """Half-width of the two-sided 95 % Student-t confidence interval of the mean."""
    v = np.asarray(values, dtype=np.float64)
    _, se = batch_mean(v, axis)
    return t_quantile_975(v.shape[axis] - 1) * se


def samples_for_target(rel_err_now, samples_now, target):
    """Samples needed for a target relative error, assuming error ~ 1/sqrt(N): ceil(N (e/t)^2)."""
    e = check_positive(rel_err_now, "rel_err_now")
    n = check_positive(samples_now, "samples_now")
    t = check_positive(target, "target")
    return np.ceil(n * (e / t) ** 2).astype(np.int64)

"""Monte Carlo error statistics for rendered measurements (batch means, Student-t intervals).

References
----------
- G. S. Fishman, *Monte Carlo: Concepts, Algorithms, and Applications* (1996), sec. 6.6 batch means.
- W. S. Gosset ("Student"), "The probable error of a mean", Biometrika 6 (1908).
"""

import numpy as np
from scipy import stats as _scipy_stats

from .units import as_finite_array, check_positive

__all__ = ["batch_mean", "relative_standard_error", "t_half_width_95", "samples_for_target"]


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
    return _scipy_stats.t.ppf(0.975, v.shape[axis] - 1) * se


def samples_for_target(rel_err_now, samples_now, target):
    """Samples needed for a target relative error, assuming error ~ 1/sqrt(N): ceil(N (e/t)^2)."""
    e = check_positive(rel_err_now, "rel_err_now")
    n = check_positive(samples_now, "samples_now")
    t = check_positive(target, "target")
    return np.ceil(n * (e / t) ** 2).astype(np.int64)

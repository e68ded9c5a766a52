"""The speed/accuracy trade of Monte Carlo measurements: fit error vs samples and time (pure numpy).

A Monte Carlo estimate's error falls as N^(-1/2) with the sample count N (central limit theorem);
time grows as t = t0 + c N (fixed scene-sync cost plus per-sample cost). Fitting log(error) on
log(N) gives the slope (expected -1/2) and lets one invert for the N and the seconds a target error
needs.

References
----------
- M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering* (4th ed., 2023), sec. 2.1.4
  (Monte Carlo error O(N^-1/2)) and sec. 2.1.1 (efficiency = 1 / (variance x time)).
- N. R. Draper, H. Smith, *Applied Regression Analysis* (3rd ed., 1998), sec. 1.4 (slope s.e.).
"""

from dataclasses import dataclass

import numpy as np

from ..metrics.laws import fit_power_law
from ..units import as_finite_array

__all__ = ["ConvergenceFit", "fit_convergence", "rms_relative_error"]


@dataclass(frozen=True)
class ConvergenceFit:
    """error = A N^slope and error = B t^time_slope on log-log axes; t = t0 + c N.

    Attributes
    ----------
    slope, slope_se : exponent of error vs samples per estimate (dimensionless, expect -0.5)
    prefactor : error at N = 1 (fraction)
    time_slope, time_slope_se : exponent of error vs seconds
    time_prefactor : error at t = 1 s (fraction); inf or 0 where the wall times barely varied (then
        :meth:`seconds_for_by_time` is nan: not measured)
    t0_s : fixed cost per measurement (s); c_s_per_sample : cost per sample (s)
    """

    slope: float
    slope_se: float
    prefactor: float
    time_slope: float
    time_slope_se: float
    time_prefactor: float
    t0_s: float
    c_s_per_sample: float

    def samples_for(self, target):
        """Samples per estimate for a relative error ``target`` (fraction), from the samples fit."""
        t = float(target)
        if not t > 0:
            raise ValueError("target error must be > 0")
        if self.slope >= 0:
            return float("inf")  # no convergence measured: no sample count reaches the target
        return _solve(t, self.prefactor, self.slope)

    def seconds_for(self, target):
        """Seconds for a relative error ``target``: t0 + c N(target) from the linear time model."""
        n = self.samples_for(target)
        return float(self.t0_s + self.c_s_per_sample * n) if np.isfinite(n) else n

    def seconds_for_by_time(self, target):
        """Seconds for a relative error ``target`` (fraction) from the fit of log error vs log seconds.

        Meaningful where the per-sample cost dominates; with a large fixed cost t0 the measured
        slope is flatter than -1/2 and this extrapolation is rough (prefer :meth:`seconds_for`).
        """
        t = float(target)
        if not t > 0:
            raise ValueError("target error must be > 0")
        if not self.time_slope < 0:
            return float("inf")
        return _solve(t, self.time_prefactor, self.time_slope)

    def to_dict(self):
        return {k: float(v) for k, v in self.__dict__.items()}


def _solve(target, prefactor, slope):
    """x where prefactor * x**slope = target (slope < 0); nan where the fit is too steep for its prefactor
    to be a float (inf or 0: x barely varied), so it cannot be extrapolated."""
    if not 0.0 < prefactor < float("inf"):
        return float("nan")
    with np.errstate(over="ignore"):
        return float(np.exp((np.log(target) - np.log(prefactor)) / slope))


def rms_relative_error(estimates, reference, axis=-1):
    """Root mean square of (estimate - reference) / reference over ``axis`` (fraction)."""
    e = as_finite_array(estimates, "estimates")
    r = as_finite_array(reference, "reference")
    if np.any(r == 0):
        raise ValueError("a zero reference value has no relative error")
    return np.sqrt(np.mean(((e - r) / r) ** 2, axis=axis))


def fit_convergence(samples, seconds, errors):
    """Fit error vs samples (log-log), error vs seconds (log-log) and t = t0 + c N (linear).

    Parameters
    ----------
    samples : (n,) samples per estimate, > 0
    seconds : (n,) wall time of each measurement, s, > 0
    errors : (n,) relative errors (fractions), > 0

    Returns
    -------
    ConvergenceFit
    """
    n = as_finite_array(samples, "samples").ravel()
    t = as_finite_array(seconds, "seconds").ravel()
    e = as_finite_array(errors, "errors").ravel()
    if not (n.size == t.size == e.size) or n.size < 2:
        raise ValueError("need at least 2 (samples, seconds, error) triples of equal length")
    by_n = fit_power_law(n, e)
    by_t = fit_power_law(t, e)
    a = np.c_[np.ones_like(n), n]
    (t0, c), *_ = np.linalg.lstsq(a, t, rcond=None)
    if c <= 0:  # time did not grow with samples (noise): fall back to proportional time
        t0, c = 0.0, float(np.sum(t * n) / np.sum(n * n))
    return ConvergenceFit(by_n.exponent, by_n.exponent_se, by_n.prefactor, by_t.exponent, by_t.exponent_se,
                          by_t.prefactor, float(max(t0, 0.0)), float(c))

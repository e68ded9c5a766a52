"""Checks of the inverse-square and cosine laws on measured irradiance (pure numpy, no bpy).

* Inverse square: E(d) = I / d^2 for a source seen from distance d along a direction where its
  radiant intensity is I; the exponent of log E vs log d is -2 in the far field. An extended source
  deviates at short range; the *near-field limit* is the distance beyond which the relative
  deviation stays under a tolerance (1 % by default). The photometric "five-times rule" says the
  law holds to about 1 % beyond five times the source's largest dimension.
* Cosine law: E(theta) = E(0) cos(theta) when the receiver tilts by theta away from the source,
  exactly so while the whole source stays above the receiver's horizon (the projected solid angle
  of anything fully above the horizon is linear in the normal).

References
----------
- P. Hanrahan, CS348B lecture 4 "Radiometry" (2011): isotropic point source E = Phi cos(theta) /
  (4 pi r^2); Lambert's cosine law E' = E cos(theta).
- J. H. Lambert, *Photometria* (1760): cosine law.
- IES Lighting Handbook (10th ed., 2011), ch. 9 "Photometry": five-times rule (the inverse-square
  law is within about 1 % at distances of at least five times the largest source dimension);
  W. R. McCluney, *Introduction to Radiometry and Photometry* (2nd ed., 2014), sec. 3.6.
- Least-squares slope and its standard error: N. R. Draper, H. Smith, *Applied Regression
  Analysis* (3rd ed., 1998), sec. 1.4.
"""

from dataclasses import dataclass

import numpy as np

from ..units import as_finite_array

__all__ = ["PowerLawFit", "fit_power_law", "near_field_limit", "five_times_rule",
           "relative_deviation", "cosine_law_analysis", "horizon_onset_deg", "within_tolerance",
           "DEFAULT_TOLERANCE", "DEFAULT_Z"]

#: Default tolerance on the relative deviation from a law (fraction, 1 %).
DEFAULT_TOLERANCE = 0.01
#: Standard errors a measured deviation may exceed the tolerance by before it counts (about
#: 99.7 % two-sided coverage for a normal estimate).
DEFAULT_Z = 3.0


@dataclass(frozen=True)
class PowerLawFit:
    """y = prefactor * x**exponent fitted by least squares on log y vs log x.

    Attributes
    ----------
    exponent : float (dimensionless)
    exponent_se : float, standard error of the exponent: the larger of the residual-based value
        (Draper & Smith eq. 1.4.5; 0 for n = 2 or a perfect fit) and the one propagated from the
        points' own relative standard errors.
    prefactor : float, in the units of y times x**-exponent: y at x = 1; inf or 0 where that value is beyond
        a float (x far from 1 and barely varying: a line too steep to extrapolate)
    residual_rms : float, RMS of the log residuals (dimensionless)
    count : int, number of points used
    """

    exponent: float
    exponent_se: float
    prefactor: float
    residual_rms: float
    count: int

    def to_dict(self):
        return {k: float(v) if k != "count" else int(v) for k, v in self.__dict__.items()}


def fit_power_law(x, y, rel_std_error=None):
    """Fit y = A x**b on log-log axes by ordinary least squares.

    Parameters
    ----------
    x, y : array_like, shape (n,), n >= 2, all > 0
    rel_std_error : array_like, shape (n,), optional
        Relative standard error of each y (the standard error of log y to first order).

    Returns
    -------
    PowerLawFit

    Raises
    ------
    ValueError
        Fewer than 2 points, non-positive or non-finite values, or all x equal.
    """
    x = as_finite_array(x, "x").ravel()
    y = as_finite_array(y, "y").ravel()
    if x.shape != y.shape:
        raise ValueError(f"x and y differ in length ({x.size} vs {y.size})")
    if x.size < 2:
        raise ValueError("a power-law fit needs at least 2 points")
    if np.any(x <= 0) or np.any(y <= 0):
        raise ValueError("a log-log fit needs x > 0 and y > 0 (a zero reading cannot be fitted)")
    lx, ly = np.log(x), np.log(y)
    mx = lx.mean()
    sxx = np.sum((lx - mx) ** 2)
    if sxx == 0.0:
        raise ValueError("all x are equal: the exponent is undefined")
    b = np.sum((lx - mx) * (ly - ly.mean())) / sxx
    a = ly.mean() - b * mx
    resid = ly - (a + b * lx)
    se_resid = np.sqrt(np.sum(resid**2) / (x.size - 2) / sxx) if x.size > 2 else 0.0
    se_meas = 0.0
    if rel_std_error is not None:
        s = as_finite_array(rel_std_error, "rel_std_error").ravel()
        if s.shape != x.shape:
            raise ValueError("rel_std_error must have one value per point")
        c = (lx - mx) / sxx  # b = sum c_i log y_i
        se_meas = float(np.sqrt(np.sum(c**2 * s**2)))
    with np.errstate(over="ignore", under="ignore"):
        # x far from 1 and barely varying (wall times of ~3 s that differ by 0.1 %) gives a steep line whose
        # value at x = 1 is beyond a float: inf or 0, which PowerLawFit.prefactor documents
        prefactor = np.exp(a)
    return PowerLawFit(float(b), float(max(se_resid, se_meas)), float(prefactor),
                       float(np.sqrt(np.mean(resid**2))), int(x.size))


def relative_deviation(measured, predicted):
    """(measured - predicted) / predicted, elementwise; nan where predicted is 0."""
    m = np.asarray(measured, dtype=np.float64)
    p = np.asarray(predicted, dtype=np.float64)
    out = np.full(np.broadcast(m, p).shape, np.nan)
    np.divide(m - p, p, out=out, where=p != 0.0)
    return out


def within_tolerance(deviation, rel_std_error=None, tolerance=DEFAULT_TOLERANCE, z=DEFAULT_Z):
    """True where |deviation| <= tolerance + z * rel_std_error (noise cannot make a point fail).

    ``deviation`` nan (undefined) counts as a failure.
    """
    dev = np.abs(np.asarray(deviation, dtype=np.float64))
    allow = 0.0 if rel_std_error is None else z * np.asarray(rel_std_error, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        return np.where(np.isfinite(dev), dev <= tolerance + allow, False)


def near_field_limit(distances, deviation, rel_std_error=None, tolerance=DEFAULT_TOLERANCE, z=DEFAULT_Z):
    """Smallest distance beyond which every |deviation| stays within tolerance (m).

    The crossing between the last failing distance and the next one is interpolated linearly in
    (log d, log |dev| - log threshold), which is exact for a deviation that falls as a power of d
    (an extended source: |dev| ~ c / d^2 in the far field).

    Parameters
    ----------
    distances : (n,) m, > 0 (any order)
    deviation : (n,) relative deviations (measured - predicted) / predicted
    rel_std_error : (n,), optional, relative standard errors of the measured values
    tolerance : float, fraction
    z : float, standard errors allowed on top of the tolerance

    Returns
    -------
    float
        0.0 when every distance passes; ``inf`` when the farthest distance still fails.
    """
    d = as_finite_array(distances, "distances").ravel()
    dev = np.asarray(deviation, dtype=np.float64).ravel()
    if d.shape != dev.shape or d.size == 0:
        raise ValueError("distances and deviation need the same, non-zero length")
    if np.any(d <= 0):
        raise ValueError("distances must be > 0")
    s = np.zeros_like(d) if rel_std_error is None else np.asarray(rel_std_error, dtype=np.float64).ravel()
    order = np.argsort(d)
    d, dev, s = d[order], dev[order], s[order]
    ok = within_tolerance(dev, s, tolerance, z)
    if ok.all():
        return 0.0
    k = int(np.nonzero(~ok)[0][-1])
    if k == d.size - 1:
        return float("inf")
    thr = tolerance + z * s
    e0, e1 = abs(dev[k]), abs(dev[k + 1])
    if not np.isfinite(e0):
        return float(d[k + 1])
    if e1 > 0.0:
        g0, g1 = np.log(e0 / thr[k]), np.log(e1 / thr[k + 1])
    else:  # an exact zero cannot be put on a log scale: interpolate the excess itself
        g0, g1 = e0 - thr[k], e1 - thr[k + 1]
    t = g0 / (g0 - g1) if g0 != g1 else 1.0
    t = min(max(t, 0.0), 1.0)
    return float(np.exp(np.log(d[k]) + t * (np.log(d[k + 1]) - np.log(d[k]))))


def five_times_rule(source_size, limit):
    """Compare a near-field limit with the photometric five-times rule.

    Parameters
    ----------
    source_size : float, m, largest dimension of the luminous area (0 for a point)
    limit : float, m, near-field limit found (0: none; inf: not reached)

    Returns
    -------
    dict with ``rule_distance`` (5 x size, m), ``limit_in_sizes`` (limit / size, nan for a point)
    and ``rule_holds`` (True when the law holds beyond the rule's distance: limit <= 5 x size).
    """
    size = float(source_size)
    lim = float(limit)
    return {
        "rule_distance": 5.0 * size,
        "limit_in_sizes": lim / size if size > 0 else float("nan"),
        "rule_holds": bool(lim <= 5.0 * size * (1 + 1e-12)),
    }


def horizon_onset_deg(angular_radius_rad):
    """Tilt (deg) at which a source of the given angular radius starts to sink below the horizon.

    A receiver tilted by theta from the direction of the source's centre loses part of a source
    whose edge lies alpha from the centre once theta + alpha > 90 deg.
    """
    alpha = np.asarray(angular_radius_rad, dtype=np.float64)
    return 90.0 - np.degrees(alpha)


def cosine_law_analysis(angles_deg, measured, rel_std_error=None, tolerance=DEFAULT_TOLERANCE, z=DEFAULT_Z):
    """Compare E(theta)/E(0) with cos(theta).

    Parameters
    ----------
    angles_deg : (n,) tilts from facing the source, deg, including 0
    measured : (n,) irradiance at each tilt (any unit)
    rel_std_error : (n,), optional, relative standard errors of ``measured``

    Returns
    -------
    dict
        ``ratio`` E/E(0), ``predicted`` cos(theta), ``rel_deviation`` ratio/cos - 1,
        ``abs_deviation`` ratio - cos, ``ratio_rel_se`` (the two readings' errors in quadrature),
        ``ok`` per angle, ``max_rel_deviation`` (max |rel|, signed value kept in
        ``max_rel_deviation_signed``), ``max_at_deg``, ``onset_deg`` (smallest tilt at which the
        deviation exceeds the tolerance, nan when none), ``passed``.
    """
    a = as_finite_array(angles_deg, "angles_deg").ravel()
    e = np.asarray(measured, dtype=np.float64).ravel()
    if a.shape != e.shape:
        raise ValueError("angles and measured values differ in length")
    if np.any((a < 0) | (a >= 90)):
        raise ValueError("tilts must lie in [0, 90) deg")
    zero = np.nonzero(a == 0.0)[0]
    if zero.size == 0:
        raise ValueError("the tilts must include 0 deg (the reference reading E(0))")
    e0 = e[zero[0]]
    if not np.isfinite(e0) or e0 <= 0.0:
        raise ValueError("E(0) is zero or not finite: the meter facing the light receives nothing")
    s = np.zeros_like(e) if rel_std_error is None else np.asarray(rel_std_error, dtype=np.float64).ravel()
    ratio = e / e0
    predicted = np.cos(np.radians(a))
    rel = relative_deviation(ratio, predicted)
    ratio_se = np.sqrt(s**2 + s[zero[0]] ** 2)
    ratio_se[zero[0]] = 0.0
    ok = within_tolerance(rel, ratio_se, tolerance, z)
    absrel = np.where(np.isfinite(rel), np.abs(rel), np.inf)
    i = int(np.argmax(absrel))
    failing = np.nonzero(~ok)[0]
    onset = float(a[failing].min()) if failing.size else float("nan")  # smallest failing tilt
    return {
        "ratio": ratio, "predicted": predicted, "rel_deviation": rel, "abs_deviation": ratio - predicted,
        "ratio_rel_se": ratio_se, "ok": ok, "max_rel_deviation": float(absrel[i]),
        "max_rel_deviation_signed": float(rel[i]), "max_at_deg": float(a[i]), "onset_deg": onset,
        "passed": bool(ok.all()),
    }

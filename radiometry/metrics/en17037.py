"""EN 17037:2018 (+A1:2021) "Daylight in buildings": the level each criterion reaches (pure).

Four criteria, each rated minimum / medium / high, or "not met", or "not assessed" when its input is
not given:

- **Daylight provision** (vertical and inclined openings, Table A.1): a target illuminance E_T over
  50 % of the reference plane and a minimum target E_TM over 95 % of it, for at least half of the
  daylight hours. Levels (E_T, E_TM): minimum 300 / 100 lx, medium 500 / 300 lx, high 750 / 500 lx.
  *Target-illuminance method* (:func:`daylight_provision_illuminance`): hourly illuminances on the
  plane's points; at each daylight hour, the share of the plane at or above the target; the level is
  met when that share reaches 50 % (E_T) and 95 % (E_TM) in at least half of the hours.
  *Daylight-factor method* (:func:`daylight_provision_daylight_factor`): D_T = 100 E_T / E_v,d over
  50 % and D_TM = 100 E_TM / E_v,d over 95 % of the plane, E_v,d the site's median external diffuse
  illuminance (the standard's Annex A tabulates it per capital; the user gives the site's).
- **Exposure to sunlight**: sunlight duration on a chosen day between 1 February and
  21 March at the assessed point: minimum 1.5 h, medium 3 h, high 4 h (``measure.analyses.sun_study``'s
  ``sunlight_hours``).
- **Protection from glare**: the DGP exceeded for no more than 5 % of the occupied time
  (the 95th percentile of the hourly DGP): minimum <= 0.45, medium <= 0.40, high <= 0.35.
- **View out**: horizontal sight angle (minimum >= 14 deg, medium >= 28 deg, high >=
  54 deg), outside distance of the view (>= 6 m, >= 20 m, >= 50 m) and the number of layers seen
  (sky, landscape, ground; minimum: landscape, medium: landscape and one more, high: all three).

**Indicative.** The standard's text was not available to check these numbers against (it is sold by the
national standards bodies); they are the values commonly quoted from it (CIBSE/SLL summaries, the
Honeybee/Pollination and ClimateStudio EN 17037 recipes), as ``radiometry.metrics.compliance`` marks the
EN 12464-1 rows. The time share of daylight provision is applied hour by hour to the plane's share
(the standard's wording); tools that count per point first (each point's share of hours) agree with it
whenever the plane is lit alike, as in the tests here. Every row says so (``indicative``). Only
Table A.1 is cited by number (as ``measure.analyses.daylight_factor`` cites it); the other rows' tables are not.
"""

import dataclasses
import math

import numpy as np

__all__ = ["LEVELS", "PROVISION_LUX", "SUNLIGHT_HOURS", "GLARE_DGP", "VIEW_OUT", "Criterion",
           "daylight_provision_illuminance", "daylight_provision_daylight_factor", "sunlight_exposure",
           "glare_protection", "view_out", "view_out_over_points", "not_assessed", "table", "NOT_ASSESSED", "NOT_MET"]

LEVELS = ("minimum", "medium", "high")
NOT_ASSESSED, NOT_MET = "not assessed", "not met"
SOURCE = "EN 17037:2018+A1:2021"
#: level -> (E_T over 50 % of the plane, E_TM over 95 %), lx (Table A.1, vertical/inclined openings)
PROVISION_LUX = {"minimum": (300.0, 100.0), "medium": (500.0, 300.0), "high": (750.0, 500.0)}
PLANE_SHARE_T, PLANE_SHARE_TM, TIME_SHARE = 0.50, 0.95, 0.50
#: level -> hours of sunlight on the reference day
SUNLIGHT_HOURS = {"minimum": 1.5, "medium": 3.0, "high": 4.0}
#: level -> the DGP that may be exceeded for at most 5 % of the occupied time
GLARE_DGP = {"minimum": 0.45, "medium": 0.40, "high": 0.35}
GLARE_TIME_SHARE = 0.05
#: level -> (horizontal sight angle deg, outside distance m, layers seen)
VIEW_OUT = {"minimum": (14.0, 6.0, 1), "medium": (28.0, 20.0, 2), "high": (54.0, 50.0, 3)}


@dataclasses.dataclass
class Criterion:
    """One row of the table: the level reached and what it was judged on."""

    criterion: str
    method: str
    level: str                      #: "minimum" | "medium" | "high" | "not met" | "not assessed"
    values: dict                    #: what was measured, with units in the keys
    per_level: dict                 #: level -> {"required": ..., "met": bool}
    source: str = SOURCE
    indicative: bool = True
    note: str = ""


def _best(per_level):
    met = [lv for lv in LEVELS if per_level[lv]["met"]]
    return met[-1] if met else NOT_MET


def daylight_provision_illuminance(illuminance, daylight_hours=None):
    """Daylight provision from hourly illuminances (T hours, N points), lx; ``daylight_hours`` (T,)
    bool (None: every row is a daylight hour). Returns :class:`Criterion`."""
    e = np.asarray(illuminance, float)
    if e.ndim != 2 or e.size == 0:
        raise ValueError(f"illuminance must be (T hours, N points), got shape {e.shape}")
    hours = np.ones(e.shape[0], bool) if daylight_hours is None else np.asarray(daylight_hours, bool)
    if hours.shape != (e.shape[0],):
        raise ValueError(f"daylight_hours must be ({e.shape[0]},), got {hours.shape}")
    if not hours.any():
        raise ValueError("no daylight hours")
    e = e[hours]
    if not np.all(np.isfinite(e)):
        raise ValueError("illuminance has NaN or infinite values in daylight hours")
    per_level = {}
    for lv, (e_t, e_tm) in PROVISION_LUX.items():
        t_hours = float(np.mean(np.mean(e >= e_t, axis=1) >= PLANE_SHARE_T))
        tm_hours = float(np.mean(np.mean(e >= e_tm, axis=1) >= PLANE_SHARE_TM))
        per_level[lv] = {"required": f"{e_t:g} lx over 50 % and {e_tm:g} lx over 95 % of the plane for 50 % "
                                     "of the daylight hours",
                         "share_of_hours_E_T": t_hours, "share_of_hours_E_TM": tm_hours,
                         "met": bool(t_hours >= TIME_SHARE and tm_hours >= TIME_SHARE)}
    return Criterion("daylight provision", "target illuminance (hourly)", _best(per_level),
                     {"daylight_hours": int(hours.sum()), "points": int(e.shape[1]),
                      "median_plane_illuminance_lux": float(np.median(e))}, per_level)


def daylight_provision_daylight_factor(daylight_factor, median_external_illuminance_lux):
    """Daylight provision by the DF method: DFs (%) on the plane's equal-area points and the site's
    E_v,d (lx). Returns :class:`Criterion`."""
    v = np.asarray(daylight_factor, float).ravel()
    if v.size == 0 or not np.all(np.isfinite(v)):
        raise ValueError("daylight factors must be finite numbers (got an empty or non-finite grid)")
    evd = float(median_external_illuminance_lux)
    if not (np.isfinite(evd) and evd > 0):
        raise ValueError(f"the median external diffuse illuminance E_v,d must be > 0 lx, got "
                         f"{median_external_illuminance_lux!r}")
    per_level = {}
    for lv, (e_t, e_tm) in PROVISION_LUX.items():
        d_t, d_tm = 100.0 * e_t / evd, 100.0 * e_tm / evd
        s_t, s_tm = float(np.mean(v >= d_t)), float(np.mean(v >= d_tm))
        per_level[lv] = {"required": f"DF {d_t:.2f} % over 50 % and {d_tm:.2f} % over 95 % of the plane",
                         "E_T_lux": e_t, "E_TM_lux": e_tm, "D_T": d_t, "D_TM": d_tm, "share_D_T": s_t,
                         "share_D_TM": s_tm, "met": bool(s_t >= PLANE_SHARE_T and s_tm >= PLANE_SHARE_TM)}
    return Criterion("daylight provision", f"daylight factor (E_v,d {evd:g} lx)", _best(per_level),
                     {"median_external_illuminance_lux": evd, "points": int(v.size),
                      "average_daylight_factor_percent": float(v.mean())}, per_level)


def sunlight_exposure(sunlight_hours):
    """Exposure to sunlight from the sunlight duration (h) at the assessed point on the reference day."""
    h = float(sunlight_hours)
    if not (np.isfinite(h) and h >= 0):
        raise ValueError(f"sunlight hours must be >= 0 h, got {sunlight_hours!r}")
    per_level = {lv: {"required": f">= {need:g} h", "met": bool(h >= need)} for lv, need in SUNLIGHT_HOURS.items()}
    return Criterion("exposure to sunlight", "sunlight duration on the reference day", _best(per_level),
                     {"sunlight_hours": h}, per_level,
                     note="the day is the caller's: EN 17037 asks for one between 1 February and 21 March")


def glare_protection(dgp_values):
    """Protection from glare from the DGP of the occupied hours (1-D array, one value per hour)."""
    d = np.asarray(dgp_values, float).ravel()
    if d.size == 0 or not np.all(np.isfinite(d)):
        raise ValueError("DGP values must be a non-empty set of finite numbers (one per occupied hour)")
    # the DGP exceeded in no more than 5 % of the hours: the smallest limit with share(d > limit) <= 5 %
    per_level = {}
    for lv, limit in GLARE_DGP.items():
        share = float(np.mean(d > limit))
        per_level[lv] = {"required": f"DGP > {limit:g} in at most 5 % of the occupied hours",
                         "share_above": share, "met": bool(share <= GLARE_TIME_SHARE)}
    return Criterion("protection from glare", "DGP exceeded in 5 % of the occupied hours", _best(per_level),
                     {"hours": int(d.size), "dgp_95th_percentile": float(np.percentile(d, 95)),
                      "dgp_max": float(d.max())}, per_level)


def view_out(horizontal_sight_angle_deg, outside_distance_m, layers):
    """View out from the horizontal sight angle (deg), the outside distance (m; inf: nothing modelled in
    front) and the number of layers seen (1-3; minimum needs the landscape layer among them: pass 0 when
    it is not seen)."""
    a, dist, n = float(horizontal_sight_angle_deg), float(outside_distance_m), int(layers)
    if not (np.isfinite(a) and not np.isnan(dist) and a >= 0 and dist >= 0 and 0 <= n <= 3):
        raise ValueError(f"view out needs an angle >= 0 deg, a distance >= 0 m and 0-3 layers, got {a}, {dist}, {n}")
    per_level = {lv: {"required": f">= {ang:g} deg, >= {d:g} m, {k} layer(s) incl. the landscape",
                      "met": bool(a >= ang and dist >= d and n >= k)} for lv, (ang, d, k) in VIEW_OUT.items()}
    return Criterion("view out", "sight angle, outside distance, layers", _best(per_level),
                     {"horizontal_sight_angle_deg": a, "outside_distance_m": dist, "layers": n}, per_level)


#: the share of the assessed points (the utilised area) from which a view out must be had
VIEW_AREA_SHARE = 0.75


def view_out_over_points(angles_deg, distances_m, layers):
    """View out over the points of the utilised area: each quantity as reached from at least 75 % of them
    (the standard's share for the layers, applied here to the sight angle and the distance too: the k-th
    largest value, k = ceil(0.75 N)), then :func:`view_out`."""
    a, d, n = (np.asarray(x, float).ravel() for x in (angles_deg, distances_m, layers))
    if not (a.size and a.size == d.size == n.size):
        raise ValueError(f"view out needs one angle, distance and layer count per point, got {a.size}, {d.size}, {n.size}")
    k = math.ceil(VIEW_AREA_SHARE * a.size - 1e-9)

    def reached(x):
        return np.sort(x)[a.size - k]

    row = view_out(reached(a), reached(d), reached(n))
    dist = "nothing in front" if math.isinf(reached(d)) else f"{reached(d):.0f} m"
    row.method = (f"{reached(a):.0f} deg, {dist}, {int(reached(n))} layers from {VIEW_AREA_SHARE:.0%} of "
                  f"{a.size} points")
    row.values["points"] = int(a.size)
    return row


def not_assessed(name, why):
    """The row of a criterion that could not be judged, with why (its ``note``)."""
    return Criterion(name, "", NOT_ASSESSED, {}, {lv: {"required": "", "met": False} for lv in LEVELS}, note=why)


def table(*, provision=None, sunlight=None, glare=None, view=None):
    """The four rows, in the standard's order; a criterion whose :class:`Criterion` is None reads
    "not assessed" with the input it needs."""
    return [provision or not_assessed("daylight provision", "needs hourly illuminances on the plane or DFs with E_v,d"),
            sunlight or not_assessed("exposure to sunlight", "needs the sunlight hours on a reference day"),
            glare or not_assessed("protection from glare", "needs the DGP of the occupied hours"),
            view or not_assessed("view out", "needs the sight angle, outside distance and layers seen")]

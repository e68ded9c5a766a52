"""EN 12464-1 compliance of a lit work plane (pure): requirements per task, maintained values, pass or
fail with the margin.

Requirements (:data:`TASKS`): maintained illuminance Ēm (lx) on the task area, uniformity U0 =
E_min / Ē, the UGR limit UGR_L and the minimum colour rendering index Ra, as printed in
EN 12464-1:2011 "Light and lighting - Lighting of work places - Part 1: Indoor work places", section 5
(Table 5.1 traffic zones, 5.26 offices, 5.36 educational buildings, 5.2 rest/sanitation rooms,
5.29 retail, 5.32 restaurants). The 2021 edition keeps these values as the *required* column and
adds a *modified* Ēm for demanding conditions: give your own :class:`Requirement` where a project
uses other values.

**Indicative.** The standard's own text was not available to check these rows against (it is sold by
the national standards bodies). The values are the ones commonly quoted from it; they agree with the
secondary sources that could be found (other lighting and building-simulation software's tables, e.g.
the IDEAS Modelica library's office record citing Table 5.26, ref. 5.26.2) for the office rows (500 lx / UGR_L 19 / Ra 80 for writing and data
processing, ref. 5.26.2; 750 / 16 / 80 technical drawing; 300 / 22 / 80 reception; 200 / 25 / 80
archives) and stairs at 100 lx, but a project must check them against its copy of the standard, or
give its own values (:func:`requirement` with ``maintained_lx=...``); every table row says so
(``Requirement.indicative``).

Maintenance: Ēm = MF x Ē_new (EN 12464-1 sec. 4.11; CIE 97:2005 MF = LLMF x LSF x LMF x RSMF); the
rendered scene is the new installation. U0 is a ratio (MF cancels) and UGR is rated with the
installation's luminances as they are (CIE 117 tables use the initial flux).

A check passes when the achieved value is on the right side of the requirement; it is *marginal* when
it is within two standard errors of it (the measurement cannot tell pass from fail at 95 %).
Ra cannot be computed from a render (no spectra): it is the luminaires' rated value given by the user,
else "not assessed".
"""

import dataclasses
import math

__all__ = ["Requirement", "TASKS", "Check", "assess", "requirement"]


@dataclasses.dataclass(frozen=True)
class Requirement:
    """What a task area needs: Ēm lx, U0, UGR_L, Ra (None: no requirement), and where it is from."""

    task: str
    maintained_lx: float
    uniformity: float = None
    ugr_limit: float = None
    ra: float = None
    source: str = "user-given"
    indicative: bool = False  #: values quoted from the standard, not checked against its text (see above)


_EN = "EN 12464-1:2011"


def _task(task, em, u0, ugr, ra, source):
    return Requirement(task, em, u0, ugr, ra, source, indicative=True)


TASKS = {
    "office_writing": _task("Offices: writing, typing, reading, data processing", 500, 0.60, 19, 80,
                            f"{_EN} Table 5.26, ref. 5.26.2"),
    "office_technical_drawing": _task("Offices: technical drawing", 750, 0.70, 16, 80, f"{_EN} Table 5.26"),
    "office_cad": _task("Offices: CAD work stations", 500, 0.60, 19, 80, f"{_EN} Table 5.26"),
    "conference": _task("Conference and meeting rooms", 500, 0.60, 19, 80, f"{_EN} Table 5.26"),
    "reception": _task("Reception desk", 300, 0.60, 22, 80, f"{_EN} Table 5.26"),
    "archive": _task("Archives", 200, 0.40, 25, 80, f"{_EN} Table 5.26"),
    "classroom": _task("Classrooms, tutorial rooms", 300, 0.60, 19, 80, f"{_EN} Table 5.36"),
    "lecture_hall": _task("Auditorium, lecture halls", 500, 0.60, 19, 80, f"{_EN} Table 5.36"),
    "corridor": _task("Circulation areas and corridors", 100, 0.40, 28, 40, f"{_EN} Table 5.1"),
    "stairs": _task("Stairs, escalators, travolators", 100, 0.40, 25, 40, f"{_EN} Table 5.1"),
    "toilets": _task("Cloakrooms, washrooms, toilets", 200, 0.40, 25, 80, f"{_EN} Table 5.2"),
    "retail_sales": _task("Sales area", 300, 0.40, 22, 80, f"{_EN} Table 5.29"),
    "restaurant": _task("Self-service restaurant", 200, 0.40, 22, 80, f"{_EN} Table 5.32"),
}


def requirement(task=None, *, maintained_lx=None, uniformity=None, ugr_limit=None, ra=None):
    """A :class:`Requirement`: a key of :data:`TASKS`, or the user's own values (``maintained_lx`` needed)."""
    if task is not None and maintained_lx is None:
        try:
            return TASKS[task]
        except KeyError:
            raise ValueError(f"unknown task {task!r}; known: {', '.join(sorted(TASKS))}, or give maintained_lx") \
                from None
    if maintained_lx is None or not float(maintained_lx) > 0:
        raise ValueError(f"maintained_lx must be > 0 lx, got {maintained_lx}")
    return Requirement(task or "user-given task", float(maintained_lx), uniformity, ugr_limit, ra, "user-given")


@dataclasses.dataclass
class Check:
    """One line of the compliance table."""

    quantity: str          #: "Ēm", "U0", "UGR (<observer>)", "Ra"
    required: str          #: e.g. ">= 500 lx"
    achieved: float        #: nan when not assessed
    unit: str
    status: str            #: "pass", "fail", "marginal" or "not assessed"
    margin: float          #: achieved - required (signed so that > 0 is on the good side); nan if not assessed
    std_error: float = 0.0  #: 1 s.e. of ``achieved`` (absolute)
    note: str = ""


def _status(margin, se):
    if not math.isfinite(margin):
        return "not assessed"
    if se > 0 and abs(margin) < 2 * se:
        return "marginal"
    return "pass" if margin >= 0 else "fail"


def assess(req, *, average_lx, minimum_lx, maintenance_factor, average_rel_se=0.0, minimum_rel_se=0.0,
           ugr=(), ra=None):
    """The compliance table of one work plane: a list of :class:`Check`.

    ``average_lx``/``minimum_lx``: Ē and E_min of the new installation (lx) with their relative standard
    errors; ``maintenance_factor`` in (0, 1]; ``ugr``: (label, UGR, 1 s.e.) per observer; ``ra``: the
    luminaires' rated Ra or None.
    """
    mf = float(maintenance_factor)
    if not 0 < mf <= 1:
        raise ValueError(f"maintenance factor must be in (0, 1], got {maintenance_factor}")
    em = mf * float(average_lx)
    em_se = em * float(average_rel_se)
    rows = [Check("Ēm", f">= {req.maintained_lx:g} lx", em, "lx", _status(em - req.maintained_lx, em_se),
                  em - req.maintained_lx, em_se, f"maintained = MF {mf:g} x Ē {float(average_lx):.4g} lx")]
    u0 = float(minimum_lx) / float(average_lx) if average_lx > 0 else math.nan
    u0_se = u0 * math.hypot(average_rel_se, minimum_rel_se) if math.isfinite(u0) else 0.0
    if req.uniformity is not None:
        rows.append(Check("U0", f">= {req.uniformity:.2f}", u0, "", _status(u0 - req.uniformity, u0_se),
                          u0 - req.uniformity, u0_se, "E_min / Ē on the grid"))
    if req.ugr_limit is not None:
        if not ugr:
            rows.append(Check("UGR", f"<= {req.ugr_limit:g}", math.nan, "", "not assessed", math.nan,
                              note="no observer position given"))
        for label, value, se in ugr:
            v = float(value)
            if v == -math.inf:
                rows.append(Check(f"UGR ({label})", f"<= {req.ugr_limit:g}", v, "", "pass", math.inf, 0.0,
                                  "no glare source in the field"))
                continue
            rows.append(Check(f"UGR ({label})", f"<= {req.ugr_limit:g}", v, "", _status(req.ugr_limit - v, se),
                              req.ugr_limit - v, float(se), "CIE 117"))
    if req.ra is not None:
        if ra is None:
            rows.append(Check("Ra", f">= {req.ra:g}", math.nan, "", "not assessed", math.nan,
                              note="no spectra in a render: rated Ra needed"))
        else:
            rows.append(Check("Ra", f">= {req.ra:g}", float(ra), "", _status(float(ra) - req.ra, 0.0),
                              float(ra) - req.ra, 0.0, "rated value of the luminaires (user-given)"))
    return rows


def overall(rows):
    """'pass' when every assessed check passes, 'fail' when one fails, else 'marginal' / 'not assessed'."""
    states = {r.status for r in rows}
    if "fail" in states:
        return "fail"
    if "marginal" in states:
        return "marginal"
    if states <= {"pass"}:
        return "pass"
    return "pass (partly assessed)" if "pass" in states else "not assessed"

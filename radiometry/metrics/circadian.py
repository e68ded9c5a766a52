"""Circadian lighting check (pure): WELL v2 feature L03, "Circadian lighting design", indicative.

WELL v2 L03 asks for a melanopic stimulus on the vertical plane at the occupant's eye, facing forward,
for at least 4 hours between 9:00 and 13:00: at least 150 EML, i.e. 136 lx melanopic EDI (CIE S 026, D65),
for 1 point; at least 275 EML, 250 lx mel-EDI, for 3 points (with L05 or L06 part 1). Projects with enhanced
daylight may reach 120 EML / 109 lx and 180 EML / 163 lx with electric light alone. EML (WELL's equivalent
melanopic lux) = mel-EDI / 0.9058. The eye: 1.2 m above the floor seated, 1.7 m standing.

**Indicative.** WELL's text was not available here to cite; these are its values as quoted by
manufacturers' summaries of WELL v2 (as ``compliance`` marks the EN 12464-1 rows), and every result says so.
WELL's hours of the day are the user's to choose (the scene is one moment).

A verdict is only as strong as the reading: "met" when the reading's lower end (its 95 % interval's low end,
or a lower bound when light was left out) reaches the threshold; "not met" only when the whole light at the
eye was read (no light, reflection, world or emitting surface left out) and its 95 % interval's high end is
below it; otherwise "unknown", with why.
"""

import numpy as np

__all__ = ["EYE_HEIGHT_M", "WELL_L03_MEL_EDI_LX", "WELL_L03_ENHANCED_DAYLIGHT_MEL_EDI_LX", "EML_PER_MEL_EDI",
           "SOURCE", "rate", "summary", "MET", "NOT_MET", "UNKNOWN"]

EYE_HEIGHT_M = {"seated": 1.2, "standing": 1.7}
#: WELL points -> melanopic EDI (lx, D65) on the vertical plane at the eye
WELL_L03_MEL_EDI_LX = {1: 136.0, 3: 250.0}
#: the same with enhanced daylight (electric light alone)
WELL_L03_ENHANCED_DAYLIGHT_MEL_EDI_LX = {1: 109.0, 3: 163.0}
#: EML (WELL, Lucas et al. 2014) per lx of mel-EDI (CIE S 026): 1 / 0.9058
EML_PER_MEL_EDI = 1.0 / 0.9058
SOURCE = "WELL v2 L03 (indicative)"
MET, NOT_MET, UNKNOWN = "met", "not met", "unknown"


def rate(mel_edi_lx, low_95=None, high_95=None, *, whole=True, thresholds=None):
    """Per threshold (points -> verdict) for one eye: ``mel_edi_lx`` the reading (lx), ``low_95``/``high_95``
    its 95 % interval (None: the reading is exact, or a lower bound when ``whole`` is False); ``whole``:
    nothing that lights the eye was left out of the reading."""
    v = float(mel_edi_lx)
    if not np.isfinite(v) or v < 0:
        raise ValueError(f"mel-EDI must be a finite number >= 0 lx, got {mel_edi_lx!r}")
    lo = v if low_95 is None else float(low_95)
    hi = v if high_95 is None else float(high_95)
    out = {}
    for points, t in (thresholds or WELL_L03_MEL_EDI_LX).items():
        if lo >= t:
            out[points] = MET
        elif whole and hi < t:
            out[points] = NOT_MET
        else:
            out[points] = UNKNOWN
    return out


def summary(verdicts, thresholds=None):
    """Over the eyes' verdicts (a list of :func:`rate` dicts): per threshold the share of eyes where it is
    met, not met and unknown, and the points reached where it is met at every eye (WELL v2 asks it at the
    workstations; a point that is unknown at one eye is not claimed)."""
    thresholds = thresholds or WELL_L03_MEL_EDI_LX
    n = len(verdicts)
    if not n:
        raise ValueError("the circadian check needs at least one eye")
    share = {p: {k: sum(1 for v in verdicts if v[p] == k) / n for k in (MET, NOT_MET, UNKNOWN)} for p in thresholds}
    reached = [p for p in sorted(thresholds) if share[p][MET] == 1.0]
    # higher only if some unreached threshold is unknown somewhere and missed nowhere
    unknown = any(share[p][UNKNOWN] > 0 and share[p][NOT_MET] == 0 for p in thresholds if p not in reached)
    return {"share": share, "points": max(reached) if reached else 0, "points_may_be_higher": unknown,
            "thresholds_mel_edi_lx": dict(thresholds),
            "thresholds_eml": {p: t * EML_PER_MEL_EDI for p, t in thresholds.items()}, "source": SOURCE,
            "indicative": True}

"""The circadian check (host side): vertical meters at the occupants' eyes, facing their view, read in
melanopic EDI (CIE S 026, ``spectra`` / ``spectral_reflected``) and rated against WELL v2 L03's
indicative thresholds (``radiometry.metrics.circadian``).

Eyes stand ``EYE_HEIGHT_M`` (1.2 m seated, 1.7 m standing) above the given floor positions. What the
spectral reading leaves out (without ``reflected``: the reflected light, the world's light indoors and
emitting surfaces'; always: lights without a spectrum) makes it a lower bound: it can show a threshold met,
never missed. With ``reflected`` every eye is read in one batch of band renders, daylight included.
"""

import numpy as np

from ...errors import RadiometerError
from ...radiometry.metrics import circadian


def circadian_check(positions, view_directions, *, request, posture="seated", reflected=False):
    """One reading per occupant (``positions`` (N, 3) floor points in scene coordinates, ``view_directions``
    one (3,) or (N, 3) direction each looks along) and the WELL v2 L03 summary: a plain dict, SI. The request
    (``measure.blender.request``): the scene, and with ``reflected`` the band renders' quality and seed."""
    from . import spectra, spectral_reflected

    if posture not in circadian.EYE_HEIGHT_M:
        raise RadiometerError(f"posture must be one of {', '.join(circadian.EYE_HEIGHT_M)}, got {posture!r}")
    pos = np.atleast_2d(np.asarray(positions, float))
    dirs = np.asarray(view_directions, float)
    if pos.ndim != 2 or pos.shape[1] != 3 or not len(pos) or not np.all(np.isfinite(pos)):
        raise RadiometerError(f"positions must be 3 finite numbers or (N, 3), got shape {pos.shape}")
    dirs = np.broadcast_to(dirs, pos.shape) if dirs.shape == (3,) else dirs
    if dirs.shape != pos.shape or not np.all(np.isfinite(dirs)):
        raise RadiometerError(f"view_directions must be one direction or one per position, got shape {dirs.shape}")
    dirs = np.array(dirs, float)
    dirs[:, 2] = 0.0                     # the meter is vertical: it faces the horizontal part of the view
    length = np.linalg.norm(dirs, axis=1)
    if np.any(length < 1e-9):
        raise RadiometerError("a view direction is zero or vertical: give the way each occupant faces (horizontal)")
    dirs = dirs / length[:, None]
    eye_h = circadian.EYE_HEIGHT_M[posture]
    eyes = pos + np.array([0.0, 0.0, eye_h / request.scale_length])
    rows, verdicts = [], []
    if reflected:  # every eye in one batch of band renders
        readings = spectral_reflected.spectral_readings(eyes, dirs, request=request)
    else:
        readings = [spectra.spectral_reading(tuple(eye), tuple(d), request=request) for eye, d in zip(eyes, dirs)]
    for eye, d, r in zip(eyes, dirs, readings):
        band = r.get("interval_95", {}).get("mel_edi_lx") if r.get("part") == "direct+reflected" else None
        left_out = list(r["not_included"])
        if not r["complete"]:
            left_out.append("lights without a spectrum or a closed form")
        # a light whose direct part is not a proven closed form (something may hide part of it) carries its
        # bound: the reading then lies anywhere in [value - slack, value + slack], never above its low end
        slack = sum(float(x.get("mel_edi_lx") or 0.0) * min(1.0, float(x.get("rel_error_bound") or 0.0))
                    for x in r["lights"] if not x.get("exact"))
        lo, hi = (band["low_95"], band["high_95"]) if band else (r["mel_edi_lx"], r["mel_edi_lx"])
        lo, hi = max(0.0, lo - slack), hi + slack
        v = circadian.rate(r["mel_edi_lx"], lo, hi, whole=not left_out)
        verdicts.append(v)
        rows.append({"eye": tuple(map(float, request.to_metres(eye))), "view_direction": tuple(map(float, d)),
                     "mel_edi_lx": float(r["mel_edi_lx"]), "low_95_lx": lo if band or slack else None,
                     "high_95_lx": hi if band or slack else None, "direct_bound_lx": slack,
                     "illuminance_lx": float(r["illuminance_lx"]), "mel_der": r.get("mel_der"),
                     "exact": bool(r["exact"]) and not left_out, "lower_bound": bool(left_out), "left_out": left_out,
                     "verdict": {str(p): k for p, k in v.items()}, "notes": list(r["notes"])})
    s = circadian.summary(verdicts)
    return {"check": "circadian lighting (WELL v2 L03, indicative)", "posture": posture, "eye_height_m": eye_h,
            "quantity": "melanopic EDI (CIE S 026/E:2018), vertical at the eye facing the view, lx",
            "eyes": rows, "points": s["points"], "points_may_be_higher": s["points_may_be_higher"],
            "share": {str(p): v for p, v in s["share"].items()},
            "thresholds_mel_edi_lx": {str(p): t for p, t in s["thresholds_mel_edi_lx"].items()},
            "thresholds_eml": {str(p): t for p, t in s["thresholds_eml"].items()}, "source": s["source"],
            "indicative": True,
            "notes": ["WELL asks for these levels at least 4 hours between 9:00 and 13:00: the scene is one moment",
                      "a reading that leaves light out is a lower bound: it shows a threshold met, never missed"],
            "units": {"mel_edi_lx": "lx", "low_95_lx": "lx", "high_95_lx": "lx", "illuminance_lx": "lx",
                      "eye_height_m": "m", "eye": "m", "mel_der": "1"}}

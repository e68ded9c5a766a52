"""Climate-based daylight metrics (pure numpy), as IES LM-83-12 defines them, plus UDI.

* sDA_{300/50%} (spatial daylight autonomy): the share of the analysis points that receive at least
  300 lx for at least 50 % of the occupied hours (LM-83: 8 am to 6 pm local time, every day of the
  year: 3650 hours).
* ASE_{1000,250h} (annual sunlight exposure): the share of the points that receive MORE than 1000 lx
  of direct sunlight for MORE than 250 occupied hours. LM-83 computes it from the sun alone, with no
  interreflection: pass the sun-only illuminance.
* UDI (useful daylight illuminance, Nabil & Mardaljevic 2005): per point, the share of occupied hours
  below 100 lx ("fell short"), within 100-2000 lx ("useful", both ends included) and above 2000 lx
  ("exceeded").

Arrays are (T, N): T hours, N points, lux; ``occupied`` is a (T,) boolean mask.
"""

import numpy as np

__all__ = ["occupied_hours", "sda", "ase", "udi"]


def occupied_hours(local_hours, start=8.0, end=18.0):
    """(T,) mask of records whose midpoint local hour lies in [start, end) (LM-83: 8 am-6 pm)."""
    h = np.asarray(local_hours, float)
    return (h >= start) & (h < end)


def _check(e, occupied):
    e = np.asarray(e, float)
    if e.ndim != 2:
        raise ValueError(f"illuminance must be (T hours, N points), got shape {e.shape}")
    occ = np.asarray(occupied, bool)
    if occ.shape != (e.shape[0],):
        raise ValueError(f"occupied must be ({e.shape[0]},), got {occ.shape}")
    if not occ.any():
        raise ValueError("no occupied hours")
    if not np.all(np.isfinite(e[occ])):
        raise ValueError("illuminance has NaN or infinite values in occupied hours")
    return e[occ]


def sda(illuminance, occupied, threshold_lux=300.0, time_fraction=0.5):
    """(sDA fraction of points, per-point fraction of occupied hours at >= threshold)."""
    e = _check(illuminance, occupied)
    frac = np.mean(e >= threshold_lux, axis=0)
    return float(np.mean(frac >= time_fraction)), frac


def ase(sun_illuminance, occupied, threshold_lux=1000.0, hours=250):
    """(ASE fraction of points, per-point number of occupied hours with > threshold of direct sun)."""
    e = _check(sun_illuminance, occupied)
    count = np.sum(e > threshold_lux, axis=0)
    return float(np.mean(count > hours)), count


def udi(illuminance, occupied, low_lux=100.0, high_lux=2000.0):
    """Per-point fractions of occupied hours (fell_short, useful, exceeded); they sum to 1."""
    e = _check(illuminance, occupied)
    short = np.mean(e < low_lux, axis=0)
    exceeded = np.mean(e > high_lux, axis=0)
    return short, 1.0 - short - exceeded, exceeded

"""Daylight maps of analysis results (host side): the per-point numbers of a daylight factor grid, an
annual run (sDA / ASE / UDI per point) or a sun study (sunlight hours), the room in plan (a section of
the captured scene's opaque triangles at the points' height, and its openings:
``radiometry.scene.plan_section``), drawn by ``plots.daylight_map``.

A map is a plan view: the points must lie on one horizontal plane (a work plane); others are refused
with one line. Points on a regular lattice are drawn as cells, others as markers. Metres throughout
(scene units times the unit scale).
"""

import numpy as np

from ...errors import RadiometerError
from ...plots import daylight_map as plot
from ..analyses.annual import AnnualResult
from ..analyses.daylight_factor import DaylightFactorGrid
from ..analyses.sun_study import SunStudyResult

#: The maps of an annual result (``metric=``): sDA's share of hours at 300 lx per point (default), the
#: hours of direct sun at 1000 lx (ASE), and the useful daylight share (UDI 100-2000 lx).
ANNUAL_METRICS = ("sda", "ase", "udi")

def room_plan(scene, height_m):
    """(walls (S, 2, 2), openings [(K, 2)]) in metres: the plan of the scene as Cycles renders it
    (``measure.capture.capture_cache``) cut at ``height_m``."""
    from ...radiometry.scene import plan_section
    from ..capture import capture_cache

    geometry = capture_cache.capture(scene).geometry
    if not geometry.count:
        return np.zeros((0, 2, 2)), []
    return plan_section.room_plan(geometry.triangles, geometry.opaque, height_m)


def map_content(result, metric=None):
    """The map's numbers for an analysis result: dict of values (N,), points (N, 3) in scene units,
    quantity, unit, title, error_text, vmin, vmax, flagged, flagged_label."""
    if isinstance(result, DaylightFactorGrid):
        if metric not in (None, "df"):
            raise RadiometerError(f"a daylight factor grid maps only its daylight factor, not {metric!r}")
        s = result.stats
        return dict(values=result.daylight_factor.ravel(), points=result.points.reshape(-1, 3),
                    quantity="daylight factor", unit="%",
                    title=f"Daylight factor on {result.target!r} ({result.nx} x {result.ny} points, CIE overcast "
                          f"sky): average {s['average']:.2f} %, min {s['minimum']:.2f} %",
                    error_text="DF relative " + plot.error_share_text(result.rel_std_error))
    if isinstance(result, AnnualResult):
        metric = metric or "sda"
        if metric not in ANNUAL_METRICS:
            raise RadiometerError(f"annual map {metric!r}: choose one of {', '.join(ANNUAL_METRICS)}")
        n = len(result.locations)
        period = "" if result.whole_year else f" (PARTIAL PERIOD: {result.weather_period})"
        hourly = (f"hourly relative 1 s.e. <= {100 * result.max_rel_std_error:.2g} % (occupied hours at 100 lx "
                  "or more)")
        if metric == "sda":
            k = int(np.sum(result.sda_uncertain))
            return dict(values=100.0 * np.asarray(result.sda_point_fraction, float), points=result.locations,
                        quantity="occupied hours at 300 lx or more", unit="%", vmin=0.0, vmax=100.0,
                        title=f"sDA300/50%: {100 * result.sda:.1f} % of {n} points pass (within 2 s.e.: "
                              f"{100 * result.sda_range[0]:.1f}-{100 * result.sda_range[1]:.1f} %){period}",
                        error_text=f"{hourly}; {k} of {n} points uncertain at 2 s.e.",
                        flagged=np.asarray(result.sda_uncertain, bool),
                        flagged_label="pass or fail uncertain at 2 s.e.")
        if metric == "ase":
            hours = np.asarray(result.ase_hours, float)
            return dict(values=hours, points=result.locations, quantity="hours of direct sun at 1000 lx or more",
                        unit="h", title=f"ASE1000/250h: {100 * result.ase:.1f} % of {n} points over 250 h{period}",
                        error_text=("direct sun alone in closed form (LM-83; the sun's centre ray tested): "
                                    "no sampling error"),
                        flagged=hours > 250.0, flagged_label="over 250 h")
        return dict(values=100.0 * np.asarray(result.udi[1], float), points=result.locations,
                    quantity="occupied hours at 100-2000 lx", unit="%", vmin=0.0, vmax=100.0,
                    title=(f"UDI 100-2000 lx: mean {100 * float(np.mean(result.udi[1])):.1f} % of occupied "
                           f"hours{period}"),
                    error_text=hourly)
    if isinstance(result, SunStudyResult):
        if metric not in (None, "sunlight_hours"):
            raise RadiometerError(f"a sun study maps only its sunlight hours, not {metric!r}")
        first, last = (t.isoformat(timespec="minutes") for t in (result.times[0], result.times[-1]))
        exact = np.asarray(result.exact, bool)
        rendered = np.asarray(result.rel_std_error, float)[~exact & np.asarray(result.sunlit, bool)]
        text = f"{100 * float(np.mean(exact)):.0f} % of {exact.size} samples exact"
        if rendered.size:
            text += f", rendered ones relative 1 s.e. <= {100 * float(np.nanmax(rendered)):.2g} %"
        return dict(values=np.asarray(result.sunlight_hours, float), points=result.locations,
                    quantity="sunlight hours", unit="h",
                    title=f"Sunlight hours, {len(result.times)} times from {first} to {last}", error_text=text)
    raise RadiometerError(f"no daylight map for a {type(result).__name__}: give a daylight factor grid, an "
                          "annual result or a sun study result")


def daylight_map(result, path, *, metric=None, scene=None, outline=True):
    """Write the plan-view map of ``result`` (see :func:`map_content`) as a PNG at ``path`` (whole or not
    at all); returns ``path``. ``outline``: draw the room's section and openings (captures the scene).
    ``scene``: a request (``measure.blender.request``), a scene or None (the context's)."""
    from ..blender import request as request_of

    request = request_of.of(scene)
    scene = request.scene
    content = map_content(result, metric)
    scale = request.scale_length
    pts = np.asarray(content.pop("points"), float).reshape(-1, 3) * scale
    values = np.asarray(content.pop("values"), float).ravel()
    if len(pts) != len(values) or not len(pts):
        raise RadiometerError(f"{len(values)} values for {len(pts)} points: nothing to map")
    z = plot.plan_height(pts[:, 2])
    walls, openings = room_plan(scene, z) if outline else (None, ())
    shape = plot.lattice_shape(pts[:, :2])
    flagged = content.pop("flagged", None)
    if shape is not None:
        values, pts = values.reshape(shape), pts.reshape(shape + (3,))
        flagged = None if flagged is None else np.asarray(flagged, bool).reshape(shape)
    return plot.daylight_map_png(path, values, pts[..., :2], walls=walls, openings=openings, section_height=z,
                                 flagged=flagged, **content)

"""Sun studies: illuminance from the sun (and optionally a CIE sky) at N meters over T times.

One time step is the module-level :func:`sun_study_step` ``(scene, *, locations, normals, when, seed,
...) -> dict of arrays``: inside ``scene_guard.preserved_scene`` it switches every rendering light
off (instanced ones too) and removes the world (or puts a temporary CIE sky there), adds a
temporary 0.53 deg sun for that time (``measure.authoring.sun.set_sun``), measures the meters with the
ordinary meter (``measure.meter.point_meter.measure_illuminance``: exact closed forms where nothing can block
the sun and nothing reflects, Cycles with a stated error elsewhere) and tests the sun's visibility
from every meter on the scene model's triangles. The scene is restored after every step, so the
same function runs here or on a Dask worker (``radiometer.cluster.run_scene_tasks``).

``sunlit`` (EN 17037 "exposure to sunlight"): the ray from the meter towards the centre of the
sun's disc meets no opaque, shadow-casting triangle (glass and other transmitting surfaces let the
sun through, as in EN 17037, which assesses the sun behind glazing) and the sun is above the
horizon; ``sunlit_fraction`` is the share of 61 rays spread over the 0.53 deg disc that get
through. The meter's own orientation does not matter for ``sunlit`` (it does for the illuminance).

Sunlight hours per point: each time sample stands for the interval centred on it (half-way to its
neighbours; the first and last samples for half their one gap: the trapezoid rule), and a point
collects that duration when it is sunlit with the sun at least ``min_elevation_deg`` high (EN
17037 sets a site minimum sun altitude; 0 by default).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math
import time

import numpy as np

from ...errors import MeasurementCancelled, RadiometerError
from ...readings import batch_method

SUN_RADIUS_DEG = 0.265
_DISC_RINGS = (1, 6, 12, 18, 24)  # 61 rays: the centre and 4 rings (one ray per ~equal area)


# --- pure helpers (numpy only) -------------------------------------------------------------------

def disc_directions(direction, radius_deg=SUN_RADIUS_DEG, rings=_DISC_RINGS):
    """(R, 3) unit vectors over a disc of angular radius ``radius_deg`` around ``direction``;
    row 0 is the centre. Rings at equal-area radii, evenly spaced in angle."""
    d = np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(d, helper)
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    out = [d]
    total = sum(rings)
    done = rings[0]
    for k, count in enumerate(rings[1:], start=1):
        # ring k covers the area share (done .. done+count) / total; put it at its mean-area radius
        r = math.radians(radius_deg) * math.sqrt((done + 0.5 * count) / total)
        for j in range(count):
            a = 2.0 * math.pi * (j + 0.5 * (k % 2)) / count
            w = math.cos(r) * d + math.sin(r) * (math.cos(a) * u + math.sin(a) * v)
            out.append(w / np.linalg.norm(w))
        done += count
    return np.array(out)


def rays_blocked(origins, directions, triangles, tol):
    """(P, R) bool: the ray from ``origins[p]`` (P, 3) along ``directions[r]`` (R, 3) meets one of
    ``triangles`` (T, 3, 3) at a distance > ``tol`` (Moller-Trumbore, edges inclusive: a ray through
    a shared edge counts as blocked). Metres. Vectorised over blocks of points x directions x triangles
    (the origins' terms are computed once for every direction: an annual run asks ~4400 sun directions)."""
    o = np.asarray(origins, float).reshape(-1, 3)
    dirs = np.asarray(directions, float).reshape(-1, 3)
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    blocked = np.zeros((len(o), len(dirs)), bool)
    if not len(tris) or not len(o) or not len(dirs):
        return blocked
    v0, e1, e2 = tris[:, 0], tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    eps = 1e-12
    slack = 1e-9 * (1.0 + max(np.abs(tris).max(), np.abs(o).max()))
    cells = 2_000_000  # points x directions x triangles per block (~16 MB per float array)
    pts_block = max(1, min(len(o), cells // len(tris)))
    for p0 in range(0, len(o), pts_block):
        tvec = o[p0:p0 + pts_block, None, :] - v0[None]          # (P, T, 3): direction-free
        qvec = np.cross(tvec, e1[None])                           # (P, T, 3)
        t_num = np.einsum("ptk,tk->pt", qvec, e2)                 # (P, T)
        dir_block = max(1, cells // (len(tvec) * len(tris)))
        lo = o[p0:p0 + pts_block]
        for r0 in range(0, len(dirs), dir_block):
            d = dirs[r0:r0 + dir_block]                           # (B, 3)
            # only triangles with a vertex ahead of some origin along some of these directions can be hit
            # (a margin of 1e-9 of the scene's extent keeps the edge-inclusive test's borderline hits)
            ahead = ((tris @ d.T).max(axis=1) > (lo @ d.T).min(axis=0)[None] + tol - slack).any(axis=1)
            k = np.flatnonzero(ahead)
            if not k.size:
                continue
            pvec = np.cross(d[:, None, :], e2[None, k])           # (B, K, 3)
            det = np.einsum("btk,tk->bt", pvec, e1[k])
            ok = np.abs(det) > 1e-300
            inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[None]  # (1, B, K)
            tv = tvec[:, k]
            u = (tv[:, None, :, 0] * pvec[None, :, :, 0] + tv[:, None, :, 1] * pvec[None, :, :, 1]
                 + tv[:, None, :, 2] * pvec[None, :, :, 2]) * inv
            v = np.einsum("ptk,bk->pbt", qvec[:, k], d) * inv
            t = t_num[:, None, k] * inv
            hit = ok[None] & (u >= -eps) & (v >= -eps) & (u + v <= 1.0 + eps) & (t > tol)
            blocked[p0:p0 + pts_block, r0:r0 + dir_block] = hit.any(axis=2)
    return blocked


def sample_hours(unix_s):
    """Duration (h) each time sample stands for: half-way to its neighbours (trapezoid rule)."""
    t = np.asarray(unix_s, float)
    if t.size < 2:
        return np.zeros(t.shape)
    order = np.argsort(t)
    ts = t[order]
    gaps = np.diff(ts) / 3600.0
    w = np.zeros(ts.size)
    w[:-1] += 0.5 * gaps
    w[1:] += 0.5 * gaps
    out = np.empty_like(w)
    out[order] = w
    return out


# --- one time step (runs here or on a worker) ------------------------------------------------------

def _set_sky(request, sky, direction, horizontal_illuminance_lux=None):
    """Put a temporary world with the sky model ``sky`` (a ``SKY_MODELS`` name) on the request's scene
    (inside the caller's guard)."""
    import bpy

    from ..authoring import sky as cie_sky_world

    request.scene.world = bpy.data.worlds.new("Radiometer sun-study sky")  # the guard restores the user's world
    cie_sky_world.set_cie_sky(request, sky, horizontal_illuminance_lux=horizontal_illuminance_lux,
                              sun_direction=tuple(float(x) for x in direction))


def sun_bounce_readings(request, model, sun_obj, info, points, normals, snapshot):
    """(readings or None, why not, ``SunBounce``): every meter read with the sun hidden, its direct light in
    closed form (the meter's own, ``direct_only``: None where that is not analytic at every meter) and its first
    bounce as Lambertian emitters (``sun_bounce``), inside the caller's guard (``snapshot``)."""
    from ..meter import point_meter as meter
    from ..meter import sun_bounce

    target = request.target_rel_error if request.target_rel_error is not None else request.preset()["target"]
    bounce = sun_bounce.plan(model, np.asarray(info["direction"], float), 0.5 * float(sun_obj.data.angle),
                             target_rel_error=target)
    if not bounce.proven:
        return None, bounce.reason, bounce
    world = request.scene.world
    if world is not None:  # the sun's direct light alone: the world's is in the readings below
        request.scene.world = None
        request.view_layer.update()
    direct = meter.measure_illuminance(points, normals, request, method="auto", direct_only=True,
                                       model=model if world is None else None)
    if world is not None:
        request.scene.world = world
        request.view_layer.update()
    if not all(r.method == "analytic" for r in direct):
        return None, "the sun's direct light is not in closed form at every meter", bounce
    rgb = np.array([r.irradiance_rgb for r in direct], float)
    bound = rgb * np.array([r.rel_error_bound for r in direct], float)[:, None]
    snapshot.remember(sun_obj, "hide_render")
    sun_obj.hide_render = True
    sun_rgb = np.asarray(sun_obj.data.color, float) * float(sun_obj.data.energy)
    sun_bounce.add_emitters(request, bounce, sun_rgb)
    request.view_layer.update()
    part = meter.ProvenPart(rgb=rgb, name="the sun's direct light (closed form)", bound_rgb=bound)
    return meter.measure_illuminance(points, normals, request, method="auto", proven=part), "", bounce


def _measure_sun(request, sun_obj, info, points, normals, snapshot):
    """(readings, notes) of the sun (and the world, if any) at the meters, ``auto``, inside the step's guard.

    With a sky (a world) the sun's first bounce is read as emitters wherever it is proven (below). Without one
    the sun is rendered as it is; where a meter finds no light in its pilot, every meter stops there
    (``stop_dark="all"``). Where one is dark, the sunlit surfaces are too small for the meters' rays to find
    (a low sun's strip on a reveal): if the sun's first bounce is proven (``sun_bounce.plan``), every meter
    is read again with the sun hidden, its direct light in closed form (the meter's own, ``direct_only``)
    and its first bounce as Lambertian emitters that Cycles samples by next-event estimation; otherwise
    every meter is read again as before (the dark ones sampling on to ``DARK_FLOOR``)."""
    from ...radiometry.sampling import allocation
    from ..meter import point_meter as meter

    started = time.perf_counter()
    model = meter.capture_model(request.scene, request.view_layer)  # with the sun (and the sky) as set
    if request.scene.world is not None:
        # With a sky every meter finds light in its pilot, so a dark pilot cannot tell that the sun's light is
        # hard to find: the sun's first bounce is read as emitters wherever it is proven (measured in the demo
        # room with the overcast sky: 2.36 s against 2.6 s at midday, 3.2 s against 2.0-3.2 s at 2 deg).
        readings, reason, bounce = sun_bounce_readings(request, model, sun_obj, info, points, normals, snapshot)
        if readings is not None:
            for r in readings:
                r.notes = list(r.notes) + [bounce.notes[0]]
            return readings, ["with the sky, the sun's first bounce was read as emitters "
                              "(radiometry/scene/sun_patches.py; the readings' notes say more)"]
        return meter.measure_illuminance(points, normals, request, method="auto", model=model), [
            f"the sun rendered as it is ({reason})"]
    first = meter.measure_illuminance(points, normals, request, method="auto", stop_dark="all", model=model)
    dark = np.array([r.upper_bound_lux is not None for r in first])
    if not dark.any() and not any(allocation.DARK_PILOT in n for r in first for n in r.notes):
        return first, []  # every meter at its target: no meter was dark
    if request.time_budget_s is not None:  # the step's budget covers both passes
        spent = time.perf_counter() - started
        request = request.but(time_budget_s=max(request.time_budget_s - spent, 0.1 * request.time_budget_s))
    readings, reason, bounce = sun_bounce_readings(request, model, sun_obj, info, points, normals, snapshot)
    if readings is not None:
        found = f"{max(int(dark.sum()), 1)} of {len(dark)} meters found no sunlight in their pilot: "
        for r in readings:
            r.notes = list(r.notes) + [found + bounce.notes[0]]
        return readings, ["where meters found no sunlight in their pilot, the sun's first bounce was read as "
                          "emitters (radiometry/scene/sun_patches.py; the readings' notes say more)"]
    readings = meter.measure_illuminance(points, normals, request, method="auto", model=model)
    for k in np.flatnonzero(dark):
        readings[k].notes = list(readings[k].notes) + [f"no sunlight found in the pilot: the sun rendered ({reason})"]
    return readings, ["where meters found no sunlight in their pilot they were read again with the sun rendered "
                      "where its first bounce is not proven (the readings' notes say why)"]


def sun_study_step(scene, *, locations, normals, when, latitude_deg, longitude_deg, elevation_m=0.0,
                   direct_normal_illuminance_lux=None, north_offset_deg=0.0, sky=None, quality="standard",
                   method="auto", seed=0, cancelled=None, sky_horizontal_illuminance_lux=None, time_budget_s=None,
                   efficacy=None):
    """Illuminance from the sun (and ``sky``) at one time; the scene is as before afterwards. A task of plain
    values (it may run on a cluster's copy of the scene): its request is built here with the caller's
    ``efficacy`` (lm/W; None: the scene's as the api reads it).

    ``locations``/``normals``: (N, 3) scene coordinates; ``when``: a timezone-aware datetime;
    ``time_budget_s``: seconds for this step's measurement (it stops at the quality's target or the
    budget, whichever comes first; the reached error is in ``rel_std_error``).
    Returns a dict of plain arrays: ``illuminance`` (N,) lux, ``rel_std_error`` (N,), ``exact``
    (N,), ``sunlit`` (N,) bool, ``sunlit_fraction`` (N,), ``azimuth_deg``, ``elevation_deg``,
    ``direct_normal_illuminance_lux``, ``method``, ``seconds``.
    """
    import bpy

    from ... import quality as quality_presets
    from ..meter import point_meter as meter
    from ..blender import request as request_of, scene_guard
    from ..authoring import sun
    from .light_isolation import rendering_light_objects

    start = time.perf_counter()
    request = request_of.build(
        scene, efficacy=efficacy, quality=quality, seed=seed, cancelled=cancelled, time_budget_s=time_budget_s,
        # with a budget the meter drops the preset's target unless it is given: give it, so whichever comes
        # first stops the step
        target_rel_error=quality_presets.PRESETS[quality]["target"] if time_budget_s is not None else None)
    scene = request.scene
    points, _single = meter.as_points(locations, "locations")
    normals = meter.as_directions(normals, len(points), "normals")
    n = len(points)
    with scene_guard.preserved_scene(scene) as snapshot:
        model = meter.capture_model(scene, request.view_layer)
        for ob in rendering_light_objects(scene, model):
            snapshot.remember(ob, "hide_render")
            ob.hide_render = True
        scene.world = None  # the guard puts the user's world back
        data = bpy.data.lights.new("Radiometer sun-study sun", "SUN")
        obj = bpy.data.objects.new(data.name, data)
        scene.collection.objects.link(obj)
        info = sun.set_sun(request, latitude_deg, longitude_deg, when,
                           direct_normal_illuminance_lux=direct_normal_illuminance_lux,
                           north_offset_deg=north_offset_deg, elevation_m=elevation_m, sun=obj)
        direction = np.asarray(info["direction"], float)
        if sky is not None:
            _set_sky(request, sky, direction, sky_horizontal_illuminance_lux)
        request.view_layer.update()
        out = {"azimuth_deg": info["azimuth_deg"], "elevation_deg": info["elevation_deg"],
               "direct_normal_illuminance_lux": info["direct_normal_illuminance_lux"]}
        sunlit_fraction = np.zeros(n)
        if info["above_horizon"]:
            geometry = model.geometry
            scale = request.scale_length
            if geometry.count:
                mask = geometry.shadow_triangles() & np.asarray(geometry.opaque, bool)
                tris = geometry.triangles[mask]
                from ...radiometry.scene.scene_model import length_tolerance

                points_m = points * scale
                blocked = rays_blocked(points_m, disc_directions(direction), tris, 4.0 * length_tolerance(points_m))
                sunlit_fraction = 1.0 - blocked.mean(axis=1)
                centre_clear = ~blocked[:, 0]
            else:
                sunlit_fraction, centre_clear = np.ones(n), np.ones(n, bool)
        else:
            centre_clear = np.zeros(n, bool)
        if info["above_horizon"] or sky is not None:
            if info["above_horizon"] and method == "auto":
                readings, out["notes"] = _measure_sun(request, obj, info, points, normals, snapshot)
            else:
                readings = meter.measure_illuminance(points, normals, request, method=method)
            out["illuminance"] = np.array([r.illuminance for r in readings])
            out["rel_std_error"] = np.array([r.rel_std_error for r in readings])
            out["exact"] = np.array([bool(r.exact) for r in readings])
            out["method"] = batch_method(readings)
        else:  # no sun, no sky: nothing to measure
            out["illuminance"], out["rel_std_error"] = np.zeros(n), np.zeros(n)
            out["exact"], out["method"] = np.ones(n, bool), "below horizon"
    out.setdefault("notes", [])
    out["sunlit"] = centre_clear & bool(info["above_horizon"])
    out["sunlit_fraction"] = sunlit_fraction
    out["seconds"] = time.perf_counter() - start
    return out


# --- the study -------------------------------------------------------------------------------------

@dataclasses.dataclass
class SunStudyResult:
    """``illuminance`` (T, N) lux, ``rel_std_error`` (T, N), ``exact`` (T, N), ``sunlit`` (T, N) bool,
    ``sunlit_fraction`` (T, N), ``sun`` (per time: time, azimuth_deg, elevation_deg,
    direct_normal_illuminance_lux), ``sample_hours`` (T,) h, ``sunlight_hours`` (N,) h, ``locations``
    and ``normals`` (N, 3), ``seconds`` per step, ``notes``."""

    times: list
    locations: np.ndarray
    normals: np.ndarray
    illuminance: np.ndarray
    rel_std_error: np.ndarray
    exact: np.ndarray
    sunlit: np.ndarray
    sunlit_fraction: np.ndarray
    sun: list
    sample_hours: np.ndarray
    sunlight_hours: np.ndarray
    seconds: np.ndarray
    min_elevation_deg: float = 0.0
    notes: list = dataclasses.field(default_factory=list)

    def to_dict(self):
        return {"times": [t.isoformat() for t in self.times], "locations": self.locations.tolist(),
                "normals": self.normals.tolist(), "illuminance_lx": self.illuminance.tolist(),
                "rel_std_error": self.rel_std_error.tolist(), "exact": self.exact.tolist(),
                "sunlit": self.sunlit.tolist(), "sunlit_fraction": self.sunlit_fraction.tolist(), "sun": self.sun,
                "sample_hours": self.sample_hours.tolist(), "sunlight_hours": self.sunlight_hours.tolist(),
                "min_elevation_deg": self.min_elevation_deg, "seconds_per_step": self.seconds.tolist(),
                "notes": list(self.notes)}

    def csv_text(self):
        """One row per (time, point): time, point, x, y, z, illuminance_lx, rel_std_error, exact, sunlit,
        sunlit_fraction, sun azimuth/elevation (deg)."""
        lines = ["time,point,x,y,z,illuminance_lx,rel_std_error,exact,sunlit,sunlit_fraction,sun_azimuth_deg,"
                 "sun_elevation_deg"]
        for i, t in enumerate(self.times):
            for k, p in enumerate(self.locations):
                lines.append(f"{t.isoformat()},{k},{p[0]:.6g},{p[1]:.6g},{p[2]:.6g},{self.illuminance[i, k]:.8g},"
                             f"{self.rel_std_error[i, k]:.4g},{int(self.exact[i, k])},{int(self.sunlit[i, k])},"
                             f"{self.sunlit_fraction[i, k]:.4g},{self.sun[i]['azimuth_deg']:.6f},"
                             f"{self.sun[i]['elevation_deg']:.6f}")
        return "\n".join(lines) + "\n"


def _check_times(times):
    if isinstance(times, _dt.datetime):
        times = [times]
    times = list(times)
    if not times:
        raise RadiometerError("no times given: pass a sequence of timezone-aware datetimes")
    return times


def sun_study(locations, normals, times, *, request, latitude_deg, longitude_deg, elevation_m=0.0,
              direct_normal_illuminance_lux=None, sky=None, north_offset_deg=0.0, min_elevation_deg=0.0,
              method="auto", sky_horizontal_illuminance_lux=None):
    """See ``radiometer.api.sun_study``. The request gives the scene, ``quality`` (None: "standard"),
    ``time_budget_s`` (per step), the seed, progress, cancel and ``client``; the steps carry its efficacy."""
    from ..meter import point_meter as meter
    from ..authoring import sun

    scene, quality, time_budget_s, seed = request.scene, request.quality or "standard", request.time_budget_s, request.seed
    progress, cancelled, client = request.progress, request.cancelled, request.client
    points, _ = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    times = _check_times(times)
    pos = sun.sun_position(latitude_deg, longitude_deg, times, elevation_m=elevation_m,
                           north_offset_deg=north_offset_deg)
    n_t = len(times)
    if direct_normal_illuminance_lux is None:
        dni = [None] * n_t
    else:
        dni = np.broadcast_to(np.asarray(direct_normal_illuminance_lux, float), (n_t,))
        if not np.all(np.isfinite(dni)) or np.any(dni < 0):
            raise RadiometerError("direct normal illuminance must be finite and >= 0 lux (one value or one per time)")
        dni = [float(v) for v in dni]
    if sky is not None:
        from ...radiometry.skies import sky_models

        try:
            sky = sky_models.sky_model(sky).name  # the workers get the mapping's name
        except ValueError as exc:
            raise RadiometerError(f"sky must be None or a sky model: {exc}") from None
    if quality not in ("preview", "standard", "reference"):
        raise RadiometerError(f"unknown quality {quality!r}; choose preview, standard or reference")
    if time_budget_s is not None and not (float(time_budget_s) > 0 and math.isfinite(float(time_budget_s))):
        raise RadiometerError(f"time_budget_s must be > 0 seconds per time step, got {time_budget_s}")
    if not math.isfinite(min_elevation_deg):
        raise RadiometerError("min_elevation_deg must be finite")
    common = dict(locations=points, normals=dirs, latitude_deg=float(latitude_deg),
                  longitude_deg=float(longitude_deg), elevation_m=float(elevation_m),
                  north_offset_deg=float(north_offset_deg), sky=sky, quality=quality, method=method,
                  sky_horizontal_illuminance_lux=sky_horizontal_illuminance_lux, time_budget_s=time_budget_s,
                  efficacy=request.efficacy)
    tasks = [dict(common, when=times[i], direct_normal_illuminance_lux=dni[i], seed=int(seed) + 1009 * i)
             for i in range(n_t)]
    started = time.perf_counter()
    if client is not None:
        try:
            from ...cluster import run_scene_tasks
        except ImportError:
            raise RadiometerError("client= needs radiometer.cluster.run_scene_tasks (the Dask scale-out), "
                                  "which is unavailable in this build") from None
        steps = run_scene_tasks(scene, sun_study_step, tasks, client=client, progress=progress,
                                cancelled=cancelled, label="sun study")
    else:
        steps = []
        for i, kwargs in enumerate(tasks):
            if cancelled is not None and cancelled():
                raise MeasurementCancelled("sun study cancelled; the scene is as it was")
            steps.append(sun_study_step(scene, cancelled=cancelled, **kwargs))
            if progress is not None:
                spent = time.perf_counter() - started
                progress(int(1000 * (i + 1) / n_t), 1000, spent / (i + 1) * (n_t - i - 1))
    stack = lambda key, dtype=float: np.array([np.asarray(s[key], dtype) for s in steps])  # noqa: E731
    sunlit = stack("sunlit", bool)
    weights = sample_hours(pos.unix_s)
    high = np.atleast_1d(pos.elevation_deg) >= min_elevation_deg
    hours = (weights * high) @ sunlit.astype(float)
    sun_rows = [{"time": times[i].isoformat(), "azimuth_deg": float(np.atleast_1d(pos.azimuth_deg)[i]),
                 "elevation_deg": float(np.atleast_1d(pos.elevation_deg)[i]),
                 "direct_normal_illuminance_lux": float(steps[i]["direct_normal_illuminance_lux"]),
                 "method": steps[i]["method"]} for i in range(n_t)]
    step_notes = list(dict.fromkeys(n for step in steps for n in step.get("notes", ())))
    notes = ["sunlit: the ray to the centre of the sun's disc meets no opaque shadow-casting surface; sunlight "
             "hours: each time sample counts for half the gaps to its neighbours (trapezoid rule)"
             + (f", sun at least {min_elevation_deg:g} deg high" if min_elevation_deg else ""),
             "illuminance: the sun" + (f" and the {sky} sky (the same horizontal illuminance at every time: "
                                       f"{sky_horizontal_illuminance_lux or 'set_cie_sky default'} lx)" if sky
                                       else " alone (other lights and the world off)")] + step_notes
    return SunStudyResult(times=times, locations=points, normals=dirs, illuminance=stack("illuminance"),
                          rel_std_error=stack("rel_std_error"), exact=stack("exact", bool), sunlit=sunlit,
                          sunlit_fraction=stack("sunlit_fraction"), sun=sun_rows, sample_hours=weights,
                          sunlight_hours=hours, seconds=np.array([s["seconds"] for s in steps]),
                          min_elevation_deg=float(min_elevation_deg), notes=notes)

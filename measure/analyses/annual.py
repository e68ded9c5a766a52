"""Annual climate-based daylight by daylight coefficients (issue 19 item 6), the two-phase way.

1. Daylight coefficients DC[p, i] (lux per cd/m^2) for every sky patch p (``radiometry.skies.sky_patches``:
   Reinhart MF:m, patch 0 the ground) at every point i, with their covariance.
   ``method="dome"`` (default): ONE render for all patches (``measure.analyses.daylight_coefficients``: a
   dome of emitting patch objects, one Cycles light group each, seen by a custom camera whose pixel
   blocks are the meters' cosine-weighted hemispheres), repeated in a few rounds for the error.
   ``method="per_patch"``: the older way, one meter measurement per patch with a one-patch world
   (``patch_coefficients``; 146 renders for Tregenza: kept for comparison).
2. Sky vectors: per hour of the EPW file the Perez all-weather sky (``radiometry.skies.perez``) gives each
   patch's luminance, the sun's direct normal illuminance spread over its 4 nearest patches (as
   Radiance's gendaymtx does for the two-phase method), and the ground rho_g E_gh / pi.
3. Hourly illuminance E = S DC (T x N) with its standard error sqrt(S_t C_i S_t) from the coefficients'
   covariance C_i; sDA (300 lx, 50 %) and UDI on E; each point's sDA verdict is also taken with every
   hour moved down and up by 2 standard errors, and a point whose verdict changes is reported as
   uncertain (``sda_range``: the sDA with the uncertain points failing / passing).
4. ASE (1000 lx, 250 h) from the DIRECT sun only, as IES LM-83-12 asks (no interreflection, no sky):
   E_sun = E_dn max(0, n . s) T(s) per hour, a closed form: E_dn the hour's direct normal illuminance
   (Perez efficacy), s the sun's true direction (SPA), the ray from the point to the sun's centre
   tested against every opaque shadow-casting triangle (0 when blocked), T the luminance-weighted
   transmittance of the thin panes it crosses (``radiometry.scene.thin_glass``, at their incidence angle).
   Metrics over the occupied hours (8 am to 6 pm local standard time, record midpoints).

Not LM-83 to the letter: the sky and the sun of step 2 are the two-phase approximation (the sun
smeared over 4 patches for sDA and UDI, as Radiance's two-phase method does); the direct sun of step
4 is tested along the centre ray only (a point within the penumbra's 0.27 deg is in or out whole).
The scene is restored after every render.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...errors import RadiometerError

#: Luminance of the one emitting patch while its coefficients are rendered (cd/m^2).
PATCH_LUMINANCE = 1000.0


def _value(tree, v, x, y):
    node = tree.nodes.new("ShaderNodeValue")
    node.outputs[0].default_value = float(v)
    node.location = (x, y)
    return node


def _math(tree, op, a, b, x, y):
    from ..authoring.sky import math_socket

    out = math_socket(tree, op, a, b)
    out.node.location = (x, y)
    return out


def build_patch_world(world):
    """Fill ``world``'s tree with the patch-selector shader; returns the dict of Value nodes to set
    (alt_lo, alt_hi, az_lo, az_width, radiance)."""
    from ...compat import ensure_node_tree

    tree = ensure_node_tree(world)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputWorld")
    bg = tree.nodes.new("ShaderNodeBackground")
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(bg.outputs[0], out.inputs["Surface"])
    coord = tree.nodes.new("ShaderNodeTexCoord")
    norm = tree.nodes.new("ShaderNodeVectorMath")
    norm.operation = "NORMALIZE"
    tree.links.new(coord.outputs["Generated"], norm.inputs[0])
    sep = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(norm.outputs["Vector"], sep.inputs[0])
    v = {name: _value(tree, 0.0, -600, -120 * k) for k, name in
         enumerate(("alt_lo", "alt_hi", "az_lo", "az_width", "radiance"))}
    alt = _math(tree, "ARCSINE", sep.outputs["Z"], 0.0, -300, 0)
    az = _math(tree, "ARCTAN2", sep.outputs["X"], sep.outputs["Y"], -300, -150)  # from +Y towards +X
    rel = _math(tree, "FLOORED_MODULO", _math(tree, "SUBTRACT", az, v["az_lo"].outputs[0], -150, -150),
                2 * math.pi, 0, -150)
    inside = _math(tree, "MULTIPLY",
                   _math(tree, "MULTIPLY", _math(tree, "GREATER_THAN", alt, v["alt_lo"].outputs[0], 0, 0),
                         _math(tree, "LESS_THAN", alt, v["alt_hi"].outputs[0], 0, 100), 150, 50),
                   _math(tree, "LESS_THAN", rel, v["az_width"].outputs[0], 150, -150), 300, 0)
    tree.links.new(_math(tree, "MULTIPLY", inside, v["radiance"].outputs[0], 450, 0), bg.inputs["Strength"])
    return v


def _select_patch(values, patches, p, radiance):
    last = p == patches.count - 1
    values["alt_lo"].outputs[0].default_value = -2.0 if p == 0 else float(patches.alt_lo[p])
    values["alt_hi"].outputs[0].default_value = 0.0 if p == 0 else (2.0 if last else float(patches.alt_hi[p]))
    full = p == 0 or last
    values["az_lo"].outputs[0].default_value = 0.0 if full else float(patches.az_lo[p])
    values["az_width"].outputs[0].default_value = 10.0 if full else float(patches.az_hi[p] - patches.az_lo[p])
    values["radiance"].outputs[0].default_value = float(radiance)


def patch_coefficients(scene, *, locations, normals, patch_indices, m=1, quality="preview", samples=None,
                       target_rel_error=None, seed=0, cancelled=None, efficacy=None):
    """One task: daylight coefficients (len(patch_indices), N) lux per cd/m^2 and their standard
    errors, for these patches; every light hidden, the world a one-patch world (scene restored).
    A task carries plain values (it may run on a cluster's copy of the scene): its request is built
    here, with the caller's ``efficacy`` (lm/W; None: the scene's as the api reads it)."""
    import bpy

    from ...radiometry.skies import sky_patches
    from ..meter import point_meter as meter
    from ..blender import request as request_of, scene_guard
    from .light_isolation import rendering_light_objects

    request = request_of.build(scene, efficacy=efficacy, quality=quality, samples=samples,
                               target_rel_error=target_rel_error, cancelled=cancelled)
    patches = sky_patches.reinhart_patches(m)
    points, _single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    radiance = PATCH_LUMINANCE / request.efficacy * request.unit_area
    dc = np.zeros((len(patch_indices), len(points)))
    se = np.zeros_like(dc)
    with scene_guard.preserved_scene(scene) as snapshot:
        model = meter.capture_model(scene, request.view_layer)
        for ob in rendering_light_objects(scene, model):
            snapshot.remember(ob, "hide_render")
            ob.hide_render = True
        world = bpy.data.worlds.new("Radiometer sky patch")
        values = build_patch_world(world)
        scene.world = world
        for k, p in enumerate(patch_indices):
            if cancelled is not None and cancelled():
                from ...errors import MeasurementCancelled

                raise MeasurementCancelled("annual daylight cancelled")
            _select_patch(values, patches, int(p), radiance)
            rs = meter.measure_illuminance(points, dirs, request.but(seed=seed + k, cancelled=None), method="render")
            rs = rs if isinstance(rs, list) else [rs]
            dc[k] = [r.illuminance / PATCH_LUMINANCE for r in rs]
            se[k] = [np.nan_to_num(r.rel_std_error) * r.illuminance / PATCH_LUMINANCE for r in rs]
    return dc, se


def coefficient_tasks(locations, normals, *, m=1, quality="preview", samples=None, target_rel_error=None, seed=0,
                      efficacy=None):
    """The :func:`patch_coefficients` kwargs of every chunk of 16 patches (chunk from patch s seeded
    ``seed + 7919 s``): the same list in this process and on a cluster."""
    from ...radiometry.skies import sky_patches

    count, chunk = sky_patches.reinhart_patches(m).count, 16
    return [dict(locations=locations, normals=normals, patch_indices=list(range(start, min(count, start + chunk))),
                 m=m, quality=quality, samples=samples, target_rel_error=target_rel_error, seed=seed + 7919 * start,
                 efficacy=efficacy)
            for start in range(0, count, chunk)]


def dome_task(scene, *, locations, normals, m=1, quality="preview", samples=None, seed=0, cancelled=None,
              progress=None, efficacy=None):
    """One task of the dome method: (DC (P, n), standard error (P, n), covariance (n, P, P)) of these
    points (``measure.analyses.daylight_coefficients.render_coefficients``); the scene is restored.
    Plain values, its request built here (as :func:`patch_coefficients`)."""
    from . import daylight_coefficients as dcm
    from ..meter import point_meter as meter
    from ..blender import request as request_of

    points, _single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    request = request_of.build(scene, efficacy=efficacy, quality=quality, samples=samples, seed=seed,
                               cancelled=cancelled, progress=progress)
    c = dcm.render_coefficients(points, dirs, request=request, m=m)
    return c.dc, c.std_error, c.covariance, c.notes


#: Points per dome task (fixed, so that a run gives the same numbers here and on any cluster).
DOME_CHUNK_POINTS = 256


def dome_tasks(locations, normals, *, m=1, quality="preview", samples=None, seed=0, efficacy=None):
    """The :func:`dome_task` kwargs of every chunk of ``DOME_CHUNK_POINTS`` points (chunk c seeded
    ``seed + 7919 c``)."""
    pts = np.asarray(locations, float).reshape(-1, 3)
    nrm = np.broadcast_to(np.asarray(normals, float).reshape(-1, 3), pts.shape)
    return [dict(locations=pts[s:s + DOME_CHUNK_POINTS], normals=nrm[s:s + DOME_CHUNK_POINTS], m=m, quality=quality,
                 samples=samples, seed=seed + 7919 * (s // DOME_CHUNK_POINTS), efficacy=efficacy)
            for s in range(0, len(pts), DOME_CHUNK_POINTS)]


def daylight_coefficients(locations, normals=(0.0, 0.0, 1.0), *, request, m=1, method="dome"):
    """(DC (P, N) lux per cd/m^2, standard error (P, N), covariance (N, P, P), notes) for every patch
    of Reinhart MF:m.

    ``method="dome"``: one render (in rounds) for every patch at once, in chunks of 256 points
    (:func:`dome_task`). ``method="per_patch"``: one measurement per patch, chunks of 16 patches
    seeded ``seed + 7919 s`` (:func:`patch_coefficients`; the covariance is then diagonal: patches
    rendered independently). Either way the same tasks run here or, with a Dask ``client``, on its
    workers (``radiometer.cluster.run_scene_tasks``), so the numbers are the same. The request gives the
    scene, ``quality`` (None: "preview"), ``samples``, ``target_rel_error``, the seed, progress, cancel and
    ``client``; the tasks carry its efficacy.
    """
    from ...radiometry.skies import sky_patches

    scene, quality, samples, seed = request.scene, request.quality or "preview", request.samples, request.seed
    target_rel_error, progress, cancelled, client = (request.target_rel_error, request.progress, request.cancelled,
                                                     request.client)
    count = sky_patches.reinhart_patches(m).count
    if method == "dome":
        from . import daylight_coefficients as dcm

        dcm.require_dome(scene)  # before any task is planned or sent to a cluster
        if target_rel_error is not None:
            raise RadiometerError("target_rel_error goes with method='per_patch'; the dome method takes quality "
                                  "or samples (its errors are stated per coefficient and per hour)")
        func, tasks = dome_task, dome_tasks(locations, normals, m=m, quality=quality, samples=samples, seed=seed,
                                            efficacy=request.efficacy)
    elif method == "per_patch":
        func, tasks = patch_coefficients, coefficient_tasks(locations, normals, m=m, quality=quality, samples=samples,
                                                            target_rel_error=target_rel_error, seed=seed,
                                                            efficacy=request.efficacy)
    else:
        raise RadiometerError(f"unknown daylight-coefficient method {method!r}: 'dome' or 'per_patch'")
    cov = None
    if client is not None:
        from ...cluster import run_scene_tasks

        parts = run_scene_tasks(scene, func, tasks, client=client, progress=progress, cancelled=cancelled,
                                label="annual daylight")
    else:
        parts, start = [], 0
        for k, task in enumerate(tasks):
            extra = {}
            if method == "dome" and progress is not None:  # per round inside the task
                extra["progress"] = lambda done, total, _eta, k=k: progress(k * total + done, len(tasks) * total, None)
            part = func(scene, cancelled=cancelled, **task, **extra)
            if method == "dome":
                # each task's covariances straight into the whole array (MF:2 x 1000 points: 2.7 GB, not twice that)
                if cov is None:
                    cov = np.empty((sum(len(t["locations"]) for t in tasks),) + part[2].shape[1:])
                cov[start:start + len(part[2])] = part[2]
                start += len(part[2])
                part = part[:2] + (None,) + part[3:]
            parts.append(part)
            if progress is not None:
                progress(k + 1, len(tasks), None)
    if method == "dome":
        dc = np.concatenate([p[0] for p in parts], axis=1)
        se = np.concatenate([p[1] for p in parts], axis=1)
        if cov is None:  # from a cluster: every task's result is here already
            cov = np.concatenate([p[2] for p in parts], axis=0)
        notes = parts[0][3]
    else:
        dc = np.concatenate([p[0] for p in parts])
        se = np.concatenate([p[1] for p in parts])
        cov = np.zeros((dc.shape[1], count, count))
        idx = np.arange(count)
        cov[:, idx, idx] = (se ** 2).T
        notes = [f"daylight coefficients over {count} patches (Reinhart MF:{m}), one render per patch"]
    return dc, se, cov, notes


def sky_matrix(weather, patches, *, ground_reflectance=0.2, north_offset_deg=0.0, year=2026):
    """``SkyMatrix`` of the EPW records: patch luminances (cd/m^2, sky + sun, two-phase), the sun's
    direct normal illuminance and direction, the records' local midpoint hours."""
    from ...radiometry.skies import perez
    from ...radiometry.sun import solar_position

    times = weather.midpoint_datetimes(year)
    unix = solar_position.unix_seconds(times)
    pos = solar_position.solar_position(unix, weather.latitude_deg, weather.longitude_deg,
                                        elevation_m=weather.elevation_m, north_offset_deg=north_offset_deg)
    directions = np.asarray(pos.direction, float)
    doy = np.array([t.timetuple().tm_yday for t in times])
    # The reader's checks (radiometry/sun/epw.py): in usable hours a value that is missing or negative has
    # the sun down (taken as 0, noted); unusable hours get no sky and are left out of the metrics.
    usable = np.ones(len(times), bool) if weather.usable is None else weather.usable
    dni = np.where(usable, np.clip(np.nan_to_num(weather.direct_normal_w_m2), 0.0, None), 0.0)
    dhi = np.where(usable, np.clip(np.nan_to_num(weather.diffuse_horizontal_w_m2), 0.0, None), 0.0)
    dew = np.where(np.isfinite(weather.dew_point_c), weather.dew_point_c, 11.0)
    s_all = np.zeros((len(times), patches.count))
    s_sun = np.zeros_like(s_all)
    e_dn = np.zeros(len(times))
    for t in range(len(times)):
        s_all[t], info = perez.sky_vector(patches, directions[t], dni[t], dhi[t], doy[t], dew[t], ground_reflectance)
        s_sun[t], _ = perez.sky_vector(patches, directions[t], dni[t], dhi[t], doy[t], dew[t], 0.0, include_sky=False)
        e_dn[t] = info["direct_normal_lux"] if directions[t][2] > 0 else 0.0
    return SkyMatrix(s_all, s_sun, e_dn, directions, weather.midpoint_hours())


@dataclasses.dataclass
class SkyMatrix:
    """``sky`` (T, P) patch luminances (cd/m^2, sun included, two-phase), ``sun_patches`` (T, P) the
    sun's part of it (over its 4 nearest patches), ``direct_normal_lux`` (T,)
    of the sun (0 below the horizon), ``sun_direction`` (T, 3) towards the sun, ``hours`` (T,) local
    standard time of the record midpoints."""

    sky: np.ndarray
    sun_patches: np.ndarray
    direct_normal_lux: np.ndarray
    sun_direction: np.ndarray
    hours: np.ndarray


def direct_sun(model, points_m, normals, sun_direction, direct_normal_lux, weights):
    """(T, N) lux of the direct sun alone (module docstring, step 4): E_dn max(0, n . s) T, the
    centre ray to the sun tested against opaque shadow-casting triangles; thin panes crossed give
    their luminance-weighted transmittance at the incidence angle. Pure numpy on the scene model."""
    from ...radiometry.scene.scene_model import length_tolerance
    from .sun_study import rays_blocked

    points_m = np.asarray(points_m, float)
    normals = np.asarray(normals, float)
    s = np.asarray(sun_direction, float)
    out = np.zeros((len(s), len(points_m)))
    up = np.flatnonzero((s[:, 2] > 0) & (np.asarray(direct_normal_lux) > 0))
    if not len(up):
        return out
    cos = np.maximum(normals @ s[up].T, 0.0).T  # (U, N)
    factor = np.ones_like(cos)
    geometry = model.geometry
    if geometry.count:
        tol = 4.0 * length_tolerance(points_m)
        opaque = geometry.shadow_triangles() & np.asarray(geometry.opaque, bool)
        factor *= ~rays_blocked(points_m, s[up], geometry.triangles[opaque], tol).T
        for obj, pane in model.panes.items():
            tris = geometry.triangles[geometry.pane_of == obj]
            crossed = rays_blocked(points_m, s[up], tris, tol).T  # (U, N)
            if not crossed.any():
                continue
            cos_i = np.abs(s[up] @ np.asarray(pane.geometry.normal, float))
            t_rgb = np.stack([np.asarray(pane.optics(c)[0], float) for c in cos_i])  # (U, 3)
            factor *= np.where(crossed, (t_rgb @ np.asarray(weights, float))[:, None], 1.0)
    out[up] = np.asarray(direct_normal_lux)[up, None] * cos * factor
    return out


@dataclasses.dataclass
class AnnualResult:
    """``illuminance`` (T, N) lux (sky + sun), ``illuminance_std_error`` (T, N), ``sun_illuminance``
    (T, N) lux of the direct sun alone (for ASE), ``occupied`` (T,), ``sda`` (fraction of points),
    ``sda_range`` (low, high: the uncertain points failing / passing), ``sda_point_fraction`` (N,),
    ``sda_uncertain`` (N,) bool, ``sda_point_fraction_bounds`` (low (N,), high (N,): the share of hours
    at 300 lx with every hour 2 standard errors lower / higher), ``ase``, ``ase_hours`` (N,), ``udi``
    (fell_short, useful, exceeded: (N,) each), ``max_rel_std_error`` of the hourly values over occupied
    hours at 100 lx or more, ``seconds_coefficients``, ``notes``, ``weather_period`` (the EPW records'
    span) and ``whole_year`` (False: the metrics cover only that period, asked for explicitly);
    ``sun_direction`` (T, 3), ``direct_normal_lux`` (T,) and ``hours`` (T,) of the sky matrix (the annual
    DGP's sun)."""

    locations: np.ndarray
    illuminance: np.ndarray
    illuminance_std_error: np.ndarray
    sun_illuminance: np.ndarray
    occupied: np.ndarray
    sda: float
    sda_range: tuple
    sda_point_fraction: np.ndarray
    sda_uncertain: np.ndarray
    sda_point_fraction_bounds: tuple
    ase: float
    ase_hours: np.ndarray
    udi: tuple
    max_rel_std_error: float
    seconds_coefficients: float
    notes: list
    weather_period: str = ""
    whole_year: bool = True
    sun_direction: np.ndarray = None
    direct_normal_lux: np.ndarray = None
    hours: np.ndarray = None

    def to_dict(self):
        return {"locations": np.asarray(self.locations).tolist(), "sda_300_50": self.sda,
                "sda_300_50_range": [float(v) for v in self.sda_range],
                "ase_1000_250h": self.ase, "ase_from": "direct sun only (closed form, LM-83)",
                "sda_point_fraction": self.sda_point_fraction.tolist(),
                "sda_point_uncertain": [bool(v) for v in self.sda_uncertain],
                "sda_point_fraction_low": self.sda_point_fraction_bounds[0].tolist(),
                "sda_point_fraction_high": self.sda_point_fraction_bounds[1].tolist(),
                "ase_hours": self.ase_hours.tolist(),
                "udi_fell_short": self.udi[0].tolist(), "udi_useful": self.udi[1].tolist(),
                "udi_exceeded": self.udi[2].tolist(), "occupied_hours": int(np.sum(self.occupied)),
                "max_rel_std_error": self.max_rel_std_error, "seconds_coefficients": self.seconds_coefficients,
                "weather_period": self.weather_period, "whole_year": self.whole_year, "notes": self.notes}

    def csv_text(self):
        lines = ["x,y,z,sda_hours_fraction,sda_uncertain,ase_hours,udi_fell_short,udi_useful,udi_exceeded"]
        for i, p in enumerate(np.asarray(self.locations)):
            lines.append(f"{p[0]:.6g},{p[1]:.6g},{p[2]:.6g},{self.sda_point_fraction[i]:.4f},"
                         f"{int(bool(self.sda_uncertain[i]))},{int(self.ase_hours[i])},"
                         f"{self.udi[0][i]:.4f},{self.udi[1][i]:.4f},{self.udi[2][i]:.4f}")
        return "\n".join(lines) + "\n"


def weather_period_notes(weather, source, partial_period):
    """[] for a whole year; for a shorter file a note saying the period when ``partial_period``,
    else RadiometerError (annual metrics from part of a year would pass as annual)."""
    if weather.is_full_year:
        return []
    if not partial_period:
        raise RadiometerError(f"{source}: {weather.period}, not a whole year (8760 hourly records, 8784 with "
                              "29 February): annual metrics refused; to compute them over this period ask for it "
                              "(partial_period=True, CLI --partial-period)")
    return [f"partial period, NOT annual: {weather.period}; sDA and UDI are shares of its occupied hours and "
            "ASE counts its hours against 250 h"]


def hourly_std_error(sky, covariance):
    """(T, N) standard error of E = sky @ DC from each point's coefficient covariance (N, P, P)."""
    out = np.empty((sky.shape[0], covariance.shape[0]))
    for i, c in enumerate(covariance):
        out[:, i] = np.sqrt(np.maximum(np.einsum("tp,tp->t", sky @ c, sky), 0.0))
    return out


def annual_daylight(locations, normals=(0.0, 0.0, 1.0), epw_path=None, *, request, m=1, ground_reflectance=0.2,
                    north_offset_deg=0.0, occupied_from=8.0, occupied_to=18.0, method="dome", partial_period=False):
    """Annual daylight metrics at points from an EPW file (module docstring). Returns ``AnnualResult``.
    The request as in :func:`daylight_coefficients` (its ``client``: a Dask client for the coefficients);
    ``method``: "dome" (one render for all patches) or "per_patch"; ``partial_period``: True to accept
    a file that is not a whole year (the notes say the period), else such a file is refused."""
    import time

    from ...radiometry.metrics import daylight_metrics
    from ...radiometry.sun import epw
    from ...radiometry.skies import sky_patches
    from ..meter import point_meter as meter

    if epw_path is None:
        raise RadiometerError("annual daylight needs an EPW weather file (epw_path)")
    if not isinstance(partial_period, (bool, np.bool_)):
        raise RadiometerError(f"partial_period must be True or False, got {partial_period!r}")
    try:
        weather = epw.read_epw(epw_path)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    period_notes = weather_period_notes(weather, epw_path, partial_period)
    try:
        rho = float(ground_reflectance)
    except (TypeError, ValueError):
        rho = float("nan")
    if not (math.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise RadiometerError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    points, _single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    patches = sky_patches.reinhart_patches(m)
    start = time.perf_counter()
    dc, dc_se, cov, dc_notes = daylight_coefficients(points, dirs, request=request, m=m, method=method)
    seconds_dc = time.perf_counter() - start
    sky = sky_matrix(weather, patches, ground_reflectance=rho, north_offset_deg=north_offset_deg)
    occupied_all = daylight_metrics.occupied_hours(sky.hours, occupied_from, occupied_to)
    occupied = occupied_all & weather.usable
    e = sky.sky @ dc
    se = np.zeros_like(e)
    se[occupied] = hourly_std_error(sky.sky[occupied], cov)
    model = meter.capture_model(request.scene, request.view_layer)
    weights, scale = request.weights, request.scale_length
    e_sun = direct_sun(model, points * scale, dirs, sky.sun_direction, sky.direct_normal_lux, weights)
    try:
        sda, frac = daylight_metrics.sda(e, occupied)
        _lo, frac_lo = daylight_metrics.sda(e - 2 * se, occupied)
        _hi, frac_hi = daylight_metrics.sda(e + 2 * se, occupied)
        ase, ase_h = daylight_metrics.ase(e_sun, occupied)
        udi = daylight_metrics.udi(e, occupied)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    uncertain = (frac_lo >= 0.5) != (frac_hi >= 0.5)
    sda_range = (float(np.mean(frac_lo >= 0.5)), float(np.mean(frac_hi >= 0.5)))
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(e > 0, se / e, 0.0)
    notes = [f"{weather.city}, {weather.latitude_deg:.2f} N {weather.longitude_deg:.2f} E: {weather.count} hourly "
             f"records, {int(occupied.sum())} occupied (local standard time {occupied_from:g}-{occupied_to:g} h)"]
    notes += dc_notes
    big = dc > 0.01 * dc.max(axis=0, keepdims=True)  # the coefficients that carry a point's light
    if big.any():
        rel_dc = dc_se[big] / dc[big]
        notes.append(f"coefficients' relative standard error (those above 1 % of a point's largest): median "
                     f"{100 * np.median(rel_dc):.2g} %, 95th percentile {100 * np.percentile(rel_dc, 95):.2g} %; "
                     "propagated with their covariance to every hour")
    notes.append(f"Perez all-weather sky per hour over {patches.count} patches (Reinhart MF:{m}, patch 0 the ground); "
                 "the sun spread over its 4 nearest patches for sDA and UDI (two-phase approximation)")
    notes.append("ASE from the direct sun alone (LM-83: no interreflection): E_dn max(0, n.s) x thin-glass "
                 "transmittance, the ray to the sun's centre tested against opaque triangles")
    if model.refractors:
        notes.append("transmitting objects that are not thin panes let the direct sun through unchanged in ASE: "
                     + ", ".join(name for name, _why in model.refractors))
    if uncertain.any():
        notes.append(f"{int(uncertain.sum())} point(s) have an sDA verdict that changes within 2 standard errors of "
                     f"their hourly illuminance (near 300 lx for about half of the hours): sDA "
                     f"{100 * sda_range[0]:.1f}-{100 * sda_range[1]:.1f} %")
    dew_missing = int(np.sum(occupied & ~np.isfinite(weather.dew_point_c)))
    if dew_missing:
        notes.append(f"dew point missing (99.9) in {dew_missing} occupied hours: 11 deg C taken there (Perez's "
                     "luminous efficacy uses it for the atmosphere's water)")
    left_out = int(np.sum(occupied_all & ~weather.usable))
    if left_out:
        notes.append(f"{left_out} occupied hours left out of sDA, ASE and UDI (their irradiance is unusable, "
                     "see the weather notes); their hourly illuminance is NaN")
    notes += period_notes + weather.notes
    e[~weather.usable] = np.nan
    e_sun[~weather.usable] = np.nan
    lit = occupied[:, None] & (e >= 100.0)  # dimmer hours count as "fell short" whatever their error
    return AnnualResult(points, e, se, e_sun, occupied, sda, sda_range, frac, uncertain, (frac_lo, frac_hi), ase,
                        ase_h, udi, float(np.max(rel[lit])) if lit.any() else 0.0, seconds_dc, notes,
                        weather.period, weather.is_full_year, sky.sun_direction, sky.direct_normal_lux,
                        sky.hours)

"""Daylight factor: DF = 100 x E_in / E_out,h under the CIE overcast sky (issue 19).

Inside ``scene_guard.preserved_scene`` every rendering light (sun lights and instanced lights too)
is hidden in renders and the world is replaced by a temporary traditional CIE overcast sky
(``measure.authoring.sky``: L = Lz (1 + 2 cos Z) / 3, E_out,h = 10 000 lx, a uniform ground of luminance
rho_g E_h / pi below a sharp horizon); the ordinary meter measures (exact where nothing lies above a
meter's horizon, rendered with a stated error through windows); the guard then restores the
user's world, lights and data-blocks. With ``method="auto"``, where ``measure.analyses.sky_component``
proves the sky component (SC: convex open openings in a closed opaque room, nothing outside in the
way), the reading is the SC in closed form plus a render of the rest only (the sky's direct emission
gated off, ``sky_component.gate_world``; the target counts the SC), and it reports ``sky_component``
and ``reflected_component``; elsewhere the whole is rendered, and the notes say why. ``method="camera"`` measures through the meter camera of
``measure.analyses.daylight_coefficients`` instead of sensor bakes (cosine-weighted rays from each point, a
fixed number per quality, the error stated; measured 7-80x less time per point for the same variance
at 3 points of the side-lit test room, 2.2x on its 100-point bench grid: docs/daylight-sky.md). Emitting surfaces (emission shaders) are NOT switched off:
they are counted as daylight (a note says so when the scene has any).

Grid form (``daylight_factor_grid``): the work plane's points as ``measure.analyses.grid`` lays them out,
with the average (BS 8206-2 / CIBSE LG10 average daylight factor: the mean over the working plane),
minimum, maximum, median, uniformity (min / average), the share of the plane at or above a target
DF, and EN 17037:2018 (Table A.1 levels, target D_T = 100 E_T / E_v,d over 50 % of the plane and
minimum target D_TM = 100 E_TM / E_v,d over 95 %) when the site's median external diffuse
illuminance E_v,d is given (EN 17037 Annex A tabulates it per CEN capital; pass the value for the
site: Radiometer ships no table).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...errors import RadiometerError
from ...radiometry.metrics import en17037

#: Unobstructed horizontal illuminance of the temporary overcast sky (lux); DF does not depend on it.
SKY_HORIZONTAL_LUX = 10_000.0


@dataclasses.dataclass
class DaylightFactorReading:
    """``daylight_factor`` (%) and its 1-sigma ``rel_std_error``; ``illuminance`` (lux) under an
    overcast sky of ``sky_horizontal_lux``; ``exact``, ``method``, ``notes`` from the meter.
    ``sky_component`` (%): the direct sky through the openings, proven in closed form (no error), and
    ``reflected_component`` (%): the rest, rendered (externally + internally reflected light, the
    ground seen through the openings); both None where the sky component was not proven.
    The BRE split-flux parts where the openings were made emitters of the sky and ground (nothing outside them; with
    a ground plane in front, below them, they emit the sky alone and these are None): the
    ``externally_reflected_component`` (%, ERC: the ground seen straight through the openings, closed
    form, exact) and the ``internally_reflected_component`` (%, IRC: the rest, rendered; it carries the
    reading's whole error); None otherwise (then the reflected component holds both)."""

    location: tuple
    normal: tuple
    daylight_factor: float
    rel_std_error: float
    illuminance: float
    sky_horizontal_lux: float
    exact: bool
    method: str
    notes: list
    sky_component: object = None
    reflected_component: object = None
    externally_reflected_component: object = None
    internally_reflected_component: object = None

    def to_dict(self):
        return dataclasses.asdict(self)


def overcast_only(request, snapshot, ground_reflectance):
    """Inside the caller's guard: lights hidden in renders, the world a temporary overcast sky.
    Returns (notes, the sky as ``authoring.sky.set_cie_sky`` set it: the analysis hands it on, never reads
    it back from the world)."""
    from ..meter import point_meter as meter
    from ..authoring import sky
    from .light_isolation import rendering_light_objects

    scene = request.scene
    model = meter.capture_model(scene, request.view_layer)
    hidden = rendering_light_objects(scene, model)
    for ob in hidden:
        snapshot.remember(ob, "hide_render")
        ob.hide_render = True
    sky_info = sky.set_cie_sky(request, "overcast", horizontal_illuminance_lux=SKY_HORIZONTAL_LUX,
                               ground_reflectance=ground_reflectance)
    request.view_layer.update()
    notes = [f"CIE overcast sky (L = Lz (1 + 2 cos Z) / 3), E_out,h = {SKY_HORIZONTAL_LUX:g} lx, ground "
             f"reflectance {ground_reflectance:g} below a sharp horizon; {len(hidden)} light(s) switched off"]
    if model.emissive_surfaces:
        notes.append("the scene's emitting surfaces stay on and are counted as daylight")
    return notes, sky_info


def _check_rho(ground_reflectance):
    try:
        rho = float(ground_reflectance)
    except (TypeError, ValueError):
        raise RadiometerError(f"ground_reflectance must be a number within 0..1, got {ground_reflectance!r}") from None
    if not (math.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise RadiometerError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    return rho


#: Points per task when a daylight-factor run goes to a Dask cluster (fixed, so that the readings do
#: not depend on the number of workers: each chunk is one measurement with its own seed).
CHUNK_POINTS = 256


def floor_lux(quality, target_abs_error):
    """The meter's absolute floor (lux) for a daylight-factor floor in DF points (None: the preset's
    ``target_abs_df``): DF points / 100 x the overcast sky's horizontal illuminance."""
    from ...quality import preset

    points = preset(quality)["target_abs_df"] if target_abs_error is None else float(target_abs_error)
    return points / 100.0 * SKY_HORIZONTAL_LUX


def daylight_factor_chunk(scene, *, locations, normals, quality, target_rel_error, seed, efficacy=None, **kwargs):
    """One cluster task: the daylight factor at a chunk of points (a list of readings). The task carries
    plain values (the caller's efficacy, lm/W, among them); the worker builds its request on the copy of the
    scene it opened."""
    from ..blender import request as request_of

    request = request_of.build(scene, efficacy=efficacy, quality=quality, target_rel_error=target_rel_error,
                               seed=seed)
    out = daylight_factor(locations, normals, request=request, **kwargs)
    return out if isinstance(out, list) else [out]


def daylight_factor(locations, normals=(0.0, 0.0, 1.0), *, request, ground_reflectance=0.2, method="auto",
                    chunk_points=CHUNK_POINTS, target_abs_df=None):
    """Daylight factor (%) at ``locations`` (3,) or (N, 3) facing ``normals``; a reading or a list.

    The request (``measure.blender.request``): the scene, ``quality`` and ``target_rel_error``, the seed,
    progress, cancel and ``client``. ``target_abs_df``: the absolute error floor in daylight-factor points
    (None: the preset's ``target_abs_df``; 0: none), beside the relative target (issue 31); the meter gets
    it in lux (the request's ``target_abs_error`` is not used here: its unit is lux).

    ``client``: a Dask client: the points go in chunks of ``chunk_points`` (task k seeded
    ``seed + 7919 k``) to the cluster's workers (``radiometer.cluster.run_scene_tasks``).
    """
    from ..meter import point_meter as meter
    from ..blender import scene_guard

    scene, quality, target_rel_error = request.scene, request.quality or "standard", request.target_rel_error
    seed, progress, cancelled, client = request.seed, request.progress, request.cancelled, request.client
    rho = _check_rho(ground_reflectance)
    points, single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    if client is not None:
        from ...cluster import run_scene_tasks

        size = max(1, int(chunk_points))
        tasks = [dict(locations=points[k:k + size], normals=dirs[k:k + size], quality=quality,
                      ground_reflectance=rho, target_rel_error=target_rel_error, method=method,
                      seed=int(seed) + 7919 * (k // size), target_abs_df=target_abs_df, efficacy=request.efficacy)
                 for k in range(0, len(points), size)]
        parts = run_scene_tasks(scene, daylight_factor_chunk, tasks, client=client, progress=progress,
                                cancelled=cancelled, label="daylight factor")
        out = [r for part in parts for r in part]
        return out[0] if single else out
    sky = ground = None  # the proven sky component and ground seen straight (lux), where proven
    if method == "camera":
        if target_rel_error is not None:
            raise RadiometerError("method='camera' takes quality (a fixed number of rays per point), not "
                                  "target_rel_error; its errors are stated")
        with scene_guard.preserved_scene(scene) as snapshot:
            notes, _sky = overcast_only(request, snapshot, rho)
            readings = _camera_readings(request, points, dirs)
    else:
        with scene_guard.preserved_scene(scene) as snapshot:
            notes, sky_info = overcast_only(request, snapshot, rho)
            measure = request.but(client=None, samples=None, time_budget_s=None,
                                  target_abs_error=floor_lux(quality, target_abs_df))
            if method == "auto":
                readings, sky, ground = _split_readings(measure, points, dirs, rho, sky_info)
            else:
                readings = meter.measure_illuminance(points, dirs, measure, method=method)
    readings = readings if isinstance(readings, list) else [readings]
    sky = [None] * len(readings) if sky is None else sky
    ground = [None] * len(readings) if ground is None else ground
    out = []
    for p, n, r, sc, gr in zip(points, dirs, readings, sky, ground):
        df = 100.0 * r.illuminance / SKY_HORIZONTAL_LUX
        sc_df = None if sc is None else 100.0 * sc / SKY_HORIZONTAL_LUX
        erc = None if gr is None else 100.0 * gr / SKY_HORIZONTAL_LUX
        how = r.method if sc is None else r.method.replace("render", "hybrid", 1)  # closed-form SC + render
        if sc is not None and erc is not None and r.samples == 0:
            df = sc_df + erc  # nothing rendered (a black room): the proven parts are the reading, without rounding
        out.append(DaylightFactorReading(tuple(map(float, p)), tuple(map(float, n)), df, float(r.rel_std_error),
                                         float(r.illuminance), SKY_HORIZONTAL_LUX, bool(r.exact), how,
                                         notes + list(r.notes), sc_df, None if sc is None else df - sc_df,
                                         erc, None if erc is None else df - sc_df - erc))
    return out[0] if single else out


def _in_the_way(sc):
    """What a proven sky component's note says stands between the point and the sky."""
    if not sc.clipped:
        return "nothing outside in the way"
    return (f"the sky past the obstructions in the view through {sc.clipped} of them, their silhouettes clipped "
            "exactly (radiometry/skies/obstructed_aperture.py; what they reflect is rendered)")


def _where_from(sc):
    """How a proven sky component was found, for its note (the gate path)."""
    if sc.past_every_surface:
        return (sc.past_every_surface + "; so the sky over every direction "
                "from the point that meets no surface at all, the surfaces' silhouettes clipped exactly on the faces "
                "of a cube round the point, every one of them opaque: radiometry/skies/obstructed_aperture.py "
                "open_directions")
    return f"{sc.apertures} convex opening(s) in a closed opaque shell, {_in_the_way(sc)}"


def _split_readings(request, points, dirs, rho, sky_info):
    """``method="auto"`` inside the caller's guard (the overcast sky set). Where the openings look out on the
    world alone (``sky_component.openings_to_world``) they become emitters of its radiance: at points
    where the sky and ground seen straight through them are proven (``sky_component``) the reading is
    that closed form plus a render of the rest, the meters linked out of the emitters; at the other
    points inside the room (a pane in the opening, something inside in the way) the whole is rendered,
    sampling the emitters as lights (with a ground plane in front of the openings, below them, the emitters carry the
    sky alone, the proven part is the sky alone, and the ground plane seen through them is rendered; a point proven
    outside that room, outdoors, is rendered whole). Otherwise, where the sky component (SC) alone is proven, the
    reading is SC plus a render of the rest with the sky's direct emission gated off
    (``sky_component.gate_world``). Elsewhere the whole is rendered under the sky. Returns (readings,
    SC lux per point or None, ground seen straight lux per point or None). The request carries the
    meter's budget (its absolute floor in lux) and the first seed; ``sky_info`` is the sky as
    :func:`overcast_only` set it (the openings' emitters carry it)."""
    from ..meter import point_meter as meter
    from ..meter import surface_gather
    from . import sky_component

    scene, seed = request.scene, request.seed
    model = meter.capture_model(scene, request.view_layer)  # the overcast sky as the meter knows it
    scale = request.scale_length
    sensors, _eps = meter.sensor_points(points, dirs, scale, model)
    target = request.target_rel_error or request.preset()["target"]
    scs = sky_component.sky_components(scene, sensors * scale, dirs, ground_reflectance=rho,
                                       horizontal_lux=SKY_HORIZONTAL_LUX, model=model, target_rel_error=target)
    proven = np.array([c.sky_lux is not None for c in scs])
    # A pane's bound must leave room for the target: where it is over half the target (of the proven part,
    # a lower bound on the reading) the point is rendered whole through the emitters instead (measured
    # behind a 6 mm pane the size of its opening: the rim where rays cross the pane's edge took up to 1.7 %).
    wide = np.array([c.bound_lux > 0.5 * target * ((c.sky_lux or 0.0) + (c.ground_lux or 0.0)) for c in scs])
    openings = sky_component.openings_to_world(model)
    # what the linked meters' proven part holds: the sky and the world's ground seen through the openings, or with
    # sky-only emitters (a ground plane in front, below them) the sky alone, the ground plane seen through them
    # rendered with the rest
    full = np.array([c.sky_lux is not None and (openings.sky_only or c.ground_lux is not None) for c in scs]) & ~wide
    emitting = np.array([c.inside for c in scs]) if openings.loops else np.zeros(len(points), bool)
    # where the gate path (below) reads the proven part; a wide pane bound: rendered whole. The gate path is not
    # taken beside the openings' emitters: a proven point outside their room (outdoors) is then rendered whole.
    gated = proven & ~wide & ~emitting.any()
    under_sky = ~emitting & ~gated  # measured whole under the sky itself, before anything is changed
    out = [None] * len(points)
    sky, grd = [None] * len(points), [None] * len(points)

    def unproven(k):
        if scs[k].sky_lux is not None:
            return (f"the bound on the light through a pane ({scs[k].bound_lux:.3g} lx) exceeds half the target")
        return scs[k].reason

    def measure_at(idx, note, seed, **kwargs):
        if not idx.size:
            return
        readings = meter.measure_illuminance(points[idx], dirs[idx], request.but(seed=seed), method="auto",
                                             model=model, **kwargs)
        for k, r in zip(idx, readings if isinstance(readings, list) else [readings]):
            r.notes += note(k)
            out[k] = r

    def measured_whole(k):
        if proven[k] and not wide[k]:  # outside the room whose openings emit
            return [f"sky component proven ({scs[k].past_every_surface}) but not used: the gate path that would take "
                    "it is not taken beside the openings' emitters, so the daylight factor is measured whole"]
        return [f"sky component not proven ({unproven(k)}): the daylight factor is measured whole"]

    measure_at(np.flatnonzero(under_sky), measured_whole, seed=seed + 1)
    efficacy = request.efficacy
    if emitting.any():
        keys, dark_world = sky_component.add_opening_emitters(request, openings, sky_info)
        request.view_layer.update()
        glazed = sum(d > 0.0 for d in openings.depth)
        sky_only = openings.sky_only

        def seen(k):  # lux of the proven part at point k
            return scs[k].sky_lux + (0.0 if sky_only else scs[k].ground_lux)

        how = ((f"the {len(openings.loops)} opening(s) emitted the sky's radiance into the room, upwards, and let "
                "every other ray through " if sky_only else
                f"the {len(openings.loops)} opening(s) emitted the sky's and ground's radiance into the room ")
               + (f"({glazed} from just outside its pane) " if glazed else "")
               + ("(only surfaces below them, a ground plane, lie in front of them, which a ray leaving upwards "
                  "never meets: sky_component.openings_to_world)" if sky_only else
                  "(nothing else lies in front of them: sky_component.openings_to_world)"))
        linked = np.flatnonzero(emitting & full)
        link_note = ""
        if linked.size:
            # the check's meter: the brightest, preferring one that sees an opening without glass
            lux = np.array([seen(k) * (1.0 if scs[k].glazed else 1e6) for k in linked])
            brightest = linked[int(np.argmax(lux))]
            ok, link_note = sky_component.check_emitter_linking(request, keys, sensors[brightest], dirs[brightest],
                                                                model, dark_world=dark_world,
                                                                sky_only=sky_info if sky_only else None)
            if not ok:  # render those points whole too, through the emitters, and say why
                linked = linked[:0]
        whole = np.flatnonzero(emitting & ~np.isin(np.arange(len(points)), linked))
        if linked.size:
            lux = np.array([seen(k) for k in linked])
            grey = np.repeat((lux / efficacy)[:, None], 3, axis=1)  # a white sky and ground: W/m^2 per channel
            bound = np.repeat((np.array([scs[k].bound_lux for k in linked]) / efficacy)[:, None], 3, axis=1)

            def linked_note(k):
                c = scs[k]
                through = (f"{c.apertures} convex opening(s) in a closed opaque shell, "
                           + _in_the_way(c)
                           + (f"; {c.glazed} seen through a colour-neutral thin pane, its T(theta) integrated with a "
                              f"hard bound of {c.bound_lux:.3g} lx (sky_aperture.pane_bounded_illuminance)"
                              if c.glazed else ""))
                return [f"sky component proven ({through}): the CIE sky "
                        + ("" if sky_only else "and the ground ") + "seen straight through them "
                        "in closed form (radiometry/skies/sky_aperture.py)" + (", bounded" if c.glazed else ", exact")
                        + ("; the ground plane seen through them rendered with the rest" if sky_only else "")
                        + f"; {how}, linked out of the meters, and Cycles rendered only the light the room's "
                        "surfaces reflect, sampling the openings as lights", link_note]

            name = ("sky through the openings (closed form)" if sky_only else
                    "sky and ground through the openings (closed form)")
            # where the room is convex, empty, Lambertian and open, the rest is gathered from bakes on its walls,
            # shared by all these meters (surface_gather); elsewhere each meter renders its own
            found = sky_component._closed_shell(model)
            plan = surface_gather.plan(model, openings, found if isinstance(found, str) else found[1],
                                       sky_component.opaque_mask(model), sensors[linked] * scale, dirs[linked],
                                       sky_component._proof_tolerance(model, sensors[linked] * scale))
            gathered = plan.usable if not isinstance(plan, str) else np.zeros(len(linked), bool)
            for use, idx in ((True, np.flatnonzero(gathered)), (False, np.flatnonzero(~gathered))):
                if idx.size:
                    measure_at(linked[idx], linked_note, seed=seed,
                               proven=meter.ProvenPart(grey[idx], name, keys, bound[idx],
                                                       covers_world=not sky_only,  # sky-only: the ground is rendered
                                                       gather=plan if use else None))
            for k in linked:
                sky[k], grd[k] = float(scs[k].sky_lux), None if sky_only else float(scs[k].ground_lux)
        measure_at(whole, lambda k: [
            f"{how}; Cycles rendered all the light here, sampling the openings as lights (the sky and ground seen "
            "straight are not proven here: " + (scs[k].reason or (
                f"the bound on the light through a pane ({scs[k].bound_lux:.3g} lx) exceeds half the target"
                if wide[k] else "the meters could not be linked out of the emitters: " + link_note)) + ")"],
                   seed=seed + 2)
        return out, sky, grd
    take = np.flatnonzero(gated)
    if not take.size:
        return out, sky, grd
    factor = sky_component.gate_world(scene)
    ok, gate_note = sky_component.check_world_gate(request, factor, model, horizontal_lux=SKY_HORIZONTAL_LUX)
    # why the room's openings were not made emitters: none proven, or (proven, but no meter inside that room) the
    # meters are outside the closed shell that holds them
    why_gate = openings.reason or "no meter is inside the closed room that holds the openings"
    if not ok:  # the gate failed its check: render those points whole too, and say why
        sky_component.set_gate_mode(factor, "off")
        scene.world.cycles.sampling_method = "AUTOMATIC"  # the temporary sky's own setting again
        request.view_layer.update()
        measure_at(take, lambda k: [gate_note, "so the sky component was not used: the whole daylight factor is "
                                               "rendered"], seed=seed)
        return out, sky, grd
    # The windows of a room of boxes as emitters (gaps in the scene's bounding faces, nothing in front of them), gated
    # like the world: the rest is then found by sampling them as lights, not by the paths' own bounces alone.
    factors, envelope, area, why_not = sky_component.add_envelope_emitters(request, model, sky_info,
                                                                           sensors[take] * scale)
    how = ""
    if envelope:
        ok, envelope_note = sky_component.check_envelope_gate(request, [factor] + factors, model, sky_info,
                                                             horizontal_lux=SKY_HORIZONTAL_LUX)
        if not ok:  # without them the gate path is as before: the world found by the paths' bounces
            envelope = sky_component.remove_objects(envelope)
        how = (f"{len(envelope)} gap(s) in the scene's bounding faces ({area:.3g} m^2: the windows of a room of boxes) "
               "emitted the sky's and ground's radiance, gated like the world "
               "(sky_component.add_envelope_emitters)" if envelope else "")
        gate_note = gate_note + "; " + envelope_note
    request.view_layer.update()
    sc_lux = np.array([scs[k].sky_lux for k in take], float)
    grey = np.repeat((sc_lux / efficacy)[:, None], 3, axis=1)  # the sky is white: W/m^2 per channel
    # a pane's T(theta) bound (hard) joins the reading's error, as on the emitters' path
    sc_bound = np.repeat((np.array([scs[k].bound_lux for k in take], float) / efficacy)[:, None], 3, axis=1)
    measure_at(take, lambda k: [
        f"sky component proven ({_where_from(scs[k])}" + (f"; {scs[k].glazed} seen through a colour-neutral thin pane, its T(theta) "
                                    f"integrated with a hard bound of {scs[k].bound_lux:.3g} lx "
                                    "(sky_aperture.pane_bounded_illuminance)" if scs[k].glazed else "")
        + "): the CIE overcast sky through them in closed form (radiometry/skies/sky_aperture.py), "
        + ("bounded; " if scs[k].glazed else "exact; ")
        + "Cycles rendered only the rest (the sky's direct emission gated off by Light Path Ray Depth, the ground "
        "seen through the openings and every reflection kept; "
        + (how + "; the openings were not made emitters themselves: " if envelope else
           "the openings were not made emitters: ")
        + f"{why_gate}" + (f"; nor the gaps in the scene's bounding faces: {why_not}" if why_not else "") + ")",
        gate_note], seed=seed, proven=meter.ProvenPart(grey, "sky component (closed form)",
                                                                       bound_rgb=sc_bound))
    for k in take:
        sky[k] = float(scs[k].sky_lux)
    return out, sky, grd


def _camera_readings(request, points, dirs):
    """Illuminance at the points through the meter camera (``measure.analyses.daylight_coefficients``: cosine-
    weighted rays from each point, no sensor bake) under the world as it is: one ``IlluminanceReading``
    per point, as the meter's (issue 30: one reading type per quantity)."""
    import time

    from . import daylight_coefficients
    from ..meter import point_meter as meter
    from ...readings import IlluminanceReading

    started = time.perf_counter()
    space, weights, efficacy = request.photometry
    e_rgb, cov, record = daylight_coefficients.render_irradiance(points, dirs, request=request)
    scale2 = request.unit_area  # Cycles renders W per scene-unit^2
    e_rgb = e_rgb / scale2
    e = e_rgb @ weights
    sd = np.sqrt(np.maximum(np.einsum("c,ncd,d->n", weights, cov, weights), 0.0)) / scale2
    sd = np.hypot(sd, meter.FLOAT32_FLOOR * np.abs(e))  # a rendered value: never below float32 rounding (issue 32)
    sd_rgb = np.sqrt(np.maximum(np.einsum("ncc->nc", cov), 0.0)) / scale2
    note = (f"meter camera: {record['rays_per_meter']} cosine-weighted rays per point from the point itself "
            f"(8 rounds; stratified per-pixel error), {record.get('engine', 'Cycles')}"
            + (f"; {record['device_note']}" if record.get("device_note") else ""))
    seconds = (time.perf_counter() - started) / max(len(points), 1)
    return [IlluminanceReading(irradiance_rgb=tuple(float(v) for v in rgb), irradiance=float(v),
                               illuminance=float(efficacy * v), rel_std_error=float(s / v) if v > 0 else math.inf,
                               method="camera", samples=int(record["rays_per_meter"]), seconds=seconds,
                               efficacy=efficacy, colour_space=space, location=tuple(float(c) for c in p),
                               normal=tuple(float(c) for c in n), exact=False,
                               std_error_rgb=tuple(float(c) for c in srgb), notes=[note])
            for rgb, v, s, srgb, p, n in zip(e_rgb, e, sd, sd_rgb, points, dirs)]


# --- the grid form ---------------------------------------------------------------------------------

def plane_statistics(df, *, target_percent=None, median_external_illuminance_lux=None):
    """Statistics of daylight factors ``df`` (%) over equal-area grid cells (pure numpy).

    Returns ``radiometry.metrics.grid.plane_statistics``' dict (every ``PLANE_METRICS`` entry): average
    (BS 8206-2 average daylight factor), minimum, maximum, median, uniformity (min / average; NaN on a
    dark plane), points; share_above_target (fraction of cells with DF >= target_percent),
    and ``en17037`` per level (minimum/medium/high): D_T, D_TM (%), share of the plane reaching each,
    and whether the level is met (D_T over >= 50 %, D_TM over >= 95 % of the plane).
    """
    from ...radiometry.metrics.grid import plane_statistics as statistics

    v = np.asarray(df, float).ravel()
    try:
        out = statistics(v, target=target_percent)  # the one plane-statistics function (issue 30)
    except ValueError:
        raise RadiometerError("daylight factors must be finite numbers (got an empty or non-finite grid)") from None
    if target_percent is not None:  # the daylight factor's own names for the target and its share
        out["target_percent"] = out.pop("target")
        out["share_above_target"] = out.pop("share_at_or_above_target")
    if median_external_illuminance_lux is not None:
        try:
            row = en17037.daylight_provision_daylight_factor(v, median_external_illuminance_lux)
        except ValueError as exc:
            raise RadiometerError(str(exc)) from None
        keys = ("E_T_lux", "E_TM_lux", "D_T", "D_TM", "share_D_T", "share_D_TM", "met")
        levels = {name: {k: lv[k] for k in keys} for name, lv in row.per_level.items()}
        out["en17037"] = {"median_external_illuminance_lux": row.values["median_external_illuminance_lux"],
                          "levels": levels}
    return out


@dataclasses.dataclass
class DaylightFactorGrid:
    """``daylight_factor`` (ny, nx) %, ``rel_std_error`` (ny, nx), ``points`` (ny, nx, 3), ``stats``
    (``plane_statistics``), ``target``, ``normal``, ``method``, ``exact``, ``notes``; ``sky_component``
    (ny, nx) % proven in closed form, NaN where not proven (None: not sought); the BRE split-flux parts
    ``externally_reflected_component`` (the ground seen straight, closed form) and
    ``internally_reflected_component`` (the rendered rest) (ny, nx) %, NaN where the openings were not
    made emitters or the point was not proven (None: not sought)."""

    target: str
    nx: int
    ny: int
    daylight_factor: np.ndarray
    rel_std_error: np.ndarray
    points: np.ndarray
    normal: tuple
    stats: dict
    method: str
    exact: bool
    notes: list
    sky_component: object = None
    externally_reflected_component: object = None
    internally_reflected_component: object = None

    _PARTS = ("sky_component", "externally_reflected_component", "internally_reflected_component")

    def to_dict(self):
        d = dataclasses.asdict(self)
        for k in ("daylight_factor", "rel_std_error", "points"):
            d[k] = np.asarray(d[k]).tolist()
        for k in self._PARTS:  # JSON has no NaN: null where not proven
            if getattr(self, k) is not None:
                d[k] = [[None if math.isnan(v) else float(v) for v in row] for row in getattr(self, k)]
        return d

    def csv_text(self):
        """One row per point: x, y, z (scene units), DF (%), its relative error, and where sought the SC,
        ERC and IRC (%; empty where not proven)."""
        parts = [k for k in self._PARTS if getattr(self, k) is not None]
        head = {"sky_component": "sky_component_percent", "externally_reflected_component": "erc_percent",
                "internally_reflected_component": "irc_percent"}
        lines = [",".join(["x,y,z,daylight_factor_percent,rel_std_error"] + [head[k] for k in parts])]
        columns = [np.asarray(getattr(self, k), float).ravel() for k in parts]
        for i, (p, v, e) in enumerate(zip(self.points.reshape(-1, 3), self.daylight_factor.ravel(),
                                          self.rel_std_error.ravel())):
            extra = ["" if math.isnan(c[i]) else f"{c[i]:.6g}" for c in columns]
            lines.append(",".join([f"{p[0]:.6g},{p[1]:.6g},{p[2]:.6g},{v:.6g},{e:.4g}"] + extra))
        return "\n".join(lines) + "\n"


def _grid_layout(request, target, resolution, spacing):
    """(plane object, nx, ny, points (ny, nx, 3), normal): ``measure.analyses.grid.grid_layout``, the layout
    ``illuminance_grid`` uses too."""
    from . import grid

    layout = grid.grid_layout(request, target, resolution, spacing)
    return layout.obj, layout.nx, layout.ny, layout.points, np.asarray(layout.normal, float)


def daylight_factor_grid(target, *, request, resolution=None, spacing=None, ground_reflectance=0.2,
                         target_percent=None, median_external_illuminance_lux=None, method="auto",
                         chunk_points=CHUNK_POINTS, target_abs_df=None):
    """Daylight factor on a work plane object's grid (``measure.analyses.grid.illuminance_grid`` points).
    The request and ``target_abs_df`` (the absolute error floor in daylight-factor points) as in
    :func:`daylight_factor`.

    The request's ``client``: a Dask client: the grid's points run in chunks of ``chunk_points`` on its
    workers (see :func:`daylight_factor`).
    """
    from . import grid
    from ..blender import scene_guard

    scene, client = request.scene, request.client
    rho = _check_rho(ground_reflectance)
    if client is not None or method in ("camera", "auto"):  # point by point (camera: no grid form; auto: the SC)
        obj, nx, ny, points, normal = _grid_layout(request, target, resolution, spacing)
        readings = daylight_factor(points.reshape(-1, 3), np.broadcast_to(normal, (nx * ny, 3)), request=request,
                                   ground_reflectance=rho, method=method, chunk_points=chunk_points,
                                   target_abs_df=target_abs_df)
        df = np.array([r.daylight_factor for r in readings], float).reshape(ny, nx)
        se = np.array([r.rel_std_error for r in readings], float).reshape(ny, nx)
        stats = plane_statistics(df, target_percent=target_percent,
                                 median_external_illuminance_lux=median_external_illuminance_lux)
        where = (f"on a Dask cluster in chunks of {int(chunk_points)} points" if client is not None
                 else "through the meter camera" if method == "camera" else "point by point")
        notes = [f"{nx} x {ny} points at cell centres on the plane, measured {where}"]
        if obj.hide_render:
            notes.append("the plane is hidden in renders: an imaginary work plane that neither blocks nor reflects")
        sc, erc, irc = (np.array([np.nan if getattr(r, part) is None else getattr(r, part) for r in readings], float)
                        for part in DaylightFactorGrid._PARTS)
        if method == "auto":
            proven = int(np.sum(~np.isnan(sc)))
            notes.append(f"sky component proven in closed form at {proven} of {nx * ny} points (the rest of the "
                         "light rendered there); " + ("every point measured whole" if proven == 0 else
                                                     f"{nx * ny - proven} point(s) measured whole"))
            if proven < nx * ny:
                # why: the point's own note ("sky component not proven (...)", or proven but not used: a point
                # outside the room whose openings emit, such as one inside a cabinet against its wall)
                first = readings[int(np.flatnonzero(np.isnan(sc))[0])]
                notes.append("at the first such point: " + next(
                    (x for x in first.notes if x.startswith("sky component")), "no sky component was stated"))
        notes += list(readings[0].notes)
        methods = sorted({r.method for r in readings})
        return DaylightFactorGrid(obj.name, nx, ny, df, se, points, tuple(float(v) for v in normal), stats,
                                  "/".join(methods), all(r.exact for r in readings), notes,
                                  *((sc.reshape(ny, nx), erc.reshape(ny, nx), irc.reshape(ny, nx)) if method == "auto"
                                    else (None, None, None)))
    with scene_guard.preserved_scene(scene) as snapshot:
        notes, _sky = overcast_only(request, snapshot, rho)
        result = grid.illuminance_grid(target, resolution=resolution, spacing=spacing, method=method,
                                       request=request.but(samples=None, time_budget_s=None, target_abs_error=floor_lux(
                                           request.quality or "standard", target_abs_df)))
    df = 100.0 * np.asarray(result.lux, float) / SKY_HORIZONTAL_LUX
    stats = plane_statistics(df, target_percent=target_percent,
                             median_external_illuminance_lux=median_external_illuminance_lux)
    return DaylightFactorGrid(result.target, result.nx, result.ny, df, np.asarray(result.rel_std_error, float),
                              np.asarray(result.points, float), tuple(result.normal), stats, result.method,
                              bool(result.exact), notes + list(result.notes))

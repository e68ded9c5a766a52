"""Annual climate-based daylight by daylight coefficients (issue 19 item 6), the two-phase way.

1. Daylight coefficients: for every sky patch p (``radiometry.sky_patches``: Reinhart MF:m, patch 0
   the ground), the scene's world is replaced by a world that emits luminance L_0 inside patch p
   only (math nodes on the ray direction, sharp patch edges), every light is hidden in renders, and
   the meter measures every point: DC[p, i] = E_i / L_0 (lux per cd/m^2), with its standard error.
   One measurement per patch, all points together; ``patch_coefficients`` is the module-level task
   (a chunk of patches) so the patches can run on a Dask cluster.
2. Sky vectors: per hour of the EPW file the Perez all-weather sky (``radiometry.perez``) gives each
   patch's luminance, the sun's direct normal illuminance spread over its 4 nearest patches (as
   Radiance's gendaymtx does for the two-phase method), and the ground rho_g E_gh / pi.
3. Hourly illuminance E = S DC (T x N), and the sun-only part E_sun = S_sun DC for ASE; metrics by
   ``radiometry.daylight_metrics`` (sDA 300 lx / 50 %, ASE 1000 lx / 250 h, UDI 100-2000 lx) over
   the occupied hours (8 am to 6 pm local standard time, record midpoints).

Not LM-83 to the letter: ASE here includes the sun's interreflected light (LM-83 asks for direct sun
only), and the sun is smeared over 4 patches (the two-phase approximation) rather than traced as a
0.53 deg disc; both as Radiance's two-phase method does. The scene is restored after every chunk.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import RadiometerError

#: Luminance of the one emitting patch while its coefficients are rendered (cd/m^2).
PATCH_LUMINANCE = 1000.0


def _value(tree, v, x, y):
    node = tree.nodes.new("ShaderNodeValue")
    node.outputs[0].default_value = float(v)
    node.location = (x, y)
    return node


def _math(tree, op, a, b, x, y):
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = op
    node.location = (x, y)
    for i, v in enumerate((a, b)):
        if isinstance(v, (int, float)):
            node.inputs[i].default_value = float(v)
        else:
            tree.links.new(v, node.inputs[i])
    return node.outputs[0]


def build_patch_world(world):
    """Fill ``world``'s tree with the patch-selector shader; returns the dict of Value nodes to set
    (alt_lo, alt_hi, az_lo, az_width, radiance)."""
    from ..compat import ensure_node_tree

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
                       target_rel_error=None, seed=0, cancelled=None):
    """One task: daylight coefficients (len(patch_indices), N) lux per cd/m^2 and their standard
    errors, for these patches; every light hidden, the world a one-patch world (scene restored)."""
    import bpy

    from ..radiometry import sky_patches
    from . import daylight_factor, meter, scene_guard

    patches = sky_patches.reinhart_patches(m)
    points, _single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    _space, _w, efficacy = meter.scene_photometry(scene)
    radiance = PATCH_LUMINANCE / efficacy * scene.unit_settings.scale_length ** 2
    dc = np.zeros((len(patch_indices), len(points)))
    se = np.zeros_like(dc)
    with scene_guard.preserved_scene(scene) as snapshot:
        model = meter.capture_model(scene)
        for ob in daylight_factor._light_objects(scene, model):
            snapshot.remember(ob, "hide_render")
            ob.hide_render = True
        world = bpy.data.worlds.new("Radiometer sky patch")
        values = build_patch_world(world)
        scene.world = world
        for k, p in enumerate(patch_indices):
            if cancelled is not None and cancelled():
                from ..errors import MeasurementCancelled

                raise MeasurementCancelled("annual daylight cancelled")
            _select_patch(values, patches, int(p), radiance)
            rs = meter.measure_illuminance(points, dirs, scene=scene, method="render", quality=quality,
                                           samples=samples, target_rel_error=target_rel_error, seed=seed + k)
            rs = rs if isinstance(rs, list) else [rs]
            dc[k] = [r.illuminance / PATCH_LUMINANCE for r in rs]
            se[k] = [np.nan_to_num(r.rel_std_error) * r.illuminance / PATCH_LUMINANCE for r in rs]
    return dc, se


def coefficient_tasks(locations, normals, *, m=1, quality="preview", samples=None, target_rel_error=None, seed=0):
    """The :func:`patch_coefficients` kwargs of every chunk of 16 patches (chunk from patch s seeded
    ``seed + 7919 s``): the same list in this process and on a cluster."""
    from ..radiometry import sky_patches

    count, chunk = sky_patches.reinhart_patches(m).count, 16
    return [dict(locations=locations, normals=normals, patch_indices=list(range(start, min(count, start + chunk))),
                 m=m, quality=quality, samples=samples, target_rel_error=target_rel_error, seed=seed + 7919 * start)
            for start in range(0, count, chunk)]


def daylight_coefficients(locations, normals=(0.0, 0.0, 1.0), *, scene=None, m=1, quality="preview", samples=None,
                          target_rel_error=None, seed=0, progress=None, cancelled=None, client=None):
    """(DC (P, N) lux per cd/m^2, standard error (P, N)) for every patch of Reinhart MF:m.

    The patches go in chunks of 16 (chunk starting at patch s seeded ``seed + 7919 s``), one
    :func:`patch_coefficients` task each: here one after the other, or with a Dask ``client`` on its
    workers (``radiometer.cluster.run_scene_tasks``); the same tasks either way, so the same numbers.
    """
    import bpy

    from ..radiometry import sky_patches

    scene = scene or bpy.context.scene
    count = sky_patches.reinhart_patches(m).count
    tasks = coefficient_tasks(locations, normals, m=m, quality=quality, samples=samples,
                              target_rel_error=target_rel_error, seed=seed)
    if client is not None:
        from ..cluster import run_scene_tasks

        parts = run_scene_tasks(scene, patch_coefficients, tasks, client=client, progress=progress,
                                cancelled=cancelled, label="annual daylight")
        return np.concatenate([d for d, _ in parts]), np.concatenate([s for _, s in parts])
    dc, se = [], []
    for task in tasks:
        d, s = patch_coefficients(scene, cancelled=cancelled, **task)
        dc.append(d)
        se.append(s)
        if progress is not None:
            idx = task["patch_indices"]
            progress(int(1000 * idx[-1] / max(count - 1, 1)), 1000, None)
    return np.concatenate(dc), np.concatenate(se)


def sky_matrix(weather, patches, *, ground_reflectance=0.2, north_offset_deg=0.0, year=2026):
    """(S (T, P) all sky + sun, S_sun (T, P) sun only) patch luminances (cd/m^2) per EPW record, and
    the records' local midpoint hours (T,)."""
    from ..radiometry import perez, solar_position

    times = weather.midpoint_datetimes(year)
    unix = solar_position.unix_seconds(times)
    pos = solar_position.solar_position(unix, weather.latitude_deg, weather.longitude_deg,
                                        elevation_m=weather.elevation_m, north_offset_deg=north_offset_deg)
    directions = np.asarray(pos.direction, float)
    doy = np.array([t.timetuple().tm_yday for t in times])
    dni = np.nan_to_num(weather.direct_normal_w_m2)
    dhi = np.nan_to_num(weather.diffuse_horizontal_w_m2)
    dew = np.where(np.isfinite(weather.dew_point_c), weather.dew_point_c, 11.0)
    s_all = np.zeros((len(times), patches.count))
    s_sun = np.zeros_like(s_all)
    for t in range(len(times)):
        s_all[t], _info = perez.sky_vector(patches, directions[t], dni[t], dhi[t], doy[t], dew[t], ground_reflectance)
        s_sun[t], _ = perez.sky_vector(patches, directions[t], dni[t], dhi[t], doy[t], dew[t], 0.0, include_sky=False)
    return s_all, s_sun, weather.midpoint_hours()


@dataclasses.dataclass
class AnnualResult:
    """``illuminance`` (T, N) lux, ``sun_illuminance`` (T, N), ``occupied`` (T,), ``sda`` (fraction of
    points), ``sda_point_fraction`` (N,), ``ase``, ``ase_hours`` (N,), ``udi`` (fell_short, useful,
    exceeded: (N,) each), ``max_rel_std_error`` of the hourly values over occupied hours, ``notes``."""

    locations: np.ndarray
    illuminance: np.ndarray
    sun_illuminance: np.ndarray
    occupied: np.ndarray
    sda: float
    sda_point_fraction: np.ndarray
    ase: float
    ase_hours: np.ndarray
    udi: tuple
    max_rel_std_error: float
    notes: list

    def to_dict(self):
        return {"locations": np.asarray(self.locations).tolist(), "sda_300_50": self.sda, "ase_1000_250h": self.ase,
                "sda_point_fraction": self.sda_point_fraction.tolist(), "ase_hours": self.ase_hours.tolist(),
                "udi_fell_short": self.udi[0].tolist(), "udi_useful": self.udi[1].tolist(),
                "udi_exceeded": self.udi[2].tolist(), "occupied_hours": int(np.sum(self.occupied)),
                "max_rel_std_error": self.max_rel_std_error, "notes": self.notes}

    def csv_text(self):
        lines = ["x,y,z,sda_hours_fraction,ase_hours,udi_fell_short,udi_useful,udi_exceeded"]
        for i, p in enumerate(np.asarray(self.locations)):
            lines.append(f"{p[0]:.6g},{p[1]:.6g},{p[2]:.6g},{self.sda_point_fraction[i]:.4f},{int(self.ase_hours[i])},"
                         f"{self.udi[0][i]:.4f},{self.udi[1][i]:.4f},{self.udi[2][i]:.4f}")
        return "\n".join(lines) + "\n"


def annual_daylight(locations, normals=(0.0, 0.0, 1.0), epw_path=None, *, scene=None, m=1, quality="preview",
                    samples=None, target_rel_error=None, ground_reflectance=0.2, north_offset_deg=0.0,
                    occupied_from=8.0, occupied_to=18.0, seed=0, progress=None, cancelled=None, client=None):
    """Annual daylight metrics at points from an EPW file (module docstring). Returns ``AnnualResult``.
    ``client``: a Dask client for the daylight coefficients (:func:`daylight_coefficients`)."""
    import bpy

    from ..radiometry import daylight_metrics, epw, sky_patches
    from . import meter

    if epw_path is None:
        raise RadiometerError("annual daylight needs an EPW weather file (epw_path)")
    try:
        weather = epw.read_epw(epw_path)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    try:
        rho = float(ground_reflectance)
    except (TypeError, ValueError):
        rho = float("nan")
    if not (math.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise RadiometerError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    scene = scene or bpy.context.scene
    points, _single = meter.as_points(locations, "locations")
    dirs = meter.as_directions(normals, len(points), "normals")
    patches = sky_patches.reinhart_patches(m)
    dc, dc_se = daylight_coefficients(points, dirs, scene=scene, m=m, quality=quality, samples=samples,
                                      target_rel_error=target_rel_error, seed=seed, progress=progress,
                                      cancelled=cancelled, client=client)
    s_all, s_sun, hours = sky_matrix(weather, patches, ground_reflectance=rho, north_offset_deg=north_offset_deg)
    e = s_all @ dc
    e_sun = s_sun @ dc
    var = (s_all ** 2) @ (dc_se ** 2)  # patches rendered independently
    occupied = daylight_metrics.occupied_hours(hours, occupied_from, occupied_to)
    try:
        sda, frac = daylight_metrics.sda(e, occupied)
        ase, ase_h = daylight_metrics.ase(e_sun, occupied)
        udi = daylight_metrics.udi(e, occupied)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(e > 0, np.sqrt(var) / e, 0.0)
    notes = [f"{weather.city}, {weather.latitude_deg:.2f} N {weather.longitude_deg:.2f} E: {weather.count} hourly "
             f"records, {int(occupied.sum())} occupied (local standard time {occupied_from:g}-{occupied_to:g} h)",
             f"daylight coefficients over {patches.count} patches (Reinhart MF:{m}, patch 0 the ground), one "
             "render per patch; Perez all-weather sky per hour; the sun spread over its 4 nearest patches "
             "(two-phase approximation); ASE includes the sun's interreflected light"]
    return AnnualResult(points, e, e_sun, occupied, sda, frac, ase, ase_h, udi,
                        float(np.max(rel[occupied])) if occupied.any() else 0.0, notes)

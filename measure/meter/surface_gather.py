"""The rendered rest of many daylight meters from bakes on the room's surfaces, shared by all of them (issue 31).

Host side of ``radiometry.sampling.surface_gather``: where a convex room with nothing inside, Lambertian walls of
known albedo and open openings made emitters (``sky_component.add_opening_emitters``) hold the meters, the light
the walls reflect towards a meter is the sum over wall cells of A_c rho_c E(y_c) / pi x J(meter, y_c), E(y_c) the
irradiance at a random point of each cell. One Cycles bake of one-texel sensors at those points (one sample each,
facing the room, the openings' emitters sampled as lights) serves every meter; repeated with new points and seeds it
gives the batches of each meter's batch-means error. Where a meter linked out of the emitters read its own render
(``point_meter``), it now reads this: the same quantity (everything the room's surfaces send it), unbiased, its
samples spent once for the whole grid instead of once per meter.

Caller's duty: run inside the caller's guard, with the openings' emitters in the scene and the world dark.
"""

import dataclasses

import numpy as np

from ...errors import MeasurementCancelled
from ...radiometry.sampling import surface_gather as gather

#: Independent draws per round (the batches of the batch-means error: 32 give it 31 degrees of freedom), and the
#: most rounds before the target is declared missed.
DRAWS = 32
MAX_ROUNDS = 16
#: Fewest meters for which the rest is gathered: its cost is one set of bakes whatever their number, a per-meter
#: render's grows with them (measured, issue 31's room, 1 %: 900 points 1.74 s against 4.54 s for the pooled
#: per-meter render; 100 points 0.50 s against 0.57 s there and 0.34 s against 0.22 s in the 4 x 3 m side-lit room).
MIN_METERS = 300
#: Most meters x cells for one draw's weights (each an (N, C) array of float64, a few of them at once): above it
#: (a hall of thousands of square metres under a fine grid) the memory and the time grow past what the gather saves.
MAX_TRANSFER = 20_000_000
#: Meters nearer a surface than this (m) are not gathered (J grows as 1 / d^2 there: the spread of the cells' points
#: would dominate): they are rendered on their own as before.
MIN_DISTANCE_M = 0.2


@dataclasses.dataclass
class GatherPlan:
    """The room's wall cells (``cells`` (C, 3, 3) m, ``areas`` (C,) m^2, ``inward`` (C, 3) unit normals into the
    room, ``albedo`` (C, 3)) and which meters may read from them (``usable`` (N,) bool)."""

    cells: object
    areas: object
    inward: object
    albedo: object
    usable: object


def plan(model, openings, shell, sealing, sensors_m, normals, tol):
    """A :class:`GatherPlan` for the meters at ``sensors_m`` (N, 3) facing ``normals``, or the reason (str) there is
    none. ``shell``: the closed room's triangles (T, 3, 3) m holding ``openings`` (or the reason, str, there is no
    such room); ``sealing``: (all triangles,) bool, those that close a room (``sky_component.opaque_mask``). The
    openings must be open (no pane: its reflection is no Lambertian wall's) and emit sky and ground (no ground plane
    outside, which a meter sees through them); every render-visible triangle opaque; the shell convex (every shell
    vertex on the inner side of every shell triangle's plane) with no sealing triangle inside it; every shell
    triangle of a Lambertian material of known albedo that emits nothing."""
    from . import sun_bounce

    if len(sensors_m) < MIN_METERS:
        return f"fewer than {MIN_METERS} meters: each renders its own rest"
    if any(d > 0.0 for d in openings.depth) or openings.sky_only:
        return "a pane or a ground plane is seen through the openings (not a Lambertian wall)"
    g = model.geometry
    if not np.all(np.asarray(g.opaque, bool)):
        return "see-through surfaces in the scene"
    if isinstance(shell, str):
        return shell
    shell = np.asarray(shell, float)
    tris = np.asarray(g.triangles, float)
    index = {t.tobytes(): k for k, t in enumerate(tris)}
    rows = np.array([index.get(t.tobytes(), -1) for t in shell])
    if np.any(rows < 0):
        return "the room's triangles could not be matched to the scene's"
    albedo_all, why = sun_bounce.receiver_albedo(model)
    albedo = albedo_all[rows]
    if not np.all(np.isfinite(albedo)):
        return "a surface of the room is not Lambertian of one known colour (" + "; ".join(why.values()) + ")"
    if g.emissive is not None and len(g.emissive) and np.any(np.asarray(g.emissive, bool)[rows]):
        return "a surface of the room emits light"
    # inward normals: the side of each triangle's plane that holds the whole shell
    normal = np.cross(shell[:, 1] - shell[:, 0], shell[:, 2] - shell[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    verts = shell.reshape(-1, 3)
    side = verts @ normal.T - np.einsum("tx,tx->t", normal, shell[:, 0])[None, :]       # (V, T)
    lo, hi = side.min(axis=0), side.max(axis=0)
    if np.any((lo < -tol) & (hi > tol)):
        return "the room is not convex (a surface sees another only in part)"
    normal = np.where((hi > tol)[:, None], normal, -normal)
    offset = np.einsum("tx,tx->t", normal, shell[:, 0])
    is_shell = np.zeros(len(g.triangles), bool)
    is_shell[rows] = True
    others = tris[np.asarray(sealing, bool) & ~is_shell]
    if len(others):
        inside = np.all(np.einsum("ovx,tx->ovt", others, normal) - offset[None, None, :] > tol, axis=2)
        if np.any(np.all(inside, axis=1)):
            return "opaque surfaces stand inside the room"
    sensors_m = np.asarray(sensors_m, float)
    cells, owner = gather.subdivide(shell, gather.CELL_EDGE_M)
    if len(cells) * len(sensors_m) <= MAX_TRANSFER:  # (refining is a loop over the cells: not for a hall)
        cells, owner = gather.refine(cells, owner, sensors_m, gather.SMALLEST_EDGE_M)
    if len(cells) * len(sensors_m) > MAX_TRANSFER:
        return f"{len(cells):,} wall cells for {len(sensors_m):,} meters: more than the gather's {MAX_TRANSFER:,} weights"
    areas = 0.5 * np.linalg.norm(np.cross(cells[:, 1] - cells[:, 0], cells[:, 2] - cells[:, 0]), axis=1)
    distance = (sensors_m @ normal.T - offset[None, :]).min(axis=1)
    return GatherPlan(cells, areas, normal[owner], albedo[owner], distance >= MIN_DISTANCE_M)


def _bake(request, model, points_m, normals, seed, bounces):
    """(M, 3) W/m^2 SI: one sample of the irradiance at each surface point, one bake (inside a guard of its own)."""
    from ..blender import scene_guard
    from ..render import render_settings, sensors
    from ...radiometry.scene import scene_model

    scene, scale = request.scene, request.scale_length
    with scene_guard.preserved_scene(scene):
        render_settings.apply(scene, samples=1, bounces=bounces, needs=model.needs)
        # every point lies on a wall: raised off it as a meter placed on a surface is (point_meter.sensor_points)
        at = points_m / scale
        placed = at + normals * scene_model.receiver_offset(at, unit_length=1.0 / scale)[:, None]
        estimates, _info = sensors.bake_irradiance(scene, request.view_layer, placed, normals, samples=1, texels=1,
                                                   cancelled=request.cancelled, seed0=int(seed))
        return estimates[0] / request.unit_area


def measure(request, model, plan_, points_m, normals, offset, *, target, target_abs=None):
    """The rest at the meters ``points_m`` (N, 3) (all usable) as ``adaptive.render_hybrid`` returns a run: rounds of
    ``DRAWS`` independent draws until each meter's scalar error is within ``target`` of its reading (``offset`` (N,)
    W/m^2: the caller's proven part, CIE-Y weighted) or ``target_abs`` (W/m^2), at most ``MAX_ROUNDS``."""
    import time

    started = time.perf_counter()
    weights = request.weights
    rng = np.random.default_rng(int(request.seed) + 104729)
    c = len(plan_.cells)
    draws, seed, rounds = [], int(request.seed), 0
    bounces = request.preset()["bounces"]
    reached = False
    while rounds < MAX_ROUNDS:
        if request.cancelled is not None and request.cancelled():
            raise MeasurementCancelled("measurement cancelled; the scene was restored")
        ys = np.concatenate([gather.uniform_points(plan_.cells, rng) for _ in range(DRAWS)])
        e = _bake(request, model, ys, np.tile(plan_.inward, (DRAWS, 1)), seed + rounds, bounces)
        radiance = np.tile(plan_.albedo, (DRAWS, 1)) * e / np.pi                       # (DRAWS * C, 3)
        for k in range(DRAWS):
            part = slice(k * c, (k + 1) * c)
            w = gather.transfer(points_m, normals, ys[part], plan_.inward, plan_.areas)  # (N, C)
            draws.append(w @ radiance[part])                                            # (N, 3)
        rounds += 1
        values = np.array(draws)                                                        # (D, N, 3)
        mean_rgb = values.mean(axis=0)
        se_rgb = values.std(axis=0, ddof=1) / np.sqrt(len(values))
        se = (values @ weights).std(axis=0, ddof=1) / np.sqrt(len(values))
        need = np.abs(mean_rgb @ weights + offset) * (target or 0.0)
        if target_abs is not None:
            need = np.maximum(need, target_abs)
        if request.progress is not None:
            from ...progress import reporter

            reporter(request.progress)(rounds, MAX_ROUNDS, None)
        if np.all(se <= need):
            reached = True
            break
    spent = np.full(len(points_m), len(draws) * c)
    return {"mean_rgb": mean_rgb, "se_rgb": se_rgb, "se": se, "samples": spent, "rounds": rounds,
            "stopped": "target reached" if reached else f"{MAX_ROUNDS} rounds", "reached": reached,
            "seconds": time.perf_counter() - started, "record": {"bounces": bounces, "surface_gather": True},
            "groups": 1, "dark": np.zeros(len(points_m), bool), "pooled": None, "pool_groups": [],
            "cells": c, "draws": len(draws)}

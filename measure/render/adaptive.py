"""Rendered irradiance with per-meter, error-targeted sample allocation and the hybrid split.

Host side of ``radiometry.sampling.allocation``: each round builds sensor quads (``sensors.build_sensor``)
for the blocks the plan gives every meter (a meter that has converged gets none), bakes them all in
ONE Cycles bake (one scene sync per round), and hands the texels back to the allocator.

Hybrid: a light whose direct light at a meter is a proven closed form (``scene_model`` EXACT or
ZERO) is excluded from that meter's sensor by light linking (the light's receiver collection set to
EXCLUDE the sensor object). Light linking in bakes removes exactly the light's direct share and
keeps its reflected light (docs/FACTS.md), so the bake renders only what no closed form
gives, and the closed form is added to it exactly. Meters that exclude different sets of lights get
sensor objects of their own. The lights' linking is restored by the scene guard.
"""

import time

import bpy
import numpy as np

from ...errors import MeasurementCancelled, RadiometerError
from ...radiometry.sampling import allocation
from . import render_settings, sensors
from ..capture import scene_capture
from ..blender import scene_guard


#: With a ``cancelled`` callback (the UI's Esc, the CLI's Ctrl-C), a round is split into bakes of
#: about this many seconds each (by the previous bake's time per sample): one extra scene sync per
#: second of baking buys a cancel that answers within about a second.
CHUNK_SECONDS = 1.0


def _call_progress(progress, fraction, seconds_left):
    if progress is not None:
        from ...progress import reporter  # one adapter for both callback forms

        reporter(progress)(int(round(1000 * fraction)), 1000, seconds_left)


def _linking_collection(snapshot, light_obj, name):
    """A receiver collection for ``light_obj`` (created, so the guard removes it), its old value remembered."""
    linking = light_obj.light_linking
    snapshot.remember(linking, "receiver_collection")
    coll = bpy.data.collections.new(name)
    linking.receiver_collection = coll
    return coll


def _exclude_from(coll, obj):
    coll.objects.link(obj)
    # collection_objects follows coll.objects' order and has no names: index lookup (FACTS.md).
    i = list(coll.objects).index(obj)
    coll.collection_objects[i].light_linking.link_state = "EXCLUDE"


def render_hybrid(request, points_scene, normals, *, needs, bounces, target=None,
                  time_budget=None, fixed_samples=None, exclusions=None, offset=None,
                  max_samples=allocation.MAX_SAMPLES_PER_METER, panes=None,
                  may_be_lit=None, min_samples=None, pooled=False, target_abs=None, stop_dark=False):
    """Rendered irradiance at the sensors, W/m^2 SI, each meter sampled to its own need.

    ``request`` (``measure.blender.request``): the scene and view layer rendered, the CIE Y weights the
    target applies to, the first seed, progress and cancel; ``target``, ``time_budget`` and
    ``fixed_samples`` are the budget as the meter resolved it from the request's preset.

    ``exclusions``: per meter, a frozenset of light OBJECT identities (``meter.light_object_key``: session
    uid, library) whose direct light is added analytically (excluded from that meter's sensor);
    ``offset`` (N,): that analytic part's scalar (CIE-Y weighted) irradiance, W/m^2, so the target
    applies to the whole reading. Returns a dict:
    mean_rgb (N, 3) and se_rgb (N, 3) of the rendered part, se (N,) scalar, samples (N,),
    rounds, stopped, reached, seconds, record (render settings).
    ``panes``: thin glass panes (``SceneModel.panes``), rendered as thin panes (``measure.capture.glass``).
    ``pooled``: with a target, pool groups of many meters on one plane (``radiometry.sampling.pooled_field``);
    then ``pooled`` (N,) bool says which readings are the fitted field's, ``pool_groups`` their checks.
    ``target_abs``: the absolute floor of the scalar 1-sigma error, W/m^2 (``allocation.allocate``); a
    pooled field keeps the relative target alone (its meters read on their own take the floor).
    """
    n = len(points_scene)
    scene, view_layer = request.scene, request.view_layer
    progress, cancelled, seed = request.progress, request.cancelled, request.seed
    scale = request.scale_length
    exclusions = exclusions or [frozenset()] * n
    offset = np.zeros(n) if offset is None else np.asarray(offset, float)
    groups = {}
    for k, ex in enumerate(exclusions):
        groups.setdefault(frozenset(ex), []).append(k)
    group_keys = list(groups)
    group_of = np.empty(n, int)
    for g, key in enumerate(group_keys):
        group_of[groups[key]] = g
    started = time.perf_counter()
    state = {"seed": int(seed), "bakes": 0, "bake_seconds": 0.0}
    texels = allocation.BLOCK_TEXELS
    weights = request.weights

    with scene_guard.preserved_scene(scene) as snapshot:
        record = render_settings.apply(scene, samples=allocation.PILOT_SPP, bounces=bounces, needs=needs)
        # The table is rotated per texel (render_settings.ROTATED_TABLE, issue 32): unbiased, texels
        # independent, so the fixed table's floor is no longer a bias. The allocator still plans and states
        # it: it moves rare-path meters to large tables in few sensor blocks, and a bake's CPU per sample
        # grows with co-located blocks (without it: 128 spp in ~700 blocks, 15x the CPU per reading at
        # standard, bench/sensor_block_cost.md). The stated error is then conservative by that floor.
        table_patterns = allocation.TABLE_PATTERNS
        if panes:  # issue 18: a pane refracting a small light is a caustic; thin glass converges
            from ..capture import glass

            record = dict(record, thin_panes=glass.swap_panes(snapshot, panes))
        # One receiver collection per excluded light, filled each round with its groups' sensors.
        # Keyed by the light object's identity (meter.light_object_key: session uid, library), never its name.
        light_keys = {ident for key in group_keys for ident in key}
        found = scene_capture.source_objects(light_keys)
        linking = {}
        for ident in sorted(light_keys, key=str):
            obj = found.get(tuple(ident))
            if obj is None or obj.type not in ("LIGHT", "MESH"):
                raise RadiometerError(f"a light or emitter of the scene (session uid {ident[0]}) vanished during the measurement")
            linking[ident] = _linking_collection(snapshot, obj, f"radiometer_exclude {obj.name}")
        previous = []

        def bake(spp, blocks):
            """One round: one bake, or with ``cancelled`` several of about CHUNK_SECONDS each (a
            bake cannot be interrupted from Python, so Esc and Ctrl-C act between them)."""
            blocks = np.asarray(blocks, int)
            per_sample = state.get("seconds_per_sample")
            if cancelled is None or per_sample is None:
                return bake_chunk(spp, blocks)
            limit = max(1, int(CHUNK_SECONDS / (per_sample * spp * texels * texels)))  # blocks per chunk
            if blocks.sum() <= limit:
                return bake_chunk(spp, blocks)
            ends = np.cumsum(blocks)
            parts, start = [], 0
            while start < ends[-1]:
                stop = start + limit
                # Blocks of the chunk: each meter's blocks that fall in [start, stop).
                chunk = np.clip(np.minimum(ends, stop) - np.maximum(ends - blocks, start), 0, None)
                parts.append(bake_chunk(spp, chunk))
                start = stop
            return tuple(np.concatenate(p) for p in zip(*parts))

        def bake_chunk(spp, blocks):
            if cancelled is not None and cancelled():
                raise MeasurementCancelled("measurement cancelled; the scene was restored")
            for obj, image in previous:  # last round's sensors: free them now, not at the end
                mesh, materials = obj.data, list(obj.data.materials)
                bpy.data.objects.remove(obj, do_unlink=True)
                bpy.data.meshes.remove(mesh)
                for mat in materials:
                    bpy.data.materials.remove(mat)
                bpy.data.images.remove(image)
            if previous:
                view_layer.update()  # drop the removed objects' bases before touching selection
            previous.clear()
            built = []
            for g, key in enumerate(group_keys):
                meters = np.flatnonzero((group_of == g) & (blocks > 0))
                if not meters.size:
                    continue
                meter_of_block = np.repeat(meters, blocks[meters])
                obj, image, per_row = sensors.build_sensor(scene, points_scene[meter_of_block],
                                                           normals[meter_of_block], texels)
                for ident in key:
                    _exclude_from(linking[ident], obj)
                built.append((obj, image, per_row, meter_of_block))
                previous.append((obj, image))
            scene.cycles.seed = state["seed"]
            scene.cycles.samples = int(spp)
            state["seed"] += 1
            sensors.select_only(view_layer, [b[0] for b in built])
            t0 = time.perf_counter()
            result = sensors.run_bake(scene, view_layer, [b[0] for b in built])
            seconds = time.perf_counter() - t0
            state["bake_seconds"] += seconds
            state["bakes"] += 1
            state["seconds_per_sample"] = seconds / max(float(blocks.sum()) * texels * texels * spp, 1.0)
            if result != {"FINISHED"}:
                raise RadiometerError(f"the Cycles bake did not finish ({', '.join(sorted(result))}); "
                                      "the scene was restored")
            idx, rgb = [], []
            for obj, image, per_row, meter_of_block in built:
                values = sensors.read_blocks(image, per_row, texels, len(meter_of_block))  # (B, t*t, 3)
                idx.append(np.repeat(meter_of_block, texels * texels))
                rgb.append(values.reshape(-1, 3))
            idx = np.concatenate(idx)
            rgb = np.concatenate(rgb) / request.unit_area  # Cycles renders per scene unit^2: to SI
            return idx, rgb @ weights, rgb

        def report(fraction, seconds_left):
            _call_progress(progress, fraction, seconds_left)

        if pooled and target is not None and time_budget is None and fixed_samples is None:
            # Issue 17: groups of many meters on one plane pool their rendered light in a fitted field,
            # its misfit checked on held-out meters (radiometry.sampling.pooled_field); the rest as below.
            from ...radiometry.sampling import pooled_field

            result = pooled_field.allocate_pooled(bake, n, points_m=points_scene * scale, normals=normals,
                                                  target=target, keys=exclusions, offset=offset, seed=seed,
                                                  progress=report, may_be_lit=may_be_lit, min_samples=min_samples,
                                                  max_samples=max_samples, table_patterns=table_patterns,
                                                  target_abs=target_abs, stop_dark=stop_dark)
        else:
            result = allocation.allocate(bake, n, target=target, time_budget=time_budget,
                                         fixed_samples=fixed_samples, offset=offset, max_samples=max_samples,
                                         progress=report, may_be_lit=may_be_lit, min_samples=min_samples,
                                         table_patterns=table_patterns,
                                         target_abs=target_abs, stop_dark=stop_dark)
    tally = result.tally
    record = dict(record, samples=None, rounds=result.rounds, bakes=state["bakes"])
    return {
        "mean_rgb": tally.mean_rgb, "se_rgb": tally.std_error_rgb, "se": tally.std_error,
        "samples": result.samples, "rounds": result.rounds, "stopped": result.stopped, "reached": result.reached,
        "seconds": time.perf_counter() - started, "bake_seconds": state["bake_seconds"], "record": record,
        "round_log": tally.rounds, "groups": len(group_keys),
        "dark": allocation.dark_meters(tally, may_be_lit),
        "pooled": getattr(result, "pooled", None), "pool_groups": getattr(result, "groups", []),
    }

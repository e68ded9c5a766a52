"""Measurement-grade Cycles settings, enabling only the render features the scene needs.

What the scene needs (``SceneModel.needs``: geometry, glossy, transmission, volumes, emitting
surfaces, an emitting world) is read by ``measure.capture.scene_capture`` from the render depsgraph, with
the node-type sets of ``measure.capture.shader_kinds``; ``apply(scene, ...)`` writes the settings; callers run inside ``scene_guard.preserved_scene`` so the user's settings come
back afterwards. The returned dict records what was enabled and why (it goes into readings' notes).
"""

import contextlib

import numpy as np

def _layer_override_targets(scene):
    """(struct, attribute, neutral value) for the view-layer overrides that are pointers or live on
    layer collections: the scene guard does not snapshot these, so they are switched off here and
    restored by whoever calls ``suspend_layer_overrides``."""
    targets = []
    for layer in scene.view_layers:
        # A material/world override replaces every material (the sensor's white diffuse too) or the
        # world for this layer: a render trick, not the scene's light (measured: world override
        # changed a bake by +2 %, a material override made an emitter read 0).
        targets.append((layer, "material_override", None))
        if hasattr(layer, "world_override"):
            targets.append((layer, "world_override", None))
        stack = list(layer.layer_collection.children)
        while stack:
            lc = stack.pop()
            stack.extend(lc.children)
            # Holdout renders a collection black; indirect-only hides it from camera rays: a
            # luminance meter looking at such a surface read 0 instead of its radiance.
            targets.append((lc, "holdout", False))
            targets.append((lc, "indirect_only", False))
    return targets


def suspend_layer_overrides(scene, snapshot=None):
    """Switch off view-layer material/world overrides and holdout/indirect-only collections.

    With ``snapshot`` (a ``scene_guard.SceneSnapshot``) the old values are restored when the guard
    exits; without it, the caller restores with the returned list of (struct, attr, old value).
    """
    changed = []
    for struct, attr, neutral in _layer_override_targets(scene):
        old = getattr(struct, attr)
        if old != neutral:
            if snapshot is not None:
                snapshot.remember(struct, attr)
            changed.append((struct, attr, old))
            setattr(struct, attr, neutral)
    return changed


def restore_layer_overrides(changed):
    for struct, attr, old in reversed(changed):
        setattr(struct, attr, old)


@contextlib.contextmanager
def layer_overrides_suspended(scene):
    """Context manager form of ``suspend_layer_overrides`` (restores on exit, even on error)."""
    changed = suspend_layer_overrides(scene)
    try:
        yield changed
    finally:
        restore_layer_overrides(changed)


class _Writes:
    """Every setting ``apply`` writes (struct, attribute, value), and those this Blender lacks."""

    current = None

    def __init__(self):
        self.items, self.missing = [], []


def _label(struct, attr):
    if type(struct).__name__ == "_Recorder":
        struct = object.__getattribute__(struct, "_struct")
    return f"{type(struct).__name__}.{attr}"


def _set(struct, attr, value):
    # Properties that a Blender version lacks (or whose enum item it lacks) are skipped, not fatal,
    # and recorded (issue 18: "a missing property is a note, not silence"; a misspelt name shows
    # up there too, and the audit test requires that list to be empty on the pinned Blender).
    log = _Writes.current
    if not _has_setting(struct, attr):  # Blender 4.5 lets setattr of an unknown name pass silently
        if log is not None:
            log.missing.append(f"{_label(struct, attr)}: no such setting")
        return
    try:
        setattr(struct, attr, value)
    except (AttributeError, TypeError, ValueError) as exc:
        if log is not None:
            what = "no such setting" if not hasattr(struct, attr) else f"value {value!r} not available ({exc})"
            log.missing.append(f"{_label(struct, attr)}: {what}")
        return
    if log is not None:
        log.items.append((struct, attr, value))


def _has_setting(struct, attr):
    """True if ``attr`` is a property of the settings struct (RNA, Python-defined ones included).

    On Blender 4.5 a Python-defined property group such as ``scene.cycles`` accepts ``setattr`` of
    any name (a plain attribute, no error); on 5.0 an unknown name raises. Asking the RNA works on both.
    """
    rna = getattr(struct, "bl_rna", None)
    return attr in rna.properties if rna is not None else hasattr(struct, attr)


class _Recorder:
    """Writes through to a settings struct and logs every write for the read-back."""

    def __init__(self, struct):
        object.__setattr__(self, "_struct", struct)

    def __getattr__(self, attr):
        return getattr(object.__getattribute__(self, "_struct"), attr)

    def __setattr__(self, attr, value):
        struct = object.__getattribute__(self, "_struct")
        if not _has_setting(struct, attr):  # strict: a misspelt name raises here (4.5 would not)
            raise AttributeError(f"{_label(struct, attr)}: no such setting")
        setattr(struct, attr, value)
        if _Writes.current is not None:
            _Writes.current.items.append((struct, attr, value))


def _same(got, want):
    if isinstance(want, float) or isinstance(got, float):
        if float(np.float32(want)) == float(want):
            # exactly a float32 (1 - 2^-20, 0.0, 1.0): it must read back exactly, since the tolerance
            # below could not tell ROTATED_TABLE from 1.0
            return float(got) == float(want)
        return abs(float(got) - float(want)) <= 1e-6 * max(1.0, abs(float(want)))  # float32 storage
    return got == want


def read_back(items):
    """Compare every written setting with what Blender now holds; raises ``RadiometerError`` naming
    the first that did not take (clamped, ignored, overwritten by a dependent setting)."""
    from ...errors import RadiometerError

    for struct, attr, want in items:
        got = getattr(struct, attr)
        if not _same(got, want):
            raise RadiometerError(f"render setting {_label(struct, attr)} = {want!r} did not take (reads {got!r}); "
                                  "the measurement would not be what it states")
    return len(items)


#: Volume scatter events a path may have when the scene has a medium, per bounce of the preset
#: (preview 128, standard 512, reference 1024 = Cycles' largest). Why so many: ``_apply``.
VOLUME_BOUNCE_FACTOR = 8

#: Scrambling distance of every measurement (issue 32; scenes with a medium since issue 18): below 1 by 2^-20 (exact in float32), so Cycles rotates
#: each texel's table by a uniform shift of [0, 1 - 2^-20) per dimension (unbiased to ~1e-6). Why: ``_apply``.
ROTATED_TABLE = 1.0 - 2.0 ** -20

#: Cycles' largest bounce limit (the range of max_bounces and of each type's limit).
MAX_BOUNCES = 1024


def apply(scene, *, samples, bounces, needs, seed=0, snapshot=None, custom_camera=False):
    """Write measurement-grade settings; return the record of what was enabled and why.

    Rule: render settings (scene.cycles, scene.render, the view layers' render controls) are the
    measurement's, because they change what Cycles converges to or how the error is estimated;
    data-blocks (objects, lights, materials, world, light linking, ray visibility, per-light
    max bounces) are the user's scene and are measured as they are. ``snapshot``: the active
    ``scene_guard.SceneSnapshot``; when given, view-layer pointer overrides are suspended too
    (bakes do that per bake in ``sensors.run_bake``). ``custom_camera``: the render looks through the meter
    camera, an OSL custom camera (``measure.blender.device``: the CPU unless the user's back-end is OptiX).
    """
    writes = _Writes.current = _Writes()
    try:
        return _apply(scene, samples=samples, bounces=bounces, needs=needs, seed=seed, snapshot=snapshot,
                      writes=writes, custom_camera=custom_camera)
    finally:
        _Writes.current = None


def _apply(scene, *, samples, bounces, needs, seed, snapshot, writes, custom_camera=False):
    cy = _Recorder(scene.cycles)
    r = _Recorder(scene.render)
    r.engine = "CYCLES"
    from ..blender.device import measurement_device

    # the user's GPU where it can (issue 17); a custom (OSL) camera only on the CPU or OptiX
    device, device_label, device_note = measurement_device(scene, custom_camera)
    cy.device = device
    cy.samples = int(samples)
    # A view layer's own sample count (view_layer.samples != 0) overrides scene samples in camera
    # renders (measured: 1 layer sample instead of 1024); the record must state what was used.
    cy.use_layer_samples = "IGNORE"
    _set(cy, "use_sample_subset", False)  # a subset renders fewer samples than recorded
    _set(cy, "sample_offset", 0)
    _set(cy, "time_limit", 0.0)  # a time limit stops before the recorded sample count
    cy.use_adaptive_sampling = False  # a noise threshold would stop early with a biased error estimate
    cy.use_denoising = False
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.light_sampling_threshold = 0.0  # the default 0.01 culls dim lights
    cy.seed = int(seed)
    cy.use_animated_seed = False
    # Batch means treat every texel/pixel as independent. Scrambling distance < 1 (or automatic)
    # makes neighbouring pixels share samples (distance 0: all texels identical, stated error 0);
    # (0.1: mean -6.6 % off, stated error 0.03 %); blue noise (also what AUTOMATIC picked) anti-
    # correlates neighbours (rho ~ -0.1); path guiding learns from other pixels (measured: error 7x
    # larger; -1.3 % combined with opaque lights). Tabulated Sobol with scrambling distance 1: each
    # pixel draws from one of 256 fixed patterns (NUM_TAB_SOBOL_PATTERNS), only shuffled per pixel,
    # so texels are independent draws of a finite table: rare paths get the table's floor
    # (radiometry/sampling/allocation.py, docs/errors.md).
    # With a participating medium the table's floor is below HEAVY_TAIL and unstated, yet it is what
    # a 512-sample reading in fog reads: -0.20 ... -0.25 % over 40 seeds at 0.56-0.85 % stated (90-95 %
    # coverage). There the scrambling distance is ROTATED_TABLE, just below 1: Cycles then gives every
    # texel the same pattern, rotated by its own uniform shift in each dimension (Cranley-Patterson),
    # so every sample is uniform on the unit cube and a texel's mean is unbiased, whatever the table;
    # texels stay independent (independent shifts). Measured there: -0.16 ... +0.03 %, 95-97.5 %
    # coverage (bench/volume_floor.md).
    # Issue 32: the same holds for rare paths without a medium. With the fixed table (distance 1) the fin
    # scene's 97 %-hidden meter read mean z -0.52 / -0.82 (sequential / staged rule, 92 / 86 % coverage) at
    # preview over 50 seeds, its table floor stated; rotated, the same seeds read -0.03 / -0.23 (98 / 92 %)
    # (bench/coverage_rare_paths_fin_stopping.md). So every measurement rotates the table, and the
    # allocator still plans the fixed table's floor for speed (``adaptive.render_hybrid``). Same CPU per sample.
    _set(cy, "sampling_pattern", "TABULATED_SOBOL")
    cy.scrambling_distance = ROTATED_TABLE
    cy.auto_scrambling_distance = False
    cy.use_guiding = False
    cy.use_fast_gi = False  # AO approximation of indirect light (measured: indirect light -> 0)
    # Forward-only path tracing misses delta lights, NEE-only misses emission found by BSDF rays.
    # (Release builds ignore the setting; set it in case a debug build reads it.)
    _set(cy, "direct_light_sampling_type", "MULTIPLE_IMPORTANCE_SAMPLING")
    _set(cy, "volume_biased", False)  # ray-marched volumes are biased; null scattering is not
    cy.film_exposure = 1.0  # film exposure scales the data itself (measured: bake x4 for exposure 4)
    # Box filter of one pixel: each pixel is the mean radiance over its own area, which is what the
    # luminance meter's cos^3 weights and the map integration assume (a 20 px Gaussian: -1 %).
    cy.pixel_filter_type = "BOX"
    r.use_persistent_data = False
    r.film_transparent = False
    r.filter_size = 0.01  # EEVEE/Workbench pixel filter (Cycles reads pixel_filter_type above)
    # Simplify approximates the scene (subdivision, particles, volume resolution, texture limit,
    # camera/distance culling relative to the user's camera, fast-GI AO bounces): the measurement
    # uses the scene at full render definition.
    r.use_simplify = False
    _set(cy, "texture_limit_render", "OFF")
    _set(cy, "use_camera_cull", False)
    _set(cy, "use_distance_cull", False)
    # A reading is at one instant (the current frame), like the analytic method.
    r.use_motion_blur = False
    # Camera renders: stamp text burnt into the pixels (measured 2.5 -> 0.81), Freestyle strokes,
    # stereo views (two files with offset cameras), lossy EXR codecs (DWAA: -0.08 %).
    r.use_stamp = False
    r.use_freestyle = False
    r.use_multiview = False
    _set(r.image_settings, "exr_codec", "ZIP")
    _set(r.image_settings, "color_management", "FOLLOW_SCENE")
    # Bake options the operator does not take as arguments come from the scene's bake settings.
    _set(r.bake, "view_from", "ABOVE_SURFACE")
    for layer in map(_Recorder, scene.view_layers):
        # Layer filters are compositing tools: without Sky the world's light vanishes from bakes
        # (measured), without Solid camera renders see no surfaces at all.
        layer.use_sky = True
        layer.use_solid = True
        layer.use_strand = True
        layer.use_volumes = True
        layer.use_motion_blur = False
        if hasattr(layer, "cycles"):
            _Recorder(layer.cycles).use_denoising = False
    overrides = [f"{getattr(s, 'name', '?')}.{a}" for s, a, _ in suspend_layer_overrides(scene, snapshot)] \
        if snapshot is not None else []
    # A world volume scatters light with no geometry in the scene: bounces are needed for it too.
    interreflection = bounces if (needs["geometry"] or needs.get("volume")) else 0
    cy.diffuse_bounces = interreflection
    cy.glossy_bounces = interreflection if needs["glossy"] else 0
    cy.transmission_bounces = interreflection if needs["transmission"] else 0
    # Volume scattering gets VOLUME_BOUNCE_FACTOR times the preset's limit. A medium that does not
    # absorb (Volume Scatter: albedo 1) keeps a path's throughput at 1, so Russian roulette never ends
    # it, and in an unbounded world volume the light of high orders fades only as it diffuses away (a
    # power law, not a^n). Measured (world Volume Scatter 0.08/m over a floor, against 1024-bounce
    # patch renders, bench/volume_bounces.md): 16 volume bounces read 0.24 % low, 32 0.16 %, 64 0.10 %,
    # 128 0.05 %, 256 0.02 %, 512 and 1024 0.00 % (± 0.04 %); there the time grows about linearly with
    # the limit (128: 7x, 1024: 60x the time of 16).
    # Absorbing media and rooms lose throughput and roulette ends their paths long before the limit.
    cy.volume_bounces = min(int(VOLUME_BOUNCE_FACTOR * interreflection), MAX_BOUNCES) if needs["volume"] else 0
    # Lights are transparent to rays and every crossing of a light counts as a transparent bounce:
    # 0 made every light opaque (a light behind another was lost: -2.8 %). Crossings cost nothing
    # unless they happen, so use Cycles' maximum.
    cy.transparent_max_bounces = 1024
    # The total is the sum of the per-type limits, within Cycles' range (0 ... 1024): with a medium
    # the volume limit alone fills it, and each type is still held to its own limit.
    cy.max_bounces = min(cy.diffuse_bounces + cy.glossy_bounces + cy.transmission_bounces + cy.volume_bounces,
                         MAX_BOUNCES)
    cy.caustics_reflective = bool(needs["glossy"])
    cy.caustics_refractive = bool(needs["transmission"])
    # Per-light / world bounce limits are data (the user's light definition, like ray visibility):
    # measured as they are, but stated in the record because they cut interreflected light.
    limited = sorted(ob.name for ob in scene.objects if ob.type == "LIGHT" and hasattr(ob.data, "cycles")
                     and ob.data.cycles.max_bounces < interreflection)
    if scene.world is not None and hasattr(scene.world, "cycles") and scene.world.cycles.max_bounces < interreflection:
        limited.append(f"world {scene.world.name}")
    return {
        "engine": f"CYCLES ({device_label})",
        "device": device,
        "device_note": device_note,
        "samples": int(samples),
        "max_bounces": cy.max_bounces,
        "diffuse_bounces": cy.diffuse_bounces,
        "glossy_bounces": cy.glossy_bounces,
        "transmission_bounces": cy.transmission_bounces,
        "volume_bounces": cy.volume_bounces,
        "transparent_bounces": cy.transparent_max_bounces,
        "caustics": bool(needs["glossy"] or needs["transmission"]),
        "denoising": False,
        "clamping": False,
        "filter_glossy": 0.0,
        "light_threshold": 0.0,
        "film_exposure": 1.0,
        "pixel_filter": "BOX 1 px",
        "sampling": (f"TABULATED_SOBOL, scrambling distance {cy.scrambling_distance:.7g}"
                     + (" (each texel's table rotated by its own uniform shift)" if cy.scrambling_distance < 1.0
                        else "") + ", no guiding, no fast GI"),
        "scrambling_distance": float(cy.scrambling_distance),
        "simplify": False,
        "motion_blur": False,
        "suspended_layer_overrides": overrides,
        "bounce_limited_lights": limited,
        "scene_has": {k: bool(v) for k, v in needs.items()},
        # Issue 18: every write read back (raises on a mismatch); settings this Blender lacks.
        "settings_read_back": read_back(writes.items),
        "settings_missing": list(writes.missing),
    }

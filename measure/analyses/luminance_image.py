"""False-colour images of the camera view (host side): per-pixel luminance (cd/m²) with its standard
error, written as a 32-bit EXR and a false-colour PNG with a legend.

Method: independent Cycles renders of the scene camera's view (new seed each, measurement-grade
settings as for the spot meter: no denoising, clamping or adaptive sampling, box pixel filter of one
pixel, lights visible to camera rays) at ``spp`` samples; per pixel the mean and the batch-means
standard error std / sqrt(renders). Rounds of :data:`RENDERS` renders; when the 90th percentile of the
pixels' relative error is above the quality's target the next round renders at 4x the samples (up to
1024: float32 accumulation), and only the last round is kept.
A pixel's luminance = K x CIE Y of its radiance (the scene's working colour space and efficacy).
Delta lights (radius 0) are invisible to camera rays: they light the scene but are not seen.
"""

import dataclasses
import math
import shutil
import time

import bpy
import numpy as np

from ... import quality as quality_presets
from ...errors import RadiometerError
from ..meter import camera as camera_mod
from ..blender import scene_guard
from ..render.rounds import RenderRounds, relative_errors

RENDERS = 8            #: independent renders per round (7 degrees of freedom per pixel error)
MAX_SPP = 1024
FIRST_SPP = 16         #: samples per pixel of the first round
#: Cap on the samples per pixel per render at quality "preview" where the caller gives none: a picture
#: at preview is one round (as the report's pictures, ``client_report.PICTURE_SPP``). Issue 31: a glare
#: picture of a sunlit room took 9 min 49 s at preview, 160 x 120 px, rounds of 16, 64, 256 and 1024 spp,
#: its walls lit by the sun patch's reflection (found by BSDF rays) never reaching 5 % at the 90th
#: percentile; the notes say how many pixels reached the target.
PREVIEW_MAX_SPP = 16
MAX_PIXELS = 1024 * 1024


@dataclasses.dataclass
class LuminanceImage:
    """Per-pixel luminance of the camera view. Arrays (H, W), top row first."""

    luminance: np.ndarray          #: cd/m²
    rel_std_error: np.ndarray      #: 1 s.e. relative (nan where the luminance is 0)
    radiance_rgb: np.ndarray       #: (H, W, 3) W/(m² sr)
    camera: str
    resolution: tuple              #: (width, height) px
    samples: int                   #: samples per pixel over the kept renders
    target_rel_error: float
    share_on_target: float         #: fraction of lit pixels whose error reached the target
    efficacy: float
    colour_space: str
    seconds: float
    notes: list
    paths: dict = dataclasses.field(default_factory=dict)  #: "exr", "png"

    def to_dict(self):
        d = {k: v for k, v in dataclasses.asdict(self).items() if k not in ("luminance", "rel_std_error",
                                                                          "radiance_rgb")}
        d["luminance_stats"] = {"min": float(np.min(self.luminance)), "max": float(np.max(self.luminance)),
                                "mean": float(np.mean(self.luminance))}
        return d


def _resolution(scene, resolution):
    if resolution is None:
        r = scene.render
        w = r.resolution_x * r.resolution_percentage / 100
        h = r.resolution_y * r.resolution_percentage / 100
        k = min(1.0, 320.0 / max(w, h))
        return max(1, round(w * k)), max(1, round(h * k))
    try:
        w, h = (int(v) for v in resolution)
    except (TypeError, ValueError):
        raise RadiometerError(f"resolution must be two integers (width, height), got {resolution!r}") from None
    if w < 1 or h < 1 or w * h > MAX_PIXELS:
        raise RadiometerError(f"resolution must be at least 1 x 1 and at most {MAX_PIXELS} pixels, got {w} x {h}")
    return w, h


def _cap(quality, max_spp):
    """Samples per pixel per render at most: ``max_spp`` (16..MAX_SPP), or by default MAX_SPP, and
    PREVIEW_MAX_SPP at quality "preview"."""
    if max_spp is None:
        max_spp = PREVIEW_MAX_SPP if quality == "preview" else MAX_SPP
    return int(min(max(int(max_spp), FIRST_SPP), MAX_SPP))


def _rounds_to_target(request, render, target, cap):
    """Rounds of :data:`RENDERS` renders from 16 samples per pixel, 4x per round up to ``cap``, until the
    90th percentile of the lit pixels' relative error (of the request's CIE Y) is on ``target``; only the
    last round is kept. The request's ``time_budget_s``: no round is started that would end past the budget
    (its time predicted from the last round's, in proportion to the samples); the first round always runs;
    its cancel and progress go to the rounds.
    Returns (the last round's renders (R, H, W, 3), (mean Y, relative s.e.) per pixel, the finite
    relative errors, samples per pixel, why it stopped)."""
    weights, time_budget_s = request.weights, request.time_budget_s
    rounds = RenderRounds(request.scene, cancelled=request.cancelled, progress=request.progress)
    spp = FIRST_SPP
    started = time.perf_counter()
    while True:
        t0 = time.perf_counter()
        stack = rounds.round(RENDERS, spp, render)            # (R, H, W, 3)
        took = time.perf_counter() - t0
        mean_y, rel = relative_errors(stack @ weights)
        lit = rel[np.isfinite(rel)]
        p90 = float(np.percentile(lit, 90)) if lit.size else 0.0
        if p90 <= target:
            return stack, (mean_y, rel), lit, spp, "target"
        if spp >= cap:
            return stack, (mean_y, rel), lit, spp, f"the cap of {cap} samples per pixel per render"
        nxt = min(cap, spp * 4)
        if time_budget_s is not None and time.perf_counter() - started + took * nxt / spp > time_budget_s:
            return stack, (mean_y, rel), lit, spp, (f"the time budget of {time_budget_s:g} s (a round at {nxt} "
                                                    f"samples per pixel would take about {took * nxt / spp:.0f} s)")
        spp = nxt


def _short_of_target(share, target, spp, stopped):
    """The note of a picture whose rounds stopped with under 90 % of its lit pixels on the target."""
    if share >= 0.9:
        return []
    return [f"only {100 * share:.0f} % of the lit pixels reached the {100 * target:g} % target at {spp} samples per "
            f"pixel (stopped by {stopped}); each pixel's error is in rel_std_error"]


def render_luminance(*, request, camera=None, resolution=None, max_spp=None):
    """:class:`LuminanceImage` of ``camera`` (an object or its name; default the scene camera).

    The request (``measure.blender.request``): the scene, ``quality`` (None: "standard"),
    ``target_rel_error`` (per pixel; None: the preset's), ``time_budget_s`` (no round of renders starts
    that would end past it), progress and cancel. ``max_spp``: cap on the samples per pixel of one render
    (16..1024; None: 1024, at preview ``PREVIEW_MAX_SPP``). The notes say how many pixels reached the
    target and what stopped the rounds."""
    scene, quality, target_rel_error = request.scene, request.quality or "standard", request.target_rel_error
    cam = scene.camera if camera is None else (scene.objects.get(camera) if isinstance(camera, str) else camera)
    if cam is None or getattr(cam, "type", None) != "CAMERA":
        raise RadiometerError("no camera to render from: give camera= or set the scene's camera")
    width, height = _resolution(scene, resolution)
    preset = quality_presets.preset(quality)
    target = float(target_rel_error) if target_rel_error is not None else float(preset["target"])
    space, weights, efficacy = request.photometry
    unit_area = request.unit_area
    folder = camera_mod.scratch_folder()
    started = time.perf_counter()
    cap = _cap(quality, max_spp)
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            camera_mod.prepare_render(scene, dict(preset, samples=FIRST_SPP), snapshot)
            scene.camera = cam

            def render(k):
                return camera_mod.render_exr(scene, folder, f"img{k}", width, height) / unit_area

            stack, (mean_y, rel), lit, spp, stopped = _rounds_to_target(request, render, target, cap)
            mean_rgb = stack.mean(axis=0)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    share = float(np.mean(lit <= target)) if lit.size else 1.0
    notes = [f"{RENDERS} independent renders of {spp} samples per pixel; error per pixel by batch means",
             f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}",
             "delta lights (radius 0) are invisible to camera rays: they light the scene but are not seen"]
    notes += _short_of_target(share, target, spp, stopped)
    return LuminanceImage(luminance=efficacy * mean_y, rel_std_error=rel, radiance_rgb=mean_rgb, camera=cam.name,
                          resolution=(width, height), samples=spp * RENDERS, target_rel_error=target,
                          share_on_target=share, efficacy=efficacy, colour_space=space,
                          seconds=time.perf_counter() - started, notes=notes)


def luminance_image(path, *, request, camera=None, resolution=None, scale="log", range=None,  # noqa: A002
                    max_spp=None):
    """Render :func:`render_luminance` and write ``path`` (.exr: 32-bit, luminance in cd/m² in R, G and
    B) and the false-colour PNG beside it (same stem, .png; legend in cd/m², ``scale`` 'log' | 'linear',
    ``range`` (lo, hi) cd/m² or automatic). Returns the :class:`LuminanceImage` with ``paths``."""
    import os

    from ..authoring import world

    if scale not in ("log", "linear"):
        raise RadiometerError(f"scale must be 'log' or 'linear', got {scale!r}")
    path = os.fspath(path)
    if not path.lower().endswith(".exr"):
        raise RadiometerError(f"path must name an .exr file, got {path!r:.200}")
    if range is not None:
        from ...plots.false_colour_image import scale_range

        try:
            scale_range([1.0], scale, range)
        except ValueError as exc:
            raise RadiometerError(str(exc)) from None
    result = render_luminance(request=request, camera=camera, resolution=resolution, max_spp=max_spp)
    world.write_exr(path, np.repeat(result.luminance[..., None], 3, axis=-1))
    result.paths["exr"] = path
    from ...plots import matplotlib_available

    if matplotlib_available():
        from ...plots.false_colour_image import false_colour_png

        png = os.path.splitext(path)[0] + ".png"
        false_colour_png(png, result.luminance, unit="cd/m²", quantity="luminance", scale=scale, value_range=range,
                         title=f"Luminance seen by {result.camera} ({result.resolution[0]} x {result.resolution[1]} px; "
                               f"{100 * result.share_on_target:.0f} % of the pixels within "
                               f"{100 * result.target_rel_error:g} %)")
        result.paths["png"] = png
    else:
        result.notes.append("no false-colour PNG: matplotlib is not installed (the EXR holds the numbers)")
    return result


# --- illuminance on the visible surfaces --------------------------------------------------------------

@dataclasses.dataclass
class IlluminanceImage:
    """Illuminance (lx) on the surface seen in each pixel, (H, W), top row first."""

    illuminance: np.ndarray
    rel_std_error: np.ndarray
    camera: str
    resolution: tuple
    samples: int
    target_rel_error: float
    share_on_target: float
    efficacy: float
    colour_space: str
    seconds: float
    notes: list
    paths: dict = dataclasses.field(default_factory=dict)

    def to_dict(self):
        d = {k: v for k, v in dataclasses.asdict(self).items() if k not in ("illuminance", "rel_std_error")}
        e = self.illuminance
        seen = e > 0
        d["illuminance_stats_lx"] = {"min": float(np.min(e)), "max": float(np.max(e)), "mean": float(np.mean(e)),
                                     "mean_seen": float(np.mean(e[seen])) if seen.any() else 0.0,
                                     "share_seen": float(np.mean(seen))}
        return d


def _light_pass_compositor(scene):
    """A compositor node group whose output is Diffuse Direct + Diffuse Indirect; returns it."""
    tree = bpy.data.node_groups.new("radiometer_diffuse_light", "CompositorNodeTree")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    layers = tree.nodes.new("CompositorNodeRLayers")
    layers.scene = scene
    add = tree.nodes.new("ShaderNodeMix")
    add.data_type, add.blend_type = "RGBA", "ADD"
    add.inputs["Factor"].default_value = 1.0
    tree.links.new(layers.outputs["Diffuse Direct"], add.inputs[6])
    tree.links.new(layers.outputs["Diffuse Indirect"], add.inputs[7])
    tree.links.new(add.outputs[2], tree.nodes.new("NodeGroupOutput").inputs[0])
    return tree


def illuminance_image(path, *, request, camera=None, resolution=None, scale="log", range=None,  # noqa: A002
                      max_spp=None):
    """Illuminance (lx) on the surfaces the camera sees: E = pi x (Diffuse Direct + Diffuse Indirect).

    Why it holds: Cycles writes a BSDF's light passes divided by its colour pass (Combined = (Direct +
    Indirect) x Colour), so on a Lambertian surface (Diffuse BSDF, roughness 0) of any albedo rho the
    passes hold L / rho = E / pi. Measured on a lit wall of albedo 0.3: pi x passes = E to 1e-4 (the
    test compares with the reference patch render). Where it does not hold: surfaces with no diffuse
    component (metals, glass, emitters, the world: 0 there), rough diffuse (Oren-Nayar, roughness > 0,
    whose reflection is not rho E / pi), and the Principled BSDF's diffuse lobe (not verified here).
    Writes ``path`` (.exr, lux in R, G, B) and a false-colour PNG beside it; sampling as
    :func:`render_luminance` (the request's quality, time budget and cancel). Returns :class:`IlluminanceImage`.
    """
    import os

    scene, quality = request.scene, request.quality or "standard"
    if not hasattr(scene, "compositing_node_group"):
        # Blender 4.x has no compositor node groups (the passes are summed in one); not ported yet.
        raise RadiometerError("illuminance images need Blender 5.0 or newer; luminance images "
                              "(luminance_image) work on 4.5 too")
    cam = scene.camera if camera is None else (scene.objects.get(camera) if isinstance(camera, str) else camera)
    if cam is None or getattr(cam, "type", None) != "CAMERA":
        raise RadiometerError("no camera to render from: give camera= or set the scene's camera")
    path = os.fspath(path)
    if not path.lower().endswith(".exr"):
        raise RadiometerError(f"path must name an .exr file, got {path!r:.200}")
    if scale not in ("log", "linear"):
        raise RadiometerError(f"scale must be 'log' or 'linear', got {scale!r}")
    width, height = _resolution(scene, resolution)
    preset = quality_presets.preset(quality)
    target = float(preset["target"])
    space, weights, efficacy = request.photometry
    unit_area = request.unit_area
    cap = _cap(quality, max_spp)
    folder = camera_mod.scratch_folder()
    started = time.perf_counter()
    old_group = scene.compositing_node_group
    layer = request.view_layer
    try:
        with scene_guard.preserved_scene(scene) as snapshot:
            camera_mod.prepare_render(scene, dict(preset, samples=FIRST_SPP), snapshot)
            scene.camera = cam
            for attr in ("use_pass_diffuse_direct", "use_pass_diffuse_indirect"):
                snapshot.remember(layer, attr)
                setattr(layer, attr, True)
            tree = _light_pass_compositor(scene)
            scene.compositing_node_group = tree

            def render(k):
                img = camera_mod.render_exr(scene, folder, f"e{k}", width, height, compositing=True)
                return math.pi * img / unit_area

            _stack, (mean_y, rel), lit, spp, stopped = _rounds_to_target(request.but(progress=None), render, target,
                                                                          cap)
    finally:
        # the scene guard removes the node group it saw created; put the user's compositor back
        scene.compositing_node_group = old_group
        shutil.rmtree(folder, ignore_errors=True)
    share = float(np.mean(lit <= target)) if lit.size else 1.0
    notes = ["E = pi (Diffuse Direct + Diffuse Indirect): holds on Lambertian surfaces (Diffuse BSDF, roughness 0); "
             "0 where nothing diffuse is seen (metal, glass, emitters, the world)",
             f"{RENDERS} independent renders of {spp} samples per pixel; error per pixel by batch means",
             f"luminous efficacy {efficacy:g} lm/W, CIE Y weights of {space}"]
    notes += _short_of_target(share, target, spp, stopped)
    result = IlluminanceImage(illuminance=efficacy * mean_y, rel_std_error=rel, camera=cam.name,
                              resolution=(width, height), samples=spp * RENDERS, target_rel_error=target,
                              share_on_target=share, efficacy=efficacy, colour_space=space,
                              seconds=time.perf_counter() - started, notes=notes)
    from ..authoring import world

    world.write_exr(path, np.repeat(result.illuminance[..., None], 3, axis=-1))
    result.paths["exr"] = path
    from ...plots import matplotlib_available

    if matplotlib_available():
        from ...plots.false_colour_image import false_colour_png

        png = os.path.splitext(path)[0] + ".png"
        false_colour_png(png, result.illuminance, unit="lx", quantity="illuminance", scale=scale, value_range=range,
                         title=f"Illuminance on the surfaces seen by {cam.name} ({width} x {height} px)")
        result.paths["png"] = png
    return result

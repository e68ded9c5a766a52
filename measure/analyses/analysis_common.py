"""Shared parts of the analyses (law checks, grids, convergence): JSON-safe results, the scene and
view layer to measure, the measurement budget handed to the meter, and plot availability.

Host side (bpy). Units as in ``radiometer.api``: scene coordinates in, SI out.
"""

import dataclasses
import math

import bpy
import numpy as np

from ... import plots as _plots
from ...outputs import json_safe
from ..meter import point_meter as meter


# --- JSON-safe results ----------------------------------------------------------------------------

def plain(value):
    """``value`` as JSON-safe Python (numpy arrays as lists, inf/nan as None, results as dicts):
    ``outputs.json_safe``, the one JSON/NaN policy."""
    return json_safe(value)


class ToDict:
    """Mixin for result dataclasses: ``to_dict()``."""

    def to_dict(self):
        """JSON-safe dict (numpy arrays as lists, inf/nan as None)."""
        return {f.name: plain(getattr(self, f.name)) for f in dataclasses.fields(self)}


def row_dict(row):
    """JSON-safe dict of a NamedTuple row (inf/nan as None)."""
    return {k: plain(v) for k, v in row._asdict().items()}


# --- scene, budget, measurement -------------------------------------------------------------------

def scene_or_context(scene):
    return scene or bpy.context.scene


def view_layer_of(scene):
    """The view layer that renders ``scene`` (the context's when it is the context scene)."""
    return bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]


def luminance_weights(scene):
    """(CIE Y weights (3,) of the scene's working space, luminous efficacy lm/W)."""
    _space, weights, efficacy = meter.scene_photometry(scene)
    return weights, efficacy


def budget(quality="standard", target_rel_error=None, samples=None, time_budget_s=None):
    """The meter's accuracy settings as keywords (see ``meter.measure_illuminance``): ``quality`` a
    preset name (target 1-sigma relative error 5 %, 1 %, 0.2 %), ``target_rel_error`` a fraction,
    ``samples`` a fixed count per meter, ``time_budget_s`` seconds per measurement."""
    return {"quality": quality or "standard", "target_rel_error": target_rel_error, "samples": samples,
            "time_budget_s": time_budget_s}


def measure(scene, points_scene, normals, *, method, budget, seed=0, progress=None, cancelled=None,
            direct_only=False, model=None):
    """One batch of illuminance readings (always a list), one scene sync, samples per meter.
    ``model``: the scene's ``SceneModel`` as it is now, when the analysis has it (else captured)."""
    readings = meter.measure_illuminance(points_scene, normals, scene=scene, method=method, seed=seed,
                                         progress=progress, cancelled=cancelled, direct_only=direct_only,
                                         model=model, **budget)
    return readings if isinstance(readings, list) else [readings]


def rel_errors(readings):
    """(N,) stated relative standard errors; 1 (100 %) where a reading has none (a zero reading)."""
    return np.array([r.rel_std_error if math.isfinite(r.rel_std_error) else 1.0 for r in readings])


def can_plot(notes):
    """True if matplotlib is installed; a plot was asked for, so without it this raises the one-line
    RadiometerError of :func:`plots.require_matplotlib` (asked for a file, unable to write it: an
    error, never a silent success). Callers that can do without pictures pass no plot path."""
    _plots.require_matplotlib()
    return True

"""Shared parts of the analyses (law checks, grids, convergence): JSON-safe results, the scene and
view layer to measure, one measurement through the meter, and plot availability.

Host side (bpy). Units as in ``radiometer.api``: scene coordinates in, SI out.
"""

import dataclasses
import math

import bpy
import numpy as np

from ... import plots as _plots
from ...outputs import json_safe
from ..blender import request as request_of
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
    """The view layer that renders ``scene`` (``measure.blender.request.view_layer_of``: one rule)."""
    return request_of.view_layer_of(scene)


def measure(request, points_scene, normals, *, method, direct_only=False, model=None):
    """One batch of illuminance readings (always a list), one scene sync, samples per meter; the request
    (``measure.blender.request``) carries the scene, budget, seed, progress and cancel.
    ``model``: the scene's ``SceneModel`` as it is now, when the analysis has it (else captured)."""
    readings = meter.measure_illuminance(points_scene, normals, request, method=method, direct_only=direct_only,
                                         model=model)
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

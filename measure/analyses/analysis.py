"""Analyses of a Blender scene: law checks, illuminance grids and convergence studies (facade).

One module per capability; this one re-exports their public names so that
``from radiometer.measure import analysis; analysis.check_inverse_square(...)`` keeps working:

* ``law_checks``: inverse-square and cosine-law checks of one light, judged on the light's own
  direct light, with the scene's share (interreflection, shadows) beside it;
* ``light_isolation``: the light under test alone (other lights, instanced ones too, and the
  world off) and its light split into direct and what the scene adds;
* ``grid``: illuminance on a work-plane grid, CSV, isolux PNG, a coloured viewport copy;
* ``convergence_study``: error vs samples and vs wall time, inverted for a target error;
* ``analysis_common``: JSON-safe results, the measurement budget, shared host helpers.

Every analysis measures through ``meter.measure_illuminance`` and takes its accuracy keywords:
``quality`` (target 1-sigma relative error 5 %, 1 %, 0.2 %), ``target_rel_error`` (fraction),
``samples`` (fixed per meter) and ``time_budget_s`` (s). Units: m, W/m^2, lux, deg.
"""

from .analysis_common import plain, plain as _plain  # noqa: F401  (_plain: older name)
from .convergence_study import ConvergenceResult, ConvergenceRow, TargetedReading, convergence_study, write_convergence_plot
from .grid import DISPLAY_OFFSET, GridResult, colour_plane, illuminance_grid, plane_frame
from .law_checks import DEFAULT_ANGLES_DEG, CosineResult, CosineRow, InverseSquareResult, InverseSquareRow, angular_radius, check_cosine_law, check_inverse_square, default_distances, default_location, write_cosine_plot, write_inverse_square_plot
from .light_isolation import LightAndScene, isolated_light, light_object, light_spec, measure_light_and_scene, scene_lights_to_check, source_size

__all__ = [
    "plain", "ConvergenceResult", "ConvergenceRow", "TargetedReading", "convergence_study", "write_convergence_plot",
    "DISPLAY_OFFSET", "GridResult", "colour_plane", "illuminance_grid", "plane_frame", "DEFAULT_ANGLES_DEG",
    "CosineResult", "CosineRow", "InverseSquareResult", "InverseSquareRow", "angular_radius", "check_cosine_law",
    "check_inverse_square", "default_distances", "default_location", "write_cosine_plot",
    "write_inverse_square_plot", "LightAndScene", "isolated_light", "light_object", "light_spec",
    "measure_light_and_scene", "scene_lights_to_check", "source_size",
]

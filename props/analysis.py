"""Analysis settings and the last results (law checks, grid, convergence, report) on the scene.

``bpy.types.Scene.radiometer_analysis``: what the sidebar shows; written by the analysis operators.
"""

import bpy
from bpy.props import (BoolProperty, CollectionProperty, FloatProperty, IntProperty, PointerProperty,
                       StringProperty)


def _is_mesh(_self, obj):
    return obj.type == "MESH"


class RadiometerLawResult(bpy.types.PropertyGroup):
    """One light's last law checks (name = light name)."""

    kind: StringProperty(description="Light type (Point, Spot, Area, Sun)", name="Type")
    inverse_checked: BoolProperty(name="Inverse Square Checked",
                                  description="The inverse-square law has been checked for this light",
                                  default=False)
    inverse_note: StringProperty(name="Inverse Square", description="Why it was not checked")
    exponent: FloatProperty(name="Exponent", description="Fitted exponent of E vs d over the far field (ideal -2)")
    exponent_se: FloatProperty(description="Standard error of the fitted exponent (dimensionless)",
                               name="Exponent s.e.")
    near_field_limit: FloatProperty(name="Near-Field Limit", description="Distance beyond which the deviation "
                                    "from I/d² stays within tolerance, m (0: everywhere; -1: never)", unit="LENGTH")
    inverse_passed: BoolProperty(description="The far-field exponent is -2 within tolerance",
                                 name="Inverse Square Passed")
    inverse_expected: BoolProperty(name="Inverse Square Near Field",
                                   description="The light departs from I/d² exactly as the closed form of its own "
                                   "shape predicts (an extended source's near field, soft falloff): physics, not a fault")
    cosine_checked: BoolProperty(name="Cosine Law Checked",
                                 description="The cosine law has been checked for this light", default=False)
    cosine_max_dev: FloatProperty(name="Cosine Max Deviation", description="max |E(θ)/(E(0) cos θ) - 1|",
                                  subtype="FACTOR")
    cosine_onset: FloatProperty(name="Onset (deg)", description="Smallest failing tilt (-1: none)")
    cosine_passed: BoolProperty(description="E(θ) = E(0) cos θ within tolerance at every tilt",
                                name="Cosine Passed")
    cosine_expected: BoolProperty(name="Cosine Near Field",
                                  description="The light departs from cos θ exactly as the closed form of its own "
                                  "shape predicts (part of an extended source below the meter's horizon): physics")
    inverse_causes: StringProperty(description="Why the inverse-square check deviates (near field, source size, ...)",
                                   name="Inverse-Square Causes")
    cosine_causes: StringProperty(description="Why the cosine check deviates (spot cone, area-light extent, ...)",
                                  name="Cosine Causes")
    inverse_plot: StringProperty(description="PNG plot of E vs distance against I/d²",
                                 name="Inverse-Square Plot", subtype="FILE_PATH")
    cosine_plot: StringProperty(description="PNG plot of E vs tilt against E(0) cos θ",
                                name="Cosine Plot", subtype="FILE_PATH")


class RadiometerAnalysisSettings(bpy.types.PropertyGroup):
    output_dir: StringProperty(name="Output", subtype="DIR_PATH", default="//radiometer/",
                               description="Folder for plots, CSV files and reports (// = next to the .blend)")
    work_plane: PointerProperty(name="Work Plane", type=bpy.types.Object, poll=_is_mesh,
                                description="Plane object whose local XY carries the grid (its +Z side)")
    plane_height: FloatProperty(name="Height", default=0.75, unit="LENGTH",
                                description="Height of a new work plane (EN 12464-1 desks: 0.75 m)")
    use_resolution: BoolProperty(name="Fixed Resolution", default=False,
                                 description="Use a fixed number of points instead of a spacing")
    resolution_x: IntProperty(description="Number of grid points along the work plane's local X",
                              name="X", default=10, min=1, max=500)
    resolution_y: IntProperty(description="Number of grid points along the work plane's local Y",
                              name="Y", default=10, min=1, max=500)
    spacing: FloatProperty(name="Spacing", default=0.0, min=0.0, unit="LENGTH",
                           description="Cell size (0 = EN 12464-1: p = 0.2 x 5^log10(d))")
    colour_plane: BoolProperty(name="Colour in Viewport", default=False,
                               description="Add a coloured copy of the grid (colour attribute) over the plane")
    target_error: FloatProperty(name="Target Error", default=0.01, min=1e-4, max=0.5, subtype="FACTOR",
                                description="Relative error the convergence study solves for")
    laws: CollectionProperty(name="Law Checks",
                             description="Last law-check results, one per light", type=RadiometerLawResult)
    grid_target: StringProperty(description="Work plane of the last illuminance grid", name="Grid")
    grid_nx: IntProperty(name="Grid Points X", description="Number of grid points along X of the last grid")
    grid_ny: IntProperty(name="Grid Points Y", description="Number of grid points along Y of the last grid")
    grid_avg: FloatProperty(description="Average illuminance of the last grid, lx", name="E_avg (lx)")
    grid_min: FloatProperty(description="Minimum illuminance of the last grid, lx", name="E_min (lx)")
    grid_max: FloatProperty(description="Maximum illuminance of the last grid, lx", name="E_max (lx)")
    grid_u0: FloatProperty(description="Uniformity E_min / E_avg of the last grid (dimensionless)", name="U0")
    grid_method: StringProperty(name="Grid Method", description="How the last grid was measured (rendered or analytic)")
    grid_image: StringProperty(name="Grid Image", description="False-colour PNG of the last grid", subtype="FILE_PATH")
    grid_csv: StringProperty(name="Grid CSV",
                             description="CSV file of the last grid's illuminances", subtype="FILE_PATH")
    conv_target: StringProperty(description="Meter of the last convergence study", name="Convergence")
    conv_slope: FloatProperty(description="Fitted slope of log(error) vs log(samples) (ideal -0.5)", name="Slope")
    conv_slope_se: FloatProperty(name="Slope Standard Error", description="Standard error of the convergence slope")
    conv_samples: FloatProperty(description="Samples needed to reach the target error", name="Samples for Target")
    conv_seconds: FloatProperty(description="Estimated render time to reach the target error, s",
                                name="Seconds for Target")
    conv_plot: StringProperty(name="Convergence Plot",
                              description="PNG plot of the error vs samples", subtype="FILE_PATH")
    report_path: StringProperty(description="Last exported report file", name="Report", subtype="FILE_PATH")


classes = (RadiometerLawResult, RadiometerAnalysisSettings)


def register_extra():
    bpy.types.Scene.radiometer_analysis = PointerProperty(type=RadiometerAnalysisSettings)


def unregister_extra():
    del bpy.types.Scene.radiometer_analysis

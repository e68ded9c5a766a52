"""Plain-data results of measurements (no bpy): what a reading carries and how it prints."""

import dataclasses
import math
from typing import Optional


@dataclasses.dataclass
class IlluminanceReading:
    """Irradiance on a surface element and its photometric twin, in SI units.

    ``irradiance`` (W/m^2) is the CIE-Y-weighted scalar of ``irradiance_rgb`` in the scene's
    working colour space, so ``illuminance = efficacy * irradiance`` (lux).
    """

    irradiance_rgb: tuple
    irradiance: float
    illuminance: float
    rel_std_error: float
    method: str
    samples: int
    seconds: float
    efficacy: float
    colour_space: str
    location: tuple = (0.0, 0.0, 0.0)
    normal: tuple = (0.0, 0.0, 1.0)
    exact: bool = False
    std_error_rgb: tuple = (0.0, 0.0, 0.0)
    notes: list = dataclasses.field(default_factory=list)
    render_settings: Optional[dict] = None
    quantity: str = "illuminance"
    #: Deterministic part of the error, relative (quadrature, possible partial occlusion); it is
    #: already included in ``rel_std_error`` (counted as one sigma).
    rel_error_bound: float = 0.0
    #: The 1-sigma relative standard error asked for (None: fixed samples or best in a time budget).
    target_rel_error: Optional[float] = None
    #: Which light came from closed forms and what Cycles rendered: {"analytic": [...], "rendered": [...]}.
    parts: dict = dataclasses.field(default_factory=dict)

    def to_dict(self):
        return dataclasses.asdict(self)

    def summary(self):
        err = "exact" if self.exact else f"±{100 * self.rel_std_error:.2g} % (1 s.e.)"
        return f"{self.illuminance:.6g} lx  ({self.irradiance:.6g} W/m²)  {err}  [{self.method}]"


@dataclasses.dataclass
class LuminanceReading:
    """Average radiance in a spot meter's acceptance cone and its photometric twin (cd/m^2)."""

    radiance_rgb: tuple
    radiance: float
    luminance: float
    rel_std_error: float
    method: str
    samples: int
    seconds: float
    efficacy: float
    colour_space: str
    acceptance_deg: float
    location: tuple = (0.0, 0.0, 0.0)
    direction: tuple = (0.0, 0.0, -1.0)
    exact: bool = False
    notes: list = dataclasses.field(default_factory=list)
    render_settings: Optional[dict] = None
    #: The 1-sigma relative standard error asked for.
    target_rel_error: Optional[float] = None
    quantity: str = "luminance"

    def to_dict(self):
        return dataclasses.asdict(self)

    def summary(self):
        return (f"{self.luminance:.6g} cd/m²  ({self.radiance:.6g} W/(m² sr))  "
                f"±{100 * self.rel_std_error:.2g} % (1 s.e.)  [{self.method}]")


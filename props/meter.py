"""Meter settings and readings (on objects) and Radiometer's scene settings."""

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty,
                       PointerProperty, StringProperty)

from ..quality import PRESETS
from ..radiometry.constants import K_M_LM_PER_W, K_RADIANCE_WHITE_LM_PER_W

METER_KINDS = [
    ("ILLUMINANCE", "Illuminance", "Cosine-corrected meter: irradiance (W/m²) and illuminance (lux) on its +Z side"),
    ("LUMINANCE", "Luminance", "Spot meter along its -Z: radiance W/(m² sr) and luminance (cd/m²) in a cone"),
    ("RADIANCE_MAP", "Radiance Map", "Panoramic 32-bit EXR of incident radiance at the point (delta lights "
                                     "are invisible to camera rays and do not appear in it)"),
]
METHODS = [
    ("auto", "Auto", "Closed forms where exact for this scene; else closed forms for the direct light they "
                     "prove plus Cycles for the rest"),
    ("analytic", "Analytic", "Closed forms for direct light (exact only when nothing else adds or blocks light)"),
    ("hybrid", "Hybrid", "Closed forms for the direct light they prove exact, Cycles for the rest"),
    ("render", "Render", "Cycles path tracing of everything, with a statistical error estimate"),
]
QUALITIES = [(name, name.title(), f"Every reading to {100 * p['target']:g} % relative standard error (1 sigma)")
             for name, p in PRESETS.items()]
EFFICACY_CONVENTIONS = [
    ("BLENDER_683", "683 lm/W (Blender, glTF)", "K = 683 lm/W for every RGB watt, as Blender's glTF I/O"),
    ("RADIANCE_179", "179 lm/W (Radiance)", "Equal-energy white over the visible range, as the Radiance renderer"),
    ("CUSTOM", "Custom", "Your own luminous efficacy"),
]
_EFFICACY_VALUES = {"BLENDER_683": K_M_LM_PER_W, "RADIANCE_179": K_RADIANCE_WHITE_LM_PER_W}


def _live_changed(self, _context):
    from . import live_state

    if self.live:
        live_state.mark_dirty(self.id_data)  # measure every meter once the scene is still


def _convention_changed(self, _context):
    if self.efficacy_convention in _EFFICACY_VALUES:
        self.efficacy = _EFFICACY_VALUES[self.efficacy_convention]


def _reading(key, default):
    """Getter of a stored reading (an ID property of the same name; ``default`` before the first)."""
    kind = type(default)

    def get(self):
        value = self.get(key, default)
        return tuple(float(v) for v in value) if kind is tuple else kind(value)

    return get


class RadiometerMeterSettings(bpy.types.PropertyGroup):
    is_meter: BoolProperty(name="Is Light Meter", default=False,
                           description="This object is a Radiometer light meter (Measure reads it)")
    kind: EnumProperty(name="Kind", items=METER_KINDS, default="ILLUMINANCE",
                       description="What the meter measures")
    acceptance_deg: FloatProperty(name="Acceptance", description="Full acceptance angle of the spot meter",
                                  default=1.0, min=0.01, max=60.0, unit="NONE", subtype="NONE")
    map_resolution: IntProperty(name="Map Height", description="Radiance map height in pixels (width = 2x)",
                                default=128, min=8, max=4096)
    # Reading (SI); written by radiometer.measure (the api stores them as ID
    # properties of the same names), persisted in the .blend. Read-only: a reading is a measurement,
    # not a setting, so neither the UI nor a script can edit it (getters without setters).
    has_reading: BoolProperty(name="Has Reading", get=_reading("has_reading", False),
                              description="The meter has been measured (the reading below is stored in the file)")
    value_rgb: FloatVectorProperty(name="RGB", size=3, get=_reading("value_rgb", (0.0, 0.0, 0.0)),
                                   description="Irradiance W/m² or radiance W/(m² sr), RGB")
    value: FloatProperty(name="Radiometric", get=_reading("value", 0.0),
                         description="Irradiance W/m² or radiance W/(m² sr) (CIE Y weighted)")
    photometric: FloatProperty(name="Photometric", get=_reading("photometric", 0.0),
                               description="Illuminance (lux) or luminance (cd/m²)")
    rel_std_error: FloatProperty(name="Relative Standard Error", get=_reading("rel_std_error", 0.0),
                                 description="Stated 1-sigma relative standard error of the reading (fraction)")
    exact: BoolProperty(name="Exact", get=_reading("exact", False),
                        description="The reading came from closed forms proven exact for this scene (no noise)")
    method: StringProperty(name="Method", get=_reading("method", ""),
                           description="How the reading was made: analytic, hybrid or render")
    samples: IntProperty(name="Samples", get=_reading("samples", 0),
                         description="Path-tracing samples spent on the reading (0 if analytic)")
    seconds: FloatProperty(name="Seconds", get=_reading("seconds", 0.0), description="Wall time of the measurement, s")
    efficacy: FloatProperty(name="Efficacy (lm/W)", get=_reading("efficacy", 0.0),
                            description="Luminous efficacy used for the photometric value when it was measured, lm/W")
    notes: StringProperty(name="Notes", get=_reading("notes", ""),
                          description="Caveats of the reading (placement, enclosure, method), separated by |")
    map_path: StringProperty(name="Radiance Map", subtype="FILE_PATH", get=_reading("map_path", ""),
                             description="The EXR file of the last radiance map")
    # The melanopic reading of the direct light (radiometer.melanopic_reading, CIE S 026), stored the same way;
    # a new photometric reading clears it (spectral_status "")
    mel_edi: FloatProperty(name="mel-EDI (lx)", get=_reading("mel_edi", 0.0),
                           description="Melanopic equivalent daylight illuminance of the direct light, lx (CIE S 026)")
    mel_der: FloatProperty(name="mel-DER", get=_reading("mel_der", 0.0),
                           description="Melanopic daylight efficacy ratio of the direct light (D65 = 1)")
    sp_ratio: FloatProperty(name="S/P", get=_reading("sp_ratio", 0.0),
                            description="Scotopic to photopic ratio of the direct light")
    spectral_status: StringProperty(name="Spectral Status", get=_reading("spectral_status", ""),
                                    description="What the melanopic reading holds (exact, or a lower bound and why); "
                                                "empty when there is none for the current reading")


class RadiometerSceneSettings(bpy.types.PropertyGroup):
    efficacy_convention: EnumProperty(name="Efficacy", items=EFFICACY_CONVENTIONS, default="BLENDER_683",
                                      update=_convention_changed,
                                      description="Which luminous efficacy turns watts into lumens")
    efficacy: FloatProperty(name="lm/W", description="Luminous efficacy K: lux = K x CIE Y of RGB irradiance",
                            default=K_M_LM_PER_W, min=1.0, max=K_M_LM_PER_W)
    method: EnumProperty(name="Method", items=METHODS, default="auto",
                         description="How meters are measured: closed forms, Cycles, or both")
    quality: EnumProperty(name="Quality", items=QUALITIES, default="standard",
                          description="Accuracy preset: the relative standard error every reading must reach")
    target_rel_error: FloatProperty(name="Target Error", description="Relative standard error (1 sigma) every "
                                    "rendered reading must reach, e.g. 0.01 = 1 % (0 = the quality preset's target)",
                                    default=0.0, min=0.0, max=0.5, subtype="FACTOR")
    show_overlay: BoolProperty(name="Readings in Viewport", default=True,
                               description="Draw each meter's reading next to it in the 3D viewport")
    live: BoolProperty(name="Live Meters", default=False, update=_live_changed,
                       description="Update meter readings as lights, meters or geometry move: exact readings "
                                   "at once where closed forms are exact, else a preview that refines to the "
                                   "chosen quality while you are idle")
    last_summary: StringProperty(name="Last Measurement", description="Readings of the last measurement, one line")
    # Written by the modal runner (operators/modal.py) while a long operation runs; not saved state.
    progress: FloatProperty(name="Progress", description="Fraction done of the running Radiometer operation",
                            default=0.0, min=0.0, max=1.0, subtype="FACTOR", options={"SKIP_SAVE"})
    progress_text: StringProperty(name="Progress Text", description="What the running operation is doing, "
                                  "with the time left", options={"SKIP_SAVE"})


classes = (RadiometerMeterSettings, RadiometerSceneSettings)


def register_extra():
    bpy.types.Object.radiometer_meter = PointerProperty(type=RadiometerMeterSettings)
    bpy.types.Scene.radiometer = PointerProperty(type=RadiometerSceneSettings)
    # The api reads the scene's efficacy setting and hands it down to measure/ (issue 30): importing it
    # installs its reader, so a session that measures without calling the api first (a cluster worker
    # running a measurement task on the file it opened) reads the file's setting too.
    from .. import api  # noqa: F401


def unregister_extra():
    del bpy.types.Scene.radiometer
    del bpy.types.Object.radiometer_meter

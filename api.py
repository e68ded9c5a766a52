"""Radiometer's stable Python API (used by the operators, the CLI and the tests).

Locations and directions are in scene coordinates (Blender units); every returned number is SI
(metres, W/m^2, lux, W/(m^2 sr), cd/m^2). Every call measures the scene as it is now (the
evaluated depsgraph). Bad input raises ``radiometer.errors.RadiometerError`` with a one-line
message and leaves the scene untouched; so does a failed or cancelled measurement.
"""

from .errors import MeasurementCancelled, RadiometerError  # noqa: F401  (re-exported)


def measure_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None, method="auto", quality="standard",
                        target_rel_error=None, progress=None, cancelled=None, seed=0):
    """Irradiance (W/m^2) and illuminance (lux) on the side ``normal`` faces.

    ``location``: 3 numbers, or (N, 3) to measure N meters in one batch (one scene sync);
    ``normal``: 3 numbers or (N, 3). ``method``: "auto" (analytic where exact, else render),
    "analytic" or "render". ``quality``: "preview", "standard", "reference". ``target_rel_error``:
    keep sampling until every 95 % interval is within this fraction. ``seed``: first Cycles seed
    (readings are deterministic for a given seed). Returns an
    ``IlluminanceReading`` (or a list of them for N locations) with ``irradiance_rgb``,
    ``irradiance``, ``illuminance``, ``rel_std_error``, ``method``, ``samples``, ``seconds``, ``notes``.
    """
    from .measure import meter

    return meter.measure_illuminance(location, normal, scene=scene, method=method, quality=quality,
                                     target_rel_error=target_rel_error, progress=progress, cancelled=cancelled,
                                     seed=seed)


def predict_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None):
    """Analytic per-light breakdown: list of dicts with light, irradiance, illuminance, model, exact."""
    from .measure import meter

    return meter.predict_illuminance(location, normal, scene=scene)


def measure_luminance(location, direction, *, acceptance_deg=1.0, scene=None, quality="standard",
                      target_rel_error=None, progress=None, cancelled=None):
    """Average radiance W/(m^2 sr) and luminance cd/m^2 seen in a cone of ``acceptance_deg`` (full angle)."""
    from .measure import camera

    return camera.measure_luminance(location, direction, acceptance_deg=acceptance_deg, scene=scene,
                                    quality=quality, target_rel_error=target_rel_error, progress=progress,
                                    cancelled=cancelled)


def capture_radiance_map(location, path, *, resolution=256, scene=None, quality="standard"):
    """Write a 32-bit equirectangular EXR of the incident radiance at ``location``; returns a RadianceMap."""
    from .measure import camera

    return camera.capture_radiance_map(location, path, resolution=resolution, scene=scene, quality=quality)


def measure_meters(objects=None, *, scene=None, quality=None, progress=None, cancelled=None):
    """Measure meter objects (default: every meter in the scene) and store the readings on them."""
    from .measure import meters

    return meters.measure_meters(objects, scene=scene, quality=quality, progress=progress, cancelled=cancelled)

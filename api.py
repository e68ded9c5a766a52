"""Radiometer's stable Python API (used by the operators, the CLI and the tests).

Locations and directions are in scene coordinates (Blender units); every returned number is SI
(metres, W/m^2, lux, W/(m^2 sr), cd/m^2). Every call measures the scene as it is now (the
evaluated depsgraph). Bad input raises ``radiometer.errors.RadiometerError`` with a one-line
message and leaves the scene untouched; so does a failed or cancelled measurement.
"""

from . import validation as _v
from .measure.blender import arguments as _b  # the Blender arguments' checks (host: bpy inside)
from .errors import MeasurementCancelled, RadiometerError  # noqa: F401  (re-exported)
from .measure.blender import efficacy as _efficacy


def _efficacy_setting(scene):
    """K (lm/W) of ``scene``'s Radiometer settings, or None where the add-on's properties are not
    registered: the api reads the UI setting and hands it down (issue 30); measure/ asks
    ``measure.blender.efficacy.of`` and reads no property group."""
    settings = getattr(scene, "radiometer", None)
    return None if settings is None else float(getattr(settings, "efficacy", 0.0) or 0.0)


_efficacy.install(_efficacy_setting)


def _request(scene=None, **fields):
    """The one request of an api call (issue 30; ``measure.blender.request``), built here and passed down:
    the scene (None: the context's), its view layer, unit scale and photometry, the efficacy read from the
    add-on's setting and passed in, and the caller's budget, seed, progress, cancel and client (None keeps a
    field's default)."""
    import bpy

    from .measure.blender import request as request_of

    scene = _b.scene(scene) or bpy.context.scene  # a wrong type is one line, never a traceback
    return request_of.build(scene, efficacy=_efficacy_setting(scene), **fields)


@_v.boundary(finite=True)
def measure_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None, method="auto", quality="standard",
                        target_rel_error=None, samples=None, time_budget_s=None, progress=None, cancelled=None,
                        seed=0, pooling=True, target_abs_error=None, stop_dark=False):
    """Irradiance (W/m^2) and illuminance (lux) on the side ``normal`` faces.

    ``location``: 3 numbers, or (N, 3) to measure N meters in one batch; ``normal``: 3 numbers or
    (N, 3). A meter placed on a surface reads the light arriving at that surface (its sensor is
    raised by a scale-aware epsilon, said in the notes). ``method``: "auto" (closed forms where
    they are exact for every contribution; otherwise the hybrid), "analytic" (closed forms for
    direct light only), "hybrid" (closed forms for the direct light they prove, Cycles for the
    rest) or "render" (Cycles for everything). ``quality``: a target 1-sigma relative standard
    error for every rendered reading: "preview" 5 %, "standard" 1 %, "reference" 0.2 %;
    ``target_rel_error`` (a fraction) overrides it; ``samples`` spends a fixed number of samples
    per meter instead (studies); ``time_budget_s`` spends about that many seconds for the best
    accuracy (with ``target_rel_error`` too: whichever comes first). Each meter gets the samples it
    needs. ``progress(done, total, seconds_left)``: called after every round (done/total in
    thousandths). ``seed``: first Cycles seed (readings are deterministic for a given seed).
    Returns an ``IlluminanceReading`` (or a list of them for N locations) with ``irradiance_rgb``,
    ``irradiance``, ``illuminance``, ``rel_std_error`` (reached), ``target_rel_error`` (asked),
    ``exact``, ``method``, ``parts`` (which light came from closed forms), ``samples``, ``seconds``,
    ``notes``. ``pooling``: with a target (not ``samples`` or ``time_budget_s``), a group of at least
    300 rendered meters on one plane (same normal, same lights in closed form) reads its rendered part
    from a smooth field fitted over all of them, its error checked on held-out meters read on their own
    (method "hybrid+pooled", said in the notes; docs/pooled-meters.md); False reads every meter alone.
    ``target_abs_error``: the absolute floor of the 1-sigma error, lux (None: the preset's, 2 / 0.5 /
    0.1 lx for preview / standard / reference): a meter stops where its error is below it or below the
    relative target, whichever is larger (a point in the dark does not chase 1 % of almost nothing);
    0: none (the relative target alone). A meter that finds no light samples on (issue 18) to
    65 536 samples and then states its error unknown; ``stop_dark=True`` stops it after its pilot with a
    one-sided bound by the rule of three (fewer than 3/n of its paths carry light): that bound holds only
    where no single light-carrying sample carries more than n/3 x the floor, which a small bright region
    seen past an obstruction breaks (tests/bpy/fin_scene.py: the 99 % hidden meter's exact reading is
    7.1 lx while one sample that finds the sunlit patch carries pi x L = 2 730 lx, so a 512-sample pilot
    that misses it would state "at most 2 lx"): a choice for meters known to sit in the dark, not the default.
    """
    location = _v.points(location, "location")
    normal = _v.directions(normal, "normal")
    _v.same_count(location, normal)
    _b.scene(scene)
    _v.measurement(quality_=quality, method_=method, target_rel_error=target_rel_error, samples_=samples,
                   time_budget_s=time_budget_s, progress=progress, cancelled=cancelled, seed_=seed)
    if not isinstance(pooling, bool):
        _v.fail("pooling", "True or False", pooling)
    if not isinstance(stop_dark, bool):
        _v.fail("stop_dark", "True or False", stop_dark)
    _v.real(target_abs_error, "target_abs_error", low=0.0, allow_none=True)
    from .measure.meter import point_meter as meter

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, samples=samples,
                       time_budget_s=time_budget_s, progress=progress, cancelled=cancelled, seed=seed,
                       target_abs_error=target_abs_error)
    return meter.measure_illuminance(location, normal, request, method=method, pooling=bool(pooling),
                                     stop_dark=stop_dark)


@_v.boundary
def predict_illuminance(location, normal=(0.0, 0.0, 1.0), *, scene=None):
    """Analytic per-light breakdown: list of dicts with light, irradiance, illuminance, model, exact."""
    location = _v.points(location, "location", allow_many=False)
    normal = _v.directions(normal, "normal", allow_many=False)
    _b.scene(scene)
    from .measure.meter import point_meter as meter

    return meter.predict_illuminance(location, normal, _request(scene))


def _spectral_options(scene, reflected, quality, seed):
    """The spectral readings' shared options, checked (one line each)."""
    _v.choice(quality, "quality", ("preview", "standard", "reference"))
    if not isinstance(reflected, bool):
        raise RadiometerError(f"reflected must be True or False, got {reflected!r}")
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise RadiometerError(f"seed must be a whole number >= 0, got {seed!r}")
    _b.scene(scene)


@_v.boundary
def spectral_reading(location, normal=(0.0, 0.0, 1.0), *, scene=None, quantity="melanopic", reflected=False,
                     quality="preview", seed=0):
    """CIE S 026 alpha-opic reading of the light at one meter (a plain, JSON-ready dict, SI): the **direct**
    light, and with ``reflected=True`` the reflected light too.

    Per light, mel-EDI = E_v x mel-DER of the light's spectrum (and likewise for the S/M/L cone-opic and
    rhodopic quantities): E_v from the meter's closed forms, the spectrum from the light's setting
    (custom property ``radiometer_spectrum``: "A", "D65", "FL2", "LED-B3", "D5000", "blackbody:3000" or a
    spectral .csv) or its blackbody temperature. Keys: ``illuminance_lx``, ``mel_edi_lx``, ``mel_der``,
    ``alpha_opic_edi_lx``, ``alpha_opic_irradiance_w_m2`` (W/m²), ``sp_ratio``, ``exact``, ``complete``
    (False: a light with no known spectrum or no closed form, named in ``notes``, and the sums are lower
    bounds), ``lights``, ``not_included`` (reflected light unless ``reflected``, the world's light where it is
    not proven in closed form, emitting surfaces: docs/spectral.md), ``units``. ``quantity``: "melanopic" (all
    alpha-opic quantities).

    ``reflected=True``: the reflected (rendered) part by band renders (Cycles' three channels carry the
    materials' reflectances at the two ends of spectral bands; materials give their spectrum in the custom
    property ``radiometer_reflectance``, a spectral file or a number, else their colour is upsampled and the
    notes say so). The totals ``illuminance_lx``, ``mel_edi_lx``, ``alpha_opic_edi_lx`` are then direct (exact) +
    reflected (estimate); ``interval_95`` gives each one's ``estimate``, ``low_95``, ``high_95`` (lx: the proven
    band range widened by 1.96 standard errors of the renders), ``std_error`` and ``band_bound``; ``direct``
    the direct-only figures; ``rgb_only`` the estimate from today's RGB render (no proven bound); ``exact``
    False. The world's light (daylight through a window) is read in the same band renders, with the world's
    spectrum (its ``radiometer_spectrum``, default D65). Refused scenes (emitting surfaces, a world volume,
    textured, tinted or other non-diffuse materials, a light without a spectrum) keep the direct reading and
    say why in ``notes``. ``quality``: "preview", "standard" or
    "reference" (samples per band render and the number of bands); ``seed``: the first Cycles seed.
    """
    location = _v.points(location, "location", allow_many=False)
    normal = _v.directions(normal, "normal", allow_many=False)
    _v.choice(quantity, "quantity", ("melanopic",))
    _spectral_options(scene, reflected, quality, seed)
    from .measure.meter import spectra, spectral_reflected

    request = _request(scene, quality=quality, seed=seed)
    if reflected:
        return spectral_reflected.spectral_reading(location, normal, request=request)
    return spectra.spectral_reading(location, normal, request=request)


@_v.boundary
def mesopic_reading(location, direction, *, acceptance_deg=1.0, scene=None, quality="preview", seed=0):
    """CIE 191:2010 mesopic luminance seen by a luminance (spot) meter at ``location`` looking along
    ``direction`` in a cone of ``acceptance_deg`` (full angle), from spectral band renders of the cone: a plain
    dict (SI) with ``photopic_cd_m2`` and ``scotopic_cd_m2`` (each ``estimate``, ``low_95``, ``high_95``,
    ``std_error``: the proven band range widened by 1.96 s.e.), ``sp_ratio``, ``mesopic_cd_m2`` (``estimate``,
    ``low_95``, ``high_95``), ``adaptation_m``, ``regime`` (photopic / mesopic / scotopic), ``notes``, ``units``.
    Lights need a known spectrum and materials plain colours, as for ``spectral_reading(reflected=True)``;
    otherwise ``RadiometerError`` says why."""
    location = _v.points(location, "location", allow_many=False)
    direction = _v.directions(direction, "direction", allow_many=False)
    acceptance_deg = _v.real(acceptance_deg, "acceptance_deg", low=0.0, high=120.0, low_open=True, high_open=True)
    _spectral_options(scene, False, quality, seed)
    from .measure.meter import spectral_reflected

    return spectral_reflected.mesopic_reading(location, direction, request=_request(scene, quality=quality, seed=seed),
                                              acceptance_deg=acceptance_deg)


@_v.boundary
def spectral_grid(target, *, resolution=None, spacing=None, scene=None, reflected=False, quality="preview", seed=0,
                  progress=None, cancelled=None):
    """Melanopic EDI (CIE S 026) on the grid :func:`illuminance_grid` lays out over a plane object (its +Z side):
    each point read as :func:`spectral_reading` reads a meter, the band renders of ``reflected=True`` in one
    batch for all points. Returns a plain dict (SI): ``mel_edi_lx``, ``illuminance_lx``, ``mel_der`` (ny, nx),
    ``low_95_lx`` / ``high_95_lx`` (with ``reflected``), ``stats`` (avg, min, max, u0 of each), ``exact``,
    ``lower_bound`` (light left out somewhere: ``not_included`` says what), ``notes``, ``units``.
    ``progress(done, total, seconds_left)`` and ``cancelled()`` as in :func:`measure_illuminance`."""
    _b.scene(scene)
    target = _b.blender_object(target, "target", scene_=scene, types=("MESH",))
    resolution = _v.resolution2(resolution, "resolution", high=1000, allow_none=True)
    spacing = _v.positive(spacing, "spacing", high=_v.MAX_COORDINATE, allow_none=True)
    _spectral_options(scene, reflected, quality, seed)
    from .measure.analyses import grid

    request = _request(scene, quality=quality, seed=seed, progress=progress, cancelled=cancelled)
    return grid.spectral_grid(target, request=request, resolution=resolution, spacing=spacing, reflected=reflected)


@_v.boundary
def write_spectral_grid_csv(result, path):
    """Write a :func:`spectral_grid` result as CSV (row, col, x, y, z, E_v and mel-EDI in lx, mel-DER, and the
    95 % interval of mel-EDI where the reflected part was read), whole or not at all; returns the path."""
    path = _v.optional_output(path, "csv")
    if not isinstance(result, dict) or "mel_edi_lx" not in result or "points" not in result:
        raise RadiometerError("result must be what spectral_grid returned")
    from .measure.analyses import grid

    return grid.write_spectral_csv(result, path)


@_v.boundary
def circadian_check(positions, view_directions=(0.0, 1.0, 0.0), *, scene=None, posture="seated", reflected=False,
                    quality="preview", seed=0):
    """Circadian lighting check (WELL v2 L03, indicative; docs/spectral.md): a vertical meter at each
    occupant's eye (``positions``: floor points, 3 numbers or (N, 3), scene coordinates; the eye 1.2 m up
    seated, 1.7 m standing) facing ``view_directions`` (one or one per position), read in melanopic EDI
    (:func:`spectral_reading`, with ``reflected`` and ``quality``/``seed`` as there), each rated against
    136 lx (1 point) and 250 lx (3 points) as met, not met or unknown. A reading that leaves light out
    (reflections unless ``reflected``, the world, emitting surfaces, lights without a spectrum) is a lower
    bound: it can show a threshold met, never missed. Returns a plain dict: ``eyes`` (per eye: ``mel_edi_lx``,
    its 95 % interval, ``verdict``, ``left_out``), ``points`` (reached at every eye), ``share``, ``units``."""
    positions = _v.points(positions, "positions")
    view_directions = _v.directions(view_directions, "view_directions")
    _v.choice(posture, "posture", ("seated", "standing"))
    _spectral_options(scene, reflected, quality, seed)
    from .measure.meter import circadian

    return circadian.circadian_check(positions, view_directions, request=_request(scene, quality=quality, seed=seed),
                                     posture=posture, reflected=reflected)


@_v.boundary
def meter_melanopic_reading(obj, *, scene=None, reflected=False, quality="preview"):
    """The melanopic (CIE S 026) reading of the direct light at an illuminance meter object, where it stands
    and faces (:func:`spectral_reading`; ``reflected=True``: with the reflected light and the world's, band
    renders at ``quality``), stored on the meter (``mel_edi``, ``mel_der``, ``sp_ratio``, ``spectral_status``:
    shown in its sidebar panel; a new Measure clears them). Returns the reading's dict."""
    import bpy

    _spectral_options(scene, reflected, quality, 0)
    scene = _b.scene(scene) or bpy.context.scene
    if not _is_meter(obj) or obj.radiometer_meter.kind != "ILLUMINANCE":
        raise RadiometerError(f"{getattr(obj, 'name', obj)!r} is not an illuminance meter")
    from .measure.meter import meter_objects

    r = meter_objects.direct_spectral_reading(obj, _request(scene, quality=quality), reflected=reflected)
    m = obj.radiometer_meter
    for key, value in meter_objects.spectral_values(r).items():
        m[key] = value
    return r


@_v.boundary
def spectrum_metrics(spectrum):
    """CIE S 026 and scotopic figures of one spectrum setting (no scene needed), a JSON-ready dict.

    ``spectrum``: "A", "D65", "FL2", "LED-B3", "D5000", "blackbody:2700" or a spectral .csv (nm, relative
    power). Returns ``spectrum`` (its label), ``alpha_opic_elr_w_per_lm`` (W/lm), ``alpha_opic_der`` and
    ``mel_der`` (1; D65 = 1), ``sp_ratio`` (1) and ``units``.
    """
    from .radiometry.photometry import action_spectra, spectral

    label, spd = spectral.spectrum_from_spec(spectrum)
    elr, der = action_spectra.alpha_opic_elr(spd), action_spectra.alpha_opic_der(spd)
    return {"spectrum": label, "alpha_opic_elr_w_per_lm": dict(zip(action_spectra.ALPHA, map(float, elr))),
            "alpha_opic_der": dict(zip(action_spectra.ALPHA, map(float, der))), "mel_der": float(der[4]),
            "sp_ratio": float(action_spectra.sp_ratio(spd)),
            "units": {"alpha_opic_elr_w_per_lm": "W/lm", "alpha_opic_der": "1", "mel_der": "1", "sp_ratio": "1"}}


@_v.boundary
def mesopic_luminance(photopic_cd_m2, sp_ratio):
    """CIE 191:2010 mesopic luminance of a photopic luminance L_p (cd/m², > 0) seen under light of S/P ratio
    ``sp_ratio`` (> 0): {"mesopic_cd_m2", "m" (adaptation coefficient, 0 scotopic to 1 photopic), "units"}."""
    from .radiometry.photometry import action_spectra

    lp = _v.positive(photopic_cd_m2, "photopic_cd_m2")
    sp = _v.positive(sp_ratio, "sp_ratio")
    lmes, m = action_spectra.mesopic_luminance(lp, sp)
    return {"mesopic_cd_m2": float(lmes), "m": float(m), "photopic_cd_m2": lp, "sp_ratio": sp,
            "units": {"mesopic_cd_m2": "cd/m²", "photopic_cd_m2": "cd/m²", "m": "1", "sp_ratio": "1"}}


@_v.boundary(finite=True)
def measure_luminance(location, direction, *, acceptance_deg=1.0, scene=None, quality="standard",
                      target_rel_error=None, progress=None, cancelled=None):
    """Average radiance W/(m^2 sr) and luminance cd/m^2 seen in a cone of ``acceptance_deg`` (full angle)."""
    location = _v.points(location, "location", allow_many=False)
    direction = _v.directions(direction, "direction", allow_many=False)
    acceptance_deg = _v.real(acceptance_deg, "acceptance_deg", low=0.0, high=120.0, low_open=True, high_open=True)
    _b.scene(scene)
    _v.measurement(quality_=quality, target_rel_error=target_rel_error, progress=progress,
                   cancelled=cancelled, method_="render")
    from .measure.meter import camera

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, progress=progress,
                       cancelled=cancelled)
    return camera.measure_luminance(location, direction, acceptance_deg=acceptance_deg, request=request)


@_v.boundary(finite=True)
def capture_radiance_map(location, path, *, resolution=256, scene=None, quality="standard"):
    """Write a 32-bit equirectangular EXR of the incident radiance at ``location``; returns a RadianceMap."""
    import os

    location = _v.points(location, "location", allow_many=False)
    if isinstance(path, str) and path.startswith("//"):  # relative to the .blend, as Blender writes it
        import bpy

        path = bpy.path.abspath(path)
    path = _v.path(path, "path")
    if os.path.isdir(path) or str(path).endswith(os.sep):
        raise RadiometerError(f"path must name an .exr file, got the folder {path!r:.200}")
    # The file written is the file reported: "map" becomes "map.exr" before anything is checked.
    path = _v.output_file(path if path.lower().endswith(".exr") else f"{path}.exr", "path")
    resolution = _v.integer(resolution, "resolution", low=4, high=_v.MAX_MAP_SIDE // 2)
    _b.scene(scene)
    _v.quality(quality)
    from .measure.meter import camera

    return camera.capture_radiance_map(location, path, resolution=resolution, request=_request(scene, quality=quality))


@_v.boundary
def measure_meters(objects=None, *, scene=None, quality=None, progress=None, cancelled=None, target_abs_error=None):
    """Measure meter objects (default: every meter in the scene) and store the readings on them.
    ``target_abs_error``: the illuminance meters' absolute error floor, lux (None: the preset's)."""
    _b.scene(scene)
    _v.real(target_abs_error, "target_abs_error", low=0.0, allow_none=True)
    _v.quality(quality, allow_none=True)
    _v.callable_or_none(progress, "progress")
    _v.callable_or_none(cancelled, "cancelled")
    if objects is not None:
        if isinstance(objects, (str, bytes)) or not hasattr(objects, "__iter__"):
            raise RadiometerError(f"objects must be a list of meter objects or None, got {objects!r:.60}")
        objects = [_b.blender_object(ob, "objects") for ob in objects]
    import bpy

    from .measure.meter import meter_objects as meters

    scene = scene or bpy.context.scene
    request, method = _settings_request(scene, quality, progress=progress, cancelled=cancelled,
                                        target_abs_error=target_abs_error)
    results = meters.measure_meters(_meters(scene, objects), request, method=method)
    for obj, reading in results:  # only once every meter is measured: a failed run changes no reading
        _store_reading(obj, reading)
    return results


# The UI's settings are read here and handed down as arguments (issue 30: host code does not read the
# property groups): the scene's Radiometer settings and each meter object's.

def _scene_settings(scene, quality=None):
    """The scene's method, quality (``quality`` overrides it) and target error (fraction; None: the preset's)."""
    s = getattr(scene, "radiometer", None)
    if s is None:  # the add-on's properties are not registered (a bare bpy): the defaults
        return {"method": "auto", "quality": quality or "standard", "target_rel_error": None}
    return {"method": s.method, "quality": quality or s.quality,
            "target_rel_error": s.target_rel_error if s.target_rel_error > 0 else None}


def _settings_request(scene, quality=None, **fields):
    """(the request, the method) of a measurement with the scene's Radiometer settings: its quality
    (``quality`` overrides it) and target error; ``fields`` as :func:`_request` takes them."""
    settings = _scene_settings(scene, quality)
    request = _request(scene, quality=settings["quality"], target_rel_error=settings["target_rel_error"], **fields)
    return request, settings["method"]


def _is_meter(ob):
    return getattr(getattr(ob, "radiometer_meter", None), "is_meter", False)


def _meter_objects(scene, objects=None):
    """``objects`` (each must be a meter) or every meter of ``scene``; none at all raises."""
    if objects is None:
        objects = [ob for ob in scene.objects if _is_meter(ob)]
    else:
        objects = list(objects)
        bad = [ob.name for ob in objects if not _is_meter(ob)]
        if bad:
            raise RadiometerError(f"not light meters: {', '.join(bad)} (add one with Add > Light Meter)")
    if not objects:
        raise RadiometerError("no light meters to measure: add one with Add > Light Meter")
    return objects


def _meters(scene, objects=None, *, every=False):
    """The meters (``measure.meter.meter_objects.Meter``: object and settings) of ``objects`` (or of the
    scene); ``every``: the scene's meters, none being no error."""
    from .measure.meter import meter_objects as meters

    if every:
        objects = [ob for ob in scene.objects if _is_meter(ob)]
    else:
        objects = _meter_objects(scene, objects)
    return [meters.Meter(ob, ob.radiometer_meter.kind, float(ob.radiometer_meter.acceptance_deg),
                         int(ob.radiometer_meter.map_resolution)) for ob in objects]


def _store_reading(obj, reading):
    """Store ``reading`` on the meter object: ID properties of its Radiometer properties (read-only
    there), so they persist in the .blend and follow undo."""
    from .measure.meter import meter_objects as meters

    m = obj.radiometer_meter
    for key, value in meters.reading_values(reading).items():
        m[key] = value


def _law_check_inputs(light, scene, tolerance, plot, quality, method, target_rel_error, samples, time_budget_s,
                      progress, cancelled, seed):
    """The law checks' shared arguments, checked: (the light object, tolerance, plot path or None)."""
    _b.scene(scene)
    light = _b.blender_object(light, "light", scene_=scene, types=("LIGHT",))
    _v.measurement(quality_=quality, method_=method, target_rel_error=target_rel_error,
                   samples_=samples, time_budget_s=time_budget_s, progress=progress, cancelled=cancelled, seed_=seed)
    return light, _v.fraction(tolerance, "tolerance"), _v.optional_output(plot, "plot")


@_v.boundary
def check_inverse_square(light, *, scene=None, distances=None, method="auto", quality="standard",
                         tolerance=0.01, target_rel_error=None, samples=None, time_budget_s=None, seed=0, plot=None,
                         progress=None, cancelled=None):
    """Sweep a meter facing ``light`` (object or name) along its axis and compare E with I/d^2.

    ``distances`` in m from the light's centre (default: 0.6 to 60 source sizes, kept in front of
    the first surface). The light is measured alone (every other light, instanced ones too, and
    the world switched off; surfaces kept) and split into its OWN direct light (closed forms where
    the scene model proves them, else Cycles at 0 bounces) and what the scene adds (total −
    direct: interreflection). The law is judged on the light's own direct light. Accuracy:
    ``quality`` (target 1-sigma relative error per reading: "preview" 5 %, "standard" 1 %,
    "reference" 0.2 %), ``target_rel_error`` (fraction, overrides it), ``samples`` (fixed per
    meter) or ``time_budget_s`` (s per measurement). ``tolerance``: fraction.

    Returns an ``InverseSquareResult``: ``passed`` (the light's own law), ``exponent`` (+
    ``exponent_se``) of the far-field fit of log E_direct vs log d, ``near_field_limit`` (m; 0
    when the law holds at every distance tried, inf when never reached), ``five_times``,
    ``total_passed`` (the total follows the law too), ``max_scene_share`` (fraction),
    ``broken_by`` ("", "light", "scene", "light and scene"), ``causes`` (each "light: ..." or
    "scene: ...") and ``rows`` (distance m, measured W/m^2 (total), predicted I/d^2 W/m^2,
    rel_deviation, rel_std_error, model W/m^2, model_deviation, ok, illuminance lx, direct W/m^2,
    scene W/m^2, direct_deviation, scene_share, shadowed, direct_rel_std_error, total_ok;
    deviations and shares as fractions). ``plot``: PNG path. A sun raises RadiometerError.
    """
    light, tolerance, plot = _law_check_inputs(light, scene, tolerance, plot, quality, method, target_rel_error,
                                               samples, time_budget_s, progress, cancelled, seed)
    distances = _v.distances(distances)
    from .measure.analyses import analysis

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, samples=samples,
                       time_budget_s=time_budget_s, seed=seed, progress=progress, cancelled=cancelled)
    return analysis.check_inverse_square(light, request=request, distances=distances, method=method,
                                         tolerance=tolerance, plot=plot)


@_v.boundary
def check_cosine_law(light, *, scene=None, location=None, angles_deg=None, method="auto", quality="standard",
                     tolerance=0.01, target_rel_error=None, samples=None, time_budget_s=None, seed=0, plot=None,
                     progress=None, cancelled=None):
    """Tilt a meter at ``location`` (scene coordinates; default 2 source sizes, at least 1 m, in front
    of the light but at most half-way to the first surface; the origin for a sun) from facing
    ``light`` to 89 deg; compare the light's own direct E(theta)/E(0) with cos(theta), with the
    total and the scene's share beside it. Accuracy keywords as in :func:`check_inverse_square`.

    Returns a ``CosineResult``: ``passed``, ``max_rel_deviation`` (fraction, the light's own),
    ``onset_deg``, ``horizon_onset_deg``, ``total_passed``, ``total_max_rel_deviation``,
    ``max_scene_share``, ``broken_by``, ``causes`` and ``rows`` (angle deg, measured W/m^2,
    predicted cos, ratio, rel_deviation, ratio_rel_se, model_ratio, ok, direct W/m^2,
    direct_ratio, direct_deviation, scene W/m^2, scene_share, total_ok).
    """
    light, tolerance, plot = _law_check_inputs(light, scene, tolerance, plot, quality, method, target_rel_error,
                                               samples, time_budget_s, progress, cancelled, seed)
    location = None if location is None else _v.points(location, "location", allow_many=False)
    angles_deg = _v.angles(angles_deg, "angles_deg", low=0.0, high=90.0)
    from .measure.analyses import analysis

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, samples=samples,
                       time_budget_s=time_budget_s, seed=seed, progress=progress, cancelled=cancelled)
    return analysis.check_cosine_law(light, request=request, location=location, angles_deg=angles_deg, method=method,
                                     tolerance=tolerance, plot=plot)


from .radiometry.metrics.grid import PLANE_METRICS  # noqa: E402  (re-exported)

#: ``PLANE_METRICS``: every statistic over a plane's cells by name (average, minimum, maximum, median,
#: uniformity, points), the numbers of ``illuminance_grid``'s ``stats`` (EN 12464-1 names: avg, min, max,
#: u0, count), ``daylight_factor_grid``'s ``stats`` and the compliance check. How to add one: the
#: checklist in ``radiometry/metrics/grid.py``.


@_v.boundary
def illuminance_grid(target, *, resolution=None, spacing=None, scene=None, method="auto", quality="standard",
                     target_rel_error=None, samples=None, time_budget_s=None, seed=0, png=None, csv=None,
                     progress=None, cancelled=None, target_abs_error=None):
    """Illuminance on a grid over a plane object's local XY (its +Z side), in one measurement.

    ``resolution=(nx, ny)`` or ``spacing`` (m); neither: EN 12464-1 p = 0.2 x 5^log10(d). Every
    point gets the samples its own target needs: ``quality`` / ``target_rel_error`` (fraction) /
    ``samples`` (per point) / ``time_budget_s`` (s, the whole grid) as in
    :func:`measure_illuminance`. Returns a ``GridResult`` with ``lux`` (ny, nx), ``points``
    (ny, nx, 3) scene coordinates, ``rel_std_error`` (ny, nx), ``max_rel_std_error``,
    ``target_rel_error``, ``stats`` (avg, min, max in lux, u0 = min/avg). ``png``: isolux image;
    ``csv``: point table. ``progress(done, total, seconds_left)`` and ``cancelled()`` as in
    :func:`measure_illuminance` (law checks too). ``target_abs_error``: the absolute error floor, lux
    (None: the preset's; see :func:`measure_illuminance`).
    """
    _b.scene(scene)
    target = _b.blender_object(target, "target", scene_=scene, types=("MESH",))
    _v.real(target_abs_error, "target_abs_error", low=0.0, allow_none=True)
    resolution = _v.resolution2(resolution, "resolution", high=1000, allow_none=True)
    spacing = _v.positive(spacing, "spacing", high=_v.MAX_COORDINATE, allow_none=True)
    _v.measurement(quality_=quality, method_=method, target_rel_error=target_rel_error,
                   samples_=samples, time_budget_s=time_budget_s, progress=progress, cancelled=cancelled, seed_=seed)
    png, csv = _v.optional_output(png, "png"), _v.optional_output(csv, "csv")
    from .measure.analyses import analysis

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, samples=samples,
                       time_budget_s=time_budget_s, seed=seed, progress=progress, cancelled=cancelled,
                       target_abs_error=target_abs_error)
    return analysis.illuminance_grid(target, request=request, resolution=resolution, spacing=spacing, method=method,
                                     png=png, csv_path=csv)


@_v.boundary
def convergence_study(target=None, *, scene=None, location=None, normal=(0.0, 0.0, 1.0), samples=(4, 16, 64, 256),
                      target_error=0.01, replicas=8, reference_samples=None, quality=None, target_rel_error=None,
                      time_budget_s=None, targeted=True, seed=0, plot=None, cancelled=None):
    """Rendered error against samples AND wall time for a meter, a plane (4 x 4 grid) or a location.

    Fixed sample counts ``samples`` (per texel) give rows of samples per reading, seconds (one
    reading of the target alone, scene sync included) and RMS relative error against the analytic
    value when exact for the scene, else a high-sample render. ``target_error`` (fraction; set by
    ``target_rel_error`` when given) is inverted through the fits. ``targeted``: also one reading
    through the meter's error-targeted allocation (target ``target_rel_error``, else the
    ``quality`` preset's, else ``target_error``; ``time_budget_s`` in s). Returns a
    ``ConvergenceResult`` with ``rows``, ``fit`` (slope of log error vs log samples, time_slope vs
    log seconds, t0_s, c_s_per_sample), ``time_slope``, ``samples_for_target``,
    ``seconds_for_target`` (s, t0 + c N), ``seconds_for_target_by_time_fit`` (s) and ``targeted``
    (samples, seconds, rel_std_error, rms_error). ``cancelled()``: polled between renders, True raises
    MeasurementCancelled.
    """
    _b.scene(scene)
    if target is not None:
        target = _b.blender_object(target, "target", scene_=scene)
    location = None if location is None else _v.points(location, "location", allow_many=False)
    normal = _v.directions(normal, "normal", allow_many=False)
    if isinstance(samples, (str, bytes)) or not hasattr(samples, "__len__") or not 1 <= len(samples) <= 64:
        raise RadiometerError(f"samples must be a list of 1 to 64 sample counts, got {samples!r:.60}")
    samples = tuple(_v.integer(n, "samples", low=1, high=_v.MAX_SAMPLES) for n in samples)
    target_error = _v.fraction(target_error, "target_error")
    replicas = _v.integer(replicas, "replicas", low=2, high=1000)
    reference_samples = _v.samples(reference_samples, "reference_samples")
    _v.measurement(quality_=quality, target_rel_error=target_rel_error, time_budget_s=time_budget_s,
                   seed_=seed, allow_none_quality=True)
    _v.callable_or_none(cancelled, "cancelled")
    plot = _v.optional_output(plot, "plot")
    from .measure.analyses import analysis

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, time_budget_s=time_budget_s,
                       seed=seed, cancelled=cancelled)  # quality None stays None: "not given" (see the study)
    return analysis.convergence_study(target, request=request, location=location, normal=normal, samples=samples,
                                      target_error=target_error, replicas=replicas,
                                      reference_samples=reference_samples, targeted=targeted, plot=plot,
                                      meter_kind=target.radiometer_meter.kind if _is_meter(target) else None)


@_v.boundary
def export_report(out_dir, *, scene=None, quality=None, method=None, target_rel_error=None, time_budget_s=None,
                  convergence=True, client=True, project=None, task=None, maintenance_factor=0.8, observers=(),
                  ra=None, convergence_samples=(4, 16, 64), progress=None, cancelled=None, phase=None,
                  daylight=False, epw=None, median_external_illuminance_lux=None, daylight_resolution=None):
    """Write report.json, report.md and PNG plots for every meter, light and work plane into ``out_dir``.

    ``quality`` (preset name), ``method`` and ``target_rel_error`` (fraction) default to the
    scene's Radiometer settings; ``time_budget_s`` (s) bounds each measurement of the report.
    ``client``: also the client's report.html and report.pdf (``project`` data dict, EN 12464-1
    ``task`` with ``maintenance_factor``, UGR ``observers`` ((x, y, z), (dx, dy, dz)), rated ``ra``;
    see docs/deliverables.md). ``convergence_samples``: the study's sample counts; ``progress(done,
    total, seconds_left)`` in thousandths of the whole report, ``phase(label)`` the part being measured,
    ``cancelled()`` polled by every measurement. ``daylight``: True adds the daylight section (daylight
    factor, with the weather file ``epw`` sDA/ASE/UDI and sunlight hours, DGP at the scene camera, the EN
    17037 table with the site's ``median_external_illuminance_lux`` for the DF method, the maps; grids of
    ``daylight_resolution`` (nx, ny), default EN 12464-1's spacing); "auto": when the scene has a sun or an
    emitting world; False: none (docs/deliverables.md).
    """
    out_dir = _v.path(out_dir, "out_dir")
    _b.scene(scene)
    if daylight not in (True, False, "auto"):
        raise RadiometerError(f"daylight must be True, False or 'auto', got {daylight!r}")
    _v.real(median_external_illuminance_lux, "median_external_illuminance_lux", low=0.0, low_open=True,
            allow_none=True)
    if epw is not None:
        epw = _v.path(epw, "epw")
    _v.measurement(quality_=quality, method_=method, target_rel_error=target_rel_error,
                   time_budget_s=time_budget_s, progress=progress, cancelled=cancelled, allow_none_quality=True,
                   allow_none_method=True)
    _v.callable_or_none(phase, "phase")
    from .measure.reports import report

    request = _request(scene, quality=quality, target_rel_error=target_rel_error, time_budget_s=time_budget_s,
                       progress=progress, cancelled=cancelled)
    return report.export_report(out_dir, **_report_scene(scene), request=request, method=method,
                                convergence=convergence, client=client, project=project, task=task,
                                maintenance_factor=maintenance_factor, observers=observers, ra=ra,
                                convergence_samples=convergence_samples,
                                phase=phase, daylight=daylight, epw=epw,
                                median_external_illuminance_lux=median_external_illuminance_lux,
                                daylight_resolution=daylight_resolution)


@_v.boundary
def export_radiance(out_dir, *, scene=None, resolution=None, spacing=None, ground_reflectance=0.2):
    """Write the scene for Radiance into ``out_dir`` (created): scene.rad (materials, geometry, thin panes
    as glass, lights), sky.rad (the world exactly, its suns; sky_gensky.rad the nearest gensky line),
    sky_overcast.rad (the daylight factor's CIE overcast sky, E_h 10 000 lx, ``ground_reflectance``), one
    .pts per work plane (grid ``resolution`` (nx, ny) or ``spacing`` m, default EN 12464-1's) and
    meters.pts, one .vf per camera, README.txt (how to run it; one line per thing not mapped) and
    radiance_export.json. All files together or none; the scene is only read. Returns a dict with
    ``files``, ``unmapped``, ``notes`` and ``summary``.
    """
    out_dir = _v.path(out_dir, "out_dir")
    _b.scene(scene)
    _v.real(ground_reflectance, "ground_reflectance", low=0.0, high=1.0)
    if resolution is not None and spacing is not None:
        raise RadiometerError("give a resolution or a spacing, not both")
    import bpy

    from .measure.reports import radiance_export

    meters = _meters(scene or bpy.context.scene, every=True)  # the UI's meter settings, read here
    return radiance_export.export_radiance(out_dir, request=_request(scene), resolution=resolution, spacing=spacing,
                                           ground_reflectance=ground_reflectance, meters=meters)


@_v.boundary
def assign_brdf(material, model, method="nodes", **params):
    """Give ``material`` the parametric BRDF ``model`` (a name from ``radiometer.brdf.names()``).

    ``method``: "nodes" (a node group: Cycles on any device, EEVEE) or "osl" (a Script node: Cycles
    on the CPU with Open Shading Language enabled). Returns the ``Fidelity`` of the mapping onto
    Cycles' closures: kind "exact" or "approximate" with the measured RMS relative difference and
    directional-albedo difference. The material stays re-editable from its Radiometer BRDF panel.
    """
    import bpy

    if not isinstance(material, bpy.types.Material):
        raise RadiometerError(f"material must be a bpy.types.Material, got {material!r:.60}")
    _v.choice(method, "method", ("nodes", "osl"))
    if not isinstance(model, str):
        raise RadiometerError(f"model must be a BRDF model name, got {model!r:.60}")
    from .shading import assign

    return assign.assign_brdf(material, model, method=method, **params)


# --- luminaires (IES LM-63, EULUMDAT) ----------------------------------------------------------

@_v.boundary
def read_photometry(path):
    """Read an IES LM-63 (.ies) or EULUMDAT (.ldt) file into a ``Photometry`` (no Blender needed):
    ``vertical_angles_deg``, ``horizontal_angles_deg``, ``candela`` (n_h, n_v), ``candela_at(v, h)``,
    ``lumens``, ``rated_lumens``, ``max_candela``, ``beam_angle_deg``, ``field_angle_deg``,
    ``symmetry``, ``metadata``, ``summary()``. Bad files raise RadiometerError naming the line."""
    path = _v.check_input_file(path, "photometric file")
    from .radiometry.photometry import photometric_files

    try:
        return photometric_files.read_photometry(path)
    except photometric_files.PhotometricFileError as exc:
        raise RadiometerError(str(exc)) from None


@_v.boundary
def import_luminaire(path, *, scene=None, location=(0.0, 0.0, 0.0), rotation_euler=(0.0, 0.0, 0.0), name=None):
    """Add a photometric file as a point light whose Cycles render gives the file's candela at the
    scene's luminous efficacy (vertical 0 deg along the light's local -Z, C0 along local +X, C90 along
    local +Y). Returns the light object; bad input raises RadiometerError and creates nothing."""
    path = _v.check_input_file(path, "photometric file")
    _b.scene(scene)
    location = _v.points(location, "location", allow_many=False)
    rotation_euler = _v.points(rotation_euler, "rotation_euler", allow_many=False)
    if name is not None and (not isinstance(name, str) or not name.strip() or len(name) > 63):
        raise RadiometerError(f"name must be a non-empty object name of at most 63 characters, got {name!r:.60}")
    from .measure.capture import luminaires

    return luminaires.import_luminaire(path, scene=_request(scene), location=location, rotation_euler=rotation_euler,
                                       name=name)


@_v.boundary
def goniometric_diagram(source, path, *, title=None):
    """Write a polar plot of the C0-C180 and C90-C270 planes of ``source`` (a file path, a
    ``Photometry`` or a light object Radiometer can read) to ``path`` (PNG); cd/klm when the file
    has a rated lamp flux, else cd. Returns ``path``. RadiometerError when matplotlib is missing."""
    path = _v.output_file(path, "path")
    if title is not None and not isinstance(title, str):
        raise RadiometerError(f"title must be a string, got {title!r:.60}")
    import os

    import numpy as np

    from .plots import goniometric
    from .radiometry.photometry import photometric_files

    if isinstance(source, photometric_files.Photometry):
        photometry = source
    elif isinstance(source, (str, bytes, os.PathLike)):
        photometry = read_photometry(source)
    else:
        from .measure.capture import luminaires

        photometry = luminaires.photometry_of_light(source)
    if photometry.photometric_type != "C":
        raise RadiometerError(f"{photometry.source}: type {photometry.photometric_type} photometry has no C-planes")
    v = np.linspace(0.0, 180.0, 721)
    scale, unit = (1000.0 / photometry.rated_lumens, "cd/klm") if photometry.rated_lumens else (1.0, "cd")
    at = lambda c: photometry.candela_at(v, c) * scale  # noqa: E731
    planes = {"C0-C180": (at(0.0), at(180.0)), "C90-C270": (at(90.0), at(270.0))}
    label = title or photometry.metadata.get("LUMINAIRE") or photometry.metadata.get("luminaire_name") \
        or os.path.basename(photometry.source)
    return goniometric.goniometric_png(os.fspath(path), v, planes, unit=unit, title=label)


# --- environment lighting (issue 14) -------------------------------------------------------------

@_v.boundary
def irradiance_environment_map(source, path, *, method="exact", resolution=(64, 32), scene=None):
    """Write the irradiance environment map E(n) of ``source`` as a 32-bit EXR (W/m^2 per pixel, the
    pixel's direction as the normal) and return a dict with ``path``, the 9 SH ``coefficients``
    (RGB), ``sh9_error`` (measured max |E9 - E_exact|, method "exact") and ``sh9_bound`` (3/32 x
    integral of L), ``notes``. ``source``: a radiance map EXR path, a ``RadianceMap`` (from
    ``capture_radiance_map``), or "world" / a scene (its world, when modelled). ``method``:
    "exact" (pixel-exact clamped-cosine integral) or "sh9" (Ramamoorthi & Hanrahan 2001);
    ``resolution`` = (width, height) of the output."""
    import os

    if isinstance(source, (str, os.PathLike)) and source != "world":
        source = _v.check_input_file(source, "radiance map")
    path = _v.output_file(path, "path")
    _v.choice(method, "method", ("exact", "sh9"))
    resolution = _v.resolution2(resolution, "resolution")
    _b.scene(scene)
    from .measure.authoring import world

    return world.irradiance_environment_map(source, path, method=method, resolution=resolution, scene=scene)


@_v.boundary(finite=True)
def world_illuminance(scene=None, normal=(0.0, 0.0, 1.0)):
    """Illuminance (lux) on a surface facing ``normal`` from the world alone, with its brightest
    direction and that direction's luminance: a dict (``illuminance``, ``irradiance_rgb``,
    ``method`` "analytic" when the world is modelled, else "render", ``exact``,
    ``brightest_direction``, ``brightest_luminance`` cd/m^2, ``notes``)."""
    _b.scene(scene)
    normal = _v.directions(normal, "normal", allow_many=False)
    from .measure.authoring import world

    return world.world_illuminance(_request(scene), normal)


@_v.boundary
def calibrate_world(scene=None, illuminance_lux=None, normal=(0.0, 0.0, 1.0)):
    """Set the world's Background strength so that the world alone gives ``illuminance_lux`` on a
    surface facing ``normal``; returns a dict with old/new strength and the illuminance after."""
    _b.scene(scene)
    illuminance_lux = _v.positive(illuminance_lux, "illuminance_lux", high=1e7)
    normal = _v.directions(normal, "normal", allow_many=False)
    from .measure.authoring import world

    return world.calibrate_world(_request(scene), illuminance_lux, normal)


@_v.boundary
def world_model(scene=None):
    """The world as Radiometer models it (``radiometry.skies.environment.WorldLight``: kind, reason, ...)."""
    _b.scene(scene)
    import bpy

    from .measure.capture import world_capture

    return world_capture.read_world(scene or bpy.context.scene)


@_v.boundary
def mirror_ball_probe(scene=None, *, size=256, shape=(128, 256), view=(0.0, -1.0, 0.0)):
    """Render the classic light probe (an ideal chrome ball in the scene's world, seen along ``view``)
    and convert it to an equirect map of ``shape`` (h, w) in the Environment Texture orientation.
    Returns (probe (size, size, 3), equirect (h, w, 3)); see README "Environment lighting" for the
    resolution loss towards the direction behind the ball."""
    _b.scene(scene)
    size = _v.integer(size, "size", low=8, high=_v.MAX_MAP_SIDE)
    shape = _v.resolution2(shape, "shape", low=2)
    view = _v.directions(view, "view", allow_many=False)
    from .measure.authoring import world
    from .radiometry.skies import environment

    from .measure.blender import scene_guard

    with scene_guard.preserved_scene(scene):  # the render leaves a 'Render Result' image otherwise
        probe, camera = world.render_mirror_ball(scene, size=size, view=view)
    return probe, environment.probe_to_equirect(probe, shape, environment.BLENDER_WORLD_ROTATION, camera)


# --- daylight: the sun (issue 19) ----------------------------------------------------------------

@_v.boundary
def sun_position(latitude_deg, longitude_deg, when, *, elevation_m=0.0, pressure_hpa=1013.25, temperature_c=12.0,
                 north_offset_deg=0.0, delta_t_s=None):
    """Where the sun is (NREL SPA, Reda & Andreas 2008; no Blender needed).

    ``when``: a timezone-aware ``datetime`` or a sequence of them (naive -> RadiometerError).
    Latitude north +, longitude east + (deg); ``elevation_m`` above sea level; pressure (hPa) and
    temperature (deg C) for the refraction; ``delta_t_s`` TT - UT (default: Espenak & Meeus).
    Returns a ``SolarPosition``: ``azimuth_deg`` (clockwise from north), ``elevation_deg``
    (apparent, with refraction), ``zenith_deg``, ``true_elevation_deg``, ``direction`` (unit
    vector towards the sun: +X east, +Y north, +Z up, turned by ``north_offset_deg`` = the angle
    from scene +Y to true north, counter-clockwise seen from above), ``earth_sun_distance_au``,
    ``equation_of_time_min``, ``delta_t_s``; arrays for a sequence of times. See docs/daylight-sun.md.
    """
    from .radiometry.sun import solar_position

    try:
        unix = solar_position.unix_seconds(when)
        return solar_position.solar_position(unix, latitude_deg, longitude_deg, elevation_m=elevation_m,
                                             pressure_hpa=pressure_hpa, temperature_c=temperature_c,
                                             delta_t_s=delta_t_s, north_offset_deg=north_offset_deg)
    except (TypeError, ValueError) as exc:
        raise RadiometerError(str(exc).splitlines()[0]) from None


@_v.boundary
def set_sun(scene, latitude_deg, longitude_deg, when, *, direct_normal_illuminance_lux=None, north_offset_deg=0.0,
            elevation_m=0.0):
    """Create or update the scene's Sun light (angle 0.53 deg) for this place and time.

    Its strength makes the meter read ``direct_normal_illuminance_lux`` (lux) facing the sun, or the
    IES clear-day model's E_dn = 127.5 klx / R^2 exp(-0.21 m) when None; below the horizon its
    strength is 0. Returns a dict (object, azimuth_deg, elevation_deg, direction,
    direct_normal_illuminance_lux, strength_w_m2, model, above_horizon, notes).
    """
    from .measure.authoring import sun

    return sun.set_sun(_request(scene), latitude_deg, longitude_deg, when,
                       direct_normal_illuminance_lux=direct_normal_illuminance_lux,
                       north_offset_deg=north_offset_deg, elevation_m=elevation_m)


# --- daylight: CIE skies and the daylight factor (issue 19) ---------------------------------------

from .radiometry.skies.sky_models import SKY_MODELS  # noqa: E402  (re-exported)

#: ``SKY_MODELS``: every sky model by name ("overcast", "cie:1" .. "cie:15"), the names ``set_cie_sky``,
#: ``sun_study(sky=...)``, the CLI's ``sun-study --sky`` and the *Set CIE Sky* operator take. How to add
#: one: the checklist in ``radiometry/skies/sky_models.py``.


@_v.boundary
def sky_model(name):
    """The sky model called ``name`` (a key of ``SKY_MODELS``, any case; a CIE type also as 7, "7",
    "cie7"): its ``name``, ``label``, ``description``, ``needs_sun``, ``relative_luminance``,
    ``sky_integral`` and ``world``. An unknown name raises ``RadiometerError`` naming every model."""
    from .radiometry.skies import sky_models

    try:
        return sky_models.sky_model(name)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None


@_v.boundary
def set_cie_sky(scene, sky_type, *, horizontal_illuminance_lux=None, sun_direction=None, ground_reflectance=0.2):
    """Make the scene's world a CIE sky whose shader evaluates the sky's luminance formula on the ray
    direction (a new World; the old one stays in the file).

    ``sky_type``: a sky model's name (``SKY_MODELS``): "overcast" (the traditional CIE overcast sky,
    L = Lz (1 + 2 cos Z) / 3) or an ISO 15469 / CIE S 011 general sky type 1..15 (int, or "cie:12"). ``horizontal_illuminance_lux``:
    the unobstructed horizontal illuminance from the sky (default 10 000 lx); ``sun_direction``:
    unit vector towards the sun (+X east, +Y north, +Z up; needed by the types that depend on the
    sun, e.g. from :func:`sun_position`); the uniform ground below a sharp horizon has luminance
    ``ground_reflectance`` x E_h / pi. The meter reads this world exactly where nothing lies above
    its horizon (see docs/daylight-sky.md). Returns a dict (world, sky_type, zenith_luminance,
    ground_luminance, ..., notes).
    """
    from .measure.authoring import sky

    return sky.set_cie_sky(_request(scene), sky_type, horizontal_illuminance_lux=horizontal_illuminance_lux,
                           sun_direction=sun_direction, ground_reflectance=ground_reflectance)


@_v.boundary
def daylight_factor(locations, normals=(0.0, 0.0, 1.0), *, scene=None, quality="standard", ground_reflectance=0.2,
                    target_rel_error=None, method="auto", seed=0, progress=None, cancelled=None, client=None,
                    target_abs_error=None):
    """Daylight factor DF = 100 x E_in / E_out,h (%) under the CIE overcast sky, at ``locations``
    (3 numbers or (N, 3), scene coordinates) facing ``normals``.

    Measured with every light switched off and a temporary overcast world (E_out,h = 10 000 lx,
    uniform ground ``ground_reflectance`` x E_h / pi below a sharp horizon); the user's world,
    lights and data-blocks are restored afterwards. Returns a ``DaylightFactorReading`` (or a list):
    ``daylight_factor`` (%), ``rel_std_error``, ``illuminance`` (lux), ``exact``, ``method``, ``notes``.
    ``method``: the meter's ("auto", ...), or "camera": cosine-weighted rays from each point through a
    custom camera, a fixed number per quality, the error stated (docs/daylight-sky.md). With "auto",
    where the sky component is proven (convex open openings in a closed opaque room, nothing outside in
    the way) it is read in closed form and only the rest is rendered: the reading's ``sky_component``
    and ``reflected_component`` (%) say how much of each (None where not proven, with the reason in
    ``notes``).
    ``client``: a Dask client: the points run in chunks of 256 on its workers (docs/cluster.md).
    ``target_abs_error``: the absolute error floor in daylight-factor points (None: the preset's, 0.025 /
    0.005 / 0.001 for preview / standard / reference; 0: none), beside the relative target.
    """
    from .measure.analyses import daylight_factor as df

    _v.real(target_abs_error, "target_abs_error", low=0.0, allow_none=True)
    request = _request(scene, quality=quality, target_rel_error=target_rel_error, seed=seed, progress=progress,
                       cancelled=cancelled, client=client)
    return df.daylight_factor(locations, normals, request=request, ground_reflectance=ground_reflectance,
                              method=method, target_abs_df=target_abs_error)


@_v.boundary
def daylight_factor_grid(target, *, resolution=None, spacing=None, scene=None, quality="standard",
                         ground_reflectance=0.2, target_percent=None, median_external_illuminance_lux=None,
                         target_rel_error=None, method="auto", seed=0, progress=None, cancelled=None, client=None,
                         target_abs_error=None):
    """Daylight factor on a work-plane object's grid (points as :func:`illuminance_grid` lays them out).

    Returns a ``DaylightFactorGrid``: ``daylight_factor`` (ny, nx) %, ``rel_std_error``, ``points``
    and ``stats``: average (BS 8206-2), minimum, maximum, median, uniformity (min / average),
    ``share_above_target`` for ``target_percent``, and EN 17037 D_T / D_TM checks per level when the
    site's ``median_external_illuminance_lux`` (E_v,d, EN 17037 Annex A) is given. ``client``: a Dask
    client: the grid's points run in chunks of 256 on its workers (docs/cluster.md).
    ``target_abs_error``: the absolute error floor in daylight-factor points (see :func:`daylight_factor`).
    With ``method="auto"`` the grid's ``sky_component`` (ny, nx) % is the proven closed form (NaN where
    not proven; see :func:`daylight_factor`).
    """
    from .measure.analyses import daylight_factor as df

    _v.real(target_abs_error, "target_abs_error", low=0.0, allow_none=True)
    request = _request(scene, quality=quality, target_rel_error=target_rel_error, seed=seed, progress=progress,
                       cancelled=cancelled, client=client)
    return df.daylight_factor_grid(target, request=request, resolution=resolution, spacing=spacing,
                                   ground_reflectance=ground_reflectance, target_percent=target_percent,
                                   median_external_illuminance_lux=median_external_illuminance_lux,
                                   method=method, target_abs_df=target_abs_error)


@_v.boundary
def daylight_map(result, path, *, metric=None, scene=None, outline=True):
    """A plan-view daylight map PNG at ``path`` (whole or not at all; checked before any work) of a
    :func:`daylight_factor_grid` result (DF %), an :func:`annual_daylight` result (``metric``: "sda", the
    share of occupied hours at 300 lx per point, ringed where its pass/fail is uncertain at 2 s.e.
    (default); "ase", hours of direct sun at 1000 lx; "udi", the share of hours at 100-2000 lx) or a
    :func:`sun_study` result (sunlight hours). Points not measured (not finite) are drawn hatched, never
    as a colour; the title states the error. ``outline``: draw the room cut at the points' height and its
    openings (from the scene as Cycles renders it). The points must lie on one horizontal plane.
    Returns ``path``. For other per-point numbers: ``plots.daylight_map.daylight_map_png``."""
    _b.scene(scene)
    path = _v.output_file(path, "png")
    from .measure.reports import daylight_maps

    return daylight_maps.daylight_map(result, path, metric=metric, scene=_request(scene), outline=bool(outline))


@_v.boundary
def annual_daylight(locations, normals=(0.0, 0.0, 1.0), epw_path=None, *, scene=None, m=1, quality="preview",
                    samples=None, target_rel_error=None, ground_reflectance=0.2, north_offset_deg=0.0,
                    occupied_from=8.0, occupied_to=18.0, seed=0, progress=None, cancelled=None, client=None,
                    method="dome", partial_period=False):
    """Annual climate-based daylight at ``locations`` from an EPW weather file, the two-phase way.

    Daylight coefficients of every sky patch (Reinhart MF:``m``; 146 patches with the ground for
    m = 1), with ``method="dome"`` from one render per round for all patches at once (a dome of
    emitting patches, one Cycles light group each, seen by a custom camera whose pixel blocks are the
    meters' hemispheres), or ``"per_patch"`` (one render per patch, the older way); per hour the
    Perez all-weather sky and the sun (spread over its 4 nearest patches) give the patch luminances;
    hourly illuminance = sky x coefficients, with its standard error. Returns an ``AnnualResult``:
    ``illuminance`` (T, N) lux, ``sda`` (sDA300/50 %) and ``sda_range`` (points whose verdict changes
    within 2 standard errors counted failing / passing), ``ase`` (ASE1000/250 h from the direct sun
    alone, LM-83), ``udi``, per-point fractions, ``to_dict()``, ``csv_text()``. See
    docs/daylight-sky.md. ``client``: a Dask client (the same tasks, the same numbers; docs/cluster.md).
    The weather file is checked (radiometry/sun/epw.py; one line naming the line, or a note): a file that is
    not a whole year is refused unless ``partial_period=True`` (the notes then say the period).
    """
    if not isinstance(partial_period, bool):
        _v.fail("partial_period", "True or False", partial_period)
    from .measure.analyses import annual

    request = _request(scene, quality=quality, samples=samples, target_rel_error=target_rel_error, seed=seed,
                       progress=progress, cancelled=cancelled, client=client)
    return annual.annual_daylight(locations, normals, epw_path, request=request, m=m,
                                  ground_reflectance=ground_reflectance, north_offset_deg=north_offset_deg,
                                  occupied_from=occupied_from, occupied_to=occupied_to, method=method,
                                  partial_period=partial_period)


# --- scale-out on Dask (issue 20) ----------------------------------------------------------------

@_v.boundary
def measure_batch(files, meters=None, *, quality="standard", method=None, seed=0, client=None, progress=None,
                  cancelled=None):
    """Readings of many .blend files (design variants), one list per file, in the order of ``files``.

    ``meters``: None (every light-meter object of each file, with the file's method), meter object
    names, or illuminance points: (x, y, z), ((x, y, z), (nx, ny, nz)) or {"location", "normal"}
    (scene coordinates; normal default +Z). ``quality``: "preview" | "standard" | "reference"
    (1-sigma targets 5 %, 1 %, 0.2 %); ``seed``: first Cycles seed of point readings. ``client``:
    None runs in this process (each file opened in turn, the open file reopened afterwards; see
    docs/cluster.md), or a ``distributed.Client`` (``radiometer.cluster.local_client(n)`` or
    ``connect(address)``): one task per file on the cluster's workers. ``progress(done, total,
    seconds_left)`` after each file. Returns ``FileReadings`` (``file``, ``scene``, ``names``,
    ``readings``, ``to_dict()``) per file. A bad or unreadable file, or a missing texture, raises
    RadiometerError naming the file and the task.
    """
    from .measure.analyses import batch

    return batch.measure_batch(files, meters, quality=quality, method=method, seed=seed, client=client,
                               progress=progress, cancelled=cancelled, read_meters=scene_meters)


@_v.boundary
def scene_meters(scene=None, objects=None):
    """(meters, settings) of a scene as its Radiometer properties say: ``meters`` the
    ``measure.meter.meter_objects.Meter`` of ``objects`` (each must be a meter; None: every meter of the
    scene; none at all raises), ``settings`` its method, quality and target error (fraction or None).
    The batch task reads an opened file's meters with it, on whichever worker opened the file."""
    import bpy

    _b.scene(scene)
    scene = scene or bpy.context.scene
    return _meters(scene, objects), _scene_settings(scene)


@_v.boundary
def sun_study(locations, normals, times, *, latitude_deg, longitude_deg, elevation_m=0.0,
              direct_normal_illuminance_lux=None, sky=None, scene=None, quality="standard", client=None,
              north_offset_deg=0.0, min_elevation_deg=0.0, method="auto", seed=0, progress=None, cancelled=None,
              sky_horizontal_illuminance_lux=None, time_budget_s=None):
    """Illuminance from the sun where it stands at each of ``times`` on N meters (issue 19).

    ``locations`` (N, 3) scene coordinates, ``normals`` (3,) or (N, 3); ``times``: timezone-aware
    datetimes; the site's latitude/longitude (deg, north/east +) and ``north_offset_deg`` as in
    :func:`sun_position`. Per time the sun is set (0.53 deg; ``direct_normal_illuminance_lux``: one
    value, one per time, or None for the IES clear-day model), every other light and the world are
    switched off (``sky``: a ``SKY_MODELS`` name, "overcast" | "cie:<type>": that sky instead, with the sun's direction
    and ``sky_horizontal_illuminance_lux`` (the same at every time; None: set_cie_sky's default)),
    and the meter measures (exact where nothing can block the sun, rendered to ``quality``
    elsewhere; ``time_budget_s``: at most about that many seconds per time step, whichever of target
    and budget comes first). Where the sunlit surfaces are too small for the meters' rays to find (a low
    sun's strip on a reveal: a meter's pilot finds no light; with a sky, always) and every sunlit surface is
    Lambertian, the step reads the sun's first bounce as emitters over the exact sunlit polygons and the
    sun's direct light in closed form (docs/daylight-sun.md, "A low sun"); the readings' notes say so. The
    scene is restored after every step. ``client``: a Dask client
    (``radiometer.cluster``); None runs here. Returns a ``SunStudyResult``: ``illuminance`` (T, N)
    lux, ``rel_std_error``, ``exact``, ``sunlit`` (T, N: the disc's centre is visible),
    ``sunlit_fraction``, ``sun`` (azimuth_deg, elevation_deg per time), ``sample_hours`` (T,),
    ``sunlight_hours`` (N,) (EN 17037 exposure: trapezoid weights, sun at least
    ``min_elevation_deg`` high), ``to_dict()``, ``csv_text()``.
    """
    from .measure.analyses import sun_study as study

    request = _request(scene, quality=quality, client=client, seed=seed, progress=progress, cancelled=cancelled,
                       time_budget_s=time_budget_s)
    return study.sun_study(locations, normals, times, request=request, latitude_deg=latitude_deg,
                           longitude_deg=longitude_deg, elevation_m=elevation_m,
                           direct_normal_illuminance_lux=direct_normal_illuminance_lux, sky=sky,
                           north_offset_deg=north_offset_deg, min_elevation_deg=min_elevation_deg, method=method,
                           sky_horizontal_illuminance_lux=sky_horizontal_illuminance_lux)


# --- deliverables: glare (issue 23) --------------------------------------------------------------

@_v.boundary
def glare_ugr(observer, view_direction, *, scene=None, quality="standard"):
    """CIE 117-1995 Unified Glare Rating for an eye at ``observer`` (scene coordinates) looking along
    ``view_direction`` (+Z up). Returns a ``GlareResult``: ``ugr``, ``ugr_std_error``,
    ``background_luminance`` (cd/m², indirect vertical illuminance at the eye / pi), ``sources`` (name,
    luminance cd/m², solid_angle sr of the part the eye sees, position_index, sigma_deg, tau_deg,
    visible_fraction and its proven bounds, visibility), ``left_out`` (name, reason: hidden from the eye,
    outside the field, ...), ``ugr_visibility_range``, ``error_unknown`` / ``not_measurable`` (the cause,
    where the error or the value cannot be given), ``notes``. Area lights, IES/EULUMDAT lights with a flat
    luminous opening and emitting meshes are rated for the part the eye sees; see ``measure.analyses.glare``."""
    from .measure.analyses import glare

    return glare.glare_ugr(observer, view_direction, request=_request(scene, quality=quality))


@_v.boundary
def glare_dgp(observer, view_direction, *, scene=None, quality="preview", resolution=128, threshold_cd_m2=2000.0,
              threshold_factor=None, low_light_correction=False, hdr_path=None):
    """Daylight glare probability (Wienold & Christoffersen 2006) for an eye at ``observer`` (scene
    coordinates) looking along ``view_direction`` (+Z up): a 180 deg angular fisheye (``resolution`` px
    a side, preview-sized) is rendered from the eye, glare sources are found on it as evalglare finds
    them (pixels above ``threshold_cd_m2``, default 2000 cd/m², or ``threshold_factor`` x the picture's
    mean luminance), E_v is the meter's. ``hdr_path``: also write the fisheye as a Radiance HDR for
    evalglare. Returns a ``DaylightGlareResult``: ``dgp``, ``dgp_std_error``, ``dgp_class``
    (imperceptible < 0.35 <= perceptible < 0.40 <= disturbing < 0.45 <= intolerable),
    ``vertical_illuminance`` (lx), ``sources`` (luminance cd/m², solid_angle sr, position_index, ...),
    ``notes``. See ``measure.analyses.daylight_glare``."""
    from .measure.analyses import daylight_glare

    return daylight_glare.glare_dgp(observer, view_direction, request=_request(scene, quality=quality),
                                    resolution=resolution,
                                    threshold_cd_m2=threshold_cd_m2, threshold_factor=threshold_factor,
                                    low_light_correction=low_light_correction, hdr_path=hdr_path)


@_v.boundary
def annual_dgp(observer, view_direction, epw_path=None, *, scene=None, m=1, quality="preview", samples=None,
               ground_reflectance=0.2, north_offset_deg=0.0, occupied_from=8.0, occupied_to=18.0, seed=0,
               low_light_correction=False, client=None, partial_period=False, progress=None, cancelled=None):
    """Annual daylight glare probability, imageless (Wienold 2009), for an eye at ``observer`` (scene
    coordinates) looking along ``view_direction`` (+Z up; not vertical), from an EPW weather file.

    E_v per hour from the daylight coefficients of a meter at the eye facing the view (as
    :func:`annual_daylight`, with its hourly standard error); at the hours where the sun is in the view's
    hemisphere and its centre ray reaches the eye, full DGP with the sun's disc (6.8e-5 sr, luminance
    E_dn / omega x the panes' transmittance) as the glare source; at the others the simplified DGPs =
    6.22e-5 E_v + 0.184 (no contrast term: the lower envelope where no sun is seen). Returns an
    ``AnnualDGPResult``: ``dgp`` (T,) and ``dgp_std_error``, ``vertical_illuminance`` (lx), ``sun_seen``,
    ``occupied``, ``hours_above`` / ``hours_above_range`` / ``share_above`` at 0.35, 0.40, 0.45,
    ``en17037`` (the protection-from-glare row; :func:`en17037_table` takes ``dgp=r.occupied_dgp()``),
    ``notes``, ``to_dict()``, ``csv_text()``. See ``measure.analyses.daylight_glare``."""
    if not isinstance(partial_period, bool):
        _v.fail("partial_period", "True or False", partial_period)
    if not isinstance(low_light_correction, bool):
        _v.fail("low_light_correction", "True or False", low_light_correction)
    from .measure.analyses import daylight_glare as adgp

    request = _request(scene, quality=quality, samples=samples, seed=seed, client=client, progress=progress,
                       cancelled=cancelled)
    return adgp.annual_dgp(observer, view_direction, epw_path, request=request, m=m,
                           ground_reflectance=ground_reflectance, north_offset_deg=north_offset_deg,
                           occupied_from=occupied_from, occupied_to=occupied_to,
                           low_light_correction=low_light_correction, partial_period=partial_period)


#: The glare indices, by the name the CLI's ``glare --index`` takes: one function per index, each
#: ``f(observer, view_direction, *, scene=None, quality=..., **its own options)`` returning a result with
#: ``summary()``, ``sources`` (dicts with ``luminance`` cd/m², ``solid_angle`` sr, ``position_index``) and
#: ``to_dict()``. How to add an index (e.g. VCP, DGI):
#:
#: 1. the formula, pure and cited, in ``radiometry/metrics/`` (as ``glare.py``, ``glare_dgp.py``), tested
#:    against its source's worked example or an independent program (evalglare for DGP);
#: 2. the measurement in ``measure/analyses/`` (as ``glare.glare_ugr``, ``daylight_glare.glare_dgp``):
#:    the scene in, a result dataclass with the fields above out, every number SI with its error;
#: 3. an api function here with ``@_v.boundary`` and its arguments checked, and one entry below;
#: 4. in ``commands/glare.py``: its own options (``INDEX_OPTIONS``) and its source line (``SOURCE_LINE``).
GLARE_INDICES = {"ugr": glare_ugr, "dgp": glare_dgp}


@_v.boundary
def en17037_table(*, illuminance=None, daylight_hours=None, daylight_factor=None, median_external_illuminance_lux=None,
                  sunlight_hours=None, dgp=None, view_out=None):
    """EN 17037:2018+A1:2021 table: the level (minimum / medium / high / not met / not assessed) of each
    criterion, values marked indicative (``radiometry.metrics.en17037``). Daylight provision from hourly
    ``illuminance`` (T hours, N plane points, lx; ``daylight_hours`` (T,) bool) or, failing that,
    ``daylight_factor`` (N,) % with the site's ``median_external_illuminance_lux`` (E_v,d); exposure
    to sunlight from ``sunlight_hours`` (h on the reference day, e.g. ``sun_study``'s); protection from
    glare from ``dgp`` (one value per occupied hour); view out from ``view_out`` = (horizontal sight
    angle deg, outside distance m, layers seen). A criterion without input reads "not assessed".
    Returns a list of dicts (criterion, method, level, values, per_level, source, indicative, note)."""
    import dataclasses

    from .radiometry.metrics import en17037

    try:
        provision = None
        if illuminance is not None:
            provision = en17037.daylight_provision_illuminance(illuminance, daylight_hours)
        elif daylight_factor is not None:
            if median_external_illuminance_lux is None:
                raise ValueError("the DF method needs the site's median_external_illuminance_lux (E_v,d)")
            provision = en17037.daylight_provision_daylight_factor(daylight_factor, median_external_illuminance_lux)
        sun = None if sunlight_hours is None else en17037.sunlight_exposure(sunlight_hours)
        glare_row = None if dgp is None else en17037.glare_protection(dgp)
        if view_out is None:
            view = None
        else:
            try:
                angle, distance, layers = view_out
            except (TypeError, ValueError):
                raise ValueError(f"view_out must be (sight angle deg, distance m, layers), got {view_out!r}") from None
            view = en17037.view_out(angle, distance, layers)
    except ValueError as exc:
        raise RadiometerError(f"EN 17037: {exc}") from None
    return [dataclasses.asdict(row) for row in en17037.table(provision=provision, sunlight=sun, glare=glare_row,
                                                             view=view)]


@_v.boundary
def view_out(eyes, *, scene=None):
    """EN 17037 view out from ``eyes`` (3 numbers or (N, 3), scene coordinates: the assessed points of the
    utilised area at eye height, e.g. a work plane's points 0.35 m up for a seated eye). Geometry only
    (``radiometry/scene/view_out.py``): rays through the openings of the opaque surfaces say per eye the
    horizontal sight angle (deg), the outside distance (m) and the layers seen (sky, landscape, ground); the
    row takes each as reached from 75 % of the eyes. "not assessed", with its cause, where the scene models
    nothing outside but flat ground. Returns a ``ViewOutResult`` (docs/deliverables.md)."""
    from .measure.analyses import daylight_glare

    return daylight_glare.view_out(eyes, request=_request(scene))


@_v.boundary
def cluster_info(scheduler):
    """Workers of the Dask cluster at ``scheduler`` ("tcp://host:8786"): a dict with ``workers``,
    ``threads``, ``hosts``, ``memory_bytes``; an unreachable scheduler raises RadiometerError (one line,
    after 5 s). See docs/cluster.md."""
    from .cluster import cluster_info as info

    return info(scheduler)


@_v.boundary
def luminance_image(path, *, scene=None, camera=None, resolution=None, quality="standard", scale="log", range=None,  # noqa: A002
                    max_spp=None, time_budget_s=None):
    """False-colour luminance image of the camera view (issue 23): renders the scene camera (or
    ``camera``) at ``resolution`` (width, height; default the scene's, at most 320 px a side), writes
    ``path`` (32-bit EXR, cd/m² in every channel) and a false-colour PNG with a legend in cd/m² beside
    it (``scale`` "log" | "linear", ``range`` (lo, hi) cd/m² or automatic). Returns a ``LuminanceImage``:
    ``luminance`` (H, W) cd/m², ``rel_std_error`` (H, W), ``paths``, ``notes``.
    ``max_spp``: samples per pixel per render at most (16-1024; None: 1024, at quality "preview" 16, one
    round of renders as the report's pictures); ``time_budget_s``: no round of renders starts that would
    end past it (issue 31). Where they stop the rounds, ``share_on_target`` and the notes say how many
    pixels reached the quality's target; every pixel states its own error."""
    _v.integer(max_spp, "max_spp", low=16, high=1024, allow_none=True)
    _v.time_budget(time_budget_s)
    from .measure.analyses import luminance_image as images

    request = _request(scene, quality=quality, time_budget_s=time_budget_s)
    return images.luminance_image(path, request=request, camera=camera, resolution=resolution, scale=scale,
                                  range=range, max_spp=max_spp)


@_v.boundary
def en12464_compliance(plane, task=None, *, maintained_lx=None, uniformity=None, ugr_limit=None, ra_required=None,
                       maintenance_factor=0.8, observers=(), ra=None, scene=None, quality="standard", grid=None):
    """EN 12464-1 compliance of a work plane (issue 23): ``task`` a key of
    ``radiometry.metrics.compliance.TASKS`` (values cited there) or the user's own ``maintained_lx`` (lx),
    ``uniformity``, ``ugr_limit``, ``ra_required``; ``maintenance_factor`` (Ēm = MF x Ē); ``observers``:
    ((x, y, z), (dx, dy, dz)) eye positions and view directions rated for UGR; ``ra``: the luminaires'
    rated Ra; ``grid``: a ``GridResult`` already measured on ``plane`` (else one is measured at the
    EN 12464-1 spacing). The grid and the UGR are measured with the electric lighting only: suns and an
    emitting world are switched off meanwhile (restored after), and the notes say so. Returns a dict:
    ``requirement``, ``checks`` (quantity, required, achieved, unit, status pass/fail/marginal/not
    assessed/error unknown, margin, std_error, note), ``overall``, ``grid``, ``glare``, ``lighting``."""
    import dataclasses

    import numpy as np

    from .radiometry.metrics import compliance

    try:
        req = compliance.requirement(task, maintained_lx=maintained_lx, uniformity=uniformity,
                                     ugr_limit=ugr_limit, ra=ra_required)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    import bpy

    from .measure.analyses import light_isolation

    for k, obs in enumerate(observers or ()):
        try:
            _position, _direction = obs
        except (TypeError, ValueError):
            raise RadiometerError(f"observer {k + 1}: give ((x, y, z), (dx, dy, dz)), got {obs!r}") from None
    # EN 12464-1 rates the electric lighting: suns and an emitting world are off while it is measured.
    with light_isolation.electric_lighting_only(scene or bpy.context.scene) as lighting:
        if grid is not None:
            g = grid
            lighting = ("the work-plane grid was given by the caller and is taken as measured (daylight included "
                        "if the scene had any then)" + (f"; glare: {lighting}" if lighting else ""))
        else:
            g = illuminance_grid(plane, scene=scene, quality=quality)
        glare_results = [glare_ugr(position, direction, scene=scene, quality=quality)
                         for position, direction in (observers or ())]
    lo_index = int(np.argmin(g.lux)) if hasattr(g.lux, "size") else 0
    try:
        rows = compliance.assess(req, average_lx=g.stats["avg"], minimum_lx=g.stats["min"],
                                 maintenance_factor=maintenance_factor,
                                 # the mean of independent readings: s.e. = sqrt(sum (E_i s_i)^2) / sum E_i
                                 average_rel_se=float(np.sqrt(np.sum(np.square(g.lux * g.rel_std_error)))
                                                      / max(float(np.sum(g.lux)), 1e-300)),
                                 minimum_rel_se=float(g.rel_std_error.ravel()[lo_index]),
                                 ugr=[(f"observer {k + 1}", r.ugr, r.ugr_std_error, r.error_unknown or r.not_measurable)
                                      for k, r in enumerate(glare_results)],
                                 ra=ra, lighting=lighting)
    except ValueError as exc:
        raise RadiometerError(str(exc)) from None
    return {"requirement": dataclasses.asdict(req), "checks": [dataclasses.asdict(r) for r in rows],
            "overall": compliance.overall(rows), "maintenance_factor": float(maintenance_factor), "grid": g,
            "glare": glare_results, "lighting": lighting or "electric lighting (the scene has no sun or emitting world)"}


@_v.boundary
def en12464_tasks():
    """The EN 12464-1 tasks :func:`en12464_compliance` knows: key -> dict (task, maintained_lx lx,
    uniformity, ugr_limit, ra, source, indicative), values as ``radiometry.metrics.compliance.TASKS`` cites them."""
    import dataclasses

    from .radiometry.metrics import compliance

    return {key: dataclasses.asdict(req) for key, req in compliance.TASKS.items()}


@_v.boundary
def compliance_to_dict(result):
    """The dict of :func:`en12464_compliance` as plain JSON-ready data: the grid and the glare ratings
    by their ``to_dict()`` (numbers, not reprs); everything else as it is."""
    out = dict(result)
    grid = out.get("grid")
    if grid is not None and hasattr(grid, "to_dict"):
        out["grid"] = grid.to_dict()
    out["glare"] = [g.to_dict() if hasattr(g, "to_dict") else g for g in out.get("glare") or ()]
    return out


@_v.boundary
def illuminance_image(path, *, scene=None, camera=None, resolution=None, quality="standard", scale="log", range=None,  # noqa: A002
                      max_spp=1024, time_budget_s=None):
    """Illuminance (lx) on the surfaces the camera sees, from Cycles' diffuse light passes:
    E = pi x (Diffuse Direct + Diffuse Indirect), exact for Lambertian surfaces (Diffuse BSDF, roughness 0);
    0 where nothing diffuse is seen (see ``measure.analyses.luminance_image.illuminance_image`` for where it does
    not hold). Writes ``path`` (32-bit EXR, lx) and a false-colour PNG beside it; returns an
    ``IlluminanceImage``: ``illuminance`` (H, W) lx, ``rel_std_error`` (H, W), ``paths``, ``notes``.
    ``max_spp``: samples per pixel per render at most (16-1024): the rounds stop there even where the
    quality's target is not reached (``share_on_target`` says how many pixels reached it);
    ``time_budget_s``: no round of renders starts that would end past it."""
    _v.integer(max_spp, "max_spp", low=16, high=1024)
    _v.time_budget(time_budget_s)
    from .measure.analyses import luminance_image as images

    request = _request(scene, quality=quality, time_budget_s=time_budget_s)
    return images.illuminance_image(path, request=request, camera=camera, resolution=resolution, scale=scale,
                                    range=range, max_spp=max_spp)


# --- for the operators, panels and the CLI (issue 30): nothing above the api imports measure/ -----
# Thin wrappers: the UI and the CLI call these, so measure/ can change behind one boundary.

@_v.boundary
def default_map_path(name):
    """Where a radiance map named ``name`` goes (an .exr path in the extension's user folder, else a
    private temporary folder); the file name is readable and distinct per name."""
    from .measure.meter import camera

    return camera.default_map_path(str(name))


@_v.boundary
def meter_default_rotation(kind):
    """A new meter's rotation (Euler angles, rad) for ``kind``: a spot meter looks along +Y."""
    from .measure.meter import meter_objects

    return tuple(meter_objects.DEFAULT_ROTATION.get(kind, (0.0, 0.0, 0.0)))


@_v.boundary
def add_meter(kind, location, *, acceptance_deg=1.0, rotation=None, context=None):
    """Create a meter object of ``kind`` ("ILLUMINANCE", "LUMINANCE", "RADIANCE_MAP") at ``location``
    (scene coordinates) in the active collection, selected and active; ``acceptance_deg``: a spot
    meter's full cone angle; ``rotation``: Euler angles (rad), None the kind's default. Returns it."""
    import bpy

    _v.choice(kind, "kind", ("ILLUMINANCE", "LUMINANCE", "RADIANCE_MAP"))
    from .measure.meter import meter_objects

    obj = meter_objects.add_meter_object(context or bpy.context, kind, location, rotation=rotation)
    settings = obj.radiometer_meter
    settings.is_meter, settings.kind, settings.acceptance_deg = True, kind, acceptance_deg
    return obj


@_v.boundary
def meter_objects(objects=None, *, scene=None):
    """The meter objects to measure: ``objects`` (each must be a meter) or every meter of ``scene``;
    none raises RadiometerError."""
    import bpy

    _b.scene(scene)
    return _meter_objects(scene or bpy.context.scene, objects)


@_v.boundary
def meter_steps(objects, *, scene=None, quality=None, batch=None, time_budget_s=None):
    """A measurement of meter ``objects`` cut into steps for a progress bar (illuminance meters in
    batches of ``batch``, None: one batch; then one step per other meter): a list of (label, weight,
    run) where ``run(progress=None, cancelled=None)`` measures the step and returns [(object,
    reading)] without storing anything (see :func:`store_reading`). Settings: the scene's, ``quality``
    overriding its preset; ``time_budget_s`` caps each step (s)."""
    import bpy

    _b.scene(scene)
    _v.quality(quality, allow_none=True)
    from .measure.meter import meter_objects as meters

    scene = scene or bpy.context.scene
    request, method = _settings_request(scene, quality, time_budget_s=time_budget_s)
    return meters.measurement_steps(request, _meters(scene, objects), method=method, batch=batch)


@_v.boundary
def store_reading(obj, reading):
    """Store ``reading`` on the meter object ``obj`` (its read-only reading properties)."""
    _store_reading(obj, reading)


@_v.boundary
def photometric_units(light_type):
    """The photometric units that apply to a Blender light type: a list of (unit, label), e.g.
    [("LUMEN", "lm"), ("CANDELA", "cd")] for "POINT"."""
    from .measure.authoring import light_power

    return [(unit, label) for unit, (types, label) in light_power.UNITS.items() if light_type in types]


@_v.boundary
def photometric_power(light, unit, *, scene=None):
    """The light's power in ``unit`` (see :func:`photometric_units`: lm, cd, lx or cd/m²) at the scene's
    luminous efficacy."""
    from .measure.authoring import light_power

    return light_power.photometric_power(light, unit, _request(scene))


@_v.boundary
def set_photometric_power(light, unit, value, *, scene=None):
    """Set the light's energy so that its power in ``unit`` is ``value``; returns the energy (W, a sun's
    strength in W/m²)."""
    from .measure.authoring import light_power

    return light_power.set_photometric_power(light, unit, value, _request(scene))


@_v.boundary
def photometric_table(light_data):
    """(table, reason): the photometric table of a light's IES node tree, or None and why not."""
    from .measure.capture import luminaires

    return luminaires.photometric_table(light_data)


@_v.boundary
def luminaire_summary(light):
    """The photometric summary of a photometric light (luminaire, lumens, max_candela, beam and field
    angles, symmetry, ...), cached while the file behind it is unchanged."""
    from .measure.capture import luminaires

    return luminaires.luminaire_summary(light)


@_v.boundary
def false_colour(t):
    """RGBA of the grids' colour map at ``t`` in [0, 1] (the isolux pictures' and the coloured plane's)."""
    from .measure.analyses import grid

    return grid.false_colour(t)


@_v.boundary
def colour_plane(result, *, scene=None, name=None):
    """A viewport-only coloured copy of a ``GridResult`` (colour attribute 'lux_colour'); returns it."""
    _b.scene(scene)
    from .measure.analyses import grid

    return grid.colour_plane(result, scene=scene, name=name)


@_v.boundary
def grid_lux_from_csv(path):
    """The (ny, nx) illuminance (lx) of a grid CSV written by ``GridResult.write_csv``."""
    from .measure.analyses import grid

    return grid.lux_from_csv(path)


@_v.boundary
def work_planes(scene=None):
    """The scene's work planes: meshes named "work plane" (any case) or marked ``radiometer_work_plane``."""
    import bpy

    _b.scene(scene)
    from .measure.analyses import grid

    return grid.work_planes(scene or bpy.context.scene)


@_v.boundary
def grid_points(target, *, scene=None, resolution=None, spacing=None):
    """The cell centres (N, 3) and normals (N, 3) of the grid :func:`illuminance_grid` lays out on
    ``target`` (EN 12464-1 spacing by default, at most 250 000 points)."""
    import numpy as np

    _b.scene(scene)
    from .measure.analyses import grid

    layout = grid.grid_layout(_request(scene), target, resolution=resolution, spacing=spacing)
    points = layout.points.reshape(-1, 3)
    return points, np.broadcast_to(layout.normal, points.shape)


@_v.boundary
def light_object(name, *, scene=None):
    """The light object named ``name`` in the scene (RadiometerError naming the lights when none)."""
    import bpy

    _b.scene(scene)
    from .measure.analyses import light_isolation

    return light_isolation.light_object(name, scene or bpy.context.scene)


@_v.boundary
def lights_to_check(scene=None):
    """The scene's lights that the law checks (and the report) check."""
    import bpy

    _b.scene(scene)
    from .measure.analyses import light_isolation

    return light_isolation.scene_lights_to_check(scene or bpy.context.scene)


@_v.boundary
def report_file_stem(name, among=()):
    """The report's file-name stem for an object ``name``: readable, unique ``among`` the names given."""
    from .measure.reports import report

    return report.plot_stem(name, among=among)


@_v.boundary
def report_fixed_files(client=True):
    """The report set's files whatever the scene holds (no Blender needed)."""
    from .measure.reports import report_files

    return report_files.fixed_files(client)


@_v.boundary
def iter_report(out_dir, **kwargs):
    """The report of :func:`export_report` as a generator of parts, for modal operators: the first
    ``next()`` yields the plan [(label, weight)], each further one measures a part, the last ends with
    the report dict (``StopIteration.value``). Keywords as ``measure.reports.report.iter_report``."""
    out_dir = _v.path(out_dir, "out_dir")
    scene = _b.scene(kwargs.pop("scene", None))
    from .measure.reports import report

    request = _request(scene, **{k: kwargs.pop(k, None) for k in ("quality", "target_rel_error", "time_budget_s",
                                                                   "progress", "cancelled")})
    return report.iter_report(out_dir, **_report_scene(scene), request=request, **kwargs)


def _report_scene(scene):
    """What a report takes from the scene's Radiometer properties: its meters and its settings."""
    import bpy

    scene = scene or bpy.context.scene
    return {"meters": _meters(scene, every=True), "settings": _scene_settings(scene)}


@_v.boundary
def report_summary_table(report_dict):
    """The text table of a report dict (or of the CLI's check result)."""
    from .measure.reports import report

    return report.summary_table(report_dict)


@_v.boundary
def save_copy(path, interrupt=None):
    """Save the open file as a copy at ``path``, whole or not at all; the session keeps its own file."""
    from .measure.blender import blend_file

    return blend_file.save_copy(path, interrupt)


@_v.boundary
def operator_report_filter(out, err=None, *, drop=("Info: ",), to_stderr=("Warning: ", "Error: "),
                           has_descriptor=True):
    """A text stream for ``sys.stdout`` that drops Blender's operator reports (lines starting with one of
    ``drop``) and sends those starting with one of ``to_stderr`` to ``err``; the API's own filter."""
    from .measure.blender import op_reports

    return op_reports.ReportFilter(out, err, drop=drop, to_stderr=to_stderr, has_descriptor=has_descriptor)


@_v.boundary
def keep_blender_reports(keep=True):
    """Let Blender's own operator reports through (the CLI's ``--verbose``) or drop them again."""
    from .measure.blender import op_reports

    op_reports.keep_reports = bool(keep)


@_v.boundary
def write_law_plot(result, path):
    """The PNG of a law check's result (an ``InverseSquareResult`` or a ``CosineResult``) at ``path``."""
    from .measure.analyses import law_checks

    if isinstance(result, law_checks.InverseSquareResult):
        return law_checks.write_inverse_square_plot(result, path)
    if isinstance(result, law_checks.CosineResult):
        return law_checks.write_cosine_plot(result, path)
    raise RadiometerError(f"result must be a law check's result, got {type(result).__name__}")

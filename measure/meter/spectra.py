"""Each emitter's spectrum (host side) and the spectral reading of the direct part at a meter.

Which spectrum an emitter has, first match wins:

1. the custom property ``radiometer_spectrum`` (:data:`PROP_SPECTRUM`) on the light object or its light
   data: a CIE illuminant ("A", "D65", "FL2", "LED-B3"), daylight at a CCT ("D5000"), a blackbody
   ("blackbody:3000") or a spectral file (nm, relative power; ``//`` paths are relative to the .blend);
2. a light with ``use_temperature`` and a white colour: a blackbody at ``temperature`` (Cycles renders
   ``color x temperature_color``, so a tinted one has no known spectrum); a sun lamp: CIE daylight at
   that CCT when 4000-25000 K (CIE 015's model of daylight phases), else the blackbody;
3. the world: the custom property on the World, else D65 (CIE S 026's reference daylight);
4. anything else: unknown, and the reading says so.

The reading (:func:`spectral_reading`) covers the **direct** light of the scene's lights, from the
meter's closed forms (``meter.predict_illuminance``): per light mel-EDI = E_v x mel-DER of its spectrum,
and so for every alpha-opic quantity. Light reflected by surfaces is added by ``spectral_reflected``
(band renders), which also reads the world's light where it is rendered and emitting surfaces' (docs/spectral.md).
"""

import bpy
import numpy as np

from ...errors import RadiometerError
from ...radiometry.photometry import action_spectra, spectral

#: Custom property holding an emitter's spectrum setting (see the module docstring).
PROP_SPECTRUM = "radiometer_spectrum"

UNITS = {"illuminance_lx": "lx", "illuminance_known_spectrum_lx": "lx", "alpha_opic_edi_lx": "lx", "mel_edi_lx": "lx",
         "mel_der": "1",
         "alpha_opic_irradiance_w_m2": "W/m²", "sp_ratio": "1", "alpha_opic_der": "1"}


def _setting(*holders):
    for holder in holders:
        if holder is not None and PROP_SPECTRUM in holder.keys():
            value = holder[PROP_SPECTRUM]
            return value if isinstance(value, str) else repr(value)
    return None


def _from_setting(value, where):
    base = bpy.path.abspath("//") if bpy.data.filepath else None
    path = bpy.path.abspath(value) if value.startswith("//") else value
    try:
        return spectral.spectrum_from_spec(path, base_dir=base)
    except RadiometerError as exc:
        raise RadiometerError(f"{where}: {PROP_SPECTRUM} {value!r}: {exc}") from None


def light_spectrum(obj):
    """(label, spectrum on ``spectral.WAVELENGTHS_NM``) of a light object, or (None, why not)."""
    data = obj.data
    value = _setting(obj, data)
    if value is not None:
        return _from_setting(value, f"light {obj.name!r}")
    if getattr(data, "use_temperature", False):
        t = float(data.temperature)
        if tuple(round(float(c), 6) for c in data.color) != (1.0, 1.0, 1.0):
            return None, (f"its colour {tuple(round(float(c), 3) for c in data.color)} tints the {t:g} K blackbody "
                          f"(set {PROP_SPECTRUM})")
        if data.type == "SUN" and spectral.DAYLIGHT_CCT_RANGE_K[0] <= t <= spectral.DAYLIGHT_CCT_RANGE_K[1]:
            return f"CIE daylight {t:g} K (sun)", spectral.cie_daylight(t)
        return f"blackbody {t:g} K", spectral.planck(t)
    return None, f"an RGB colour only (use the light's temperature or set {PROP_SPECTRUM})"


def material_spectrum_setting(mat):
    """(label, spectrum) of an emitting material's ``radiometer_spectrum``, or None where it has none."""
    value = _setting(mat)
    return None if value is None else _from_setting(value, f"material {mat.name!r}")


def world_spectrum(scene):
    """(label, spectrum) of the scene's world: its ``radiometer_spectrum`` setting, else CIE D65."""
    value = _setting(scene.world)
    if value is not None:
        return _from_setting(value, f"world {scene.world.name!r}")
    return "CIE D65 (default sky, not stated)", spectral.cie_illuminant("D65")


def _light_row(row, spectra):
    out = {"light": row["light"], "source": row.get("source"), "illuminance_lx": row["illuminance"],
           "exact": bool(row.get("exact")), "rel_error_bound": row.get("rel_error_bound", 0.0)}
    if row["illuminance"] is None:
        out.update(spectrum=None, note=row.get("note"))
        return out
    label, spd = spectra[row.get("source")]
    if label is None:  # (None, why not)
        out.update(spectrum=None, note=f"no known spectrum: {spd}")
        return out
    out["spectrum"] = label
    ev = float(row["illuminance"])
    der = action_spectra.alpha_opic_der(spd)
    out.update(alpha_opic_der=dict(zip(action_spectra.ALPHA, map(float, der))),
               alpha_opic_edi_lx=dict(zip(action_spectra.ALPHA, map(float, ev * der))),
               alpha_opic_irradiance_w_m2=dict(zip(action_spectra.ALPHA,
                                                   map(float, action_spectra.alpha_opic_irradiance(spd, ev)))),
               mel_der=float(der[4]), mel_edi_lx=float(ev * der[4]), sp_ratio=float(action_spectra.sp_ratio(spd)))
    return out


def spectral_reading(location, normal=(0.0, 0.0, 1.0), *, request, with_world=True):
    """The alpha-opic (CIE S 026) reading of the direct light at one meter, SI units (a plain dict).

    Keys: ``part`` ("direct"), ``illuminance_lx`` (E_v of the lights in closed form), ``illuminance_known_spectrum_lx``
    (of those with a known spectrum: ``mel_der`` is mel-EDI over it), ``mel_edi_lx``, ``mel_der``,
    ``alpha_opic_edi_lx`` and ``alpha_opic_irradiance_w_m2`` (dicts over S/M/L cone, rhodopic, melanopic),
    ``sp_ratio``, ``exact`` (every light's direct part a proven closed form and its spectrum known),
    ``complete`` (every light's spectrum known; else the sums are lower bounds of the lights that have
    one), ``lights`` (per light), ``not_included`` (what this reading leaves out), ``units``.
    ``with_world`` False leaves the world's direct light out even where it is proven (the band renders of
    ``spectral_reflected`` then read all of the world's light).
    (``spectral_reflected.spectral_reading`` adds the reflected part.) The request
    (``measure.blender.request``): the scene and its photometry.
    """
    from . import point_meter as meter

    scene = request.scene
    rows = meter.predict_illuminance(location, normal, request, with_world=True)
    world = rows.pop(0)
    spectra = {}
    if world is not None and world["illuminance"] is not None and with_world:
        rows.append(world)
        spectra[None] = world_spectrum(scene)   # the world's row has no source object
    for row in rows:
        source = row.get("source")
        if source not in spectra:
            obj = bpy.data.objects.get(source) if source else None
            spectra[source] = light_spectrum(obj) if obj is not None and obj.type == "LIGHT" else \
                (None, "not a light object")
    lights = [_light_row(row, spectra) for row in rows]
    known = [r for r in lights if r.get("mel_der") is not None]
    missing = [r for r in lights
               if r.get("mel_der") is None and (r["illuminance_lx"] is None or r["illuminance_lx"] > 0)]
    ev_known = sum(r["illuminance_lx"] for r in known)
    edi = {a: sum(r["alpha_opic_edi_lx"][a] for r in known) for a in action_spectra.ALPHA}
    irr = {a: sum(r["alpha_opic_irradiance_w_m2"][a] for r in known) for a in action_spectra.ALPHA}
    # scotopic lumens add: S/P of the sum is the photopic-weighted mean of the lights' S/P
    sp = sum(r["sp_ratio"] * r["illuminance_lx"] for r in known) / ev_known if ev_known > 0 else None
    not_included = ["light reflected by surfaces (the rendered part)"]
    model = meter.capture_model(scene, request.view_layer)
    if np.any(np.asarray(model.geometry.emissive, bool)):
        not_included.append("emitting surfaces")
    if world is not None and (world["illuminance"] is None or not with_world):
        label, _ = world_spectrum(scene)
        why = world["note"] if world["illuminance"] is None else "left out of the direct part"
        not_included.append(f"the world ({why}; its spectrum: {label})")
    notes = []
    if missing:
        notes.append("lower bound: no spectrum or no closed form for " + "; ".join(
            f"{r['light']} ({r.get('note')})" for r in missing))
    mel_der = edi["melanopic"] / ev_known if ev_known > 0 else None
    out = {
        "quantity": "alpha-opic (CIE S 026/E:2018)", "part": "direct",
        "location": tuple(map(float, location)), "normal": tuple(map(float, normal)),
        "illuminance_lx": float(sum(r["illuminance_lx"] for r in lights if r["illuminance_lx"] is not None)),
        "illuminance_known_spectrum_lx": float(ev_known), "mel_edi_lx": edi["melanopic"],
        "mel_der": mel_der, "rel_error_bound": max((r["rel_error_bound"] or 0.0 for r in known), default=0.0),
        "alpha_opic_edi_lx": edi, "alpha_opic_irradiance_w_m2": irr, "sp_ratio": sp,
        "exact": bool(known) and not missing and all(r["exact"] for r in known),
        "complete": not missing, "lights": lights, "not_included": not_included, "notes": notes,
        "units": UNITS,
    }
    return out

"""`measure`: measure every light meter in a .blend and print the readings (SI units)."""

HELP = "measure every light meter in the scene (lux, cd/m²) and print the readings"
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=None,
                        help="quality preset: its target error wins over a target stored in the .blend "
                             "(default: the scene's setting)")
    parser.add_argument("--method", choices=("auto", "analytic", "hybrid", "render"), default=None,
                        help="measurement method (default: the scene's setting)")
    parser.add_argument("--target", type=float, default=None, metavar="FRACTION",
                        help="relative standard error (1 sigma) every reading must reach, e.g. 0.01 "
                             "(default: the quality preset's target: preview 0.05, standard 0.01, reference 0.002)")
    parser.add_argument("--quantity", choices=("photopic", "melanopic"), default="photopic",
                        help="photopic: lux and cd/m² only; melanopic: also the CIE S 026 reading of each "
                             "illuminance meter's direct light (mel-EDI lx, mel-DER, alpha-opic W/m², S/P) from "
                             "each light's spectrum (docs/spectral.md) (default: photopic)")
    parser.add_argument("--reflected", action="store_true",
                        help="with --quantity melanopic: add the light reflected by the room's surfaces, by band renders "
                             "with a stated 95 %% interval (materials' spectra: their radiometer_reflectance property; "
                             "docs/spectral.md)")
    parser.add_argument("--target-abs", type=float, default=None, metavar="LX",
                        help="absolute floor of an illuminance meter's error (1 sigma, lux): a meter stops where its "
                             "error is below it or below --target (default: the quality preset's: preview 2, "
                             "standard 0.5, reference 0.1; 0: none)")


def format_value(value, digits=6):
    """A reading with ``digits`` significant digits; "n/a" for a missing or non-finite one."""
    import math

    if value is None or not math.isfinite(value):
        return "n/a"
    return f"{value:.{digits}g}"


def format_table(results):
    """One line per meter: the reading with the digits its error supports ("402 lx ±1.1 %", as the
    sidebar shows it), the target, the method, then EV100 and the light's CCT/Duv."""
    from ..readings import format_error, photographic_summary
    from ..readings import format_value as supported

    lines = [f"{'meter':<22} {'reading':>10} {'unit':<6} {'± 1 s.e.':>9} {'target':>7}  method    photographic"]
    for obj, r in results:
        if r.quantity == "luminance":
            value, unit = r.luminance, "cd/m²"
        else:
            value, unit = r.illuminance, "lx"
        se = r.rel_std_error
        err = format_error(se if se is not None else float("nan"), r.exact)
        upper = getattr(r, "upper_bound_lux", None)
        if upper is not None:  # issue 31: no light found after the pilot: a one-sided bound, never ±inf
            err = f"≤ {upper:.2g} lx"
        target = getattr(r, "target_rel_error", None)
        asked = f"{100 * target:g} %" if target else "-"
        reading = supported(value, se if se is not None else 0.0, r.exact)
        lines.append(f"{obj.name:<22} {reading:>10} {unit:<6} {err:>9} {asked:>7}  {r.method:<9} "
                     f"{photographic_summary(r)}".rstrip())
    return "\n".join(lines)


def format_spectral(rows):
    """One line per illuminance meter: the direct part's E_v (all lights in closed form, and those of known
    spectrum), mel-EDI, mel-DER and S/P, and whether exact ("lower bound": a light without a spectrum)."""
    from ..readings import format_value as supported

    lines = ["spectral (CIE S 026), direct light only:",
             f"{'meter':<22} {'E_v direct':>11} {'of known':>11} {'mel-EDI':>10} {'mel-DER':>8} {'S/P':>6}  status"]
    for name, sr in rows:
        if sr is None:
            lines.append(f"{name:<22} {'n/a':>11} {'n/a':>11} {'n/a':>10} {'n/a':>8} {'n/a':>6}  "
                         "luminance meter: mesopic luminance with --reflected")
            continue
        status = "exact" if sr["exact"] else ("lower bound" if not sr["complete"] else "bounded")
        mel_der = "n/a" if sr["mel_der"] is None else f"{sr['mel_der']:.4f}"
        sp = "n/a" if sr["sp_ratio"] is None else f"{sr['sp_ratio']:.3f}"
        lines.append(f"{name:<22} {supported(sr['illuminance_lx'], 0.0, True) + ' lx':>11} "
                     f"{supported(sr['illuminance_known_spectrum_lx'], 0.0, True) + ' lx':>11} "
                     f"{supported(sr['mel_edi_lx'], 0.0, True) + ' lx':>10} {mel_der:>8} {sp:>6}  {status}")
    return "\n".join(lines)


def _mesopic_line(sr):
    """A luminance meter's line in the --reflected table: CIE 191 mesopic luminance, or why not."""
    if sr is None or sr.get("not_measured"):
        return "luminance meter: no mesopic reading" + (f" ({sr['not_measured']})" if sr else "")
    lp, mes = sr["photopic_cd_m2"], sr["mesopic_cd_m2"]
    if mes is None:
        return "luminance meter: no light in its cone"
    return (f"luminance meter: L_p {lp['estimate']:.4g} cd/m² ({lp['low_95']:.4g}-{lp['high_95']:.4g}), S/P "
            f"{sr['sp_ratio']:.3f}, mesopic (CIE 191) {mes['estimate']:.4g} cd/m² ({mes['low_95']:.4g}-"
            f"{mes['high_95']:.4g}), {sr['regime']}")


def format_spectral_total(rows):
    """One line per illuminance meter: E_v and mel-EDI of direct + reflected light with their 95 % intervals
    (band renders), or why the reflected part was not added."""
    lines = ["spectral (CIE S 026), direct + reflected light (band renders; 95 % intervals):",
             f"{'meter':<22} {'E_v':>10} {'95 % interval':>21} {'mel-EDI':>10} {'95 % interval':>21}  direct mel-EDI"]
    for name, sr in rows:
        if sr is None or "mesopic_cd_m2" in sr:
            lines.append(f"{name:<22} " + _mesopic_line(sr))
            continue
        if "interval_95" not in sr:
            why = next((n for n in sr["notes"] if n.startswith("reflected part not added")), "direct only")
            lines.append(f"{name:<22} direct only: E_v {sr['illuminance_lx']:.4g} lx, mel-EDI {sr['mel_edi_lx']:.4g} lx; "
                         f"{why}")
            continue
        ev, mel = sr["interval_95"]["illuminance_lx"], sr["interval_95"]["mel_edi_lx"]
        direct = f"{sr['direct']['mel_edi_lx']:.4g} lx" + (" (exact)" if sr["direct"]["exact"] else "")
        lines.append(f"{name:<22} {ev['estimate']:>7.4g} lx {ev['low_95']:>8.4g}-{ev['high_95']:<8.4g} lx "
                     f"{mel['estimate']:>7.4g} lx {mel['low_95']:>8.4g}-{mel['high_95']:<8.4g} lx  {direct}")
    return "\n".join(lines)


def spectral_rows(results, scene, reflected=False, quality="preview"):
    """(meter name, ``api.spectral_reading`` dict) for every illuminance meter; a luminance meter's is
    ``api.mesopic_reading``'s with ``reflected`` (its cone is all rendered light), else None."""
    from .. import api
    from ..errors import RadiometerError

    def luminance(r):
        if not reflected:
            return None
        try:
            return api.mesopic_reading(r.location, r.direction, acceptance_deg=r.acceptance_deg, scene=scene,
                                       quality=quality)
        except RadiometerError as exc:
            return {"mesopic_cd_m2": None, "not_measured": str(exc)}

    return [(obj.name, luminance(r) if r.quantity == "luminance" else
             api.spectral_reading(r.location, r.normal, scene=scene, reflected=reflected, quality=quality))
            for obj, r in results]


def used_settings(args, stored):
    """The settings this run uses and where each comes from: the command line wins over the .blend.

    ``stored``: the scene's (method, quality, target_rel_error) with target 0 meaning "the quality
    preset's". A ``--quality`` given without ``--target`` measures to that preset's target even when
    the .blend stores a target of its own (asked for reference quality: reference quality).
    Returns {"method", "quality", "target_rel_error", "source": {name: "command line" | ".blend"}}.
    """
    from ..quality import preset

    method, quality, target = stored
    given = {k: getattr(args, k, None) for k in ("method", "quality", "target")}  # `demo` has no --method
    src = {"method": ".blend", "quality": ".blend", "target_rel_error": ".blend"}
    if given["method"]:
        method, src["method"] = given["method"], "command line"
    if given["quality"]:
        quality, src["quality"] = given["quality"], "command line"
    if given["target"] is not None:
        target, src["target_rel_error"] = given["target"], "command line"
    elif given["quality"] or not target:
        target, src["target_rel_error"] = preset(quality)["target"], f"quality {quality}"
    return {"method": method, "quality": quality, "target_rel_error": float(target), "source": src}


def format_settings(used):
    src = used["source"]
    return (f"settings: method {used['method']} ({src['method']}), quality {used['quality']} ({src['quality']}), "
            f"target {100 * used['target_rel_error']:g} % 1-sigma ({src['target_rel_error']})")


def run(args):
    import bpy

    from .. import api

    scene = bpy.context.scene
    if getattr(args, "reflected", False) and getattr(args, "quantity", "photopic") != "melanopic":
        from ..errors import RadiometerError

        raise RadiometerError("--reflected needs --quantity melanopic")
    if args.target is not None:
        from ..errors import RadiometerError

        if not 0 < args.target < 0.5:
            raise RadiometerError(f"--target must be a fraction in (0, 0.5), got {args.target}")
    target_abs = getattr(args, "target_abs", None)
    if target_abs is not None and not (0 <= target_abs < float("inf")):
        from ..errors import RadiometerError

        raise RadiometerError(f"--target-abs must be a finite number of lux >= 0, got {target_abs}")
    s = scene.radiometer
    used = used_settings(args, (s.method, s.quality, s.target_rel_error))
    progress = getattr(args, "progress", None)
    if progress is not None:
        progress.label = "measuring"
    # For this run only: the scene's own settings are put back (`blender -c` may run in a user's session).
    before = (s.method, s.quality, s.target_rel_error)
    s.method, s.quality, s.target_rel_error = used["method"], used["quality"], used["target_rel_error"]
    try:
        results = api.measure_meters(scene=scene, quality=used["quality"], progress=progress,
                                        cancelled=getattr(args, "cancelled", None), target_abs_error=target_abs)
    finally:
        s.method, s.quality, s.target_rel_error = before
    if progress is not None:
        progress.clear()
    spectral = spectral_rows(results, scene, reflected=bool(getattr(args, "reflected", False)),
                             quality=used["quality"]) if getattr(args, "quantity", "photopic") == "melanopic" else None
    print(format_settings(used))
    print(format_table(results))
    meters_out = [dict(name=obj.name, **r.to_dict()) for obj, r in results]
    if spectral is not None:
        print(format_spectral_total(spectral) if getattr(args, "reflected", False) else format_spectral(spectral))
        for d, (_, sr) in zip(meters_out, spectral):
            d["spectral"] = sr
    return {"scene": scene.name, "file": bpy.data.filepath, "settings": used, "meters": meters_out}

"""The rendered (reflected) part of a spectral reading, by band renders (host side; issue 35).

Cycles renders RGB. Here its three channels carry three spectral samples instead
(``radiometry.photometry.spectral_bands``: the bands, the proven band bound, the conversion): for every
render, each material's colour holds its reflectance at the low or high end of a band and each light's
colour its radiant power in that band; the meter's hybrid reading (closed forms for the proven direct
light, Cycles for the rest) then reads, per channel, that band's rendered light. Every colour and light
setting is put back after each render, also on error.

Materials need a reflectance spectrum: the custom property ``radiometer_reflectance`` on the material
(a spectral file, nm and reflectance in [0, 1], or one number for a flat spectrum), else its RGB colour
upsampled by Mallett & Yuksel's sRGB basis (EGSR 2019, ``spectral_bands.mallett_reflectance``; the stated box
rule where the working space is not linear Rec.709; the reading says which materials).
Supported: Diffuse BSDF and Principled BSDF with an unlinked colour, objects without material (Cycles'
grey 0.8), and neutral Glass, Transparent, Refraction, Translucent and Glossy BSDFs (an unlinked grey
colour: the same factor at every wavelength, so nothing to sweep). The world's light (the sky through a
window) is read in the same renders: a stand-in copy of the world emits its luminance (Cycles' RGB to BW
of its colour) times the world spectrum's band power per channel (:func:`_world_stand_in`); the user's
world is put back and the copy removed. Anything else (textures, other shaders, emitting surfaces, a
world volume) is refused with the reason: the reading then has no spectral reflected part.
"""

import math
import os

import bpy
import numpy as np

from ...compat import active_node_tree
from ...errors import MeasurementCancelled, RadiometerError
from ...radiometry.photometry import action_spectra, spectral, spectral_bands
from . import spectra

#: Custom property holding a material's reflectance spectrum (a spectral file or one number).
PROP_REFLECTANCE = "radiometer_reflectance"

#: Per quality: (samples per meter of each band render, at most this many bands). Fixed samples: every
#: channel gets them, not only the Y-weighted sum a relative target watches. Measured in issue 35's red room
#: (bench/spectral_room.md): a render of one meter takes ~0.1 s at 4096 samples.
BAND_PLAN = {"preview": (4096, 32), "standard": (16384, 64), "reference": (65536, 128)}

_COLOUR_INPUT = {"BSDF_DIFFUSE": "Color", "BSDF_PRINCIPLED": "Base Color"}
_PASSIVE = {"OUTPUT_MATERIAL", "MIX_SHADER", "ADD_SHADER", "REROUTE", "FRAME"}
#: BSDFs that scale light by their colour alone: with a plain grey colour they act alike at every
#: wavelength (Cycles' Fresnel does not depend on it), so a path's product stays monotone in the swept
#: reflectances and the band range still holds. Window glass is the usual one.
_NEUTRAL = {"BSDF_GLASS", "BSDF_TRANSPARENT", "BSDF_REFRACTION", "BSDF_TRANSLUCENT", "BSDF_GLOSSY",
            "BSDF_ANISOTROPIC"}
#: World nodes whose Color input is emitted light.
_WORLD_EMITTERS = {"BACKGROUND", "EMISSION"}


def _grey(sock):
    return len({round(float(c), 6) for c in tuple(sock.default_value)[:3]}) == 1


def _emission_off(node):
    strength = node.inputs.get("Emission Strength")
    return strength is not None and not strength.is_linked and float(strength.default_value) == 0.0


def _material_sockets(mat, emitters=None):
    """The colour sockets that carry ``mat``'s reflectance, or raise naming what is not supported. With a list
    ``emitters``, the colour sockets of its emitted light (an Emission shader, a Principled BSDF's emission)
    are appended to it instead of refused."""
    if mat is None:
        return []
    tree = active_node_tree(mat)
    if tree is None:  # Blender 4.x with nodes off: Cycles renders its viewport colour, which no band sweeps
        raise RadiometerError(f"material {mat.name!r} renders without nodes (its viewport colour): turn its "
                              "nodes on")
    sockets = []
    emits = False

    def emitted(sock):
        if emitters is None:
            raise RadiometerError(f"material {mat.name!r} emits light (its band render is not built)")
        if sock.is_linked:
            raise RadiometerError(f"material {mat.name!r}: its emitted colour is linked (a texture or a "
                                  "blackbody node): set a plain colour and its radiometer_spectrum")
        emitters.append(sock)

    for node in tree.nodes:
        if node.type == "EMISSION":
            emitted(node.inputs["Color"])
            emits = True
            continue
        if node.type in _COLOUR_INPUT:
            sock = node.inputs[_COLOUR_INPUT[node.type]]
            if sock.is_linked:
                raise RadiometerError(f"material {mat.name!r}: its {node.name!r} colour is linked (a texture)")
            sockets.append(sock)
            for other in node.inputs:  # other colours (Principled tints, emission) would act as RGB in every band
                if other.type != "RGBA" or other.identifier == sock.identifier or not other.enabled:
                    continue
                if other.name == "Emission Color" and not _emission_off(node):
                    emitted(other)
                    emits = True
                    continue
                if other.name != "Emission Color" and (other.is_linked or not _grey(other)):
                    raise RadiometerError(f"material {mat.name!r}: its {node.name!r} {other.name} is not a plain "
                                          "grey (a tint acts as RGB in every band)")
        elif node.type in _NEUTRAL:
            colour = node.inputs.get("Color")
            if colour is not None and (colour.is_linked or not _grey(colour)):
                raise RadiometerError(f"material {mat.name!r}: its {node.name!r} colour is not a plain grey (a "
                                      "tinted glass or metal would act as the same RGB in every band)")
        elif node.type not in _PASSIVE:
            raise RadiometerError(f"material {mat.name!r}: node {node.name!r} ({node.type}) is not a plain "
                                  "diffuse, Principled or neutral colour")
    if not sockets and not emits and not any(node.type in _NEUTRAL for node in tree.nodes):
        raise RadiometerError(f"material {mat.name!r} has no Diffuse or Principled BSDF")
    return sockets


def material_reflectance(mat, sockets, space="Linear Rec.709"):
    """(label, reflectance on the 1 nm grid) of a material: its ``radiometer_reflectance``, else its colour
    upsampled (label says so): Mallett & Yuksel's sRGB basis in a linear Rec.709 working ``space``
    (``spectral_bands.mallett_reflectance``), the stated box rule in any other."""
    if mat is None:
        return "no material (Cycles' grey 0.8)", np.full(spectral.WAVELENGTHS_NM.shape, 0.8)
    if PROP_REFLECTANCE in mat.keys():
        value = mat[PROP_REFLECTANCE]
        if isinstance(value, (int, float)):
            if not 0.0 <= float(value) <= 1.0:
                raise RadiometerError(f"material {mat.name!r}: {PROP_REFLECTANCE} {value!r} is not in [0, 1]")
            return f"flat {float(value):g}", np.full(spectral.WAVELENGTHS_NM.shape, float(value))
        base = bpy.path.abspath("//") if bpy.data.filepath else None
        path = bpy.path.abspath(value) if str(value).startswith("//") else str(value)
        path = path if os.path.isabs(path) or base is None else os.path.join(base, path)
        try:
            wl, refl = spectral.read_spectrum_csv(path)
        except RadiometerError as exc:
            raise RadiometerError(f"material {mat.name!r}: {PROP_REFLECTANCE}: {exc}") from None
        if np.max(refl) > 1.0:
            raise RadiometerError(f"material {mat.name!r}: {PROP_REFLECTANCE} {path}: a reflectance must be <= 1, "
                                  f"got {np.max(refl):g}")
        return f"file {os.path.basename(path)}", spectral.resample(wl, refl)
    if not sockets:  # neutral BSDFs only (glass), or an emitter: nothing varies with wavelength, nothing to sweep
        return "neutral (grey glass, transparent or glossy, or an emitter)", np.ones(spectral.WAVELENGTHS_NM.shape)
    colours = {tuple(round(float(c), 6) for c in tuple(sock.default_value)[:3]) for sock in sockets}
    if len(colours) > 1:
        raise RadiometerError(f"material {mat.name!r} mixes BSDFs of different colours: give it its "
                              f"{PROP_REFLECTANCE} (a spectral file)")
    rgb = tuple(sockets[0].default_value)[:3]
    if space == "Linear Rec.709":
        return (f"RGB {tuple(round(c, 3) for c in rgb)} upsampled (Mallett & Yuksel 2019 sRGB basis, stated)",
                spectral_bands.mallett_reflectance(rgb))
    return (f"RGB {tuple(round(c, 3) for c in rgb)} upsampled (box rule, stated: the working space {space} is not "
            "the sRGB basis's)", spectral_bands.box_reflectance(rgb))


def _scene_materials(scene, emitters=None):
    """{material or None: sockets} of every rendered mesh object; ``emitters``: a dict that receives
    {material: [its emitted-colour sockets]} of the materials that emit (else they are refused)."""
    found = {}
    for obj in scene.objects:
        if obj.type not in ("MESH", "CURVE", "SURFACE", "META", "FONT") or obj.hide_render:
            continue
        slots = [s.material for s in obj.material_slots] or [None]
        for mat in slots:
            if mat not in found:
                emitted = [] if emitters is not None else None
                found[mat] = _material_sockets(mat, emitted)
                if emitted:
                    emitters[mat] = emitted
    return found


def _light_colour(data):
    c = np.array(tuple(data.color)[:3], float)
    if getattr(data, "use_temperature", False):
        c = c * np.array(tuple(data.temperature_color)[:3], float)
    return c


def _has_emitter(tree, seen=()):
    """True when a node group inside ``tree`` holds a Background or Emission node."""
    for node in tree.nodes:
        if node.type in _WORLD_EMITTERS:
            return True
        if node.type == "GROUP" and node.node_tree is not None and node.node_tree not in seen:
            if _has_emitter(node.node_tree, (*seen, node.node_tree)):
                return True
    return False


def _world_stand_in(world, weights):
    """(copy of ``world``, set(m)): the copy emits, at every direction, the luminance of the world's colour
    there (Y with the scene's ``weights``; Cycles' RGB to BW where the colour is linked, e.g. a sky texture
    or an image) times the RGB multiplier ``m`` that ``set`` writes. Band renders set m to the world
    spectrum's band powers per unit luminance. The caller assigns the copy and removes it afterwards; the
    user's world is never edited. Raises ``RadiometerError`` for what this cannot scale."""
    if active_node_tree(world) is None:  # rendered from its plain colour
        y = float(np.asarray(tuple(world.color)[:3], float) @ weights)
        copy = world.copy()

        def set_plain(m):
            copy.color = tuple(y * float(c) for c in m)
        return copy, set_plain
    for node in world.node_tree.nodes:
        if node.type == "GROUP" and node.node_tree is not None and _has_emitter(node.node_tree):
            raise RadiometerError(f"world {world.name!r}: node group {node.name!r} holds a Background or Emission "
                                  "(its band render is not built)")
    copy = world.copy()
    tree = copy.node_tree
    setters = []
    for node in list(tree.nodes):
        if node.type not in _WORLD_EMITTERS:
            continue
        sock = node.inputs["Color"]
        if not sock.is_linked:
            y = float(np.asarray(tuple(sock.default_value)[:3], float) @ weights)
            setters.append(lambda m, sock=sock, y=y: setattr(sock, "default_value", (*(y * float(c) for c in m), 1.0)))
            continue
        source = sock.links[0].from_socket
        grey = tree.nodes.new("ShaderNodeRGBToBW")
        mix = tree.nodes.new("ShaderNodeMix")
        mix.data_type, mix.blend_type, mix.clamp_result = "RGBA", "MULTIPLY", False
        mix.inputs["Factor"].default_value = 1.0
        a = next(i for i in mix.inputs if i.identifier == "A_Color")
        b = next(i for i in mix.inputs if i.identifier == "B_Color")
        tree.links.new(source, grey.inputs["Color"])
        tree.links.new(grey.outputs["Val"], a)
        tree.links.new(next(o for o in mix.outputs if o.identifier == "Result_Color"), sock)
        setters.append(lambda m, b=b: setattr(b, "default_value", (*(float(c) for c in m), 1.0)))

    def set_nodes(m):
        for f in setters:
            f(m)
    return copy, set_nodes


def _per_unit_luminance(spd):
    """A source's spectrum scaled to sum p V = 1: its power per unit of Y-weighted radiance (the world, an
    emitting surface), so a band's power is its share of that luminance."""
    return spd / float(spd @ action_spectra.PHOTOPIC_V)


def _channels(power, edges, render):
    """The three channel values of one band render for a source of 1 nm ``power``: its power in each band the
    render's channels carry (unused channels 0)."""
    band = spectral_bands.band_sums(power, edges)
    return [band[b] for b, _end in render] + [0.0] * (3 - len(render))


def _restore(saved):
    for struct, attr, value in reversed(saved):
        current = getattr(struct, attr)
        if (tuple(current) if hasattr(current, "__len__") else current) != value:
            setattr(struct, attr, value)


def _remember(saved, struct, attr):
    value = getattr(struct, attr)
    saved.append((struct, attr, tuple(value) if hasattr(value, "__len__") else value))


def _preview(request):
    """The request with its quality, "preview" where none was given (the band renders' default)."""
    return request.but(quality=request.quality or "preview")


def reflected_reading(location, normal, *, request, samples=None, max_bands=None):
    """The rendered part of the light at one meter, in bands: :func:`reflected_readings` of one meter."""
    return reflected_readings([location], [normal], request=request, samples=samples, max_bands=max_bands)[0]


def _band_plan(request, samples=None, max_bands=None):
    """Everything the band renders need, read from the request's scene (nothing changed): the sources' band
    powers, the materials' reflectance table, the bands and the render layout (by the request's quality). A
    dict; raises ``RadiometerError`` for what the band renders cannot read."""
    from . import point_meter as meter

    scene, quality = request.scene, request.quality or "preview"
    model = meter.capture_model(scene, request.view_layer)
    world = scene.world if model.world_emits else None
    if world is not None and model.world_volume:
        raise RadiometerError("the world has a volume (its spectral band render is not built)")
    lights = [obj for obj in scene.objects if obj.type == "LIGHT" and not obj.hide_render]
    space, weights, efficacy = request.photometry
    power = []
    for obj in lights:
        if getattr(obj.data, "use_nodes", False):
            raise RadiometerError(f"light {obj.name!r} uses a node tree (its colour is not the light's spectrum)")
        label, spd = spectra.light_spectrum(obj)
        if label is None:
            raise RadiometerError(f"light {obj.name!r} has no known spectrum: {spd}")
        y = float(_light_colour(obj.data) @ weights)
        # radiant power per 1 nm sample, per watt of the light, scaled so that sum P V = Y(colour): the
        # photometric amount Cycles' RGB light carries (E_v = efficacy x Y-weighted irradiance)
        power.append(float(obj.data.energy) * spd * y / float(spd @ action_spectra.PHOTOPIC_V))
    world_label = world_power = None
    if world is not None:
        world_label, world_spd = spectra.world_spectrum(scene)
        world_power = _per_unit_luminance(world_spd)
        power.append(world_power)
    emitting = {}
    materials = _scene_materials(scene, emitting)
    if model.emissive_surfaces and not emitting:
        raise RadiometerError("surfaces emit light from no material's Emission (e.g. a volume or a point cloud): "
                              "their band render is not built")
    surfaces = []  # (emitted-colour sockets, luminance of each, power per unit luminance, label)
    for mat, socks in emitting.items():
        value = spectra.material_spectrum_setting(mat)
        if value is None:
            raise RadiometerError(f"material {mat.name!r} emits light with no known spectrum (set its "
                                  f"{spectra.PROP_SPECTRUM})")
        label, spd = value
        lum = [float(np.asarray(tuple(s.default_value)[:3], float) @ weights) for s in socks]
        surfaces.append((socks, lum, _per_unit_luminance(spd), f"{mat.name}: {label}"))
        power.append(surfaces[-1][2])
    labels, refl = {}, []
    for mat, sockets in materials.items():
        label, r = material_reflectance(mat, sockets, space)
        labels[mat.name if mat is not None else "(none)"] = label
        refl.append(r)
    refl = np.array(refl)
    n_samples, n_bands = BAND_PLAN[quality]
    n_samples, n_bands = samples or n_samples, max_bands or n_bands
    edges = spectral_bands.plan_bands(refl, n_bands)
    rmin, rmax, t_all = spectral_bands.band_table(refl, edges)
    varying = np.ptp(refl, axis=1) > 1e-9  # a flat spectrum (a grey) sweeps nothing
    upsampled = [name for (name, label), v in zip(labels.items(), varying) if v and "upsampled" in label]
    return {"upsampled": upsampled, "surfaces": surfaces, "world": world, "world_label": world_label,
            "world_power": world_power, "lights": lights, "power": np.array(power), "materials": materials, "labels": labels, "edges": edges, "rmin": rmin,
            "rmax": rmax, "t": t_all[varying].mean(axis=0) if varying.any() else np.full(refl.shape[1], 0.5),
            "layout": spectral_bands.channel_layout(len(edges) - 1), "samples": int(n_samples),
            "weights": weights, "efficacy": efficacy}


def _peak_render(plan):
    """The band render whose channels hold the band at 555 nm (V's peak): the source-alone renders use it."""
    band = int(np.searchsorted(plan["edges"], 555 - int(spectral.WAVELENGTHS_NM[0]), side="right")) - 1
    return next(k for k, render in enumerate(plan["layout"]) if any(b == band for b, _end in render))


def _run_band_renders(request, plan, read, n_points):
    """Set every render's colours (materials at a band end, sources at the band's power), call ``read(k)`` ->
    per meter (rgb, se_rgb, bound_rgb) of the rendered band light, and put every setting back (also on error
    or cancel; the world's stand-in removed). Returns per meter ({(band, end): value}, {...: s.e.},
    {...: deterministic bound})."""
    import time

    scene, progress, cancelled = request.scene, request.progress, request.cancelled
    values, ses, bounds = ([{} for _ in range(n_points)] for _ in range(3))
    n_sources = len(plan["power"])
    alone_renders = list(range(n_sources)) if n_sources > 1 else []
    gains = np.ones((n_points, n_sources))
    saved = []
    stand_in = None
    world, layout, edges = plan["world"], plan["layout"], plan["edges"]
    start = time.perf_counter()
    try:
        if world is not None:
            stand_in, set_world = _world_stand_in(world, plan["weights"])
            scene.world = stand_in
        for mat, sockets in plan["materials"].items():
            for sock in sockets:
                _remember(saved, sock, "default_value")
        for obj in plan["lights"]:
            for attr in ("color", "use_temperature", "energy"):
                _remember(saved, obj.data, attr)
        for socks, _lum, _p, _label in plan["surfaces"]:
            for sock in socks:
                _remember(saved, sock, "default_value")
        def set_render(render, alone=None):
            """Materials at the render's band ends, every source at its band power (``alone``: only the
            source of that index in ``plan["power"]``: lights, then the world, then emitting surfaces)."""
            for m, (mat, sockets) in enumerate(plan["materials"].items()):
                colour = [plan["rmax"][b, m] if end else plan["rmin"][b, m] for b, end in render]
                colour += [0.0] * (3 - len(render))
                for sock in sockets:
                    sock.default_value = (*colour, 1.0)
            n_lights, n_world = len(plan["lights"]), int(stand_in is not None)

            def lit(index):
                return alone is None or alone == index

            for j, (obj, p) in enumerate(zip(plan["lights"], plan["power"])):
                colour = _channels(p, edges, render)
                top = max(colour) or 1.0
                obj.data.use_temperature = False
                obj.data.color = tuple(c / top for c in colour)
                obj.data.energy = top if lit(j) else 0.0
            if stand_in is not None:
                set_world([c * lit(n_lights) for c in _channels(plan["world_power"], edges, render)])
            for j, (socks, lum, p, _label) in enumerate(plan["surfaces"]):
                colour = _channels(p, edges, render)
                on = lit(n_lights + n_world + j)
                for sock, y in zip(socks, lum):  # its luminance times the band power per unit luminance
                    sock.default_value = (*(y * c * on for c in colour), 1.0)

        def stop_if_cancelled():
            if cancelled is not None and cancelled():
                raise MeasurementCancelled("cancelled: the spectral band renders stopped; every setting is as it was")

        for k, render in enumerate(layout):
            stop_if_cancelled()
            set_render(render)
            for i, (rgb, se, bound) in enumerate(read(k)):
                for j, key in enumerate(render):
                    values[i][key], ses[i][key], bounds[i][key] = float(rgb[j]), float(se[j]), float(bound[j])
            if progress is not None:
                spent = time.perf_counter() - start
                progress(k + 1, len(layout) + len(alone_renders), spent / (k + 1) * (len(layout) - k - 1))
        # Where several sources light the room, one more render per source ALONE (at the render holding 555 nm)
        # gives each source's share of the light at each meter: the estimate inside a band weights the
        # sources' spectra by that share (their powers alone mix watts with per-unit-luminance amounts, and
        # say nothing of how much of each reaches the meter). The bounds do not use it.
        if alone_renders:
            k_star = _peak_render(plan)
            render = layout[k_star]
            for s in alone_renders:
                stop_if_cancelled()
                set_render(render, alone=s)
                sent = np.array(_channels(plan["power"][s], edges, render)[:len(render)])
                for i, (rgb, _se, _bound) in enumerate(read(len(layout) + s)):
                    gains[i, s] = float(np.sum(rgb[:len(render)])) / float(np.sum(sent)) if np.sum(sent) > 0 else 0.0
                if progress is not None:
                    progress(len(layout) + s + 1, len(layout) + len(alone_renders), None)
    finally:
        _restore(saved)
        if stand_in is not None:
            scene.world = world
            bpy.data.worlds.remove(stand_in)
    return values, ses, bounds, (gains if alone_renders else None)


def _upsampling_bound(plan):
    """{quantity: relative bound} of the upsampling assumption (0 where no coloured material was upsampled)."""
    up = spectral_bands.UPSAMPLING_REL_BOUND
    return {k: (v if plan["upsampled"] else 0.0) for k, v in up.items()}


def _band_notes(plan, what="per meter"):
    edges, layout = plan["edges"], plan["layout"]
    up = spectral_bands.UPSAMPLING_REL_BOUND
    return ([f"materials upsampled from their colour ({', '.join(repr(n) for n in plan['upsampled'])}): the band "
             f"range holds for the assumed spectra; each interval is widened by the assumption's largest error "
             f"measured over coloured rooms (E_v {100 * up['illuminance_lx']:.1f} %, mel-EDI "
             f"{100 * up['melanopic']:.1f} % of the reading; bench/spectral_room_family.md; not proven)"]
            if plan["upsampled"] else []) + ([f"rendered part in {len(edges) - 1} bands ({len(layout)} Cycles renders of {plan['samples']:,} samples "
             f"{what}): every material's reflectance at each band's low and high end, so the band's light "
             "lies between the two (proven: paths are products of reflectances); the estimate interpolates",
             "not counted: light beyond Cycles' bounce limit (as for every rendered reading)"]
            + [f"material {name!r}: reflectance {label}" for name, label in plan["labels"].items()
               if "upsampled" in label]
            + [f"emitting surface {label}: its light (direct and reflected) is read in the band renders with that "
               "spectrum times its luminance" for _s, _l, _p, label in plan["surfaces"]]
            + ([f"the world's light (direct and reflected) is read in the band renders with its spectrum "
                f"({plan['world_label']}) times its luminance: "
                + ("no spectrum is stated on the World, so CIE D65 is assumed (set its radiometer_spectrum)"
                   if "default" in plan["world_label"] else "a stated spectrum is trusted")
                + ", and the world's colour is not checked against it"] if plan["world"] is not None else [])
            + ([f"{len(plan['power'])} sources: the estimate inside each band weights their spectra by each one's "
                f"share of the light {what.replace('per ', 'at each ')} (one more render of each source alone, at "
                "the band holding 555 nm: an estimate, not proven); the band range stays the extremes over the "
                "sources"] if len(plan["power"]) > 1 else []))


def _bands_nm(plan):
    wl, edges = spectral.WAVELENGTHS_NM, plan["edges"]
    return [(float(wl[edges[k]]), float(wl[edges[k + 1] - 1])) for k in range(len(edges) - 1)]


def reflected_readings(locations, normals, *, request, samples=None, max_bands=None):
    """The rendered part of the light at N meters (one batch per band render), in bands: a list of dicts (SI),
    one per meter, or raise ``RadiometerError`` why not.

    Keys: ``illuminance_lx``, ``alpha_opic_irradiance_w_m2``, ``alpha_opic_edi_lx`` (each a dict of
    ``estimate``, ``lower`` and ``upper`` (the proven band range), ``std_error`` (1 sigma, stochastic),
    ``low_95`` and ``high_95`` (the range widened by 1.96 sigma)), ``bands_nm``, ``renders``, ``materials``,
    ``notes``, ``world`` (the world spectrum's label where the renders read the world's light, else None).
    The request (``measure.blender.request``): the scene, the quality (None: "preview": the bands and samples
    per meter), the first seed, ``progress(done, total, seconds_left)`` after every band render (done/total in
    renders) and ``cancelled()`` (True stops before the next render: ``MeasurementCancelled``, every setting
    put back)."""
    from . import point_meter as meter

    locations = np.atleast_2d(np.asarray(locations, float))
    normals = np.broadcast_to(np.asarray(normals, float), locations.shape)
    plan = _band_plan(request, samples, max_bands)
    # each band render: a fixed number of samples per meter at the meter's standard bounces, its own seed
    band = request.but(quality="standard", samples=plan["samples"], target_rel_error=None, time_budget_s=None,
                       target_abs_error=None, progress=None, cancelled=None)

    def read(k):
        readings = meter.measure_illuminance(locations, normals, band.but(seed=request.seed + 104729 * k),
                                             method="hybrid", pooling=False)
        readings = readings if isinstance(readings, list) else [readings]
        direct = meter.analytic_light_irradiance(locations, normals, band)
        out = []
        for i, reading in enumerate(readings):
            rendered = np.asarray(reading.irradiance_rgb, float) - sum(
                (direct[name][i] for name in reading.parts.get("analytic", []) if name in direct), np.zeros(3))
            # the meter's deterministic bound (a caustic's or mirror image's closed form, a bounded closed
            # form), stated on its Y-weighted reading: shared across the channels in proportion to their
            # readings; and the colours and strengths set here are stored in float32 (a closed-form part is
            # then off by ~1e-7)
            rel = float(reading.rel_error_bound or 0.0) + meter.FLOAT32_FLOOR
            bound = rel * np.abs(np.asarray(reading.irradiance_rgb, float)) if math.isfinite(rel) else \
                np.full(3, math.inf)
            out.append((rendered, np.asarray(reading.std_error_rgb, float), bound))
        return out

    values, ses, bounds, gains = _run_band_renders(request, plan, read, len(locations))
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.ACTION_SPECTRA])
    # E_v: efficacy x the V-weighted band sum; alpha-opic as the direct part's: (efficacy / K_m,S026) x sum E s
    efficacy = plan["efficacy"]
    scale = np.array([efficacy] + [efficacy / action_spectra.K_M_S026_LM_PER_W] * 5)
    notes = _band_notes(plan)
    out = []
    for i in range(len(locations)):
        combined = spectral_bands.combine(plan["edges"], plan["power"], w, plan["t"], values[i], ses[i],
                                          plan["layout"], channel_bound=bounds[i],
                                          source_gain=None if gains is None else gains[i])

        def part(q, factor=1.0, assumed=0.0):
            d = {key: float(combined[key][q] * scale[q] * factor) for key in ("estimate", "lower", "upper",
                                                                              "std_error")}
            # a material upsampled from its colour: the band range holds for the assumed spectrum; the
            # assumption's measured error widens it
            d["upsampling_bound"] = assumed * abs(d["estimate"])
            d["low_95"] = d["lower"] - d["upsampling_bound"] - 1.96 * d["std_error"]
            d["high_95"] = d["upper"] + d["upsampling_bound"] + 1.96 * d["std_error"]
            return d

        up = _upsampling_bound(plan)
        out.append({
            "illuminance_lx": part(0, assumed=up["illuminance_lx"]),
            "alpha_opic_irradiance_w_m2": {a: part(j + 1, assumed=up[a]) for j, a in enumerate(action_spectra.ALPHA)},
            "alpha_opic_edi_lx": {a: part(j + 1, 1.0 / float(action_spectra.D65_ELR_W_PER_LM[j]), assumed=up[a])
                                  for j, a in enumerate(action_spectra.ALPHA)},
            "bands_nm": _bands_nm(plan), "samples_per_render": plan["samples"],
            "renders": len(plan["layout"]) + (0 if gains is None else len(plan["power"])),
            "materials": plan["labels"], "notes": list(notes), "world": plan["world_label"],
            "emitting_surfaces": [label for _s, _l, _p, label in plan["surfaces"]],
        })
    return out


def mesopic_reading(location, direction, *, request, acceptance_deg=1.0):
    """CIE 191:2010 mesopic luminance seen by a luminance (spot) meter, from band renders: a dict (SI) or raise
    ``RadiometerError`` why not.

    Each band render reads the meter's cone (``camera.measure_luminance``, its quality's target, seeds apart
    per render); the bands give the photopic L_p = K sum L_e V and scotopic L_s = K' sum L_e V' luminances
    (K' = 1700.06 lm/W, scaled by the scene's efficacy / 683.002 as the alpha-opic sums are), each with its
    proven band range widened by 1.96 standard errors; L_mes = CIE 191 at (L_p, S/P = L_s / L_p). Its 95 %
    interval is the least and greatest L_mes over the four corners of the (L_p, L_s) box: L_mes rises with
    both (checked numerically over L_p 1e-4..1e3 cd/m^2, S/P 0.25..4, tests/test_spectral.py). The request:
    the scene, the quality (None: "preview"), the first seed, progress and cancel (per band render)."""
    from . import camera
    from .point_meter import FLOAT32_FLOOR as FLOAT32

    request = _preview(request)
    plan = _band_plan(request)
    cone = request.but(target_rel_error=None, samples=None, time_budget_s=None, target_abs_error=None,
                       progress=None, cancelled=None)

    def read(k):
        r = camera.measure_luminance(location, direction, acceptance_deg=acceptance_deg,
                                     request=cone.but(seed=request.seed + 104729 * k))
        rgb = np.asarray(r.radiance_rgb, float)
        return [(rgb, np.asarray(r.std_error_rgb, float), FLOAT32 * np.abs(rgb))]

    values, ses, bounds, gains = _run_band_renders(request, plan, read, 1)
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.SCOTOPIC_V])
    combined = spectral_bands.combine(plan["edges"], plan["power"], w, plan["t"], values[0], ses[0],
                                      plan["layout"], channel_bound=bounds[0],
                                      source_gain=None if gains is None else gains[0])
    k_p = plan["efficacy"]
    k_s = plan["efficacy"] / action_spectra.K_M_S026_LM_PER_W * action_spectra.KP_M_LM_PER_W
    parts = {}
    up = _upsampling_bound(plan)
    for q, (name, factor, key) in enumerate((("photopic_cd_m2", k_p, "illuminance_lx"),
                                              ("scotopic_cd_m2", k_s, "rhodopic"))):  # V' is S 026's rhodopic
        d = {k: float(combined[k][q] * factor) for k in ("estimate", "lower", "upper", "std_error")}
        d["upsampling_bound"] = up[key] * abs(d["estimate"])
        d["low_95"] = max(0.0, d["lower"] - d["upsampling_bound"] - 1.96 * d["std_error"])
        d["high_95"] = d["upper"] + d["upsampling_bound"] + 1.96 * d["std_error"]
        parts[name] = d
    lp, ls = parts["photopic_cd_m2"], parts["scotopic_cd_m2"]
    notes = _band_notes(plan, "of the meter's cone") + [
        "delta lights (radius 0) are invisible to camera rays and cannot be seen by a luminance meter"]
    out = {"quantity": "mesopic luminance (CIE 191:2010) in the meter's cone", "location": tuple(map(float, location)),
           "direction": tuple(map(float, direction)), "acceptance_deg": float(acceptance_deg),
           "photopic_cd_m2": lp, "scotopic_cd_m2": ls, "exact": False,
           "bands_nm": _bands_nm(plan), "renders": len(plan["layout"]), "materials": plan["labels"],
           "world": plan["world_label"], "notes": notes,
           "units": {"photopic_cd_m2": "cd/m²", "scotopic_cd_m2": "cd/m² (scotopic)", "mesopic_cd_m2": "cd/m²",
                     "sp_ratio": "1", "adaptation_m": "1", "acceptance_deg": "deg"}}
    if lp["estimate"] <= 0 or ls["estimate"] <= 0:
        out.update(sp_ratio=None, mesopic_cd_m2=None, adaptation_m=None, regime=None)
        out["notes"].append("no light in the meter's cone: no mesopic luminance")
        return out
    est, m = action_spectra.mesopic_luminance(lp["estimate"], ls["estimate"] / lp["estimate"])
    corners = [(a, b) for a in (lp["low_95"], lp["high_95"]) for b in (ls["low_95"], ls["high_95"]) if a > 0 and b > 0]
    if len(corners) == 4:
        ends = [float(action_spectra.mesopic_luminance(a, b / a)[0]) for a, b in corners]
        low, high = min(ends), max(ends)
    else:  # a band range reaching 0: the low end is unknown above 0
        low, high = 0.0, float(action_spectra.mesopic_luminance(lp["high_95"], ls["high_95"] / lp["high_95"])[0])
    lo_r, hi_r = action_spectra.MESOPIC_RANGE_CD_M2
    out.update(sp_ratio=ls["estimate"] / lp["estimate"], adaptation_m=float(m),
               mesopic_cd_m2={"estimate": float(est), "low_95": low, "high_95": high},
               regime="photopic" if est >= hi_r else ("scotopic" if est <= lo_r else "mesopic"))
    return out


def rgb_only_reading(location, normal, *, request, samples=None):
    """Today's RGB render of the rendered part, converted with a stated assumption (no band renders).

    ``spectral_bands.rgb_only_estimate``: the room's gain in each box band (B 380-489, G 490-589, R 590-780
    nm) is the RGB render's gain in that channel. Its error is not proven: ``rel_error_bound`` is the largest
    relative error measured over a family of coloured rooms (``spectral_bands.RGB_ONLY_REL_BOUND``,
    bench/spectral_room_family.md). Where the world emits: ``{"not_given": why}``. The request: the scene, the
    render's quality (None: "preview") and seed."""
    from . import point_meter as meter

    request = _preview(request)
    scene = request.scene
    if meter.capture_model(scene, request.view_layer).world_emits:
        return {"not_given": "the world emits: its light has no one power to take the RGB render's gain from "
                             "(the band renders read it)"}
    _space, weights, efficacy = request.photometry
    lights = [obj for obj in scene.objects if obj.type == "LIGHT" and not obj.hide_render]
    power, rgb_sum = np.zeros(spectral.WAVELENGTHS_NM.shape), np.zeros(3)
    for obj in lights:
        label, spd = spectra.light_spectrum(obj)
        if label is None:
            raise RadiometerError(f"light {obj.name!r} has no known spectrum: {spd}")
        colour = _light_colour(obj.data)
        power += float(obj.data.energy) * spd * float(colour @ weights) / float(spd @ action_spectra.PHOTOPIC_V)
        rgb_sum += float(obj.data.energy) * colour
    reading = meter.measure_illuminance(location, normal, request.but(
        samples=samples, target_rel_error=None, time_budget_s=None, target_abs_error=None, progress=None,
        cancelled=None), method="hybrid", pooling=False)
    direct = {row["light"]: np.asarray(row["irradiance_rgb"], float)
              for row in meter.predict_illuminance(location, normal, request) if row["irradiance_rgb"] is not None}
    rendered = np.asarray(reading.irradiance_rgb, float) - sum(
        (direct[name] for name in reading.parts.get("analytic", []) if name in direct), np.zeros(3))
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.ACTION_SPECTRA])
    scale = np.array([efficacy] + [efficacy / action_spectra.K_M_S026_LM_PER_W
                                   / float(action_spectra.D65_ELR_W_PER_LM[i]) for i in range(5)])
    est = spectral_bands.rgb_only_estimate(rendered, rgb_sum, power, w) * scale
    # its standard error: the channels' (correlated: added linearly) through the same linear map
    se = spectral_bands.rgb_only_estimate(np.abs(np.asarray(reading.std_error_rgb, float)), rgb_sum, power, w) * scale
    bound = spectral_bands.RGB_ONLY_REL_BOUND
    return {"illuminance_lx": float(est[0]), "illuminance_std_error_lx": float(se[0]),
            "alpha_opic_edi_lx": {a: float(v) for a, v in zip(action_spectra.ALPHA, est[1:])},
            "mel_edi_lx": float(est[5]), "mel_edi_std_error_lx": float(se[5]),
            "rel_error_bound": {"illuminance_lx": bound["illuminance_lx"], "mel_edi_lx": bound["mel_edi_lx"]},
            "assumption": "the room's gain in each box band (B 380-489, G 490-589, R 590-780 nm) is the RGB "
                          "render's gain in that channel; bound measured over a family of coloured rooms, not proven",
            "units": {"illuminance_lx": "lx", "mel_edi_lx": "lx", "alpha_opic_edi_lx": "lx", "rel_error_bound": "1"}}


def spectral_reading(location, normal=(0.0, 0.0, 1.0), *, request):
    """``spectra.spectral_reading`` (the direct part) with the rendered part added in bands.

    Then ``part`` is "direct+reflected"; ``illuminance_lx``, ``mel_edi_lx``, ``alpha_opic_edi_lx`` and
    ``alpha_opic_irradiance_w_m2`` are totals (direct exact + reflected estimate); ``interval_95`` holds each
    one's estimate, 95 % interval, standard error and band bound; ``direct`` the direct-only figures;
    ``reflected`` the band reading (:func:`reflected_reading`); ``rgb_only`` the RGB-only estimate of the
    reflected part (``{"not_given": why}`` where the world emits); ``exact`` is False. Where the band render
    is refused, the direct reading comes back with the reason in ``notes`` and the reflected light still in
    ``not_included``. The request as :func:`spectral_readings` takes it.
    """
    request = _preview(request)
    out = spectral_readings([location], [normal], request=request)[0]
    if out["part"] == "direct+reflected":
        try:
            out["rgb_only"] = rgb_only_reading(location, normal, request=request.but(seed=request.seed + 1))
        except RadiometerError as exc:
            out["rgb_only"] = {"not_given": str(exc)}
    return out


def spectral_readings(locations, normals, *, request):
    """:func:`spectral_reading` at N meters, the band renders in one batch (no ``rgb_only``): a list of dicts.
    The request (scene, quality (None: "preview"), seed, progress, cancel) as in :func:`reflected_readings`."""
    from . import point_meter as meter

    request = _preview(request)
    scene = request.scene
    locations = np.atleast_2d(np.asarray(locations, float))
    normals = np.broadcast_to(np.asarray(normals, float), locations.shape)

    def direct(with_world):
        return [spectra.spectral_reading(tuple(p), tuple(n), request=request, with_world=with_world)
                for p, n in zip(locations, normals)]

    # the band renders read all of an emitting world's light, its direct part too: the direct part leaves it
    # out (the world's row never decides ``complete``), and takes it back only where the band renders refuse
    world_in_band = meter.capture_model(scene, request.view_layer).world_emits
    outs = direct(not world_in_band)
    if not all(o["complete"] for o in outs):
        outs = direct(True) if world_in_band else outs
        for o in outs:
            o["notes"].append("reflected part not added: every light needs a spectrum and a closed form here")
        return outs
    try:
        bands = reflected_readings(locations, normals, request=request)
    except MeasurementCancelled:
        raise
    except RadiometerError as exc:
        outs = direct(True) if world_in_band else outs
        for o in outs:
            o["notes"].append(f"reflected part not added: {exc}")
        return outs
    if world_in_band:
        for o in outs:
            o["not_included"] = [x for x in o["not_included"] if not x.startswith("the world")]
    if bands[0]["emitting_surfaces"]:  # their light is in the band renders
        for o in outs:
            o["not_included"] = [x for x in o["not_included"] if x != "emitting surfaces"]
    return [_with_reflected(o, band) for o, band in zip(outs, bands)]


def _with_reflected(out, band):
    """The direct reading ``out`` with the band reading ``band`` added (totals, 95 % intervals)."""
    direct = {k: out[k] for k in ("illuminance_lx", "mel_edi_lx", "alpha_opic_edi_lx", "alpha_opic_irradiance_w_m2",
                                  "mel_der", "sp_ratio", "exact")}
    ev_d = out["illuminance_lx"]

    def total(d_value, part):
        return {"estimate": d_value + part["estimate"], "low_95": d_value + part["low_95"],
                "high_95": d_value + part["high_95"], "std_error": part["std_error"],
                "band_bound": max(part["estimate"] - part["lower"], part["upper"] - part["estimate"]),
                "upsampling_bound": part.get("upsampling_bound", 0.0)}

    ev = total(ev_d, band["illuminance_lx"])
    edi = {a: total(direct["alpha_opic_edi_lx"][a], band["alpha_opic_edi_lx"][a]) for a in action_spectra.ALPHA}
    irr = {a: total(direct["alpha_opic_irradiance_w_m2"][a], band["alpha_opic_irradiance_w_m2"][a])
           for a in action_spectra.ALPHA}
    out.update(part="direct+reflected", direct=direct, reflected=band, exact=False,
               illuminance_lx=ev["estimate"], illuminance_known_spectrum_lx=ev["estimate"],
               mel_edi_lx=edi["melanopic"]["estimate"],
               mel_der=edi["melanopic"]["estimate"] / ev["estimate"] if ev["estimate"] > 0 else None,
               alpha_opic_edi_lx={a: v["estimate"] for a, v in edi.items()},
               alpha_opic_irradiance_w_m2={a: v["estimate"] for a, v in irr.items()},
               interval_95={"illuminance_lx": ev, "mel_edi_lx": edi["melanopic"],
                            "alpha_opic_edi_lx": edi, "alpha_opic_irradiance_w_m2": irr},
               sp_ratio=None, not_included=[x for x in out["not_included"] if not x.startswith("light reflected")])
    out["notes"] += band["notes"] + ["S/P of the total is not given with the reflected part (the bands bound "
                                     "the scotopic and photopic sums separately)"]
    return out

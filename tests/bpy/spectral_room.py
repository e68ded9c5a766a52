"""The coloured room of issue 35 in Blender: the box of ``tests/spectral_radiosity.py`` (4 x 3 x 2.7 m,
saturated red walls, white ceiling, light-grey floor; the reflectance spectra of the ColorChecker as
colour-science 0.4.6 ships Ohta's data) lit by one point light of known spectrum. Test/bench code only.
"""

import bpy
import numpy as np

from radiometer.demo import builders

import spectral_radiosity as ref  # tests/ is on sys.path (tests/bpy/conftest.py or the bench script)


def build(scene, csv_dir, *, temperature_k=4000.0, power_w=ref.LIGHT_POWER_W):
    """The box, its materials (``radiometer_reflectance`` = a CSV per material written to ``csv_dir``, the
    base colour its Rec.709 RGB under D65) and the light; returns the light object."""
    builders.black_world(scene)
    _surfaces(scene, csv_dir, ref.FACE_GROUPS, ref.FACES)
    # a white light with Temperature on: a blackbody (measure/meter/spectra.py), Cycles' colour temperature_color
    return builders.add_light(scene, "POINT", ref.LIGHT_M, name="lamp", energy=power_w, shadow_soft_size=0.0,
                              use_temperature=True, temperature=temperature_k)


def build_daylit(scene, csv_dir, *, strength=1.0, spectrum=None):
    """The daylit variant (``ref.FACES_DAYLIT``): the box with a floor-to-ceiling opening in wall y0, no light,
    a uniform white world of ``strength`` (radiance ``strength`` W/(m² sr) per channel: L_v = efficacy x
    strength) whose spectrum is ``spectrum`` (the World's ``radiometer_spectrum``; None: the default, D65).
    Returns the world."""
    world = builders.black_world(scene, "sky")
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = strength
    if spectrum is not None:
        world["radiometer_spectrum"] = spectrum
    _surfaces(scene, csv_dir, {k: v for k, v in ref.FACE_GROUPS_DAYLIT.items() if k != "window"}, ref.FACES_DAYLIT)
    return world


def _surfaces(scene, csv_dir, groups, faces_of):
    """One mesh object per face group, its material's ``radiometer_reflectance`` a CSV of its ColorChecker
    spectrum written to ``csv_dir`` and its colour that spectrum's Rec.709 RGB under D65."""
    for name, faces in groups.items():
        refl = ref.reflectance(ref.MATERIAL_OF[name])
        path = csv_dir / f"{ref.MATERIAL_OF[name].replace(' ', '_')}.csv"
        path.write_text("nm,reflectance\n" + "".join(f"{w:g},{v:.6g}\n" for w, v in
                                                      zip(ref.WAVELENGTHS_NM, refl)))
        mat = builders.diffuse_material(name, ref.rec709_of_reflectance(refl))
        mat["radiometer_reflectance"] = str(path)
        verts, quads = [], []
        for face in faces:
            quads.append(tuple(range(len(verts), len(verts) + 4)))
            verts += [tuple(map(float, c)) for c in faces_of[face]]
        builders.mesh_object(name, verts, quads, mat, scene.collection)


DAYLIT_REFERENCE_JSON = __file__.rpartition("/")[0] + "/spectral_room_daylit_reference.json"


def expected_daylit(scene, world, meter="eye"):
    """(reference, its discretisation uncertainty) of the daylit box, scaled to the world's luminance (the
    JSON is per 1 cd/m², D65): dicts {(part, quantity): lx} for the total, direct and reflected light."""
    import json

    from radiometer.measure.blender import request as request_of

    with open(DAYLIT_REFERENCE_JSON) as f:
        data = json.load(f)[meter]
    hs = sorted(data, key=float)
    fine, coarse = data[hs[0]], data[hs[1]]
    _space, weights, efficacy = request_of.build(scene).photometry
    background = world.node_tree.nodes["Background"]
    lum = efficacy * float(np.asarray(tuple(background.inputs["Color"].default_value)[:3]) @ weights) \
        * background.inputs["Strength"].default_value
    value = {(p, q): lum * fine[p][q] for p in ("total", "reflected", "direct") for q in ("illuminance_lx", "mel_edi_lx")}
    error = {(p, q): lum * abs(fine[p][q] - coarse[p][q]) for p in ("total", "reflected", "direct")
             for q in ("illuminance_lx", "mel_edi_lx")}
    return value, error


REFERENCE_JSON = __file__.rpartition("/")[0] + "/spectral_room_reference.json"


def reference():
    """The numpy radiosity of the box per 1 cd of luminous intensity (``bench/spectral_room.py`` wrote it):
    {meter: {h: {"direct"|"reflected"|"total": quantities}}}."""
    import json

    with open(REFERENCE_JSON) as f:
        return json.load(f)


def luminous_intensity_cd(scene, light):
    """I_v of the Blender light as the meter counts it: efficacy x Y(Cycles' colour) x P / (4 pi)."""
    import math

    import numpy as np

    from radiometer.measure.blender import request as request_of

    _space, weights, efficacy = request_of.build(scene).photometry
    colour = np.asarray(tuple(light.data.color), float) * np.asarray(tuple(light.data.temperature_color), float)
    return efficacy * float(colour @ weights) * light.data.energy / (4.0 * math.pi)


def expected(scene, light, meter="eye"):
    """(reference (the finest h), its discretisation uncertainty |finest - next coarser|), per 1 cd scaled to the
    light: dicts of E_v and mel-EDI (lx) for the total and reflected light."""
    ref = reference()[meter]
    hs = sorted(ref, key=float)
    fine, coarse = ref[hs[0]], ref[hs[1]]
    iv = luminous_intensity_cd(scene, light)
    value = {(p, q): iv * fine[p][q] for p in ("total", "reflected", "direct") for q in ("illuminance_lx", "mel_edi_lx")}
    error = {(p, q): iv * abs(fine[p][q] - coarse[p][q]) for p in ("total", "reflected", "direct")
             for q in ("illuminance_lx", "mel_edi_lx")}
    return value, error


def coverage(api, location, normal, value, seeds):
    """How many of ``seeds`` preview readings (``api.spectral_reading(..., reflected=True)``, seeds 0..) hold the
    total E_v and mel-EDI of ``value`` (``expected``'s dict) in their 95 % intervals: ({"ev": n, "mel": n}, the
    last reading)."""
    covered = {"ev": 0, "mel": 0}
    for seed in range(seeds):
        r = api.spectral_reading(location, normal, reflected=True, quality="preview", seed=seed)
        row = reading_row(r)
        covered["ev"] += row["ev_lo"] <= value[("total", "illuminance_lx")] <= row["ev_hi"]
        covered["mel"] += row["mel_lo"] <= value[("total", "mel_edi_lx")] <= row["mel_hi"]
    return covered, r


def reading_row(r):
    """The figures of one ``api.spectral_reading(..., reflected=True)`` a comparison needs (lx; the RGB-only
    ones None where it is not given: a world that emits)."""
    iv = r["interval_95"]
    return {"ev": iv["illuminance_lx"]["estimate"], "ev_lo": iv["illuminance_lx"]["low_95"],
            "ev_hi": iv["illuminance_lx"]["high_95"], "ev_se": iv["illuminance_lx"]["std_error"],
            "ev_band": iv["illuminance_lx"]["band_bound"],
            "mel": iv["mel_edi_lx"]["estimate"], "mel_lo": iv["mel_edi_lx"]["low_95"],
            "mel_hi": iv["mel_edi_lx"]["high_95"], "mel_se": iv["mel_edi_lx"]["std_error"],
            "mel_band": iv["mel_edi_lx"]["band_bound"],
            "ev_direct": r["direct"]["illuminance_lx"], "mel_direct": r["direct"]["mel_edi_lx"],
            "rgb_ev_reflected": r["rgb_only"].get("illuminance_lx"), "rgb_mel_reflected": r["rgb_only"].get("mel_edi_lx"),
            "rgb_mel_se": r["rgb_only"].get("mel_edi_std_error_lx"),
            "rgb_ev_se": r["rgb_only"].get("illuminance_std_error_lx"),
            "ev_reflected": r["reflected"]["illuminance_lx"]["estimate"],
            "mel_reflected": r["reflected"]["alpha_opic_edi_lx"]["melanopic"]["estimate"]}

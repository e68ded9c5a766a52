"""Issue 35: the RGB-only estimate of the reflected part against a spectral radiosity, over coloured rooms.

For each room (tests/spectral_radiosity.py's box, walls one ColorChecker colour, ceiling white 9.5, floor
neutral 8; h = 0.4 m) and light (blackbody 2700, 4000, 6500 K; CIE LED-B3), two radiosities of the same
geometry: the truth at 5 nm with the reflectance spectra, and the RGB renderer's model (3 channels, each
material its Rec.709 RGB under D65, the light its Rec.709 RGB with Y = its luminous intensity), which is what
Cycles computes for the RGB scene. ``spectral_bands.rgb_only_estimate`` turns the RGB result into E_v and
mel-EDI of the reflected light; its relative error against the truth, per room, is the table. The bound is
the largest over the family WITHOUT the red walls of the acceptance room (held out), written to
bench/spectral_room_family.json/.md. A third solve per room takes every material's spectrum as the band
renders assume it for a material with no spectrum (its Rec.709 colour upsampled by Mallett & Yuksel's basis,
``spectral_bands.mallett_reflectance``): its error against the truth is the upsampling's measured bound
(``spectral_bands.UPSAMPLING_REL_BOUND``). Run from the repository root with PYTHONPATH holding ``radiometer``.
"""

import json
import pathlib
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent / "tests")]

import spectral_radiosity as ref  # noqa: E402

from radiometer.radiometry.photometry import action_spectra, spectral, spectral_bands  # noqa: E402

H = 0.4
HELD_OUT = "red"
LIGHTS = {"blackbody 2700 K": lambda: ref.light_spectrum("blackbody:2700"),
          "blackbody 4000 K": lambda: ref.light_spectrum("blackbody:4000"),
          "blackbody 6500 K": lambda: ref.light_spectrum("blackbody:6500"),
          "CIE LED-B3": lambda: spectral.cie_illuminant("LED-B3")[::5]}


def rec709_light(spd):
    """Rec.709 RGB of a light spectrum scaled to Y = 1 (its colour, as a renderer holds it)."""
    import colour

    xyz = spd @ ref._cmfs()
    return colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_XYZ_to_RGB @ (xyz / xyz[1])


def case(wall, light, iv=1.0, efficacy=683.0):
    import colour

    spd = LIGHTS[light]()
    materials = dict(ref.MATERIAL_OF, **{"red walls": wall})
    truth = ref.solve(spd, iv, h=H, q=3, materials=materials)
    rgb_light = rec709_light(spd)
    weights = colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_RGB_to_XYZ[1]
    rho_rgb = {g: ref.rec709_of_reflectance(ref.reflectance(materials[g])) for g in ref.FACE_GROUPS}
    rgb = ref.transport(rho_rgb, iv / efficacy * rgb_light, h=H, q=3)  # W/sr per channel, Y-weighted = I_v / K
    # the band renders' assumption for a material with no spectrum: its colour upsampled (1 nm -> the 5 nm grid)
    up = {g: spectral_bands.mallett_reflectance(rho_rgb[g])[::5] for g in ref.FACE_GROUPS}
    v5, _ = ref.action_spectra()
    k = iv / (efficacy * np.sum(spd * v5) * ref.STEP_NM)
    upsampled = ref.transport(up, k * spd, h=H, q=3)
    # the product's conversion, on the 1 nm grid: the light's power scaled so its V-sum is its Y-weighted power
    spd_1nm = np.interp(spectral.WAVELENGTHS_NM, ref.WAVELENGTHS_NM, spd)
    p = spd_1nm * float(rgb_light @ weights) / float(spd_1nm @ action_spectra.PHOTOPIC_V)
    w = np.vstack([action_spectra.PHOTOPIC_V, action_spectra.ACTION_SPECTRA[4]])
    rows = {}
    for m in ref.METERS:
        r = rgb[m][1]
        est = spectral_bands.rgb_only_estimate(r, rgb_light, p, w)
        ev = efficacy * est[0]
        mel = efficacy / action_spectra.K_M_S026_LM_PER_W * est[1] / float(action_spectra.D65_ELR_W_PER_LM[4])
        t = truth[m]["quantities"]["reflected"]
        ev_rgb = efficacy * float(r @ weights)  # Cycles' own E_v of the reflected part
        grey = ev_rgb * float(action_spectra.melanopic_der(spd_1nm))  # for comparison: the light's mel-DER kept
        u = ref.quantities(upsampled[m][1], efficacy)
        rows[m] = {"ev_true": t["illuminance_lx"], "mel_true": t["mel_edi_lx"], "ev_est": ev, "mel_est": mel,
                   "ev_rgb_render": ev_rgb, "mel_grey_world": grey,
                   "ev_up_rel": u["illuminance_lx"] / t["illuminance_lx"] - 1.0,
                   "mel_up_rel": u["mel_edi_lx"] / t["mel_edi_lx"] - 1.0,
                   "alpha_up_rel": {a: u["alpha_opic_edi_lx"][a] / t["alpha_opic_edi_lx"][a] - 1.0
                                    for a in action_spectra.ALPHA},
                   "ev_rel": ev / t["illuminance_lx"] - 1.0, "mel_rel": mel / t["mel_edi_lx"] - 1.0,
                   "ev_rgb_rel": ev_rgb / t["illuminance_lx"] - 1.0, "mel_grey_rel": grey / t["mel_edi_lx"] - 1.0}
    return rows


def main():
    import colour

    walls = list(colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"])
    table = []
    for wall in walls:
        for light in LIGHTS:
            for m, row in case(wall, light).items():
                table.append({"wall": wall, "light": light, "meter": m, **row})
                print(wall, light, m, {k: round(v, 4) for k, v in row.items() if k.endswith("rel") and not isinstance(v, dict)}, flush=True)
    family = [r for r in table if r["wall"] != HELD_OUT]
    held = [r for r in table if r["wall"] == HELD_OUT]
    bound = {"illuminance_lx": max(abs(r["ev_rel"]) for r in family),
             "alpha_opic_edi_lx (melanopic)": max(abs(r["mel_rel"]) for r in family)}
    out = {"h_m": H, "held_out": HELD_OUT, "bound_rel": bound,
           "held_out_rel": {"ev": [r["ev_rel"] for r in held], "mel": [r["mel_rel"] for r in held]},
           "grey_world_max_rel": max(abs(r["mel_grey_rel"]) for r in family),
           "upsampling_bound_rel": {"illuminance_lx": max(abs(r["ev_up_rel"]) for r in family),
                                    **{a: max(abs(r["alpha_up_rel"][a]) for r in family) for a in action_spectra.ALPHA}},
           "upsampling_held_out_rel": {"ev": [r["ev_up_rel"] for r in held], "mel": [r["mel_up_rel"] for r in held]},
           "rgb_render_ev_max_rel": max(abs(r["ev_rgb_rel"]) for r in family), "rows": table}
    (HERE / "spectral_room_family.json").write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: v for k, v in out.items() if k != "rows"}, indent=1))


def write_md():
    d = json.loads((HERE / "spectral_room_family.json").read_text())
    rows = d["rows"]
    lines = [
        "# Issue 35: the RGB-only estimate of the reflected part over coloured rooms",
        "",
        "`bench/spectral_room_family.py`: tests/spectral_radiosity.py's box (h = %.1f m), walls one ColorChecker" % d["h_m"],
        "colour (Ohta, colour-science 0.4.6), ceiling white 9.5, floor neutral 8; each room solved at 5 nm with the",
        "spectra (truth) and in RGB with the materials' Rec.709 colours under D65 (what an RGB renderer computes).",
        "Relative errors of the reflected part at the two meters (eye: vertical at 1.2 m; desk: up at 0.8 m):",
        "`rgb-only` is `spectral_bands.rgb_only_estimate` (the product's conversion), `RGB render E_v` is Cycles'",
        "own Y-weighted E_v of the RGB render, `grey world mel` is that E_v x the light's mel-DER (for comparison).",
        "",
        f"**Bound** (largest |error| over the family without `{d['held_out']}`): E_v "
        f"{100 * d['bound_rel']['illuminance_lx']:.1f} %, mel-EDI {100 * d['bound_rel']['alpha_opic_edi_lx (melanopic)']:.1f} %. "
        f"Held-out `{d['held_out']}` rooms: E_v errors "
        + ", ".join(f"{100 * v:+.1f} %" for v in d["held_out_rel"]["ev"]) + "; mel-EDI "
        + ", ".join(f"{100 * v:+.1f} %" for v in d["held_out_rel"]["mel"]) + ". For comparison over the family: "
        f"RGB render E_v up to {100 * d['rgb_render_ev_max_rel']:.1f} % off, grey world mel-EDI up to "
        f"{100 * d['grey_world_max_rel']:.1f} %.",
        "",
        f"**Upsampling** (a material with no spectrum: its colour through Mallett & Yuksel's sRGB basis, solved at 5 nm "
        f"like the truth): largest |error| over the family E_v {100 * d['upsampling_bound_rel']['illuminance_lx']:.2f} %, "
        f"mel-EDI {100 * d['upsampling_bound_rel']['melanopic']:.2f} %, S/M/L-cone "
        f"{100 * d['upsampling_bound_rel']['s_cone']:.2f} / {100 * d['upsampling_bound_rel']['m_cone']:.2f} / "
        f"{100 * d['upsampling_bound_rel']['l_cone']:.2f} %, rhodopic {100 * d['upsampling_bound_rel']['rhodopic']:.2f} % "
        f"(`spectral_bands.UPSAMPLING_REL_BOUND`); held-out "
        f"`{d['held_out']}`: E_v " + ", ".join(f"{100 * v:+.2f} %" for v in d["upsampling_held_out_rel"]["ev"])
        + "; mel-EDI " + ", ".join(f"{100 * v:+.2f} %" for v in d["upsampling_held_out_rel"]["mel"]) + ".",
        "",
        "| wall | light | meter | E_v true (lx per cd) | mel-EDI true | rgb-only E_v | rgb-only mel-EDI | RGB render E_v | "
        "grey world mel | upsampled E_v | upsampled mel-EDI |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['wall']} | {r['light']} | {r['meter']} | {r['ev_true']:.4f} | {r['mel_true']:.4f} | "
                     f"{100 * r['ev_rel']:+.1f} % | {100 * r['mel_rel']:+.1f} % | {100 * r['ev_rgb_rel']:+.1f} % | "
                     f"{100 * r['mel_grey_rel']:+.1f} % | {100 * r['ev_up_rel']:+.2f} % | {100 * r['mel_up_rel']:+.2f} % |")
    (HERE / "spectral_room_family.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines[:12]))


if __name__ == "__main__":
    if sys.argv[1:] == ["md"]:
        write_md()
    else:
        main()

"""`circadian`: the circadian lighting check (WELL v2 L03, indicative): melanopic EDI on the vertical plane at
occupants' eyes (CIE S 026), each rated met / not met / unknown against 136 lx (1 point) and 250 lx (3 points)."""

HELP = ("circadian lighting check (WELL v2 L03, indicative): melanopic EDI (lx) at each --position's eye (1.2 m "
        "seated, 1.7 m --standing) facing its direction; a reading that leaves light out is a lower bound")
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("--position", type=float, nargs=6, action="append", required=True,
                        metavar=("X", "Y", "Z", "DX", "DY", "DZ"),
                        help="an occupant: floor point (scene coordinates) and the direction faced (repeatable)")
    parser.add_argument("--standing", action="store_true", help="eyes 1.7 m above the floor (default seated, 1.2 m)")
    parser.add_argument("--reflected", action="store_true",
                        help="add the light reflected by the room's surfaces (band renders, with a 95 %% interval)")
    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default="preview")


def _lux(value):
    return "-" if value is None else f"{value:.4g}"


def run(args):
    import bpy

    from ... import api
    from .._io import deliver

    positions = [p[:3] for p in args.position]
    directions = [p[3:] for p in args.position]
    r = api.circadian_check(positions, directions, scene=bpy.context.scene,
                            posture="standing" if args.standing else "seated", reflected=args.reflected,
                            quality=args.quality)
    print(f"circadian check ({r['source']}): melanopic EDI, vertical at the eye {r['eye_height_m']:g} m up, "
          f"thresholds {r['thresholds_mel_edi_lx']['1']:g} lx (1 point), {r['thresholds_mel_edi_lx']['3']:g} lx (3 points)")
    print(f"{'eye (m)':<24} {'E_v lx':>8} {'mel-EDI lx':>11} {'95 % interval lx':>18}  1 point   3 points  left out")
    for e in r["eyes"]:
        eye = "(" + ", ".join(f"{v:.2f}" for v in e["eye"]) + ")"
        band = f"{_lux(e['low_95_lx'])}-{_lux(e['high_95_lx'])}" if e["low_95_lx"] is not None else \
            ("exact" if e["exact"] else "lower bound")
        print(f"{eye:<24} {e['illuminance_lx']:8.4g} {e['mel_edi_lx']:11.4g} {band:>18}  {e['verdict']['1']:<9} "
              f"{e['verdict']['3']:<9} {'; '.join(e['left_out']) or '-'}")
    more = " (may be more: some eyes' readings are lower bounds)" if r["points_may_be_higher"] else ""
    print(f"WELL L03 points at every eye: {r['points']}{more}")
    deliver(args, r)
    return r

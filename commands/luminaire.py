"""`luminaire`: read an IES LM-63 or EULUMDAT file: flux, maximum intensity, beam and field angles."""

HELP = "read a photometric file (.ies, .ldt): flux, max intensity, beam/field angle; --plot a goniometric diagram"
NEEDS_SCENE = False


def add_arguments(parser):
    parser.add_argument("file", help="IES LM-63 (.ies) or EULUMDAT (.ldt) file")
    parser.add_argument("--plot", metavar="PNG", help="write the goniometric diagram (C0-C180, C90-C270) to PNG")


def format_summary(s):
    lines = [f"{s['source']}: {s['format']}, type {s['photometric_type']}, symmetry {s['symmetry']}"]
    for key, label in (("manufacturer", "manufacturer"), ("luminaire", "luminaire"),
                       ("catalogue_number", "catalogue number")):
        if s.get(key):
            lines.append(f"  {label}: {s[key].splitlines()[0]}")
    lines.append(f"  luminous flux      {s['lumens']:.6g} lm (integrated from the table)")
    rated = "absolute photometry" if s["rated_lumens"] is None else f"{s['rated_lumens']:.6g} lm"
    lines.append(f"  rated lamp flux    {rated}")
    if s.get("light_output_ratio") is not None:
        lines.append(f"  light output ratio {100 * s['light_output_ratio']:.4g} %")
    lines.append(f"  max intensity      {s['max_candela']:.6g} cd")
    if s.get("beam_angle_deg") is not None:
        lines.append(f"  beam angle (50 %)  {s['beam_angle_deg']:.4g} deg")
        lines.append(f"  field angle (10 %) {s['field_angle_deg']:.4g} deg")
    lines.append(f"  table              {s['n_horizontal']} C-planes x {s['n_vertical']} vertical angles")
    return "\n".join(lines)


def run(args):
    from .. import api

    photometry = api.read_photometry(args.file)
    summary = photometry.summary()
    print(format_summary(summary))
    if args.plot:
        api.goniometric_diagram(photometry, args.plot)
        print(f"\nWrote {args.plot}")
        summary["plot"] = args.plot
    return summary

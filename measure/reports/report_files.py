"""The names of a report's files (no bpy: the CLI checks them before Blender starts)."""


def fixed_files(client=True):
    """The report set's files whatever the scene holds (the pictures' names depend on it)."""
    return ("report.json", "report.md") + (("report.html", "report.pdf") if client else ())


def planned_files(light_stems, plane_stems, draw, convergence, client):
    """Every file name a report may write into its folder, from the stems of its lights and work
    planes: checked before any measurement."""
    names = list(fixed_files(client))
    for stem in light_stems:
        names += [f"inverse_square_{stem}.png", f"cosine_{stem}.png"] if draw else []
    for stem in plane_stems:
        names += [f"grid_{stem}.csv"] + ([f"isolux_{stem}.png"] if draw else [])
    names += ["convergence.png"] if draw and convergence else []
    names += ["luminance.exr", "luminance.png"] if draw and client else []
    return names

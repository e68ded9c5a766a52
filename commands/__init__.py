"""Headless subcommands shared by ``python -m radiometer`` and ``blender -c radiometer``.

Each submodule defines ``HELP`` (one line), ``NEEDS_SCENE`` (True when it takes a .blend),
``add_arguments(parser)`` and ``run(args) -> dict`` (JSON-serialisable; the CLI writes it to
``--json FILE``). ``run`` raises ``radiometer.errors.RadiometerError`` for bad input; the CLI turns
that into a one-line message and exit code 2.
"""

# Subcommand name -> module name, in the order --help lists them.
SUBCOMMANDS = {
    "demo": "demo",
    "measure": "measure",
    "brdf": "brdf",
    "check": "check",
    "grid": "grid",
    "report": "report",
    "luminaire": "luminaire",
    "world": "world",
    "batch": "batch",
    "sun": "daylight.sun",
    "sun-study": "daylight.sun_study",
    "daylight-factor": "daylight.daylight_factor",
    "annual": "daylight.annual",
    "glare": "glare",
    "compliance": "deliverables.compliance",
    "illuminance-image": "deliverables.illuminance_image",
    "circadian": "deliverables.circadian",
    "export-radiance": "export_radiance",
}

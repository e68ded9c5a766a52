"""Quality presets for render-based readings (pure data, no bpy).

A reading bakes ``texels`` x ``texels`` independent sensor texels per meter, each with
``samples`` Cycles samples, ``bakes`` times (new seed each time); the standard error comes from
the spread of those independent batches (batch means). The numbers were chosen from the measured
convergence study in ``bench/results.md`` (error falls as 1/sqrt(samples); see README's table).
"""

PRESETS = {
    # name: samples per texel, texels per side, bakes, light bounces when geometry is present
    "preview": {"samples": 16, "texels": 2, "bakes": 1, "bounces": 4},
    "standard": {"samples": 64, "texels": 4, "bakes": 1, "bounces": 8},
    "reference": {"samples": 1024, "texels": 4, "bakes": 2, "bounces": 16},
}

METHODS = ("auto", "analytic", "render")


def preset(name):
    from .errors import RadiometerError

    try:
        return dict(PRESETS[name])
    except KeyError:
        raise RadiometerError(f"unknown quality {name!r}; choose one of {', '.join(PRESETS)}") from None

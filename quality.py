"""Quality presets for render-based readings (pure data, no bpy).

A reading bakes ``texels`` x ``texels`` independent sensor texels per meter, each with
``samples`` Cycles samples, ``bakes`` times (new seed each time); the standard error comes from
the spread of those independent batches (batch means).

Chosen from the measured convergence study (``bench/presets.md``; error falls as 1/sqrt(N)):
on the demo room (interreflection) the first draft (64 x 16 samples, 8 bounces) gave 4.3 %
relative error and 4 bounces biased preview by -6 %, while direct light from an area light was
already at 0.04 %. So: enough samples for ~1 % in an interreflecting room at ``standard`` (about a
second on 2 cores), and bounce limits high enough that truncation bias is negligible (Cycles ends
paths by Russian roulette long before: a 0.7-albedo room loses 0.7^64 ~ 1e-10 at 64 bounces).
Samples per texel stay <= 1024 and the budget goes into more texels (independent batches):
Cycles accumulates each pixel in float32, and a delta-lit reading with 16384 samples per texel
drifted by 5e-6 (262144: 5.5e-5) while 1024 stayed at 1.4e-7 (bench/results.md, section 4).
More batches also make the batch-means error estimate steadier.
"""

PRESETS = {
    # name: samples per texel, texels per side, bakes, light bounces when geometry is present
    "preview": {"samples": 32, "texels": 2, "bakes": 1, "bounces": 16},
    "standard": {"samples": 256, "texels": 8, "bakes": 1, "bounces": 64},
    "reference": {"samples": 1024, "texels": 8, "bakes": 4, "bounces": 128},
}

METHODS = ("auto", "analytic", "render")


def preset(name):
    from .errors import RadiometerError

    try:
        return dict(PRESETS[name])
    except KeyError:
        raise RadiometerError(f"unknown quality {name!r}; choose one of {', '.join(PRESETS)}") from None

"""Quality presets (pure data, no bpy): a preset is a TARGET relative standard error.

A rendered reading is sampled, meter by meter, until its 1-sigma relative standard error reaches
the target (``radiometry.sampling.allocation``): preview 5 %, standard 1 %, reference 0.2 %. Chosen from
the measured convergence study (``bench/presets.md``): in the interreflecting demo room the
first round's fixed "standard" (256 samples x 64 texels) read 0.95 % RMS, a direct-lit area light
0.007 %, the same count for both; now each meter gets what it needs. Bounce limits stay high
enough that truncation bias is negligible (Cycles ends paths by Russian roulette long before: a
0.7-albedo room loses 0.7^64 ~ 1e-10 at 64 bounces). ``target_rel_error`` overrides the preset's
target; ``samples`` (a fixed number of samples per meter, for studies) and ``time_budget_s``
(best accuracy within a wall-clock budget) replace it.
"""

PRESETS = {
    # name: target 1-sigma relative standard error, light bounces when geometry is present
    "preview": {"target": 0.05, "bounces": 16},
    "standard": {"target": 0.01, "bounces": 64},
    "reference": {"target": 0.002, "bounces": 128},
}

#: Fixed-sample legacy settings (samples per texel, texels per side, bakes) per preset, used by the
#: convergence study and the benchmarks that need a fixed budget.
FIXED = {
    "preview": {"samples": 32, "texels": 2, "bakes": 1},
    "standard": {"samples": 256, "texels": 8, "bakes": 1},
    "reference": {"samples": 1024, "texels": 8, "bakes": 4},
}

METHODS = ("auto", "analytic", "hybrid", "render")


def preset(name):
    """The preset's settings: target, bounces, and the fixed-budget samples/texels/bakes."""
    from .errors import RadiometerError

    try:
        return dict(PRESETS[name], **FIXED[name])
    except KeyError:
        raise RadiometerError(f"unknown quality {name!r}; choose one of {', '.join(PRESETS)}") from None

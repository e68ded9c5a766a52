"""The quality-preset study alone: ``.venv/bin/python bench/presets.py``.

The study is section 5 of `make bench` (``run.bench_presets``): time, reached error (RMS against a
closed form or a 0.05 % render) and stated error per preset (target 5 % / 1 % / 0.2 %) on a
delta-lit, an area-lit and an interreflecting scene, and a check that every reading's
``rel_std_error`` is within its target. This entry point runs only that section and writes
``bench/presets.md`` and ``bench/presets.json`` (`make bench` writes them too, from its own run).
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def main(argv=None):
    import run

    out = os.path.join(HERE, "_presets_only")
    code = run.main(["--only", "presets", "--out", out] + list(argv or []))
    for name in ("presets.md", "presets.json"):
        os.replace(os.path.join(out, name), os.path.join(HERE, name))
    for name in ("results.md", "results.json"):
        os.remove(os.path.join(out, name))
    os.rmdir(out)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

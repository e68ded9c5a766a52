"""Render rounds: the one loop of independent Cycles renders every camera reading runs.

Each render gets the next seed (``seed_of(k)``, default ``k``) and the round's samples per pixel;
cancellation is checked before each render and progress reported after it; a round's results come
back stacked along a new first axis, ready for batch means (``radiometry.sampling.stats.batch_mean``:
the renders are independent, so their spread is the honest error of their mean).
"""

import numpy as np

from ...errors import MeasurementCancelled
from ...radiometry.sampling import stats

#: Relative float32 floor of every rendered value's 1-sigma error (issue 18, F3): Cycles shades, films and
#: accumulates in float32 (unit roundoff 2^-24); a rendered value passes some tens of operations (light
#: evaluation, BSDF and the thin-pane stand-in's math nodes, film sum and division), whose independent
#: roundings add to about sqrt(64) x 2^-24 = 4 x 2^-23 = 4.8e-7. Measured: a point light through a
#: tilted pane, rendered, read 1.19e-7 low (one ulp) while its batch-means s.e. was 1e-8.
FLOAT32_FLOOR = 4.0 * 2.0 ** -23


class RenderRounds:
    """Independent renders of ``scene`` in rounds. ``progress(done, total)`` after each render, with
    ``total`` from ``total_of(done)`` (default: one more round than done); ``cancelled()`` polled before
    each render raises :class:`MeasurementCancelled` (the caller's scene guard restores the scene)."""

    def __init__(self, scene, *, cancelled=None, progress=None, seed_of=None, total_of=None):
        self.scene, self.cancelled, self.progress = scene, cancelled, progress
        self.seed_of = seed_of or (lambda k: k)
        self.total_of = total_of
        self.renders = 0  # renders done so far (k of the next one)

    def round(self, count, spp, render):
        """``count`` renders at ``spp`` samples: ``render(k)`` -> array for render number k; stacked."""
        out = []
        for _ in range(int(count)):
            if self.cancelled is not None and self.cancelled():
                raise MeasurementCancelled("measurement cancelled; the scene was restored")
            self.scene.cycles.seed = int(self.seed_of(self.renders))
            self.scene.cycles.samples = int(spp)
            out.append(np.asarray(render(self.renders), dtype=np.float64))
            self.renders += 1
            if self.progress is not None:
                total = self.total_of(self.renders) if self.total_of else self.renders + int(count)
                self.progress(self.renders, total)
        return np.array(out)


def relative_errors(values):
    """Per-element (mean, relative standard error) over the renders of one round (axis 0), by batch
    means, never below ``FLOAT32_FLOOR`` (issue 32: identical renders of a uniform emitter gave 0); the
    relative error is nan where the mean is 0 (nothing to be relative to)."""
    mean, se = stats.batch_mean(values, axis=0)
    se = np.hypot(se, FLOAT32_FLOOR * np.abs(mean))
    with np.errstate(divide="ignore", invalid="ignore"):
        return mean, np.where(mean > 0, se / mean, np.nan)

"""Per-meter sample allocation for error-targeted measurement (pure numpy, no bpy).

A measurement runs in rounds. Every round bakes *blocks*: a block is one sensor quad of
``texels`` independent texels, each texel the mean of ``spp`` Cycles samples, and a meter may own
any number of blocks (quads at the same place), or none once it has converged. After each round the
per-sample variance of every meter is estimated from all its texels so far (pooled over rounds,
each round's texels weighted by their degrees of freedom), and the next round gives each meter
the samples it still needs:

    n_k = safety * sigma_k^2 / (target * |mu_k|)^2        (1-sigma relative standard error = target)

The estimate of a meter is the sample-weighted mean of its texels and its standard error is
sqrt(sigma_k^2 / n_k): batch means, where the batches are independent texels (Cycles scrambles
every pixel independently) of possibly different sample counts.
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = ["MeterTally", "needed_samples", "plan_round", "PILOT_SPP", "MAX_SPP", "BLOCK_TEXELS"]

#: Samples per texel in the pilot round, and at most in any round: Cycles accumulates a pixel in
#: float32, and beyond ~1024 samples the rounding drifts (5e-6 at 16384, README "Quality presets").
PILOT_SPP = 8
MAX_SPP = 1024
#: Blocks per meter in the pilot: 2 x 16 texels give 31 degrees of freedom for the variance, so
#: the pilot's error statement is a steady one (the stopping rule below needs it).
PILOT_BLOCKS = 2
#: Texels per block side (a block holds BLOCK_TEXELS**2 independent estimates).
BLOCK_TEXELS = 4


@dataclass
class MeterTally:
    """Running sums of every meter's texels (scalar, e.g. CIE Y, and RGB), in any units.

    For each meter k: ``n`` samples so far, ``sum_w``: sum of spp * x (x a texel's mean), for the
    pooled variance ``ss``: sum over rounds of spp * sum_j (x_j - mean_round)^2, ``dof``: sum over
    rounds of (texels - 1).
    """

    count: int
    n: np.ndarray = None
    sum_x: np.ndarray = None
    sum_rgb: np.ndarray = None
    ss: np.ndarray = None
    dof: np.ndarray = None
    ss_rgb: np.ndarray = None
    rounds: list = field(default_factory=list)

    def __post_init__(self):
        z = np.zeros(self.count)
        self.n, self.sum_x, self.ss, self.dof = z.copy(), z.copy(), z.copy(), z.copy()
        self.sum_rgb, self.ss_rgb = np.zeros((self.count, 3)), np.zeros((self.count, 3))

    def add(self, meter_index, spp, scalar, rgb):
        """Add one round: ``meter_index`` (M,) the meter of each of M texels, ``scalar`` (M,) and
        ``rgb`` (M, 3) the texels' values, all texels of this round with ``spp`` samples."""
        meter_index = np.asarray(meter_index, int)
        scalar = np.asarray(scalar, float)
        rgb = np.asarray(rgb, float)
        counts = np.bincount(meter_index, minlength=self.count).astype(float)
        sums = np.bincount(meter_index, weights=scalar, minlength=self.count)
        means = np.divide(sums, counts, out=np.zeros(self.count), where=counts > 0)
        dev = scalar - means[meter_index]
        self.ss += spp * np.bincount(meter_index, weights=dev * dev, minlength=self.count)
        self.dof += np.maximum(counts - 1, 0)
        self.n += spp * counts
        self.sum_x += spp * sums
        for c in range(3):
            s = np.bincount(meter_index, weights=rgb[:, c], minlength=self.count)
            m = np.divide(s, counts, out=np.zeros(self.count), where=counts > 0)
            d = rgb[:, c] - m[meter_index]
            self.ss_rgb[:, c] += spp * np.bincount(meter_index, weights=d * d, minlength=self.count)
            self.sum_rgb[:, c] += spp * s
        self.rounds.append({"spp": int(spp), "texels": int(len(meter_index)),
                            "meters": int(np.count_nonzero(counts))})

    @property
    def mean(self):
        return np.divide(self.sum_x, self.n, out=np.zeros(self.count), where=self.n > 0)

    @property
    def mean_rgb(self):
        return np.divide(self.sum_rgb, self.n[:, None], out=np.zeros((self.count, 3)), where=self.n[:, None] > 0)

    @property
    def per_sample_variance(self):
        """Pooled per-sample variance (nan where fewer than 2 texels)."""
        return np.divide(self.ss, self.dof, out=np.full(self.count, np.nan), where=self.dof > 0)

    @property
    def std_error(self):
        return np.sqrt(np.divide(self.per_sample_variance, self.n, out=np.full(self.count, np.nan),
                                 where=self.n > 0))

    @property
    def std_error_rgb(self):
        var = np.divide(self.ss_rgb, self.dof[:, None], out=np.full((self.count, 3), np.nan),
                        where=self.dof[:, None] > 0)
        return np.sqrt(np.divide(var, self.n[:, None], out=np.full((self.count, 3), np.nan),
                                 where=self.n[:, None] > 0))

    def rel_std_error(self, offset=0.0):
        """Relative standard error of (rendered mean + ``offset``), where ``offset`` (N,) is an exact
        part added to the reading (the hybrid's analytic direct light)."""
        total = np.abs(self.mean + offset)
        se = self.std_error
        out = np.divide(se, total, out=np.full(self.count, np.inf), where=total > 0)
        return np.where((se == 0) & (total == 0), 0.0, out)  # a meter in total darkness: 0 +- 0


def needed_samples(tally, target, offset=0.0, safety=1.3, max_samples=1 << 24):
    """Total samples each meter needs for a 1-sigma relative error of ``target`` (N,), capped.

    ``safety`` covers the noise of the pilot's variance estimate (relative s.d. sqrt(2 / dof)).
    """
    total = np.abs(tally.mean + offset)
    var = tally.per_sample_variance
    with np.errstate(divide="ignore", invalid="ignore"):
        need = safety * var / (target * total) ** 2
    need = np.where(np.isfinite(need), need, np.where(var > 0, max_samples, 0.0))
    return np.minimum(np.ceil(need), max_samples)


def plan_round(remaining, block_texels=BLOCK_TEXELS ** 2, max_spp=MAX_SPP, overshoot=0.1, max_blocks=1 << 16):
    """(spp, blocks per meter) for the next round given ``remaining`` samples per meter (N,).

    The per-texel sample count is common to a bake, so a meter gets whole blocks of
    ``block_texels * spp`` samples. ``spp`` is chosen as large as possible (fewer texels to read)
    while the rounding-up wastes at most ``overshoot`` of the samples asked for, and the block count
    stays within ``max_blocks`` (the bake image's size).
    """
    remaining = np.maximum(np.asarray(remaining, float), 0.0)
    active = remaining > 0
    if not active.any():
        return 0, np.zeros(len(remaining), int)
    asked = remaining[active].sum()
    spp = 1
    for candidate in (2 ** k for k in range(int(np.log2(max_spp)), -1, -1)):
        blocks = np.ceil(remaining[active] / (block_texels * candidate))
        waste = blocks.sum() * block_texels * candidate - asked
        if waste <= overshoot * asked or candidate == 1:
            spp = candidate
            break
    while True:
        blocks = np.where(active, np.ceil(remaining / (block_texels * spp)), 0).astype(int)
        if blocks.sum() <= max_blocks or spp >= max_spp:
            break
        spp *= 2
    return int(spp), np.minimum(blocks, max_blocks)


def budget_round(tally, samples_left, offset=0.0, block_texels=BLOCK_TEXELS ** 2, max_spp=MAX_SPP):
    """Blocks per meter spending about ``samples_left`` samples so as to lower the worst relative
    error (the time-budget mode): meter k gets a share proportional to sigma_k^2 / mu_k^2."""
    total = np.abs(tally.mean + offset)
    var = np.nan_to_num(tally.per_sample_variance, nan=0.0)
    weight = np.divide(var, total ** 2, out=np.zeros(tally.count), where=total > 0)
    if weight.sum() <= 0 or samples_left <= 0:
        return 0, np.zeros(tally.count, int)
    # Equalise the final relative variance: n_k proportional to weight_k.
    final = (tally.n.sum() + samples_left) * weight / weight.sum()
    return plan_round(np.maximum(final - tally.n, 0.0), block_texels=block_texels, max_spp=max_spp)


@dataclass
class AllocationResult:
    tally: MeterTally
    rounds: int
    seconds: float
    reached: bool                  #: every meter met the target (target mode)
    stopped: str = ""              #: why the loop ended
    samples: np.ndarray = None     #: (N,) samples spent per meter


def allocate(bake, count, *, target=None, time_budget=None, fixed_samples=None, offset=0.0, max_rounds=6,
             max_samples=1 << 24, progress=None, clock=None):
    """Run rounds of ``bake`` until every meter meets ``target`` (1-sigma relative standard error),
    or spend about ``time_budget`` seconds as well as possible, or spend ``fixed_samples`` per meter.

    ``bake(spp, blocks)`` bakes ``blocks[k]`` blocks for meter k, ``spp`` samples per texel, and
    returns ``(meter_index (M,), scalar (M,), rgb (M, 3))`` for its M texels. ``offset`` (N,) is the
    exact part of each reading (rendered mean + offset is the reading). ``progress(fraction,
    seconds_left)`` is called after every round with the plan's estimate. Returns an
    :class:`AllocationResult`.
    """
    import time

    clock = clock or time.perf_counter
    started = clock()
    tally = MeterTally(count)
    costs = []  # (samples, seconds) per round: time model seconds = a + b * samples

    def run(spp, blocks):
        t0 = clock()
        idx, scalar, rgb = bake(int(spp), np.asarray(blocks, int))
        costs.append((float(np.sum(blocks)) * BLOCK_TEXELS ** 2 * spp, clock() - t0))
        tally.add(idx, spp, scalar, rgb)

    def model():
        if len(costs) == 1:
            s, t = costs[0]
            return 0.5 * t, 0.5 * t / max(s, 1.0)  # one point: split it evenly (a guess)
        s, t = np.array(costs).T
        b = max(np.polyfit(s, t, 1)[0], 1e-12) if np.ptp(s) > 0 else t.mean() / max(s.mean(), 1.0)
        a = max(float(np.mean(t - b * s)), 0.0)
        return a, b

    def report(done_fraction, samples_left, rounds_left):
        if progress is not None:
            a, b = model()
            progress(min(done_fraction, 1.0), a * rounds_left + b * samples_left)

    if fixed_samples is not None:
        per_meter = np.full(count, float(fixed_samples))
        spp, blocks = plan_round(per_meter, overshoot=0.0)
        run(spp, np.maximum(blocks, 2 if spp * BLOCK_TEXELS ** 2 < 2 else 1))
        report(1.0, 0, 0)
        return AllocationResult(tally, 1, clock() - started, True, "fixed budget", tally.n.copy())

    run(PILOT_SPP, np.full(count, PILOT_BLOCKS))
    reached, stopped = False, "round limit"
    for round_no in range(1, max_rounds + 1):
        rel = tally.rel_std_error(offset)
        if target is not None:
            # Stop a meter only when its estimated error is below the target by the estimate's
            # own uncertainty (relative s.d. of a standard error ~ 1/sqrt(2 dof)): stopping on a
            # lucky low variance estimate would make the stated errors too small (coverage).
            margin = 1.0 + 1.0 / np.sqrt(2.0 * np.maximum(tally.dof, 1.0))
            need = needed_samples(tally, target, offset, max_samples=max_samples)
            remaining = np.where(rel * margin > target, np.maximum(need - tally.n, 1.0), 0.0)
            if not remaining.any():
                reached, stopped = True, "target reached"
                break
            if np.all((remaining == 0) | (tally.n >= max_samples)):
                stopped = "sample cap"
                break
            if time_budget is not None and clock() - started >= time_budget:
                stopped = "time budget"
                break
            report(tally.n.sum() / (tally.n.sum() + remaining.sum()), remaining.sum(), 1)
            spp, blocks = plan_round(remaining)
        else:
            elapsed = clock() - started
            a, b = model()
            left = (time_budget - elapsed - a) / b if time_budget is not None else 0.0
            if left < 0.05 * tally.n.sum() or round_no > 3:
                stopped = "time budget"
                break
            report(elapsed / time_budget, left, 1)
            spp, blocks = budget_round(tally, left, offset)
            if not blocks.any():
                stopped = "converged"
                break
        run(spp, blocks)
    report(1.0, 0, 0)
    if target is not None and not reached:
        reached = bool(np.all(tally.rel_std_error(offset) <= target))
    return AllocationResult(tally, len(tally.rounds), clock() - started, reached, stopped, tally.n.copy())

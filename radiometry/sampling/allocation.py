"""Per-meter sample allocation for error-targeted measurement (pure numpy, no bpy).

A measurement runs in rounds. Every round bakes *blocks*: a block is one sensor quad of
``BLOCK_TEXELS**2`` independent texels, each texel the mean of ``spp`` Cycles samples; a meter may
own any number of blocks (quads at the same place), or none once it has converged.

Cycles' samplers are quasi-Monte Carlo (scrambled Sobol per pixel): a texel's variance falls
FASTER than 1/spp for smooth integrands (measured on a soft point light: the per-sample spread
estimated at 8, 64 and 1024 samples per texel was 22 %, 5.2 % and 0.74 %), so no per-sample variance
can be pooled across sample counts. Each round is therefore a batch-means estimate of its own
(its texels at one spp are independent: per-pixel scrambling), rounds are combined weighted by
their samples, and the combined variance is the sum of the rounds' own:

    mean = sum_r n_r m_r / N,     se^2 = sum_r (n_r / N)^2 v_r / J_r

(n_r samples, J_r texels, texel variance v_r in round r). The plan grows the common spp by 4x a
round (up to 1024, the float32 accumulation limit) and gives each unconverged meter the texels its
texel-variance model predicts: v(spp) = v_last (spp_last / spp)^alpha, alpha measured per meter
from its last two rounds (1, the Monte Carlo rate, until then; clipped to [1, 2]).
"""

from dataclasses import dataclass, field

import numpy as np

__all__ = ["MeterTally", "plan_round", "known_spp_share", "pilot_blocks", "allocate", "PILOT_SPP", "MAX_SPP", "BLOCK_TEXELS"]

#: Samples per texel in the pilot round, and at most in any round: Cycles accumulates a pixel in
#: float32, and beyond ~1024 samples the rounding drifts (5e-6 at 16384, README "Quality presets").
PILOT_SPP = 8
MAX_SPP = 1024
#: Blocks per meter in the pilot, and at least in any round a meter takes part in: 2 x 16 texels
#: give 31 degrees of freedom for a round's variance, a steady error statement.
PILOT_BLOCKS = 2
MIN_BLOCKS = 2
#: Texels per block side (a block holds BLOCK_TEXELS**2 independent estimates).
BLOCK_TEXELS = 4
#: Fewest samples of a pilot bake in all (issue 17): a bake's fixed cost (scene sync, kernel set-up)
#: is worth a thousand samples or more in every scene measured (small room: 0.017 s for a 1-spp bake
#: against 16 us a sample; 130k triangles: 0.19 s against ~10 us), so a smaller pilot saves little,
#: while 512 samples end a single meter that needs fewer (about 450 with the stopping margin) in one
#: bake instead of two (bench/speed-results.md: 15 of its 18 single-meter readings; one meter at 1 %:
#: 130k room 0.69 s vs 0.96 s, small room 0.10 s vs 0.14 s; 1024 was faster still but spent 3x the
#: samples the meter needed).
PILOT_MIN_SAMPLES = 512
#: Growth of the common samples per texel from round to round.
SPP_GROWTH = 4
#: Most blocks in one round (the bake image: 65536 blocks x 16 texels = a 1024 x 1024 float image).
MAX_BLOCKS = 1 << 16
#: What one texel costs beyond its samples (image, read-back), in samples, when choosing spp.
TEXEL_COST = 32
#: With a time budget, a round takes at most this many times the samples of the largest round so
#: far: the time model is a line fitted to the rounds measured, and extrapolated 150-fold from the
#: pilot it under-estimated the one big round it planned by 30 % (a 10 s budget took 15 s; 60 s took
#: 258 s with 100 lights: issue 21). Growing geometrically, each round is judged on measured costs.
BUDGET_GROWTH = 8
#: A round costs a scene sync: a round planned below this fraction of the samples spent so far is
#: doubled, so the last few meters do not take one round each.
SMALL_ROUND = 0.1
#: Standard deviations of a texel variance estimate's own noise added when planning a round (so one
#: unlucky low estimate does not leave the meter for yet another round, which costs a scene sync).
PLAN_SPREAD_SDS = 1.5
#: ...and half of it when at least ``MANY_METERS`` meters share the round: the margin then costs more
#: samples than the sync of a short extra round for the meters that fall short (issue 17, throughput
#: room, 1000 meters at 1 %: 1.27 M samples at 0.75 s.d., 1.56 M at 1.5; a sync is worth ~1k samples
#: in a small room and ~19k in a 130k-triangle room, the margin ~0.4 x the round's samples). No margin
#: at all (1.19 M) took more rounds and stopped more meters on lucky-low variance estimates (synthetic
#: coverage 0.942 instead of 0.949).
PLAN_SPREAD_SDS_MANY = 0.75
MANY_METERS = 128
#: Most samples one meter may take in a target-driven measurement (about 4 M): a meter that reads
#: almost nothing (a dark corner lit only by faint reflections) can need unbounded samples for a
#: RELATIVE target; it stops here and its reading says the target was not reached.
MAX_SAMPLES_PER_METER = 1 << 22
#: A meter whose every texel so far is 0 while light may reach it (a lit surface above its horizon,
#: a light that may be partly hidden) is not converged until it has taken this many samples: a small
#: bright region seen past an obstruction is a rare path, and a pilot that missed it reads 0 +- 0
#: (issue 18: 58.5 lx read as 0 lx with a stated error of 0).
DARK_FLOOR = 1 << 16
#: Why ``allocate`` stopped every meter after the pilot (``stop_dark="all"``); the meter's notes quote it.
DARK_PILOT = "a dark pilot stopped every meter"
#: Cycles' Tabulated Sobol sampler with scrambling distance 1 (what ``measure/render/render_settings.py`` set
#: before issue 32; it now rotates each texel's table, and passes ``table_patterns=0``): every texel draws its
#: samples of a dimension from ONE of 256 fixed patterns of S points (S = the round's spp rounded up to
#: a power of two, 256..8192; blender/cycles scene/integrator.cpp, kernel/sample/tabulated_sobol.h),
#: so a mean over any number of texels converges to the table's mean, not to the integral. Over the
#: random scrambles the table was generated with, that mean deviates by sd sqrt(v_S / 256), v_S the
#: texel variance at S samples. For smooth integrands that is far below the batch-means error; where the
#: light comes by rare paths it is not (issue 18, the fin scene: a meter 97 % hidden read 2.3 % low at
#: 4 M samples stating 0.41 %, the same -2.3 % for two seeds; bench/coverage_rare_paths_fin.md).
TABLE_PATTERNS = 256
TABLE_SIZES = (256, 8192)
#: Per-sample relative variance (texel variance x spp / mean^2 of the rendered part) from which a
#: meter's light counts as coming by rare paths (found in fewer than about 1 sample in 100: Bernoulli
#: (1 - p) / p >= 100) and the table's floor is added to its stated error. The floor as computed takes
#: all of a texel's variance to come from one dimension pair; light that needs several bounces to find
#: its rare region mixes independently chosen patterns and has a far smaller floor, which is why the
#: threshold is not lower: measured per-sample values 20-47 for the skylight room's shade and the glossy
#: floor, whose 50-seed coverage without any floor was 94-96 % (bench/coverage_rare_paths*.md), 139 and
#: 420 for the fin scene's 97 % and 99 % hidden meters. Below it, a single-bounce rare path can still
#: carry an unstated table error of up to sqrt(100 / (1024 x 256)) = 2 % (at 1024 spp; docs/errors.md).
HEAVY_TAIL = 100.0
#: Samples per texel for meters whose table floor matters: the largest table (8192 points a pattern).
#: Above MAX_SPP, Cycles' float32 accumulation drifts (5e-6 at 16384 samples, README "Quality
#: presets"), negligible against the floors it lowers (a few %).
RARE_PATH_SPP = TABLE_SIZES[1]


#: Issue 32: the samples that decide when to stop must not bias the reading. A target-driven measurement
#: runs in two stages: PLANNING rounds (the pilot and the sequential rounds above, aimed at
#: ``PLAN_FACTOR`` x the target, about 1 / PLAN_FACTOR^2 of the samples) measure each meter's texel
#: variance and its decay with spp; then ONE MEASUREMENT, sized from the planning alone, with fresh
#: seeds, gives the reading and its stated error. The measurement's size is a function of the planning
#: samples only, which are independent of it, so its mean is unbiased (E[m | size] = mu). Sequential
#: stopping on the running relative error read rare-hit meters high (a high running mean has a small
#: relative error: slit-sky DF +1.66 % over 12 seeds stating 0.77 %; mean z +0.8 to +1.2 in
#: tests/test_unbiased_stopping.py).
PLAN_FACTOR = 2.0
#: The measurement is planned with this many standard deviations of its own error estimate's noise
#: (relative s.d. 1 / sqrt(2 dof)) below the target, so it meets the target without a second try.
MEASURE_MARGIN_SDS = 1.5
#: A measurement that misses the target (its stated error above it) is replaced ONCE by a fresh one
#: sized from it; the second is kept whatever it states. Choosing between two independent readings by
#: the first one's outcome biases by at most sqrt(P(retry)) standard errors (Cauchy-Schwarz:
#: |E[z 1_retry]| <= sqrt(E[z^2] P(retry))); measured P(retry) and mean z in
#: tests/test_unbiased_stopping.py and docs/errors.md.
MEASURE_TRIES = 2


def effective_target(target, target_abs, tally, offset=0.0):
    """(N,) relative target per meter: ``target`` or, where the absolute floor ``target_abs`` (N,) (in
    the tally's scalar units) allows more, target_abs / |mean + offset| (inf where the reading is 0)."""
    if target_abs is None:
        return target
    total = np.abs(tally.mean + offset)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel_abs = np.where(total > 0, np.asarray(target_abs, float) / total, np.inf)
    return np.maximum(target, np.where(np.asarray(target_abs, float) > 0, rel_abs, 0.0))


def measurement_round(tally, target, offset=0.0, max_samples=MAX_SAMPLES_PER_METER, min_samples=None,
                      spread_sds=PLAN_SPREAD_SDS, skip=None):
    """(spp (N,), blocks (N,)) of an independent measurement that alone meets ``target`` (N,) relative
    at each meter, planned from ``tally`` (the planning rounds) only; ``skip`` (N,) bool: meters that
    get none. Per meter the cheapest of 1x, 2x, 4x its last spp (by its texel-variance model; at most
    MAX_SPP, or the larger table where its table floor needs it), counting each texel's own cost as
    ``TEXEL_COST`` samples, at least ``MIN_BLOCKS`` blocks and ``min_samples``."""
    total = np.abs(tally.mean + offset)
    target = np.broadcast_to(np.asarray(target, float), total.shape)
    v_last, s_last, alpha, _measured = tally.texel_variance_model()
    s_last = np.where(s_last > 0, s_last, PILOT_SPP)
    v_last = np.nan_to_num(v_last, nan=0.0)
    inflate = 1.0 + spread_sds * np.sqrt(2.0 / np.maximum(tally.dof, 1.0))
    floor_now = tally.table_floor
    need_min = np.zeros(tally.count) if min_samples is None else np.minimum(np.asarray(min_samples, float),
                                                                           max_samples)
    texels_per_block = BLOCK_TEXELS ** 2
    best_cost = np.full(tally.count, np.inf)
    best_spp = s_last.astype(int)
    best_blocks = np.full(tally.count, MIN_BLOCKS)
    for step in (1, 2, 4, 8):
        spp = np.minimum(s_last * step, np.where(floor_now > 0, RARE_PATH_SPP, MAX_SPP)).astype(int)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            v = inflate * v_last * (s_last / spp) ** alpha
            floor = np.where(floor_now > 0, tally.table_floor_at_each(spp), 0.0)
            goal = target * total
            c = np.maximum(goal ** 2 - floor ** 2, 0.25 * goal ** 2)
            texels = v / c
            # The measurement's own error estimate is noisy (relative s.d. 1 / sqrt(2 (J - 1))): aim below.
            texels = texels * (1.0 + MEASURE_MARGIN_SDS / np.sqrt(2.0 * np.maximum(texels, 32.0) - 2.0)) ** 2
        texels = np.where(np.isfinite(texels), texels, 0.0)
        texels = np.maximum(texels, np.ceil(need_min / spp))
        blocks = np.maximum(np.ceil(texels / texels_per_block), MIN_BLOCKS)
        blocks = np.minimum(blocks, np.maximum(np.floor(max_samples / (spp * texels_per_block)), MIN_BLOCKS))
        cost = blocks * texels_per_block * (spp + TEXEL_COST)
        better = cost < best_cost * 0.95
        best_cost = np.where(better, cost, best_cost)
        best_spp = np.where(better, spp, best_spp)
        best_blocks = np.where(better, blocks, best_blocks)
    if skip is not None:
        best_blocks = np.where(skip, 0, best_blocks)
    return best_spp.astype(int), best_blocks.astype(int)


def run_measurement(run, count, spp, blocks, max_blocks=MAX_BLOCKS):
    """Bake a planned measurement: one bake per distinct spp (split at ``max_blocks``); every size is
    fixed before the first of them, so none depends on the measurement's own texels."""
    for s in np.unique(spp[blocks > 0]):
        at = np.where((spp == s), blocks, 0)
        while at.any():
            take = np.minimum(at, np.maximum(at * max_blocks // max(int(at.sum()), 1), np.where(at > 0, 1, 0)))
            run(int(s), take)
            at = at - take


def _masked(tally, keep):
    """``tally``'s rounds with the meters not in ``keep`` (N,) bool removed (texels 0)."""
    out = MeterTally(tally.count, table_patterns=tally.table_patterns)
    for r in tally.rounds:
        out.rounds.append(dict(r, texels=np.where(keep, r["texels"], 0)))
    return out


def table_size(spp):
    """Points per pattern of Cycles' tabulated Sobol table at ``spp`` samples per pixel."""
    size = 1 << max(int(spp) - 1, 1).bit_length()  # next power of two above spp - 1
    return int(min(max(size, TABLE_SIZES[0]), TABLE_SIZES[1]))


@dataclass
class MeterTally:
    """Per-round sums of every meter's texels (scalar, e.g. CIE Y, and RGB), in any units."""

    count: int
    rounds: list = field(default_factory=list)
    #: Patterns of the sampler's fixed table (``TABLE_PATTERNS`` for Cycles' tabulated Sobol), or 0: no
    #: table (independent samples). With a table, meters whose light comes by rare paths (``HEAVY_TAIL``)
    #: state the table's floor too (``table_floor``).
    table_patterns: int = 0

    def add(self, meter_index, spp, scalar, rgb):
        """Add one round: ``meter_index`` (M,) the meter of each of M texels, ``scalar`` (M,) and
        ``rgb`` (M, 3) the texels' values, all with ``spp`` samples."""
        idx = np.asarray(meter_index, int)
        values = np.concatenate([np.asarray(scalar, float)[:, None], np.asarray(rgb, float)], axis=1)  # (M, 4)
        counts = np.bincount(idx, minlength=self.count).astype(float)
        sums = np.stack([np.bincount(idx, weights=values[:, c], minlength=self.count) for c in range(4)], axis=1)
        means = np.divide(sums, counts[:, None], out=np.zeros_like(sums), where=counts[:, None] > 0)
        dev = values - means[idx]
        ss = np.stack([np.bincount(idx, weights=dev[:, c] ** 2, minlength=self.count) for c in range(4)], axis=1)
        var = np.divide(ss, (counts - 1)[:, None], out=np.full_like(ss, np.nan), where=counts[:, None] > 1)
        self.rounds.append({"spp": int(spp), "texels": counts, "mean": means, "var": var})

    def _per_rounds(self, name, compute):
        """``compute()``, kept until a round is added (as ``_combined``): the planner asks for the same
        per-round summaries several times a round (issue 17: a reading's fixed Python cost). A copy is
        handed out, so a caller's in-place change stays its own."""
        kept = self.__dict__.setdefault("_kept", {}).get(name)
        if kept is None or kept[0] != len(self.rounds):
            kept = self.__dict__["_kept"][name] = (len(self.rounds), compute())
        value = kept[1]
        return tuple(v.copy() for v in value) if isinstance(value, tuple) else value.copy()

    @property
    def n(self):
        """Samples per meter so far."""
        return self._per_rounds("n", lambda: sum((r["spp"] * r["texels"] for r in self.rounds),
                                                 np.zeros(self.count)))

    def _combined(self):
        # Every property below reads the combination; it changes only when a round is added.
        cached = self.__dict__.get("_cache")
        if cached is not None and cached[0] == len(self.rounds):
            return cached[1][:2]
        n = self.n
        mean = np.zeros((self.count, 4))
        var = np.zeros((self.count, 4))
        for r in self.rounds:
            w = np.divide(r["spp"] * r["texels"], n, out=np.zeros(self.count), where=n > 0)
            has = r["texels"] > 0
            mean += w[:, None] * np.where(has[:, None], r["mean"], 0.0)
            v = np.where(has[:, None], r["var"], 0.0)  # nan (one texel) stays nan: no statement
            var += (w ** 2)[:, None] * np.divide(v, r["texels"][:, None], out=np.zeros_like(v),
                                                 where=has[:, None])
        floor = self._table_floor(n, mean)
        self.__dict__["_cache"] = (len(self.rounds), (mean, var + floor ** 2, var, floor))
        return mean, var + floor ** 2

    def _table_floor(self, n, mean):
        """(N, 4) floor of each meter's error from the sampler's fixed table, 0 where none is stated.

        Each round's table mean deviates by sqrt(v_S / patterns), v_S the texel variance at the table's
        S samples, taken as v_r spp_r / S (the Monte Carlo rate; QMC decays faster, so this is the larger
        value). Tables of different S share their patterns' first points, so the rounds' floors are added
        as fully correlated (sample-weighted sum, not in quadrature)."""
        floor = np.zeros((self.count, 4))
        if not self.table_patterns:
            return floor
        heavy = np.zeros(self.count, bool)
        for r in self.rounds:
            w = np.divide(r["spp"] * r["texels"], n, out=np.zeros(self.count), where=n > 0)
            has = (r["texels"] > 1)[:, None]
            per_sample = np.where(has, np.nan_to_num(r["var"], nan=0.0), 0.0) * r["spp"]  # (N, 4)
            floor += w[:, None] * np.sqrt(per_sample / (table_size(r["spp"]) * self.table_patterns))
            heavy |= (mean[:, 0] != 0) & (per_sample[:, 0] >= HEAVY_TAIL * mean[:, 0] ** 2)
        return np.where(heavy[:, None], floor, 0.0)

    def table_floor_at(self, spp):
        """(N,) the scalar floor a meter would state with all its samples at ``spp`` (its latest round's
        per-sample variance over that table), 0 where none is stated: what planning a round there uses."""
        if not self.table_patterns or not self.rounds:
            return np.zeros(self.count)
        per_sample = np.zeros(self.count)
        for r in self.rounds:
            per_sample = np.where(r["texels"] > 1, np.nan_to_num(r["var"][:, 0], nan=0.0) * r["spp"], per_sample)
        at = np.sqrt(per_sample / (table_size(spp) * self.table_patterns))
        return np.where(self.table_floor > 0, at, 0.0)

    def table_floor_at_each(self, spp):
        """(N,) ``table_floor_at`` with each meter's own ``spp`` (N,)."""
        spp = np.broadcast_to(np.asarray(spp, int), (self.count,))
        out = np.zeros(self.count)
        for s in np.unique(spp):
            out = np.where(spp == s, self.table_floor_at(int(s)), out)
        return out

    @property
    def table_floor(self):
        """(N,) the scalar error floor of the sampler's table stated in ``std_error`` (0 where none)."""
        self._combined()
        return self.__dict__["_cache"][1][3][:, 0]

    @property
    def sampling_std_error(self):
        """(N,) the scalar batch-means standard error alone (what more samples reduce)."""
        self._combined()
        return np.sqrt(self.__dict__["_cache"][1][2][:, 0])

    @property
    def mean(self):
        return self._combined()[0][:, 0]

    @property
    def mean_rgb(self):
        return self._combined()[0][:, 1:]

    @property
    def std_error(self):
        return np.sqrt(self._combined()[1][:, 0])

    @property
    def std_error_rgb(self):
        return np.sqrt(self._combined()[1][:, 1:])

    @property
    def dof(self):
        """Degrees of freedom of each meter's latest round (texels - 1)."""
        return self._per_rounds("dof", self._dof)

    def _dof(self):
        out = np.zeros(self.count)
        for r in self.rounds:
            out = np.where(r["texels"] > 0, r["texels"] - 1, out)
        return out

    def rel_std_error(self, offset=0.0):
        """Relative standard error of (rendered mean + ``offset``), where ``offset`` (N,) is an exact
        part added to the reading (the hybrid's analytic direct light)."""
        total = np.abs(self.mean + offset)
        se = self.std_error
        out = np.divide(se, total, out=np.full(self.count, np.inf), where=total > 0)
        return np.where((se == 0) & (total == 0), 0.0, out)  # a meter in total darkness: 0 +- 0

    def texel_variance_model(self):
        """(v_last, spp_last, alpha, measured), each (N,): every meter's latest round's texel variance
        (scalar), its spp, the decay exponent of texel variance with spp (1 until two spp were
        tried) and whether it was measured."""
        return self._per_rounds("texel_variance_model", self._texel_variance_model)

    def _texel_variance_model(self):
        v_last = np.full(self.count, np.nan)
        s_last = np.zeros(self.count)
        v_prev = np.full(self.count, np.nan)
        s_prev = np.zeros(self.count)
        for r in self.rounds:
            has = r["texels"] > 1
            # The previous point of the decay law is the last round at a DIFFERENT spp.
            moved = has & (s_last != r["spp"]) & (s_last > 0)
            v_prev = np.where(moved, v_last, v_prev)
            s_prev = np.where(moved, s_last, s_prev)
            v_last = np.where(has, r["var"][:, 0], v_last)
            s_last = np.where(has, r["spp"], s_last)
        alpha = np.ones(self.count)
        ok = (s_prev > 0) & (s_last != s_prev) & (v_last > 0) & (v_prev > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            measured = -np.log(v_last / v_prev) / np.log(s_last / s_prev)
        alpha = np.where(ok, np.clip(np.nan_to_num(measured, nan=1.0), 1.0, 2.0), alpha)
        return v_last, s_last, alpha, ok


def pilot_blocks(count):
    """Blocks per meter in the pilot of ``count`` meters (at ``PILOT_SPP``): ``PILOT_BLOCKS``, more
    when the meters are so few that the pilot would hold fewer than ``PILOT_MIN_SAMPLES``."""
    per_block = PILOT_SPP * BLOCK_TEXELS ** 2
    return max(PILOT_BLOCKS, int(np.ceil(PILOT_MIN_SAMPLES / (max(int(count), 1) * per_block))))


def floor_round(tally, min_samples, max_samples=MAX_SAMPLES_PER_METER):
    """(spp, blocks (N,)) of one round that brings every meter to ``min_samples`` (N,) samples (capped
    at ``max_samples``); spp as high as keeps MIN_BLOCKS blocks per meter (independent texels for the
    batch-means error), at most MAX_SPP."""
    need = np.clip(np.minimum(np.asarray(min_samples, float), max_samples) - tally.n, 0.0, None)
    if not np.any(need > 0):
        return PILOT_SPP, np.zeros(len(need), int)
    per_texel = float(np.max(need)) / (MIN_BLOCKS * BLOCK_TEXELS ** 2)
    spp = int(min(MAX_SPP, max(PILOT_SPP, 2 ** int(np.floor(np.log2(max(per_texel, 1.0)))))))
    blocks = np.where(need > 0, np.maximum(np.ceil(need / (spp * BLOCK_TEXELS ** 2)), MIN_BLOCKS), 0)
    return spp, blocks.astype(int)


def dark_meters(tally, may_be_lit):
    """(N,) bool: meters whose rendered texels are all exactly 0 so far although ``may_be_lit``."""
    if may_be_lit is None:
        return np.zeros(tally.count, bool)
    return np.asarray(may_be_lit, bool) & (tally.mean == 0.0) & (tally.std_error == 0.0)


def plan_round(tally, target, spp, offset=0.0, max_blocks=None, max_samples=MAX_SAMPLES_PER_METER,
               may_be_lit=None, spread_sds=PLAN_SPREAD_SDS):
    """Blocks per meter for a round at ``spp`` samples per texel so that, COMBINED with the rounds
    so far, each unconverged meter reaches ``target`` (1-sigma relative, on mean + offset), by the
    texel-variance model. Meters already at the target (with a margin for the noise of their own
    error estimate) get none.

    With A = sum_r n_r^2 v_r / J_r over the rounds so far, n samples so far and the new round's
    texel variance v at ``spp``, J new texels give se^2 = (A + spp^2 v J) / (n + spp J)^2; the
    smallest J with se <= target' |mean| solves a quadratic.
    """
    total = np.abs(tally.mean + offset)
    rel = tally.rel_std_error(offset)
    # Stop a meter only when its estimated error is below the target by that estimate's own
    # uncertainty (relative s.d. of a standard error ~ 1/sqrt(2 dof)): stopping on a lucky low
    # variance estimate would make the stated errors too small (coverage).
    margin = 1.0 + 1.0 / np.sqrt(2.0 * np.maximum(tally.dof, 1.0))
    todo = (rel * margin > target) & (tally.n < max_samples)
    v_last, s_last, alpha, measured = tally.texel_variance_model()
    n_old = tally.n
    a_old = (tally.sampling_std_error * n_old) ** 2          # sum_r n_r^2 v_r / J_r
    # The table's floor (rare paths, ``table_floor``) is not reduced by more texels: the sampling part
    # must reach what the target leaves of it, at the floor of this round's table (a larger spp, a
    # larger table, a lower floor: choose_spp weighs it). Where the floor leaves less than half the
    # target, the round aims the sampling part at half the target and the next spp step lowers the floor.
    floor = np.minimum(tally.table_floor, tally.table_floor_at(spp))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # 1.5 standard deviations of v_last's own noise (relative sd sqrt(2 / dof)) on top, so one
        # unlucky low estimate does not leave the meter for yet another round.
        v = (1.0 + spread_sds * np.sqrt(2.0 / np.maximum(tally.dof, 1.0))) * v_last * (s_last / spp) ** alpha
        c = np.maximum((target / margin * total) ** 2 - floor ** 2, 0.25 * (target / margin * total) ** 2)
        qa = c * spp ** 2
        qb = 2 * c * n_old * spp - spp ** 2 * v
        qc = c * n_old ** 2 - a_old
        texels = (-qb + np.sqrt(np.maximum(qb * qb - 4 * qa * qc, 0.0))) / (2 * qa)
    texels = np.where(np.isfinite(texels), texels, 0.0)
    blocks = np.where(todo, np.maximum(np.ceil(texels / BLOCK_TEXELS ** 2), MIN_BLOCKS), 0)
    # Until a meter's decay exponent is measured (two rounds at different spp), alpha = 1 may
    # overshoot a smooth integrand by orders of magnitude: take one short step first (<= 8x the
    # pilot's samples), then plan precisely. At the spp its variance was measured at, the plan
    # needs no exponent and is precise already.
    known = measured | (s_last == spp)
    blocks = np.where(known, blocks, np.minimum(blocks, 2 * PILOT_BLOCKS))
    dark = dark_meters(tally, may_be_lit) & (tally.n < min(DARK_FLOOR, max_samples))
    if dark.any():  # keep looking for rare light up to the floor (``DARK_FLOOR``)
        need = np.ceil((min(DARK_FLOOR, max_samples) - tally.n) / (spp * BLOCK_TEXELS ** 2))
        blocks = np.where(dark, np.maximum(need, MIN_BLOCKS), blocks)
    cap = np.maximum(np.floor((max_samples - tally.n) / (spp * BLOCK_TEXELS ** 2)), MIN_BLOCKS)
    blocks = np.minimum(blocks, cap).astype(int)
    max_blocks = MAX_BLOCKS if max_blocks is None else max_blocks
    if blocks.sum() > max_blocks:
        blocks = np.maximum((blocks * max_blocks) // blocks.sum(), np.where(blocks > 0, 1, 0))
    return blocks


def choose_spp(tally, target, previous, offset=0.0, max_samples=MAX_SAMPLES_PER_METER, may_be_lit=None,
               spread_sds=PLAN_SPREAD_SDS):
    """Samples per texel for the next round: 4x the previous one while some meter's decay exponent
    is unmeasured (it needs two sample counts), then whichever of 1x, 2x, 4x the previous plans the
    fewest samples (small remaining needs are not rounded up to 32 texels x 1024; never fewer samples
    per texel than before, so large needs do not explode into texels)."""
    _v, _s, _alpha, measured = tally.texel_variance_model()
    grown = min(MAX_SPP, previous * SPP_GROWTH)
    rel = tally.rel_std_error(offset)
    total = np.abs(tally.mean + offset)
    floor_rel = np.divide(tally.table_floor, total, out=np.zeros(tally.count), where=total > 0)
    rare = (floor_rel > 0.5 * target) & (rel > target)
    if np.any(rare):
        # A meter lit by rare paths whose table floor matters: a larger table has a lower floor
        # (1 / sqrt(S)); the smallest that leaves the sampling part at least half the target, at most
        # the largest (fin scene, 99 % hidden: 8 % at 128 spp, 4 % at 1024, 1.4 % at 8192).
        for size in (MAX_SPP, 2 * MAX_SPP, 4 * MAX_SPP):
            at = np.divide(tally.table_floor_at(size), total, out=np.zeros(tally.count), where=total > 0)
            if np.all(at[rare] <= 0.5 * np.broadcast_to(target, at.shape)[rare]):
                return max(size, previous)
        return RARE_PATH_SPP
    if not np.all(measured | (rel <= target)):
        # The step that measures the decay exponent (4x: a 2x step measured it too noisily,
        # 6x the oracle's samples on a QMC-like integrand at 0.2 % against 4x).
        return grown
    best, best_cost = grown, np.inf
    for spp in sorted({previous, min(MAX_SPP, 2 * previous), grown}):
        # Samples, plus each texel's own cost (reading it back, its share of the image) counted
        # as TEXEL_COST samples.
        blocks = plan_round(tally, target, spp, offset, max_blocks=1 << 40, max_samples=max_samples,
                            may_be_lit=may_be_lit, spread_sds=spread_sds).sum()
        cost = blocks * (spp + TEXEL_COST) * (1.0 if blocks <= MAX_BLOCKS else np.inf)
        if cost < best_cost * 0.95:  # prefer fewer, larger texels when it is a tie
            best, best_cost = spp, cost
        elif cost <= best_cost * 1.05:
            best = spp
    return best


def known_spp_share(tally, target, known_spp, blocks, spp, offset=0.0,
                    max_samples=MAX_SAMPLES_PER_METER, may_be_lit=None, spread_sds=PLAN_SPREAD_SDS):
    """Blocks (N,) at ``known_spp`` for the meters that finish more cheaply there than in the planned
    step (``blocks`` at ``spp``), or None.

    The step to a new spp is capped while a meter's decay exponent is unmeasured, and its whole
    blocks at 4x the samples per texel overshoot a small remaining need (the throughput room: 1024
    samples where ~500 were needed). At the spp a meter's texel variance was measured at, its plan
    needs no exponent: a meter whose remaining need costs fewer samples there is baked there, in a
    bake of its own (one more scene sync: only in the step right after the pilot, and when it saves
    at least ``SMALL_ROUND`` of the samples spent so far, the rule that sizes the smallest round worth
    a sync) or, in any round, instead of the step when every meter fits. Which spp a meter's texels have does not change the estimator: rounds are combined by
    their samples, each with its own batch-means variance.
    """
    same = plan_round(tally, target, known_spp, offset, max_samples=max_samples, may_be_lit=may_be_lit,
                      spread_sds=spread_sds)
    _v, s_last, _alpha, measured = tally.texel_variance_model()
    # Only meters whose step is the capped one (exponent unmeasured, variance known at known_spp):
    # the others' plan is precise at any spp and choose_spp already picked the best common one.
    fits = (blocks > 0) & (same > 0) & ~measured & (s_last == known_spp) & (same * known_spp <= blocks * spp)
    if not fits.any():
        return None
    if np.any((blocks > 0) & ~fits):  # a bake of its own: right after the pilot only, and when worth it
        saved = float(np.sum(np.where(fits, blocks * spp - same * known_spp, 0))) * BLOCK_TEXELS ** 2
        if len(tally.rounds) > 1 or saved < SMALL_ROUND * tally.n.sum():
            return None
    return np.where(fits, same, 0)


@dataclass
class AllocationResult:
    tally: MeterTally
    rounds: int
    seconds: float
    reached: bool                  #: every meter met the target (target mode)
    stopped: str = ""              #: why the loop ended
    samples: np.ndarray = None     #: (N,) samples spent per meter (planning and measurement)
    planning_samples: np.ndarray = None  #: (N,) of those, the planning's (not in the estimate; issue 32)


def allocate(bake, count, *, target=None, time_budget=None, fixed_samples=None, offset=0.0, max_rounds=8,
             max_samples=MAX_SAMPLES_PER_METER, progress=None, clock=None, may_be_lit=None, min_samples=None,
             table_patterns=0, target_abs=None, staged=False, stop_dark=False):
    """Run rounds of ``bake`` until every meter meets ``target`` (1-sigma relative standard error),
    or spend about ``time_budget`` seconds lowering the worst error, or spend ``fixed_samples`` per
    meter.

    ``bake(spp, blocks)`` bakes ``blocks[k]`` blocks for meter k, ``spp`` samples per texel, and
    returns ``(meter_index (M,), scalar (M,), rgb (M, 3))`` for its M texels. ``offset`` (N,) is the
    exact part of each reading (rendered mean + offset is the reading). ``progress(fraction,
    seconds_left)`` is called before every round with the plan's estimate. Returns an
    :class:`AllocationResult`. ``may_be_lit`` (N,) bool: meters that light may reach by a path the
    pilot can miss; while all their texels read 0 they are not converged (``DARK_FLOOR``), unless an
    absolute floor ``target_abs`` is given and ``stop_dark``: then such a meter stops after its pilot (issue
    31; its caller states the rule-of-three bound, which holds only where no single light-carrying sample
    can carry much more than the floor: not the default, see docs/errors.md). ``stop_dark="all"``: as True,
    and a dark pilot stops every meter there (the caller reads them another way).
    ``min_samples`` (N,) or None: a floor of samples per meter, taken in one round right after the
    pilot (issue 18: light from a small bright region of a rendered world comes by rare paths that a
    256-sample pilot misses while its variance looks tiny; see ``floor_round``).
    ``table_patterns``: the sampler's fixed table (``TABLE_PATTERNS`` for Cycles' tabulated Sobol) whose
    floor meters lit by rare paths state (``MeterTally.table_patterns``); 0: independent samples.
    ``target_abs`` (N,) or None: an absolute floor of the 1-sigma error in the tally's scalar units; a
    meter stops where its error is below it or below ``target`` relative, whichever allows more.
    ``staged`` (with a target and no time budget; issue 32): planning rounds aimed at ``PLAN_FACTOR`` x
    the target, then one independent measurement (``measurement_round``) whose tally is the result's. A
    meter whose planning found nothing (every texel 0, after DARK_FLOOR samples where ``may_be_lit`` and
    no ``target_abs``) takes no measurement (``dark_meters``). ``samples`` counts both stages.
    """
    import time

    clock = clock or time.perf_counter
    started = clock()
    tally = MeterTally(count, table_patterns=table_patterns)
    costs = []  # (samples, seconds) per round: time model seconds = a + b * samples

    def run(spp, blocks, into=None):
        t0 = clock()
        idx, scalar, rgb = bake(int(spp), np.asarray(blocks, int))
        costs.append((float(np.sum(blocks)) * BLOCK_TEXELS ** 2 * spp, clock() - t0))
        (tally if into is None else into).add(idx, spp, scalar, rgb)

    def time_model():
        s, t = np.array(costs).T
        if len(costs) == 1 or np.ptp(s) == 0:
            return 0.5 * t.mean(), 0.5 * t.mean() / max(s.mean(), 1.0)  # one point: split it evenly
        b = max(np.polyfit(s, t, 1)[0], 1e-12)
        return max(float(np.mean(t - b * s)), 0.0), b

    def report(fraction, seconds_left):
        if progress is not None:
            progress(min(max(fraction, 0.0), 1.0), max(seconds_left, 0.0))

    if fixed_samples is not None:
        spp = int(min(MAX_SPP, max(1, fixed_samples // (MIN_BLOCKS * BLOCK_TEXELS ** 2))))
        blocks = max(MIN_BLOCKS, int(np.ceil(fixed_samples / (spp * BLOCK_TEXELS ** 2))))
        report(0.0, 0.0)
        run(spp, np.full(count, blocks))
        report(1.0, 0.0)
        return AllocationResult(tally, 1, clock() - started, True, "fixed budget", tally.n.copy())

    staged = bool(staged) and target is not None and time_budget is None
    target_abs = None if target_abs is None else np.broadcast_to(np.asarray(target_abs, float), (count,))
    spp = PILOT_SPP
    run(spp, np.full(count, pilot_blocks(count)))
    if min_samples is not None and not staged:  # staged: the floor is the measurement's (issue 32)
        floor_spp, floor_blocks = floor_round(tally, min_samples, max_samples)
        if floor_blocks.any():
            run(floor_spp, floor_blocks)
    reached, stopped = False, "round limit"
    goal = target
    plan_factor = PLAN_FACTOR if staged else 1.0
    # Issue 31: with an absolute floor, a meter whose pilot found no light stops there (its reading states
    # a one-sided bound, ``dark_meters``) instead of chasing DARK_FLOOR samples, when asked (stop_dark).
    plan_lit = None if target_abs is not None and stop_dark else may_be_lit
    if stop_dark == "all" and target_abs is not None and dark_meters(tally, may_be_lit).any():
        # the caller reads these meters another way when any of them is dark (a sun study's low sun): the other
        # meters' rounds would be spent for nothing
        return AllocationResult(tally, len(costs), clock() - started, False, DARK_PILOT, tally.n.copy())
    for _round in range(max_rounds):
        elapsed = clock() - started
        if time_budget is not None and elapsed >= time_budget:
            stopped = "time budget"
            break
        if target is None:
            # Time budget alone: aim each round at the error the remaining time can buy for the
            # worst meter (equal relative errors), by the same texel-variance model.
            a, b = time_model()
            left = max((time_budget - elapsed - a) / b, 0.0)
            rel = tally.rel_std_error(offset)
            finite = rel[np.isfinite(rel) & (rel > 0)]
            if not finite.size or left < 1.0:
                stopped = "time budget" if finite.size else "converged"
                break
            n_now = tally.n.sum()
            goal = float(np.max(finite)) * np.sqrt(n_now / (n_now + left))
        else:
            goal = effective_target(target * plan_factor, None if target_abs is None else target_abs * plan_factor,
                                    tally, offset)
        previous = spp
        many = plan_round(tally, goal, previous, offset, max_samples=max_samples, may_be_lit=plan_lit)
        sds = PLAN_SPREAD_SDS_MANY if np.count_nonzero(many) >= MANY_METERS else PLAN_SPREAD_SDS
        spp = choose_spp(tally, goal, spp, offset, max_samples=max_samples, may_be_lit=plan_lit, spread_sds=sds)
        blocks = plan_round(tally, goal, spp, offset, max_samples=max_samples, may_be_lit=plan_lit,
                            spread_sds=sds)
        if not blocks.any():
            reached, stopped = True, "target reached" if target is not None else "converged"
            break
        side, known = None, None
        _v, s_last, _alpha, measured = tally.texel_variance_model()
        unmeasured = s_last[(blocks > 0) & ~measured & (s_last > 0)]
        if time_budget is None and unmeasured.size:
            values, counts = np.unique(unmeasured, return_counts=True)
            known = int(values[np.argmax(counts)])  # the spp those meters' variance was measured at
            if known != spp:
                side = known_spp_share(tally, goal, known, blocks, spp, offset, max_samples=max_samples,
                                       may_be_lit=plan_lit, spread_sds=sds)
            if side is not None:
                blocks = np.where(side > 0, 0, blocks)
        planned = float(blocks.sum()) * BLOCK_TEXELS ** 2 * spp
        planned += 0.0 if side is None else float(side.sum()) * BLOCK_TEXELS ** 2 * known
        if target is not None and planned < SMALL_ROUND * tally.n.sum():
            def doubled(b, s):
                return np.minimum(2 * b, np.maximum(b, np.floor((max_samples - tally.n) / (
                    s * BLOCK_TEXELS ** 2)).astype(int)))

            blocks = doubled(blocks, spp)
            planned = float(blocks.sum()) * BLOCK_TEXELS ** 2 * spp
            if side is not None:
                side = doubled(side, known)
                planned += float(side.sum()) * BLOCK_TEXELS ** 2 * known
        if time_budget is not None:
            a, b = time_model()
            affordable = (time_budget - elapsed - a) / b
            if affordable < planned:
                if affordable < 0.1 * planned:
                    stopped = "time budget"
                    break
                blocks = np.maximum((blocks * affordable / planned).astype(int), np.where(blocks > 0, 1, 0))
                planned = float(blocks.sum()) * BLOCK_TEXELS ** 2 * spp
            cap = BUDGET_GROWTH * max(samples for samples, _seconds in costs)
            if planned > cap:
                blocks = np.maximum((blocks * cap / planned).astype(int), np.where(blocks > 0, 1, 0))
                planned = float(blocks.sum()) * BLOCK_TEXELS ** 2 * spp
        a, b = time_model()
        report(tally.n.sum() / (tally.n.sum() + planned), a + b * planned)
        if side is not None:
            run(known, side)
        if blocks.any():
            run(spp, blocks)
        else:
            spp = previous  # every meter took the known-spp share: the next step grows from there
    if staged:
        return _measure(run, tally, count, target, target_abs, offset, max_samples, min_samples, started, clock,
                        report)
    report(1.0, 0.0)
    if target is not None:
        reached = bool(np.all(tally.rel_std_error(offset) <= effective_target(target, target_abs, tally, offset)))
        if reached:
            stopped = "target reached"
    return AllocationResult(tally, len(tally.rounds), clock() - started, reached, stopped, tally.n.copy())


def _measure(run, plan, count, target, target_abs, offset, max_samples, min_samples, started, clock, report):
    """The measurement stage of ``allocate`` (issue 32): one independent measurement sized from the
    planning tally ``plan`` alone; a meter whose measurement misses the target takes one fresh one in
    its place (``MEASURE_TRIES``). Returns the AllocationResult of the measurement's tally."""
    spent = plan.n.copy()
    all_zero = (plan.mean == 0.0) & (plan.std_error == 0.0)
    floor = np.zeros(count) if min_samples is None else np.asarray(min_samples, float)
    skip = all_zero & (floor <= plan.n)  # found nothing, and no sample floor asks for more: stop (dark)
    sds = PLAN_SPREAD_SDS_MANY if count >= MANY_METERS else PLAN_SPREAD_SDS
    tally = MeterTally(count, table_patterns=plan.table_patterns)
    report(plan.n.sum() / max(plan.n.sum() * (1 + PLAN_FACTOR ** 2), 1.0), 0.0)
    goal = effective_target(target, target_abs, plan, offset)
    spp, blocks = measurement_round(plan, goal, offset, max_samples, floor, sds, skip)
    run_measurement(lambda s, b: run(s, b, tally), count, spp, blocks)
    rounds = len(plan.rounds) + len(tally.rounds)
    spent += tally.n
    for _try in range(1, MEASURE_TRIES):
        goal = effective_target(target, target_abs, tally, offset)
        missed = (blocks > 0) & (tally.rel_std_error(offset) > goal) & (tally.n < max_samples)
        if not missed.any():
            break
        again = MeterTally(count, table_patterns=plan.table_patterns)
        spp2, blocks2 = measurement_round(tally, goal, offset, max_samples, floor, sds, ~missed)
        run_measurement(lambda s, b: run(s, b, again), count, spp2, blocks2)
        rounds += len(again.rounds)
        spent += again.n
        kept = _masked(tally, ~missed)
        kept.rounds += again.rounds
        tally, blocks = kept, np.where(missed, blocks2, blocks)
    report(1.0, 0.0)
    reached = bool(np.all(skip | (tally.rel_std_error(offset) <= effective_target(target, target_abs, tally, offset))))
    stopped = "target reached" if reached else "target missed by the measurement (stated as measured)"
    return AllocationResult(tally, rounds, clock() - started, reached, stopped, spent, planning_samples=plan.n.copy())

//! How the F-only timing takes its samples, as pure functions over a [`PassClock`] (the GPU
//! in [`crate::timing::Stopwatch`], a model of a device and its timer in
//! [`SimulatedClock`]); the browser bench's script (`web/bench.js`) twins these rules.
//!
//! - **Amplified samples.** A timed pass evaluates the Fresnel method `evaluations` times
//!   per pixel (`fs_ramp` of `shaders/fresnel_pass.wgsl` repeats `shade` at c, c + φ,
//!   c + 2φ … mod 1 and writes the mean, so every repeat is live). At warm-up (after one
//!   cold round, whose first uses of each pipeline measure nothing) the count grows until the cheapest Fresnel method's pass spans [`SPAN_OVER_RESOLUTION`] × the
//!   timer's resolution, [`SPAN_OVER_FLOOR`] × a wall timer's floor (an empty submit's round
//!   trip) and [`MIN_SAMPLE_MS`] (so the fixed cost of a pass — clear, set-up, store — is
//!   small beside the work): a pass that takes 0.05 ms on a desktop GPU or 0.3 ms on a phone
//!   is then resolved by a timer quantised to 100 µs.
//! - **The timer's resolution** is estimated from the raw readings: the greatest common
//!   divisor of the differences between every reading taken and the first (a timer
//!   quantised to q reads multiples of q; a fine timer's readings share no divisor beyond
//!   its tick), never below the nominal tick.
//! - **Unbiased order.** Each round visits the (material, method) pairs in an order drawn
//!   from a seeded generator (SplitMix64, Steele et al. 2014; Fisher–Yates shuffle), the
//!   seed recorded; each submit opens with an untimed throwaway pass, so no pair is always
//!   the first, slower, pass of a submit.
//! - **Warm-up until settled.** After the scene's warm-up rounds, untimed rounds go on while
//!   the last one is still clearly faster than the ones before it ([`settled`]: its total
//!   below [`SETTLED`] × the median total of the [`SETTLE_WINDOW`] rounds before it), at most
//!   [`MAX_EXTRA_WARMUP`] more: a CPU rasteriser (SwiftShader) still compiles and warms its
//!   caches for several rounds after a short warm-up, and a median over rounds that are half
//!   cold is no measure. On a GPU that is warm after the first round it adds none.
//! - **Statistics.** Every sample is kept; per pair the mean, median, interquartile range
//!   and count, the cost per F evaluation per pixel (ns), and a flag when the median is
//!   within [`NEAR_RESOLUTION`] × the resolution or [`NEAR_FLOOR`] × a wall timer's floor
//!   (the floor is a fixed overhead in every reading, not a quantum: within twice the floor
//!   at least half the reading is the round trip; an amplified sample spans
//!   [`SPAN_OVER_FLOOR`] × the floor, so a floor measured under load that differs between
//!   calibration and timing does not flag it).

use anyhow::Result;

/// A sample must span at least this many timer resolutions.
pub const SPAN_OVER_RESOLUTION: f64 = 100.0;
/// A wall-timed sample must span at least this many empty round trips (the floor).
pub const SPAN_OVER_FLOOR: f64 = 10.0;
/// A sample spans at least this long whatever the timer (the pass's fixed cost amortised).
pub const MIN_SAMPLE_MS: f64 = 2.0;
/// A median within this many resolutions is flagged.
pub const NEAR_RESOLUTION: f64 = 10.0;
/// A wall-timed median within this many floors (empty round trips) is flagged.
pub const NEAR_FLOOR: f64 = 2.0;
/// The largest amplification tried.
pub const MAX_EVALUATIONS: u32 = 1 << 16;
/// Calibration rounds at most (each multiplies the amplification by 2 to 64).
pub const MAX_CALIBRATION_ROUNDS: usize = 12;
/// A warm-up round whose total is below this fraction of the recent rounds' median is
/// still getting faster ([`settled`]).
pub const SETTLED: f64 = 0.95;
/// The rounds before the last that [`settled`] compares it with.
pub const SETTLE_WINDOW: usize = 3;
/// Untimed rounds added at most beyond the scene's warm-up.
pub const MAX_EXTRA_WARMUP: u32 = 30;
/// The seed of the pair order when none is given.
pub const DEFAULT_SEED: u64 = nklut_effects::scene::DEFAULT_TIMING_SEED;

/// One timed pass: the timer's raw readings at its start and end, in nanoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawSample {
    pub start_ns: u64,
    pub end_ns: u64,
}

impl RawSample {
    pub fn ms(self) -> f64 {
        self.end_ns.saturating_sub(self.start_ns) as f64 / 1e6
    }
}

/// What times a pass: one submit that opens with an untimed throwaway pass, then times
/// pair `pair` evaluating `evaluations` times per pixel.
pub trait PassClock {
    fn pass(&mut self, pair: usize, evaluations: u32) -> Result<RawSample>;
    /// The timer's nominal tick in ns (the timestamp period; 1 for a nanosecond clock).
    fn tick_ns(&self) -> f64;
    /// The smallest time a pass can read (ms): an empty submit's round trip for a wall
    /// timer, 0 for timestamps.
    fn floor_ms(&mut self) -> Result<f64>;
}

/// Whether warm-up rounds whose totals (ms, in the order run) are `totals` have settled:
/// fewer than two rounds, or the last not below [`SETTLED`] × the median of the (at most
/// [`SETTLE_WINDOW`]) rounds before it.
pub fn settled(totals: &[f64]) -> bool {
    let Some((&last, before)) = totals.split_last() else { return true };
    if before.is_empty() {
        return true;
    }
    let mut recent: Vec<f64> = before[before.len().saturating_sub(SETTLE_WINDOW)..].to_vec();
    recent.sort_by(f64::total_cmp);
    let n = recent.len();
    let median = if n % 2 == 1 { recent[n / 2] } else { 0.5 * (recent[n / 2 - 1] + recent[n / 2]) };
    last >= SETTLED * median
}

/// Greatest common divisor.
fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The timer's resolution (ns) estimated from its raw readings: the greatest common divisor
/// of every reading's difference from the first, at least `tick_ns`. `None` while every
/// reading is equal (nothing seen to resolve yet).
pub fn resolution_ns(readings: &[u64], tick_ns: f64) -> Option<f64> {
    let first = *readings.first()?;
    let divisor = readings.iter().fold(0, |g, &r| gcd(g, r.abs_diff(first)));
    (divisor > 0).then(|| (divisor as f64).max(tick_ns))
}

/// The span a sample must reach (ms) for a timer of `resolution_ns` and `floor_ms`.
pub fn target_ms(resolution_ns: f64, floor_ms: f64) -> f64 {
    (SPAN_OVER_RESOLUTION * resolution_ns / 1e6).max(SPAN_OVER_FLOOR * floor_ms).max(MIN_SAMPLE_MS)
}

/// The next amplification after a round whose cheapest pass read `cheapest_ms` against
/// `target` (ms): enough to reach it with a 20 % margin, at least ×2, at most ×64
/// (×64 when the pass read 0: below the resolution).
pub fn next_evaluations(evaluations: u32, cheapest_ms: f64, target: f64) -> u32 {
    let factor = if cheapest_ms > 0.0 { (1.2 * target / cheapest_ms).ceil().clamp(2.0, 64.0) } else { 64.0 };
    ((evaluations as f64 * factor) as u64).min(MAX_EVALUATIONS as u64) as u32
}

/// SplitMix64 (Steele, Lea & Flood 2014): the pair order's generator.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform integer in 0..n (n > 0), by the high bits of a 64 × 64 → 128 product.
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }

    /// 0..n in a Fisher–Yates order.
    pub fn permutation(&mut self, n: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            order.swap(i, self.below(i + 1));
        }
        order
    }
}

/// What each pair is: a Fresnel method (the amplification is chosen on the cheapest of
/// them) or a baseline (constant, bare fetch), which a compiler may fold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairKind {
    pub baseline: bool,
}

/// Warm-up rounds and timed rounds, as the scene's `timing` says; `amplify` false keeps one
/// evaluation per pixel (the single-draw design, for comparison).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plan {
    pub warmup: u32,
    pub repeats: u32,
    pub amplify: bool,
    pub seed: u64,
}

/// The samples of every pair and how they were taken.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// F evaluations per pixel in every timed pass.
    pub evaluations: u32,
    /// The timer's resolution estimated from every reading taken (ns); the nominal tick
    /// when every reading was equal.
    pub resolution_ns: f64,
    /// The wall timer's floor (ms), 0 with timestamps.
    pub floor_ms: f64,
    /// The span the cheapest Fresnel method's pass had to reach (ms), and whether the
    /// amplification stopped at [`MAX_EVALUATIONS`] or the calibration rounds before it.
    pub target_ms: f64,
    pub capped: bool,
    /// The amplifications tried at warm-up, with the cheapest Fresnel pass each read (ms).
    pub calibration: Vec<(u32, f64)>,
    /// The untimed rounds run at the chosen amplification: the scene's warm-up and those
    /// added until [`settled`].
    pub warmup_rounds: u32,
    pub seed: u64,
    /// Per pair, the timed samples in ms (every one kept).
    pub samples: Vec<Vec<f64>>,
}

/// What one round read (ms): its cheapest Fresnel pass and the sum of all its passes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RoundTimes {
    cheapest: f64,
    total: f64,
}

/// One round: every pair once in `order`, its samples pushed when `keep`; the raw readings
/// collected.
fn round(
    clock: &mut dyn PassClock,
    order: &[usize],
    evaluations: u32,
    kinds: &[PairKind],
    readings: &mut Vec<u64>,
    mut keep: Option<&mut Vec<Vec<f64>>>,
) -> Result<RoundTimes> {
    let mut times = RoundTimes { cheapest: f64::INFINITY, total: 0.0 };
    for &pair in order {
        let raw = clock.pass(pair, evaluations)?;
        readings.extend([raw.start_ns, raw.end_ns]);
        if !kinds[pair].baseline || kinds.iter().all(|k| k.baseline) {
            times.cheapest = times.cheapest.min(raw.ms());
        }
        times.total += raw.ms();
        if let Some(samples) = keep.as_deref_mut() {
            samples[pair].push(raw.ms());
        }
    }
    Ok(times)
}

/// Time every pair of `kinds` on `clock` by `plan`: calibration rounds choosing the
/// amplification (when `plan.amplify`), `plan.warmup` untimed rounds at it, then
/// `plan.repeats` timed rounds, each in its own seeded order.
pub fn measure(clock: &mut dyn PassClock, kinds: &[PairKind], plan: &Plan) -> Result<Measurement> {
    let mut rng = SplitMix64::new(plan.seed);
    let mut readings = Vec::new();
    let floor_ms = clock.floor_ms()?;
    let mut evaluations = 1;
    let mut calibration = Vec::new();
    let mut capped = false;
    let mut target = target_ms(clock.tick_ns(), floor_ms);
    if plan.amplify && !kinds.is_empty() {
        // A cold round first: a pipeline's first use (compilation, caches) is no measure.
        let order = rng.permutation(kinds.len());
        round(clock, &order, evaluations, kinds, &mut readings, None)?;
        for attempt in 0.. {
            let order = rng.permutation(kinds.len());
            let cheapest = round(clock, &order, evaluations, kinds, &mut readings, None)?.cheapest;
            calibration.push((evaluations, cheapest));
            let resolution = resolution_ns(&readings, clock.tick_ns()).unwrap_or(f64::INFINITY);
            target = target_ms(resolution, floor_ms);
            // A pass reading exactly 0 is below the resolution whatever the estimate says.
            if cheapest >= target && cheapest > 0.0 {
                break;
            }
            if evaluations >= MAX_EVALUATIONS || attempt + 1 >= MAX_CALIBRATION_ROUNDS {
                capped = true;
                break;
            }
            evaluations = next_evaluations(evaluations, cheapest, if target.is_finite() { target } else { MIN_SAMPLE_MS });
        }
    }
    let mut totals = Vec::new();
    while (totals.len() as u32) < plan.warmup || (!settled(&totals) && (totals.len() as u32) < plan.warmup + MAX_EXTRA_WARMUP) {
        let order = rng.permutation(kinds.len());
        totals.push(round(clock, &order, evaluations, kinds, &mut readings, None)?.total);
    }
    let warmup_rounds = totals.len() as u32;
    let mut samples = vec![Vec::with_capacity(plan.repeats as usize); kinds.len()];
    for _ in 0..plan.repeats {
        let order = rng.permutation(kinds.len());
        round(clock, &order, evaluations, kinds, &mut readings, Some(&mut samples))?;
    }
    let resolution_ns = resolution_ns(&readings, clock.tick_ns()).unwrap_or(clock.tick_ns());
    if !plan.amplify {
        target = target_ms(resolution_ns, floor_ms);
    }
    Ok(Measurement {
        evaluations,
        resolution_ns,
        floor_ms,
        target_ms: target,
        capped,
        calibration,
        warmup_rounds,
        seed: plan.seed,
        samples,
    })
}

/// The statistics of one pair's samples.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleStats {
    pub n: usize,
    pub mean_ms: f64,
    pub median_ms: f64,
    pub spread_ms: f64,
    /// Median pass time per F evaluation per pixel (ns).
    pub ns_per_evaluation: f64,
    /// The median is within [`NEAR_RESOLUTION`] × the resolution or [`NEAR_FLOOR`] × the wall
    /// floor.
    pub near_resolution: bool,
}

/// The median (ms) at or below which a pair is flagged as not resolved.
pub fn near_ms(resolution_ns: f64, floor_ms: f64) -> f64 {
    (NEAR_RESOLUTION * resolution_ns / 1e6).max(NEAR_FLOOR * floor_ms)
}

/// Statistics of `samples` taken at `evaluations` per pixel over `pixels` pixels.
pub fn stats(samples: &[f64], evaluations: u32, pixels: u64, measurement: &Measurement) -> SampleStats {
    let (median_ms, spread_ms) = nklut_pipeline::stats::median_and_iqr(samples);
    let n = samples.len();
    let mean_ms = if n == 0 { f64::NAN } else { samples.iter().sum::<f64>() / n as f64 };
    let near = near_ms(measurement.resolution_ns, measurement.floor_ms);
    SampleStats {
        n,
        mean_ms,
        median_ms,
        spread_ms,
        ns_per_evaluation: median_ms * 1e6 / (evaluations as f64 * pixels.max(1) as f64),
        // A NaN median (no samples) is not resolved either.
        near_resolution: median_ms.is_nan() || median_ms <= near,
    }
}

/// A device and its timer as a model: pair `i` costs `cost_ns[i]` per evaluation per pixel
/// over `pixels` pixels plus `fixed_ns` per pass; the first pass of a submit costs
/// `first_pass_ns` more; readings are floored to multiples of `quantum_ns`; a wall timer's
/// empty round trip is `floor_ns` (and no pass reads less). A deterministic jitter of up to
/// `jitter` (relative) comes from a seeded generator.
#[derive(Clone, Debug)]
pub struct SimulatedClock {
    pub cost_ns: Vec<f64>,
    pub pixels: u64,
    pub fixed_ns: f64,
    pub first_pass_ns: f64,
    pub quantum_ns: u64,
    pub floor_ns: u64,
    pub jitter: f64,
    /// The model's time now (ns).
    pub now_ns: u64,
    pub rng: SplitMix64,
    /// With no throwaway pass (the old design) the timed pass is the first of its submit.
    pub throwaway: bool,
    /// A device still warming up: the first `cold_passes` passes cost up to
    /// (1 + `cold_factor`) × their work, the excess falling linearly to 0.
    pub cold_passes: u64,
    pub cold_factor: f64,
    /// Passes timed so far.
    pub passes: u64,
}

impl SimulatedClock {
    pub fn new(cost_ns: Vec<f64>, pixels: u64, quantum_ns: u64) -> Self {
        SimulatedClock {
            cost_ns,
            pixels,
            fixed_ns: 0.0,
            first_pass_ns: 0.0,
            quantum_ns: quantum_ns.max(1),
            floor_ns: 0,
            jitter: 0.02,
            now_ns: 1_000_003_917,
            rng: SplitMix64::new(7),
            throwaway: true,
            cold_passes: 0,
            cold_factor: 0.0,
            passes: 0,
        }
    }

    fn read(&self, t: u64) -> u64 {
        t - t % self.quantum_ns
    }
}

impl PassClock for SimulatedClock {
    fn pass(&mut self, pair: usize, evaluations: u32) -> Result<RawSample> {
        let noise = 1.0 + self.jitter * (self.rng.next_u64() as f64 / u64::MAX as f64 - 0.5);
        let first = if self.throwaway { 0.0 } else { self.first_pass_ns };
        let cold = 1.0 + self.cold_factor * (1.0 - self.passes as f64 / self.cold_passes.max(1) as f64).max(0.0);
        self.passes += 1;
        let work = (self.fixed_ns + first + self.cost_ns[pair] * evaluations as f64 * self.pixels as f64) * noise * cold;
        // The throwaway pass (its first-pass penalty included) runs before the timed one.
        if self.throwaway {
            self.now_ns += (self.fixed_ns + self.first_pass_ns) as u64;
        }
        let start = self.now_ns;
        let end = start + (work as u64).max(self.floor_ns);
        self.now_ns = end + 1_337;
        Ok(RawSample { start_ns: self.read(start), end_ns: self.read(end) })
    }

    fn tick_ns(&self) -> f64 {
        1.0
    }

    fn floor_ms(&mut self) -> Result<f64> {
        Ok(self.read(self.floor_ns) as f64 / 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_resolution_is_the_common_divisor_of_the_readings() {
        // Readings quantised to 100 µs: multiples of 100 000 ns from an offset.
        let quantised = [5_300_000, 5_400_000, 5_700_000, 6_100_000];
        assert_eq!(resolution_ns(&quantised, 1.0), Some(100_000.0));
        // Two readings 2 quanta apart only: the estimate is an upper bound, 200 µs.
        assert_eq!(resolution_ns(&[0, 200_000], 1.0), Some(200_000.0));
        // A fine clock: 1 ns, but never below the nominal tick.
        assert_eq!(resolution_ns(&[1000, 1003, 1010], 1.0), Some(1.0));
        assert_eq!(resolution_ns(&[1000, 1003, 1010], 52.08), Some(52.08));
        assert_eq!(resolution_ns(&[7, 7, 7], 1.0), None);
        assert_eq!(resolution_ns(&[], 1.0), None);
    }

    #[test]
    fn the_target_span_is_the_largest_of_its_three_rules() {
        assert_eq!(target_ms(100_000.0, 0.0), 10.0); // 100 × 100 µs
        assert_eq!(target_ms(1.0, 0.0), MIN_SAMPLE_MS);
        assert_eq!(target_ms(1.0, 2.5), 25.0); // 10 × a 2.5 ms round trip
        assert_eq!(next_evaluations(1, 0.0, 10.0), 64);
        assert_eq!(next_evaluations(4, 1.0, 10.0), 48); // ceil(12) = 12 → 4 × 12
        assert_eq!(next_evaluations(4, 9.0, 10.0), 8); // at least × 2
        assert_eq!(next_evaluations(MAX_EVALUATIONS / 2, 0.0, 10.0), MAX_EVALUATIONS);
    }

    #[test]
    fn the_order_is_a_seeded_permutation_that_moves_every_pair() {
        // SplitMix64's first outputs for seed 0 (Vigna's reference splitmix64.c).
        let mut rng = SplitMix64::new(0);
        assert_eq!(rng.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(rng.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        let mut rng = SplitMix64::new(DEFAULT_SEED);
        let mut first = [0usize; 6];
        for _ in 0..600 {
            let order = rng.permutation(6);
            let mut sorted = order.clone();
            sorted.sort();
            assert_eq!(sorted, [0, 1, 2, 3, 4, 5]);
            first[order[0]] += 1;
        }
        // Each pair leads about 100 of 600 rounds.
        assert!(first.iter().all(|&n| (60..140).contains(&n)), "{first:?}");
        let again: Vec<_> = (0..3).map(|_| SplitMix64::new(5).permutation(9)).collect();
        assert!(again.windows(2).all(|w| w[0] == w[1]), "the same seed, the same order");
    }

    /// Pair costs per evaluation per pixel (ns): exact, schlick, lazanyi, constant.
    const COSTS: [f64; 4] = [40.0, 10.0, 14.0, 2.0];
    const KINDS: [PairKind; 4] =
        [PairKind { baseline: false }, PairKind { baseline: false }, PairKind { baseline: false }, PairKind { baseline: true }];

    /// A phone-like pass through a browser's 100 µs timer: 256 pixels at 10–40 ns plus
    /// 30 µs of fixed cost, so one single-evaluation pass (33–40 µs) is ≪ the quantum.
    fn short_pass(quantum_ns: u64, floor_ns: u64) -> SimulatedClock {
        let mut clock = SimulatedClock::new(COSTS.to_vec(), 256, quantum_ns);
        clock.fixed_ns = 30_000.0;
        clock.floor_ns = floor_ns;
        clock
    }

    fn ratios(m: &Measurement) -> Vec<f64> {
        let exact = stats(&m.samples[0], m.evaluations, 256, m).median_ms;
        m.samples.iter().map(|s| stats(s, m.evaluations, 256, m).median_ms / exact).collect()
    }

    /// Tolerance of an amplified ratio against the true cost ratio (COSTS[i] / COSTS[0]).
    const TOLERANCE: f64 = 0.03;

    #[test]
    fn amplified_ratios_survive_a_quantised_timer_and_single_passes_do_not() {
        let plan = Plan { warmup: 1, repeats: 9, amplify: true, seed: DEFAULT_SEED };
        let truth: Vec<f64> = COSTS.iter().map(|c| c / COSTS[0]).collect();
        for (quantum, floor) in [(100_000, 0), (100_000, 312_500), (1, 0)] {
            let m = measure(&mut short_pass(quantum, floor), &KINDS, &plan).unwrap();
            // The resolution is found from the readings alone.
            let expected_resolution = if quantum > 1 { quantum as f64 } else { 1.0 };
            assert_eq!(m.resolution_ns, expected_resolution, "quantum {quantum}");
            assert!(!m.capped && m.evaluations > 1, "{m:?}");
            let cheapest = stats(&m.samples[1], m.evaluations, 256, &m);
            assert!(cheapest.median_ms >= SPAN_OVER_RESOLUTION * m.resolution_ns / 1e6, "{cheapest:?}");
            assert!(!cheapest.near_resolution);
            for (i, (r, t)) in ratios(&m).iter().zip(&truth).enumerate().take(3) {
                assert!((r - t).abs() <= TOLERANCE, "quantum {quantum} floor {floor} pair {i}: {r} against {t}");
            }
            // ns per evaluation per pixel: the model's cost, the fixed cost amortised.
            let ns = stats(&m.samples[0], m.evaluations, 256, &m).ns_per_evaluation;
            assert!((ns / COSTS[0] - 1.0).abs() < 0.05, "{ns}");
            assert_eq!(m.samples.iter().map(Vec::len).collect::<Vec<_>>(), [9; 4]);
        }
        // The old design: one evaluation per pass. Through 100 µs every median reads 0 or
        // one quantum (ratios 0, 1 or NaN); through the wall floor every method reads the
        // floor (all ratios 1); both far from the truth and flagged.
        let single = Plan { amplify: false, ..plan };
        for (quantum, floor) in [(100_000, 0), (100_000, 312_500)] {
            let m = measure(&mut short_pass(quantum, floor), &KINDS, &single).unwrap();
            assert_eq!(m.evaluations, 1);
            let worst =
                ratios(&m).iter().zip(&truth).map(|(r, t)| if r.is_finite() { (r - t).abs() } else { f64::INFINITY }).fold(0.0, f64::max);
            assert!(worst > 0.5, "quantum {quantum} floor {floor}: {:?}", ratios(&m));
            assert!(stats(&m.samples[0], 1, 256, &m).near_resolution);
        }
    }

    #[test]
    fn the_throwaway_pass_takes_the_first_pass_penalty_off_every_pair() {
        // Two pairs of equal cost and a first pass 30 % slower: without a throwaway pass and
        // in a fixed order, one always ran first; here each submit's throwaway takes it.
        let mut clock = SimulatedClock::new(vec![10.0, 10.0], 100_000, 1);
        clock.first_pass_ns = 300_000.0;
        let plan = Plan { warmup: 0, repeats: 15, amplify: true, seed: 3 };
        let kinds = [PairKind { baseline: false }; 2];
        let m = measure(&mut clock, &kinds, &plan).unwrap();
        let ratio = stats(&m.samples[0], 1, 1, &m).median_ms / stats(&m.samples[1], 1, 1, &m).median_ms;
        assert!((ratio - 1.0).abs() < 0.02, "{ratio}");
    }

    #[test]
    fn settled_compares_the_last_round_with_the_median_of_the_three_before() {
        assert!(settled(&[]) && settled(&[5.0]));
        // Median of (10, 9, 8) is 9: 8.56 is 0.951 × 9, settled; 8.5 is 0.944 ×, not.
        assert!(settled(&[12.0, 10.0, 9.0, 8.0, 8.56]));
        assert!(!settled(&[12.0, 10.0, 9.0, 8.0, 8.5]));
        // Two rounds: the one before is the median.
        assert!(!settled(&[10.0, 9.4]) && settled(&[10.0, 9.6]));
        // Slower is settled (a noisy round, not a warming one).
        assert!(settled(&[10.0, 10.0, 10.0, 14.0]));
    }

    #[test]
    fn warm_up_goes_on_until_a_warming_device_has_settled() {
        // Six pairs of equal cost on a device whose passes cost up to 2× for its first
        // 12 rounds (72 passes), the excess falling linearly: with the scene's 3 warm-up
        // rounds alone, 9 of 15 timed rounds would be cold and every median ≈ 1.2× the warm
        // cost. Settling adds rounds until a round is no longer 5 % faster than the median
        // of the three before it.
        let warm_ns = 1e6;
        let mut clock = SimulatedClock::new(vec![warm_ns / 100.0; 6], 100, 1);
        (clock.cold_passes, clock.cold_factor) = (72, 1.0);
        let plan = Plan { warmup: 3, repeats: 15, amplify: false, seed: 5 };
        let m = measure(&mut clock, &[PairKind { baseline: false }; 6], &plan).unwrap();
        assert!((11..=3 + MAX_EXTRA_WARMUP).contains(&m.warmup_rounds), "{}", m.warmup_rounds);
        for samples in &m.samples {
            let median = stats(samples, 1, 100, &m).median_ms;
            assert!((median / (warm_ns / 1e6) - 1.0).abs() < 0.03, "median {median} ms against 1 ms warm");
        }
        // A device warm from the start: the scene's warm-up and not one round more (2 %
        // jitter never reads 5 % faster than the median of three).
        let mut clock = SimulatedClock::new(vec![warm_ns / 100.0; 6], 100, 1);
        let m = measure(&mut clock, &[PairKind { baseline: false }; 6], &plan).unwrap();
        assert_eq!(m.warmup_rounds, 3);
    }

    #[test]
    fn a_timer_that_never_moves_caps_the_amplification_and_flags_it() {
        let mut clock = SimulatedClock::new(vec![1e-9; 2], 1, 1_000_000_000_000);
        let m = measure(&mut clock, &[PairKind { baseline: false }; 2], &Plan { warmup: 0, repeats: 2, amplify: true, seed: 1 }).unwrap();
        assert!(m.capped);
        assert!(stats(&m.samples[0], m.evaluations, 1, &m).near_resolution);
    }

    #[test]
    fn the_flag_keeps_a_margin_below_the_span_an_amplified_sample_reaches() {
        // 100 µs timestamps: flagged at or below 1 ms (10 quanta), the target 10 ms.
        assert_eq!(near_ms(100_000.0, 0.0), 1.0);
        assert_eq!(target_ms(100_000.0, 0.0), 10.0);
        // A wall timer with a 0.3125 ms floor and a 100 µs quantum: flagged at or below
        // 2 floors (0.625 ms) — a single draw that reads the floor is flagged — while the
        // target is 10 floors (3.125 ms); a floor that read 3× longer during calibration
        // than during timing (a loaded machine) still leaves the samples 1.67× above it.
        assert_eq!(near_ms(100_000.0, 0.3125), 1.0);
        assert_eq!(near_ms(1.0, 0.3125), 0.625);
        assert_eq!(target_ms(1.0, 0.3125), 3.125);
        assert!(target_ms(1.0, 0.3125) / 3.0 > near_ms(1.0, 0.3125));
        // Before the margin, the flag sat at 10 floors, the target itself.
        assert!(near_ms(1.0, 0.3125) < SPAN_OVER_FLOOR * 0.3125);
    }
}

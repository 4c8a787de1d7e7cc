//! The error integrals of SPEC §6 over θ ∈ [0, π/2], uniform in θ:
//!   mean relative error = ∫ |F_m − F_e|/F_e dθ / ∫ [F_e > 0] dθ,
//!   RMS absolute error  = √(∫ (F_m − F_e)² dθ / (π/2)),
//!   max absolute error  = sup |F_m − F_e|,
//! for a method in f64 and its f32 shader twin at once (both against f64 `exact`).
//!
//! [`brute_force`] is the reference: midpoints θ_j = (j + ½)·(π/2)/M, M = 10⁶.
//! [`adaptive`] is the fast path: globally adaptive Gauss–Kronrod (7/15 points, QUADPACK
//! QAG style) on panels between breakpoints (kinks of the integrand the caller knows:
//! critical angle, clamps, texel centres, steep scales), where every panel on which
//! F_m64 − F_e changes sign between nodes is first split at the root (of the cubic
//! through the neighbouring nodes), so that |·| never puts a kink inside a panel.
//! Many breakpoints (LUTs) use the 3/7-point rule, few the 7/15-point one. Refinement is driven by the f64
//! integrands; the f32 integrands are integrated on the same nodes (their rounding
//! noise is not integrable to 4 digits; see docs/precision.md). The maximum is the
//! largest |F_m − F_e| over all nodes and both ends, refined by golden-section search
//! around the best node.

use std::collections::BinaryHeap;
use std::f64::consts::FRAC_PI_2;

use rayon::prelude::*;

/// One evaluation: exact F and the method in f64 and in f32 (widened).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub exact: f64,
    pub approx: [f64; 2],
}

/// Figures for one precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Figures {
    /// Mean of |F_m − F_e|/F_e over θ where F_e > 0; `None` when F_e = 0 everywhere.
    pub mean_rel_error: Option<f64>,
    pub max_abs_error: f64,
    pub rms_abs_error: f64,
}

/// The result of one integration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Integral {
    /// Index 0: the f64 method; 1: the f32 twin.
    pub figures: [Figures; 2],
    /// Evaluation points where F_e = 0 (excluded from the relative error).
    pub excluded_samples: u64,
    /// Evaluation points (each evaluates exact, the method in f64 and in f32).
    pub evaluations: u64,
}

/// Running sums of the integrands (or of the samples, for the brute force).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sums {
    relative: [f64; 2],
    squared: [f64; 2],
    included: f64,
}

impl Sums {
    fn of(sample: &Sample) -> Self {
        let mut sums = Sums::default();
        let included = sample.exact > 0.0;
        for p in 0..2 {
            let difference = sample.approx[p] - sample.exact;
            sums.squared[p] = difference * difference;
            if included {
                sums.relative[p] = difference.abs() / sample.exact;
            }
        }
        sums.included = if included { 1.0 } else { 0.0 };
        sums
    }

    fn add_scaled(&mut self, other: &Sums, weight: f64) {
        for p in 0..2 {
            self.relative[p] += weight * other.relative[p];
            self.squared[p] += weight * other.squared[p];
        }
        self.included += weight * other.included;
    }

    fn add(&mut self, other: &Sums) {
        self.add_scaled(other, 1.0);
    }
}

/// Largest |F_m − F_e| seen, per precision, with where.
#[derive(Clone, Copy, Debug, Default)]
struct Maximum {
    value: [f64; 2],
    theta: [f64; 2],
}

impl Maximum {
    fn see(&mut self, theta: f64, sample: &Sample) {
        for p in 0..2 {
            let error = (sample.approx[p] - sample.exact).abs();
            if error > self.value[p] {
                self.value[p] = error;
                self.theta[p] = theta;
            }
        }
    }

    fn merge(mut self, other: Maximum) -> Maximum {
        for p in 0..2 {
            if other.value[p] > self.value[p] {
                self.value[p] = other.value[p];
                self.theta[p] = other.theta[p];
            }
        }
        self
    }
}

fn figures(sums: &Sums, length: f64, maximum: &Maximum) -> [Figures; 2] {
    [0, 1].map(|p| Figures {
        mean_rel_error: (sums.included > 0.0).then(|| sums.relative[p] / sums.included),
        max_abs_error: maximum.value[p],
        rms_abs_error: (sums.squared[p] / length).max(0.0).sqrt(),
    })
}

/// The number of midpoints of the reference brute force (SPEC §6).
pub const BRUTE_FORCE_SAMPLES: usize = 1_000_000;

/// Brute force over `samples` θ-midpoints θ_j = (j + ½)·(π/2)/M, in parallel (rayon).
pub fn brute_force(f: &(impl Fn(f64) -> Sample + Sync), samples: usize) -> Integral {
    const CHUNK: usize = 8192;
    let step = FRAC_PI_2 / samples as f64;
    let (sums, maximum, excluded) = (0..samples.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let mut sums = Sums::default();
            let mut maximum = Maximum::default();
            let mut excluded = 0u64;
            for j in chunk * CHUNK..((chunk + 1) * CHUNK).min(samples) {
                let theta = (j as f64 + 0.5) * step;
                let sample = f(theta);
                excluded += u64::from(!(sample.exact > 0.0));
                sums.add(&Sums::of(&sample));
                maximum.see(theta, &sample);
            }
            (sums, maximum, excluded)
        })
        .reduce(
            || (Sums::default(), Maximum::default(), 0),
            |mut a, b| {
                a.0.add(&b.0);
                (a.0, a.1.merge(b.1), a.2 + b.2)
            },
        );
    // Midpoint sums: Σ over samples × step = ∫; the means need only the counts.
    Integral {
        figures: figures(&sums, samples as f64, &maximum),
        excluded_samples: excluded,
        evaluations: samples as u64,
    }
}

/// A Gauss–Kronrod rule: Kronrod abscissae on [−1, 1] (descending, last = centre),
/// Kronrod weights, and Gauss weights for the odd-indexed abscissae (centre included).
struct Rule {
    abscissae: &'static [f64],
    kronrod: &'static [f64],
    gauss: &'static [f64],
}

impl Rule {
    fn points(&self) -> usize {
        2 * self.abscissae.len() - 1
    }
}

/// Gauss–Kronrod 7/15 (QUADPACK qk15).
const GK15: Rule = Rule {
    abscissae: &[
        0.991_455_371_120_812_6,
        0.949_107_912_342_758_5,
        0.864_864_423_359_769_1,
        0.741_531_185_599_394_4,
        0.586_087_235_467_691_1,
        0.405_845_151_377_397_2,
        0.207_784_955_007_898_5,
        0.0,
    ],
    kronrod: &[
        0.022_935_322_010_529_22,
        0.063_092_092_629_978_55,
        0.104_790_010_322_250_2,
        0.140_653_259_715_525_9,
        0.169_004_726_639_267_9,
        0.190_350_578_064_785_4,
        0.204_432_940_075_298_9,
        0.209_482_141_084_727_8,
    ],
    gauss: &[0.129_484_966_168_869_7, 0.279_705_391_489_276_7, 0.381_830_050_505_118_9, 0.417_959_183_673_469_4],
};

/// Tolerances of the adaptive path.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Target of Σ|K − G| relative to each f64 integral (relative and squared error).
    pub relative: f64,
    /// Give up refining after this many evaluations.
    pub max_evaluations: u64,
    /// Panels narrower than this (radians) are not split further.
    pub min_width: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Self { relative: 1e-7, max_evaluations: 400_000, min_width: 1e-12 }
    }
}

/// One Gauss–Kronrod panel.
#[derive(Clone, Copy, Debug)]
struct Panel {
    a: f64,
    b: f64,
    kronrod: Sums,
    /// |K − G| of the f64 relative and squared integrands.
    error: [f64; 2],
    /// Where F_m64 − F_e changes sign between nodes (from the local interpolating
    /// cubic): such panels are split there at once.
    crossing: Option<f64>,
    /// The largest f64 |F_m − F_e| at a node and the neighbouring nodes around it.
    peak: (f64, f64, f64),
    /// Priority: error normalised by the integral estimates.
    priority: f64,
}

impl PartialEq for Panel {
    fn eq(&self, other: &Self) -> bool {
        self.priority == other.priority
    }
}
impl Eq for Panel {}
impl PartialOrd for Panel {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Panel {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.priority.total_cmp(&other.priority)
    }
}

struct Adaptive<'a, F: Fn(f64) -> Sample> {
    f: &'a F,
    rule: &'static Rule,
    evaluations: u64,
    excluded: u64,
    maximum: Maximum,
    /// Scratch: the nodes of the panel being evaluated, increasing θ.
    nodes: Vec<(f64, Sample)>,
}

/// Difference f64 method − exact, the sign of which decides the splits.
fn difference(sample: &Sample) -> f64 {
    sample.approx[0] - sample.exact
}

/// The difference is at the level of f64 rounding of F: its sign changes are noise,
/// not crossings worth a split.
fn rounding_level(sample: &Sample) -> bool {
    difference(sample).abs() <= 1e-13 * sample.exact.abs().max(sample.approx[0].abs())
}

/// A root in (x[i], x[i+1]) of the cubic through the nodes i − 1 … i + 2 (fewer at the
/// ends), where the difference changes sign between nodes i and i + 1; by bisection on
/// the polynomial (no further evaluations).
fn interpolated_root(nodes: &[(f64, Sample)], i: usize) -> f64 {
    let lo = i.saturating_sub(1);
    let hi = (i + 2).min(nodes.len() - 1);
    let points: Vec<(f64, f64)> = nodes[lo..=hi].iter().map(|(x, s)| (*x, difference(s))).collect();
    let p = |x: f64| -> f64 {
        points
            .iter()
            .enumerate()
            .map(|(j, &(xj, yj))| {
                yj * points.iter().enumerate().filter(|&(m, _)| m != j).map(|(_, &(xm, _))| (x - xm) / (xj - xm)).product::<f64>()
            })
            .sum()
    };
    let (mut a, mut b) = (nodes[i].0, nodes[i + 1].0);
    let positive_at_a = difference(&nodes[i].1) > 0.0;
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if (p(m) > 0.0) == positive_at_a {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

impl<'a, F: Fn(f64) -> Sample> Adaptive<'a, F> {
    fn eval(&mut self, theta: f64) -> Sample {
        let sample = (self.f)(theta);
        self.evaluations += 1;
        self.excluded += u64::from(!(sample.exact > 0.0));
        self.maximum.see(theta, &sample);
        sample
    }

    /// Evaluate the rule on [a, b].
    fn panel(&mut self, a: f64, b: f64) -> Panel {
        let rule = self.rule;
        let centre = 0.5 * (a + b);
        let half = 0.5 * (b - a);
        let last = rule.abscissae.len() - 1;
        let mut nodes = std::mem::take(&mut self.nodes);
        nodes.clear();
        let mut kronrod = Sums::default();
        let mut gauss = Sums::default();
        // The ends carry no weight but close the sign check: a crossing between the outer
        // node and the end would otherwise go unseen.
        nodes.push((a, self.eval(a)));
        for slot in 0..rule.points() {
            let j = if slot <= last { slot } else { 2 * last - slot };
            let x = if slot <= last { centre - half * rule.abscissae[j] } else { centre + half * rule.abscissae[j] };
            let sample = self.eval(x);
            let sums = Sums::of(&sample);
            kronrod.add_scaled(&sums, rule.kronrod[j] * half);
            if j % 2 == 1 {
                gauss.add_scaled(&sums, rule.gauss[j / 2] * half);
            }
            nodes.push((x, sample));
        }
        nodes.push((b, self.eval(b)));
        let crossing = nodes
            .windows(2)
            .position(|w| difference(&w[0].1) * difference(&w[1].1) < 0.0 && !(rounding_level(&w[0].1) && rounding_level(&w[1].1)))
            .map(|i| interpolated_root(&nodes, i))
            .filter(|&r| r > a && r < b);
        let peak = {
            let (i, value) = nodes
                .iter()
                .enumerate()
                .map(|(i, (_, s))| (i, difference(s).abs()))
                .fold((0, -1.0), |best, x| if x.1 > best.1 { x } else { best });
            let lo = if i == 0 { a } else { nodes[i - 1].0 };
            let hi = nodes.get(i + 1).map_or(b, |n| n.0);
            (value, lo, hi)
        };
        self.nodes = nodes;
        let error = [(kronrod.relative[0] - gauss.relative[0]).abs(), (kronrod.squared[0] - gauss.squared[0]).abs()];
        Panel { a, b, kronrod, error, crossing, peak, priority: 0.0 }
    }

    /// Panels covering [a, b], split at every sign change of the difference found
    /// between nodes, so that no panel has the kink of |F_m − F_e| inside.
    fn settled(&mut self, a: f64, b: f64, max_evaluations: u64, out: &mut Vec<Panel>) {
        let mut stack = vec![(a, b)];
        while let Some((a, b)) = stack.pop() {
            let panel = self.panel(a, b);
            match panel.crossing {
                Some(split) if self.evaluations < max_evaluations && split - a > 1e-12 && b - split > 1e-12 => {
                    stack.push((split, b));
                    stack.push((a, split));
                }
                _ => out.push(panel),
            }
        }
    }
}

/// Adaptive integration over [0, π/2] with the given interior breakpoints (any order,
/// out-of-range and duplicates ignored). Panels are refined worst first (error
/// normalised by the first estimate of each integral) until Σ error ≤ tolerance, by
/// bisection; every new panel is first split where the difference changes sign.
pub fn adaptive(f: &impl Fn(f64) -> Sample, breakpoints: &[f64], tolerance: Tolerance) -> Integral {
    let mut points: Vec<f64> = breakpoints.iter().copied().filter(|t| *t > 0.0 && *t < FRAC_PI_2).collect();
    points.push(0.0);
    points.push(FRAC_PI_2);
    points.sort_by(f64::total_cmp);
    points.dedup_by(|a, b| (*a - *b).abs() <= 1e-14);

    let rule = &GK15;
    let mut state = Adaptive { f, rule, evaluations: 0, excluded: 0, maximum: Maximum::default(), nodes: Vec::with_capacity(15) };
    let mut panels = Vec::with_capacity(2 * points.len());
    for w in points.windows(2) {
        state.settled(w[0], w[1], tolerance.max_evaluations, &mut panels);
    }
    // The maximum can sit on a breakpoint (a kink: texel centre, clamp, critical angle).
    for &theta in &points {
        state.eval(theta);
    }
    let total = |panels: &mut dyn Iterator<Item = &Panel>| {
        panels.fold(Sums::default(), |mut s, p| {
            s.add(&p.kronrod);
            s
        })
    };
    let estimate = total(&mut panels.iter());
    let scale = [estimate.relative[0].abs().max(1e-300), estimate.squared[0].abs().max(1e-300)];
    let priority = |p: &Panel| p.error[0] / scale[0] + p.error[1] / scale[1];
    let mut heap: BinaryHeap<Panel> = panels
        .into_iter()
        .map(|mut p| {
            p.priority = priority(&p);
            p
        })
        .collect();
    let mut error_sum: f64 = heap.iter().map(|p| p.priority).sum();
    let mut refinements = 0u64;
    while error_sum > tolerance.relative && state.evaluations < tolerance.max_evaluations {
        let Some(worst) = heap.pop() else { break };
        error_sum -= worst.priority;
        if worst.b - worst.a <= tolerance.min_width {
            heap.push(Panel { priority: 0.0, ..worst });
            continue;
        }
        let middle = 0.5 * (worst.a + worst.b);
        let mut children = Vec::with_capacity(4);
        state.settled(worst.a, middle, tolerance.max_evaluations, &mut children);
        state.settled(middle, worst.b, tolerance.max_evaluations, &mut children);
        for mut child in children {
            child.priority = priority(&child);
            error_sum += child.priority;
            heap.push(child);
        }
        refinements += 1;
        // Re-sum now and then against drift of the running total.
        if refinements % 256 == 0 {
            error_sum = heap.iter().map(|p| p.priority).sum();
        }
    }
    let mut panels = heap.into_vec();
    let sums = total(&mut panels.iter());
    panels.sort_by(|x, y| y.peak.0.total_cmp(&x.peak.0));
    for panel in panels.iter().take(PEAKS_REFINED) {
        refine_maximum(&mut state, panel.peak.1, panel.peak.2);
    }
    Integral { figures: figures(&sums, FRAC_PI_2, &state.maximum), excluded_samples: state.excluded, evaluations: state.evaluations }
}

/// How many of the largest node errors (one per panel) are refined.
const PEAKS_REFINED: usize = 3;

/// Golden-section search for the largest f64 error in [lo, hi] (between the nodes
/// around a panel's largest node error); every point seen counts for both precisions.
fn refine_maximum<F: Fn(f64) -> Sample>(state: &mut Adaptive<'_, F>, mut lo: f64, mut hi: f64) {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let error = |state: &mut Adaptive<'_, F>, theta: f64| {
        let sample = state.eval(theta);
        (sample.approx[0] - sample.exact).abs()
    };
    let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut e1, mut e2) = (error(state, x1), error(state, x2));
    for _ in 0..40 {
        if e1 >= e2 {
            hi = x2;
            (x2, e2) = (x1, e1);
            x1 = hi - ratio * (hi - lo);
            e1 = error(state, x1);
        } else {
            lo = x1;
            (x1, e1) = (x2, e2);
            x2 = lo + ratio * (hi - lo);
            e2 = error(state, x2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant_error(theta: f64) -> Sample {
        // F_e = 0.5, F_m = 0.5 + 0.1 sin θ: mean rel = 0.2·(2/π)·∫sin = 0.4/π·... see below.
        Sample { exact: 0.5, approx: [0.5 + 0.1 * theta.sin(), 0.5 + 0.1 * theta.sin()] }
    }

    #[test]
    fn smooth_integrand_matches_closed_form() {
        // mean |g|/F = (0.1/0.5)·(1/(π/2))∫₀^{π/2} sin θ dθ = 0.2·2/π.
        // rms = √(0.01·(1/(π/2))∫sin² θ dθ) = √(0.01·½) = 0.0707…
        let i = adaptive(&constant_error, &[], Tolerance::default());
        let expected = 0.4 / std::f64::consts::PI;
        assert!((i.figures[0].mean_rel_error.unwrap() - expected).abs() < 1e-13);
        assert!((i.figures[0].rms_abs_error - 0.005f64.sqrt()).abs() < 1e-13);
        assert!((i.figures[0].max_abs_error - 0.1).abs() < 1e-12);
        assert!(i.evaluations < 200, "{}", i.evaluations);
        let b = brute_force(&constant_error, 100_000);
        assert!((b.figures[0].mean_rel_error.unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn sign_changes_are_split_at_the_root() {
        // F_m − F_e = 0.1 (θ − 1): |·| has a kink at θ = 1.
        let f = |theta: f64| Sample { exact: 1.0, approx: [1.0 + 0.1 * (theta - 1.0); 2] };
        let i = adaptive(&f, &[], Tolerance::default());
        // ∫|θ − 1| over [0, π/2] = ½ + ½(π/2 − 1)².
        let exact = 0.1 * (0.5 + 0.5 * (FRAC_PI_2 - 1.0).powi(2)) / FRAC_PI_2;
        assert!((i.figures[0].mean_rel_error.unwrap() - exact).abs() < 1e-14, "{:?}", i.figures[0]);
        assert!(i.evaluations < 200);
    }

    #[test]
    fn zero_reflectance_is_excluded() {
        let f = |_| Sample { exact: 0.0, approx: [0.0; 2] };
        let i = adaptive(&f, &[], Tolerance::default());
        assert_eq!(i.figures[0].mean_rel_error, None);
        assert_eq!(i.excluded_samples, i.evaluations);
        let b = brute_force(&f, 1000);
        assert_eq!(b.excluded_samples, 1000);
        assert_eq!(b.figures[1].mean_rel_error, None);
    }
}

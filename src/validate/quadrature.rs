//! The error integrals of SPEC §6 over θ ∈ [0, π/2], uniform in θ:
//!   mean relative error = ∫ |F_m − F_e|/F_e dθ / ∫ [F_e > 0] dθ,
//!   RMS absolute error  = √(∫ (F_m − F_e)² dθ / (π/2)),
//!   max absolute error  = sup |F_m − F_e|,
//! for a *family* of methods at once: every member is measured in f64 and in its f32
//! shader twin, all against one f64 `exact`, which is evaluated once per θ and shared
//! (the analytic methods of a channel form one family; the five encodings of one LUT
//! size another).
//!
//! [`brute_force`] is the reference: midpoints θ_j = (j + ½)·(π/2)/M, M = 10⁶.
//!
//! [`adaptive`] is the fast path. The interval is cut at breakpoints the caller knows
//! (kinks of an integrand: texel centres, clamps, the critical angle; steep scales). Each
//! panel gets a [`Rule`] whose nodes include both ends (shared with the neighbours): the
//! 7-point Kronrod rule ([`KRONROD7`], 9 nodes) where panels are few and wide, the
//! 3-point Gauss rule ([`GAUSS3`], 5 nodes) where they are many and narrow (LUT texel
//! intervals, N ≥ 128). On a panel the relative integrand g = (F_m − F_e)/F_e is smooth,
//! but |g| has a kink wherever g changes sign, and for LUTs it changes sign on about half
//! of the texel intervals (quantisation errors of either sign). Instead of splitting
//! there (new evaluations), g is replaced on the panel by its interpolating polynomial p
//! through the nodes; the roots of p are found by regula falsi (Illinois) on p, between
//! nodes of opposite sign and, by a slope bound, between nodes of the same sign where p
//! could dip through zero; ∫|p| is then summed exactly piece by piece from the
//! antiderivative. Panels without a sign change take the rule's sum of g. The squared
//! integrand needs no roots. Error estimates: Kronrod against its embedded Gauss-3 rule,
//! scaled as QUADPACK does; Gauss-3 from the highest coefficient of the interpolant (see
//! [`Estimate`]). Panels are bisected worst first (QUADPACK QAG style) until, for every
//! member, the summed estimate is below the tolerance relative to its integral.
//!
//! Refinement is driven by the f64 integrands. The f32 integrand carries rounding noise,
//! which no quadrature integrates to 4 digits (docs/precision.md): where its sign agrees
//! with the f64 one at every node of a panel, it is integrated the same way between the
//! f64 roots; otherwise (noise dominates) its panel value is the rule's sum of |g|, a
//! quadrature-weighted sample mean.
//!
//! The maximum is the largest |F_m − F_e| over all nodes, refined by Brent's search
//! around the largest node of the f64 difference (and the runners-up that come near it).

use std::collections::BinaryHeap;
use std::f64::consts::FRAC_PI_2;

use rayon::prelude::*;

/// One evaluation of one member: exact F and the method in f64 and in f32 (widened).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    pub exact: f64,
    pub approx: [f64; 2],
}

impl Sample {
    /// F_m − F_e in precision `p` (0: f64, 1: f32).
    #[inline]
    fn difference(&self, p: usize) -> f64 {
        self.approx[p] - self.exact
    }
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
    /// Points θ at which the family was evaluated (exact once, every member in f64 and
    /// f32); the members of a family share them.
    pub evaluations: u64,
}

/// Integrals (or sample sums, for the brute force) of one member.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sums {
    relative: [f64; 2],
    squared: [f64; 2],
}

impl Sums {
    fn add(&mut self, other: &Sums) {
        for p in 0..2 {
            self.relative[p] += other.relative[p];
            self.squared[p] += other.squared[p];
        }
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
            let error = sample.difference(p).abs();
            if error > self.value[p] {
                self.value[p] = error;
                self.theta[p] = theta;
            }
        }
    }

    fn merge(mut self, other: &Maximum) -> Maximum {
        for p in 0..2 {
            if other.value[p] > self.value[p] {
                self.value[p] = other.value[p];
                self.theta[p] = other.theta[p];
            }
        }
        self
    }
}

/// Figures from the integrals over a θ-range of `length` of which `included` has F_e > 0.
fn figures(sums: &Sums, included: f64, length: f64, maximum: &Maximum) -> [Figures; 2] {
    [0, 1].map(|p| Figures {
        mean_rel_error: (included > 0.0).then(|| sums.relative[p] / included),
        max_abs_error: maximum.value[p],
        rms_abs_error: (sums.squared[p] / length).max(0.0).sqrt(),
    })
}

/// The number of midpoints of the reference brute force (SPEC §6).
pub const BRUTE_FORCE_SAMPLES: usize = 1_000_000;

/// Brute force over `samples` θ-midpoints θ_j = (j + ½)·(π/2)/M, in parallel (rayon);
/// `evaluate(θ, out)` fills one [`Sample`] per member.
pub fn brute_force(evaluate: &(impl Fn(f64, &mut [Sample]) + Sync), members: usize, samples: usize) -> Vec<Integral> {
    const CHUNK: usize = 8192;
    let step = FRAC_PI_2 / samples as f64;
    let empty = || (vec![Sums::default(); members], vec![Maximum::default(); members], 0u64);
    let (sums, maxima, excluded) = (0..samples.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            let (mut sums, mut maxima, mut excluded) = empty();
            let mut out = vec![Sample::default(); members];
            for j in chunk * CHUNK..((chunk + 1) * CHUNK).min(samples) {
                let theta = (j as f64 + 0.5) * step;
                evaluate(theta, &mut out);
                let included = out.first().is_some_and(|s| s.exact > 0.0);
                excluded += u64::from(!included);
                for (m, sample) in out.iter().enumerate() {
                    for p in 0..2 {
                        let difference = sample.difference(p);
                        sums[m].squared[p] += difference * difference;
                        if included {
                            sums[m].relative[p] += difference.abs() / sample.exact;
                        }
                    }
                    maxima[m].see(theta, sample);
                }
            }
            (sums, maxima, excluded)
        })
        .reduce(empty, |mut a, b| {
            for m in 0..members {
                a.0[m].add(&b.0[m]);
                a.1[m] = a.1[m].merge(&b.1[m]);
            }
            (a.0, a.1, a.2 + b.2)
        });
    // Midpoint sums: the means need only the counts.
    let included = (samples as u64 - excluded) as f64;
    (0..members)
        .map(|m| Integral {
            figures: figures(&sums[m], included, samples as f64, &maxima[m]),
            excluded_samples: excluded,
            evaluations: samples as u64,
        })
        .collect()
}

/// A panel rule on [−1, 1]: M nodes, increasing, the first and last at the ends (shared
/// with the neighbouring panels), the weights of the rule, its error estimate (see
/// [`Estimate`]), and the monomial coefficients of the Lagrange basis of the nodes
/// (L_i(t) = Σ_k lagrange[i][k] t^k), so that p(t) = Σ_i g_i L_i(t) interpolates node
/// values g.
pub struct Rule<const M: usize> {
    nodes: [f64; M],
    weights: [f64; M],
    estimate: Estimate<M>,
    lagrange: [[f64; M]; M],
}

/// How a rule estimates its error on a panel.
pub enum Estimate<const M: usize> {
    /// Against an embedded lower-degree rule with these weights, scaled as QUADPACK does.
    Embedded([f64; M]),
    /// From the highest coefficient c of the interpolant of the smooth function under the
    /// integral (g for the relative error, F_m − F_e for the squared one): the rule is
    /// exact to a degree above the interpolant's, so its error comes from higher terms,
    /// taken as no larger than |c| times this factor (the rule's error on t^(M+1)).
    Tail(f64),
}

impl<const M: usize> Rule<M> {
    const fn new(nodes: [f64; M], weights: [f64; M], estimate: Estimate<M>) -> Self {
        // Multiply out Π_{m≠i} (t − t_m)/(t_i − t_m), lowest power first.
        let mut lagrange = [[0.0; M]; M];
        let mut i = 0;
        while i < M {
            let mut poly = [0.0; M];
            poly[0] = 1.0;
            let mut degree = 0;
            let mut m = 0;
            while m < M {
                if m != i {
                    let scale = 1.0 / (nodes[i] - nodes[m]);
                    let mut power = degree + 1;
                    while power > 0 {
                        poly[power] = (poly[power - 1] - nodes[m] * poly[power]) * scale;
                        power -= 1;
                    }
                    poly[0] = -nodes[m] * poly[0] * scale;
                    degree += 1;
                }
                m += 1;
            }
            lagrange[i] = poly;
            i += 1;
        }
        Self { nodes, weights, estimate, lagrange }
    }

    /// The rule and the embedded rule (0 for a [`Estimate::Tail`] rule) applied to node
    /// values.
    #[cfg(test)]
    fn sums(&self, values: &[f64; M]) -> (f64, f64) {
        let embedded_weights = match &self.estimate {
            Estimate::Embedded(weights) => weights,
            Estimate::Tail(_) => &[0.0; M],
        };
        let mut main = 0.0;
        let mut embedded = 0.0;
        for i in 0..M {
            main += self.weights[i] * values[i];
            embedded += embedded_weights[i] * values[i];
        }
        (main, embedded)
    }

    /// The rule's value on [−1, 1] and its error estimate, for node values of the
    /// integrand. `tail` gives, for [`Estimate::Tail`], the size of the interpolant's
    /// highest coefficient as it bears on the integral: |c_top| of the smooth function
    /// under the integral, times 2·max|s| when the integrand is its square s²
    /// (∫(s + ε)² − ∫s² ≈ 2∫sε).
    ///
    /// [`Estimate::Embedded`]: QUADPACK's (Piessens et al. 1983, qk15) scaling of
    /// E = |main − embedded| by the integrand's variation V = Σ w_i |f_i − main/2|:
    /// E·min(1, (200 E/V)^1.5). E is the error of the embedded (lower-degree) rule; the
    /// main rule's error falls much faster with the panel width, which the power models.
    fn estimate(&self, values: &[f64; M], tail: impl FnOnce() -> f64) -> (f64, f64) {
        let main = self.integral(values);
        let error = match &self.estimate {
            Estimate::Embedded(weights) => {
                let embedded: f64 = (0..M).map(|i| weights[i] * values[i]).sum();
                let mean = 0.5 * main;
                let variation: f64 = (0..M).map(|i| self.weights[i] * (values[i] - mean).abs()).sum();
                let difference = (main - embedded).abs();
                if variation > 0.0 && difference > 0.0 {
                    let ratio = (200.0 * difference / variation).min(1.0);
                    difference * ratio * ratio.sqrt()
                } else {
                    difference
                }
            }
            Estimate::Tail(factor) => factor * tail(),
        };
        (main, error)
    }

    /// The rule applied to node values (the integral over [−1, 1]).
    #[inline]
    fn integral(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.weights[i] * values[i]).sum()
    }

    /// The highest (t^(M−1)) coefficient of the interpolant of node values: the
    /// (M−1)-th divided difference.
    #[inline]
    fn top_coefficient(&self, values: &[f64; M]) -> f64 {
        (0..M).map(|i| self.lagrange[i][M - 1] * values[i]).sum()
    }

    /// The interpolating polynomial of node values `g` (monomials in t, lowest first).
    fn interpolate(&self, g: &[f64; M]) -> [f64; M] {
        let mut coefficients = [0.0; M];
        for (value, basis) in g.iter().zip(self.lagrange.iter()) {
            for (c, b) in coefficients.iter_mut().zip(basis) {
                *c += value * b;
            }
        }
        coefficients
    }

    /// The sign changes of the interpolant p of `g` on [−1, 1], increasing, into
    /// `roots`; returns how many. Between nodes of opposite sign there is a root. Between
    /// nodes of the same sign p can still dip through zero (twice): a root r in (lo, hi)
    /// needs |p(lo)| + |p(hi)| ≤ max|p'|·(hi − lo), with max|p'| ≤ Σ k|c_k| x^(k−1) on
    /// [lo, hi], x = max(|lo|, |hi|); intervals that pass this test are halved and tested
    /// again, down to 1/32 of the gap between nodes. A dip narrower than that is missed,
    /// and with it an area below max|p'|·(gap/32)².
    fn sign_change_roots(&self, g: &[f64; M], coefficients: &[f64; M], roots: &mut [f64; MAX_ROOTS]) -> usize {
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if scale == 0.0 {
            return 0;
        }
        // The bound on [−1, 1], to rule out most gaps before the finer one on a gap.
        let slope_bound: f64 = coefficients.iter().enumerate().skip(1).map(|(k, c)| k as f64 * c.abs()).sum();
        let mut found = Roots { roots, count: 0 };
        for i in 0..M - 1 {
            let (lo, hi) = (self.nodes[i], self.nodes[i + 1]);
            if g[i] * g[i + 1] < 0.0 {
                found.push(root(coefficients, lo, hi, scale));
            } else if g[i].abs() + g[i + 1].abs() <= slope_bound * (hi - lo) {
                found.dips(coefficients, scale, (lo, g[i]), (hi, g[i + 1]), 5);
            }
        }
        found.count
    }
}

/// Roots found so far on a panel, in increasing order.
struct Roots<'a> {
    roots: &'a mut [f64; MAX_ROOTS],
    count: usize,
}

impl Roots<'_> {
    fn push(&mut self, r: f64) {
        if self.count < MAX_ROOTS {
            self.roots[self.count] = r;
            self.count += 1;
        }
    }

    /// Sign changes of p in (lo, hi) where p(lo), p(hi) have the same sign, by bisection
    /// while the slope bound cannot exclude a root, `depth` levels deep.
    fn dips<const M: usize>(&mut self, coefficients: &[f64; M], scale: f64, lo: (f64, f64), hi: (f64, f64), depth: u32) {
        if lo.1 * hi.1 < 0.0 {
            self.push(root(coefficients, lo.0, hi.0, scale));
            return;
        }
        if depth == 0 || lo.1 == 0.0 || hi.1 == 0.0 {
            return;
        }
        let x = lo.0.abs().max(hi.0.abs());
        let slope_bound = coefficients.iter().enumerate().skip(1).rev().fold(0.0, |acc, (k, c)| acc * x + k as f64 * c.abs());
        if lo.1.abs() + hi.1.abs() > slope_bound * (hi.0 - lo.0) {
            return;
        }
        let middle = 0.5 * (lo.0 + hi.0);
        let value = horner(coefficients, middle);
        self.dips(coefficients, scale, lo, (middle, value), depth - 1);
        self.dips(coefficients, scale, (middle, value), hi, depth - 1);
    }
}

/// The 7-point Kronrod rule (exact to degree 11) with its embedded 3-point Gauss rule
/// (degree 5), plus the two ends as interpolation nodes (weight 0); QUADPACK's qk7
/// abscissae and weights. For panels wide enough that the integrand's curvature matters.
pub const KRONROD7: Rule<9> = Rule::new(
    [
        -1.0,
        -0.960_491_268_708_020_3,
        -0.774_596_669_241_483_4,
        -0.434_243_749_346_802_6,
        0.0,
        0.434_243_749_346_802_6,
        0.774_596_669_241_483_4,
        0.960_491_268_708_020_3,
        1.0,
    ],
    [
        0.0,
        0.104_656_226_026_467_27,
        0.268_488_089_868_333_44,
        0.401_397_414_775_962_2,
        0.450_916_538_658_474_14,
        0.401_397_414_775_962_2,
        0.268_488_089_868_333_44,
        0.104_656_226_026_467_27,
        0.0,
    ],
    Estimate::Embedded([0.0, 0.0, 5.0 / 9.0, 0.0, 8.0 / 9.0, 0.0, 5.0 / 9.0, 0.0, 0.0]),
);

/// The 3-point Gauss rule (nodes ±√(3/5), 0; weights 5/9, 8/9, 5/9; exact to degree 5)
/// plus the two ends as interpolation nodes (weight 0): three new evaluations per panel,
/// a degree-4 interpolant for the roots, and a [`Estimate::Tail`] error estimate (G3's
/// error on t⁶ is 2/7 − 2·(5/9)·(3/5)³ = 0.0457). For the narrow panels between LUT
/// texel centres, where F_m − F_e is nearly quadratic and Kronrod's seven nodes would
/// be wasted; an embedded rule cannot judge it (any 5-node rule below degree 5 sees the
/// genuine t⁴ of (F_m − F_e)² as error).
pub const GAUSS3: Rule<5> = Rule::new(
    [-1.0, -0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4, 1.0],
    [0.0, 5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0, 0.0],
    Estimate::Tail(0.0457),
);

/// p(t) by Horner's rule.
#[inline]
fn horner<const M: usize>(coefficients: &[f64; M], t: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, c| acc * t + c)
}

/// ∫₀ᵗ p by Horner's rule on the antiderivative.
#[inline]
fn antiderivative<const M: usize>(coefficients: &[f64; M], t: f64) -> f64 {
    let mut acc = 0.0;
    for (power, c) in coefficients.iter().enumerate().rev() {
        acc = acc * t + c / (power + 1) as f64;
    }
    acc * t
}

/// A root of p in (lo, hi) where p(lo) and p(hi) differ in sign: Illinois regula falsi
/// until the bracket is below 1e-4 or |p| below 1e-5 of `scale` (the largest |g| on the
/// panel). A root off by δ changes ∫|p| by about |p'|δ², below 1e-8 of the panel's
/// integral.
fn root<const M: usize>(coefficients: &[f64; M], mut lo: f64, mut hi: f64, scale: f64) -> f64 {
    let (mut f_lo, mut f_hi) = (horner(coefficients, lo), horner(coefficients, hi));
    if f_lo == 0.0 {
        return lo;
    }
    if f_hi == 0.0 || f_lo * f_hi > 0.0 {
        return hi;
    }
    let small = 1e-5 * scale;
    let mut side = 0i8;
    for _ in 0..60 {
        let x = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        let x = if x > lo && x < hi { x } else { 0.5 * (lo + hi) };
        let f = horner(coefficients, x);
        if f.abs() <= small || hi - lo < 1e-4 {
            return x;
        }
        if (f > 0.0) == (f_lo > 0.0) {
            lo = x;
            f_lo = f;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            f_hi = f;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (lo + hi)
}

/// At most this many sign changes of p are resolved per panel.
const MAX_ROOTS: usize = 32;

/// ∫_{−1}^{1} |p| given p's sign changes at `roots` (increasing).
fn absolute_integral<const M: usize>(coefficients: &[f64; M], roots: &[f64]) -> f64 {
    let mut total = 0.0;
    let mut from = antiderivative(coefficients, -1.0);
    for &t in roots.iter().chain(std::iter::once(&1.0)) {
        let to = antiderivative(coefficients, t);
        total += (to - from).abs();
        from = to;
    }
    total
}

/// Tolerances of the adaptive path.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Target of the summed panel error estimates (see [`Estimate`]) relative to each
    /// member's f64 integral (relative and squared error separately).
    pub relative: f64,
    /// Give up refining after this many evaluations (of the whole family).
    pub max_evaluations: u64,
    /// Panels narrower than this (radians) are not split further.
    pub min_width: f64,
}

impl Default for Tolerance {
    fn default() -> Self {
        Self { relative: 1e-6, max_evaluations: 400_000, min_width: 1e-12 }
    }
}

/// Integrals below these are f64 rounding, not errors worth refining: a mean relative
/// error of 1e-12 and an RMS absolute error of 1e-13.
const RELATIVE_FLOOR: f64 = 1e-12 * FRAC_PI_2;
const SQUARED_FLOOR: f64 = 1e-26 * FRAC_PI_2;

/// The largest f64 |F_m − F_e| at a node of a panel: its value, its θ, and the θ of the
/// neighbouring nodes (the bracket searched for the maximum).
#[derive(Clone, Copy, Debug, Default)]
struct Peak {
    value: f64,
    theta: f64,
    lo: f64,
    hi: f64,
}

/// What one panel contributes for one member.
#[derive(Clone, Copy, Debug, Default)]
struct MemberPanel {
    sums: Sums,
    /// Error estimates (see [`Estimate`]) of the f64 relative and squared integrands.
    error: [f64; 2],
    /// The largest f64 |F_m − F_e| at a node.
    peak: Peak,
}

#[derive(Clone, Copy, Debug)]
struct Panel {
    a: f64,
    b: f64,
    /// Ids of the end points in the point store.
    ends: [usize; 2],
    /// θ-measure of the panel where F_e > 0.
    included: f64,
    /// Refined away (replaced by its halves) or frozen at the minimum width.
    settled: bool,
}

/// Heap entry: priority and panel id.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ranked(f64, usize);
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The state of one adaptive integration of a family.
struct Adaptive<'a, F: Fn(f64, &mut [Sample]), const M: usize> {
    evaluate: &'a F,
    rule: &'static Rule<M>,
    members: usize,
    evaluations: u64,
    excluded: u64,
    maxima: Vec<Maximum>,
    /// Samples at panel ends, `members` per point.
    points: Vec<Sample>,
    panels: Vec<Panel>,
    /// `members` entries per panel.
    contributions: Vec<MemberPanel>,
    /// Scratch: the M nodes of the panel being built, `members` samples per node.
    nodes: Vec<Sample>,
}

impl<'a, F: Fn(f64, &mut [Sample]), const M: usize> Adaptive<'a, F, M> {
    /// Evaluate the family at θ into `out`.
    fn eval_into(&mut self, theta: f64, out: &mut [Sample]) {
        (self.evaluate)(theta, out);
        self.evaluations += 1;
        self.excluded += u64::from(!out.first().is_some_and(|s| s.exact > 0.0));
        for (maximum, sample) in self.maxima.iter_mut().zip(out.iter()) {
            maximum.see(theta, sample);
        }
    }

    /// Evaluate at θ and keep the samples as a panel end; returns the point id.
    fn point(&mut self, theta: f64) -> usize {
        let id = self.points.len() / self.members.max(1);
        let mut out = vec![Sample::default(); self.members];
        self.eval_into(theta, &mut out);
        self.points.extend(out);
        id
    }

    /// Build the panel [a, b] between the stored end points and return its id.
    fn panel(&mut self, a: f64, b: f64, ends: [usize; 2]) -> usize {
        let members = self.members;
        let rule = self.rule;
        let centre = 0.5 * (a + b);
        let half = 0.5 * (b - a);
        let mut nodes = std::mem::take(&mut self.nodes);
        nodes.clear();
        nodes.resize(M * members, Sample::default());
        nodes[..members].copy_from_slice(&self.points[ends[0] * members..(ends[0] + 1) * members]);
        nodes[(M - 1) * members..].copy_from_slice(&self.points[ends[1] * members..(ends[1] + 1) * members]);
        for i in 1..M - 1 {
            self.eval_into(centre + half * rule.nodes[i], &mut nodes[i * members..(i + 1) * members]);
        }
        let exact: [f64; M] = std::array::from_fn(|i| nodes[i * members].exact);
        let all_included = exact.iter().all(|&f| f > 0.0);
        let included = if all_included {
            b - a
        } else {
            half * rule.integral(&exact.map(|f| if f > 0.0 { 1.0 } else { 0.0 }))
        };
        let inverse: [f64; M] = exact.map(|f| if f > 0.0 { 1.0 / f } else { 0.0 });
        let theta_of = |i: usize| centre + half * rule.nodes[i];
        for m in 0..members {
            let sample = |i: usize| nodes[i * members + m];
            let mut contribution = MemberPanel::default();
            let mut f64_roots = [0.0; MAX_ROOTS];
            let mut f64_root_count = 0;
            for p in 0..2 {
                let d: [f64; M] = std::array::from_fn(|i| sample(i).difference(p));
                let squared = d.map(|x| x * x);
                // Error estimates only for f64, which drives the refinement.
                let (main_squared, error_squared) = if p == 0 {
                    let size = d.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    rule.estimate(&squared, || rule.top_coefficient(&d).abs() * 2.0 * size)
                } else {
                    (rule.integral(&squared), 0.0)
                };
                contribution.sums.squared[p] = half * main_squared;
                let g: [f64; M] = std::array::from_fn(|i| d[i] * inverse[i]);
                let coefficients = if p == 0 { rule.interpolate(&g) } else { [0.0; M] };
                let (main_relative, error_relative) =
                    if p == 0 { rule.estimate(&g, || coefficients[M - 1].abs()) } else { (rule.integral(&g), 0.0) };
                let relative = if !all_included {
                    // F_e = 0 somewhere (only n = 1, k = 0): the rule on |g| with g = 0
                    // where excluded.
                    rule.integral(&g.map(f64::abs))
                } else if p == 0 {
                    f64_root_count = rule.sign_change_roots(&g, &coefficients, &mut f64_roots);
                    if f64_root_count == 0 {
                        main_relative.abs()
                    } else {
                        absolute_integral(&coefficients, &f64_roots[..f64_root_count])
                    }
                } else if f64_root_count == 0 && g.windows(2).all(|w| w[0] * w[1] > 0.0) {
                    main_relative.abs()
                } else if (0..M).all(|i| d[i] * sample(i).difference(0) > 0.0) {
                    // f32 follows the f64 difference: same sign changes, same roots.
                    absolute_integral(&rule.interpolate(&g), &f64_roots[..f64_root_count])
                } else {
                    // Noise dominates the f32 difference: a weighted sample mean of |g|.
                    rule.integral(&g.map(f64::abs))
                };
                contribution.sums.relative[p] = half * relative;
                if p == 0 {
                    contribution.error = [half * error_relative, half * error_squared];
                    let (i, peak) =
                        d.iter().map(|x| x.abs()).enumerate().fold((0, -1.0), |best, (i, x)| if x > best.1 { (i, x) } else { best });
                    let lo = theta_of(i.saturating_sub(1));
                    let hi = theta_of((i + 1).min(M - 1));
                    contribution.peak = Peak { value: peak, theta: theta_of(i), lo, hi };
                }
            }
            self.contributions.push(contribution);
        }
        self.nodes = nodes;
        self.panels.push(Panel { a, b, ends, included, settled: false });
        self.panels.len() - 1
    }

    fn contributions(&self, panel: usize) -> &[MemberPanel] {
        &self.contributions[panel * self.members..(panel + 1) * self.members]
    }
}

/// Adaptive integration over [0, π/2] of a family of `members` integrands, with the
/// given interior breakpoints (any order; out-of-range and duplicates ignored).
/// `evaluate(θ, out)` fills one [`Sample`] per member, all with the same exact F.
pub fn adaptive(evaluate: &impl Fn(f64, &mut [Sample]), members: usize, breakpoints: &[f64], tolerance: Tolerance) -> Vec<Integral> {
    let mut cuts: Vec<f64> = breakpoints.iter().copied().filter(|t| *t > 0.0 && *t < FRAC_PI_2).collect();
    cuts.push(0.0);
    cuts.push(FRAC_PI_2);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-14);
    // Many narrow panels (LUT texel intervals): Gauss; few wide ones: Kronrod.
    if cuts.len() > NARROW_PANELS {
        integrate(&GAUSS3, evaluate, members, &cuts, tolerance)
    } else {
        integrate(&KRONROD7, evaluate, members, &cuts, tolerance)
    }
}

/// From this many panels on, [`GAUSS3`] is used instead of [`KRONROD7`]: the panels
/// are then at most about π/2 / 100 wide on average (the LUT sizes 128 and up).
const NARROW_PANELS: usize = 100;

fn integrate<F: Fn(f64, &mut [Sample]), const M: usize>(
    rule: &'static Rule<M>,
    evaluate: &F,
    members: usize,
    cuts: &[f64],
    tolerance: Tolerance,
) -> Vec<Integral> {
    let mut state = Adaptive {
        evaluate,
        rule,
        members,
        evaluations: 0,
        excluded: 0,
        maxima: vec![Maximum::default(); members],
        points: Vec::with_capacity(cuts.len() * 2 * members),
        panels: Vec::with_capacity(cuts.len() * 2),
        contributions: Vec::with_capacity(cuts.len() * 2 * members),
        nodes: Vec::with_capacity(M * members),
    };
    let ids: Vec<usize> = cuts.iter().map(|&theta| state.point(theta)).collect();
    for (w, id) in cuts.windows(2).zip(ids.windows(2)) {
        state.panel(w[0], w[1], [id[0], id[1]]);
    }

    // Criteria: per member, the f64 relative and squared integrals, each normalised by
    // its first estimate.
    let mut scale = vec![[0.0f64; 2]; members];
    for panel in 0..state.panels.len() {
        for (s, c) in scale.iter_mut().zip(state.contributions(panel)) {
            s[0] += c.sums.relative[0];
            s[1] += c.sums.squared[0];
        }
    }
    let scale: Vec<[f64; 2]> = scale.iter().map(|s| [s[0].abs().max(RELATIVE_FLOOR), s[1].abs().max(SQUARED_FLOOR)]).collect();
    // Add (sign 1) or remove (sign −1) a panel's normalised errors to the per-criterion
    // sums; returns their total, the panel's priority.
    let account = |sums: &mut [f64], contributions: &[MemberPanel], sign: f64| -> f64 {
        let mut total = 0.0;
        for ((c, s), pair) in contributions.iter().zip(&scale).zip(sums.chunks_exact_mut(2)) {
            let errors = [c.error[0] / s[0], c.error[1] / s[1]];
            pair[0] += sign * errors[0];
            pair[1] += sign * errors[1];
            total += errors[0] + errors[1];
        }
        total
    };
    let mut error_sums = vec![0.0; 2 * members];
    let mut heap = BinaryHeap::with_capacity(state.panels.len());
    for panel in 0..state.panels.len() {
        let priority = account(&mut error_sums, state.contributions(panel), 1.0);
        heap.push(Ranked(priority, panel));
    }
    let worst = |sums: &[f64]| sums.iter().copied().fold(0.0, f64::max);
    let mut refinements = 0u64;
    while worst(&error_sums) > tolerance.relative && state.evaluations < tolerance.max_evaluations {
        let Some(Ranked(_, id)) = heap.pop() else { break };
        let panel = state.panels[id];
        state.panels[id].settled = true;
        account(&mut error_sums, state.contributions(id), -1.0);
        if panel.b - panel.a <= tolerance.min_width {
            // Frozen: kept in the totals, no longer refined.
            state.panels[id].settled = false;
            continue;
        }
        let middle = 0.5 * (panel.a + panel.b);
        let mid = state.point(middle);
        for (a, b, ends) in [(panel.a, middle, [panel.ends[0], mid]), (middle, panel.b, [mid, panel.ends[1]])] {
            let child = state.panel(a, b, ends);
            let priority = account(&mut error_sums, state.contributions(child), 1.0);
            heap.push(Ranked(priority, child));
        }
        refinements += 1;
        // Re-sum now and then against drift of the running totals.
        if refinements.is_multiple_of(256) {
            error_sums.iter_mut().for_each(|s| *s = 0.0);
            for Ranked(_, id) in heap.iter() {
                account(&mut error_sums, state.contributions(*id), 1.0);
            }
        }
    }

    let live: Vec<usize> = (0..state.panels.len()).filter(|&p| !state.panels[p].settled).collect();
    let included: f64 = live.iter().map(|&p| state.panels[p].included).sum();
    let mut sums = vec![Sums::default(); members];
    for &p in &live {
        for (s, c) in sums.iter_mut().zip(state.contributions(p)) {
            s.add(&c.sums);
        }
    }
    // The maximum: Brent's search around the largest node differences.
    for m in 0..members {
        let mut peaks = [Peak::default(); PEAKS_REFINED];
        for &p in &live {
            let peak = state.contributions(p)[m].peak;
            if let Some(slot) = peaks.iter().position(|q| peak.value > q.value) {
                peaks[slot..].rotate_right(1);
                peaks[slot] = peak;
            }
        }
        // The runners-up only where their node value comes near the maximum found so far:
        // between nodes a smooth difference rises by far less than 10 %.
        for (rank, peak) in peaks.iter().enumerate() {
            if peak.value > 0.0 && (rank == 0 || peak.value >= 0.9 * state.maxima[m].value[0]) {
                refine_maximum(&mut state, m, peak);
            }
        }
    }
    (0..members)
        .map(|m| Integral {
            figures: figures(&sums[m], included, FRAC_PI_2, &state.maxima[m]),
            excluded_samples: state.excluded,
            evaluations: state.evaluations,
        })
        .collect()
}

/// How many of the largest node differences (one per panel) may be refined, per member.
const PEAKS_REFINED: usize = 3;

/// Brent's method (Brent 1973, ch. 5: parabolic steps with golden-section fallback) for
/// the largest f64 |F_m − F_e| of `member` in the peak's bracket, starting from its node;
/// to 1e-9 relative in θ, which puts a smooth maximum at f64 precision in about ten
/// evaluations. Every point seen counts for every member and both precisions.
fn refine_maximum<F: Fn(f64, &mut [Sample]), const M: usize>(state: &mut Adaptive<'_, F, M>, member: usize, peak: &Peak) {
    const TOLERANCE: f64 = 1e-9;
    let mut out = vec![Sample::default(); state.members];
    // Minimise −|d|; the state records every evaluation.
    let f = |theta: f64| {
        state.eval_into(theta, &mut out);
        -out[member].difference(0).abs()
    };
    crate::minimise::brent(f, (peak.lo, peak.hi), (peak.theta, -peak.value), |x| TOLERANCE * x.abs() + 1e-15, 40);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A family of one member from a single-sample function.
    fn single(f: impl Fn(f64) -> Sample) -> impl Fn(f64, &mut [Sample]) {
        move |theta, out: &mut [Sample]| out[0] = f(theta)
    }

    /// ∫_{−1}^{1} t^power.
    fn monomial_integral(power: i32) -> f64 {
        if power % 2 == 0 {
            2.0 / (power + 1) as f64
        } else {
            0.0
        }
    }

    #[test]
    fn rules_are_exact_to_their_degree() {
        let kronrod = |power: i32| KRONROD7.sums(&KRONROD7.nodes.map(|t| t.powi(power)));
        let gauss = |power: i32| {
            let (main, _) = GAUSS3.sums(&GAUSS3.nodes.map(|t| t.powi(power)));
            (main, main)
        };
        let cases: [(i32, i32, &dyn Fn(i32) -> (f64, f64)); 2] = [(11, 5, &kronrod), (5, 5, &gauss)];
        for (rule_main, rule_embedded, sums) in cases {
            for power in 0..=rule_main {
                let (main, embedded) = sums(power);
                let exact = monomial_integral(power);
                assert!((main - exact).abs() < 1e-15, "x^{power}: {main} vs {exact}");
                if power <= rule_embedded {
                    assert!((embedded - exact).abs() < 1e-15, "embedded x^{power}: {embedded} vs {exact}");
                }
            }
            // One degree more is not exact (the rule is what it claims, no more).
            let (main, _) = sums(rule_main + 1);
            assert!((main - monomial_integral(rule_main + 1)).abs() > 1e-6);
        }
    }

    fn check_interpolant<const M: usize>(rule: &Rule<M>) {
        // p(t) = (t − 0.3)(t + 0.55)(t − 0.9) = t³ − 0.65 t² − 0.39 t + 0.1485 (degree 3 < M).
        let p = |t: f64| (t - 0.3) * (t + 0.55) * (t - 0.9);
        let g = rule.nodes.map(p);
        let coefficients = rule.interpolate(&g);
        let expected = [0.1485, -0.39, -0.65, 1.0];
        for (k, c) in coefficients.iter().enumerate() {
            assert!((c - expected.get(k).copied().unwrap_or(0.0)).abs() < 1e-13, "{coefficients:?}");
        }
        let mut roots = [0.0; MAX_ROOTS];
        let count = rule.sign_change_roots(&g, &coefficients, &mut roots);
        assert_eq!(count, 3, "{:?}", &roots[..count]);
        // Roots are found to |p| ≤ 1e-5 of the largest |g| (see `root`).
        for (r, expected) in roots[..3].iter().zip([-0.55, 0.3, 0.9]) {
            assert!((r - expected).abs() < 1e-4, "{roots:?}");
        }
        // ∫|p| over [−1, 1], by the antiderivative P(t) = t⁴/4 − 0.65t³/3 − 0.195t² + 0.1485t.
        let big_p = |t: f64| t.powi(4) / 4.0 - 0.65 * t.powi(3) / 3.0 - 0.195 * t * t + 0.1485 * t;
        let knots = [-1.0, -0.55, 0.3, 0.9, 1.0];
        let expected: f64 = knots.windows(2).map(|w| (big_p(w[1]) - big_p(w[0])).abs()).sum();
        // A root off by δ moves ∫|p| by about |p'|δ²: ≤ 1e-8 of it.
        assert!((absolute_integral(&coefficients, &roots[..3]) - expected).abs() < 1e-8 * expected);
    }

    #[test]
    fn interpolant_reproduces_polynomials_roots_and_absolute_integrals() {
        check_interpolant(&KRONROD7);
        check_interpolant(&GAUSS3);
    }

    #[test]
    fn a_dip_through_zero_between_nodes_is_found() {
        // g(t) = (t − 0.15)(t − 0.35) − 0.001: both roots lie between the Kronrod nodes
        // 0 and 0.434, where g is positive at both nodes.
        let g_of = |t: f64| (t - 0.15) * (t - 0.35);
        let g = KRONROD7.nodes.map(g_of);
        assert!(g[4] > 0.0 && g[5] > 0.0);
        let coefficients = KRONROD7.interpolate(&g);
        let mut roots = [0.0; MAX_ROOTS];
        let count = KRONROD7.sign_change_roots(&g, &coefficients, &mut roots);
        assert_eq!(&roots[..count].iter().map(|r| (r * 1e3).round() / 1e3).collect::<Vec<_>>(), &[0.15, 0.35]);
    }

    #[test]
    fn smooth_integrand_matches_closed_form() {
        // F_e = 0.5, F_m = 0.5 + 0.1 sin θ.
        // mean |g|/F = (0.1/0.5)·(1/(π/2))∫₀^{π/2} sin θ dθ = 0.2·2/π.
        // rms = √(0.01·(1/(π/2))∫sin² θ dθ) = √(0.01·½) = 0.0707…
        let f = single(|theta: f64| Sample { exact: 0.5, approx: [0.5 + 0.1 * theta.sin(); 2] });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        let expected = 0.4 / std::f64::consts::PI;
        assert!((i.figures[0].mean_rel_error.unwrap() - expected).abs() < 1e-13);
        assert!((i.figures[0].rms_abs_error - 0.005f64.sqrt()).abs() < 1e-13);
        assert!((i.figures[0].max_abs_error - 0.1).abs() < 1e-12);
        assert!(i.evaluations < 300, "{}", i.evaluations);
        let b = brute_force(&f, 1, 100_000)[0];
        assert!((b.figures[0].mean_rel_error.unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn sign_changes_are_integrated_through_the_root() {
        // F_m − F_e = 0.1 (θ − 1): |·| has a kink at θ = 1, inside the only panel.
        let f = single(|theta: f64| Sample { exact: 1.0, approx: [1.0 + 0.1 * (theta - 1.0); 2] });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        // ∫|θ − 1| over [0, π/2] = ½ + ½(π/2 − 1)².
        let exact = 0.1 * (0.5 + 0.5 * (FRAC_PI_2 - 1.0).powi(2)) / FRAC_PI_2;
        assert!((i.figures[0].mean_rel_error.unwrap() - exact).abs() < 1e-14, "{:?}", i.figures[0]);
        assert!((i.figures[1].mean_rel_error.unwrap() - exact).abs() < 1e-14, "{:?}", i.figures[1]);
        assert!(i.evaluations < 50, "{}", i.evaluations);
    }

    #[test]
    fn members_share_evaluations_and_keep_their_own_figures() {
        // Member 0: F_m − F_e = 0.1 sin θ; member 1: 0.2 (θ − 1) on F_e = 1.
        let f = |theta: f64, out: &mut [Sample]| {
            out[0] = Sample { exact: 1.0, approx: [1.0 + 0.1 * theta.sin(); 2] };
            out[1] = Sample { exact: 1.0, approx: [1.0 + 0.2 * (theta - 1.0); 2] };
        };
        let both = adaptive(&f, 2, &[], Tolerance::default());
        assert_eq!(both[0].evaluations, both[1].evaluations);
        assert!((both[0].figures[0].mean_rel_error.unwrap() - 0.1 / FRAC_PI_2).abs() < 1e-13);
        let kink = 0.2 * (0.5 + 0.5 * (FRAC_PI_2 - 1.0).powi(2)) / FRAC_PI_2;
        assert!((both[1].figures[0].mean_rel_error.unwrap() - kink).abs() < 1e-13);
        assert!((both[1].figures[0].max_abs_error - 0.2).abs() < 1e-12);
    }

    #[test]
    fn noisy_f32_difference_is_a_sample_mean_of_its_magnitude() {
        // f64 exact (difference 0), f32 alternating ±1e-7 relative noise: the figure must
        // be about 1e-7, not the cancelled mean.
        let f = single(|theta: f64| {
            let noise = if ((theta * 1e6) as i64) % 2 == 0 { 1e-7 } else { -1e-7 };
            Sample { exact: 0.5, approx: [0.5, 0.5 * (1.0 + noise)] }
        });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        assert_eq!(i.figures[0].mean_rel_error, Some(0.0));
        let f32_mean = i.figures[1].mean_rel_error.unwrap();
        assert!((f32_mean - 1e-7).abs() < 1e-12, "{f32_mean}");
    }

    #[test]
    fn zero_reflectance_is_excluded() {
        let f = single(|_| Sample { exact: 0.0, approx: [0.0; 2] });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        assert_eq!(i.figures[0].mean_rel_error, None);
        assert_eq!(i.excluded_samples, i.evaluations);
        let b = brute_force(&f, 1, 1000)[0];
        assert_eq!(b.excluded_samples, 1000);
        assert_eq!(b.figures[1].mean_rel_error, None);
    }
}

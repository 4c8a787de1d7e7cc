//! The fast path of the error integrals: adaptive panel quadrature over [0, π/2] with the
//! caller's breakpoints, bisecting the worst panel first (QUADPACK QAG style; Piessens
//! et al. 1983), the maximum refined by Brent's search. The method is described in the
//! module doc of [`super`].

use std::collections::BinaryHeap;
use std::f64::consts::FRAC_PI_2;

use super::rule::{absolute_integral, Rule, GAUSS3, KRONROD7, MAX_ROOTS};
use super::{figures, Integral, Integrand, Maximum, Sample, Sums};
use nklut_optics::fresnel::Precision;

/// Tolerances of the adaptive path.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Target of the summed panel error estimates (see [`super::rule::Estimate`])
    /// relative to each member's f64 integral (relative and squared error separately).
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

/// From this many panels on, [`GAUSS3`] is used instead of [`KRONROD7`]: the panels
/// are then at most about π/2 / 100 wide on average (the LUT sizes 128 and up).
const NARROW_PANELS: usize = 100;

/// How many of the largest node differences (one per panel) may be refined, per member.
const PEAKS_REFINED: usize = 3;

/// The two integrands whose accuracy drives the refinement, for one member: the
/// relative error |F_m − F_e|/F_e and the squared error (F_m − F_e)², both in f64.
#[derive(Clone, Copy, Debug, Default)]
struct Criteria {
    relative: f64,
    squared: f64,
}

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
    /// Error estimates (see [`super::rule::Estimate`]) of the f64 integrals.
    error: Criteria,
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
    /// Refined away: replaced by its halves, no longer in the totals. A panel frozen at
    /// the minimum width is not settled: it stays in the totals, unrefined.
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

/// A panel [a, b] as the affine image of the rule's [−1, 1].
#[derive(Clone, Copy, Debug)]
struct Span {
    centre: f64,
    half: f64,
}

impl Span {
    fn new(a: f64, b: f64) -> Self {
        Self { centre: 0.5 * (a + b), half: 0.5 * (b - a) }
    }

    fn theta(&self, t: f64) -> f64 {
        self.centre + self.half * t
    }
}

/// How the f32 relative integrand |g| is integrated on a panel. The f64 integrand
/// decides where the roots are; the f32 one follows it or is noise.
#[inline(always)]
fn single_precision_relative<const M: usize>(
    rule: &Rule<M>,
    g: &[f64; M],
    f32_difference: &[f64; M],
    f64_difference: &[f64; M],
    f64_roots: &[f64],
    all_included: bool,
) -> f64 {
    if !all_included {
        // F_e = 0 somewhere (only n = 1, k = 0): the rule on |g| with g = 0 where excluded.
        rule.integral(&g.map(f64::abs))
    } else if f64_roots.is_empty() && g.windows(2).all(|w| w[0] * w[1] > 0.0) {
        // One sign throughout.
        rule.integral(g).abs()
    } else if (0..M).all(|i| f32_difference[i] * f64_difference[i] > 0.0) {
        // f32 follows the f64 difference: same sign changes, same roots.
        absolute_integral(&rule.interpolate(g), f64_roots)
    } else {
        // Noise dominates the f32 difference: a weighted sample mean of |g|.
        rule.integral(&g.map(f64::abs))
    }
}

/// One member's contribution to a panel, from its samples at the rule's nodes.
/// `inverse` holds 1/F_e at the nodes (0 where F_e = 0).
#[inline(always)]
fn member_panel<const M: usize>(rule: &Rule<M>, span: Span, samples: [Sample; M], inverse: &[f64; M], all_included: bool) -> MemberPanel {
    let difference = |precision| -> [f64; M] { std::array::from_fn(|i| samples[i].difference(precision)) };
    let relative = |d: &[f64; M]| -> [f64; M] { std::array::from_fn(|i| d[i] * inverse[i]) };
    let d64 = difference(Precision::F64);
    let d32 = difference(Precision::F32);
    let (g64, g32) = (relative(&d64), relative(&d32));

    // f64 drives the refinement: error estimates, roots, the peak.
    let size = d64.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let (squared64, squared_error) = rule.estimate(&d64.map(|x| x * x), || rule.top_coefficient(&d64).abs() * 2.0 * size);
    let coefficients = rule.interpolate(&g64);
    let (signed64, relative_error) = rule.estimate(&g64, || coefficients[M - 1].abs());
    let mut roots = [0.0; MAX_ROOTS];
    let root_count = if all_included { rule.sign_change_roots(&g64, &coefficients, &mut roots) } else { 0 };
    let f64_roots = &roots[..root_count];
    let relative64 = if !all_included {
        rule.integral(&g64.map(f64::abs))
    } else if f64_roots.is_empty() {
        signed64.abs()
    } else {
        absolute_integral(&coefficients, f64_roots)
    };
    let relative32 = single_precision_relative(rule, &g32, &d32, &d64, f64_roots, all_included);
    let squared32 = rule.integral(&d32.map(|x| x * x));

    let half = span.half;
    let mut sums = Sums::default();
    sums.squared.f64 = half * squared64;
    sums.relative.f64 = half * relative64;
    sums.squared.f32 = half * squared32;
    sums.relative.f32 = half * relative32;
    MemberPanel { sums, error: Criteria { relative: half * relative_error, squared: half * squared_error }, peak: peak(rule, span, &d64) }
}

/// The node of largest |F_m − F_e| and its neighbours.
#[inline(always)]
fn peak<const M: usize>(rule: &Rule<M>, span: Span, difference: &[f64; M]) -> Peak {
    let (i, value) = difference.iter().map(|x| x.abs()).enumerate().fold((0, -1.0), |best, (i, x)| if x > best.1 { (i, x) } else { best });
    let theta_of = |i: usize| span.theta(rule.nodes[i]);
    Peak { value, theta: theta_of(i), lo: theta_of(i.saturating_sub(1)), hi: theta_of((i + 1).min(M - 1)) }
}

/// The state of one adaptive integration of a family.
struct Adaptive<'a, I: Integrand + ?Sized, const M: usize> {
    integrand: &'a I,
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

impl<'a, I: Integrand + ?Sized, const M: usize> Adaptive<'a, I, M> {
    fn new(rule: &'static Rule<M>, integrand: &'a I, members: usize, cuts: usize) -> Self {
        Self {
            integrand,
            rule,
            members,
            evaluations: 0,
            excluded: 0,
            maxima: vec![Maximum::default(); members],
            points: Vec::with_capacity(cuts * 2 * members),
            panels: Vec::with_capacity(cuts * 2),
            contributions: Vec::with_capacity(cuts * 2 * members),
            nodes: Vec::with_capacity(M * members),
        }
    }

    /// Evaluate the family at each of `thetas` into `out` (`members` samples per θ) and
    /// count and see the points in the order given.
    fn evaluate(&mut self, thetas: &[f64], out: &mut [Sample]) {
        let members = self.members;
        self.integrand.evaluate(thetas, out);
        for (j, &theta) in thetas.iter().enumerate() {
            let samples = &out[j * members..(j + 1) * members];
            self.evaluations += 1;
            self.excluded += u64::from(!samples.first().is_some_and(|s| s.exact > 0.0));
            for (maximum, sample) in self.maxima.iter_mut().zip(samples) {
                maximum.see(theta, sample);
            }
        }
    }

    /// Keep evaluated samples (`members` of them) as a panel end; returns the point id.
    fn store_point(&mut self, samples: &[Sample]) -> usize {
        let id = self.points.len() / self.members.max(1);
        self.points.extend_from_slice(samples);
        id
    }

    /// The θ of the interior nodes of the panel [a, b], in increasing order, appended to
    /// `thetas`.
    fn interior_thetas(&self, a: f64, b: f64, thetas: &mut Vec<f64>) {
        let span = Span::new(a, b);
        thetas.extend(self.rule.nodes[1..M - 1].iter().map(|&t| span.theta(t)));
    }

    /// Build the panel [a, b] between the stored end points, with the samples at its
    /// interior nodes (`members` per node, in node order), and return its id.
    #[inline(always)]
    fn panel(&mut self, a: f64, b: f64, ends: [usize; 2], interior: &[Sample]) -> usize {
        let (members, rule) = (self.members, self.rule);
        let span = Span::new(a, b);
        let mut nodes = std::mem::take(&mut self.nodes);
        nodes.clear();
        nodes.extend_from_slice(&self.points[ends[0] * members..(ends[0] + 1) * members]);
        nodes.extend_from_slice(interior);
        nodes.extend_from_slice(&self.points[ends[1] * members..(ends[1] + 1) * members]);
        let exact: [f64; M] = std::array::from_fn(|i| nodes[i * members].exact);
        let all_included = exact.iter().all(|&f| f > 0.0);
        let included = if all_included { b - a } else { span.half * rule.integral(&exact.map(|f| if f > 0.0 { 1.0 } else { 0.0 })) };
        let inverse: [f64; M] = exact.map(|f| if f > 0.0 { 1.0 / f } else { 0.0 });
        for m in 0..members {
            let samples = std::array::from_fn(|i| nodes[i * members + m]);
            self.contributions.push(member_panel(rule, span, samples, &inverse, all_included));
        }
        self.nodes = nodes;
        self.panels.push(Panel { a, b, ends, included, settled: false });
        self.panels.len() - 1
    }

    fn contributions(&self, panel: usize) -> &[MemberPanel] {
        &self.contributions[panel * self.members..(panel + 1) * self.members]
    }

    /// The panels still in the totals.
    fn live(&self) -> Vec<usize> {
        (0..self.panels.len()).filter(|&p| !self.panels[p].settled).collect()
    }
}

/// Adaptive integration over [0, π/2] of a family of `members` integrands, with the
/// given interior breakpoints (any order; out-of-range and duplicates ignored).
/// `integrand` fills one [`Sample`] per member at each θ, all with the same exact F.
pub fn adaptive<I: Integrand + ?Sized>(integrand: &I, members: usize, breakpoints: &[f64], tolerance: Tolerance) -> Vec<Integral> {
    let mut cuts: Vec<f64> = breakpoints.iter().copied().filter(|t| *t > 0.0 && *t < FRAC_PI_2).collect();
    cuts.push(0.0);
    cuts.push(FRAC_PI_2);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-14);
    // Many narrow panels (LUT texel intervals): Gauss; few wide ones: Kronrod.
    if cuts.len() > NARROW_PANELS {
        integrate(&GAUSS3, integrand, members, &cuts, tolerance)
    } else {
        integrate(&KRONROD7, integrand, members, &cuts, tolerance)
    }
}

/// The initial panels between the cuts, then the refinement. The cuts and every
/// initial panel's interior nodes are evaluated as one batch, in the order cuts first,
/// then the panels' nodes panel by panel.
///
/// The panel arithmetic is compiled for the widest vector unit the CPU has (AVX-512,
/// AVX2, or the baseline target), chosen at run time; the operations and their order are
/// the same in each (Rust never fuses a multiply and an add), so the bits are too.
#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn integrate<I: Integrand + ?Sized, const M: usize>(
    rule: &'static Rule<M>,
    integrand: &I,
    members: usize,
    cuts: &[f64],
    tolerance: Tolerance,
) -> Vec<Integral> {
    let mut state = Adaptive::new(rule, integrand, members, cuts.len());
    let mut thetas = cuts.to_vec();
    for w in cuts.windows(2) {
        state.interior_thetas(w[0], w[1], &mut thetas);
    }
    let mut samples = vec![Sample::default(); thetas.len() * members];
    state.evaluate(&thetas, &mut samples);
    let (ends, interiors) = samples.split_at(cuts.len() * members);
    let ids: Vec<usize> = ends.chunks(members.max(1)).map(|point| state.store_point(point)).collect();
    let per_panel = (M - 2) * members;
    for (p, w) in cuts.windows(2).enumerate() {
        let ends = if members == 0 { [0, 0] } else { [ids[p], ids[p + 1]] };
        state.panel(w[0], w[1], ends, &interiors[p * per_panel..(p + 1) * per_panel]);
    }
    refine(&mut state, tolerance);
    totals(&mut state)
}

/// Per member, the f64 relative and squared integrals of the initial panels: the scales
/// that make the members' error estimates comparable.
fn error_scales<I: Integrand + ?Sized, const M: usize>(state: &Adaptive<'_, I, M>) -> Vec<Criteria> {
    let mut scale = vec![Criteria::default(); state.members];
    for panel in 0..state.panels.len() {
        for (s, c) in scale.iter_mut().zip(state.contributions(panel)) {
            s.relative += c.sums.relative.f64;
            s.squared += c.sums.squared.f64;
        }
    }
    scale.iter().map(|s| Criteria { relative: s.relative.abs().max(RELATIVE_FLOOR), squared: s.squared.abs().max(SQUARED_FLOOR) }).collect()
}

/// Add (sign 1) or remove (sign −1) a panel's normalised errors to the per-member sums;
/// returns their total, the panel's priority.
fn account(sums: &mut [Criteria], scale: &[Criteria], contributions: &[MemberPanel], sign: f64) -> f64 {
    let mut total = 0.0;
    for ((c, s), sum) in contributions.iter().zip(scale).zip(sums.iter_mut()) {
        let errors = Criteria { relative: c.error.relative / s.relative, squared: c.error.squared / s.squared };
        sum.relative += sign * errors.relative;
        sum.squared += sign * errors.squared;
        total += errors.relative + errors.squared;
    }
    total
}

/// Bisect the panel of largest error estimate until every member's summed estimates are
/// below the tolerance (or the evaluations run out).
#[inline(always)]
fn refine<I: Integrand + ?Sized, const M: usize>(state: &mut Adaptive<'_, I, M>, tolerance: Tolerance) {
    let scale = error_scales(state);
    let mut error_sums = vec![Criteria::default(); state.members];
    let mut heap = BinaryHeap::with_capacity(state.panels.len());
    for panel in 0..state.panels.len() {
        let priority = account(&mut error_sums, &scale, state.contributions(panel), 1.0);
        heap.push(Ranked(priority, panel));
    }
    let worst = |sums: &[Criteria]| sums.iter().flat_map(|s| [s.relative, s.squared]).fold(0.0, f64::max);
    let mut refinements = 0u64;
    let members = state.members;
    let (mut thetas, mut samples) = (Vec::with_capacity(2 * M - 3), Vec::new());
    while worst(&error_sums) > tolerance.relative && state.evaluations < tolerance.max_evaluations {
        let Some(Ranked(_, id)) = heap.pop() else { break };
        let panel = state.panels[id];
        account(&mut error_sums, &scale, state.contributions(id), -1.0);
        if panel.b - panel.a <= tolerance.min_width {
            // Frozen: kept in the totals, no longer refined.
            continue;
        }
        state.panels[id].settled = true;
        // The midpoint and both halves' interior nodes, evaluated as one batch.
        let middle = 0.5 * (panel.a + panel.b);
        thetas.clear();
        thetas.push(middle);
        state.interior_thetas(panel.a, middle, &mut thetas);
        state.interior_thetas(middle, panel.b, &mut thetas);
        samples.clear();
        samples.resize(thetas.len() * members, Sample::default());
        state.evaluate(&thetas, &mut samples);
        let mid = state.store_point(&samples[..members]);
        let per_panel = (M - 2) * members;
        let halves = [(panel.a, middle, [panel.ends[0], mid]), (middle, panel.b, [mid, panel.ends[1]])];
        for (half, (a, b, ends)) in halves.into_iter().enumerate() {
            let interior = &samples[members + half * per_panel..members + (half + 1) * per_panel];
            let child = state.panel(a, b, ends, interior);
            let priority = account(&mut error_sums, &scale, state.contributions(child), 1.0);
            heap.push(Ranked(priority, child));
        }
        refinements += 1;
        // Re-sum now and then against drift of the running totals.
        if refinements.is_multiple_of(256) {
            error_sums.iter_mut().for_each(|s| *s = Criteria::default());
            for Ranked(_, id) in heap.iter() {
                account(&mut error_sums, &scale, state.contributions(*id), 1.0);
            }
        }
    }
}

/// The figures of every member from the live panels, the maximum refined.
fn totals<I: Integrand + ?Sized, const M: usize>(state: &mut Adaptive<'_, I, M>) -> Vec<Integral> {
    let live = state.live();
    let included: f64 = live.iter().map(|&p| state.panels[p].included).sum();
    let mut sums = vec![Sums::default(); state.members];
    for &p in &live {
        for (s, c) in sums.iter_mut().zip(state.contributions(p)) {
            s.add(&c.sums);
        }
    }
    for m in 0..state.members {
        refine_maxima(state, m, &live);
    }
    (0..state.members)
        .map(|m| Integral {
            figures: figures(&sums[m], included, FRAC_PI_2, &state.maxima[m]),
            excluded_samples: state.excluded,
            evaluations: state.evaluations,
        })
        .collect()
}

/// Brent's search around the largest node differences of `member`: the largest, and the
/// runners-up only where their node value comes near the maximum found so far (between
/// nodes a smooth difference rises by far less than 10 %).
fn refine_maxima<I: Integrand + ?Sized, const M: usize>(state: &mut Adaptive<'_, I, M>, member: usize, live: &[usize]) {
    let mut peaks = [Peak::default(); PEAKS_REFINED];
    for &p in live {
        let peak = state.contributions(p)[member].peak;
        if let Some(slot) = peaks.iter().position(|q| peak.value > q.value) {
            peaks[slot..].rotate_right(1);
            peaks[slot] = peak;
        }
    }
    for (rank, peak) in peaks.iter().enumerate() {
        if peak.value > 0.0 && (rank == 0 || peak.value >= 0.9 * state.maxima[member].value.f64) {
            refine_maximum(state, member, peak);
        }
    }
}

/// Brent's method (Brent 1973, ch. 5: parabolic steps with golden-section fallback) for
/// the largest f64 |F_m − F_e| of `member` in the peak's bracket, starting from its node;
/// to 1e-9 relative in θ, which puts a smooth maximum at f64 precision in about ten
/// evaluations. Every point seen counts for every member and both precisions.
fn refine_maximum<I: Integrand + ?Sized, const M: usize>(state: &mut Adaptive<'_, I, M>, member: usize, peak: &Peak) {
    const TOLERANCE: f64 = 1e-9;
    let mut out = vec![Sample::default(); state.members];
    // Minimise −|d|; the state records every evaluation.
    let f = |theta: f64| {
        state.evaluate(&[theta], &mut out);
        -out[member].difference(Precision::F64).abs()
    };
    nklut_optics::minimise::brent(f, (peak.lo, peak.hi), (peak.theta, -peak.value), |x| TOLERANCE * x.abs() + 1e-15, 40);
}

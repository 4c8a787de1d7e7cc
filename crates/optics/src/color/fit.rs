//! Effective channel indices: the (n, k) whose exact Fresnel curve is closest to a
//! channel of the spectral reference curve over all angles.
//!
//! Minimises the relative least squares Σ_i q_i ((F(n, k, θ_i) − F_ref,i)/F_ref,i)² over
//! the angle quadrature (nodes θ_i, weights q_i: a mean over θ uniform in [0°, 90°]) with
//! Levenberg–Marquardt (Marquardt's diagonal scaling, central-difference Jacobian) in
//! the unconstrained parameters u = ln n, v = ln(k + K_OFFSET), so that n > 0 and
//! k = max(eᵛ − K_OFFSET, 0) ≥ 0 by construction. Several deterministic starts; the one
//! with the smallest cost wins. Since F_exact ≤ 1, a reference above 1 (gold's red
//! channel) can only be approached, never matched.

use super::angle_average::AngleQuadrature;
use crate::fresnel;
use crate::spectrum::Index;

/// k = eᵛ − K_OFFSET: lets the search reach k = 0 at a finite v.
const K_OFFSET: f64 = 1e-6;
/// Search box in (ln n, ln(k + K_OFFSET)): n ∈ [10⁻³, 100], k ∈ [0, 100].
const U_RANGE: (f64, f64) = (-6.907_755_278_982_137, 4.605_170_185_988_092);
const V_RANGE: (f64, f64) = (-13.815_510_557_964_274, 4.605_170_185_988_092);
/// The search box in (n, k): a fit ending on one of these bounds did not converge inside it.
pub const N_BOUNDS: (f64, f64) = (1e-3, 100.0);
/// The largest k of the search box.
pub const K_MAX: f64 = 100.0;
const MAX_ITERATIONS: usize = 100;
const JACOBIAN_STEP: f64 = 1e-6;

/// A fitted index and its mean relative error over θ against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EffectiveIndex {
    /// The fitted (n, k).
    pub index: Index,
    /// Mean over θ of |F_exact(n, k, θ) − F_ref(θ)| / |F_ref(θ)| (a fraction).
    pub error: f64,
}

impl EffectiveIndex {
    /// Whether the fit ended on the search box's edge ([`N_BOUNDS`], [`K_MAX`]): the best
    /// (n, k) lies outside the box (or nowhere), and the index is a curve fit, not the
    /// material's optics — gold's red channel fits to (0.001, 100).
    pub fn at_bound(&self) -> bool {
        let Index { n, k } = self.index;
        n <= N_BOUNDS.0 * (1.0 + 1e-6) || n >= N_BOUNDS.1 * (1.0 - 1e-6) || k >= K_MAX * (1.0 - 1e-6)
    }
}

/// Mean over θ of |F_exact(index, θ) − F_ref(θ)| / |F_ref(θ)| with `reference[i]` at
/// `quadrature.cosines[i]`. Nodes where F_ref is 0 or not finite are left out (the
/// weights of the rest renormalised); with none left the error is 0.
pub fn mean_relative_error(index: Index, reference: &[f64], quadrature: &AngleQuadrature) -> f64 {
    let mut curve = vec![0.0; quadrature.cosines.len()];
    fresnel::ExactTerms::new(fresnel::sanitise(index)).reflectances(&quadrature.cosines, &mut curve);
    let mut sum = 0.0;
    let mut weight = 0.0;
    for ((&f, &q), &r) in curve.iter().zip(&quadrature.weights).zip(reference) {
        if r != 0.0 && r.is_finite() {
            sum += q * (f - r).abs() / r.abs();
            weight += q;
        }
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

/// The effective index of one channel: `reference[i]` is the spectral reference at
/// `quadrature.cosines[i]`, `start` the first guess (the three-wavelength index). Always
/// returns a finite n > 0 and k ≥ 0.
pub fn fit_effective_index(reference: &[f64], start: Index, quadrature: &AngleQuadrature) -> EffectiveIndex {
    let problem = Problem::new(reference, quadrature);
    fit_from(&problem, &starts(start, problem.normal_reference()), start, reference, quadrature)
}

/// [`fit_effective_index`] from the given first guesses only (for a caller that already
/// has a good one, e.g. the best index of a one-parameter family); `start` is also the
/// answer if no guess can be evaluated.
pub fn fit_effective_index_from(reference: &[f64], guesses: &[Index], quadrature: &AngleQuadrature) -> EffectiveIndex {
    let problem = Problem::new(reference, quadrature);
    let guesses: Vec<Index> = guesses.iter().map(|g| sanitise(*g)).collect();
    fit_from(&problem, &guesses, guesses.first().copied().unwrap_or(Index::new(1.5, 0.0)), reference, quadrature)
}

fn fit_from(problem: &Problem, guesses: &[Index], start: Index, reference: &[f64], quadrature: &AngleQuadrature) -> EffectiveIndex {
    let best = guesses.iter().map(|guess| problem.minimise(to_parameters(*guess))).fold(
        None,
        |best: Option<([f64; 2], f64)>, candidate| match best {
            Some(b) if b.1 <= candidate.1 => Some(b),
            _ => Some(candidate),
        },
    );
    let index = best.map_or(sanitise(start), |(p, _)| to_index(p));
    EffectiveIndex { index, error: mean_relative_error(index, reference, quadrature) }
}

/// Deterministic first guesses: the given index, the dielectric with the reference's
/// near-normal reflectance F (n = (1 + √F)/(1 − √F), k = 0) and a metal with n = 0.5 and
/// the k that gives F at normal incidence.
fn starts(start: Index, normal_reflectance: f64) -> Vec<Index> {
    let mut guesses = vec![sanitise(start)];
    let f = normal_reflectance.clamp(1e-8, 0.999);
    let root = f.sqrt();
    guesses.push(Index::new((1.0 + root) / (1.0 - root), 0.0));
    let n = 0.5_f64;
    let k_squared = (f * (n + 1.0).powi(2) - (n - 1.0).powi(2)) / (1.0 - f);
    if k_squared > 0.0 {
        guesses.push(Index::new(n, k_squared.sqrt()));
    }
    guesses
}

/// A physical, finite index inside the search box.
fn sanitise(index: Index) -> Index {
    let n = if index.n.is_finite() && index.n > 0.0 { index.n } else { 1.5 };
    let k = if index.k.is_finite() && index.k > 0.0 { index.k } else { 0.0 };
    to_index(to_parameters(Index::new(n, k)))
}

fn to_parameters(index: Index) -> [f64; 2] {
    let u = index.n.max(f64::MIN_POSITIVE).ln();
    let v = (index.k.max(0.0) + K_OFFSET).ln();
    clamp([u, v])
}

fn to_index(p: [f64; 2]) -> Index {
    Index::new(p[0].exp(), (p[1].exp() - K_OFFSET).max(0.0))
}

fn clamp(p: [f64; 2]) -> [f64; 2] {
    let u = if p[0].is_finite() { p[0].clamp(U_RANGE.0, U_RANGE.1) } else { 0.0 };
    let v = if p[1].is_finite() { p[1].clamp(V_RANGE.0, V_RANGE.1) } else { V_RANGE.0 };
    [u, v]
}

/// The least-squares problem of one channel: nodes, √weight/|F_ref| factors, targets.
struct Problem {
    cosines: Vec<f64>,
    scales: Vec<f64>,
    targets: Vec<f64>,
}

impl Problem {
    fn new(reference: &[f64], quadrature: &AngleQuadrature) -> Self {
        let mut problem = Problem { cosines: vec![], scales: vec![], targets: vec![] };
        for ((&c, &q), &r) in quadrature.cosines.iter().zip(&quadrature.weights).zip(reference) {
            if r != 0.0 && r.is_finite() {
                problem.cosines.push(c);
                problem.scales.push(q.sqrt() / r.abs());
                problem.targets.push(r);
            }
        }
        problem
    }

    /// The reference at the node closest to normal incidence (0 with no nodes).
    fn normal_reference(&self) -> f64 {
        self.cosines.iter().zip(&self.targets).fold((f64::NEG_INFINITY, 0.0), |best, (&c, &r)| if c > best.0 { (c, r) } else { best }).1
    }

    fn residuals(&self, p: [f64; 2], out: &mut [f64]) {
        fresnel::ExactTerms::new(fresnel::sanitise(to_index(p))).reflectances(&self.cosines, out);
        for (i, out) in out.iter_mut().enumerate() {
            *out = self.scales[i] * (*out - self.targets[i]);
        }
    }

    fn cost(&self, p: [f64; 2], scratch: &mut [f64]) -> f64 {
        self.residuals(p, scratch);
        let cost: f64 = scratch.iter().map(|r| r * r).sum();
        if cost.is_finite() {
            cost
        } else {
            f64::INFINITY
        }
    }

    /// Levenberg–Marquardt from `p`; returns the final parameters and cost.
    fn minimise(&self, mut p: [f64; 2]) -> ([f64; 2], f64) {
        let m = self.cosines.len();
        let (mut residual, mut plus, mut minus, mut scratch) = (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let mut jacobian = [vec![0.0; m], vec![0.0; m]];
        let mut cost = self.cost(p, &mut residual);
        let mut damping = 1e-3;
        for _ in 0..MAX_ITERATIONS {
            self.residuals(p, &mut residual);
            for (axis, column) in jacobian.iter_mut().enumerate() {
                let (mut up, mut down) = (p, p);
                up[axis] += JACOBIAN_STEP;
                down[axis] -= JACOBIAN_STEP;
                self.residuals(up, &mut plus);
                self.residuals(down, &mut minus);
                for i in 0..m {
                    column[i] = (plus[i] - minus[i]) / (2.0 * JACOBIAN_STEP);
                }
            }
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
            let (a11, a12, a22) = (dot(&jacobian[0], &jacobian[0]), dot(&jacobian[0], &jacobian[1]), dot(&jacobian[1], &jacobian[1]));
            let (g1, g2) = (dot(&jacobian[0], &residual), dot(&jacobian[1], &residual));
            let mut accepted = None;
            while damping < 1e12 {
                let d11 = a11 + damping * a11.max(1e-12);
                let d22 = a22 + damping * a22.max(1e-12);
                let det = d11 * d22 - a12 * a12;
                let step = [-(d22 * g1 - a12 * g2) / det, -(d11 * g2 - a12 * g1) / det];
                if det > 0.0 && step.iter().all(|s| s.is_finite()) {
                    let candidate = clamp([p[0] + step[0], p[1] + step[1]]);
                    let candidate_cost = self.cost(candidate, &mut scratch);
                    if candidate_cost < cost {
                        accepted = Some((candidate, candidate_cost));
                        damping = (damping / 3.0).max(1e-12);
                        break;
                    }
                }
                damping *= 4.0;
            }
            let Some((candidate, candidate_cost)) = accepted else { break };
            let moved = (candidate[0] - p[0]).abs().max((candidate[1] - p[1]).abs());
            let gained = cost - candidate_cost;
            p = candidate;
            cost = candidate_cost;
            if moved < 1e-10 || gained <= 1e-13 * cost {
                break;
            }
        }
        (p, cost)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::angle_average::angle_quadrature;
    use proptest::prelude::*;

    fn curve(index: Index, quadrature: &AngleQuadrature) -> Vec<f64> {
        quadrature.cosines.iter().map(|&c| fresnel::exact(index.n, index.k, c)).collect()
    }

    #[test]
    fn recovers_the_index_of_an_exact_curve_from_a_distant_start() {
        let rule = angle_quadrature();
        for truth in [Index::new(0.27, 2.9), Index::new(1.45, 0.0), Index::new(2.4, 0.3), Index::new(1.1, 6.5)] {
            let fit = fit_effective_index(&curve(truth, rule), Index::new(1.0, 1.0), rule);
            assert!(fit.error < 1e-7, "{truth:?} → {fit:?}");
            assert!((fit.index.n / truth.n - 1.0).abs() < 1e-4, "{truth:?} → {fit:?}");
            assert!((fit.index.k - truth.k).abs() < 1e-4 * truth.k.max(1.0), "{truth:?} → {fit:?}");
        }
    }

    #[test]
    fn a_reference_above_one_cannot_be_matched() {
        let rule = angle_quadrature();
        let reference: Vec<f64> = curve(Index::new(0.2, 3.5), rule).iter().map(|f| f * 1.05).collect();
        let fit = fit_effective_index(&reference, Index::new(0.2, 3.5), rule);
        // F_exact ≤ 1, so where F_ref > 1 the relative error is at least (F_ref − 1)/F_ref.
        let floor: f64 = reference.iter().zip(&rule.weights).filter(|(r, _)| **r > 1.0).map(|(r, q)| q * (r - 1.0) / r).sum();
        assert!(floor > 1e-3, "{floor}");
        assert!(fit.error >= floor && fit.error < 3.0 * floor, "{fit:?} vs floor {floor}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// Whatever the reference — physical, scaled, negative in places — the fit is a
        /// physical index with a finite error.
        #[test]
        fn fit_is_always_physical(n in 0.05f64..5.0, k in 0.0f64..8.0, scale in -0.2f64..1.3, tilt in -0.5f64..0.5, start_n in 0.01f64..10.0, start_k in 0.0f64..10.0) {
            let rule = angle_quadrature();
            let reference: Vec<f64> = rule.cosines.iter().map(|&c| scale * fresnel::exact(n, k, c) + tilt * c * (1.0 - c)).collect();
            let fit = fit_effective_index(&reference, Index::new(start_n, start_k), rule);
            prop_assert!(fit.index.n > 0.0 && fit.index.n.is_finite(), "{:?}", fit);
            prop_assert!(fit.index.k >= 0.0 && fit.index.k.is_finite(), "{:?}", fit);
            prop_assert!(fit.error.is_finite() && fit.error >= 0.0, "{:?}", fit);
        }

        #[test]
        fn fit_survives_degenerate_starts(start_n in prop_oneof![Just(f64::NAN), Just(0.0), Just(-1.0), Just(f64::INFINITY), 0.01f64..3.0], start_k in prop_oneof![Just(f64::NAN), Just(-2.0), Just(f64::INFINITY), 0.0f64..3.0]) {
            let rule = angle_quadrature();
            let reference = curve(Index::new(0.5, 2.0), rule);
            let fit = fit_effective_index(&reference, Index::new(start_n, start_k), rule);
            prop_assert!(fit.index.n > 0.0 && fit.index.n.is_finite() && fit.index.k >= 0.0 && fit.index.k.is_finite());
            prop_assert!(fit.error < 1e-6, "{:?}", fit);
        }
    }
}

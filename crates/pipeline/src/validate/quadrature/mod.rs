//! The error integrals of a Fresnel method (SPEC §6) over θ ∈ [0, π/2], uniform in θ:
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

pub mod adaptive;
pub mod brute_force;
pub mod rule;

pub use adaptive::{adaptive, Tolerance};
pub use brute_force::{brute_force, BRUTE_FORCE_SAMPLES};

use nklut_optics::fresnel::{PerPrecision, Precision};

/// What is integrated: a family of members evaluated together at each θ.
pub trait Integrand {
    /// The samples at each of `thetas`, in that order, into `out`: one [`Sample`] per
    /// member at each θ (point-major, `out.len()` = members × `thetas.len()`), every
    /// member with the same exact F. Batches let an integrand evaluate several angles in
    /// vector lanes; each sample must not depend on the others in the batch.
    fn evaluate(&self, thetas: &[f64], out: &mut [Sample]);
}

/// A family evaluated one θ at a time by `f(θ, out)` (one sample per member).
impl<F: Fn(f64, &mut [Sample])> Integrand for F {
    fn evaluate(&self, thetas: &[f64], out: &mut [Sample]) {
        let members = out.len() / thetas.len().max(1);
        for (j, &theta) in thetas.iter().enumerate() {
            self(theta, &mut out[j * members..(j + 1) * members]);
        }
    }
}

/// One evaluation of one member: exact F and the method in f64 and in f32 (widened).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    pub exact: f64,
    pub approx: PerPrecision<f64>,
}

impl Sample {
    /// F_m − F_e in `precision`.
    #[inline]
    fn difference(&self, precision: Precision) -> f64 {
        self.approx[precision] - self.exact
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
    /// The f64 method and its f32 twin.
    pub figures: PerPrecision<Figures>,
    /// Evaluation points where F_e = 0 (excluded from the relative error).
    pub excluded_samples: u64,
    /// Points θ at which the family was evaluated (exact once, every member in f64 and
    /// f32); the members of a family share them.
    pub evaluations: u64,
}

/// Integrals (or sample sums, for the brute force) of one member.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sums {
    relative: PerPrecision<f64>,
    squared: PerPrecision<f64>,
}

impl Sums {
    fn add(&mut self, other: &Sums) {
        for precision in Precision::ALL {
            self.relative[precision] += other.relative[precision];
            self.squared[precision] += other.squared[precision];
        }
    }
}

/// Largest |F_m − F_e| seen, per precision, with where.
#[derive(Clone, Copy, Debug, Default)]
struct Maximum {
    value: PerPrecision<f64>,
    theta: PerPrecision<f64>,
}

impl Maximum {
    fn see(&mut self, theta: f64, sample: &Sample) {
        for precision in Precision::ALL {
            let error = sample.difference(precision).abs();
            if error > self.value[precision] {
                self.value[precision] = error;
                self.theta[precision] = theta;
            }
        }
    }

    fn merge(mut self, other: &Maximum) -> Maximum {
        for precision in Precision::ALL {
            if other.value[precision] > self.value[precision] {
                self.value[precision] = other.value[precision];
                self.theta[precision] = other.theta[precision];
            }
        }
        self
    }
}

/// Figures from the integrals over a θ-range of `length` of which `included` has F_e > 0.
fn figures(sums: &Sums, included: f64, length: f64, maximum: &Maximum) -> PerPrecision<Figures> {
    PerPrecision::from_fn(|precision| Figures {
        mean_rel_error: (included > 0.0).then(|| sums.relative[precision] / included),
        max_abs_error: maximum.value[precision],
        rms_abs_error: (sums.squared[precision] / length).max(0.0).sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use std::f64::consts::FRAC_PI_2;

    use super::*;

    /// A family of one member from a single-sample function.
    fn single(f: impl Fn(f64) -> Sample) -> impl Fn(f64, &mut [Sample]) {
        move |theta, out: &mut [Sample]| out[0] = f(theta)
    }

    #[test]
    fn smooth_integrand_matches_closed_form() {
        // F_e = 0.5, F_m = 0.5 + 0.1 sin θ.
        // mean |g|/F = (0.1/0.5)·(1/(π/2))∫₀^{π/2} sin θ dθ = 0.2·2/π.
        // rms = √(0.01·(1/(π/2))∫sin² θ dθ) = √(0.01·½) = 0.0707…
        let f = single(|theta: f64| Sample { exact: 0.5, approx: PerPrecision::splat(0.5 + 0.1 * theta.sin()) });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        let expected = 0.4 / std::f64::consts::PI;
        assert!((i.figures.f64.mean_rel_error.unwrap() - expected).abs() < 1e-13);
        assert!((i.figures.f64.rms_abs_error - 0.005f64.sqrt()).abs() < 1e-13);
        assert!((i.figures.f64.max_abs_error - 0.1).abs() < 1e-12);
        assert!(i.evaluations < 300, "{}", i.evaluations);
        let b = brute_force(&f, 1, 100_000)[0];
        assert!((b.figures.f64.mean_rel_error.unwrap() - expected).abs() < 1e-9);
    }

    #[test]
    fn sign_changes_are_integrated_through_the_root() {
        // F_m − F_e = 0.1 (θ − 1): |·| has a kink at θ = 1, inside the only panel.
        let f = single(|theta: f64| Sample { exact: 1.0, approx: PerPrecision::splat(1.0 + 0.1 * (theta - 1.0)) });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        // ∫|θ − 1| over [0, π/2] = ½ + ½(π/2 − 1)².
        let exact = 0.1 * (0.5 + 0.5 * (FRAC_PI_2 - 1.0).powi(2)) / FRAC_PI_2;
        assert!((i.figures.f64.mean_rel_error.unwrap() - exact).abs() < 1e-14, "{:?}", i.figures.f64);
        assert!((i.figures.f32.mean_rel_error.unwrap() - exact).abs() < 1e-14, "{:?}", i.figures.f32);
        assert!(i.evaluations < 50, "{}", i.evaluations);
    }

    #[test]
    fn members_share_evaluations_and_keep_their_own_figures() {
        // Member 0: F_m − F_e = 0.1 sin θ; member 1: 0.2 (θ − 1) on F_e = 1.
        let f = |theta: f64, out: &mut [Sample]| {
            out[0] = Sample { exact: 1.0, approx: PerPrecision::splat(1.0 + 0.1 * theta.sin()) };
            out[1] = Sample { exact: 1.0, approx: PerPrecision::splat(1.0 + 0.2 * (theta - 1.0)) };
        };
        let both = adaptive(&f, 2, &[], Tolerance::default());
        assert_eq!(both[0].evaluations, both[1].evaluations);
        assert!((both[0].figures.f64.mean_rel_error.unwrap() - 0.1 / FRAC_PI_2).abs() < 1e-13);
        let kink = 0.2 * (0.5 + 0.5 * (FRAC_PI_2 - 1.0).powi(2)) / FRAC_PI_2;
        assert!((both[1].figures.f64.mean_rel_error.unwrap() - kink).abs() < 1e-13);
        assert!((both[1].figures.f64.max_abs_error - 0.2).abs() < 1e-12);
    }

    #[test]
    fn noisy_f32_difference_is_a_sample_mean_of_its_magnitude() {
        // f64 exact (difference 0), f32 alternating ±1e-7 relative noise: the figure must
        // be about 1e-7, not the cancelled mean.
        let f = single(|theta: f64| {
            let noise = if ((theta * 1e6) as i64) % 2 == 0 { 1e-7 } else { -1e-7 };
            Sample { exact: 0.5, approx: PerPrecision { f64: 0.5, f32: 0.5 * (1.0 + noise) } }
        });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        assert_eq!(i.figures.f64.mean_rel_error, Some(0.0));
        let f32_mean = i.figures.f32.mean_rel_error.unwrap();
        assert!((f32_mean - 1e-7).abs() < 1e-12, "{f32_mean}");
    }

    #[test]
    fn zero_reflectance_is_excluded() {
        let f = single(|_| Sample { exact: 0.0, approx: PerPrecision::splat(0.0) });
        let i = adaptive(&f, 1, &[], Tolerance::default())[0];
        assert_eq!(i.figures.f64.mean_rel_error, None);
        assert_eq!(i.excluded_samples, i.evaluations);
        let b = brute_force(&f, 1, 1000)[0];
        assert_eq!(b.excluded_samples, 1000);
        assert_eq!(b.figures.f32.mean_rel_error, None);
    }
}

//! The engine parameterisations of a Fresnel curve and their fits to a reference curve
//! F_ref(μ), μ = cosθ, one colour channel at a time (the generalized Schlick exponent is
//! shared by the three channels, as MaterialX's node takes one float).
//!
//! - F82 tint (Hoffman 2019, "Fresnel Equations Considered Harmful"; 2023, "Generalization
//!   of Adobe's Fresnel Model"; OpenPBR 1.1 `specular_color` of metals): with μ̄ = 1/7 and
//!   F_S(μ) = F0 + (1 − F0)(1 − μ)⁵, tint = F_ref(μ̄)/F_S(μ̄) and
//!   F(μ) = F_S(μ) − b μ(1 − μ)⁶, b = F_S(μ̄)(1 − tint)/(μ̄(1 − μ̄)⁶).
//! - Gulbrandsen 2014, "Artist Friendly Metallic Fresnel" (JCGT 3(4)), MaterialX
//!   `artistic_ior`: reflectivity r and edge tint g map to
//!   n = g (1 − r)/(1 + r) + (1 − g)(1 + √r)/(1 − √r),
//!   k = √(max(0, ((n + 1)² r − (n − 1)²)/(1 − r))); F = exact Fresnel of (n, k).
//!   r is clamped to [0, 0.99] as MaterialX's implementation does.
//! - Generalized Schlick (Hoffman 2023; MaterialX `generalized_schlick_bsdf`, function
//!   `mx_fresnel_hoffman_schlick`): S(μ) = color0 + (color90 − color0)(1 − μ)^p,
//!   F(μ) = S(μ) − a μ(1 − μ)⁶ with a = S(μ̄)(1 − color82)/(μ̄(1 − μ̄)⁶).
//!
//! Fits minimise the relative least squares Σ_i q_i ((F(μ_i) − F_ref,i)/F_ref,i)² over the
//! angle quadrature (a mean over θ uniform in [0°, 90°]) with a grid scan followed by
//! Brent's method ([`minimise_1d`]).

use nklut_optics::color::AngleQuadrature;
use nklut_optics::fresnel::{self, ExactTerms, LAZANYI_COS};
use nklut_optics::spectrum::Index;

/// μ̄ = cos θ̄ = 1/7 (θ̄ ≈ 81.8°), where μ(1 − μ)⁶ peaks: the angle of the F82 models.
pub const EDGE_COS: f64 = LAZANYI_COS;
/// Gulbrandsen's reflectivity is clamped to [0, GULBRANDSEN_MAX_R] (MaterialX's
/// `mx_artistic_ior` does the same; √r → 1 sends n to infinity).
pub const GULBRANDSEN_MAX_R: f64 = 0.99;
/// The range searched for the generalized Schlick exponent.
pub const EXPONENT_RANGE: (f64, f64) = (1.0, 16.0);

/// The tint that takes a curve worth `model_at_edge` at μ̄ to `reference_at_edge`:
/// their ratio, or 1 (no tint) where the ratio is undefined.
fn edge_tint(model_at_edge: f64, reference_at_edge: f64) -> f64 {
    if model_at_edge.abs() > 1e-300 && reference_at_edge.is_finite() {
        reference_at_edge / model_at_edge
    } else {
        1.0
    }
}

/// μ(1 − μ)⁶ at μ̄: the weight of the F82 correction term there.
fn edge_weight() -> f64 {
    EDGE_COS * (1.0 - EDGE_COS).powi(6)
}

/// Hoffman's F82-tint model of one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct F82Tint {
    pub f0: f64,
    /// F_ref(μ̄)/F_S(μ̄): OpenPBR `specular_color`, Blender 4 "Specular Tint" of metals.
    pub tint: f64,
    /// b = F_S(μ̄)(1 − tint)/(μ̄(1 − μ̄)⁶): the coefficient a shader evaluates.
    pub b: f64,
}

impl F82Tint {
    /// The model that starts at `f0` and passes through `reference_at_edge` at μ̄.
    pub fn new(f0: f64, reference_at_edge: f64) -> Self {
        let schlick = fresnel::schlick(f0, EDGE_COS);
        let tint = edge_tint(schlick, reference_at_edge);
        Self { f0, tint, b: schlick * (1.0 - tint) / edge_weight() }
    }

    pub fn reflectance(&self, cos_theta: f64) -> f64 {
        fresnel::lazanyi(self.f0, self.b, cos_theta)
    }
}

/// Gulbrandsen's artist-friendly parameters of one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gulbrandsen {
    /// Reflectivity r = F0, in [0, GULBRANDSEN_MAX_R].
    pub r: f64,
    /// Edge tint g: 0 gives the largest n (k = 0), 1 the smallest n (largest k).
    pub g: f64,
}

impl Gulbrandsen {
    /// n_min = (1 − r)/(1 + r) and n_max = (1 + √r)/(1 − √r) for this r.
    fn n_range(r: f64) -> (f64, f64) {
        let root = r.sqrt();
        ((1.0 - r) / (1.0 + r), (1.0 + root) / (1.0 - root))
    }

    /// r clamped to the model's domain (NaN reads as 0).
    pub fn clamp_r(r: f64) -> f64 {
        if r.is_nan() {
            0.0
        } else {
            r.clamp(0.0, GULBRANDSEN_MAX_R)
        }
    }

    /// (r, g) → (n, k) (the formulas of the module header).
    pub fn index(&self) -> Index {
        let r = Self::clamp_r(self.r);
        let (n_min, n_max) = Self::n_range(r);
        let n = self.g * n_min + (1.0 - self.g) * n_max;
        let k_squared = ((n + 1.0) * (n + 1.0) * r - (n - 1.0) * (n - 1.0)) / (1.0 - r);
        Index::new(n, k_squared.max(0.0).sqrt())
    }

    /// (n, k) → (r, g): r = ((n − 1)² + k²)/((n + 1)² + k²), g = (n_max − n)/(n_max − n_min)
    /// (g = 0 where the range is empty, r = 0). The inverse of [`Gulbrandsen::index`] for
    /// r ≤ GULBRANDSEN_MAX_R and g ∈ [0, 1].
    pub fn from_index(index: Index) -> Self {
        let r = Self::clamp_r(fresnel::schlick_f0(index.n, index.k));
        let (n_min, n_max) = Self::n_range(r);
        let span = n_max - n_min;
        let g = if span > 0.0 { (n_max - index.n) / span } else { 0.0 };
        Self { r, g }
    }

    /// The (r, g) with r = `f0` (clamped) whose exact Fresnel curve is closest to
    /// `reference` (at `rule.cosines`), g ∈ [0, 1].
    pub fn fit(f0: f64, reference: &[f64], rule: &AngleQuadrature) -> Self {
        let r = Self::clamp_r(f0);
        let mut curve = vec![0.0; rule.cosines.len()];
        let cost = |g: f64| {
            ExactTerms::new(Gulbrandsen { r, g }.index()).reflectances(&rule.cosines, &mut curve);
            relative_cost(&curve, reference, rule)
        };
        Self { r, g: minimise_1d(cost, 0.0, 1.0, 16, 1e-7) }
    }
}

/// Hoffman's generalized Schlick model of the three channels (MaterialX
/// `generalized_schlick_bsdf`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneralizedSchlick {
    pub color0: [f64; 3],
    pub color82: [f64; 3],
    pub color90: [f64; 3],
    pub exponent: f64,
}

impl GeneralizedSchlick {
    /// color0 = `f0`, color90 = 1 (every Fresnel curve reaches 1 at grazing), the given
    /// exponent, and color82 so that the model passes through `reference_at_edge` at μ̄.
    pub fn through_edge(f0: [f64; 3], reference_at_edge: [f64; 3], exponent: f64) -> Self {
        let model = Self { color0: f0, color82: [1.0; 3], color90: [1.0; 3], exponent };
        Self { color82: [0, 1, 2].map(|c| edge_tint(model.schlick(c, EDGE_COS), reference_at_edge[c])), ..model }
    }

    /// S(μ) = color0 + (color90 − color0)(1 − μ)^p of channel `c`.
    fn schlick(&self, c: usize, cos_theta: f64) -> f64 {
        let m = 1.0 - fresnel::unit_cos(cos_theta);
        self.color0[c] + (self.color90[c] - self.color0[c]) * m.powf(self.exponent)
    }

    /// F(μ) of channel `c`.
    pub fn reflectance(&self, c: usize, cos_theta: f64) -> f64 {
        let mu = fresnel::unit_cos(cos_theta);
        let a = self.schlick(c, EDGE_COS) * (1.0 - self.color82[c]) / edge_weight();
        self.schlick(c, mu) - a * mu * (1.0 - mu).powi(6)
    }

    /// The exponent in [`EXPONENT_RANGE`] (color82 following it) whose curves are closest
    /// to `reference[c]` summed over the three channels.
    pub fn fit(f0: [f64; 3], reference_at_edge: [f64; 3], reference: &[Vec<f64>; 3], rule: &AngleQuadrature) -> Self {
        // Per node, ln(1 − μ) and μ(1 − μ)⁶, so that a trial exponent costs one exp per
        // node: (1 − μ)^p = exp(p ln(1 − μ)) (0 at μ = 1, where ln gives −∞).
        let log_m: Vec<f64> = rule.cosines.iter().map(|&mu| (1.0 - fresnel::unit_cos(mu)).ln()).collect();
        let edge_term: Vec<f64> = rule.cosines.iter().map(|&mu| mu * (1.0 - mu).powi(6)).collect();
        let cost = |p: f64| {
            let model = Self::through_edge(f0, reference_at_edge, p);
            let a = [0, 1, 2].map(|c| model.schlick(c, EDGE_COS) * (1.0 - model.color82[c]) / edge_weight());
            let mut total = 0.0;
            for (i, &q) in rule.weights.iter().enumerate() {
                let m_p = (p * log_m[i]).exp();
                for c in 0..3 {
                    let r = reference[c][i];
                    if r != 0.0 && r.is_finite() {
                        let f = model.color0[c] + (model.color90[c] - model.color0[c]) * m_p - a[c] * edge_term[i];
                        let e = (f - r) / r;
                        total += q * e * e;
                    }
                }
            }
            if total.is_finite() {
                total
            } else {
                f64::INFINITY
            }
        };
        let exponent = minimise_1d(cost, EXPONENT_RANGE.0, EXPONENT_RANGE.1, 30, 1e-6);
        Self::through_edge(f0, reference_at_edge, exponent)
    }
}

/// Σ_i q_i ((F_i − F_ref,i)/F_ref,i)² with F_i = `curve[i]` the model at `rule.cosines[i]`,
/// over the nodes where F_ref is finite and not 0; ∞ when the model gives a non-finite value.
pub fn relative_cost(curve: &[f64], reference: &[f64], rule: &AngleQuadrature) -> f64 {
    let mut cost = 0.0;
    for ((&f, &q), &r) in curve.iter().zip(&rule.weights).zip(reference) {
        if r != 0.0 && r.is_finite() {
            let e = (f - r) / r;
            cost += q * e * e;
        }
    }
    if cost.is_finite() {
        cost
    } else {
        f64::INFINITY
    }
}

/// The x in [lo, hi] that minimises `cost`: the best of `grid` + 1 equally spaced points,
/// then Brent's method (parabolic interpolation with golden-section fallback; Brent 1973,
/// "Algorithms for Minimization without Derivatives", ch. 5) in the interval of its
/// neighbours until x is known to `tolerance`. Deterministic; a cost that is not unimodal
/// within one grid step can only mislead it inside that step.
pub fn minimise_1d(mut cost: impl FnMut(f64) -> f64, lo: f64, hi: f64, grid: usize, tolerance: f64) -> f64 {
    let step = (hi - lo) / grid as f64;
    let at = |i: usize| if i == grid { hi } else { lo + step * i as f64 };
    let (best, best_cost) = (0..=grid).map(|i| (i, cost(at(i)))).fold((0, f64::INFINITY), |b, (i, v)| if v < b.1 { (i, v) } else { b });
    let bracket = (at(best.saturating_sub(1)), at((best + 1).min(grid)));
    nklut_optics::minimise::brent(cost, bracket, (at(best), best_cost), |_| 0.5 * tolerance, 200).0
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::color::angle_quadrature;

    fn exact_curve(index: Index, rule: &AngleQuadrature) -> Vec<f64> {
        rule.cosines.iter().map(|&c| fresnel::exact(index.n, index.k, c)).collect()
    }

    #[test]
    fn f82_tint_reproduces_f0_and_the_edge_value() {
        // Gold-like channel: F0 = 0.9, reference 0.8 at μ̄.
        let model = F82Tint::new(0.9, 0.8);
        assert_eq!(model.reflectance(1.0), 0.9);
        assert!((model.reflectance(EDGE_COS) - 0.8).abs() < 1e-15);
        assert!((model.reflectance(0.0) - 1.0).abs() < 1e-15);
        // By hand: F_S(1/7) = 0.9 + 0.1 (6/7)^5 = 0.946 355 468 2…, tint = 0.8 / that.
        let schlick = 0.9 + 0.1 * (6.0f64 / 7.0).powi(5);
        assert!((model.tint - 0.8 / schlick).abs() < 1e-15 && model.tint < 1.0);
        // A reference on Schlick's curve needs no tint.
        let plain = F82Tint::new(0.5, fresnel::schlick(0.5, EDGE_COS));
        assert!((plain.tint - 1.0).abs() < 1e-15 && plain.b.abs() < 1e-14);
    }

    #[test]
    fn gulbrandsen_maps_the_ends_of_the_edge_tint_by_hand() {
        // r = 0.25: √r = 0.5, n_max = 1.5/0.5 = 3 (k = 0), n_min = 0.75/1.25 = 0.6.
        let dielectric = Gulbrandsen { r: 0.25, g: 0.0 }.index();
        assert!((dielectric.n - 3.0).abs() < 1e-15 && dielectric.k.abs() < 1e-7, "{dielectric:?}");
        let metal = Gulbrandsen { r: 0.25, g: 1.0 }.index();
        // k² = (1.6² · 0.25 − 0.4²)/0.75 = (0.64 − 0.16)/0.75 = 0.64.
        assert!((metal.n - 0.6).abs() < 1e-15 && (metal.k - 0.8).abs() < 1e-15, "{metal:?}");
        // Both have F0 = r.
        for index in [dielectric, metal] {
            assert!((fresnel::exact(index.n, index.k, 1.0) - 0.25).abs() < 1e-14);
        }
    }

    #[test]
    fn gulbrandsen_round_trips_through_n_and_k() {
        for r in [0.0001, 0.04, 0.3, 0.6, 0.9, 0.99] {
            for g in [0.0, 0.1, 0.5, 0.77, 1.0] {
                let there = Gulbrandsen { r, g };
                let back = Gulbrandsen::from_index(there.index());
                assert!((back.r - r).abs() < 1e-12, "{there:?} → {back:?}");
                assert!((back.g - g).abs() < 1e-9, "{there:?} → {back:?}");
            }
        }
    }

    #[test]
    fn gulbrandsen_fit_recovers_an_exact_curve() {
        let rule = angle_quadrature();
        for truth in [Index::new(0.27, 2.9), Index::new(1.5, 0.0), Index::new(1.1, 6.5)] {
            let f0 = fresnel::exact(truth.n, truth.k, 1.0);
            let fit = Gulbrandsen::fit(f0, &exact_curve(truth, rule), rule);
            let index = fit.index();
            assert!((index.n / truth.n - 1.0).abs() < 1e-5 && (index.k - truth.k).abs() < 1e-5 * truth.k.max(1.0), "{truth:?} → {index:?}");
        }
    }

    #[test]
    fn generalized_schlick_with_exponent_five_is_the_f82_tint_model() {
        let (f0, edge) = ([0.95, 0.6, 0.3], [0.9, 0.62, 0.5]);
        let model = GeneralizedSchlick::through_edge(f0, edge, 5.0);
        for c in 0..3 {
            let f82 = F82Tint::new(f0[c], edge[c]);
            assert!((model.color82[c] - f82.tint).abs() < 1e-15);
            for mu in [0.0, 0.05, EDGE_COS, 0.4, 0.9, 1.0] {
                assert!((model.reflectance(c, mu) - f82.reflectance(mu)).abs() < 1e-14, "{c} {mu}");
            }
        }
    }

    #[test]
    fn generalized_schlick_fit_recovers_its_own_exponent() {
        let rule = angle_quadrature();
        let truth = GeneralizedSchlick::through_edge([0.9, 0.5, 0.04], [0.85, 0.55, 0.2], 3.7);
        let reference: [Vec<f64>; 3] = std::array::from_fn(|c| rule.cosines.iter().map(|&mu| truth.reflectance(c, mu)).collect());
        let edge = [0, 1, 2].map(|c| truth.reflectance(c, EDGE_COS));
        let fit = GeneralizedSchlick::fit(truth.color0, edge, &reference, rule);
        assert!((fit.exponent - 3.7).abs() < 1e-5, "{fit:?}");
        for (c, edge) in edge.iter().enumerate() {
            assert_eq!(fit.reflectance(c, 1.0), truth.color0[c]);
            assert!((fit.reflectance(c, EDGE_COS) - edge).abs() < 1e-15);
        }
    }

    #[test]
    fn minimiser_finds_a_parabola_vertex_and_the_better_of_two_wells() {
        let x = minimise_1d(|x| (x - 0.3141).powi(2), 0.0, 1.0, 8, 1e-9);
        assert!((x - 0.3141).abs() < 1e-8, "{x}");
        // Two wells, the deeper at 0.8; a pure golden search from [0, 1] could end at 0.2.
        let x = minimise_1d(|x| ((x - 0.2).powi(2) + 0.01).min((x - 0.8).powi(2)), 0.0, 1.0, 10, 1e-9);
        assert!((x - 0.8).abs() < 1e-8, "{x}");
        // The minimum at an end of the range.
        assert_eq!(minimise_1d(|x| x, 2.0, 3.0, 4, 1e-9), 2.0);
    }
}

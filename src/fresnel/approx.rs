//! The Schlick family (SPEC §5.2–5.5): closed forms in f64 and their f32 shader twins,
//! and the per-channel parameters (F0, compensated λ, Lazányi a).
//!
//! Shader conventions mirrored by the `*_f32` functions: integer powers are products
//! (m² = m·m, m⁵ = m²·m²·m, m⁶ = m⁵·m), a real power `pow(m, p)` is `exp2(p·log2(m))`
//! (how WGSL defines and GPUs implement it), no fma.

use super::{unit_cos, unit_cos_f32, ExactTerms};
use crate::spectrum::Index;

/// cosθ at which `schlick_compensated` is exact: θ = acos(0.1) = 84.26° (SPEC §5.4).
pub const COMPENSATION_COS: f64 = 0.1;
/// cosθ at which `lazanyi` is exact: c = 1/7 (θ ≈ 81.8°), where c(1 − c)⁶ peaks (SPEC §5.5).
pub const LAZANYI_COS: f64 = 1.0 / 7.0;

#[inline]
fn fifth(m: f64) -> f64 {
    let m2 = m * m;
    m2 * m2 * m
}

#[inline]
fn fifth_f32(m: f32) -> f32 {
    let m2 = m * m;
    m2 * m2 * m
}

/// `pow(m, p)` as a GPU evaluates it: exp2(p·log2 m); 0 for m = 0 and p > 0.
#[inline]
pub fn shader_pow(m: f32, p: f32) -> f32 {
    (p * m.log2()).exp2()
}

/// Normal-incidence reflectance F0 = ((n − 1)² + k²)/((n + 1)² + k²) (SPEC §5.2).
pub fn schlick_f0(n: f64, k: f64) -> f64 {
    let f0 = ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k);
    if f0.is_nan() {
        1.0
    } else {
        f0
    }
}

/// `schlick` (SPEC §5.2; Schlick 1994, "An Inexpensive BRDF Model for Physically-based
/// Rendering", eq. 24): F = F0 + (1 − F0)(1 − c)⁵.
#[inline]
pub fn schlick(f0: f64, cos_theta: f64) -> f64 {
    let m5 = fifth(1.0 - unit_cos(cos_theta));
    f0 + (1.0 - f0) * m5
}

/// f32 shader twin of [`schlick`].
#[inline]
pub fn schlick_f32(f0: f32, cos_theta: f32) -> f32 {
    let m5 = fifth_f32(1.0 - unit_cos_f32(cos_theta));
    f0 + (1.0 - f0) * m5
}

/// `schlick_nk` (SPEC §5.3; Lazányi & Szirmay-Kalos 2005, "Fresnel Term Approximations
/// for Metals", eq. 3): F = ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²), from n and k at
/// the point of use. Algebraically equal to `schlick` (1 − F0 = 4n/((n + 1)² + k²)).
#[inline]
pub fn schlick_nk(n: f64, k: f64, cos_theta: f64) -> f64 {
    let m5 = fifth(1.0 - unit_cos(cos_theta));
    ((n - 1.0) * (n - 1.0) + 4.0 * n * m5 + k * k) / ((n + 1.0) * (n + 1.0) + k * k)
}

/// f32 shader twin of [`schlick_nk`].
#[inline]
pub fn schlick_nk_f32(n: f32, k: f32, cos_theta: f32) -> f32 {
    let m5 = fifth_f32(1.0 - unit_cos_f32(cos_theta));
    ((n - 1.0) * (n - 1.0) + 4.0 * n * m5 + k * k) / ((n + 1.0) * (n + 1.0) + k * k)
}

/// Why `schlick_compensated` has no usable λ for a channel (SPEC §5.4). In every case
/// the method falls back to plain `schlick_nk` (correction weight 0): the limit λ → ∞
/// of the formula, i.e. no compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CompensationFallback {
    /// D = schlick_nk(c*) − exact(c*) ≤ 0: Schlick already under-estimates at 84.26°, the
    /// subtracted term 2n(1 − c)^λ can only make it worse; ln(D/2n) has no real value.
    WrongSign,
    /// D ≥ 2n: λ ≤ 0, so the term would not vanish at normal incidence (λ < 0 diverges
    /// at c = 1).
    NoDecay,
    /// D/2n underflows (n huge or D ≈ 1e-300): λ is infinite, i.e. no correction.
    Negligible,
}

impl CompensationFallback {
    pub fn name(self) -> &'static str {
        match self {
            CompensationFallback::WrongSign => "wrong-sign",
            CompensationFallback::NoDecay => "no-decay",
            CompensationFallback::Negligible => "negligible",
        }
    }
}

/// Parameters of `schlick_compensated` for one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compensation {
    /// The exponent λ (1 on fallback, unused since the weight is 0).
    pub lambda: f64,
    /// The weight of the correction term: 2n, or 0 on fallback.
    pub weight: f64,
    /// Why there is no λ, if there is none.
    pub fallback: Option<CompensationFallback>,
}

/// λ of `schlick_compensated` (SPEC §5.4) so that the formula is exact at c* = 0.1
/// (θ = 84.26°): with D = schlick_nk(c*) − exact(c*),
///   2n (1 − c*)^λ = D  ⇒  λ = ln(D / 2n) / ln(1 − c*),
/// usable when 0 < D < 2n; otherwise a [`CompensationFallback`].
pub fn compensation(index: Index, exact: &ExactTerms) -> Compensation {
    let Index { n, k } = index;
    let c = COMPENSATION_COS;
    let difference = schlick_nk(n, k, c) - exact.reflectance(c);
    let weight = 2.0 * n;
    let fallback = |reason| Compensation { lambda: 1.0, weight: 0.0, fallback: Some(reason) };
    if !(difference > 0.0) {
        return fallback(CompensationFallback::WrongSign);
    }
    if difference >= weight {
        return fallback(CompensationFallback::NoDecay);
    }
    let lambda = (difference / weight).ln() / (1.0 - c).ln();
    if !lambda.is_finite() || lambda <= 0.0 {
        return fallback(CompensationFallback::Negligible);
    }
    Compensation { lambda, weight, fallback: None }
}

/// `schlick_compensated` (SPEC §5.4): F = schlick_nk(c) − w (1 − c)^λ with w = 2n, or
/// w = 0 on fallback (see [`compensation`]). Not clamped: near grazing it can leave
/// [0, 1] (F(0) = 1 − 2n), which is part of its measured error.
#[inline]
pub fn schlick_compensated(n: f64, k: f64, weight: f64, lambda: f64, cos_theta: f64) -> f64 {
    let m = 1.0 - unit_cos(cos_theta);
    schlick_nk(n, k, cos_theta) - weight * m.powf(lambda)
}

/// f32 shader twin of [`schlick_compensated`] (`pow` as exp2(λ·log2 m)).
#[inline]
pub fn schlick_compensated_f32(n: f32, k: f32, weight: f32, lambda: f32, cos_theta: f32) -> f32 {
    let m = 1.0 - unit_cos_f32(cos_theta);
    schlick_nk_f32(n, k, cos_theta) - weight * shader_pow(m, lambda)
}

/// a of `lazanyi` (SPEC §5.5) so that it is exact at c = 1/7:
///   a = (schlick(1/7) − exact(1/7)) / ((1/7)(6/7)⁶).
/// Lazányi & Szirmay-Kalos 2005 (error compensation term a·c·(1 − c)^α, α = 6);
/// Hoffman 2019, "Fresnel Equations Considered Harmful" (the F82 tint form).
pub fn lazanyi_a(index: Index, exact: &ExactTerms) -> f64 {
    let c = LAZANYI_COS;
    let f0 = schlick_f0(index.n, index.k);
    let m = 1.0 - c;
    let a = (schlick(f0, c) - exact.reflectance(c)) / (c * fifth(m) * m);
    if a.is_finite() {
        a
    } else {
        0.0
    }
}

/// `lazanyi` (SPEC §5.5): F = F0 + (1 − F0)(1 − c)⁵ − a c (1 − c)⁶.
#[inline]
pub fn lazanyi(f0: f64, a: f64, cos_theta: f64) -> f64 {
    let c = unit_cos(cos_theta);
    let m = 1.0 - c;
    let m5 = fifth(m);
    f0 + (1.0 - f0) * m5 - a * c * (m5 * m)
}

/// f32 shader twin of [`lazanyi`].
#[inline]
pub fn lazanyi_f32(f0: f32, a: f32, cos_theta: f32) -> f32 {
    let c = unit_cos_f32(cos_theta);
    let m = 1.0 - c;
    let m5 = fifth_f32(m);
    f0 + (1.0 - f0) * m5 - a * c * (m5 * m)
}

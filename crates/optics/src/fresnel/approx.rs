//! The Schlick family (SPEC §5.2–5.5): closed forms, each written once over [`Real`] —
//! f64 for the CPU, f32 as the shader twin — and the per-channel parameters (F0,
//! compensated λ, Lazányi a).
//!
//! Shader conventions every body follows: integer powers are products (m² = m·m,
//! m⁵ = m²·m²·m, m⁶ = m⁵·m), a real power is [`Real::power`] (`exp2(p·log2(m))` in f32,
//! how WGSL defines and GPUs implement it), no fma.

use super::real::Real;
use super::{unit_cos, ExactTerms};
use crate::spectrum::Index;

/// cosθ at which `schlick_compensated` is exact: θ = acos(0.1) = 84.26° (SPEC §5.4).
pub const COMPENSATION_COS: f64 = 0.1;
/// cosθ at which `lazanyi` is exact: c = 1/7 (θ ≈ 81.8°), where c(1 − c)⁶ peaks (SPEC §5.5).
pub const LAZANYI_COS: f64 = 1.0 / 7.0;

/// m⁵ as m²·m²·m.
#[inline]
fn fifth<T: Real>(m: T) -> T {
    let m2 = m * m;
    m2 * m2 * m
}

/// Normal-incidence reflectance F0 = ((n − 1)² + k²)/((n + 1)² + k²) (SPEC §5.2).
///
/// ```
/// use nklut_optics::fresnel::{exact, schlick_f0};
/// // Gold at 535 nm: F0 is exact F at normal incidence.
/// let (n, k) = (0.52, 2.17);
/// assert!((schlick_f0(n, k) - exact(n, k, 1.0)).abs() < 1e-12);
/// ```
pub fn schlick_f0(n: f64, k: f64) -> f64 {
    let f0 = ((n - 1.0) * (n - 1.0) + k * k) / ((n + 1.0) * (n + 1.0) + k * k);
    if f0.is_nan() {
        1.0
    } else {
        f0
    }
}

/// `schlick` (SPEC §5.2; Schlick 1994, "An Inexpensive BRDF Model for Physically-based
/// Rendering", eq. 24): F = F0 + (1 − F0)(1 − c)⁵. One body for f64 and f32.
///
/// ```
/// use nklut_optics::fresnel::schlick;
/// assert_eq!(schlick(0.04_f64, 1.0), 0.04);
/// assert_eq!(schlick(0.04_f32, 0.0), 1.0);
/// assert!((schlick(0.04_f64, 0.5) - (0.04 + 0.96 / 32.0)).abs() < 1e-15);
/// ```
#[inline]
pub fn schlick<T: Real>(f0: T, cos_theta: T) -> T {
    let m5 = fifth(T::ONE - unit_cos(cos_theta));
    f0 + (T::ONE - f0) * m5
}

/// `schlick_nk` (SPEC §5.3; Lazányi & Szirmay-Kalos 2005, "Fresnel Term Approximations
/// for Metals", eq. 3): F = ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²), from n and k at
/// the point of use. Algebraically equal to `schlick` (1 − F0 = 4n/((n + 1)² + k²)).
#[inline]
pub fn schlick_nk<T: Real>(n: T, k: T, cos_theta: T) -> T {
    let m5 = fifth(T::ONE - unit_cos(cos_theta));
    ((n - T::ONE) * (n - T::ONE) + T::of(4.0) * n * m5 + k * k) / ((n + T::ONE) * (n + T::ONE) + k * k)
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
    /// The name in tables.
    pub fn name(self) -> &'static str {
        match self {
            CompensationFallback::WrongSign => "wrong-sign",
            CompensationFallback::NoDecay => "no-decay",
            CompensationFallback::Negligible => "negligible",
        }
    }
}

/// Parameters of `schlick_compensated` for one channel (f64; f32 as a shader has them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compensation<T = f64> {
    /// The exponent λ (1 on fallback, unused since the weight is 0).
    pub lambda: T,
    /// The weight of the correction term: 2n, or 0 on fallback.
    pub weight: T,
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
pub fn schlick_compensated<T: Real>(n: T, k: T, weight: T, lambda: T, cos_theta: T) -> T {
    let m = T::ONE - unit_cos(cos_theta);
    schlick_nk(n, k, cos_theta) - weight * m.power(lambda)
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
pub fn lazanyi<T: Real>(f0: T, a: T, cos_theta: T) -> T {
    let c = unit_cos(cos_theta);
    let m = T::ONE - c;
    let m5 = fifth(m);
    f0 + (T::ONE - f0) * m5 - a * c * (m5 * m)
}

/// The colours an engine's F82-tint material receives for one channel (SPEC §5.8): F0
/// and the tint F(μ̄)/F_S(μ̄) at μ̄ = 1/7, each clamped to [0, 1] — a colour input holds
/// no more — and authored as 8-bit sRGB (a colour picker's value; Adobe publishes its
/// materials' F0 and tint so), read back as the linear values a shader sees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct F82Colours<T = f64> {
    /// F0, linear, in [0, 1].
    pub f0: T,
    /// The tint F(μ̄)/F_S(μ̄), linear, in [0, 1].
    pub tint: T,
}

/// [`F82Colours`] of an index: F0 and the tint computed from exact F, then authored.
pub fn f82_colours(index: Index, exact: &ExactTerms) -> F82Colours {
    let f0 = schlick_f0(index.n, index.k);
    let tint = exact.reflectance(LAZANYI_COS) / schlick(f0, LAZANYI_COS);
    let authored = |value: f64| crate::encoding::Encoding::Unorm8Srgb.quantise(if value.is_finite() { value } else { 1.0 });
    F82Colours { f0: authored(f0), tint: authored(tint) }
}

/// `f82_tint` (SPEC §5.8; the F82-tint model of OpenPBR 1.1's metal, the Adobe Standard
/// Material and Blender 4's Principled BSDF, after Hoffman 2023): from the colours F0 and
/// tint an engine is given, F = F_S(c) − b c(1 − c)⁶ with F_S(c) = F0 + (1 − F0)(1 − c)⁵ and
/// b = F_S(μ̄)(1 − tint)/(μ̄(1 − μ̄)⁶), μ̄ = 1/7: b is formed from the colours per evaluation,
/// as a shader does. With unclamped, unquantised colours it is `lazanyi`; its error beyond
/// `lazanyi`'s is what authoring F0 and the tint as colours costs.
#[inline]
pub fn f82_tint<T: Real>(f0: T, tint: T, cos_theta: T) -> T {
    let c = unit_cos(cos_theta);
    let m = T::ONE - c;
    let m5 = fifth(m);
    let mu = T::of(LAZANYI_COS);
    let mu_m = T::ONE - mu;
    let mu_m5 = fifth(mu_m);
    let at_mu = f0 + (T::ONE - f0) * mu_m5;
    let b = at_mu * (T::ONE - tint) / (mu * (mu_m5 * mu_m));
    f0 + (T::ONE - f0) * m5 - b * c * (m5 * m)
}

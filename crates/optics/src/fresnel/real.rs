//! The arithmetic the Fresnel methods are written in once, for two targets: f64 on the
//! CPU (the reference) and f32 with a shader's operation order (the twin of the WGSL in
//! `shaders/`). A body generic over [`Real`] performs the same operations in the same
//! order in both precisions, so the two cannot drift; only what a target does
//! differently is a method here: a real power (`powf` on the CPU; WGSL defines `pow` as
//! exp2(p·log2 m), which is what GPUs evaluate) and the truncation a texture unit uses.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// f64 or f32, as the methods use them.
pub trait Real:
    Copy
    + std::fmt::Debug
    + Send
    + Sync
    + 'static
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// A constant of the formulas (exact in both precisions where the formulas use it).
    fn of(value: f64) -> Self;
    /// A texel count.
    fn count(count: usize) -> Self;
    /// The smaller of the two.
    fn min(self, other: Self) -> Self;
    /// The larger of the two.
    fn max(self, other: Self) -> Self;
    /// `self` within [lo, hi].
    fn clamp(self, lo: Self, hi: Self) -> Self;
    /// √x.
    fn sqrt(self) -> Self;
    /// |x|.
    fn abs(self) -> Self;
    /// √(x² + y²) without overflow.
    fn hypot(self, other: Self) -> Self;
    /// `pow(m, p)` as the target evaluates it.
    fn power(self, p: Self) -> Self;
    /// ⌊x⌋ for x ≥ 0 by truncation through an unsigned integer (no libm rounding call).
    fn truncate(self) -> Self;
    /// A texel index from a value already clamped to [0, N − 1].
    fn index(self) -> usize;
    /// The trigonometry of the horizon-based AO integral (`acos` of a value in [−1, 1]).
    fn acos(self) -> Self;
    /// cos x.
    fn cos(self) -> Self;
    /// sin x.
    fn sin(self) -> Self;
    /// ⌊x⌋ for any sign (a pixel coordinate).
    fn floor(self) -> Self;
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;

    #[inline]
    fn of(value: f64) -> Self {
        value
    }

    #[inline]
    fn count(count: usize) -> Self {
        count as f64
    }

    #[inline]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }

    #[inline]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }

    #[inline]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        f64::clamp(self, lo, hi)
    }

    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }

    #[inline]
    fn abs(self) -> Self {
        f64::abs(self)
    }

    #[inline]
    fn hypot(self, other: Self) -> Self {
        f64::hypot(self, other)
    }

    /// `powf`: the CPU reference.
    #[inline]
    fn power(self, p: Self) -> Self {
        self.powf(p)
    }

    #[inline]
    fn truncate(self) -> Self {
        (self as u64) as f64
    }

    #[inline]
    fn index(self) -> usize {
        self as usize
    }

    #[inline]
    fn acos(self) -> Self {
        f64::acos(self)
    }

    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }

    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }

    #[inline]
    fn floor(self) -> Self {
        f64::floor(self)
    }
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;

    #[inline]
    fn of(value: f64) -> Self {
        value as f32
    }

    #[inline]
    fn count(count: usize) -> Self {
        count as f32
    }

    #[inline]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }

    #[inline]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }

    #[inline]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        f32::clamp(self, lo, hi)
    }

    #[inline]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }

    #[inline]
    fn abs(self) -> Self {
        f32::abs(self)
    }

    #[inline]
    fn hypot(self, other: Self) -> Self {
        f32::hypot(self, other)
    }

    /// WGSL's `pow`: exp2(p·log2 m); 0 for m = 0 and p > 0.
    #[inline]
    fn power(self, p: Self) -> Self {
        (p * self.log2()).exp2()
    }

    #[inline]
    fn truncate(self) -> Self {
        (self as u32) as f32
    }

    #[inline]
    fn index(self) -> usize {
        self as usize
    }

    #[inline]
    fn acos(self) -> Self {
        f32::acos(self)
    }

    #[inline]
    fn cos(self) -> Self {
        f32::cos(self)
    }

    #[inline]
    fn sin(self) -> Self {
        f32::sin(self)
    }

    #[inline]
    fn floor(self) -> Self {
        f32::floor(self)
    }
}

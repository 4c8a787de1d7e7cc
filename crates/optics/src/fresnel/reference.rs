//! An independent `exact` in complex arithmetic, the oracle the tests compare the real
//! a/b formulation of [`super::exact`] against. Not used on any hot path.
//!
//! pbrt-v4's `FrComplex` (Pharr, Jakob, Humphreys, PBR 4th ed. §9.3.6), written with
//! w = √(η² − s²) = η cosθ_t:
//!   r⊥ = (c − w)/(c + w),   r∥ = (η²c − w)/(η²c + w),   F = (|r⊥|² + |r∥|²)/2.
//! [`exact_complex`] rationalises the numerators so that it stays accurate as η → 1:
//!   c − w = (1 − η²)/(c + w),   η²c − w = (η² − 1)(η²c² − s²)/(η²c + w),
//! with η² − 1 = (n − 1)(n + 1) − k² + 2ink, and Re(η² − s²) summed in twice the working
//! precision. [`exact_complex_textbook`] is the plain form.

#[derive(Clone, Copy, Debug, PartialEq)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }

    fn real(re: f64) -> Self {
        Self::new(re, 0.0)
    }

    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }

    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }

    fn mul(self, o: Self) -> Self {
        Self::new(self.re * o.re - self.im * o.im, self.re * o.im + self.im * o.re)
    }

    fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }

    /// |self / o|².
    fn ratio_norm_squared(self, o: Self) -> f64 {
        let (a, b) = (self.abs(), o.abs());
        if b == 0.0 {
            return if a == 0.0 { f64::NAN } else { f64::INFINITY };
        }
        (a / b) * (a / b)
    }

    /// Principal square root (Im ≥ 0 for Im(self) ≥ 0), without cancellation.
    fn sqrt(self) -> Self {
        let (x, y) = (self.re, self.im);
        if x == 0.0 && y == 0.0 {
            return Self::real(0.0);
        }
        let t = ((self.abs() + x.abs()) / 2.0).sqrt();
        if x >= 0.0 {
            Self::new(t, y / (2.0 * t))
        } else {
            Self::new(y.abs() / (2.0 * t), t.copysign(y))
        }
    }
}

/// x² as an unevaluated sum hi + lo (exact: fma error-free transformation).
fn square(x: f64) -> (f64, f64) {
    let hi = x * x;
    (hi, x.mul_add(x, -hi))
}

trait Negate {
    fn neg(self) -> Self;
}

impl Negate for (f64, f64) {
    fn neg(self) -> Self {
        (-self.0, -self.1)
    }
}

/// Σ of (hi, lo) pairs as if in twice the working precision, then rounded (Ogita, Rump &
/// Oishi 2005, "Accurate sum and dot product", Algorithm 4.4 `Sum2`).
fn accurate_sum(terms: &[(f64, f64)]) -> f64 {
    let (mut sum, mut error) = (0.0f64, 0.0f64);
    for &x in terms.iter().flat_map(|(hi, lo)| [hi, lo]) {
        let t = sum + x;
        let z = t - sum;
        error += (sum - (t - z)) + (x - z);
        sum = t;
    }
    sum + error
}

/// Unpolarised reflectance of η = n + ik at cosθ in complex arithmetic, rationalised
/// (see the module doc). n = 1, k = 0 gives 0; a vanishing denominator (grazing onto a
/// totally reflecting or η = 0 surface) gives 1.
pub fn exact_complex(n: f64, k: f64, cos_theta: f64) -> f64 {
    let c = cos_theta.clamp(0.0, 1.0);
    if n == 1.0 && k == 0.0 {
        return 0.0;
    }
    let eta = Complex::new(n, k);
    let eta2 = eta.mul(eta);
    let eta2_minus_1 = Complex::new((n - 1.0) * (n + 1.0) - k * k, 2.0 * n * k);
    let sin2 = (1.0 - c) * (1.0 + c);
    // Re(η² − s²) = n² − k² − 1 + c² in twice the working precision: accurate both for
    // gases at grazing (n² ≈ s²) and for tiny n at normal incidence (n² ≈ 1 − 1 + n²).
    let w = Complex::new(accurate_sum(&[square(n), square(k).neg(), (-1.0, 0.0), square(c)]), 2.0 * n * k).sqrt();
    let c_plus_w = Complex::real(c).add(w);
    let perp = Complex::new(-eta2_minus_1.re, -eta2_minus_1.im).ratio_norm_squared(c_plus_w.mul(c_plus_w));
    let eta2c_plus_w = eta2.mul(Complex::real(c)).add(w);
    // (η² + 1)c² − 1 = η²c² − s², without the cancellation of (η² + 1)c² against 1.
    let factor = eta2.mul(Complex::real(c * c)).sub(Complex::real(sin2));
    let parl = eta2_minus_1.mul(factor).ratio_norm_squared(eta2c_plus_w.mul(eta2c_plus_w));
    let f = 0.5 * (perp + parl);
    if f.is_finite() {
        f
    } else {
        1.0
    }
}

/// The plain pbrt-v4 form (no rationalisation): accurate except where n ≈ 1 and k ≈ 0.
pub fn exact_complex_textbook(n: f64, k: f64, cos_theta: f64) -> f64 {
    let c = cos_theta.clamp(0.0, 1.0);
    let eta = Complex::new(n, k);
    let eta2 = eta.mul(eta);
    let w = eta2.sub(Complex::real(1.0 - c * c)).sqrt();
    let cc = Complex::real(c);
    let perp = cc.sub(w).ratio_norm_squared(cc.add(w));
    let eta2c = eta2.mul(cc);
    let parl = eta2c.sub(w).ratio_norm_squared(eta2c.add(w));
    let f = 0.5 * (perp + parl);
    if f.is_finite() {
        f
    } else {
        1.0
    }
}

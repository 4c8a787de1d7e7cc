//! `exact` (SPEC §5.1): unpolarised reflectance (Rs + Rp)/2 of η = n + ik, written once
//! over [`Real`]: in f64 for the CPU and in f32 with the operation order of the WGSL
//! shader.

use super::real::Real;
use super::{sanitise, unit_cos};
use crate::spectrum::Index;

/// Largest |n|, k the fast square root `√(A² + 4n²k²)` handles without overflow; inputs
/// beyond it take `hypot`.
const SQUARE_SAFE: f64 = 1e100;

/// Per-channel terms of `exact` that do not depend on the angle.
///
/// With s² = 1 − c², A = n² − k² − s² and a + ib = √(η² − s²) (a, b ≥ 0):
///   A = a₀ + c² with a₀ = (n − 1)(n + 1) − k²,
///   r = √(A² + 4n²k²), a² = (r + A)/2, b² = (r − A)/2, a²b² = n²k²,
///   a² − c² = a₀ + b².
/// Born & Wolf §14.2; the printed form of SPEC §5.1 rearranged without tanθ:
///   Rs = ((a − c)² + b²) / ((a + c)² + b²)
///   Rp = Rs · ((ac − s²)² + b²c²) / ((ac + s²)² + b²c²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExactTerms<T = f64> {
    /// a₀ = (n − 1)(n + 1) − k²: A at grazing incidence, exact in n − 1 for gases.
    a0: T,
    /// n² − k²: A at normal incidence, exact for small n.
    n2_minus_k2: T,
    /// (nk)².
    nk_squared: T,
    /// 4(nk)², as the shader forms it: 4·(nk·nk).
    four_nk_squared: T,
    /// n = 1, k = 0: no interface, F = 0 at every angle.
    vacuum: bool,
    /// |n| or k so large that A² could overflow (never in f32, whose range ends first:
    /// the shader has no such guard).
    huge: bool,
}

impl ExactTerms {
    /// Terms for a sanitised index (see [`sanitise`]).
    pub fn new(index: Index) -> Self {
        Self::of(index.n, index.k)
    }
}

impl<T: Real> ExactTerms<T> {
    /// Terms of η = n + ik as given (sanitise first for the f64 path).
    pub fn of(n: T, k: T) -> Self {
        let nk = n * k;
        Self {
            a0: (n - T::ONE) * (n + T::ONE) - k * k,
            n2_minus_k2: n * n - k * k,
            nk_squared: nk * nk,
            four_nk_squared: T::of(4.0) * (nk * nk),
            vacuum: n == T::ONE && k == T::ZERO,
            huge: n > T::of(SQUARE_SAFE) || k > T::of(SQUARE_SAFE),
        }
    }

    /// F(cosθ) for this channel. Stable over the whole domain:
    /// - A is (n² − k²) − s² for c² > ½ (exact for small n near normal incidence) and
    ///   a₀ + c² otherwise (exact in n − 1 for gases near grazing);
    /// - the larger of a², b² is (r + |A|)/2 and the other n²k²/that (no r + A cancellation
    ///   when A ≪ 0);
    /// - a − c is (a₀ + b²)/(a + c) when A ≥ 0, exact in n − 1 as n → 1 (gases);
    /// - (Rs + Rp)/2 is formed with a single division.
    #[inline]
    pub fn reflectance(&self, cos_theta: T) -> T {
        let c = unit_cos(cos_theta);
        if self.vacuum {
            return T::ZERO;
        }
        let sin2 = (T::ONE - c) * (T::ONE + c);
        let c2 = c * c;
        let big_a = if c2 > T::of(0.5) { self.n2_minus_k2 - sin2 } else { self.a0 + c2 };
        let r = if self.huge { big_a.hypot(self.four_nk_squared.sqrt()) } else { (big_a * big_a + self.four_nk_squared).sqrt() };
        let larger = T::of(0.5) * (r + big_a.abs());
        let smaller = if larger > T::ZERO { self.nk_squared / larger } else { T::ZERO };
        let (a2, b2) = if big_a >= T::ZERO { (larger, smaller) } else { (smaller, larger) };
        let a = a2.sqrt();
        let a_plus_c = a + c;
        let a_minus_c = if big_a >= T::ZERO && a_plus_c > T::ZERO { (self.a0 + b2) / a_plus_c } else { a - c };
        let s_num = a_minus_c * a_minus_c + b2;
        let s_den = a_plus_c * a_plus_c + b2;
        let ac = a * c;
        let b2c2 = b2 * c2;
        let p_num = (ac - sin2) * (ac - sin2) + b2c2;
        let p_den = (ac + sin2) * (ac + sin2) + b2c2;
        let denominator = T::of(2.0) * s_den * p_den;
        if !(denominator > T::ZERO) {
            // a = b = c = 0 (grazing on η = 1 handled above) or η = 0 at normal incidence:
            // every such limit is total reflection.
            return T::ONE;
        }
        (s_num * (p_den + p_num) / denominator).max(T::ZERO).min(T::ONE)
    }
}

/// How many cosines [`ExactTerms::reflectance_lanes`] evaluates at once: one AVX-512
/// register of f64, two of AVX2.
pub const LANES: usize = 8;

impl ExactTerms {
    /// [`ExactTerms::reflectance`] at `LANES` cosines, each lane with the same operations in
    /// the same order as the scalar form (so the same bits): the branches on the angle
    /// become selects between both sides, which lets the compiler keep the lanes in vector
    /// registers. The branches on the index (vacuum, huge) are taken once for all lanes.
    #[inline(always)]
    pub fn reflectance_lanes(&self, cosines: &[f64; LANES]) -> [f64; LANES] {
        if self.vacuum {
            return [0.0; LANES];
        }
        if self.huge {
            return cosines.map(|c| self.reflectance(c));
        }
        let mut out = [0.0; LANES];
        for (f, &cos_theta) in out.iter_mut().zip(cosines) {
            let c = if cos_theta >= 0.0 { cos_theta.min(1.0) } else { 0.0 };
            let sin2 = (1.0 - c) * (1.0 + c);
            let c2 = c * c;
            let big_a = if c2 > 0.5 { self.n2_minus_k2 - sin2 } else { self.a0 + c2 };
            let r = (big_a * big_a + self.four_nk_squared).sqrt();
            let larger = 0.5 * (r + big_a.abs());
            let smaller = if larger > 0.0 { self.nk_squared / larger } else { 0.0 };
            let above = big_a >= 0.0;
            let a2 = if above { larger } else { smaller };
            let b2 = if above { smaller } else { larger };
            let a = a2.sqrt();
            let a_plus_c = a + c;
            let a_minus_c = if above && a_plus_c > 0.0 { (self.a0 + b2) / a_plus_c } else { a - c };
            let s_num = a_minus_c * a_minus_c + b2;
            let s_den = a_plus_c * a_plus_c + b2;
            let ac = a * c;
            let b2c2 = b2 * c2;
            let p_num = (ac - sin2) * (ac - sin2) + b2c2;
            let p_den = (ac + sin2) * (ac + sin2) + b2c2;
            let denominator = 2.0 * s_den * p_den;
            // max then min, not clamp: a NaN quotient (0/0) becomes 0 here, where clamp keeps it.
            #[allow(clippy::manual_clamp)]
            let value = (s_num * (p_den + p_num) / denominator).max(0.0).min(1.0);
            *f = if denominator > 0.0 { value } else { 1.0 };
        }
        out
    }

    /// [`ExactTerms::reflectance`] at each of `cosines`, written to `out` (the shorter of
    /// the two decides how many): [`LANES`] at a time, same bits. The vector width is
    /// chosen at run time (AVX-512, AVX2, or what the baseline target allows).
    pub fn reflectances(&self, cosines: &[f64], out: &mut [f64]) {
        reflectances_in_lanes(self, cosines, out)
    }
}

#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn reflectances_in_lanes(terms: &ExactTerms, cosines: &[f64], out: &mut [f64]) {
    for (chunk, out) in cosines.chunks(LANES).zip(out.chunks_mut(LANES)) {
        let mut lanes = [1.0; LANES];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let values = terms.reflectance_lanes(&lanes);
        let used = chunk.len().min(out.len());
        out[..used].copy_from_slice(&values[..used]);
    }
}

/// `exact` (SPEC §5.1) for one channel: unpolarised reflectance of η = n + ik at cosθ.
/// See [`ExactTerms`] for the formulas and the stable forms. k = 0 is the dielectric
/// case (n < 1 gives total reflection beyond the critical angle, F = 1); n = 1, k = 0
/// gives F = 0. Bad input (NaN, negative, infinite) is read as described in
/// [`sanitise`] and never yields NaN.
///
/// ```
/// use nklut_optics::fresnel::exact;
/// // Glass at normal incidence: ((n − 1)/(n + 1))² = 0.04.
/// assert!((exact(1.5, 0.0, 1.0) - 0.04).abs() < 1e-15);
/// // Grazing incidence reflects everything; from inside water past its critical angle too.
/// assert_eq!(exact(1.5, 0.0, 0.0), 1.0);
/// assert_eq!(exact(1.0 / 1.333, 0.0, 0.5), 1.0);
/// ```
pub fn exact(n: f64, k: f64, cos_theta: f64) -> f64 {
    ExactTerms::new(sanitise(Index::new(n, k))).reflectance(cos_theta)
}

/// `exact` in f32 with the operation order of the WGSL shader (no hypot, no fma):
///   a0 = (n − 1)(n + 1) − k²; A = (n² − k²) − s² if c² > ½ else a0 + c²; r = sqrt(A·A + 4·(nk)²);
///   larger = 0.5(r + |A|); smaller = (nk)²/larger; select a², b² by sign(A);
///   a − c = (a0 + b²)/(a + c) when A ≥ 0 else a − c;
///   F = ((a−c)² + b²)((ac+s²)² + b²c² + (ac−s²)² + b²c²) / (2((a+c)² + b²)((ac+s²)² + b²c²)).
///
/// Precision (see docs/precision.md): absolute error stays below ~1e-6 everywhere, but
/// relative accuracy is lost where F is tiny because n itself is rounded to f32:
/// as n → 1 (gases, n − 1 ≈ 3e-4) the relative error of F is ≈ 2·6e-8/(n − 1) ≈ 4e-4,
/// and it grows without bound as n − 1 → 0. Water at normal incidence (F ≈ 0.02) keeps
/// ~1e-6 relative accuracy.
pub fn exact_f32(n: f32, k: f32, cos_theta: f32) -> f32 {
    ExactTerms::of(n, k).reflectance(cos_theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_textbook_formula() {
        // F0 = ((n−1)² + k²)/((n+1)² + k²); glass n = 1.5 → 0.04 exactly.
        assert!((exact(1.5, 0.0, 1.0) - 0.04).abs() < 1e-15);
        let (n, k) = (0.2, 3.5);
        let f0 = ((n - 1.0f64).powi(2) + k * k) / ((n + 1.0f64).powi(2) + k * k);
        assert!((exact(n, k, 1.0) - f0).abs() < 1e-14);
    }

    #[test]
    fn grazing_is_total_and_subcritical_total_reflection() {
        assert_eq!(exact(1.5, 0.0, 0.0), 1.0);
        assert_eq!(exact(0.8, 0.0, 0.3), 1.0); // sinθ = 0.954 > n
        assert_eq!(exact(0.0, 0.0, 1.0), 1.0); // η = 0: perfect reflector
        assert_eq!(exact(1.0, 0.0, 0.0), 0.0); // no interface
    }

    #[test]
    fn glass_at_brewster_is_half_of_rs() {
        // At tanθ_B = n, Rp = 0 and Rs = ((n² − 1)/(n² + 1))²: F = Rs/2.
        let n: f64 = 1.5;
        let c = 1.0 / (1.0 + n * n).sqrt();
        let rs = ((n * n - 1.0) / (n * n + 1.0)).powi(2);
        assert!((exact(n, 0.0, c) - rs / 2.0).abs() < 1e-15);
    }

    #[test]
    fn lanes_give_the_bits_of_the_scalar_form() {
        // Every branch of the scalar form: normal/grazing halves (c² ≷ ½), A ≷ 0, total
        // reflection (n < 1, η = 0), gases (n − 1 tiny), vacuum, huge indices, bad cosines.
        let indices = [
            (1.5, 0.0),
            (0.2, 3.5),
            (0.8, 0.0),
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0003, 0.0),
            (1.0, 1e-9),
            (2.4, 0.01),
            (1e120, 2.0),
            (3.0, 1e130),
            (0.05, 0.0),
        ];
        let mut cosines: Vec<f64> = (0..=64).map(|i| i as f64 / 64.0).collect();
        // 1/√2 and the double below it: c² on either side of ½.
        let diagonal = std::f64::consts::FRAC_1_SQRT_2;
        cosines.extend([f64::NAN, -0.5, 2.0, 1e-300, diagonal, f64::from_bits(diagonal.to_bits() - 1)]);
        for (n, k) in indices {
            let terms = ExactTerms::new(sanitise(Index::new(n, k)));
            for chunk in cosines.chunks(LANES) {
                let mut lanes = [0.5; LANES];
                lanes[..chunk.len()].copy_from_slice(chunk);
                let got = terms.reflectance_lanes(&lanes);
                for (c, f) in lanes.iter().zip(got) {
                    assert_eq!(f.to_bits(), terms.reflectance(*c).to_bits(), "n = {n}, k = {k}, c = {c}");
                }
            }
            let mut all = vec![f64::NAN; cosines.len()];
            terms.reflectances(&cosines, &mut all);
            for (c, f) in cosines.iter().zip(&all) {
                assert_eq!(f.to_bits(), terms.reflectance(*c).to_bits(), "n = {n}, k = {k}, c = {c}");
            }
        }
    }

    #[test]
    fn bad_input_is_never_nan() {
        for n in [f64::NAN, -1.0, 0.0, f64::INFINITY, 1e300] {
            for k in [f64::NAN, -1.0, 0.0, f64::INFINITY, 1e300] {
                for c in [f64::NAN, -0.5, 0.0, 0.5, 1.0, 2.0] {
                    let f = exact(n, k, c);
                    assert!((0.0..=1.0).contains(&f), "exact({n}, {k}, {c}) = {f}");
                    let g = exact_f32(n as f32, k as f32, c as f32);
                    assert!((0.0..=1.0).contains(&g), "exact_f32({n}, {k}, {c}) = {g}");
                }
            }
        }
    }
}

//! Fresnel reflectance methods (SPEC §5). Every method maps (n, k, cosθ) to F for one
//! colour channel; outside medium air.

/// `exact` (SPEC §5.1): unpolarised reflectance (Rs + Rp)/2 of η = n + ik at cosθ = `cos_theta`.
///
/// With s² = 1 − c², A = n² − k² − s², r = √(A² + 4n²k²), a² = (r + A)/2, b² = (r − A)/2
/// (a + ib = √(η² − s²)), the printed forms rearrange without tanθ to
///   Rs = ((a − c)² + b²) / ((a + c)² + b²)
///   Rp = Rs · ((a c − s²)² + b² c²) / ((a c + s²)² + b² c²).
/// Stability: a² and b² are computed as the larger of (r ± A)/2 and the other as
/// (nk)²/larger (no r + A cancellation when A ≪ 0); a − c is computed as
/// (a² − c²)/(a + c) with a² − c² = (n − 1)(n + 1) − k² + 2n²k²/(r + A) when A ≥ 0, so
/// F stays relatively accurate as n → 1 (gases). Covers k = 0 (dielectric; n < 1 gives
/// total reflection beyond the critical angle). Source: SPEC §5.1, Born & Wolf §14.2.
pub fn exact(n: f64, k: f64, cos_theta: f64) -> f64 {
    let c = cos_theta.clamp(0.0, 1.0);
    if n == 1.0 && k == 0.0 {
        return 0.0; // no interface
    }
    let s2 = (1.0 - c) * (1.0 + c);
    let big_a = (n - 1.0) * (n + 1.0) - k * k + c * c; // n² − k² − s²
    let nk = n * k;
    let r = big_a.hypot(2.0 * nk);
    let (a2, b2) = if big_a >= 0.0 {
        let a2 = (r + big_a) / 2.0;
        (a2, if a2 > 0.0 { nk * nk / a2 } else { 0.0 })
    } else {
        let b2 = (r - big_a) / 2.0;
        (if b2 > 0.0 { nk * nk / b2 } else { 0.0 }, b2)
    };
    let a = a2.sqrt();
    if a + c == 0.0 {
        return 1.0; // grazing incidence on anything but vacuum
    }
    let a_minus_c = if big_a >= 0.0 {
        let a2_minus_c2 = (n - 1.0) * (n + 1.0) - k * k + if r + big_a > 0.0 { 2.0 * nk * nk / (r + big_a) } else { 0.0 };
        a2_minus_c2 / (a + c)
    } else {
        a - c
    };
    let rs = (a_minus_c * a_minus_c + b2) / ((a + c) * (a + c) + b2);
    let ac = a * c;
    let p_num = (ac - s2) * (ac - s2) + b2 * c * c;
    let p_den = (ac + s2) * (ac + s2) + b2 * c * c;
    let rp = if p_den > 0.0 { rs * p_num / p_den } else { rs };
    (0.5 * (rs + rp)).clamp(0.0, 1.0)
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
    }
}

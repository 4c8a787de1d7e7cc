//! `schlick_fitted` (SPEC §5.9): Schlick's form with its exponent fitted per channel,
//! F = F0 + (1 − F0)(1 − c)^p. F0 stays exact at normal incidence; p replaces Schlick's 5
//! (Schlick 1994, eq. 24) with the power of least squared relative error against `exact` at
//! [`FIT_SAMPLES`] θ-midpoints (uniform in θ and relative, like the error measure of SPEC
//! §6: a fit of absolute error lets dielectrics' small F near normal incidence go, and
//! made water's mean relative error 0.112 against Schlick's 0.087): the power
//! is searched on the grid 2^(i/2), 0.5 … [`MAX_POWER`], then refined by Brent's method in
//! log₂ p between the best grid point's neighbours. A shader pays one `pow` for the
//! freedom; its error against `schlick` is what one fitted number per channel buys.
//!
//! The power stops at 64: a shader's `pow(m, p)` is exp2(p·log2 m), and WGSL guarantees
//! log2 only to 2⁻²¹ absolute near m = 1, so F carries an uncertainty of up to
//! (1 − F0) m^p · p · ln 2 · 2⁻²¹, which at p = 1024 (where gases and n = 1 would go) reached
//! 1.4e-5 on lavapipe against the f32 twin. Only near-vacuum indices want more than 64.

use std::f64::consts::FRAC_PI_2;

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::unit_cos;
use crate::minimise::brent;

/// Number of θ-midpoints of the fit: θ_j = (j + ½)·90°/M.
pub const FIT_SAMPLES: usize = 256;
/// The largest power fitted (see the module doc).
pub const MAX_POWER: f64 = 64.0;
/// The power grid searched first: 2^(i/2) for i in −2..=12 (0.5 … [`MAX_POWER`]).
const POWER_GRID: std::ops::RangeInclusive<i32> = -2..=12;

/// F = F0 + (1 − F0)(1 − c)^p, one body for f64 and f32 (a real power is
/// [`Real::power`]: `powf` on the CPU, WGSL's exp2(p·log2 m) in f32).
///
/// ```
/// use nklut_optics::fresnel::methods::schlick_fitted::schlick_power;
/// use nklut_optics::fresnel::schlick;
/// // With p = 5 it is Schlick's approximation.
/// assert!((schlick_power(0.04_f64, 5.0, 0.3) - schlick(0.04, 0.3)).abs() < 1e-15);
/// assert_eq!(schlick_power(0.04_f64, 7.5, 1.0), 0.04);
/// assert_eq!(schlick_power(0.04_f64, 7.5, 0.0), 1.0);
/// ```
#[inline]
pub fn schlick_power<T: Real>(f0: T, power: T, cos_theta: T) -> T {
    let m = T::ONE - unit_cos(cos_theta);
    f0 + (T::ONE - f0) * m.power(power)
}

/// The smallest F a relative residual divides by: n = 1, k = 0 has F = 0 at every angle,
/// and its residual (1 − c)^p/F_FLOOR then still falls as p grows.
const F_FLOOR: f64 = 1e-12;

/// The sum of squared relative residuals of power 2^`log2_power` over the fit samples,
/// given ln(1 − c_j) and exact F(c_j).
fn residual(f0: f64, log2_power: f64, log_m: &[f64], exact: &[f64]) -> f64 {
    let power = log2_power.exp2();
    log_m.iter().zip(exact).map(|(l, f)| (f0 + (1.0 - f0) * (power * l).exp() - f) / f.max(F_FLOOR)).map(|r| r * r).sum()
}

/// The power of least squared relative error for `channel` (see the module doc). Deterministic and finite
/// for every index: a flat residual (F0 = 1) keeps the first best grid point.
pub fn fit_power(channel: &Channel) -> f64 {
    let cosines: Vec<f64> = (0..FIT_SAMPLES).map(|j| ((j as f64 + 0.5) * FRAC_PI_2 / FIT_SAMPLES as f64).cos()).collect();
    let log_m: Vec<f64> = cosines.iter().map(|c| (-c).ln_1p()).collect();
    let exact: Vec<f64> = cosines.iter().map(|&c| channel.exact.reflectance(c)).collect();
    let f = |log2_power: f64| residual(channel.f0, log2_power, &log_m, &exact);
    let grid: Vec<f64> = POWER_GRID.map(|i| i as f64 / 2.0).collect();
    let values: Vec<f64> = grid.iter().map(|&x| f(x)).collect();
    let best = (0..grid.len()).fold(0, |best, i| if values[i] < values[best] { i } else { best });
    let bracket = (grid[best.saturating_sub(1)], grid[(best + 1).min(grid.len() - 1)]);
    let (log2_power, value) = brent(f, bracket, (grid[best], values[best]), |_| 1e-10, 200);
    if value < values[best] { log2_power } else { grid[best] }.exp2()
}

/// The unit of `schlick_fitted`: the power per channel.
pub struct SchlickFitted;

impl FresnelMethod for SchlickFitted {
    type Params<T: Real> = T;
    const NAME: &'static str = "schlick_fitted";
    const WGSL_FUNCTION: &'static str = "fresnel_schlick_fitted";
    const WGSL: &'static str = "
// schlick_fitted (SPEC §5.9): F0 + (1 − F0)(1 − c)^p, p fitted per channel.
fn fresnel_schlick_fitted(c: f32, p: MaterialParams) -> vec3<f32> {
    let m = vec3<f32>(1.0 - clamp(c, 0.0, 1.0));
    let f0 = p.f0.rgb;
    return f0 + (vec3<f32>(1.0) - f0) * shader_pow(m, p.schlick_power.rgb);
}
";
    const UNIFORM: &'static [&'static str] = &["schlick_power"];

    fn fit(channel: &Channel) -> f64 {
        fit_power(channel)
    }

    fn members<T: Real>(power: &T, out: &mut [T]) {
        out[0] = *power;
    }

    fn from_members<T: Real>(members: &[T]) -> T {
        members[0]
    }

    #[inline]
    fn reflectance(channel: &Channel, power: &f64, cos_theta: f64) -> Option<f64> {
        Some(schlick_power(channel.f0, *power, cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, power: &f32, cos_theta: f32) -> Option<f32> {
        Some(schlick_power(channel.f0, *power, cos_theta))
    }

    /// (1 − c)^p changes on the scale c ~ 1/p.
    fn kinks(_: &Channel, power: &f64) -> Vec<f64> {
        [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0].map(|j| j / power).to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fresnel::{schlick, Prepared};
    use crate::spectrum::Index;

    fn channel(n: f64, k: f64) -> Channel {
        *Prepared::new(Index::new(n, k)).channel()
    }

    /// The fitted power against a brute-force scan of log₂ p in steps of 1e-4 over
    /// [−1, 6]: no scanned power fits better (to rounding), and the fit is within a step
    /// of the scan's best.
    #[test]
    fn the_fit_is_the_least_squares_power() {
        for (n, k) in [(0.17, 3.75), (1.5, 0.0), (0.5, 2.3), (2.4, 0.0), (1.1, 0.02), (0.05, 4.5)] {
            let channel = channel(n, k);
            let cosines: Vec<f64> = (0..FIT_SAMPLES).map(|j| ((j as f64 + 0.5) * FRAC_PI_2 / FIT_SAMPLES as f64).cos()).collect();
            let log_m: Vec<f64> = cosines.iter().map(|c| (-c).ln_1p()).collect();
            let exact: Vec<f64> = cosines.iter().map(|&c| crate::fresnel::exact(n, k, c)).collect();
            let scan = (0..=70_000).map(|i| -1.0 + i as f64 * 1e-4).map(|x| (residual(channel.f0, x, &log_m, &exact), x));
            let (best, at) = scan.fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
            let power = fit_power(&channel);
            let fitted = residual(channel.f0, power.log2(), &log_m, &exact);
            assert!(fitted <= best * (1.0 + 1e-9) + 1e-300, "({n}, {k}): fit {power} → {fitted:e}, scan 2^{at} → {best:e}");
            assert!((power.log2() - at).abs() <= 2e-4, "({n}, {k}): fit log₂ p = {}, scan {at}", power.log2());
        }
    }

    /// Gold's red channel: exact F dips below Schlick's curve near grazing, so the best
    /// power is above 5 and the fit beats Schlick's on average; water's best power is just
    /// below 5 (4.853 by a numpy scan of the same residual, step 1e-3 in log₂ p).
    #[test]
    fn a_metal_gets_a_power_other_than_five_and_a_smaller_error() {
        let gold = channel(0.17054450589301903, 3.7487680870353586);
        let power = fit_power(&gold);
        assert!(power > 5.0 && power < 20.0, "{power}");
        let error = |f: &dyn Fn(f64) -> f64| (0..90).map(|d| (d as f64 + 0.5).to_radians().cos()).map(|c| (f(c) - gold.exact.reflectance(c)).abs()).sum::<f64>();
        let fitted = error(&|c| schlick_power(gold.f0, power, c));
        let fixed = error(&|c| schlick(gold.f0, c));
        assert!(fitted < fixed, "fitted {fitted} vs schlick {fixed}");
        let water = fit_power(&channel(1.333, 0.0));
        assert!((water - 4.853).abs() < 0.005, "{water}");
    }

    /// Every index of the domain's edges gives a finite power and F in [0, 1] at both
    /// ends: no interface (F0 = 0: F → 0 wants the largest power), a perfect mirror (F0 = 1:
    /// every power fits; the first grid point is kept), a gas and a huge k.
    #[test]
    fn edges_stay_finite() {
        for (n, k) in [(1.0, 0.0), (1.000293, 0.0), (1.0, 1e150), (1e-3, 0.0), (1e3, 1e3)] {
            let channel = channel(n, k);
            let power = fit_power(&channel);
            assert!(power.is_finite() && (0.5..=MAX_POWER).contains(&power), "({n}, {k}): {power}");
            for c in [0.0, 0.5, 1.0] {
                let f = schlick_power(channel.f0, power, c);
                assert!((0.0..=1.0).contains(&f), "({n}, {k}) at {c}: {f}");
            }
        }
        assert_eq!(fit_power(&channel(1.0, 1e150)), 0.5);
        assert_eq!(fit_power(&channel(1.0, 0.0)), MAX_POWER);
    }
}

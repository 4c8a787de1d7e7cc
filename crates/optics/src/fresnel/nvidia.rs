//! `nvidia` (SPEC §5.6): the empirical Fresnel term F = max(0, min(1, bias + scale·(1 − c)^power))
//! of NVIDIA's Cg Tutorial (Fernando & Kilgard 2003, ch. 7 "Environment Mapping
//! Techniques", the "empirical approximation" of the Fresnel equation) and GPU Gems.
//! It has no index, so bias, scale and power are fitted per material and channel.

use std::f64::consts::FRAC_PI_2;

use super::real::Real;
use super::{unit_cos, ExactTerms};

/// Number of θ-midpoints the fit uses: θ_j = (j + ½)·90°/M, uniform in θ like the error
/// measure of SPEC §6.
pub const NVIDIA_FIT_SAMPLES: usize = 256;
/// The power grid searched before refinement: 2^(i/2) for i in −2..=20 (0.5 … 1024;
/// gases, whose F rises only near grazing, want powers in the hundreds).
const POWER_GRID: std::ops::RangeInclusive<i32> = -2..=20;
/// Golden-section steps: the bracket (1 in log₂ power) shrinks to 0.618³² ≈ 2e-7.
const GOLDEN_STEPS: usize = 32;

/// The fitted parameters of `nvidia` for one channel (f64; f32 as a shader has them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NvidiaFit<T = f64> {
    /// The bias of bias + scale (1 − c)^power.
    pub bias: T,
    /// The scale.
    pub scale: T,
    /// The power.
    pub power: T,
    /// RMS residual of the (unclamped) fit over the fit samples (0 in the shader's).
    pub rms_residual: T,
}

/// `nvidia` (SPEC §5.6): max(0, min(1, bias + scale·(1 − c)^power)); in f32 the shader's
/// `clamp(bias + scale * pow(1 - c, power), 0, 1)`.
#[inline]
pub fn nvidia<T: Real>(bias: T, scale: T, power: T, cos_theta: T) -> T {
    let m = T::ONE - unit_cos(cos_theta);
    (bias + scale * m.power(power)).min(T::ONE).max(T::ZERO)
}

/// The fit samples: ln(1 − c_j) and exact F(c_j).
struct Samples {
    log_m: Vec<f64>,
    reflectance: Vec<f64>,
}

/// Closed-form linear least squares of y ≈ bias + scale·x for x_j = (1 − c_j)^power:
/// returns (bias, scale, sum of squared residuals).
fn solve(samples: &Samples, power: f64) -> (f64, f64, f64) {
    let count = samples.log_m.len() as f64;
    let x: Vec<f64> = samples.log_m.iter().map(|l| (power * l).exp()).collect();
    let mean_x = x.iter().sum::<f64>() / count;
    let mean_y = samples.reflectance.iter().sum::<f64>() / count;
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for (xi, yi) in x.iter().zip(&samples.reflectance) {
        let (dx, dy) = (xi - mean_x, yi - mean_y);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    if !(sxx > 1e-300) {
        return (mean_y, 0.0, syy);
    }
    let scale = sxy / sxx;
    ((mean_y - scale * mean_x), scale, (syy - sxy * scale).max(0.0))
}

/// Least-squares fit of `nvidia` against `exact` (SPEC §5.6), deterministic: the
/// unclamped model bias + scale·(1 − c)^power is fitted to exact F at
/// [`NVIDIA_FIT_SAMPLES`] θ-midpoints. For each power the 2-parameter linear problem is
/// solved in closed form; the power is searched on the grid 2^(i/2), 0.5 … 1024, then
/// refined by golden-section search in log₂ power between the best point's neighbours.
/// (Clamping afterwards can only reduce the error, since exact F lies in [0, 1].)
pub fn fit_nvidia(exact: &ExactTerms) -> NvidiaFit {
    let samples = {
        let theta = |j: usize| (j as f64 + 0.5) * FRAC_PI_2 / NVIDIA_FIT_SAMPLES as f64;
        let cosines: Vec<f64> = (0..NVIDIA_FIT_SAMPLES).map(|j| theta(j).cos()).collect();
        Samples {
            log_m: cosines.iter().map(|c| (-c).ln_1p()).collect(),
            reflectance: cosines.iter().map(|&c| exact.reflectance(c)).collect(),
        }
    };
    let residual = |log2_power: f64| solve(&samples, log2_power.exp2()).2;
    let grid: Vec<f64> = POWER_GRID.map(|i| i as f64 / 2.0).collect();
    let best = (0..grid.len()).map(|i| (residual(grid[i]), i)).fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a }).1;
    let (mut lo, mut hi) = (grid[best.saturating_sub(1)], grid[(best + 1).min(grid.len() - 1)]);
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut f1, mut f2) = (residual(x1), residual(x2));
    for _ in 0..GOLDEN_STEPS {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - ratio * (hi - lo);
            f1 = residual(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + ratio * (hi - lo);
            f2 = residual(x2);
        }
    }
    let (log2_power, refined) = if f1 <= f2 { (x1, f1) } else { (x2, f2) };
    // Keep the grid point if refinement did not beat it (flat residuals).
    let log2_power = if residual(grid[best]) < refined { grid[best] } else { log2_power };
    let power = log2_power.exp2();
    let (bias, scale, sse) = solve(&samples, power);
    NvidiaFit { bias, scale, power, rms_residual: (sse / NVIDIA_FIT_SAMPLES as f64).sqrt() }
}

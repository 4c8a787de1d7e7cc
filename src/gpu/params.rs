//! Per-material shader parameters (SPEC §5), computed on the CPU from (n, k) per channel,
//! and f32 CPU references that mirror `shaders/fresnel.wgsl` operation by operation.
//!
//! MERGE: use fresnel::Prepared — the fresnel module owns the per-method precomputation
//! (compensated λ, lazanyi a, nvidia fit); this file computes the same closed forms so the
//! GPU runner can work before that module is merged. Dedupe by filling `MaterialUniform`
//! from `fresnel::Prepared` and deleting `prepare_channel`.

// MERGE: use fresnel::Prepared (compensated λ, lazanyi a, nvidia fit are computed here meanwhile).

use bytemuck::{Pod, Zeroable};

use crate::fresnel;
use crate::scene::Method;
use crate::spectrum::{ChannelIndex, Index};

/// cosθ at which `schlick_compensated` is exact: θ = 84.26° (SPEC §5.4).
pub fn compensated_cos() -> f64 {
    84.26f64.to_radians().cos()
}

/// cosθ at which `lazanyi` is exact: c = 1/7, θ ≈ 81.8° (SPEC §5.5).
pub const LAZANYI_COS: f64 = 1.0 / 7.0;
/// The exponent α of `lazanyi` (SPEC §5.5).
pub const LAZANYI_ALPHA: i32 = 6;

/// `schlick_compensated` for one channel: F = schlick_nk − scale (1 − c)^exponent, or plain
/// schlick_nk where `fallback`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Compensation {
    pub exponent: f64,
    pub scale: f64,
    /// No real positive λ makes the formula exact at 84.26° (schlick_nk ≤ exact there, as
    /// for gold's green): the method falls back to plain `schlick_nk` for that channel.
    pub fallback: bool,
}

/// `nvidia` for one channel: clamp(bias + scale (1 − c)^power, 0, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NvidiaFit {
    pub bias: f64,
    pub scale: f64,
    pub power: f64,
}

/// Everything the shaders need for one channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelParams {
    pub index: Index,
    pub f0: f64,
    pub compensation: Compensation,
    pub lazanyi_a: f64,
    pub nvidia: NvidiaFit,
}

/// F0 = ((n − 1)² + k²)/((n + 1)² + k²) (SPEC §5.2).
pub fn f0(index: Index) -> f64 {
    let Index { n, k } = index;
    ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k)
}

/// `schlick` in f64: F0 + (1 − F0)(1 − c)⁵ (Schlick 1994).
pub fn schlick(f0: f64, c: f64) -> f64 {
    f0 + (1.0 - f0) * (1.0 - c).powi(5)
}

/// `schlick_nk` in f64: ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²) (Lazányi &
/// Szirmay-Kalos 2005).
pub fn schlick_nk(index: Index, c: f64) -> f64 {
    let Index { n, k } = index;
    ((n - 1.0).powi(2) + 4.0 * n * (1.0 - c).powi(5) + k * k) / ((n + 1.0).powi(2) + k * k)
}

/// λ of `schlick_compensated` (SPEC §5.4): with c* = cos 84.26°, scale = 2n,
/// schlick_nk(c*) − 2n (1 − c*)^λ = exact(c*)  ⇔  λ = ln((S − E)/2n) / ln(1 − c*).
/// A real positive λ needs 0 < (S − E)/2n < 1; otherwise the channel falls back.
pub fn compensation(index: Index) -> Compensation {
    let c = compensated_cos();
    let scale = 2.0 * index.n;
    let excess = schlick_nk(index, c) - fresnel::exact(index.n, index.k, c);
    let ratio = excess / scale;
    if ratio > 0.0 && ratio < 1.0 && scale > 0.0 {
        Compensation { exponent: ratio.ln() / (1.0 - c).ln(), scale, fallback: false }
    } else {
        Compensation { exponent: 5.0, scale: 0.0, fallback: true }
    }
}

/// a of `lazanyi` (SPEC §5.5): schlick(c*) − a c* (1 − c*)⁶ = exact(c*) at c* = 1/7.
pub fn lazanyi_a(index: Index) -> f64 {
    let c = LAZANYI_COS;
    let schlick_value = schlick(f0(index), c);
    (schlick_value - fresnel::exact(index.n, index.k, c)) / (c * (1.0 - c).powi(LAZANYI_ALPHA))
}

/// Least-squares fit of `nvidia` against `exact` on 181 angles uniform in θ ∈ [0°, 90°]
/// (the measure of SPEC §6): for each power on a grid (0.25…12, step 0.05, then ±0.05 in
/// steps of 0.001) bias and scale solve the linear normal equations; the power with the
/// least clamped squared error wins.
pub fn nvidia_fit(index: Index) -> NvidiaFit {
    let samples: Vec<(f64, f64)> = (0..=180)
        .map(|i| {
            let c = (i as f64 * 0.5).to_radians().cos();
            (1.0 - c, fresnel::exact(index.n, index.k, c))
        })
        .collect();
    let fit_at = |power: f64| -> (NvidiaFit, f64) {
        let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
        for &(x, y) in &samples {
            let p = x.powf(power);
            sx += p;
            sy += y;
            sxx += p * p;
            sxy += p * y;
        }
        let m = samples.len() as f64;
        let det = m * sxx - sx * sx;
        let scale = if det.abs() > 1e-300 { (m * sxy - sx * sy) / det } else { 0.0 };
        let bias = (sy - scale * sx) / m;
        let fit = NvidiaFit { bias, scale, power };
        let error = samples.iter().map(|&(x, y)| (nvidia(fit, 1.0 - x) - y).powi(2)).sum();
        (fit, error)
    };
    let best = |powers: &mut dyn Iterator<Item = f64>| powers.map(fit_at).min_by(|a, b| a.1.total_cmp(&b.1)).expect("non-empty grid");
    let coarse = best(&mut (5..=240).map(|i| i as f64 * 0.05));
    let centre = coarse.0.power;
    best(&mut (-50..=50).map(|i| centre + i as f64 * 0.001).filter(|p| *p > 0.0)).0
}

/// `nvidia` in f64.
pub fn nvidia(fit: NvidiaFit, c: f64) -> f64 {
    (fit.bias + fit.scale * (1.0 - c).powf(fit.power)).clamp(0.0, 1.0)
}

/// All parameters of one channel.
pub fn prepare_channel(index: Index) -> ChannelParams {
    ChannelParams { index, f0: f0(index), compensation: compensation(index), lazanyi_a: lazanyi_a(index), nvidia: nvidia_fit(index) }
}

/// All parameters of a material, red, green, blue.
pub fn prepare(channels: &ChannelIndex) -> [ChannelParams; 3] {
    channels.map(prepare_channel)
}

/// The uniform block `MaterialParams` of `shaders/fresnel.wgsl`: one vec4 per field, rgb =
/// red, green, blue, w unused (0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MaterialUniform {
    pub n: [f32; 4],
    pub k: [f32; 4],
    pub f0: [f32; 4],
    pub compensated_exponent: [f32; 4],
    pub compensated_scale: [f32; 4],
    pub compensated_fallback: [f32; 4],
    pub lazanyi_a: [f32; 4],
    pub nvidia_bias: [f32; 4],
    pub nvidia_scale: [f32; 4],
    pub nvidia_power: [f32; 4],
    pub constant_colour: [f32; 4],
}

impl MaterialUniform {
    pub fn new(params: &[ChannelParams; 3]) -> Self {
        let v = |f: &dyn Fn(&ChannelParams) -> f64| [f(&params[0]) as f32, f(&params[1]) as f32, f(&params[2]) as f32, 0.0];
        MaterialUniform {
            n: v(&|p| p.index.n),
            k: v(&|p| p.index.k),
            f0: v(&|p| p.f0),
            compensated_exponent: v(&|p| p.compensation.exponent),
            compensated_scale: v(&|p| p.compensation.scale),
            compensated_fallback: v(&|p| if p.compensation.fallback { 1.0 } else { 0.0 }),
            lazanyi_a: v(&|p| p.lazanyi_a),
            nvidia_bias: v(&|p| p.nvidia.bias),
            nvidia_scale: v(&|p| p.nvidia.scale),
            nvidia_power: v(&|p| p.nvidia.power),
            constant_colour: v(&|p| p.f0),
        }
    }

    pub fn from_channels(channels: &ChannelIndex) -> Self {
        Self::new(&prepare(channels))
    }
}

/// f32 CPU references, one per WGSL method, same operations in the same order.
/// MERGE: fresnel::*_f32 — replace with the fresnel module's f32 methods once merged (they
/// must keep matching the WGSL within 1e-5, which `tests/gpu.rs` checks).
// MERGE: fresnel::*_f32 (these mirror shaders/fresnel.wgsl; tests/gpu.rs holds them to 1e-5).
pub mod reference {
    use super::MaterialUniform;
    use crate::scene::Method;

    fn pow5(x: f32) -> f32 {
        let x2 = x * x;
        x2 * x2 * x
    }

    fn pow_or_zero(x: f32, p: f32) -> f32 {
        if x <= 0.0 {
            0.0
        } else {
            x.powf(p)
        }
    }

    /// `exact_channel` of the WGSL (the stable form of `fresnel::exact`, in f32).
    pub fn exact_f32(n: f32, k: f32, c_in: f32) -> f32 {
        let c = c_in.clamp(0.0, 1.0);
        if n == 1.0 && k == 0.0 {
            return 0.0;
        }
        let s2 = (1.0 - c) * (1.0 + c);
        let big_a = (n - 1.0) * (n + 1.0) - k * k + c * c;
        let nk = n * k;
        let r = (big_a * big_a + 4.0 * nk * nk).sqrt();
        let (a2, b2) = if big_a >= 0.0 {
            let a2 = (r + big_a) * 0.5;
            (a2, if a2 > 0.0 { nk * nk / a2 } else { 0.0 })
        } else {
            let b2 = (r - big_a) * 0.5;
            (if b2 > 0.0 { nk * nk / b2 } else { 0.0 }, b2)
        };
        let a = a2.sqrt();
        if a + c == 0.0 {
            return 1.0;
        }
        let a_minus_c = if big_a >= 0.0 {
            let r_plus_a = r + big_a;
            let a2_minus_c2 = (n - 1.0) * (n + 1.0) - k * k + if r_plus_a > 0.0 { 2.0 * nk * nk / r_plus_a } else { 0.0 };
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

    pub fn schlick_f32(f0: f32, c: f32) -> f32 {
        f0 + (1.0 - f0) * pow5(1.0 - c)
    }

    pub fn schlick_nk_f32(n: f32, k: f32, c: f32) -> f32 {
        let k2 = k * k;
        let (nm1, np1) = (n - 1.0, n + 1.0);
        (nm1 * nm1 + 4.0 * n * pow5(1.0 - c) + k2) / (np1 * np1 + k2)
    }

    pub fn schlick_compensated_f32(n: f32, k: f32, exponent: f32, scale: f32, fallback: bool, c: f32) -> f32 {
        let base = schlick_nk_f32(n, k, c);
        if fallback {
            base
        } else {
            base - scale * pow_or_zero(1.0 - c, exponent)
        }
    }

    pub fn lazanyi_f32(f0: f32, a: f32, c: f32) -> f32 {
        let x = 1.0 - c;
        let x6 = x * x * x * x * x * x;
        schlick_f32(f0, c) - a * (c * x6)
    }

    pub fn nvidia_f32(bias: f32, scale: f32, power: f32, c: f32) -> f32 {
        (bias + scale * pow_or_zero(1.0 - c, power)).clamp(0.0, 1.0)
    }

    /// The method's F for `channel` (0 red, 1 green, 2 blue). `None` for the methods that
    /// read a texture (`lut`, `texture`): their reference is the CPU LUT model.
    pub fn evaluate_f32(method: Method, m: &MaterialUniform, channel: usize, c: f32) -> Option<f32> {
        let i = channel;
        Some(match method {
            Method::Exact => exact_f32(m.n[i], m.k[i], c),
            Method::Schlick => schlick_f32(m.f0[i], c),
            Method::SchlickNk => schlick_nk_f32(m.n[i], m.k[i], c),
            Method::SchlickCompensated => {
                schlick_compensated_f32(m.n[i], m.k[i], m.compensated_exponent[i], m.compensated_scale[i], m.compensated_fallback[i] > 0.5, c)
            }
            Method::Lazanyi => lazanyi_f32(m.f0[i], m.lazanyi_a[i], c),
            Method::Nvidia => nvidia_f32(m.nvidia_bias[i], m.nvidia_scale[i], m.nvidia_power[i], c),
            Method::Constant => m.constant_colour[i],
            Method::Lut | Method::Texture => return None,
        })
    }
}

/// Methods whose parameters depend on nothing but this module (all but the texture ones).
pub fn needs_texture(method: Method) -> bool {
    matches!(method, Method::Lut | Method::Texture)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOLD: [Index; 3] = [Index::new(0.16, 3.8), Index::new(0.5, 2.3), Index::new(1.2, 1.8)];
    const WATER: Index = Index::new(1.333, 0.0);

    #[test]
    fn compensated_is_exact_at_84_degrees_or_falls_back() {
        let c = compensated_cos();
        for index in GOLD.into_iter().chain([WATER, Index::new(0.2, 3.5)]) {
            let p = compensation(index);
            let exact = fresnel::exact(index.n, index.k, c);
            let value = if p.fallback { schlick_nk(index, c) } else { schlick_nk(index, c) - p.scale * (1.0 - c).powf(p.exponent) };
            assert!(value.is_finite() && p.exponent.is_finite());
            if !p.fallback {
                assert!((value - exact).abs() < 1e-12, "{index:?}");
                assert!(p.exponent > 0.0);
            }
        }
    }

    #[test]
    fn lazanyi_is_exact_at_one_seventh() {
        for index in GOLD {
            let a = lazanyi_a(index);
            let c = LAZANYI_COS;
            let value = schlick(f0(index), c) - a * c * (1.0 - c).powi(6);
            assert!((value - fresnel::exact(index.n, index.k, c)).abs() < 1e-12);
        }
    }

    #[test]
    fn nvidia_fit_tracks_exact() {
        for index in GOLD.into_iter().chain([WATER]) {
            let fit = nvidia_fit(index);
            let rms = ((0..=90).map(|d| {
                let c = (d as f64).to_radians().cos();
                (nvidia(fit, c) - fresnel::exact(index.n, index.k, c)).powi(2)
            }))
            .sum::<f64>()
                / 91.0;
            assert!(rms.sqrt() < 0.05, "{index:?} {fit:?} rms {}", rms.sqrt());
        }
    }

    #[test]
    fn schlick_nk_equals_schlick() {
        for index in GOLD.into_iter().chain([WATER]) {
            for i in 0..=10 {
                let c = i as f64 / 10.0;
                assert!((schlick_nk(index, c) - schlick(f0(index), c)).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn f32_exact_mirrors_f64() {
        for index in GOLD.into_iter().chain([WATER, Index::new(2.42, 0.0)]) {
            for i in 0..=100 {
                let c = i as f64 / 100.0;
                let f = reference::exact_f32(index.n as f32, index.k as f32, c as f32) as f64;
                assert!((f - fresnel::exact(index.n, index.k, c)).abs() < 1e-5, "{index:?} c {c}");
            }
        }
    }
}

//! Texel encodings and the LUT sampling model (SPEC §5.7), private to the bake until the
//! fresnel module's versions are merged.
//!
//! MERGE: replace with fresnel::{Encoding, sample_lut} — `Encoding`, `quantise`, `decode`
//! and `sample_lut` here have exactly the semantics the bake documents in its manifest:
//! round-to-nearest unorm quantisation after clamping to [0, 1], sRGB with the
//! IEC 61966-2-1 transfer function, IEEE half/single floats with round-to-nearest-even,
//! and linear filtering with clamp-to-edge at texel centres (i + ½)/N.

use clap::ValueEnum;
use half::f16;
use serde::Serialize;

/// How a texture stores F. MERGE: replace with fresnel::Encoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, ValueEnum, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Encoding {
    /// 8-bit PNG, code = round(255 · clamp(F, 0, 1)), linear.
    Unorm8,
    /// 8-bit PNG, code = round(255 · srgb_encode(clamp(F, 0, 1))) (IEC 61966-2-1); an
    /// sRGB texture format decodes it to linear F before filtering.
    #[value(name = "unorm8-srgb")]
    Unorm8Srgb,
    /// 16-bit PNG, code = round(65535 · clamp(F, 0, 1)), linear.
    Unorm16,
    /// OpenEXR half float (binary16, round-to-nearest-even), linear, not clamped.
    F16,
    /// OpenEXR single float (binary32, round-to-nearest-even), linear, not clamped.
    F32,
}

impl Encoding {
    /// Every encoding, in the order outputs list them.
    pub const ALL: [Encoding; 5] = [Encoding::Unorm8, Encoding::Unorm8Srgb, Encoding::Unorm16, Encoding::F16, Encoding::F32];

    /// The name used on the command line, in folder names and in the manifest.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Unorm8 => "unorm8",
            Encoding::Unorm8Srgb => "unorm8-srgb",
            Encoding::Unorm16 => "unorm16",
            Encoding::F16 => "f16",
            Encoding::F32 => "f32",
        }
    }

    pub fn extension(self) -> &'static str {
        if self.is_float() { "exr" } else { "png" }
    }

    pub fn is_float(self) -> bool {
        matches!(self, Encoding::F16 | Encoding::F32)
    }

    /// `linear` or `srgb-encoded` (the stored values, not what a sampler returns).
    pub fn color_space(self) -> &'static str {
        if self == Encoding::Unorm8Srgb { "srgb-encoded" } else { "linear" }
    }

    /// The largest stored code of an integer encoding (2^bits − 1).
    fn unorm_max(self) -> Option<f64> {
        match self {
            Encoding::Unorm8 | Encoding::Unorm8Srgb => Some(255.0),
            Encoding::Unorm16 => Some(65535.0),
            Encoding::F16 | Encoding::F32 => None,
        }
    }

    /// The quantisation step bound |decode(quantise(F)) − F| for F in range: half a code
    /// for unorm (measured in the stored space; for sRGB that is the encoded value),
    /// half an ulp for floats (relative 2⁻¹¹ for binary16, 2⁻²⁴ for binary32).
    pub fn half_step(self, value: f64) -> f64 {
        match self {
            Encoding::Unorm8 | Encoding::Unorm8Srgb => 0.5 / 255.0,
            Encoding::Unorm16 => 0.5 / 65535.0,
            // Subnormal halves have an absolute spacing of 2⁻²⁴.
            Encoding::F16 => (value.abs() * 2f64.powi(-11)).max(2f64.powi(-25)),
            Encoding::F32 => (value.abs() * 2f64.powi(-24)).max(2f64.powi(-150)),
        }
    }

    /// The GPU texture formats that sample this encoding as the LUT model assumes.
    pub fn gpu_formats(self) -> &'static str {
        match self {
            Encoding::Unorm8 => "WebGPU rgba8unorm (pad RGB to RGBA); Vulkan R8G8B8A8_UNORM; GL RGBA8",
            Encoding::Unorm8Srgb => "WebGPU rgba8unorm-srgb; Vulkan R8G8B8A8_SRGB; GL SRGB8_ALPHA8",
            Encoding::Unorm16 => "Vulkan R16G16B16A16_UNORM; GL RGBA16 (WebGPU core has no filterable 16-bit unorm: convert to rgba16float or rgba32float)",
            Encoding::F16 => "WebGPU rgba16float; Vulkan R16G16B16A16_SFLOAT; GL RGBA16F",
            Encoding::F32 => "WebGPU rgba32float (filterable only with the float32-filterable feature); Vulkan R32G32B32A32_SFLOAT; GL RGBA32F",
        }
    }

    /// How to turn a stored value into F, in words.
    pub fn decode_rule(self) -> &'static str {
        match self {
            Encoding::Unorm8 => "F = code / 255",
            Encoding::Unorm8Srgb => "V = code / 255; F = V / 12.92 if V <= 0.04045 else ((V + 0.055) / 1.055)^2.4 (IEC 61966-2-1)",
            Encoding::Unorm16 => "F = code / 65535",
            Encoding::F16 => "F = value (binary16)",
            Encoding::F32 => "F = value (binary32)",
        }
    }
}

/// sRGB encoding (IEC 61966-2-1): V = 12.92 L for L ≤ 0.0031308, else 1.055 L^(1/2.4) − 0.055.
pub fn srgb_encode(linear: f64) -> f64 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding (IEC 61966-2-1): L = V / 12.92 for V ≤ 0.04045, else ((V + 0.055)/1.055)^2.4.
pub fn srgb_decode(encoded: f64) -> f64 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Stored texel values of one image, interleaved R G B, row-major from the first row.
#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    U8(Vec<u8>),
    U16(Vec<u16>),
    F16(Vec<f16>),
    F32(Vec<f32>),
}

impl Texels {
    pub fn len(&self) -> usize {
        match self {
            Texels::U8(v) => v.len(),
            Texels::U16(v) => v.len(),
            Texels::F16(v) => v.len(),
            Texels::F32(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn empty(encoding: Encoding, capacity: usize) -> Self {
        match encoding {
            Encoding::Unorm8 | Encoding::Unorm8Srgb => Texels::U8(Vec::with_capacity(capacity)),
            Encoding::Unorm16 => Texels::U16(Vec::with_capacity(capacity)),
            Encoding::F16 => Texels::F16(Vec::with_capacity(capacity)),
            Encoding::F32 => Texels::F32(Vec::with_capacity(capacity)),
        }
    }

    /// The rows one after the other (an atlas). All rows must share one variant.
    pub fn concat<'a>(encoding: Encoding, rows: impl IntoIterator<Item = &'a Texels>) -> Texels {
        let mut out = Texels::empty(encoding, 0);
        for row in rows {
            match (&mut out, row) {
                (Texels::U8(o), Texels::U8(r)) => o.extend_from_slice(r),
                (Texels::U16(o), Texels::U16(r)) => o.extend_from_slice(r),
                (Texels::F16(o), Texels::F16(r)) => o.extend_from_slice(r),
                (Texels::F32(o), Texels::F32(r)) => o.extend_from_slice(r),
                _ => unreachable!("rows of one encoding share one texel type"),
            }
        }
        out
    }

    /// The linear F each stored value stands for (what a GPU sampler returns per texel).
    pub fn decode(&self, encoding: Encoding) -> Vec<f64> {
        match self {
            Texels::U8(v) if encoding == Encoding::Unorm8Srgb => v.iter().map(|&c| srgb_decode(c as f64 / 255.0)).collect(),
            Texels::U8(v) => v.iter().map(|&c| c as f64 / 255.0).collect(),
            Texels::U16(v) => v.iter().map(|&c| c as f64 / 65535.0).collect(),
            Texels::F16(v) => v.iter().map(|&x| x.to_f64()).collect(),
            Texels::F32(v) => v.iter().map(|&x| x as f64).collect(),
        }
    }
}

/// One channel-interleaved row quantised: the stored texels and how many texels had a
/// channel outside [0, 1] that an integer encoding clamped.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantised {
    pub texels: Texels,
    pub clamped: usize,
}

/// Round-to-nearest unorm code of `value` in [0, 1]: round(value · max).
fn unorm(value: f64, max: f64) -> f64 {
    (value.clamp(0.0, 1.0) * max).round()
}

/// Quantise a row (F per channel at the texel cosines, all channels of equal length) in
/// `encoding`, interleaving R G B. Integer encodings clamp to [0, 1] and count the texels
/// where any channel needed it; float encodings keep every value.
pub fn quantise(encoding: Encoding, curve: &[Vec<f64>; 3]) -> Quantised {
    let n = curve[0].len();
    let texel = |i: usize| [curve[0][i], curve[1][i], curve[2][i]];
    let clamped = match encoding.unorm_max() {
        Some(_) => (0..n).filter(|&i| texel(i).iter().any(|v| !(0.0..=1.0).contains(v))).count(),
        None => 0,
    };
    let values = (0..n).flat_map(texel);
    let texels = match encoding {
        Encoding::Unorm8 => Texels::U8(values.map(|v| unorm(v, 255.0) as u8).collect()),
        Encoding::Unorm8Srgb => Texels::U8(values.map(|v| unorm(srgb_encode(v.clamp(0.0, 1.0)), 255.0) as u8).collect()),
        Encoding::Unorm16 => Texels::U16(values.map(|v| unorm(v, 65535.0) as u16).collect()),
        Encoding::F16 => Texels::F16(values.map(f16::from_f64).collect()),
        Encoding::F32 => Texels::F32(values.map(|v| v as f32).collect()),
    };
    Quantised { texels, clamped }
}

/// The cosines of the texel centres of an N-texel LUT: c_i = (i + ½)/N (SPEC §5.7).
pub fn texel_cosines(size: usize) -> Vec<f64> {
    (0..size).map(|i| (i as f64 + 0.5) / size as f64).collect()
}

/// The LUT model (SPEC §5.7), MERGE: replace with fresnel::sample_lut. A GPU's linear
/// filter with clamp-to-edge at u = c over N texels t_i centred at (i + ½)/N:
/// x = c·N − ½, i = ⌊x⌋, f = x − i, F = (1 − f)·t[clamp(i)] + f·t[clamp(i + 1)] with
/// indices clamped to [0, N − 1]. (GPUs quantise f to 8 fractional bits; the model does not.)
pub fn sample_lut(texels: &[f64], cos_theta: f64) -> f64 {
    let n = texels.len();
    if n == 0 {
        return f64::NAN;
    }
    let x = cos_theta.clamp(0.0, 1.0) * n as f64 - 0.5;
    if x <= 0.0 {
        return texels[0]; // below the first centre: clamp-to-edge
    }
    // x > 0, so truncation is ⌊x⌋ (and avoids a libm floor call in the error loop).
    let i = x as usize;
    if i >= n - 1 {
        return texels[n - 1]; // beyond the last centre
    }
    let f = x - i as f64;
    (1.0 - f) * texels[i] + f * texels[i + 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_and_matches_the_standard_points() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-15);
        assert!((srgb_encode(0.18) - 0.461_356).abs() < 1e-6);
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-12);
        }
    }

    #[test]
    fn quantise_rounds_to_nearest_and_counts_clamps() {
        let curve = [vec![0.5, 1.2, -0.1], vec![1.0 / 510.0 + 1e-9, 0.0, 0.0], vec![0.0, 0.0, 0.0]];
        let q = quantise(Encoding::Unorm8, &curve);
        assert_eq!(q.texels, Texels::U8(vec![128, 1, 0, 255, 0, 0, 0, 0, 0]));
        assert_eq!(q.clamped, 2);
        let f = quantise(Encoding::F16, &curve);
        assert_eq!(f.clamped, 0);
        assert_eq!(f.texels.decode(Encoding::F16)[3], f16::from_f64(1.2).to_f64());
    }

    #[test]
    fn sampling_at_texel_centres_returns_texels_and_clamps_at_the_edges() {
        let t = [0.0, 1.0, 4.0, 9.0];
        for (i, c) in texel_cosines(4).into_iter().enumerate() {
            assert!((sample_lut(&t, c) - t[i]).abs() < 1e-15);
        }
        assert_eq!(sample_lut(&t, 0.0), 0.0);
        assert_eq!(sample_lut(&t, 1.0), 9.0);
        assert!((sample_lut(&t, 0.25) - 0.5).abs() < 1e-15); // halfway between centres 1/8 and 3/8
        // The model as printed, with ⌊x⌋ and clamped indices.
        let model = |c: f64| {
            let x = c * 4.0 - 0.5;
            let (i, f) = (x.floor(), x - x.floor());
            let at = |j: f64| t[j.clamp(0.0, 3.0) as usize];
            (1.0 - f) * at(i) + f * at(i + 1.0)
        };
        for k in 0..=1000 {
            let c = k as f64 / 1000.0;
            assert!((sample_lut(&t, c) - model(c)).abs() < 1e-12, "c = {c}");
        }
    }
}

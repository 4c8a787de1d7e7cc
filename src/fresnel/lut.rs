//! `lut` (SPEC §5.7): a 1D texture of F over c = cosθ ∈ [0, 1] read with a GPU's linear
//! filtering, and the texel encodings.
//!
//! Texel convention (OpenGL/Vulkan/D3D/WebGPU): texel i of N holds F at the texel centre
//! c_i = (i + ½)/N. Sampling at u = c: x = u·N − ½, i₀ = ⌊x⌋, i₁ = i₀ + 1, each clamped to
//! [0, N − 1] (clamp-to-edge), t = x − ⌊x⌋, F = T[i₀](1 − t) + T[i₁]t (WGSL `mix`).
//! Below the first centre and above the last, both indices clamp to the edge texel.
//! Not modelled: the reduced precision of hardware filter weights (e.g. 8 fractional
//! bits of t on current NVIDIA and AMD GPUs).

use half::f16;

use super::real::Real;
use super::unit_cos;

/// The texel counts of the "what accuracy costs" sweep.
pub const LUT_SIZES: [usize; 6] = [16, 32, 64, 128, 256, 1024];

/// How a texel is stored. Values are reflectances in [0, 1] (linear).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Encoding {
    /// 8-bit unsigned normalised, linear: code = round(255 F).
    Unorm8,
    /// 8-bit unsigned normalised, stored sRGB-encoded (IEC 61966-2-1 transfer
    /// function); the texture unit decodes to linear before filtering.
    Unorm8Srgb,
    /// 16-bit unsigned normalised: code = round(65535 F).
    Unorm16,
    /// IEEE 754 binary16, round to nearest even.
    F16,
    /// IEEE 754 binary32, round to nearest even.
    F32,
}

impl Encoding {
    pub const ALL: [Encoding; 5] = [Encoding::Unorm8, Encoding::Unorm8Srgb, Encoding::Unorm16, Encoding::F16, Encoding::F32];

    /// The name used on the command line, in tables and in the manifest.
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Unorm8 => "unorm8",
            Encoding::Unorm8Srgb => "unorm8-srgb",
            Encoding::Unorm16 => "unorm16",
            Encoding::F16 => "f16",
            Encoding::F32 => "f32",
        }
    }

    pub fn from_name(name: &str) -> Option<Encoding> {
        Encoding::ALL.into_iter().find(|e| e.name() == name)
    }

    /// Bytes one channel of one texel takes.
    pub fn bytes_per_channel(self) -> usize {
        match self {
            Encoding::Unorm8 | Encoding::Unorm8Srgb => 1,
            Encoding::Unorm16 | Encoding::F16 => 2,
            Encoding::F32 => 4,
        }
    }

    /// The stored code of a linear value: the unorm integer, or the bits of the float.
    /// Unorm encodings clamp to [0, 1] first; NaN stores as 0.
    pub fn encode(self, value: f64) -> u32 {
        let unit = if value >= 0.0 { value.min(1.0) } else { 0.0 };
        match self {
            Encoding::Unorm8 => (unit * 255.0).round() as u32,
            Encoding::Unorm8Srgb => (srgb_encode(unit) * 255.0).round() as u32,
            Encoding::Unorm16 => (unit * 65535.0).round() as u32,
            Encoding::F16 => f16::from_f64(if value.is_nan() { 0.0 } else { value }).to_bits() as u32,
            Encoding::F32 => (if value.is_nan() { 0.0 } else { value } as f32).to_bits(),
        }
    }

    /// The linear value a texture unit reads for a stored code.
    pub fn decode(self, code: u32) -> f64 {
        match self {
            Encoding::Unorm8 => code.min(255) as f64 / 255.0,
            Encoding::Unorm8Srgb => SRGB8_DECODED[code.min(255) as usize],
            Encoding::Unorm16 => code.min(65535) as f64 / 65535.0,
            Encoding::F16 => f16::from_bits(code as u16).to_f64(),
            Encoding::F32 => f32::from_bits(code) as f64,
        }
    }

    /// The value after encode + decode: what the shader sees for `value`.
    pub fn quantise(self, value: f64) -> f64 {
        self.decode(self.encode(value))
    }
}

/// The linear value of every 8-bit sRGB code: [`srgb_decode`] of code/255, once.
static SRGB8_DECODED: std::sync::LazyLock<[f64; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|code| srgb_decode(code as f64 / 255.0)));

/// The sRGB transfer function (IEC 61966-2-1), one definition for the whole crate:
/// [`crate::color::srgb::encode`] and [`crate::color::srgb::decode`]. Texels are clamped
/// to [0, 1] before they are encoded, where the colour stage's extension to negative
/// values (mirrored) plays no part.
pub use crate::color::srgb::{decode as srgb_decode, encode as srgb_encode};

/// cosθ at the centre of texel `i` of `texels`: (i + ½)/N.
pub fn lut_texel_cos(i: usize, texels: usize) -> f64 {
    (i as f64 + 0.5) / texels.max(1) as f64
}

/// Where linear filtering with clamp-to-edge reads a texture: the two texels and the
/// weight of the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter<T> {
    pub lower: usize,
    pub upper: usize,
    /// The weight t of `upper`; `lower` has 1 − t.
    pub weight: T,
}

/// Where linear filtering with clamp-to-edge reads a texture of `count` texels at u = c
/// (see the module doc). The same for every texture of that size, so several encodings
/// can share it. In f32 the shader's arithmetic.
#[inline]
pub fn filter_weights<T: Real>(count: usize, cos_theta: T) -> Filter<T> {
    let x = unit_cos(cos_theta) * T::count(count) - T::of(0.5);
    // x ∈ [−½, N − ½], so ⌊x⌋ is −1 or the truncation (no libm call: the baseline
    // x86-64 target has no rounding instruction).
    let floor = if x < T::ZERO { -T::ONE } else { x.truncate() };
    let last = T::count(count.saturating_sub(1));
    Filter { lower: floor.clamp(T::ZERO, last).index(), upper: (floor + T::ONE).clamp(T::ZERO, last).index(), weight: x - floor }
}

/// Linear filtering with clamp-to-edge, as a GPU samples a 1D texture at u = c (see the
/// module doc). Returns 0 for an empty texture.
pub fn sample_lut<T: Real>(texels: &[T], cos_theta: T) -> T {
    if texels.is_empty() {
        return T::ZERO;
    }
    filter(texels, filter_weights(texels.len(), cos_theta))
}

/// The filtered value T[i₀](1 − t) + T[i₁]t (WGSL `mix`) for weights from
/// [`filter_weights`].
#[inline]
pub fn filter<T: Real>(texels: &[T], weights: Filter<T>) -> T {
    texels[weights.lower] * (T::ONE - weights.weight) + texels[weights.upper] * weights.weight
}

/// `curve` at the texel centres c_i = (i + ½)/N of a texture of `texels` texels (at
/// least one): the values [`Lut::from_values`] quantises.
pub fn texel_values(texels: usize, curve: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..texels.max(1)).map(|i| curve(lut_texel_cos(i, texels))).collect()
}

/// Texel count and encoding of a LUT.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LutSpec {
    pub texels: usize,
    pub encoding: Encoding,
}

impl LutSpec {
    pub const fn new(texels: usize, encoding: Encoding) -> Self {
        Self { texels, encoding }
    }

    /// "N=256,unorm8".
    pub fn name(&self) -> String {
        format!("N={},{}", self.texels, self.encoding.name())
    }

    /// Bytes of an RGB texture of this spec: N × 3 channels × bytes per channel.
    pub fn texture_bytes(&self) -> usize {
        self.texels * 3 * self.encoding.bytes_per_channel()
    }

    /// Every spec of the sweep: [`LUT_SIZES`] × [`Encoding::ALL`].
    pub fn sweep() -> Vec<LutSpec> {
        LUT_SIZES.iter().flat_map(|&n| Encoding::ALL.map(|e| LutSpec::new(n, e))).collect()
    }
}

impl Default for LutSpec {
    fn default() -> Self {
        Self::new(256, Encoding::Unorm8)
    }
}

/// One channel of a LUT: texel values after encode + decode (what the shader reads).
#[derive(Clone, Debug, PartialEq)]
pub struct Lut {
    pub spec: LutSpec,
    /// Decoded linear texel values, f64.
    pub texels: Vec<f64>,
    /// The same as the texture unit hands them to the shader, f32.
    pub texels_f32: Vec<f32>,
}

impl Lut {
    /// Texel i = quantise(curve(c_i)) with c_i = (i + ½)/N.
    pub fn bake(spec: LutSpec, curve: impl Fn(f64) -> f64) -> Self {
        Self::from_values(spec, &texel_values(spec.texels, curve))
    }

    /// Texel i = quantise(values[i]): `values` are the curve at the texel centres
    /// c_i = (i + ½)/N, so that one evaluation of the curve serves every encoding.
    pub fn from_values(spec: LutSpec, values: &[f64]) -> Self {
        let texels: Vec<f64> = values.iter().map(|&v| spec.encoding.quantise(v)).collect();
        let texels_f32 = texels.iter().map(|&v| v as f32).collect();
        Self { spec, texels, texels_f32 }
    }

    #[inline]
    pub fn sample(&self, cos_theta: f64) -> f64 {
        sample_lut(&self.texels, cos_theta)
    }

    #[inline]
    pub fn sample_f32(&self, cos_theta: f32) -> f32 {
        sample_lut(&self.texels_f32, cos_theta)
    }
}

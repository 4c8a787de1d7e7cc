//! `lut` (SPEC §5.7): a 1D texture of F over c = cosθ ∈ [0, 1] read with a GPU's linear
//! filtering, and the texel encodings.
//!
//! Texel convention (OpenGL/Vulkan/D3D/WebGPU): texel i of N holds F at the texel centre
//! c_i = (i + ½)/N. Sampling at u = c: x = u·N − ½, i₀ = ⌊x⌋, i₁ = i₀ + 1, each clamped to
//! [0, N − 1] (clamp-to-edge), t = x − ⌊x⌋, F = T\[i₀\](1 − t) + T\[i₁\]t (WGSL `mix`).
//! Below the first centre and above the last, both indices clamp to the edge texel.
//! Not modelled: the reduced precision of hardware filter weights (e.g. 8 fractional
//! bits of t on current NVIDIA and AMD GPUs).

use super::real::Real;
use super::unit_cos;
use crate::encoding::texel_cos;
pub use crate::encoding::Encoding;

/// The texel counts of the "what accuracy costs" sweep.
pub const LUT_SIZES: [usize; 6] = [16, 32, 64, 128, 256, 1024];

/// Where linear filtering with clamp-to-edge reads a texture: the two texels and the
/// weight of the second.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter<T> {
    /// The texel below u.
    pub lower: usize,
    /// The texel above u (the same at the edges).
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

/// The filtered value T\[i₀\](1 − t) + T\[i₁\]t (WGSL `mix`) for weights from
/// [`filter_weights`].
#[inline]
pub fn filter<T: Real>(texels: &[T], weights: Filter<T>) -> T {
    texels[weights.lower] * (T::ONE - weights.weight) + texels[weights.upper] * weights.weight
}

/// `curve` at the texel centres c_i = (i + ½)/N of a texture of `texels` texels (at
/// least one): the values [`Lut::from_values`] quantises.
pub fn texel_values(texels: usize, curve: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..texels.max(1)).map(|i| curve(texel_cos(i, texels))).collect()
}

/// Texel count and encoding of a LUT.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LutSpec {
    /// Texels N.
    pub texels: usize,
    /// How each texel is stored.
    pub encoding: Encoding,
}

impl LutSpec {
    /// N texels stored as `encoding`.
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
    /// Texel count and encoding.
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

    /// Texel i = quantise(values\[i\]): `values` are the curve at the texel centres
    /// c_i = (i + ½)/N, so that one evaluation of the curve serves every encoding.
    pub fn from_values(spec: LutSpec, values: &[f64]) -> Self {
        let texels: Vec<f64> = values.iter().map(|&v| spec.encoding.quantise(v)).collect();
        let texels_f32 = texels.iter().map(|&v| v as f32).collect();
        Self { spec, texels, texels_f32 }
    }

    /// F at `cos_theta`, filtered as a GPU sampler does, in f64.
    #[inline]
    pub fn sample(&self, cos_theta: f64) -> f64 {
        sample_lut(&self.texels, cos_theta)
    }

    /// F at `cos_theta`, filtered as a GPU sampler does, in f32.
    #[inline]
    pub fn sample_f32(&self, cos_theta: f32) -> f32 {
        sample_lut(&self.texels_f32, cos_theta)
    }
}
/// File-level facts of an encoding: what a texture file of it holds and how a GPU samples it.
impl Encoding {
    /// What the file holds, in one line (the `--encoding` help).
    pub fn description(self) -> &'static str {
        match self {
            Encoding::Unorm8 => "8-bit PNG, code = round(255 * clamp(F, 0, 1)), linear",
            Encoding::Unorm8Srgb => {
                "8-bit PNG, code = round(255 * srgb_encode(clamp(F, 0, 1))); an sRGB texture format decodes it to linear F before filtering"
            }
            Encoding::Unorm16 => "16-bit PNG, code = round(65535 * clamp(F, 0, 1)), linear",
            Encoding::F16 => "OpenEXR half float (binary16, round-to-nearest-even), linear, not clamped",
            Encoding::F32 => "OpenEXR single float (binary32, round-to-nearest-even), linear, not clamped",
        }
    }

    /// The file's extension: `exr` for the floats, `png` otherwise.
    pub fn extension(self) -> &'static str {
        if self.is_float() {
            "exr"
        } else {
            "png"
        }
    }

    /// Whether texels are floats (f16, f32).
    pub fn is_float(self) -> bool {
        matches!(self, Encoding::F16 | Encoding::F32)
    }

    /// Bits one channel of one texel takes.
    pub fn bits_per_channel(self) -> u32 {
        8 * self.bytes_per_channel() as u32
    }

    /// `linear` or `srgb-encoded` (the stored values, not what a sampler returns).
    pub fn color_space(self) -> &'static str {
        if self == Encoding::Unorm8Srgb {
            "srgb-encoded"
        } else {
            "linear"
        }
    }

    /// The quantisation step bound |decode(encode(F)) − F| for F in range: half a code
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
            Encoding::Unorm16 => {
                "Vulkan R16G16B16A16_UNORM; GL RGBA16 (WebGPU core has no filterable 16-bit unorm: convert to rgba16float or rgba32float)"
            }
            Encoding::F16 => "WebGPU rgba16float; Vulkan R16G16B16A16_SFLOAT; GL RGBA16F",
            Encoding::F32 => {
                "WebGPU rgba32float (filterable only with the float32-filterable feature); Vulkan R32G32B32A32_SFLOAT; GL RGBA32F"
            }
        }
    }

    /// How to turn a stored value into F, in words (what `Encoding::decode` does).
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

//! `lut` (SPEC §5.7): a 1D texture of F over c = cosθ ∈ [0, 1] read with a GPU's linear
//! filtering, and the texel encodings.
//!
//! Texel convention (OpenGL/Vulkan/D3D/WebGPU): texel i of N holds F at the texel centre
//! c_i = (i + ½)/N. Sampling at u = c: x = u·N − ½, i₀ = ⌊x⌋, i₁ = i₀ + 1, each clamped to
//! [0, N − 1] (clamp-to-edge), t = x − ⌊x⌋, F = T[i₀](1 − t) + T[i₁]t (WGSL `mix`).
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
    (0..texels.max(1)).map(|i| curve(texel_cos(i, texels))).collect()
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

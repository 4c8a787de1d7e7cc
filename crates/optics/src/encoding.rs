//! How values are stored in textures and pictures: the sRGB transfer function
//! (IEC 61966-2-1:1999), the texel encodings of the LUTs (unorm, sRGB, IEEE half and
//! single floats) and the texel-centre convention c_i = (i + ½)/N of OpenGL, Vulkan,
//! Direct3D and WebGPU (SPEC §5.7). A leaf: the colour stage, the Fresnel LUTs, the bake
//! and the pictures all encode through here.

use half::f16;

/// The sRGB encoding (transfer function) of a linear value, IEC 61966-2-1:
/// 12.92·L for L ≤ 0.0031308, else 1.055·L^(1/2.4) − 0.055. Negative values are
/// encoded with the sign mirrored (the extended-range convention) so that out-of-gamut
/// values stay visible instead of being clamped here.
pub fn srgb_encode(linear: f64) -> f64 {
    let magnitude = linear.abs();
    let encoded = if magnitude <= 0.0031308 { 12.92 * magnitude } else { 1.055 * magnitude.powf(1.0 / 2.4) - 0.055 };
    encoded.copysign(linear)
}

/// The inverse of [`srgb_encode`]: V/12.92 for V ≤ 0.04045, else ((V + 0.055)/1.055)^2.4.
pub fn srgb_decode(encoded: f64) -> f64 {
    let magnitude = encoded.abs();
    let linear = if magnitude <= 0.04045 { magnitude / 12.92 } else { ((magnitude + 0.055) / 1.055).powf(2.4) };
    linear.copysign(encoded)
}

/// cosθ at the centre of texel `i` of `texels`: (i + ½)/N.
pub fn texel_cos(i: usize, texels: usize) -> f64 {
    (i as f64 + 0.5) / texels.max(1) as f64
}

/// The cosines of the centres of all `texels` texels, in order (see [`texel_cos`]).
pub fn texel_cosines(texels: usize) -> Vec<f64> {
    (0..texels).map(|i| texel_cos(i, texels)).collect()
}

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
    /// Every encoding, in the order of the tables.
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

    /// The encoding of [`Encoding::name`] `name`.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transfer_function_known_points() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-15);
        assert!((srgb_encode(0.0031308) - 0.040449936).abs() < 1e-8);
        // Middle grey: linear 0.18 encodes to 0.4613561295...
        assert!((srgb_encode(0.18) - 0.461356129500).abs() < 1e-9, "{}", srgb_encode(0.18));
        for v in [-0.3, 0.001, 0.02, 0.5, 1.2] {
            assert!((srgb_decode(srgb_encode(v)) - v).abs() < 1e-14);
        }
    }

    #[test]
    fn texel_centres_are_half_a_texel_in() {
        assert_eq!(texel_cosines(4), vec![0.125, 0.375, 0.625, 0.875]);
        assert_eq!(texel_cos(0, 1), 0.5);
    }
}

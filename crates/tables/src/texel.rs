//! What the bake adds to the fresnel module's texel encodings (SPEC §5.7): the stored
//! code arrays of PNG/EXR images. (The file-level facts of each encoding — file
//! extension, colour space, decode rule in words, GPU formats, quantisation bound — are
//! `fresnel::Encoding`'s own.)
//!
//! The encoding itself — unorm codes round(max · clamp(F, 0, 1)), sRGB with the
//! IEC 61966-2-1 transfer function, IEEE half/single floats with round-to-nearest-even —
//! and the LUT model (linear filtering with clamp-to-edge at texel centres (i + ½)/N) are
//! `fresnel::{Encoding, sample_lut}`, re-exported here so that bake code and its tests
//! name one implementation.

use half::f16;

pub use nklut_optics::fresnel::{sample_lut, Encoding};

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

    /// The texels of `codes` (`Encoding::encode` values, one per channel) in the
    /// variant `encoding` stores.
    fn from_codes(encoding: Encoding, codes: impl Iterator<Item = u32>) -> Self {
        // `Encoding::encode` returns codes ≤ 255 / 65535 and the bits of the float, so the casts are exact.
        match encoding {
            Encoding::Unorm8 | Encoding::Unorm8Srgb => Texels::U8(codes.map(|c| c as u8).collect()),
            Encoding::Unorm16 => Texels::U16(codes.map(|c| c as u16).collect()),
            Encoding::F16 => Texels::F16(codes.map(|c| f16::from_bits(c as u16)).collect()),
            Encoding::F32 => Texels::F32(codes.map(f32::from_bits).collect()),
        }
    }

    /// The rows one after the other (an atlas). All rows must share one variant.
    pub fn concat<'a>(encoding: Encoding, rows: impl IntoIterator<Item = &'a Texels>) -> Texels {
        let mut out = Texels::from_codes(encoding, std::iter::empty());
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

    /// The linear F each stored value stands for (what a GPU sampler returns per texel):
    /// `Encoding::decode` of each code.
    pub fn decode(&self, encoding: Encoding) -> Vec<f64> {
        match self {
            Texels::U8(v) => v.iter().map(|&c| encoding.decode(c as u32)).collect(),
            Texels::U16(v) => v.iter().map(|&c| encoding.decode(c as u32)).collect(),
            Texels::F16(v) => v.iter().map(|&x| encoding.decode(x.to_bits() as u32)).collect(),
            Texels::F32(v) => v.iter().map(|&x| encoding.decode(x.to_bits())).collect(),
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

/// Quantise a row (F per channel at the texel cosines, all channels of equal length) in
/// `encoding` (`Encoding::encode`), interleaving R G B. Integer encodings clamp to [0, 1]
/// and count the texels where any channel needed it; float encodings keep every value.
pub fn quantise(encoding: Encoding, curve: &[Vec<f64>; 3]) -> Quantised {
    let n = curve[0].len();
    let texel = |i: usize| [curve[0][i], curve[1][i], curve[2][i]];
    let clamped = if encoding.is_float() { 0 } else { (0..n).filter(|&i| texel(i).iter().any(|v| !(0.0..=1.0).contains(v))).count() };
    let texels = Texels::from_codes(encoding, (0..n).flat_map(texel).map(|v| encoding.encode(v)));
    Quantised { texels, clamped }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn bits_per_channel_of_each_encoding() {
        assert_eq!(Encoding::ALL.map(Encoding::bits_per_channel), [8, 8, 16, 16, 32]);
    }

    #[test]
    fn sampling_at_texel_centres_returns_texels_and_clamps_at_the_edges() {
        let t = [0.0f64, 1.0, 4.0, 9.0];
        for (i, c) in nklut_optics::encoding::texel_cosines(4).into_iter().enumerate() {
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

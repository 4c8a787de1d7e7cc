//! XYZ ↔ linear sRGB (IEC 61966-2-1:1999) and 8-bit colour-picker values; the transfer
//! function itself is [`crate::encoding::srgb_encode`].

use crate::encoding::srgb_encode;

/// A 3×3 matrix, row-major.
pub type Matrix3 = [[f64; 3]; 3];

/// sRGB primaries (x, y), IEC 61966-2-1: red, green, blue.
pub const SRGB_PRIMARIES: [(f64, f64); 3] = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)];

/// D65 as IEC 61966-2-1 states it, chromaticity (x, y): the one D65 white of the colour
/// code (the spectral reference colours use the white of their own integration, SPEC §4).
pub const D65_CHROMATICITY: (f64, f64) = (0.3127, 0.3290);

/// [`D65_CHROMATICITY`] in XYZ with Y = 1: (x/y, 1, (1 − x − y)/y).
pub const D65_WHITE_XYZ: [f64; 3] =
    [D65_CHROMATICITY.0 / D65_CHROMATICITY.1, 1.0, (1.0 - D65_CHROMATICITY.0 - D65_CHROMATICITY.1) / D65_CHROMATICITY.1];

/// The matrix printed in IEC 61966-2-1 (XYZ → linear sRGB, D65 white x = 0.3127,
/// y = 0.3290), 4 decimals. It is not exactly the inverse of the primaries' matrix
/// (its first entry is 3.2406 where the derivation gives 3.24097): the derivation is
/// used, and this only checks it to within 5·10⁻⁴.
pub const IEC_XYZ_TO_SRGB: Matrix3 = [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]];

/// m · v.
pub fn multiply(m: &Matrix3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// Inverse by the adjugate; `None` for a singular matrix.
pub fn invert(m: &Matrix3) -> Option<Matrix3> {
    let cofactor = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    let det = m[0][0] * cofactor(0, 0) + m[0][1] * cofactor(0, 1) + m[0][2] * cofactor(0, 2);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // inverse[r][c] = cofactor(c, r) / det (transpose of the cofactor matrix).
    Some([0, 1, 2].map(|r| [0, 1, 2].map(|c| cofactor(c, r) / det)))
}

/// Linear sRGB → XYZ for a given white: the columns are the primaries' XYZ (x/y, 1,
/// (1 − x − y)/y) scaled so that RGB (1, 1, 1) maps to `white_xyz` (the derivation of
/// IEC 61966-2-1 §5 and SMPTE RP 177). With the white of the spectral integration
/// itself, a perfect reflector comes out as (1, 1, 1) to rounding (SPEC §4).
pub fn rgb_to_xyz_matrix(white_xyz: [f64; 3]) -> Matrix3 {
    primaries_to_xyz_matrix(SRGB_PRIMARIES, white_xyz)
}

/// RGB → XYZ of any RGB space given its primaries' chromaticities (red, green, blue) and
/// its white's XYZ: the same derivation as [`rgb_to_xyz_matrix`].
pub fn primaries_to_xyz_matrix(primaries: [(f64, f64); 3], white_xyz: [f64; 3]) -> Matrix3 {
    let primary = |(x, y): (f64, f64)| [x / y, 1.0, (1.0 - x - y) / y];
    let [r, g, b] = primaries.map(primary);
    let columns: Matrix3 = [[r[0], g[0], b[0]], [r[1], g[1], b[1]], [r[2], g[2], b[2]]];
    let scale = multiply(&invert(&columns).expect("the primaries of an RGB space are independent"), white_xyz);
    [0, 1, 2].map(|row| [0, 1, 2].map(|col| columns[row][col] * scale[col]))
}

/// The XYZ (Y = 1) of a white given by its chromaticity (x, y).
pub fn white_from_chromaticity((x, y): (f64, f64)) -> [f64; 3] {
    [x / y, 1.0, (1.0 - x - y) / y]
}

/// The product a · b of two 3×3 matrices.
pub fn matrix_product(a: &Matrix3, b: &Matrix3) -> Matrix3 {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| (0..3).map(|i| a[r][i] * b[i][c]).sum()))
}

/// An 8-bit sRGB colour picker value of a linear colour: each channel clamped to [0, 1]
/// (per channel, so an out-of-gamut colour shifts hue), [`srgb_encode`]d, times 255, rounded.
///
/// ```
/// use nklut_optics::color::srgb::{hex_swatch, srgb8};
/// // Linear 0.21404 is sRGB 0.5 (the transfer function of IEC 61966-2-1): code 127.5.
/// assert_eq!(srgb8([0.0, 0.2140, 2.0]), [0, 127, 255]);
/// assert_eq!(srgb8([0.0, 0.2141, 2.0]), [0, 128, 255]);
/// assert_eq!(hex_swatch([0.0, 0.2141, 2.0]), "#0080ff");
/// ```
pub fn srgb8(linear: [f64; 3]) -> [u8; 3] {
    linear.map(|v| (srgb_encode(v.clamp(0.0, 1.0)) * 255.0).round() as u8)
}

/// `#rrggbb` of a linear-sRGB colour: clamped to [0, 1], sRGB-encoded, 8 bits.
pub fn hex_swatch(rgb: [f64; 3]) -> String {
    let [r, g, b] = srgb8(rgb);
    format!("#{r:02x}{g:02x}{b:02x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_matrix_matches_the_printed_one() {
        // Nominal D65 white from (x, y) = (0.3127, 0.3290).
        let white = D65_WHITE_XYZ;
        let to_rgb = invert(&rgb_to_xyz_matrix(white)).unwrap();
        for r in 0..3 {
            for c in 0..3 {
                assert!((to_rgb[r][c] - IEC_XYZ_TO_SRGB[r][c]).abs() < 5e-4, "[{r}][{c}] {}", to_rgb[r][c]);
            }
        }
        let ones = multiply(&to_rgb, white);
        assert!(ones.iter().all(|v| (v - 1.0).abs() < 1e-14), "{ones:?}");
    }
}

//! Linear Rec.709/sRGB → ACEScg (ACES AP1 primaries, linear), the working space of many
//! film and game pipelines.
//!
//! Sources: AP1 primaries and the ACES white (x, y) = (0.32168, 0.33767) from
//! SMPTE ST 2065-1 / Academy S-2014-004 (ACEScg); sRGB primaries and D65 (0.3127, 0.3290)
//! from IEC 61966-2-1; white-point adaptation D65 → ACES white with the Bradford
//! transform (Lam 1985, as in ICC.1 Annex E and OpenColorIO's ACES config):
//! M = XYZ→AP1 · B⁻¹ · diag(B·W_aces / B·W_d65) · B · sRGB→XYZ. Every matrix is derived
//! here from those chromaticities; the test checks the product against the published one.

use std::sync::OnceLock;

use super::srgb::{self, invert, matrix_product, multiply, primaries_to_xyz_matrix, white_from_chromaticity, Matrix3};

/// ACES AP1 primaries (x, y): red, green, blue.
pub const AP1_PRIMARIES: [(f64, f64); 3] = [(0.713, 0.293), (0.165, 0.830), (0.128, 0.044)];
/// The ACES white point (x, y) (≈ D60).
pub const ACES_WHITE: (f64, f64) = (0.32168, 0.33767);
/// D65 as IEC 61966-2-1 states it (x, y).
pub use super::srgb::D65_CHROMATICITY as D65_WHITE;
/// The Bradford cone-response matrix (XYZ → ρ γ β).
pub const BRADFORD: Matrix3 = [[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]];

/// The chromatic adaptation of XYZ from `source` white to `destination` white (Bradford).
pub fn bradford_adaptation(source: [f64; 3], destination: [f64; 3]) -> Matrix3 {
    let cone_source = multiply(&BRADFORD, source);
    let cone_destination = multiply(&BRADFORD, destination);
    let scale: Matrix3 = [0, 1, 2].map(|r| [0, 1, 2].map(|c| if r == c { cone_destination[r] / cone_source[r] } else { 0.0 }));
    let back = invert(&BRADFORD).expect("the Bradford matrix is invertible");
    matrix_product(&back, &matrix_product(&scale, &BRADFORD))
}

/// Linear sRGB (Rec.709 primaries, D65) → linear ACEScg (AP1, ACES white), built once.
pub fn srgb_to_acescg_matrix() -> &'static Matrix3 {
    static MATRIX: OnceLock<Matrix3> = OnceLock::new();
    MATRIX.get_or_init(|| {
        let d65 = white_from_chromaticity(D65_WHITE);
        let aces = white_from_chromaticity(ACES_WHITE);
        let to_xyz = srgb::rgb_to_xyz_matrix(d65);
        let adapt = bradford_adaptation(d65, aces);
        let from_xyz = invert(&primaries_to_xyz_matrix(AP1_PRIMARIES, aces)).expect("AP1 primaries are independent");
        matrix_product(&from_xyz, &matrix_product(&adapt, &to_xyz))
    })
}

/// A linear-sRGB colour in ACEScg (linear AP1).
pub fn srgb_to_acescg(rgb: [f64; 3]) -> [f64; 3] {
    multiply(srgb_to_acescg_matrix(), rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_bradford_matrix() {
        // sRGB → ACEScg (Bradford) as MaterialX's standard library applies it
        // (`mx_srgb_texture_to_acescg`, libraries/stdlib/genglsl, "same matrix as
        // vp2ShaderFragments"), printed to 8 digits; the GLSL mat3 is column-major.
        let published = [[0.61309740, 0.33952315, 0.04737945], [0.07019372, 0.91635388, 0.01345240], [0.02061559, 0.10956977, 0.86981463]];
        let m = srgb_to_acescg_matrix();
        for r in 0..3 {
            for c in 0..3 {
                assert!((m[r][c] - published[r][c]).abs() < 2e-6, "[{r}][{c}] {} vs {}", m[r][c], published[r][c]);
            }
        }
    }

    #[test]
    fn white_stays_white_and_primaries_stay_inside_ap1() {
        let white = srgb_to_acescg([1.0, 1.0, 1.0]);
        assert!(white.iter().all(|v| (v - 1.0).abs() < 1e-12), "{white:?}");
        // AP1 contains the Rec.709 gamut: every sRGB primary has non-negative AP1 coordinates.
        for primary in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            assert!(srgb_to_acescg(primary).iter().all(|v| *v > 0.0), "{primary:?}");
        }
    }
}

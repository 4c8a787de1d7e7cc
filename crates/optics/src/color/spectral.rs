//! The spectral reference colour of SPEC §4:
//!
//!   RGB(θ) = M · ∫ R(θ, λ) S(λ) \[x̄ ȳ z̄\](λ) dλ / ∫ S(λ) ȳ(λ) dλ,
//!
//! λ = 360…830 nm in 1 nm steps, the integrals as sums over that grid (CIE 15:2004 §7.1:
//! summation at 1 nm), S = D65, x̄ȳz̄ = CIE 1931 2°, M = XYZ → linear sRGB normalised so
//! that a perfect reflector (R ≡ 1) gives (1, 1, 1). Everything that does not depend on
//! the material is folded once into per-wavelength weights w(λ) = M·\[x̄ ȳ z̄\](λ) S(λ) / Σ S ȳ,
//! so a colour is one dot product Σ_λ R(θ, λ) w(λ) per channel.

use std::sync::OnceLock;

use super::cie;
use super::lab::{xyz_to_lab, Lab};
use super::srgb::{self, Matrix3};
use crate::db::PageData;
use crate::fresnel;
use crate::spectrum::{self, Index, SPECTRAL_SAMPLES};

/// The material-independent part of SPEC §4, computed once (see [`spectral_weights`]).
#[derive(Clone, Debug)]
pub struct SpectralWeights {
    /// w(λ_i) = M·\[x̄ ȳ z̄\](λ_i) S(λ_i) / Σ S ȳ for λ_i = 360 + i nm: linear-sRGB
    /// weights, Σ_i w(λ_i) = (1, 1, 1).
    pub rgb: Vec<[f64; 3]>,
    /// S(λ_i) ȳ(λ_i) / Σ S ȳ: the share of the luminance weight at each sample.
    pub luminance: Vec<f64>,
    /// Samples at and after this index have zero weight (D65 ends at 780 nm) and are
    /// skipped by the sums.
    pub active: usize,
    /// The XYZ of the illuminant over the grid, Y = 1: the white of the normalisation.
    pub white_xyz: [f64; 3],
    /// XYZ → linear sRGB, normalised to `white_xyz`.
    pub xyz_to_rgb: Matrix3,
    /// Linear sRGB → XYZ (the inverse).
    pub rgb_to_xyz: Matrix3,
}

/// The weights of SPEC §4, built from the embedded CIE tables on first use.
pub fn spectral_weights() -> &'static SpectralWeights {
    static WEIGHTS: OnceLock<SpectralWeights> = OnceLock::new();
    WEIGHTS.get_or_init(build_weights)
}

fn build_weights() -> SpectralWeights {
    let tables = cie::tables();
    let illuminated: Vec<[f64; 3]> = tables.cmf.iter().zip(&tables.d65).map(|(cmf, s)| cmf.map(|c| c * s)).collect();
    let norm: f64 = illuminated.iter().map(|xyz| xyz[1]).sum();
    let white_xyz = [0, 1, 2].map(|j| illuminated.iter().map(|xyz| xyz[j]).sum::<f64>() / norm);
    let rgb_to_xyz = srgb::rgb_to_xyz_matrix(white_xyz);
    let xyz_to_rgb = srgb::invert(&rgb_to_xyz).expect("the sRGB matrix is invertible");
    let rgb: Vec<[f64; 3]> = illuminated.iter().map(|xyz| srgb::multiply(&xyz_to_rgb, xyz.map(|v| v / norm))).collect();
    let active = rgb.iter().rposition(|w| w.iter().any(|v| *v != 0.0)).map_or(0, |last| last + 1);
    SpectralWeights { luminance: illuminated.iter().map(|xyz| xyz[1] / norm).collect(), rgb, active, white_xyz, xyz_to_rgb, rgb_to_xyz }
}

impl SpectralWeights {
    /// CIELAB of a linear-sRGB colour, white = the illuminant (D65) of the grid.
    pub fn lab(&self, rgb: [f64; 3]) -> Lab {
        xyz_to_lab(srgb::multiply(&self.rgb_to_xyz, rgb), self.white_xyz)
    }

    /// Chromaticity (x, y) of an XYZ colour.
    pub fn chromaticity(xyz: [f64; 3]) -> (f64, f64) {
        let sum = xyz[0] + xyz[1] + xyz[2];
        (xyz[0] / sum, xyz[1] / sum)
    }
}

/// Linear sRGB of a reflectance spectrum given on the grid (`reflectance[i]` at
/// 360 + i nm; missing samples count as 0): Σ_i R_i w(λ_i).
pub fn reflectance_spectrum_rgb(reflectance: &[f64]) -> [f64; 3] {
    let weights = spectral_weights();
    let mut rgb = [0.0; 3];
    for (r, w) in reflectance.iter().zip(&weights.rgb[..weights.active]) {
        for j in 0..3 {
            rgb[j] += r * w[j];
        }
    }
    rgb
}

/// A material's spectrum (from [`sample_spectrum`]) ready for reference colours
/// (SPEC §4): exact Fresnel's θ-independent terms once per distinct index — a run of
/// equal indices (held ends) shares one, with the summed weights of its wavelengths.
#[derive(Clone, Debug)]
pub struct PreparedSpectrum {
    groups: Vec<(fresnel::ExactTerms, [f64; 3])>,
}

impl PreparedSpectrum {
    /// The curve's terms of `spectrum` (one index per sample of the 1 nm grid).
    pub fn new(spectrum: &[Index]) -> Self {
        let weights = spectral_weights();
        debug_assert_eq!(spectrum.len(), SPECTRAL_SAMPLES);
        let mut groups: Vec<(fresnel::ExactTerms, [f64; 3])> = Vec::new();
        let mut previous = Index::new(f64::NAN, f64::NAN);
        for (index, w) in spectrum.iter().zip(&weights.rgb[..weights.active]) {
            if *index != previous {
                groups.push((fresnel::ExactTerms::new(fresnel::sanitise(*index)), [0.0; 3]));
                previous = *index;
            }
            let group = &mut groups.last_mut().expect("pushed above").1;
            group[0] += w[0];
            group[1] += w[1];
            group[2] += w[2];
        }
        Self { groups }
    }

    /// How many exact reflectances one colour sums: the distinct indices of the spectrum's
    /// weighted wavelengths (a run of equal indices counts once).
    pub fn distinct_indices(&self) -> usize {
        self.groups.len()
    }

    /// The reference colour (linear sRGB) at cosθ = `cos_theta`, R from [`fresnel::exact`].
    pub fn rgb(&self, cos_theta: f64) -> [f64; 3] {
        self.groups.iter().fold([0.0; 3], |rgb, (terms, w)| {
            let r = terms.reflectance(cos_theta);
            [rgb[0] + r * w[0], rgb[1] + r * w[1], rgb[2] + r * w[2]]
        })
    }

    /// [`PreparedSpectrum::rgb`] at each of `cosines` (e.g. the LUT texel centres), with
    /// the same bits: [`fresnel::LANES`] cosines at a time through
    /// [`fresnel::ExactTerms::reflectance_lanes`], each lane summing the wavelength groups
    /// in the same order as `rgb`. The vector width is chosen at run time (AVX-512, AVX2,
    /// or what the baseline target allows).
    pub fn curve(&self, cosines: &[f64]) -> Vec<[f64; 3]> {
        curve_in_lanes(self, cosines)
    }
}

#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn curve_in_lanes(spectrum: &PreparedSpectrum, cosines: &[f64]) -> Vec<[f64; 3]> {
    let mut curve = Vec::with_capacity(cosines.len());
    for chunk in cosines.chunks(fresnel::LANES) {
        // A short last chunk is padded with normal incidence; those lanes are dropped.
        let mut lanes = [1.0; fresnel::LANES];
        lanes[..chunk.len()].copy_from_slice(chunk);
        let mut sums = [[0.0; fresnel::LANES]; 3];
        for (terms, w) in &spectrum.groups {
            let r = terms.reflectance_lanes(&lanes);
            for (channel, sum) in sums.iter_mut().enumerate() {
                for (s, r) in sum.iter_mut().zip(r) {
                    *s += r * w[channel];
                }
            }
        }
        curve.extend((0..chunk.len()).map(|lane| [sums[0][lane], sums[1][lane], sums[2][lane]]));
    }
    curve
}

/// The spectral reference colour (linear sRGB) at cosθ = `cos_theta` of a material whose
/// index on the grid is `spectrum` (from [`sample_spectrum`]): SPEC §4.
pub fn reflectance_rgb(spectrum: &[Index], cos_theta: f64) -> [f64; 3] {
    PreparedSpectrum::new(spectrum).rgb(cos_theta)
}

/// [`reflectance_rgb`] at each of `cosines` (e.g. the LUT texel centres (i + ½)/N).
pub fn spectral_curve(spectrum: &[Index], cosines: &[f64]) -> Vec<[f64; 3]> {
    PreparedSpectrum::new(spectrum).curve(cosines)
}

/// The index of a page on the spectral grid (360…830 nm, 1 nm), with the nearest
/// measured n and k held outside the data (SPEC §4, [`spectrum::index_held`]), and the
/// share of the luminance weight Σ S ȳ that lies outside the data's range.
///
/// A held or formula value that is not a physical index (n ≤ 0, k < 0, not finite — a
/// formula outside the visible window can do this) is replaced by the nearest valid
/// sample and counted as extrapolated too, so the spectrum is always usable.
pub fn sample_spectrum(data: &PageData) -> (Vec<Index>, f64) {
    let (lo_nm, hi_nm) = data_range_nm(data);
    // µm → nm rounding (0.36 µm × 1000 = 360.00000000000006) must not count as outside.
    const EPS_NM: f64 = 1e-9;
    let weights = spectral_weights();
    let mut spectrum = Vec::with_capacity(SPECTRAL_SAMPLES);
    let mut valid = Vec::with_capacity(SPECTRAL_SAMPLES);
    let mut extrapolated = 0.0;
    for i in 0..SPECTRAL_SAMPLES {
        let nm = spectrum::spectral_wavelength_nm(i);
        let index = spectrum::index_held(data, nm);
        let is_valid = index.n > 0.0 && index.n.is_finite() && index.k >= 0.0 && index.k.is_finite();
        if !is_valid || nm < lo_nm - EPS_NM || nm > hi_nm + EPS_NM {
            extrapolated += weights.luminance[i];
        }
        spectrum.push(index);
        valid.push(is_valid);
    }
    replace_invalid_by_nearest(&mut spectrum, &valid);
    (spectrum, extrapolated.clamp(0.0, 1.0))
}

/// The wavelength range (nm) covered by both n and k.
fn data_range_nm(data: &PageData) -> (f64, f64) {
    let (n_lo, n_hi) = data.n.range_um();
    let (k_lo, k_hi) = data.k.as_ref().map_or((f64::NEG_INFINITY, f64::INFINITY), |k| k.range_um());
    (n_lo.max(k_lo) * 1000.0, n_hi.min(k_hi) * 1000.0)
}

/// Replace each invalid sample by the nearest valid one (ties: the shorter wavelength);
/// with no valid sample at all, vacuum (n = 1, k = 0), which reflects nothing.
fn replace_invalid_by_nearest(spectrum: &mut [Index], valid: &[bool]) {
    if valid.iter().all(|v| *v) {
        return;
    }
    let valid_positions: Vec<usize> = (0..spectrum.len()).filter(|&i| valid[i]).collect();
    for i in 0..spectrum.len() {
        if valid[i] {
            continue;
        }
        let nearest = valid_positions.iter().min_by_key(|&&j| (j.abs_diff(i), j)).copied();
        spectrum[i] = nearest.map_or(Index::new(1.0, 0.0), |j| spectrum[j]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::parse_page;

    #[test]
    fn perfect_reflector_is_white() {
        let rgb = reflectance_spectrum_rgb(&[1.0; SPECTRAL_SAMPLES]);
        for v in rgb {
            assert!((v - 1.0).abs() < 1e-14, "{rgb:?}");
        }
    }

    #[test]
    fn d65_white_point_chromaticity() {
        let (x, y) = SpectralWeights::chromaticity(spectral_weights().white_xyz);
        assert!((x - 0.3127).abs() < 1e-4 && (y - 0.3290).abs() < 1e-4, "x = {x}, y = {y}");
        assert_eq!(spectral_weights().white_xyz[1], 1.0);
        assert_eq!(spectral_weights().active, 421); // 360..=780 nm
    }

    #[test]
    fn constant_dielectric_is_neutral_grey() {
        let spectrum = vec![Index::new(1.5, 0.0); SPECTRAL_SAMPLES];
        for c in [1.0, 0.5, 0.1] {
            let rgb = reflectance_rgb(&spectrum, c);
            let expected = fresnel::exact(1.5, 0.0, c);
            for v in rgb {
                // Σ w = (1, 1, 1) to a few ulp: the grey is exact to ~1e-15 relative.
                assert!((v / expected - 1.0).abs() < 1e-13, "c = {c}: {rgb:?} vs {expected}");
            }
        }
    }

    #[test]
    fn weights_match_the_printed_iec_matrix_to_its_rounding() {
        let m = spectral_weights().xyz_to_rgb;
        for (r, (row, printed)) in m.iter().zip(srgb::IEC_XYZ_TO_SRGB).enumerate() {
            for (c, (value, printed)) in row.iter().zip(printed).enumerate() {
                assert!((value - printed).abs() < 2e-3, "[{r}][{c}] {value}");
            }
        }
    }

    #[test]
    fn curve_has_the_bits_of_one_colour_at_a_time() {
        // A varying metal, a dielectric with n < 1 somewhere (total reflection), held ends
        // (runs of equal indices) and a vacuum stretch; cosines incl. a short last chunk.
        let spectrum: Vec<Index> = (0..SPECTRAL_SAMPLES)
            .map(|i| match i {
                0..=30 => Index::new(1.0, 0.0),
                31..=120 => Index::new(0.9 + i as f64 * 1e-3, 0.0),
                121..=300 => Index::new(0.2 + i as f64 * 1e-3, 3.0 - i as f64 * 2e-3),
                _ => Index::new(1.45, 0.0),
            })
            .collect();
        let prepared = PreparedSpectrum::new(&spectrum);
        let mut cosines = crate::encoding::texel_cosines(37);
        cosines.extend([0.0, 1.0, -0.1, 1.5]);
        let curve = prepared.curve(&cosines);
        assert_eq!(curve.len(), cosines.len());
        for (c, rgb) in cosines.iter().zip(&curve) {
            assert_eq!(rgb.map(f64::to_bits), prepared.rgb(*c).map(f64::to_bits), "cosθ = {c}");
        }
        assert!(prepared.curve(&[]).is_empty());
    }

    #[test]
    fn held_ends_are_counted_as_extrapolated() {
        // Data over 400–700 nm: 360–399 and 701–780 nm are held.
        let data = parse_page("t.yml", "DATA:\n  - type: tabulated nk\n    data: |\n        0.40 1.2 0.5\n        0.70 1.4 0.1\n").unwrap();
        let (spectrum, share) = sample_spectrum(&data);
        assert_eq!(spectrum[0], Index::new(1.2, 0.5));
        assert_eq!(spectrum[470], Index::new(1.4, 0.1));
        let w = &spectral_weights().luminance;
        let expected: f64 = w[..40].iter().sum::<f64>() + w[341..].iter().sum::<f64>();
        assert!((share - expected).abs() < 1e-15 && share > 0.0 && share < 0.01, "{share}");
        let covered =
            parse_page("t.yml", "DATA:\n  - type: tabulated nk\n    data: |\n        0.36 1.2 0.5\n        0.83 1.4 0.1\n").unwrap();
        assert_eq!(sample_spectrum(&covered).1, 0.0);
    }

    #[test]
    fn invalid_formula_values_are_replaced_by_the_nearest_valid_sample() {
        // Cauchy n = 1.6 − 0.1/λ²… made to go negative below ~395 nm: n = C1 + C2 λ^-2.
        let data =
            parse_page("t.yml", "DATA:\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 2.0 -0.3 -2\n").unwrap();
        let (spectrum, share) = sample_spectrum(&data);
        assert!(spectrum.iter().all(|i| i.n > 0.0 && i.n.is_finite()));
        // n(λ) = 2 − 0.3/λ² ≤ 0 for λ ≤ 387.3 nm: samples 360..=387 replaced by n(388 nm).
        assert_eq!(spectrum[0], spectrum[28]);
        assert!(spectrum[28].n > 0.0 && spectrum[27] == spectrum[28]);
        assert!(share > 0.0);
    }
}

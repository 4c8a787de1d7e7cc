//! The validated error of a baked row: the LUT model on the decoded texels against a
//! reference curve, over θ uniform in [0°, 90°] (SPEC §5.7, §6). Two rules: the dense
//! midpoint rule of `error_samples` against `exact` (cheap to evaluate), and the colour
//! module's angle quadrature against the spectral reference (each value a 471-wavelength sum).

use serde::Serialize;

use crate::color::AngleQuadrature;
use crate::fresnel::{self, sample_lut};
use crate::spectrum::ChannelIndex;

/// Error samples per texel of the LUT (at least `MIN_ERROR_SAMPLES`, at most `MAX_ERROR_SAMPLES`).
pub const ERROR_SAMPLES_PER_TEXEL: usize = 32;
pub const MIN_ERROR_SAMPLES: usize = 4096;
pub const MAX_ERROR_SAMPLES: usize = 1 << 18;

/// M, the number of θ samples used for an N-texel LUT: clamp(32 N, 4096, 262144).
pub fn error_samples(size: usize) -> usize {
    (ERROR_SAMPLES_PER_TEXEL * size).clamp(MIN_ERROR_SAMPLES, MAX_ERROR_SAMPLES)
}

/// cosθ_j of the midpoint rule for θ uniform in [0°, 90°]: θ_j = (j + ½)·(π/2)/M.
/// Near grazing the spacing in cosθ is ≈ (π/2)/M, i.e. ≥ 16 samples per texel for M = 32 N.
pub fn error_cosines(samples: usize) -> Vec<f64> {
    let h = std::f64::consts::FRAC_PI_2 / samples as f64;
    (0..samples).map(|j| ((j as f64 + 0.5) * h).cos()).collect()
}

/// The midpoint rule of `error_cosines` as a quadrature (equal weights 1/M).
pub fn midpoint_rule(samples: usize) -> AngleQuadrature {
    AngleQuadrature { cosines: error_cosines(samples), weights: vec![1.0 / samples as f64; samples] }
}

/// `exact` (SPEC §5.1) per channel at each cosine: the reference of the three-channel error.
pub fn exact_reference(index: &ChannelIndex, cosines: &[f64]) -> [Vec<f64>; 3] {
    index.map(|i| cosines.iter().map(|&c| fresnel::exact(i.n, i.k, c)).collect())
}

/// Split interleaved R G B values into three channels.
pub fn deinterleave(values: &[f64]) -> [Vec<f64>; 3] {
    std::array::from_fn(|c| values.iter().skip(c).step_by(3).copied().collect())
}

/// Error figures of one row against one reference (SPEC §6 definitions, midpoint rule in θ).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LutError {
    /// Per channel (red, green, blue): mean over θ (the rule's weights, renormalised over
    /// the samples with F_ref > 0) of |F_lut − F_ref| / F_ref.
    pub mean_relative: [Option<f64>; 3],
    /// Mean of the channels' `mean_relative` (the per-material figure of SPEC §6).
    pub mean_relative_rgb: Option<f64>,
    /// Per channel: max |F_lut − F_ref| over all samples.
    pub max_absolute: [f64; 3],
    /// Largest of `max_absolute`.
    pub max_absolute_rgb: f64,
    /// Per channel: samples left out of the mean because F_ref = 0 (relative error undefined).
    pub excluded_zero_reference: [usize; 3],
}

/// The LUT model (decoded texels, linear filtering, clamp-to-edge) against `reference`
/// sampled at `rule.cosines` (`midpoint_rule` or `color::angle_quadrature`).
pub fn lut_error(decoded: &[Vec<f64>; 3], rule: &AngleQuadrature, reference: &[Vec<f64>; 3]) -> LutError {
    let mut mean_relative = [None; 3];
    let mut max_absolute = [0.0; 3];
    let mut excluded = [0; 3];
    for c in 0..3 {
        let (mut sum, mut weight, mut counted) = (0.0, 0.0, 0usize);
        for ((&cos, &q), &f_ref) in rule.cosines.iter().zip(&rule.weights).zip(&reference[c]) {
            let diff = (sample_lut(&decoded[c], cos) - f_ref).abs();
            max_absolute[c] = f64::max(max_absolute[c], diff);
            if f_ref > 0.0 {
                sum += q * diff / f_ref;
                weight += q;
                counted += 1;
            }
        }
        excluded[c] = rule.cosines.len() - counted;
        mean_relative[c] = (counted > 0).then(|| sum / weight);
    }
    let present: Vec<f64> = mean_relative.iter().flatten().copied().collect();
    LutError {
        mean_relative,
        mean_relative_rgb: (!present.is_empty()).then(|| present.iter().sum::<f64>() / present.len() as f64),
        max_absolute,
        max_absolute_rgb: max_absolute.iter().copied().fold(0.0, f64::max),
        excluded_zero_reference: excluded,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::texel::{quantise, Encoding};
    use crate::encoding::texel_cosines;
    use crate::spectrum::Index;

    /// The midpoint rule agrees with a brute-force 10⁶-point mean (SPEC §6) to 3 digits.
    #[test]
    fn midpoint_mean_matches_a_dense_mean() {
        let gold = [Index::new(0.18, 3.4), Index::new(0.5, 2.2), Index::new(1.3, 1.9)];
        let size = 32;
        let cos = texel_cosines(size);
        let curve = gold.map(|i| cos.iter().map(|&c| fresnel::exact(i.n, i.k, c)).collect::<Vec<_>>());
        let decoded = deinterleave(&quantise(Encoding::Unorm8, &curve).texels.decode(Encoding::Unorm8));
        let coarse_rule = midpoint_rule(error_samples(size));
        let coarse = lut_error(&decoded, &coarse_rule, &exact_reference(&gold, &coarse_rule.cosines));
        let dense_rule = midpoint_rule(1_000_000);
        let dense = lut_error(&decoded, &dense_rule, &exact_reference(&gold, &dense_rule.cosines));
        let (a, b) = (coarse.mean_relative_rgb.unwrap(), dense.mean_relative_rgb.unwrap());
        assert!((a - b).abs() < 1e-3 * b, "{a} vs {b}");
        assert!(coarse.max_absolute_rgb <= dense.max_absolute_rgb + 1e-12);
        assert!(coarse.max_absolute_rgb > 0.9 * dense.max_absolute_rgb);
    }

    #[test]
    fn vacuum_reference_is_excluded_not_nan() {
        let zero = [vec![0.0; 16], vec![0.0; 16], vec![0.0; 16]];
        let e = lut_error(&[vec![0.0; 4], vec![0.0; 4], vec![0.0; 4]], &midpoint_rule(16), &zero);
        assert_eq!(e.mean_relative, [None; 3]);
        assert_eq!(e.mean_relative_rgb, None);
        assert_eq!(e.excluded_zero_reference, [16; 3]);
    }
}

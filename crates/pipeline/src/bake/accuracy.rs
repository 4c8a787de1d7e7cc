//! The validated error of a baked row: the LUT model on the decoded texels against a
//! reference curve, over θ uniform in [0°, 90°] (SPEC §5.7, §6). Two rules: the dense
//! midpoint rule of `error_samples` against `exact` (cheap to evaluate), and the colour
//! module's angle quadrature against the spectral reference (each value a 471-wavelength sum).

use serde::Serialize;

use nklut_optics::color::AngleQuadrature;
use nklut_optics::fresnel;
use nklut_optics::spectrum::ChannelIndex;

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
    AngleQuadrature::of_nodes(error_cosines(samples), vec![1.0 / samples as f64; samples])
}

/// `exact` (SPEC §5.1) per channel at each cosine: the reference of the three-channel error.
pub fn exact_reference(index: &ChannelIndex, cosines: &[f64]) -> [Vec<f64>; 3] {
    index.map(|i| {
        let mut curve = vec![0.0; cosines.len()];
        fresnel::ExactTerms::new(fresnel::sanitise(i)).reflectances(cosines, &mut curve);
        curve
    })
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

/// The linear-filter taps of an N-texel LUT at each cosine of a rule
/// ([`fresnel::lut::filter_weights`]): the same for every row, set and channel of a bake,
/// so computed once.
#[derive(Clone, Debug)]
pub struct Taps {
    texels: usize,
    lower: Vec<u32>,
    upper: Vec<u32>,
    /// 1 − t: the weight of the lower texel.
    lower_weight: Vec<f64>,
    /// t: the weight of the upper texel.
    upper_weight: Vec<f64>,
}

impl Taps {
    pub fn new(texels: usize, cosines: &[f64]) -> Self {
        let mut taps = Taps { texels, lower: vec![], upper: vec![], lower_weight: vec![], upper_weight: vec![] };
        for &c in cosines {
            let fresnel::Filter { lower, upper, weight: t } = fresnel::filter_weights(texels.max(1), c);
            taps.lower.push(lower as u32);
            taps.upper.push(upper as u32);
            taps.lower_weight.push(1.0 - t);
            taps.upper_weight.push(t);
        }
        taps
    }
}

/// The LUT model (decoded texels, linear filtering, clamp-to-edge) against `reference`
/// sampled at `rule.cosines` (`midpoint_rule` or `color::angle_quadrature`).
pub fn lut_error(decoded: &[Vec<f64>; 3], rule: &AngleQuadrature, reference: &[Vec<f64>; 3]) -> LutError {
    lut_error_with_taps(decoded, &Taps::new(decoded[0].len(), &rule.cosines), rule, reference)
}

/// [`lut_error`] with the taps of `rule.cosines` for LUTs of `decoded[c].len()` texels
/// computed beforehand (by [`Taps::new`]).
pub fn lut_error_with_taps(decoded: &[Vec<f64>; 3], taps: &Taps, rule: &AngleQuadrature, reference: &[Vec<f64>; 3]) -> LutError {
    let mut mean_relative = [None; 3];
    let mut max_absolute = [0.0; 3];
    let mut excluded = [0; 3];
    for (c, sums) in channel_sums(decoded, taps, rule, reference).iter().enumerate() {
        max_absolute[c] = sums.max_absolute;
        excluded[c] = rule.cosines.len() - sums.counted;
        mean_relative[c] = (sums.counted > 0).then(|| sums.sum / sums.weight);
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

/// The running sums of one channel's error over a rule, in the rule's order.
#[derive(Clone, Copy, Debug, Default)]
struct ChannelSums {
    /// Σ q |F_lut − F_ref| / F_ref over the samples with F_ref > 0.
    sum: f64,
    /// Σ q over the same samples.
    weight: f64,
    counted: usize,
    max_absolute: f64,
}

/// Samples per block of [`channel_sums`]: the per-sample terms of a block are formed in
/// vector registers, then added in order.
const BLOCK: usize = 64;

/// The sums of the three channels. Channels that share the taps and the reference's
/// length are summed side by side, each in the rule's order (three independent chains of
/// additions instead of one after another); any other channel alone.
fn channel_sums(decoded: &[Vec<f64>; 3], taps: &Taps, rule: &AngleQuadrature, reference: &[Vec<f64>; 3]) -> [ChannelSums; 3] {
    let fits = |c: usize| !decoded[c].is_empty() && decoded[c].len() == taps.texels && reference[c].len() == reference[0].len();
    if (0..3).all(fits) {
        return channel_sums_in_blocks(decoded.each_ref().map(Vec::as_slice), taps, rule, reference.each_ref().map(Vec::as_slice));
    }
    std::array::from_fn(|c| one_channel_sums(&decoded[c], taps, rule, &reference[c]))
}

/// The sums of one channel, whatever its texel count.
fn one_channel_sums(texels: &[f64], taps: &Taps, rule: &AngleQuadrature, reference: &[f64]) -> ChannelSums {
    if texels.is_empty() {
        // No texture samples as 0, as a one-texel texture of 0 does.
        return one_channel_sums(&[0.0], &Taps::new(1, &rule.cosines), rule, reference);
    }
    if texels.len() != taps.texels {
        return one_channel_sums(texels, &Taps::new(texels.len(), &rule.cosines), rule, reference);
    }
    let [sums] = channel_sums_in_blocks([texels], taps, rule, [reference]);
    sums
}

/// F_lut = T[lower](1 − t) + T[upper] t ([`fresnel::lut::filter`]) and the error terms per
/// sample, then the sums in the rule's order — the same operations as one sample at a time,
/// for `C` channels that share the taps and the reference's length.
#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn channel_sums_in_blocks<const C: usize>(
    texels: [&[f64]; C],
    taps: &Taps,
    rule: &AngleQuadrature,
    reference: [&[f64]; C],
) -> [ChannelSums; C] {
    let mut sums = [ChannelSums::default(); C];
    let count = reference.first().map_or(0, |r| rule.cosines.len().min(r.len()));
    let (mut diff, mut term) = ([[0.0; BLOCK]; C], [[0.0; BLOCK]; C]);
    let mut start = 0;
    while start < count {
        let end = (start + BLOCK).min(count);
        let len = end - start;
        let (lower, upper) = (&taps.lower[start..end], &taps.upper[start..end]);
        let (lower_weight, upper_weight) = (&taps.lower_weight[start..end], &taps.upper_weight[start..end]);
        let q = &rule.weights[start..end];
        for c in 0..C {
            let (texels, f_ref) = (texels[c], &reference[c][start..end]);
            // Taps lie below the texel count; the clamp only lets the loop run in vector lanes.
            // Callers pass no empty texture (see `channel_sums`).
            let Some(last) = texels.len().checked_sub(1) else { continue };
            let taps = lower.iter().zip(upper).zip(lower_weight.iter().zip(upper_weight));
            let terms = diff[c][..len].iter_mut().zip(&mut term[c][..len]);
            for ((((&lo, &hi), (&lw, &uw)), (&q, &f_ref)), (diff, term)) in taps.zip(q.iter().zip(f_ref)).zip(terms) {
                let (lo, hi) = ((lo as usize).min(last), (hi as usize).min(last));
                let value = texels[lo] * lw + texels[hi] * uw;
                *diff = (value - f_ref).abs();
                *term = q * *diff / f_ref;
            }
        }
        for j in 0..len {
            for c in 0..C {
                let sums = &mut sums[c];
                sums.max_absolute = f64::max(sums.max_absolute, diff[c][j]);
                if reference[c][start + j] > 0.0 {
                    sums.sum += term[c][j];
                    sums.weight += q[j];
                    sums.counted += 1;
                }
            }
        }
        start = end;
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::texel::{quantise, Encoding};
    use nklut_optics::encoding::texel_cosines;
    use nklut_optics::spectrum::Index;

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

    /// The figures one sample at a time with `sample_lut`, as the definitions read.
    fn lut_error_by_samples(
        decoded: &[Vec<f64>; 3],
        rule: &AngleQuadrature,
        reference: &[Vec<f64>; 3],
    ) -> ([f64; 3], [f64; 3], [f64; 3], [usize; 3]) {
        let (mut sum, mut weight, mut max, mut counted) = ([0.0; 3], [0.0; 3], [0.0; 3], [0; 3]);
        for c in 0..3 {
            for ((&cos, &q), &f_ref) in rule.cosines.iter().zip(&rule.weights).zip(&reference[c]) {
                let diff = (fresnel::sample_lut(&decoded[c], cos) - f_ref).abs();
                max[c] = f64::max(max[c], diff);
                if f_ref > 0.0 {
                    sum[c] += q * diff / f_ref;
                    weight[c] += q;
                    counted[c] += 1;
                }
            }
        }
        (sum, weight, max, counted)
    }

    #[test]
    fn blocks_and_shared_taps_give_the_bits_of_one_sample_at_a_time() {
        let gold = [Index::new(0.18, 3.4), Index::new(0.5, 2.2), Index::new(1.3, 1.9)];
        for size in [1, 7, 64] {
            let curve = gold.map(|i| texel_cosines(size).iter().map(|&c| fresnel::exact(i.n, i.k, c)).collect::<Vec<_>>());
            let decoded = deinterleave(&quantise(Encoding::Unorm8Srgb, &curve).texels.decode(Encoding::Unorm8Srgb));
            // 1000 samples: several blocks and a short last one; a reference with zeros and
            // a negative value (excluded from the mean, counted in the maximum).
            let rule = midpoint_rule(1000);
            let mut reference = exact_reference(&gold, &rule.cosines);
            reference[1][3] = 0.0;
            reference[2][999] = -0.25;
            let taps = Taps::new(size, &rule.cosines);
            let fast = lut_error_with_taps(&decoded, &taps, &rule, &reference);
            assert_eq!(fast, lut_error(&decoded, &rule, &reference));
            let (sum, weight, max, counted) = lut_error_by_samples(&decoded, &rule, &reference);
            for c in 0..3 {
                assert_eq!(fast.mean_relative[c].map(f64::to_bits), Some((sum[c] / weight[c]).to_bits()), "size {size}, channel {c}");
                assert_eq!(fast.max_absolute[c].to_bits(), max[c].to_bits());
                assert_eq!(fast.excluded_zero_reference[c], 1000 - counted[c]);
            }
            // Taps of another size are not used for this one.
            assert_eq!(lut_error_with_taps(&decoded, &Taps::new(size + 1, &rule.cosines), &rule, &reference), fast);
            // Channels of different sizes (each alone) against channels summed side by side.
            let mut mixed = decoded.clone();
            mixed[1] = decoded[1].iter().chain(&decoded[1]).copied().collect();
            let mixed_error = lut_error_with_taps(&mixed, &taps, &rule, &reference);
            let (sum, weight, max, _) = lut_error_by_samples(&mixed, &rule, &reference);
            for c in 0..3 {
                assert_eq!(
                    mixed_error.mean_relative[c].map(f64::to_bits),
                    Some((sum[c] / weight[c]).to_bits()),
                    "mixed, size {size}, channel {c}"
                );
                assert_eq!(mixed_error.max_absolute[c].to_bits(), max[c].to_bits());
            }
            assert_eq!((mixed_error.mean_relative[0], mixed_error.mean_relative[2]), (fast.mean_relative[0], fast.mean_relative[2]));
        }
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

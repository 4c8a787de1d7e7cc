//! The validated error of a baked row: the LUT model on the decoded texels against a
//! reference curve, over θ uniform in [0°, 90°] (SPEC §5.7, §6). Two rules: the dense
//! midpoint rule of `error_samples` against `exact` (cheap to evaluate), and the colour
//! module's angle quadrature against the spectral reference (each value a 471-wavelength sum).
//! Both rules are extended by the two ends of the interval, θ = 90° (cos θ = 0) and θ = 0°
//! (cos θ = 1), with weight 0 ([`with_ends`]): they enter the maximum, not the mean. At
//! θ = 90° — the silhouette, where a shader's `clamp(dot(N, V), 0, 1)` gives 0 — exact F is
//! 1 and linear filtering with clamp-to-edge returns texel 0, so the largest error of a
//! steep row sits there, beyond every interior node.
//!
//! The recommended encodings ([`recommend`]): for each encoding, the smallest texture
//! width among [`candidate_sizes`] whose error meets [`RecommendationBound`], cheapest
//! first in GPU bytes (RGBA texels: 4 channels × bytes per channel × width).

use serde::Serialize;

use nklut_optics::color::AngleQuadrature;
use nklut_optics::fresnel;
use nklut_optics::spectrum::ChannelIndex;

use super::texel::{quantise, Encoding};

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

/// `rule` with the two ends of [0°, 90°] appended, θ = 90° (cos θ = 0) then θ = 0°
/// (cos θ = 1), each of weight 0: the mean is the rule's, the maximum includes the ends.
pub fn with_ends(rule: &AngleQuadrature) -> AngleQuadrature {
    let mut cosines = rule.cosines.clone();
    let mut weights = rule.weights.clone();
    cosines.extend([0.0, 1.0]);
    weights.extend([0.0, 0.0]);
    AngleQuadrature::of_nodes(cosines, weights)
}

/// A reference's value per channel at the ends of [0°, 90°].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ends {
    /// At θ = 90° (cos θ = 0).
    pub grazing: [f64; 3],
    /// At θ = 0° (cos θ = 1): F0.
    pub normal: [f64; 3],
}

/// `exact` (SPEC §5.1) of each channel of `index` at the ends (F(0) = 1 for every index
/// but vacuum, F(1) = F0 = ((n − 1)² + k²)/((n + 1)² + k²)).
pub fn exact_ends(index: &ChannelIndex) -> Ends {
    let at = |cos: f64| std::array::from_fn(|c| fresnel::ExactTerms::new(fresnel::sanitise(index[c])).reflectance(cos));
    Ends { grazing: at(0.0), normal: at(1.0) }
}

/// A reference at the nodes of a rule followed by its values at the ends: the reference
/// of [`with_ends`] of that rule.
pub fn append_ends(at_nodes: &[Vec<f64>; 3], ends: &Ends) -> [Vec<f64>; 3] {
    std::array::from_fn(|c| at_nodes[c].iter().copied().chain([ends.grazing[c], ends.normal[c]]).collect())
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
    /// Per channel: |F_lut − F_ref| at θ = 90° (cos θ = 0), where the sampler returns texel
    /// 0 — the silhouette's figure, part of `max_absolute`; null when the rule has no node
    /// at cos θ = 0.
    pub grazing_absolute: Option<[f64; 3]>,
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
    let grazing = rule.cosines.iter().position(|&c| c == 0.0);
    let grazing_absolute = grazing
        .map(|j| std::array::from_fn(|c| (fresnel::sample_lut(&decoded[c], 0.0) - reference[c].get(j).copied().unwrap_or(0.0)).abs()));
    LutError {
        mean_relative,
        mean_relative_rgb: (!present.is_empty()).then(|| present.iter().sum::<f64>() / present.len() as f64),
        max_absolute,
        max_absolute_rgb: max_absolute.iter().copied().fold(0.0, f64::max),
        excluded_zero_reference: excluded,
        grazing_absolute,
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

/// What a recommended size × encoding must meet, on the row's own exact curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RecommendationBound {
    /// `max_absolute_rgb` (θ = 90° included) at most this.
    pub max_absolute: f64,
    /// `mean_relative_rgb` at most this (a row whose reference is 0 everywhere has none
    /// and meets it).
    pub mean_relative: f64,
}

/// The default bound: 1 % of reflectance at worst (the silhouette included), 1 % relative
/// on average.
pub const RECOMMENDATION_BOUND: RecommendationBound = RecommendationBound { max_absolute: 0.01, mean_relative: 0.01 };

/// Smallest and largest power-of-two width tried besides the bake's own.
pub const MIN_CANDIDATE_SIZE: usize = 16;
pub const MAX_CANDIDATE_SIZE: usize = 1024;

/// The widths a recommendation tries: the powers of two from [`MIN_CANDIDATE_SIZE`] to
/// [`MAX_CANDIDATE_SIZE`] and the bake's own `size`, ascending.
pub fn candidate_sizes(size: usize) -> Vec<usize> {
    let mut sizes: Vec<usize> = std::iter::successors(Some(MIN_CANDIDATE_SIZE), |s| (*s < MAX_CANDIDATE_SIZE).then_some(s * 2)).collect();
    sizes.push(size.max(1));
    sizes.sort_unstable();
    sizes.dedup();
    sizes
}

/// GPU bytes of one row of `size` texels in `encoding`: RGBA (WebGPU and Vulkan have no
/// three-channel formats) × bytes per channel × width.
pub fn gpu_bytes(encoding: Encoding, size: usize) -> usize {
    4 * encoding.bytes_per_channel() * size
}

/// One size × encoding that meets the bound, with its figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Choice {
    pub size: usize,
    pub encoding: String,
    /// [`gpu_bytes`]: the cost the list is sorted by.
    pub gpu_bytes: usize,
    /// `max_absolute_rgb` of that texture (θ = 90° included).
    pub max_absolute_rgb: f64,
    pub mean_relative_rgb: Option<f64>,
}

/// The rule and filter taps every row's candidates are measured with, made once per bake:
/// the bake's own rule — the midpoint rule of `error_samples(N)` for the bake's width N,
/// with the ends, the rule of every row's `error_vs_exact` — and the taps of each candidate
/// width on it. One rule for all widths keeps the reference to one evaluation per row
/// (shared with `error_vs_exact`); wider candidates get fewer than 32 samples per texel,
/// their maximum still taken at θ = 90° and θ = 0°.
#[derive(Clone, Debug)]
pub struct Candidates {
    rule: AngleQuadrature,
    /// Per candidate width, ascending: (width, taps on `rule`).
    sizes: Vec<(usize, Taps)>,
}

impl Candidates {
    pub fn new(size: usize) -> Self {
        let rule = with_ends(&midpoint_rule(error_samples(size)));
        let sizes = candidate_sizes(size).into_iter().map(|n| (n, Taps::new(n, &rule.cosines))).collect();
        Candidates { rule, sizes }
    }

    /// The rule the candidates are measured on.
    pub fn rule(&self) -> &AngleQuadrature {
        &self.rule
    }

    /// The candidates (width, encoding) of a row whose exact curve is that of `index`, with
    /// their error against `reference` (that curve on [`Candidates::rule`]); widths ascending.
    /// With a bound, each encoding stops at the first width that meets it (all that
    /// [`recommend`] needs); without, every candidate.
    pub fn errors(
        &self,
        index: &ChannelIndex,
        reference: &[Vec<f64>; 3],
        bound: Option<&RecommendationBound>,
    ) -> Vec<(usize, Encoding, LutError)> {
        let mut out = Vec::new();
        let mut done = [false; Encoding::ALL.len()];
        for (n, taps) in &self.sizes {
            if done.iter().all(|&d| d) {
                break;
            }
            let curve = exact_reference(index, &nklut_optics::encoding::texel_cosines(*n));
            for (e, encoding) in Encoding::ALL.into_iter().enumerate() {
                if done[e] {
                    continue;
                }
                let decoded = deinterleave(&quantise(encoding, &curve).texels.decode(encoding));
                let error = lut_error_with_taps(&decoded, taps, &self.rule, reference);
                done[e] = bound.is_some_and(|b| meets(&error, b));
                out.push((*n, encoding, error));
            }
        }
        out
    }
}

/// Whether `error` meets `bound`.
pub fn meets(error: &LutError, bound: &RecommendationBound) -> bool {
    error.max_absolute_rgb <= bound.max_absolute && error.mean_relative_rgb.is_none_or(|m| m <= bound.mean_relative)
}

/// From candidate errors (as [`Candidates::errors`] lists them): per encoding, the smallest
/// width that meets `bound`; cheapest first ([`gpu_bytes`]), then the smaller maximum, then
/// the encoding's order. Empty when no candidate meets it.
pub fn recommend(errors: &[(usize, Encoding, LutError)], bound: &RecommendationBound) -> Vec<Choice> {
    let mut choices: Vec<(Encoding, Choice)> = Vec::new();
    for encoding in Encoding::ALL {
        let smallest = errors.iter().filter(|(_, e, error)| *e == encoding && meets(error, bound)).min_by_key(|(n, _, _)| *n);
        if let Some((n, _, error)) = smallest {
            choices.push((
                encoding,
                Choice {
                    size: *n,
                    encoding: encoding.name().into(),
                    gpu_bytes: gpu_bytes(encoding, *n),
                    max_absolute_rgb: error.max_absolute_rgb,
                    mean_relative_rgb: error.mean_relative_rgb,
                },
            ));
        }
    }
    choices
        .sort_by(|(ea, a), (eb, b)| a.gpu_bytes.cmp(&b.gpu_bytes).then(a.max_absolute_rgb.total_cmp(&b.max_absolute_rgb)).then(ea.cmp(eb)));
    choices.into_iter().map(|(_, c)| c).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
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
    /// Unpolarised Fresnel reflectance of a dielectric, written out from the amplitude
    /// coefficients (Born & Wolf §1.5): rs = (c − w)/(c + w), rp = (n²c − w)/(n²c + w),
    /// w = √(n² − 1 + c²).
    fn dielectric(n: f64, c: f64) -> f64 {
        let w = (n * n - 1.0 + c * c).sqrt();
        let (rs, rp) = ((c - w) / (c + w), (n * n * c - w) / (n * n * c + w));
        0.5 * (rs * rs + rp * rp)
    }

    /// At θ = 90° the sampler holds texel 0 = F(0.5/N) while exact F is 1: the silhouette's
    /// error, larger than at any interior sample of a steep (dielectric) row.
    #[test]
    fn the_maximum_includes_the_silhouette() {
        let glass = [Index::new(1.5, 0.0); 3];
        let size = 64;
        let curve = glass.map(|i| texel_cosines(size).iter().map(|&c| fresnel::exact(i.n, i.k, c)).collect::<Vec<_>>());
        let decoded = deinterleave(&quantise(Encoding::F32, &curve).texels.decode(Encoding::F32));
        let interior = midpoint_rule(error_samples(size));
        let ends = with_ends(&interior);
        assert_eq!(ends.cosines.len(), interior.cosines.len() + 2);
        let with = lut_error(&decoded, &ends, &exact_reference(&glass, &ends.cosines));
        let without = lut_error(&decoded, &interior, &exact_reference(&glass, &interior.cosines));
        let by_hand = 1.0 - dielectric(1.5, 0.5 / size as f64);
        for c in 0..3 {
            let grazing = with.grazing_absolute.unwrap()[c];
            assert!((grazing - by_hand).abs() < 1e-6, "{grazing} vs {by_hand}");
            assert_eq!(with.max_absolute[c], grazing);
            // The nearest interior sample, θ = 90°·(1 − 1/(2M)), falls 2.5 % short of it.
            assert!(without.max_absolute[c] < 0.99 * grazing, "{} vs {grazing}", without.max_absolute[c]);
        }
        // Weight 0: the ends leave the mean alone.
        assert_eq!(with.mean_relative, without.mean_relative);
        assert_eq!(without.grazing_absolute, None);
        // F0 of glass n = 1.5: ((n − 1)/(n + 1))² = 0.04; at grazing 1.
        let e = exact_ends(&glass);
        assert!((e.normal[0] - 0.04).abs() < 1e-15 && (e.grazing[0] - 1.0).abs() < 1e-15, "{e:?}");
    }

    #[test]
    fn candidate_widths_are_powers_of_two_and_the_bakes_own() {
        assert_eq!(candidate_sizes(256), vec![16, 32, 64, 128, 256, 512, 1024]);
        assert_eq!(candidate_sizes(100), vec![16, 32, 64, 100, 128, 256, 512, 1024]);
        assert_eq!(candidate_sizes(4096).last(), Some(&4096));
        assert_eq!(gpu_bytes(Encoding::F32, 256), 4096);
        assert_eq!(gpu_bytes(Encoding::Unorm8Srgb, 64), 256);
    }

    /// Per encoding the smallest width that meets the bound, cheapest first, ties to the
    /// smaller maximum; encodings that never meet it are left out.
    #[test]
    fn recommend_picks_the_smallest_width_per_encoding_cheapest_first() {
        let error = |max: f64, mean: f64| LutError {
            mean_relative: [Some(mean); 3],
            mean_relative_rgb: Some(mean),
            max_absolute: [max; 3],
            max_absolute_rgb: max,
            excluded_zero_reference: [0; 3],
            grazing_absolute: None,
        };
        let bound = RecommendationBound { max_absolute: 0.01, mean_relative: 0.01 };
        let errors = vec![
            (32, Encoding::Unorm8, error(0.02, 0.001)),
            (64, Encoding::Unorm8, error(0.009, 0.005)),
            (128, Encoding::Unorm8, error(0.004, 0.004)),
            (32, Encoding::Unorm8Srgb, error(0.005, 0.02)),
            (64, Encoding::Unorm8Srgb, error(0.008, 0.009)),
            (32, Encoding::F16, error(0.009, 0.001)),
            (32, Encoding::Unorm16, error(0.2, 0.5)),
            (16, Encoding::F32, error(0.011, 0.001)),
            (32, Encoding::F32, error(0.001, 0.0001)),
        ];
        let got: Vec<(usize, String, usize)> = recommend(&errors, &bound).into_iter().map(|c| (c.size, c.encoding, c.gpu_bytes)).collect();
        // unorm8-srgb@64 (256 B, max 0.008) before unorm8@64 (256 B, 0.009); f16@32 256 B
        // and 0.009 ties unorm8@64 on both: encoding order; f32@32 512 B last.
        assert_eq!(
            got,
            vec![(64, "unorm8-srgb".into(), 256), (64, "unorm8".into(), 256), (32, "f16".into(), 256), (32, "f32".into(), 512)]
        );
        assert!(recommend(&errors, &RecommendationBound { max_absolute: 1e-6, mean_relative: 1e-6 }).is_empty());
    }

    /// The candidates' figures are `lut_error` of each width on the bake's rule with ends;
    /// with a bound, each encoding stops at its first width that meets it.
    #[test]
    fn candidates_are_each_widths_error_on_the_bakes_rule() {
        let gold = [Index::new(0.18, 3.4), Index::new(0.5, 2.2), Index::new(1.3, 1.9)];
        let candidates = Candidates::new(48);
        let rule = with_ends(&midpoint_rule(error_samples(48)));
        assert_eq!(candidates.rule().cosines, rule.cosines);
        let reference = exact_reference(&gold, &rule.cosines);
        let errors = candidates.errors(&gold, &reference, None);
        assert_eq!(errors.len(), candidate_sizes(48).len() * 5);
        for n in [16, 48, 1024] {
            let curve = exact_reference(&gold, &texel_cosines(n));
            for encoding in Encoding::ALL {
                let decoded = deinterleave(&quantise(encoding, &curve).texels.decode(encoding));
                let want = lut_error(&decoded, &rule, &reference);
                let got = &errors.iter().find(|(m, e, _)| *m == n && *e == encoding).unwrap().2;
                assert_eq!(got, &want, "{n} {}", encoding.name());
            }
        }
        let bound = RECOMMENDATION_BOUND;
        let stopped = candidates.errors(&gold, &reference, Some(&bound));
        assert!(stopped.len() < errors.len());
        assert_eq!(recommend(&stopped, &bound), recommend(&errors, &bound));
        for encoding in Encoding::ALL {
            let tried: Vec<&LutError> = stopped.iter().filter(|(_, e, _)| *e == encoding).map(|(_, _, error)| error).collect();
            assert!(tried[..tried.len() - 1].iter().all(|error| !meets(error, &bound)), "{}", encoding.name());
        }
    }
}

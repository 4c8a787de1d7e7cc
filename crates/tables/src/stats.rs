//! Order statistics of measured samples (timings): the linearly interpolated quantile, the
//! median, and the median with its interquartile range. One definition for every table that
//! reports a median: the effects' CPU frame times, the GPU runner's pass times, the report's
//! medians over materials.
//!
//! Error summaries ([`ErrorSummary`]): of a list of signed errors with a weight each (1 per
//! vertex or pixel, a vertex's area for area weighting), the weighted mean of |e|, the
//! weighted signed mean, the weighted median, 90th and 99th percentiles and the largest |e|.
//! The weighted quantile generalises the linear one above (Hyndman and Fan's type 7): the
//! sorted values sit at the centres of their weights, c_k = Σ_{i<k} w_i + w_k/2, rescaled so
//! the first sits at 0 and the last at 1, and q is interpolated linearly between them; with
//! equal weights c_k is (k − ½)·w and the positions are k/(n − 1), the type-7 ones.
//!
//! Histograms ([`Histogram`]) of the same weighted signed errors: equal bins over a range,
//! counts and summed weights per bin, values beyond the range counted in the end bins.

/// Linear-interpolated quantile `q` ∈ [0, 1] of sorted values (NaN for none).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let position = q * (sorted.len() - 1) as f64;
    let (low, high) = (position.floor() as usize, position.ceil() as usize);
    sorted[low] + (sorted[high] - sorted[low]) * (position - low as f64)
}

/// The median of `values` (the mean of the middle two for an even count); `None` for none.
pub fn median(values: &[f64]) -> Option<f64> {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    (!sorted.is_empty()).then(|| quantile(&sorted, 0.5))
}

/// Median and spread (interquartile range, q75 − q25).
pub fn median_and_iqr(samples: &[f64]) -> (f64, f64) {
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    (quantile(&sorted, 0.5), quantile(&sorted, 0.75) - quantile(&sorted, 0.25))
}

/// The weighted quantile `q` ∈ [0, 1] of (value, weight) pairs sorted by value, all weights
/// positive (NaN for none): linear between the values placed at the centres of their
/// weights (module doc); equal weights give [`quantile`].
pub fn weighted_quantile(sorted: &[(f64, f64)], q: f64) -> f64 {
    let (Some(first), Some(last)) = (sorted.first(), sorted.last()) else { return f64::NAN };
    let mut centres = Vec::with_capacity(sorted.len());
    let mut below = 0.0;
    for &(_, weight) in sorted {
        centres.push(below + weight / 2.0);
        below += weight;
    }
    let (start, span) = (centres[0], centres[centres.len() - 1] - centres[0]);
    if !(span > 0.0) {
        return first.0 + (last.0 - first.0) * q.clamp(0.0, 1.0);
    }
    let target = start + q.clamp(0.0, 1.0) * span;
    let k = centres.partition_point(|&c| c < target).clamp(1, sorted.len() - 1);
    let (c0, c1) = (centres[k - 1], centres[k]);
    let t = if c1 > c0 { ((target - c0) / (c1 - c0)).clamp(0.0, 1.0) } else { 1.0 };
    sorted[k - 1].0 + (sorted[k].0 - sorted[k - 1].0) * t
}

/// The summary of a list of signed errors e (measured − reference) with weights w: weighted
/// means of |e| and of e, the weighted median, p90 and p99 of |e|, the largest |e|, and how
/// many entries it counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    pub count: usize,
    pub mean: f64,
    pub signed_mean: f64,
    pub median: f64,
    pub p90: f64,
    pub p99: f64,
    pub max: f64,
}

impl ErrorSummary {
    /// The summary of nothing: count 0, every figure 0.
    pub const NONE: ErrorSummary = ErrorSummary { count: 0, mean: 0.0, signed_mean: 0.0, median: 0.0, p90: 0.0, p99: 0.0, max: 0.0 };

    /// The summary of `errors` with `weights` (one per error; an entry with a non-finite
    /// error or a weight that is not positive and finite is left out); `None` when nothing is
    /// left.
    pub fn weighted(errors: &[f64], weights: &[f64]) -> Option<ErrorSummary> {
        let mut kept: Vec<(f64, f64, f64)> = errors
            .iter()
            .zip(weights)
            .filter(|(e, w)| e.is_finite() && w.is_finite() && **w > 0.0)
            .map(|(&e, &w)| (e.abs(), w, e))
            .collect();
        if kept.is_empty() {
            return None;
        }
        let total: f64 = kept.iter().map(|k| k.1).sum();
        let mean = kept.iter().map(|k| k.0 * k.1).sum::<f64>() / total;
        let signed_mean = kept.iter().map(|k| k.2 * k.1).sum::<f64>() / total;
        kept.sort_by(|a, b| a.0.total_cmp(&b.0));
        let sorted: Vec<(f64, f64)> = kept.iter().map(|k| (k.0, k.1)).collect();
        Some(ErrorSummary {
            count: sorted.len(),
            mean,
            signed_mean,
            median: weighted_quantile(&sorted, 0.5),
            p90: weighted_quantile(&sorted, 0.9),
            p99: weighted_quantile(&sorted, 0.99),
            max: sorted[sorted.len() - 1].0,
        })
    }

    /// The summary with every error weighted 1.
    pub fn of(errors: &[f64]) -> Option<ErrorSummary> {
        ErrorSummary::weighted(errors, &vec![1.0; errors.len()])
    }
}

/// The bins of a histogram: `bins` equal bins from `low` to `high`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistogramBins {
    pub low: f64,
    pub high: f64,
    pub bins: usize,
}

/// A weighted histogram of signed errors over [`HistogramBins`]: per bin how many entries
/// fall in it and their summed weight; bin k holds `edges[k] ≤ e < edges[k + 1]`, a value
/// below `low` is counted in the first bin and one at or above `high` in the last (none is
/// lost), and an entry with a non-finite value or a weight that is not positive and finite
/// is left out (as in [`ErrorSummary`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    /// bins + 1 edges, `low` to `high`: `edges[k] = (low·(bins − k) + high·k)/bins` (exact at
    /// both ends, and at every edge a decimal range such as ±0.5 in 40 bins names).
    pub edges: Vec<f64>,
    pub counts: Vec<u64>,
    pub weights: Vec<f64>,
}

impl Histogram {
    /// The histogram of `values` with `weights` (one per value); `None` for bins that are
    /// not a finite, increasing range of at least one bin.
    pub fn weighted(values: &[f64], weights: &[f64], bins: HistogramBins) -> Option<Histogram> {
        let HistogramBins { low, high, bins: n } = bins;
        if n == 0 || !low.is_finite() || !high.is_finite() || !(low < high) {
            return None;
        }
        let edges: Vec<f64> = (0..=n).map(|k| (low * (n - k) as f64 + high * k as f64) / n as f64).collect();
        let mut counts = vec![0; n];
        let mut summed = vec![0.0; n];
        for (&value, &weight) in values.iter().zip(weights) {
            if !(value.is_finite() && weight.is_finite() && weight > 0.0) {
                continue;
            }
            // The bin of the last edge at or below the value (edges are increasing), clamped.
            let bin = edges.partition_point(|&edge| edge <= value).saturating_sub(1).min(n - 1);
            counts[bin] += 1;
            summed[bin] += weight;
        }
        Some(Histogram { edges, counts, weights: summed })
    }

    /// The histogram with every value weighted 1.
    pub fn of(values: &[f64], bins: HistogramBins) -> Option<Histogram> {
        Histogram::weighted(values, &vec![1.0; values.len()], bins)
    }

    /// The summed weight of every bin.
    pub fn total_weight(&self) -> f64 {
        self.weights.iter().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four bins over [−1, 1) (edges −1, −0.5, 0, 0.5, 1): −3 and −1 in the first (below the
    /// range, at its low edge), −0.5 in the second (a value on an edge belongs to the bin it
    /// opens), −0.2 too; 0 and 0.25 in the third; 0.5, 0.9, 1 and 7 in the last (at or above
    /// the high edge counted there); NaN and ±∞ left out.
    #[test]
    fn histogram_of_a_hand_made_list() {
        let bins = HistogramBins { low: -1.0, high: 1.0, bins: 4 };
        let values = [-3.0, -1.0, -0.5, -0.2, 0.0, 0.25, 0.5, 0.9, 1.0, 7.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        let h = Histogram::of(&values, bins).unwrap();
        assert_eq!(h.edges, [-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(h.counts, [2, 2, 2, 4]);
        assert_eq!(h.weights, [2.0, 2.0, 2.0, 4.0]);
        assert_eq!(h.total_weight(), 10.0);
        // Area weights: a weight of 0, negative or NaN leaves its entry out; the rest sum.
        let weights = [0.5, 0.25, 2.0, 0.0, 1.5, -1.0, 0.125, f64::NAN, 3.0, 1.0, 1.0, 1.0, 1.0];
        let w = Histogram::weighted(&values, &weights, bins).unwrap();
        assert_eq!(w.counts, [2, 1, 1, 3]);
        assert_eq!(w.weights, [0.75, 2.0, 1.5, 4.125]);
        // Bins that are no range: none.
        for bad in [
            HistogramBins { low: 0.0, high: 1.0, bins: 0 },
            HistogramBins { low: 1.0, high: 1.0, bins: 2 },
            HistogramBins { low: 1.0, high: -1.0, bins: 2 },
            HistogramBins { low: f64::NAN, high: 1.0, bins: 2 },
            HistogramBins { low: 0.0, high: f64::INFINITY, bins: 2 },
        ] {
            assert_eq!(Histogram::of(&values, bad), None, "{bad:?}");
        }
        assert_eq!(Histogram::of(&[], bins).unwrap().counts, [0; 4]);
    }

    proptest::proptest! {
        /// Every finite value is counted once, in the bin whose edges hold it (the end bins
        /// also holding what lies beyond).
        #[test]
        fn every_value_lands_in_its_bin(values in proptest::collection::vec(-3.0f64..3.0, 0..200), bins in 1usize..50) {
            let h = Histogram::of(&values, HistogramBins { low: -1.0, high: 2.0, bins }).unwrap();
            proptest::prop_assert_eq!(h.counts.iter().sum::<u64>(), values.len() as u64);
            for k in 0..bins {
                let inside = values.iter().filter(|&&v| {
                    (k == 0 || v >= h.edges[k]) && (k == bins - 1 || v < h.edges[k + 1])
                }).count() as u64;
                proptest::prop_assert_eq!(h.counts[k], inside, "bin {}", k);
            }
        }
    }

    /// A hand-made list: errors −0.3, 0.1, −0.2, 0.5, 0.0 (|e| sorted 0, 0.1, 0.2, 0.3, 0.5 at
    /// positions 0, ¼, ½, ¾, 1). Mean |e| 1.1/5 = 0.22, signed mean 0.1/5 = 0.02, median
    /// 0.2; p90 at position 0.9 lies 0.6 of the way from 0.3 to 0.5: 0.42; p99: 0.3 + 0.96 ×
    /// 0.2 = 0.492; max 0.5.
    #[test]
    fn error_summary_of_a_hand_made_list() {
        let s = ErrorSummary::of(&[-0.3, 0.1, -0.2, 0.5, 0.0]).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert_eq!(s.count, 5);
        assert!(close(s.mean, 0.22) && close(s.signed_mean, 0.02), "{s:?}");
        assert!(close(s.median, 0.2) && close(s.p90, 0.42) && close(s.p99, 0.492) && s.max == 0.5, "{s:?}");
        // Weights 1, 1, 1, 1, 0 drop the 0; weights 3 on 0.1 and 1 elsewhere: centres of
        // 0.1 (w 3), 0.2, 0.3, 0.5 at 1.5, 3.5, 4.5, 5.5 → positions 0, ½, ¾, 1 over the
        // span 4; mean |e| (0.3 + 0.2 + 0.3 + 0.5)/6 = 1.3/6, signed (0.3 − 0.2 − 0.3 +
        // 0.5)/6 = 0.3/6; median 0.2; p90 = 0.3 + 0.6 × 0.2 = 0.42.
        let w = ErrorSummary::weighted(&[-0.3, 0.1, -0.2, 0.5, 0.0], &[1.0, 3.0, 1.0, 1.0, 0.0]).unwrap();
        assert_eq!(w.count, 4);
        assert!(close(w.mean, 1.3 / 6.0) && close(w.signed_mean, 0.05), "{w:?}");
        assert!(close(w.median, 0.2) && close(w.p90, 0.42) && w.max == 0.5, "{w:?}");
        // Area weights: a heavy entry pulls the median to itself (weights 1, 1, 10 on
        // 0.1, 0.2, 0.9: centres 0.5, 1.5, 7 → positions 0, 1/6.5, 1; the median at 0.5
        // lies (0.5 − 1/6.5)/(1 − 1/6.5) = 0.409 of the way from 0.2 to 0.9: 0.4864).
        let heavy = ErrorSummary::weighted(&[0.1, 0.2, -0.9], &[1.0, 1.0, 10.0]).unwrap();
        let position = 1.0 / 6.5;
        assert!(close(heavy.median, 0.2 + 0.7 * (0.5 - position) / (1.0 - position)), "{heavy:?}");
        assert!(close(heavy.signed_mean, (0.1 + 0.2 - 9.0) / 12.0));
        // Nothing left: none; one entry: itself everywhere; non-finite errors are left out.
        assert_eq!(ErrorSummary::of(&[]), None);
        assert_eq!(ErrorSummary::weighted(&[0.3], &[0.0]), None);
        let one = ErrorSummary::of(&[-0.25, f64::NAN]).unwrap();
        assert_eq!((one.count, one.median, one.p99, one.max, one.signed_mean), (1, 0.25, 0.25, 0.25, -0.25));
    }

    /// Equal weights give the linear quantile of timings, at every q.
    #[test]
    fn weighted_quantile_with_equal_weights_is_the_linear_quantile() {
        let values = [0.0, 0.5, 0.75, 2.0, 2.5, 7.0, 9.0];
        let pairs: Vec<(f64, f64)> = values.iter().map(|&v| (v, 2.5)).collect();
        for i in 0..=100 {
            let q = i as f64 / 100.0;
            assert!((weighted_quantile(&pairs, q) - quantile(&values, q)).abs() < 1e-12, "q {q}");
        }
    }

    #[test]
    fn median_and_interquartile_range() {
        let (median_value, iqr) = median_and_iqr(&[5.0, 1.0, 3.0, 2.0, 4.0]);
        assert_eq!(median_value, 3.0);
        assert_eq!(iqr, 2.0);
        let (median_value, _) = median_and_iqr(&[1.0, 2.0]);
        assert_eq!(median_value, 1.5);
        assert_eq!((median(&[4.0, 1.0, 2.0, 3.0]), median(&[2.0]), median(&[])), (Some(2.5), Some(2.0), None));
    }
}

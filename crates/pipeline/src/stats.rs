//! Order statistics of measured samples (timings): the linearly interpolated quantile, the
//! median, and the median with its interquartile range. One definition for every table that
//! reports a median: the effects' CPU frame times, the GPU runner's pass times, the report's
//! medians over materials.

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

#[cfg(test)]
mod tests {
    use super::*;

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

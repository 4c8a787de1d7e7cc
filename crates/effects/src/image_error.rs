//! The image error of an effects frame against a reference frame, over the pixels where the
//! reference shows a given specular object, or any (elsewhere both show the same diffuse
//! colour): the
//! relative error |a − r|/r per pixel and channel of the image-error measurement
//! (docs/precision.md; [`relative_error`]: samples with r ≤ 0 skipped and counted, and no
//! mean at all where none is left), the mean absolute error, and the mean CIEDE2000
//! difference of the colours (linear sRGB → XYZ → CIELAB, D65 white). The GPU runner's
//! image error takes the same rule from here.

use super::trace::TracedFrame;
use nklut_optics::color::lab::{delta_e2000, xyz_to_lab};
use nklut_optics::color::srgb::{multiply, rgb_to_xyz_matrix};

use nklut_optics::color::srgb::D65_WHITE_XYZ;

/// The relative error of a rendered channel value `a` against its reference `r`: |a − r|/r
/// where r > 0; `None` where r ≤ 0 (undefined: such samples are skipped and counted).
pub fn relative_error(a: f64, r: f64) -> Option<f64> {
    (r > 0.0).then(|| (a - r).abs() / r)
}

/// The error of one frame against its reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameError {
    /// Pixels compared (the reference shows a specular object there).
    pub pixels: usize,
    /// Mean of [`relative_error`] over the channel samples that have one; `None` when none
    /// has (every r ≤ 0, or no pixel).
    pub mean_relative: Option<f64>,
    /// The samples behind `mean_relative`.
    pub relative_samples: usize,
    pub max_relative: f64,
    /// Pixel channels with r = 0, left out of the relative error.
    pub skipped_zero_reference: usize,
    pub mean_absolute: f64,
    pub max_absolute: f64,
    pub mean_delta_e2000: f64,
}

/// Compare `frame` with `reference` (same size) over the pixels where the reference shows
/// any specular object.
pub fn compare(frame: &TracedFrame, reference: &TracedFrame) -> FrameError {
    compare_where(frame, reference, |seen| seen.is_some())
}

/// Compare over every pixel.
pub fn compare_all(frame: &TracedFrame, reference: &TracedFrame) -> FrameError {
    compare_where(frame, reference, |_| true)
}

/// Compare over the pixels where the reference shows specular object `object`.
pub fn compare_object(frame: &TracedFrame, reference: &TracedFrame, object: usize) -> FrameError {
    compare_where(frame, reference, |seen| seen == Some(object))
}

/// CIEDE2000 between two linear-sRGB colours (→ XYZ → CIELAB, D65 white): the colour
/// difference every effects table reports.
pub fn delta_e2000_rgb(a: [f64; 3], r: [f64; 3]) -> f64 {
    let to_xyz = rgb_to_xyz_matrix(D65_WHITE_XYZ);
    let lab = |rgb: [f64; 3]| xyz_to_lab(multiply(&to_xyz, rgb), D65_WHITE_XYZ);
    delta_e2000(lab(a), lab(r))
}

/// [`delta_e2000_rgb`] per pixel of `frame` against `reference`.
pub fn delta_e_map(frame: &TracedFrame, reference: &TracedFrame) -> Vec<f64> {
    frame.radiance.iter().zip(&reference.radiance).map(|(a, r)| delta_e2000_rgb(*a, *r)).collect()
}

fn compare_where(frame: &TracedFrame, reference: &TracedFrame, counted: impl Fn(Option<usize>) -> bool) -> FrameError {
    let mut error = FrameError::default();
    let (mut relative_sum, mut relative_count, mut absolute_sum, mut delta_e_sum) = (0.0, 0usize, 0.0, 0.0);
    for ((a, r), seen) in frame.radiance.iter().zip(&reference.radiance).zip(&reference.seen) {
        if !counted(*seen) {
            continue;
        }
        error.pixels += 1;
        for c in 0..3 {
            let absolute = (a[c] - r[c]).abs();
            absolute_sum += absolute;
            error.max_absolute = error.max_absolute.max(absolute);
            match relative_error(a[c], r[c]) {
                Some(relative) => {
                    relative_sum += relative;
                    relative_count += 1;
                    error.max_relative = error.max_relative.max(relative);
                }
                None => error.skipped_zero_reference += 1,
            }
        }
        delta_e_sum += delta_e2000_rgb(*a, *r);
    }
    let mean = |sum: f64, count: usize| if count > 0 { sum / count as f64 } else { 0.0 };
    error.mean_relative = (relative_count > 0).then(|| relative_sum / relative_count as f64);
    error.relative_samples = relative_count;
    error.mean_absolute = mean(absolute_sum, 3 * error.pixels);
    error.mean_delta_e2000 = mean(delta_e_sum, error.pixels);
    error
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(radiance: Vec<[f64; 3]>, seen: Vec<Option<usize>>) -> TracedFrame {
        TracedFrame { width: radiance.len() as u32, height: 1, radiance, seen, rays: 0 }
    }

    #[test]
    fn errors_count_only_specular_pixels_and_skip_zero_references() {
        let seen = vec![Some(0), Some(1), None];
        let reference = frame(vec![[0.5, 0.0, 0.25], [1.0, 1.0, 1.0], [0.2, 0.2, 0.2]], seen.clone());
        let rendered = frame(vec![[0.55, 0.1, 0.25], [1.0, 1.0, 1.0], [0.9, 0.9, 0.9]], seen);
        let e = compare(&rendered, &reference);
        assert_eq!((e.pixels, e.skipped_zero_reference), (2, 1));
        // Relative: 0.05/0.5 = 0.1, then 0, 0, 0, 0 over five channels.
        assert!((e.mean_relative.unwrap() - 0.1 / 5.0).abs() < 1e-15 && (e.max_relative - 0.1).abs() < 1e-12);
        assert_eq!(e.relative_samples, 5);
        assert!((e.mean_absolute - 0.15 / 6.0).abs() < 1e-15 && (e.max_absolute - 0.1).abs() < 1e-15);
        assert!(e.mean_delta_e2000 > 0.0);
        assert_eq!(compare(&reference, &reference).mean_delta_e2000, 0.0);
        let second = compare_object(&rendered, &reference, 1);
        assert_eq!((second.pixels, second.mean_absolute, second.mean_relative), (1, 0.0, Some(0.0)));
        // A black reference leaves no relative error to take a mean of: none, not 0.
        let black = frame(vec![[0.0; 3]], vec![Some(0)]);
        let lit = frame(vec![[0.1; 3]], vec![Some(0)]);
        let none = compare(&lit, &black);
        assert_eq!((none.pixels, none.mean_relative, none.skipped_zero_reference), (1, None, 3));
        assert_eq!(
            (relative_error(0.5, 0.0), relative_error(0.5, -1.0), relative_error(0.6, 0.5).map(|e| (e * 1e12).round())),
            (None, None, Some(2e11))
        );
    }
}

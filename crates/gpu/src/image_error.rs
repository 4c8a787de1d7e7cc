//! Image error (SPEC §6): per pixel and channel |a − r| / r between a method's render `a`
//! and the `exact` render `r`, over the pixels the object covers (reference alpha = 1; the
//! clear colour has alpha 0), skipping (and counting) the samples without one, by the rule
//! of the CPU tracers' image error (`nklut_effects::image_error::relative_error`: r ≤ 0);
//! mean per frame, then mean over frames, none where no frame has a sample. Pure CPU over
//! RGBA f32 images.

use nklut_effects::image_error::relative_error;

/// The comparison of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameErrorSums {
    pub sum_relative: f64,
    /// Channel samples with r > 0.
    pub samples: u64,
    pub max_relative: f64,
    /// Pixels the object covers.
    pub pixels: u64,
    /// Channel samples with r ≤ 0 (relative error undefined).
    pub skipped_zero_reference: u64,
}

impl FrameErrorSums {
    pub fn mean(&self) -> Option<f64> {
        (self.samples > 0).then(|| self.sum_relative / self.samples as f64)
    }
}

/// Compare two RGBA images of the same size (row-major, 4 f32 per pixel).
pub fn compare(method: &[f32], reference: &[f32]) -> FrameErrorSums {
    assert_eq!(method.len(), reference.len(), "images of different sizes");
    let mut error = FrameErrorSums::default();
    for (a, r) in method.chunks_exact(4).zip(reference.chunks_exact(4)) {
        if r[3] < 0.5 {
            continue;
        }
        error.pixels += 1;
        for channel in 0..3 {
            let Some(relative) = relative_error(a[channel] as f64, r[channel] as f64) else {
                error.skipped_zero_reference += 1;
                continue;
            };
            error.sum_relative += relative;
            error.samples += 1;
            error.max_relative = error.max_relative.max(relative);
        }
    }
    error
}

/// Frames of one (object, material, method).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSummary {
    pub frames: u32,
    sum_of_frame_means: f64,
    frames_with_samples: u32,
    pub max_relative: f64,
    pub pixels: u64,
    pub skipped_zero_reference: u64,
}

impl ErrorSummary {
    pub fn add(&mut self, frame: &FrameErrorSums) {
        self.frames += 1;
        if let Some(mean) = frame.mean() {
            self.sum_of_frame_means += mean;
            self.frames_with_samples += 1;
        }
        self.max_relative = self.max_relative.max(frame.max_relative);
        self.pixels += frame.pixels;
        self.skipped_zero_reference += frame.skipped_zero_reference;
    }

    /// Mean over frames of the per-frame mean relative error (frames where the object
    /// covers no pixel with r > 0 do not count); `None` when there is none.
    pub fn mean_relative(&self) -> Option<f64> {
        (self.frames_with_samples > 0).then(|| self.sum_of_frame_means / self.frames_with_samples as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_covered_pixels_count_and_zero_references_are_skipped() {
        let reference = [0.5, 0.25, 0.0, 1.0, /* background */ 9.0, 9.0, 9.0, 0.0];
        let method = [0.55, 0.25, 0.1, 1.0, 0.0, 0.0, 0.0, 0.0];
        let e = compare(&method, &reference);
        assert_eq!(e.pixels, 1);
        assert_eq!(e.samples, 2);
        assert_eq!(e.skipped_zero_reference, 1);
        assert!((e.mean().unwrap() - 0.05).abs() < 1e-7);
        assert!((e.max_relative - 0.1).abs() < 1e-6);
        let mut summary = ErrorSummary::default();
        summary.add(&e);
        summary.add(&compare(&reference, &reference));
        assert_eq!(summary.frames, 2);
        assert!((summary.mean_relative().unwrap() - 0.025).abs() < 1e-7);
        assert_eq!(ErrorSummary::default().mean_relative(), None);
        assert_eq!(summary.pixels, 2);
    }
}

//! The tables of the GPU runner's Fresnel measurements (`nklut gpu run`, and the browser
//! bench's page): each table's columns, written by `nklut-gpu` (and followed by the page's
//! result) and read by the report, the recommendations and the device checks through these
//! constants, so that writer and readers cannot disagree on a column's name, description or
//! kind. A table written before a column existed reads that column's cells as absent.

/// `gpu_timing.*`: the pass time of each Fresnel method and baseline, one row per timed (material, method).
pub mod gpu_timing {
    use crate::columns::*;

    crate::table_files!("gpu_timing");

    crate::table_columns! {
        ADAPTER: Text = Column::new("adapter", "adapter name as the driver reports it");
        BACKEND: Text = Column::new("backend", "wgpu backend");
        DRIVER: Text = Column::new("driver", "driver name and version");
        TIMER: Text = Column::new("timer", "timestamp (GPU timestamp queries around the pass) or wall (CPU time around submit-and-wait)");
        METHOD: Text = Column::new("method", "Fresnel method (SPEC §5) or baseline (constant, texture)");
        FORMULA: Text = Column::new("formula", "for exact: dielectric (k = 0) on a dielectric material, complex on a conductor (the study's anchors); else empty");
        MATERIAL: Text = Column::new("material", "page id");
        RESOLUTION: Text = Column::new("resolution", "fullscreen pass size WxH in pixels");
        EVALUATIONS: Integer = Column::new("evaluations", "F evaluations per pixel in each timed pass (chosen at warm-up so a sample spans >= 100 x the timer's resolution)");
        TIMER_RESOLUTION_NS: Float = Column::new("timer_resolution_ns", "the timer's resolution estimated from its readings (ns)");
        SEED: Text = Column::new("seed", "seed of the order of the (material, method) pairs in each round");
        REPEATS: Integer = Column::new("repeats", "timed samples kept (after warm-up)");
        MEAN_MS: Float = Column::new("mean_ms", "mean pass time (ms)");
        MEDIAN_MS: Float = Column::new("median_ms", "median pass time (ms)");
        SPREAD_MS: Float = Column::new("spread_ms", "interquartile range of the pass times (ms)");
        NS_PER_EVALUATION: Float = Column::new("ns_per_evaluation", "median pass time per F evaluation per pixel (ns)");
        RELATIVE_TO_EXACT: OptionalFloat = Column::new("relative_to_exact", "median_ms / median_ms of exact on the same material");
        RELATIVE_TO_FETCH: OptionalFloat = Column::new("relative_to_fetch", "median_ms / median_ms of the bare texture fetch (texture) on the same material");
        RELATIVE_TO_EXACT_DIELECTRIC: OptionalFloat = Column::new("relative_to_exact_dielectric", "median_ms / median_ms of exact on the first dielectric material timed (the study's normalisation); empty when the scene times none");
        NEAR_RESOLUTION: Text = Column::new("near_resolution", "yes when the median is within 10 x the timer's resolution or 2 x the wall timer's floor: not resolved");
        SAMPLES_MS: Text = Column::new("samples_ms", "every timed sample (ms), space-separated, in the order taken");
    }
}

/// `image_errors.*`: each method's rendered image against the exact method's, one row per (object, material, method).
pub mod image_errors {
    use crate::columns::*;

    crate::table_files!("image_errors");

    crate::table_columns! {
        MATERIAL: Text = Column::new("material", "page id");
        METHOD: Text = Column::new("method", "Fresnel method (SPEC §5) or baseline");
        OBJECT: Text = Column::new("object", "mesh: cube, sphere or the OBJ file stem");
        FRAMES: Integer = Column::new("frames", "frames of the camera orbit");
        RESOLUTION: Text = Column::new("resolution", "render target WxH in pixels");
        MEAN_REL_ERROR: OptionalFloat = Column::new("mean_rel_error", "mean over frames of the mean over covered pixels and channels of |a - r| / r (r = exact render; r <= 0 skipped); empty where no sample had r > 0");
        MAX_REL_ERROR: Float = Column::new("max_rel_error", "largest |a - r| / r of any covered pixel and channel");
        PIXELS: Integer = Column::new("pixels", "covered pixels summed over frames");
        SKIPPED_ZERO_REFERENCE: Integer = Column::new("skipped_zero_reference", "covered pixel channels with r = 0, left out of the error");
    }
}

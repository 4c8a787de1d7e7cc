//! The tables of the effects (`nklut effects`, and `nklut gpu` on an effects scene): each
//! table's columns, written by `nklut-effects` and `nklut-gpu` and read by the pipeline's
//! effects report through these constants alone, so that writer and reader cannot disagree
//! on a column's name, description or kind. `STEM` is each table's file name without its
//! extension (`<stem>.csv`, `.json`, `.parquet`), `CSV` its CSV file's name. A table written before a column existed
//! reads that column's cells as absent (`crate::columns::Kind::read`).

/// The columns that name a distance-map configuration, shared by `effects_errors`, `effects_cpu_timing` and `effects_timing`.
pub mod configuration {
    use crate::columns::*;

    crate::table_columns! {
        REFLECTION_DEPTH: Integer = Column::new("reflection_depth", "most reflections along a path (0: not named)");
        REFRACTION_DEPTH: Integer = Column::new("refraction_depth", "most refractions along a path (0: not named)");
        LINEAR_STEPS: Integer = Column::new("linear_steps", "linear search steps per layer");
        SECANT_STEPS: Integer = Column::new("secant_steps", "secant refinements after the linear search");
        MAP_SIZE: Integer = Column::new("map_size", "distance-map texels per cube face edge");
        LAYERS: Integer = Column::new("layers", "distance-map layers (all but the last: peeled specular surfaces; last: diffuse)");
    }
}

/// `effects_errors.*` (`nklut effects`): the image error of multiple reflections and refractions, one row per (object, material, method, depths, search steps).
pub mod effects_errors {
    use super::configuration;
    use crate::columns::*;

    crate::table_files!("effects_errors");

    crate::table_columns! {
        OBJECT: Text = Column::new("object", "mesh of the specular object: sphere, room, plane or the OBJ file stem");
        MATERIAL: Text = Column::new("material", "page id");
        METHOD: Text = Column::new("method", "Fresnel method of every bounce");
        RENDERER: Text = Column::new("renderer", "what traced the distance maps: cpu-twin (the f64 CPU twin of the GPU algorithm) or gpu (the GPU passes)");
        REFLECTION_DEPTH: Integer = configuration::REFLECTION_DEPTH;
        REFRACTION_DEPTH: Integer = configuration::REFRACTION_DEPTH;
        LINEAR_STEPS: Integer = configuration::LINEAR_STEPS;
        SECANT_STEPS: Integer = configuration::SECANT_STEPS;
        MAP_SIZE: Integer = configuration::MAP_SIZE;
        LAYERS: Integer = configuration::LAYERS;
        FRAMES: Integer = Column::new("frames", "camera frames rendered");
        RESOLUTION: Text = Column::new("resolution", "frame size WxH in pixels");
        PIXELS: Integer = Column::new("pixels", "pixels showing the object, summed over frames");
        GEOMETRY_MEAN_REL_ERROR: OptionalFloat = Column::new("geometry_mean_rel_error", "distance maps with exact Fresnel vs the reference: mean |a - r| / r over the object's pixels and channels (r = 0 skipped)");
        GEOMETRY_MEAN_DELTA_E2000: Float = Column::new("geometry_mean_delta_e2000", "distance maps with exact Fresnel vs the reference: mean CIEDE2000 of the colours");
        FRESNEL_MEAN_REL_ERROR: OptionalFloat = Column::new("fresnel_mean_rel_error", "the method vs exact Fresnel on the same distance-map paths: mean |a - r| / r");
        FRESNEL_MEAN_DELTA_E2000: Float = Column::new("fresnel_mean_delta_e2000", "the method vs exact Fresnel on the same distance-map paths: mean CIEDE2000");
        TOTAL_MEAN_REL_ERROR: OptionalFloat = Column::new("total_mean_rel_error", "distance maps with the method vs the reference: mean |a - r| / r");
        TOTAL_MEAN_DELTA_E2000: Float = Column::new("total_mean_delta_e2000", "distance maps with the method vs the reference: mean CIEDE2000");
        TOTAL_MEAN_ABS_ERROR: Float = Column::new("total_mean_abs_error", "distance maps with the method vs the reference: mean |a - r| (linear radiance)");
    }
}

/// `effects_cpu_timing.*` (`nklut effects`): the CPU twin's frame time, one row per (method, depths, search steps).
pub mod effects_cpu_timing {
    use super::configuration;
    use crate::columns::*;

    crate::table_files!("effects_cpu_timing");

    crate::table_columns! {
        RENDERER: Text = Column::new("renderer", "what traced the distance-map frames (cpu-twin: the f64 CPU twin)");
        METHOD: Text = Column::new("method", "Fresnel method of every bounce");
        REFLECTION_DEPTH: Integer = configuration::REFLECTION_DEPTH;
        REFRACTION_DEPTH: Integer = configuration::REFRACTION_DEPTH;
        LINEAR_STEPS: Integer = configuration::LINEAR_STEPS;
        SECANT_STEPS: Integer = configuration::SECANT_STEPS;
        MAP_SIZE: Integer = configuration::MAP_SIZE;
        LAYERS: Integer = configuration::LAYERS;
        FRAMES: Integer = Column::new("frames", "camera frames timed");
        RESOLUTION: Text = Column::new("resolution", "frame size WxH in pixels");
        FRAME_MS: Float = Column::new("frame_ms", "median wall time of one frame through the distance maps (on the CPU: a ratio to reference_ms carries to another machine, the figure itself does not)");
        REFERENCE_MS: Float = Column::new("reference_ms", "median wall time of the f64 reference tracer's frame of the same configuration (the anchor)");
        RATIO_TO_REFERENCE: Float = Column::new("ratio_to_reference", "frame_ms / reference_ms");
    }
}

/// `effects_timing.*` (`nklut gpu`): GPU time of the distance-map update and the shading pass, one row per (method, depths, search steps).
pub mod effects_timing {
    use super::configuration;
    use crate::columns::*;

    crate::table_files!("effects_timing");

    crate::table_columns! {
        ADAPTER: Text = Column::new("adapter", "adapter name as the driver reports it");
        BACKEND: Text = Column::new("backend", "wgpu backend");
        TIMER: Text = Column::new("timer", "timestamp (GPU timestamp queries around the pass) or wall (CPU time around submit-and-wait)");
        METHOD: Text = Column::new("method", "Fresnel method of every bounce");
        EFFECT: Text = Column::new("effect", "shading pipeline: reflection (refraction compiled out) or refraction (both)");
        REFLECTION_DEPTH: Integer = configuration::REFLECTION_DEPTH;
        REFRACTION_DEPTH: Integer = configuration::REFRACTION_DEPTH;
        LINEAR_STEPS: Integer = configuration::LINEAR_STEPS;
        SECANT_STEPS: Integer = configuration::SECANT_STEPS;
        MAP_SIZE: Integer = configuration::MAP_SIZE;
        LAYERS: Integer = configuration::LAYERS;
        CUBE_MAPS: Integer = Column::new("cube_maps", "distance maps updated per frame (one per specular object)");
        RESOLUTION: Text = Column::new("resolution", "shading target WxH in pixels");
        REPEATS: Integer = Column::new("repeats", "timed passes of each kind (after warm-up)");
        MAP_UPDATE_MS: Float = Column::new("map_update_ms", "median time of one update of every distance map (6 faces × layers render passes per map)");
        SHADING_MS: Float = Column::new("shading_ms", "median time of the shading pass (rasterise + bounce loop)");
        SHADING_SPREAD_MS: Float = Column::new("shading_spread_ms", "interquartile range of the shading pass times");
        FRAME_MS: Float = Column::new("frame_ms", "map_update_ms + shading_ms: a frame whose objects move");
    }
}

/// `effects_hero.*` (`nklut effects`): the hero frame's panels, their files and figures.
pub mod effects_hero {
    use crate::columns::*;

    crate::table_files!("effects_hero");

    crate::table_columns! {
        EFFECT: Text = Column::new("effect", "the family of effects: reflections and refractions, or ambient occlusion");
        PANEL: Text = Column::new("panel", "the panel's stem: reference, a Fresnel method, or an AO variant (none, passesN_tree, passesN_brute_force)");
        LABEL: Text = Column::new("label", "what the panel shows, in words");
        METHOD: Text = Column::new("method", "Fresnel method or AO variant (reference for the reference)");
        REFLECTION_DEPTH: OptionalFloat = Column::new("reflection_depth", "most reflections along a path (distance-map panels)");
        REFRACTION_DEPTH: OptionalFloat = Column::new("refraction_depth", "most refractions along a path (distance-map panels)");
        LINEAR_STEPS: OptionalFloat = Column::new("linear_steps", "linear search steps per layer (distance-map panels)");
        SECANT_STEPS: OptionalFloat = Column::new("secant_steps", "secant refinements (distance-map panels)");
        PASSES: OptionalFloat = Column::new("passes", "accessibility passes (AO panels; 0: no AO)");
        RESOLUTION: Text = Column::new("resolution", "frame size WxH in pixels");
        FILE: Text = Column::new("file", "the panel, sRGB PNG, relative to the scene's output folder");
        ERROR_FILE: Text = Column::new("error_file", "false colour of |panel - reference| summed over R, G, B (empty for the reference)");
        CROP_X: Integer = Column::new("crop_x", "left edge of the crop window (pixels)");
        CROP_Y: Integer = Column::new("crop_y", "top edge of the crop window (pixels)");
        CROP_SIZE: Integer = Column::new("crop_size", "side of the square crop window (pixels): where the largest error sits");
        CROP_FILE: Text = Column::new("crop_file", "the panel inside the crop window");
        CROP_ERROR_FILE: Text = Column::new("crop_error_file", "the error image inside the crop window");
        PIXELS: Integer = Column::new("pixels", "pixels the figures are taken over (reflections and refractions: where the reference shows a specular object; AO: every pixel)");
        MEAN_ABS_ERROR: Float = Column::new("mean_abs_error", "mean |panel - reference| over those pixels and the three channels (linear radiance)");
        MAX_ABS_ERROR: Float = Column::new("max_abs_error", "largest |panel - reference| over those pixels and channels");
        MEAN_DELTA_E2000: Float = Column::new("mean_delta_e2000", "mean CIEDE2000 of panel against reference over those pixels");
        MEAN_REL_ERROR: OptionalFloat = Column::new("mean_rel_error", "mean |a - r| / r over the channel samples with r > 0");
        ERROR_SCALE: Float = Column::new("error_scale", "|Δ| summed over R, G, B at which the error image turns white (the colour bar's right end): reflections and refractions the 1-2-5 step at or above the 99th percentile over the set's panels and counted pixels, ambient occlusion fixed");
        ERROR_SCALE_FILE: Text = Column::new("error_scale_file", "the error image's legend: colour bar with its values");
        EXACT_ERROR_FILE: Text = Column::new("exact_error_file", "false colour of |panel - exact method's panel| summed over R, G, B: the Fresnel method's own error through the same maps (empty where none)");
        CROP_EXACT_ERROR_FILE: Text = Column::new("crop_exact_error_file", "that error image inside the crop window");
        EXACT_MEAN_DELTA_E2000: OptionalFloat = Column::new("exact_mean_delta_e2000", "mean CIEDE2000 of panel against the exact method's panel over the same pixels");
        EXACT_MEAN_ABS_ERROR: OptionalFloat = Column::new("exact_mean_abs_error", "mean |panel - exact method's panel| over those pixels and channels");
        EXACT_MAX_ABS_ERROR: OptionalFloat = Column::new("exact_max_abs_error", "largest |panel - exact method's panel| over those pixels and channels");
        EXACT_ERROR_SCALE: OptionalFloat = Column::new("exact_error_scale", "|Δ| at which the against-exact image turns white (the same rule over the set's against-exact images)");
        EXACT_ERROR_SCALE_FILE: Text = Column::new("exact_error_scale_file", "the against-exact image's legend");
    }
}

/// `spectral_errors.*` (`nklut effects` on a scene with `effects.spectral`): three channels against the spectral reference, one row per (object, material, index source, depths).
pub mod spectral_errors {
    use super::configuration;
    use crate::columns::*;

    crate::table_files!("spectral_errors");

    crate::table_columns! {
        OBJECT: Text = Column::new("object", "mesh of the specular object: sphere, cube, prism, room, plane or the OBJ file stem");
        OBJECT_INDEX: Integer = Column::new("object_index", "the object's position in the scene's objects list, from 0");
        MATERIAL: Text = Column::new("material", "page id");
        INDEX_SOURCE: Text = Column::new("index_source", "where the three-channel frame's (n, k) come from: three-wavelength (at the channel wavelengths), effective (colors' fit over angle to the spectral reference; attenuation keeps the three-wavelength k) or engine (conductors as F82-tint curves from the three-wavelength index, dielectrics as one IOR, the green channel's n, absorption kept)");
        REFLECTION_DEPTH: Integer = configuration::REFLECTION_DEPTH;
        REFRACTION_DEPTH: Integer = configuration::REFRACTION_DEPTH;
        WAVELENGTHS: Integer = Column::new("wavelengths", "wavelength bins of the spectral frame (421: every 1 nm of 360-780 nm, colors' sum)");
        RESOLUTION: Text = Column::new("resolution", "frame size WxH in pixels (camera frame 0)");
        PIXELS: Integer = Column::new("pixels", "pixels where the spectral frame shows the object");
        MEAN_DELTA_E2000: Float = Column::new("mean_delta_e2000", "three-channel reference vs spectral reference: mean CIEDE2000 over the object's pixels");
        P95_DELTA_E2000: Float = Column::new("p95_delta_e2000", "95th percentile (linear interpolation) of the CIEDE2000 over the object's pixels");
        MAX_DELTA_E2000: Float = Column::new("max_delta_e2000", "largest CIEDE2000 over the object's pixels");
        SPECTRAL_MS: Float = Column::new("spectral_ms", "wall time of the spectral reference's frame (all objects)");
        THREE_CHANNEL_MS: Float = Column::new("three_channel_ms", "wall time of the three-channel reference's frame with this index source");
        SPECTRAL_WAVELENGTH_RAYS_PER_S: Float = Column::new("spectral_wavelength_rays_per_s", "wavelength-rays (one ray at one wavelength; a ray carrying a bundle counts each) per second of the spectral frame");
        THREE_CHANNEL_RAYS_PER_S: Float = Column::new("three_channel_rays_per_s", "rays per second of the three-channel frame");
        TOTAL_INTERNAL_REFLECTIONS: Integer = Column::new("total_internal_reflections", "total internal reflections in the spectral frame, counted per wavelength (all objects)");
    }
}

/// `ao_errors.*` (`nklut effects`): ambient-occlusion and indirect-light error, one row per (mesh, technique, passes); the GTAO rows' preset and heuristics last.
pub mod ao_errors {
    use crate::columns::*;

    crate::table_files!("ao_errors");

    crate::table_columns! {
        MESH: Text = Column::new("mesh", "mesh name");
        TECHNIQUE: Text = Column::new("technique", "surfels (surfel AO, Bunnell) or gtao (screen-space ground-truth AO, Jimenez et al. 2016: per pixel only)");
        SURFELS: Integer = Column::new("surfels", "surfels (mesh vertices)");
        RECEIVER_GAIN: OptionalFloat = Column::new("receiver_gain", "g of the shadow form: 1 the disc form factor, 4 its receiver cosine x 4 clamped to 1 (a variant); empty for gtao");
        PASSES: Integer = Column::new("passes", "accessibility passes (gtao: 0, one screen-space pass per frame)");
        HIERARCHY: Boolean = Column::new("hierarchy", "emitters from the surfel tree (true) or every surfel (false); false for gtao");
        GTAO_RADIUS: OptionalFloat = Column::new("gtao_radius", "gtao: occluders within this distance count (scene units)");
        GTAO_SLICES: OptionalFloat = Column::new("gtao_slices", "gtao: slice directions per pixel");
        GTAO_STEPS: OptionalFloat = Column::new("gtao_steps", "gtao: G-buffer samples per side of a slice");
        MEAN_ERROR: OptionalFloat = Column::new("mean_error", "mean over vertices of |e|, e = accessibility - ray-traced reference (empty for gtao: no per-vertex values)");
        SIGNED_ERROR: OptionalFloat = Column::new("signed_error", "mean over vertices of e (positive: the surfels under-occlude)");
        MEDIAN_ERROR: OptionalFloat = Column::new("median_error", "median over vertices of |e|");
        P90_ERROR: OptionalFloat = Column::new("p90_error", "90th percentile over vertices of |e|");
        P99_ERROR: OptionalFloat = Column::new("p99_error", "99th percentile over vertices of |e|");
        MAX_ERROR: OptionalFloat = Column::new("max_error", "largest |e| over vertices");
        AREA_MEAN_ERROR: OptionalFloat = Column::new("area_mean_error", "mean of |e| weighted by the vertices' areas (a third of each adjacent triangle)");
        AREA_SIGNED_ERROR: OptionalFloat = Column::new("area_signed_error", "area-weighted mean of e");
        AREA_MEDIAN_ERROR: OptionalFloat = Column::new("area_median_error", "area-weighted median of |e|");
        AREA_P90_ERROR: OptionalFloat = Column::new("area_p90_error", "area-weighted 90th percentile of |e|");
        AREA_P99_ERROR: OptionalFloat = Column::new("area_p99_error", "area-weighted 99th percentile of |e|");
        AREA_MAX_ERROR: OptionalFloat = Column::new("area_max_error", "largest |e| over vertices of positive area");
        PIXELS: Integer = Column::new("pixels", "pixels of the picture where the object is the nearest surface (0: no picture measured)");
        PIXEL_MEAN_ERROR: OptionalFloat = Column::new("pixel_mean_error", "mean over those pixels of |e|, accessibility and reference interpolated from the vertices");
        PIXEL_SIGNED_ERROR: OptionalFloat = Column::new("pixel_signed_error", "mean over those pixels of e");
        PIXEL_MEDIAN_ERROR: OptionalFloat = Column::new("pixel_median_error", "median over those pixels of |e|");
        PIXEL_P90_ERROR: OptionalFloat = Column::new("pixel_p90_error", "90th percentile over those pixels of |e|");
        PIXEL_P99_ERROR: OptionalFloat = Column::new("pixel_p99_error", "99th percentile over those pixels of |e|");
        PIXEL_MAX_ERROR: OptionalFloat = Column::new("pixel_max_error", "largest |e| over those pixels");
        DEFECT_VERTICES: Integer = Column::new("defect_vertices", "vertices of flipped or degenerate triangles (their error is the mesh's; counted in the columns above)");
        MEAN_ERROR_WITHOUT_DEFECTS: OptionalFloat = Column::new("mean_error_without_defects", "mean over vertices of |e| leaving out the defect vertices");
        MAX_ERROR_WITHOUT_DEFECTS: OptionalFloat = Column::new("max_error_without_defects", "largest |e| over vertices leaving out the defect vertices");
        REFERENCE_STANDARD_ERROR: Float = Column::new("reference_standard_error", "mean standard error of the reference's per-vertex estimates (bounds its noise's effect on mean_error)");
        BENT_NORMAL_MEAN_ANGLE: OptionalFloat = Column::new("bent_normal_mean_angle", "mean over vertices of the angle (degrees) between the surfel bent normal and the ray-traced one (mean unoccluded direction); empty where the scene asks for no bent normals");
        BENT_NORMAL_MEDIAN_ANGLE: OptionalFloat = Column::new("bent_normal_median_angle", "median of that angle (degrees)");
        BENT_NORMAL_P90_ANGLE: OptionalFloat = Column::new("bent_normal_p90_angle", "90th percentile of that angle (degrees)");
        NORMAL_MEAN_ANGLE: OptionalFloat = Column::new("normal_mean_angle", "mean over vertices of the angle (degrees) between the plain normal and the ray-traced bent normal (what bending has to correct)");
        INTERACTIONS: Integer = Column::new("interactions", "emitter evaluations of all passes so far, whole scene (gtao: G-buffer reads of the frame, pixels x slices x 2 x steps); the cost in operations, machine-independent");
        CPU_MS: Float = Column::new("cpu_ms", "wall time of all passes so far on the CPU, whole scene (gtao: the frame), in ms (a ratio between rows carries to another machine, the figure does not)");
        INDIRECT_MEAN_ERROR: OptionalFloat = Column::new("indirect_mean_error", "indirect light, one bounce with emitters weighted 1: mean over vertices and channels of |surfels - ray-traced| (units of the scene's light); empty when the scene asks for no indirect light");
        INDIRECT_SIGNED_ERROR: OptionalFloat = Column::new("indirect_signed_error", "mean over vertices and channels of surfels - ray-traced, emitters weighted 1 (negative: too little bounce light)");
        INDIRECT_ACCESSIBILITY_WEIGHTED_MEAN_ERROR: OptionalFloat = Column::new("indirect_accessibility_weighted_mean_error", "as indirect_mean_error with each emitter weighted by this row's accessibility (the chapter's modulation)");
        INDIRECT_ACCESSIBILITY_WEIGHTED_SIGNED_ERROR: OptionalFloat = Column::new("indirect_accessibility_weighted_signed_error", "as indirect_signed_error with each emitter weighted by this row's accessibility");
        INDIRECT_REFERENCE_MEAN: OptionalFloat = Column::new("indirect_reference_mean", "mean of the ray-traced one-bounce irradiance over the same vertices and channels");
        PIXEL_MEAN_ERROR_WITHIN_RADIUS: OptionalFloat = Column::new("pixel_mean_error_within_radius", "gtao: mean over the covered pixels of |e| against a reference that counts occluders within the radius only (what the screen space misses, the radius's cut aside)");
        PIXEL_SIGNED_ERROR_WITHIN_RADIUS: OptionalFloat = Column::new("pixel_signed_error_within_radius", "gtao: mean over the covered pixels of e against that range-limited reference");
        INDIRECT_REFERENCE_STANDARD_ERROR: OptionalFloat = Column::new("indirect_reference_standard_error", "mean standard error of the ray-traced one-bounce irradiance");
        PIXEL_P90_ERROR_WITHIN_RADIUS: OptionalFloat = Column::new("pixel_p90_error_within_radius", "gtao: 90th percentile over the covered pixels of |e| against the range-limited reference");
        PIXEL_P99_ERROR_WITHIN_RADIUS: OptionalFloat = Column::new("pixel_p99_error_within_radius", "gtao: 99th percentile over the covered pixels of |e| against the range-limited reference");
        GTAO_PRESET: Text = Column::new("gtao_preset", "gtao: the named configuration (bare: Algorithm 1 of Jimenez et al. 2016; xe-low/medium/high/ultra: XeGTAO's quality levels and default heuristics; unreal: Unreal's r.GTAO defaults), with (modified) where the scene overrode a heuristic; empty for surfels");
        GTAO_RADIUS_MULTIPLIER: OptionalFloat = Column::new("gtao_radius_multiplier", "gtao: the search radius is gtao_radius x this (XeGTAO 1.457)");
        GTAO_FALLOFF_RANGE: OptionalFloat = Column::new("gtao_falloff_range", "gtao: fraction of the search radius over which a sample's weight falls to 0 (0: hard cut; XeGTAO 0.615)");
        GTAO_DISTRIBUTION_POWER: OptionalFloat = Column::new("gtao_distribution_power", "gtao: sample k at ((k + offset)/steps)^power of the screen radius (XeGTAO 2)");
        GTAO_THIN_OCCLUDER: OptionalFloat = Column::new("gtao_thin_occluder", "gtao: thin-occluder compensation, depth offsets x (1 + this) for the falloff (XeGTAO default 0)");
        GTAO_THICKNESS_BLEND: OptionalFloat = Column::new("gtao_thickness_blend", "gtao: a sample below the horizon pulls it toward itself by this squared (Unreal r.GTAO.ThicknessBlend 0.5; 0: the highest sample)");
        GTAO_FINAL_POWER: OptionalFloat = Column::new("gtao_final_power", "gtao: accessibility raised to this power (XeGTAO 2.2)");
        GTAO_CLAMP_TO_EDGE: OptionalFloat = Column::new("gtao_clamp_to_edge", "gtao: 1 where a sample beyond the image's edge reads the edge texel's depth (XeGTAO's clamping sampler), 0 where it is skipped");
        GTAO_DENOISE_PASSES: OptionalFloat = Column::new("gtao_denoise_passes", "gtao: passes of XeGTAO's edge-aware 3x3 denoiser over the image (0: none; XeGTAO 1)");
        GTAO_FRAMES: OptionalFloat = Column::new("gtao_frames", "gtao: frames of per-pixel noise accumulated (1: no noise)");
    }
}

/// `ao_histogram.*` (`nklut effects`): the signed ambient-occlusion error binned, one row per (mesh, technique, passes, weighting, bin).
pub mod ao_histogram {
    use crate::columns::*;

    crate::table_files!("ao_histogram");

    crate::table_columns! {
        MESH: Text = Column::new("mesh", "mesh name");
        TECHNIQUE: Text = Column::new("technique", "how accessibility was computed: surfel AO gathering every emitter (brute force) or through the surfel tree (tree)");
        PASSES: Integer = Column::new("passes", "accessibility passes");
        WEIGHTING: Text = Column::new("weighting", "what is counted: vertex (each vertex 1), area (each vertex its area, a third of each adjacent triangle) or pixel (each pixel of the picture where the object is the nearest surface)");
        BIN: Integer = Column::new("bin", "bin index, 0 at the most negative error");
        LOWER: Float = Column::new("lower", "the bin's lower edge of e = accessibility - ray-traced reference (the first bin also holds every e below it)");
        UPPER: Float = Column::new("upper", "the bin's upper edge, excluded (the last bin also holds every e at or above it)");
        COUNT: Integer = Column::new("count", "vertices or pixels in the bin");
        WEIGHT: Float = Column::new("weight", "their summed weight (the count for vertex and pixel, the summed area for area)");
        SHARE: Float = Column::new("share", "the bin's weight over the histogram's total weight (0 where the total is 0)");
    }
}

/// `ao_timing.*` (`nklut gpu`): ambient-occlusion GPU time, one row per (mesh, way of gathering) and per GTAO configuration.
pub mod ao_timing {
    use crate::columns::*;

    crate::table_files!("ao_timing");

    crate::table_columns! {
        ADAPTER: Text = Column::new("adapter", "adapter name as the driver reports it");
        DRIVER: Text = Column::new("driver", "driver name and version");
        MESH: Text = Column::new("mesh", "mesh of the sweep: name, then decimated (vertex-clustering cell edge) or subdivided (levels)");
        SURFELS: Integer = Column::new("surfels", "surfels (mesh vertices)");
        EMITTERS: Text = Column::new("emitters", "brute_force (every surfel), hierarchy (the surfel tree's cut, kappa = 16), or gtao (screen-space, per pixel: no emitters)");
        TREE_NODES: Integer = Column::new("tree_nodes", "nodes of the surfel tree uploaded (0 for brute force)");
        PASSES: Integer = Column::new("passes", "accessibility passes per timed sample");
        DISPATCHES: Integer = Column::new("dispatches", "compute dispatches per timed sample");
        WIDTH: Integer = Column::new("width", "gtao: frame width in pixels (0 for the surfel pass, which is per vertex)");
        HEIGHT: Integer = Column::new("height", "gtao: frame height in pixels (0 for the surfel pass)");
        COVERED_PIXELS: Integer = Column::new("covered_pixels", "gtao: pixels that see a surface (0 for the surfel pass)");
        SLICES: Integer = Column::new("slices", "gtao: slices per pixel (0 for the surfel pass)");
        STEPS: Integer = Column::new("steps", "gtao: G-buffer samples per side of a slice (0 for the surfel pass)");
        PRESET: Text = Column::new("preset", "gtao: the configuration's preset (bare: Algorithm 1; xe-low, xe-medium, xe-high, xe-ultra: XeGTAO's), with (modified) where the scene overrode a heuristic; empty for the surfel pass");
        RADIUS: OptionalFloat = Column::new("radius", "gtao: search radius in scene units, before the preset's radius multiplier; empty for the surfel pass");
        FRAMES: Integer = Column::new("frames", "gtao: frames accumulated to convergence (per-pixel noise; 1 without noise); 0 for the surfel pass");
        TIMER: Text = Column::new("timer", "timestamp (GPU timestamp queries around the compute pass) or wall (CPU time around submit-and-wait)");
        REPEATS: Integer = Column::new("repeats", "timed samples (after warm-up)");
        MEDIAN_MS: Float = Column::new("median_ms", "median time of one sample (ms); gtao: one frame's dispatch and its denoiser passes");
        SPREAD_MS: Float = Column::new("spread_ms", "interquartile range of the samples (ms)");
        CONVERGENCE_MS: OptionalFloat = Column::new("convergence_ms", "gtao: time to convergence, median_ms (one frame) x frames; empty for the surfel pass (its median_ms is its whole cost)");
        FITTED_EXPONENT: OptionalFloat = Column::new("fitted_exponent", "p of time = c n^p, least squares of ln median_ms on ln surfels over every row of the same emitters; empty with fewer than two sizes");
    }
}

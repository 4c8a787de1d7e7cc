//! The `ao_errors` table: per mesh, receiver gain g, pass count and hierarchy on/off, the
//! accessibility error e = a − reference (positive: the surfels under-occlude) summarised
//! three ways by `nklut_tables::stats::ErrorSummary` (mean |e|, signed mean, median, p90,
//! p99, max |e|): per vertex, weighted by the vertices' areas (a third of the adjacent
//! triangles: what the surface holds), and per pixel of the picture the object covers (both
//! interpolated from the vertices: what the camera sees). Screen-space GTAO
//! (`super::gtao`) has rows of its own (`technique` gtao): per pixel only, against the same
//! interpolated reference on the same pixels. Vertices of flipped or degenerate
//! triangles (`super::surfel::mesh_defects`) are counted and the per-vertex error given
//! without them too. Beside them the reference's own mean standard error (how far its noise
//! can move the mean), and where the scene asks for indirect light, its error. Rows are
//! computed here from plain data; the table is written through `nklut_tables::output`
//! (CSV, Parquet, columns.json).

use super::accessibility::{accessibility_by_pass, BruteForce, Emitters};
use super::hierarchy::{Closeness, SurfelTree};
use super::reference::ReferenceAccessibility;
use super::shadow::ShadowForm;
use super::surfel::Surfel;
use nklut_tables::output::Table;
use nklut_tables::stats::ErrorSummary;

/// The accessibility error of one object, summarised per vertex, per area and per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct AccessibilityErrors {
    /// Every vertex weighted 1 (a zero summary of count 0 for an object with no vertex).
    pub per_vertex: ErrorSummary,
    /// Each vertex weighted by its surfel's area; `None` where every area is 0.
    pub area_weighted: Option<ErrorSummary>,
    /// Each pixel of the picture where the object is the nearest surface; `None` where no
    /// picture was measured or the object covers no pixel.
    pub per_pixel: Option<ErrorSummary>,
    /// Vertices of flipped or degenerate triangles.
    pub defect_vertices: usize,
    /// The per-vertex summary without those vertices (`None` when none is left).
    pub without_defects: Option<ErrorSummary>,
}

/// The angle (degrees) between the surfel bent normal and the ray-traced one (the mean
/// unoccluded direction), per vertex with any open ray, and the same for the plain normal:
/// what bending buys.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BentNormalErrors {
    pub surfel: ErrorSummary,
    pub normal: ErrorSummary,
}

/// Signed differences a − b.
pub fn signed_differences(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

impl AccessibilityErrors {
    /// The summaries of per-vertex errors `errors` (a − reference) with the vertices'
    /// `areas` and `defects` flags, and the per-pixel errors where measured.
    pub fn new(errors: &[f64], areas: &[f64], defects: &[bool], pixels: Option<&[f64]>) -> AccessibilityErrors {
        let kept: Vec<f64> = errors.iter().zip(defects).filter(|(_, &d)| !d).map(|(&e, _)| e).collect();
        AccessibilityErrors {
            per_vertex: ErrorSummary::of(errors).unwrap_or(ErrorSummary::NONE),
            area_weighted: ErrorSummary::weighted(errors, areas),
            per_pixel: pixels.and_then(ErrorSummary::of),
            defect_vertices: defects.iter().filter(|&&d| d).count(),
            without_defects: ErrorSummary::of(&kept),
        }
    }
}

/// How a row's accessibility was computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Technique {
    /// Surfel AO: the row's passes, hierarchy and receiver gain say how.
    Surfels,
    /// Screen-space GTAO with these parameters (one pass per frame, per pixel only).
    Gtao(crate::scene::surfels::Gtao),
}

impl Technique {
    /// The name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Technique::Surfels => "surfels",
            Technique::Gtao(_) => "gtao",
        }
    }

    fn gtao(self) -> Option<crate::scene::surfels::Gtao> {
        match self {
            Technique::Surfels => None,
            Technique::Gtao(g) => Some(g),
        }
    }
}

/// One configuration's error against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    pub mesh: String,
    pub technique: Technique,
    pub surfels: usize,
    pub receiver_gain: f64,
    pub passes: u32,
    pub hierarchy: bool,
    pub accessibility: AccessibilityErrors,
    pub reference_standard_error: f64,
    /// Bent normals against the ray-traced ones (where the scene asks for bent normals).
    pub bent_normals: Option<BentNormalErrors>,
    /// Emitter evaluations of all passes so far over the whole scene (every object's
    /// receivers): the cost in operations, the same on every machine.
    pub interactions: u64,
    /// Wall time of those passes on the CPU in ms (the whole scene).
    pub cpu_ms: f64,
    /// Indirect light (one bounce, emitters weighted 1): mean |surfels − ray-traced| over
    /// vertices and channels; `None` where the scene asks for none.
    pub indirect_mean_error: Option<f64>,
    /// Its signed mean (surfels − ray-traced).
    pub indirect_signed_error: Option<f64>,
    /// The same with emitters weighted by this row's accessibility (the chapter's modulation).
    pub indirect_accessibility_weighted_mean_error: Option<f64>,
    pub indirect_accessibility_weighted_signed_error: Option<f64>,
    /// The ray-traced one-bounce irradiance's mean over the same vertices and channels.
    pub indirect_reference_mean: Option<f64>,
    /// Its mean standard error.
    pub indirect_reference_standard_error: Option<f64>,
    /// GTAO only: the per-pixel error against a reference that counts occluders within
    /// GTAO's radius alone (what the depth buffer misses, the radius's cut aside).
    pub within_radius: Option<ErrorSummary>,
}

/// What to compare: the forms, the passes 1..=`passes`, and whether to run brute force
/// (which costs n² per pass) besides the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    pub forms: Vec<ShadowForm>,
    pub passes: u32,
    pub brute_force: bool,
    pub closeness: Closeness,
}

/// The rows of one mesh (its vertices' `defects` flags): every form × hierarchy (brute
/// force first, where asked) × pass; no pictures, so no per-pixel error.
pub fn error_rows(
    mesh: &str,
    surfels: &[Surfel],
    defects: &[bool],
    reference: &ReferenceAccessibility,
    comparison: &Comparison,
) -> Vec<ErrorRow> {
    let areas: Vec<f64> = surfels.iter().map(|s| s.area).collect();
    let mut rows = Vec::new();
    for &form in &comparison.forms {
        let brute = BruteForce { surfels, form };
        let tree = SurfelTree::new(surfels, form, comparison.closeness);
        let mut runs: Vec<(bool, &dyn Emitters)> = Vec::new();
        if comparison.brute_force {
            runs.push((false, &brute));
        }
        runs.push((true, &tree));
        for (hierarchy, emitters) in runs {
            for result in accessibility_by_pass(emitters, comparison.passes).iter().skip(1) {
                let errors = signed_differences(&result.values, &reference.values);
                rows.push(ErrorRow {
                    mesh: mesh.into(),
                    technique: Technique::Surfels,
                    surfels: surfels.len(),
                    receiver_gain: form.receiver_gain,
                    passes: result.passes,
                    hierarchy,
                    accessibility: AccessibilityErrors::new(&errors, &areas, defects, None),
                    reference_standard_error: reference.mean_standard_error(),
                    bent_normals: None,
                    interactions: result.interactions,
                    cpu_ms: result.elapsed_ms,
                    indirect_mean_error: None,
                    indirect_signed_error: None,
                    indirect_accessibility_weighted_mean_error: None,
                    indirect_accessibility_weighted_signed_error: None,
                    indirect_reference_mean: None,
                    indirect_reference_standard_error: None,
                    within_radius: None,
                });
            }
        }
    }
    rows
}

/// The `ao_errors` table of `rows`.
pub fn ao_errors_table(rows: &[ErrorRow]) -> Table {
    let surfels = |r: &ErrorRow| r.technique == Technique::Surfels;
    let vertex = |f: fn(&ErrorSummary) -> f64| {
        rows.iter().map(|r| (r.accessibility.per_vertex.count > 0).then(|| f(&r.accessibility.per_vertex))).collect::<Vec<_>>()
    };
    let gtao = |f: fn(crate::scene::surfels::Gtao) -> f64| rows.iter().map(|r| r.technique.gtao().map(f)).collect::<Vec<_>>();
    let area = |f: fn(&ErrorSummary) -> f64| rows.iter().map(|r| r.accessibility.area_weighted.as_ref().map(f)).collect::<Vec<_>>();
    let pixel = |f: fn(&ErrorSummary) -> f64| rows.iter().map(|r| r.accessibility.per_pixel.as_ref().map(f)).collect::<Vec<_>>();
    let bent = |f: fn(&BentNormalErrors) -> f64| rows.iter().map(|r| r.bent_normals.as_ref().map(f)).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .text("mesh", "mesh name", rows.iter().map(|r| r.mesh.clone()).collect())
        .text("technique", "surfels (surfel AO, Bunnell) or gtao (screen-space ground-truth AO, Jimenez et al. 2016: per pixel only)", rows.iter().map(|r| r.technique.name().to_string()).collect())
        .integer("surfels", "surfels (mesh vertices)", rows.iter().map(|r| r.surfels as i64).collect())
        .optional_float(
            "receiver_gain",
            "g of the shadow form: 1 the disc form factor, 4 its receiver cosine x 4 clamped to 1 (a variant); empty for gtao",
            rows.iter().map(|r| surfels(r).then_some(r.receiver_gain)).collect(),
        )
        .integer("passes", "accessibility passes (gtao: 0, one screen-space pass per frame)", rows.iter().map(|r| r.passes as i64).collect())
        .boolean("hierarchy", "emitters from the surfel tree (true) or every surfel (false); false for gtao", rows.iter().map(|r| r.hierarchy).collect())
        .optional_float("gtao_radius", "gtao: occluders within this distance count (scene units)", gtao(|g| g.radius))
        .optional_float("gtao_slices", "gtao: slice directions per pixel", gtao(|g| g.slices as f64))
        .optional_float("gtao_steps", "gtao: G-buffer samples per side of a slice", gtao(|g| g.steps as f64))
        .optional_float("mean_error", "mean over vertices of |e|, e = accessibility - ray-traced reference (empty for gtao: no per-vertex values)", vertex(|s| s.mean))
        .optional_float("signed_error", "mean over vertices of e (positive: the surfels under-occlude)", vertex(|s| s.signed_mean))
        .optional_float("median_error", "median over vertices of |e|", vertex(|s| s.median))
        .optional_float("p90_error", "90th percentile over vertices of |e|", vertex(|s| s.p90))
        .optional_float("p99_error", "99th percentile over vertices of |e|", vertex(|s| s.p99))
        .optional_float("max_error", "largest |e| over vertices", vertex(|s| s.max))
        .optional_float("area_mean_error", "mean of |e| weighted by the vertices' areas (a third of each adjacent triangle)", area(|s| s.mean))
        .optional_float("area_signed_error", "area-weighted mean of e", area(|s| s.signed_mean))
        .optional_float("area_median_error", "area-weighted median of |e|", area(|s| s.median))
        .optional_float("area_p90_error", "area-weighted 90th percentile of |e|", area(|s| s.p90))
        .optional_float("area_p99_error", "area-weighted 99th percentile of |e|", area(|s| s.p99))
        .optional_float("area_max_error", "largest |e| over vertices of positive area", area(|s| s.max))
        .integer(
            "pixels",
            "pixels of the picture where the object is the nearest surface (0: no picture measured)",
            rows.iter().map(|r| r.accessibility.per_pixel.map_or(0, |s| s.count as i64)).collect(),
        )
        .optional_float("pixel_mean_error", "mean over those pixels of |e|, accessibility and reference interpolated from the vertices", pixel(|s| s.mean))
        .optional_float("pixel_signed_error", "mean over those pixels of e", pixel(|s| s.signed_mean))
        .optional_float("pixel_median_error", "median over those pixels of |e|", pixel(|s| s.median))
        .optional_float("pixel_p90_error", "90th percentile over those pixels of |e|", pixel(|s| s.p90))
        .optional_float("pixel_p99_error", "99th percentile over those pixels of |e|", pixel(|s| s.p99))
        .optional_float("pixel_max_error", "largest |e| over those pixels", pixel(|s| s.max))
        .integer(
            "defect_vertices",
            "vertices of flipped or degenerate triangles (their error is the mesh's; counted in the columns above)",
            rows.iter().map(|r| r.accessibility.defect_vertices as i64).collect(),
        )
        .optional_float(
            "mean_error_without_defects",
            "mean over vertices of |e| leaving out the defect vertices",
            rows.iter().map(|r| r.accessibility.without_defects.map(|s| s.mean)).collect(),
        )
        .optional_float(
            "max_error_without_defects",
            "largest |e| over vertices leaving out the defect vertices",
            rows.iter().map(|r| r.accessibility.without_defects.map(|s| s.max)).collect(),
        )
        .float(
            "reference_standard_error",
            "mean standard error of the reference's per-vertex estimates (bounds its noise's effect on mean_error)",
            rows.iter().map(|r| r.reference_standard_error).collect(),
        )
        .optional_float(
            "bent_normal_mean_angle",
            "mean over vertices of the angle (degrees) between the surfel bent normal and the ray-traced one (mean unoccluded direction); empty where the scene asks for no bent normals",
            bent(|b| b.surfel.mean),
        )
        .optional_float("bent_normal_median_angle", "median of that angle (degrees)", bent(|b| b.surfel.median))
        .optional_float("bent_normal_p90_angle", "90th percentile of that angle (degrees)", bent(|b| b.surfel.p90))
        .optional_float(
            "normal_mean_angle",
            "mean over vertices of the angle (degrees) between the plain normal and the ray-traced bent normal (what bending has to correct)",
            bent(|b| b.normal.mean),
        )
        .integer("interactions", "emitter evaluations of all passes so far, whole scene (gtao: G-buffer reads of the frame, pixels x slices x 2 x steps); the cost in operations, machine-independent", rows.iter().map(|r| r.interactions as i64).collect())
        .float("cpu_ms", "wall time of all passes so far on the CPU, whole scene (gtao: the frame), in ms (a ratio between rows carries to another machine, the figure does not)", rows.iter().map(|r| r.cpu_ms).collect())
        .optional_float(
            "indirect_mean_error",
            "indirect light, one bounce with emitters weighted 1: mean over vertices and channels of |surfels - ray-traced| (units of the scene's light); empty when the scene asks for no indirect light",
            rows.iter().map(|r| r.indirect_mean_error).collect(),
        )
        .optional_float(
            "indirect_signed_error",
            "mean over vertices and channels of surfels - ray-traced, emitters weighted 1 (negative: too little bounce light)",
            rows.iter().map(|r| r.indirect_signed_error).collect(),
        )
        .optional_float(
            "indirect_accessibility_weighted_mean_error",
            "as indirect_mean_error with each emitter weighted by this row's accessibility (the chapter's modulation)",
            rows.iter().map(|r| r.indirect_accessibility_weighted_mean_error).collect(),
        )
        .optional_float(
            "indirect_accessibility_weighted_signed_error",
            "as indirect_signed_error with each emitter weighted by this row's accessibility",
            rows.iter().map(|r| r.indirect_accessibility_weighted_signed_error).collect(),
        )
        .optional_float("indirect_reference_mean", "mean of the ray-traced one-bounce irradiance over the same vertices and channels", rows.iter().map(|r| r.indirect_reference_mean).collect())
        .optional_float(
            "pixel_mean_error_within_radius",
            "gtao: mean over the covered pixels of |e| against a reference that counts occluders within the radius only (what the screen space misses, the radius's cut aside)",
            rows.iter().map(|r| r.within_radius.map(|s| s.mean)).collect(),
        )
        .optional_float(
            "pixel_signed_error_within_radius",
            "gtao: mean over the covered pixels of e against that range-limited reference",
            rows.iter().map(|r| r.within_radius.map(|s| s.signed_mean)).collect(),
        )
        .optional_float(
            "indirect_reference_standard_error",
            "mean standard error of the ray-traced one-bounce irradiance",
            rows.iter().map(|r| r.indirect_reference_standard_error).collect(),
        )
        .optional_float(
            "pixel_p90_error_within_radius",
            "gtao: 90th percentile over the covered pixels of |e| against the range-limited reference",
            rows.iter().map(|r| r.within_radius.map(|s| s.p90)).collect(),
        )
        .optional_float(
            "pixel_p99_error_within_radius",
            "gtao: 99th percentile over the covered pixels of |e| against the range-limited reference",
            rows.iter().map(|r| r.within_radius.map(|s| s.p99)).collect(),
        );
    gtao_heuristic_columns(&mut table, rows);
    table
}

/// The GTAO rows' preset and heuristics, a column each (empty for the surfels' rows).
fn gtao_heuristic_columns(table: &mut Table, rows: &[ErrorRow]) {
    let gtao = |f: fn(crate::scene::surfels::Gtao) -> f64| rows.iter().map(|r| r.technique.gtao().map(f)).collect::<Vec<_>>();
    table
        .text(
            "gtao_preset",
            "gtao: the named configuration (bare: Algorithm 1 of Jimenez et al. 2016; xe-low/medium/high/ultra: XeGTAO's quality levels and default heuristics; unreal: Unreal's r.GTAO defaults), with (modified) where the scene overrode a heuristic; empty for surfels",
            rows.iter().map(|r| r.technique.gtao().map_or(String::new(), |g| g.preset_label())).collect(),
        )
        .optional_float("gtao_radius_multiplier", "gtao: the search radius is gtao_radius x this (XeGTAO 1.457)", gtao(|g| g.heuristics.radius_multiplier))
        .optional_float("gtao_falloff_range", "gtao: fraction of the search radius over which a sample's weight falls to 0 (0: hard cut; XeGTAO 0.615)", gtao(|g| g.heuristics.falloff_range))
        .optional_float("gtao_distribution_power", "gtao: sample k at ((k + offset)/steps)^power of the screen radius (XeGTAO 2)", gtao(|g| g.heuristics.distribution_power))
        .optional_float("gtao_thin_occluder", "gtao: thin-occluder compensation, depth offsets x (1 + this) for the falloff (XeGTAO default 0)", gtao(|g| g.heuristics.thin_occluder))
        .optional_float(
            "gtao_thickness_blend",
            "gtao: a sample below the horizon pulls it toward itself by this squared (Unreal r.GTAO.ThicknessBlend 0.5; 0: the highest sample)",
            gtao(|g| g.heuristics.thickness_blend),
        )
        .optional_float("gtao_final_power", "gtao: accessibility raised to this power (XeGTAO 2.2)", gtao(|g| g.heuristics.final_power))
        .optional_float(
            "gtao_clamp_to_edge",
            "gtao: 1 where a sample beyond the image's edge reads the edge texel's depth (XeGTAO's clamping sampler), 0 where it is skipped",
            gtao(|g| f64::from(u8::from(g.heuristics.clamp_to_edge))),
        )
        .optional_float(
            "gtao_denoise_passes",
            "gtao: passes of XeGTAO's edge-aware 3x3 denoiser over the image (0: none; XeGTAO 1)",
            gtao(|g| f64::from(g.heuristics.denoise_passes)),
        )
        .optional_float("gtao_frames", "gtao: frames of per-pixel noise accumulated (1: no noise)", gtao(|g| if g.heuristics.noise { g.heuristics.frames as f64 } else { 1.0 }));
}

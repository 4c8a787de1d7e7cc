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
use nklut_tables::effects_tables::ao_errors;
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
        .put(ao_errors::MESH, rows.iter().map(|r| r.mesh.clone()).collect())
        .put(ao_errors::TECHNIQUE, rows.iter().map(|r| r.technique.name().to_string()).collect())
        .put(ao_errors::SURFELS, rows.iter().map(|r| r.surfels as i64).collect())
        .put(ao_errors::RECEIVER_GAIN, rows.iter().map(|r| surfels(r).then_some(r.receiver_gain)).collect())
        .put(ao_errors::PASSES, rows.iter().map(|r| r.passes as i64).collect())
        .put(ao_errors::HIERARCHY, rows.iter().map(|r| r.hierarchy).collect())
        .put(ao_errors::GTAO_RADIUS, gtao(|g| g.radius))
        .put(ao_errors::GTAO_SLICES, gtao(|g| g.slices as f64))
        .put(ao_errors::GTAO_STEPS, gtao(|g| g.steps as f64))
        .put(ao_errors::MEAN_ERROR, vertex(|s| s.mean))
        .put(ao_errors::SIGNED_ERROR, vertex(|s| s.signed_mean))
        .put(ao_errors::MEDIAN_ERROR, vertex(|s| s.median))
        .put(ao_errors::P90_ERROR, vertex(|s| s.p90))
        .put(ao_errors::P99_ERROR, vertex(|s| s.p99))
        .put(ao_errors::MAX_ERROR, vertex(|s| s.max))
        .put(ao_errors::AREA_MEAN_ERROR, area(|s| s.mean))
        .put(ao_errors::AREA_SIGNED_ERROR, area(|s| s.signed_mean))
        .put(ao_errors::AREA_MEDIAN_ERROR, area(|s| s.median))
        .put(ao_errors::AREA_P90_ERROR, area(|s| s.p90))
        .put(ao_errors::AREA_P99_ERROR, area(|s| s.p99))
        .put(ao_errors::AREA_MAX_ERROR, area(|s| s.max))
        .put(ao_errors::PIXELS, rows.iter().map(|r| r.accessibility.per_pixel.map_or(0, |s| s.count as i64)).collect())
        .put(ao_errors::PIXEL_MEAN_ERROR, pixel(|s| s.mean))
        .put(ao_errors::PIXEL_SIGNED_ERROR, pixel(|s| s.signed_mean))
        .put(ao_errors::PIXEL_MEDIAN_ERROR, pixel(|s| s.median))
        .put(ao_errors::PIXEL_P90_ERROR, pixel(|s| s.p90))
        .put(ao_errors::PIXEL_P99_ERROR, pixel(|s| s.p99))
        .put(ao_errors::PIXEL_MAX_ERROR, pixel(|s| s.max))
        .put(ao_errors::DEFECT_VERTICES, rows.iter().map(|r| r.accessibility.defect_vertices as i64).collect())
        .put(ao_errors::MEAN_ERROR_WITHOUT_DEFECTS, rows.iter().map(|r| r.accessibility.without_defects.map(|s| s.mean)).collect())
        .put(ao_errors::MAX_ERROR_WITHOUT_DEFECTS, rows.iter().map(|r| r.accessibility.without_defects.map(|s| s.max)).collect())
        .put(ao_errors::REFERENCE_STANDARD_ERROR, rows.iter().map(|r| r.reference_standard_error).collect())
        .put(ao_errors::BENT_NORMAL_MEAN_ANGLE, bent(|b| b.surfel.mean))
        .put(ao_errors::BENT_NORMAL_MEDIAN_ANGLE, bent(|b| b.surfel.median))
        .put(ao_errors::BENT_NORMAL_P90_ANGLE, bent(|b| b.surfel.p90))
        .put(ao_errors::NORMAL_MEAN_ANGLE, bent(|b| b.normal.mean))
        .put(ao_errors::INTERACTIONS, rows.iter().map(|r| r.interactions as i64).collect())
        .put(ao_errors::CPU_MS, rows.iter().map(|r| r.cpu_ms).collect())
        .put(ao_errors::INDIRECT_MEAN_ERROR, rows.iter().map(|r| r.indirect_mean_error).collect())
        .put(ao_errors::INDIRECT_SIGNED_ERROR, rows.iter().map(|r| r.indirect_signed_error).collect())
        .put(
            ao_errors::INDIRECT_ACCESSIBILITY_WEIGHTED_MEAN_ERROR,
            rows.iter().map(|r| r.indirect_accessibility_weighted_mean_error).collect(),
        )
        .put(
            ao_errors::INDIRECT_ACCESSIBILITY_WEIGHTED_SIGNED_ERROR,
            rows.iter().map(|r| r.indirect_accessibility_weighted_signed_error).collect(),
        )
        .put(ao_errors::INDIRECT_REFERENCE_MEAN, rows.iter().map(|r| r.indirect_reference_mean).collect())
        .put(ao_errors::PIXEL_MEAN_ERROR_WITHIN_RADIUS, rows.iter().map(|r| r.within_radius.map(|s| s.mean)).collect())
        .put(ao_errors::PIXEL_SIGNED_ERROR_WITHIN_RADIUS, rows.iter().map(|r| r.within_radius.map(|s| s.signed_mean)).collect())
        .put(ao_errors::INDIRECT_REFERENCE_STANDARD_ERROR, rows.iter().map(|r| r.indirect_reference_standard_error).collect())
        .put(ao_errors::PIXEL_P90_ERROR_WITHIN_RADIUS, rows.iter().map(|r| r.within_radius.map(|s| s.p90)).collect())
        .put(ao_errors::PIXEL_P99_ERROR_WITHIN_RADIUS, rows.iter().map(|r| r.within_radius.map(|s| s.p99)).collect());
    gtao_heuristic_columns(&mut table, rows);
    table
}

/// The GTAO rows' preset and heuristics, a column each (empty for the surfels' rows).
fn gtao_heuristic_columns(table: &mut Table, rows: &[ErrorRow]) {
    let gtao = |f: fn(crate::scene::surfels::Gtao) -> f64| rows.iter().map(|r| r.technique.gtao().map(f)).collect::<Vec<_>>();
    table
        .put(ao_errors::GTAO_PRESET, rows.iter().map(|r| r.technique.gtao().map_or(String::new(), |g| g.preset_label())).collect())
        .put(ao_errors::GTAO_RADIUS_MULTIPLIER, gtao(|g| g.heuristics.radius_multiplier))
        .put(ao_errors::GTAO_FALLOFF_RANGE, gtao(|g| g.heuristics.falloff_range))
        .put(ao_errors::GTAO_DISTRIBUTION_POWER, gtao(|g| g.heuristics.distribution_power))
        .put(ao_errors::GTAO_THIN_OCCLUDER, gtao(|g| g.heuristics.thin_occluder))
        .put(ao_errors::GTAO_THICKNESS_BLEND, gtao(|g| g.heuristics.thickness_blend))
        .put(ao_errors::GTAO_FINAL_POWER, gtao(|g| g.heuristics.final_power))
        .put(ao_errors::GTAO_CLAMP_TO_EDGE, gtao(|g| f64::from(u8::from(g.heuristics.clamp_to_edge))))
        .put(ao_errors::GTAO_DENOISE_PASSES, gtao(|g| f64::from(g.heuristics.denoise_passes)))
        .put(ao_errors::GTAO_FRAMES, gtao(|g| if g.heuristics.noise { g.heuristics.frames as f64 } else { 1.0 }));
}

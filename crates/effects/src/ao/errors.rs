//! The `ao_errors` table: per mesh, receiver gain g, pass count and hierarchy on/off, the
//! mean and largest |accessibility − reference| over the mesh's vertices, with the
//! reference's own mean standard error beside them (the figure that says how far its noise
//! can move the mean), and where the scene asks for indirect light, its error. Rows are computed here from plain data; the table is written through
//! `nklut_pipeline::output` (CSV, Parquet, columns.json).

use super::accessibility::{accessibility_by_pass, BruteForce, Emitters};
use super::hierarchy::{Closeness, SurfelTree};
use super::reference::ReferenceAccessibility;
use super::shadow::ShadowForm;
use super::surfel::Surfel;
use nklut_pipeline::output::Table;

/// One configuration's error against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorRow {
    pub mesh: String,
    pub surfels: usize,
    pub receiver_gain: f64,
    pub passes: u32,
    pub hierarchy: bool,
    pub mean_error: f64,
    pub max_error: f64,
    pub reference_standard_error: f64,
    /// Emitter evaluations of all passes so far over the whole scene (every object's
    /// receivers): the cost in operations, the same on every machine.
    pub interactions: u64,
    /// Wall time of those passes on the CPU in ms (the whole scene).
    pub cpu_ms: f64,
    /// Indirect light (one bounce, emitters weighted by this row's accessibility): mean
    /// |surfels − ray-traced| over vertices and channels; `None` where the scene asks for none.
    pub indirect_mean_error: Option<f64>,
    /// The ray-traced one-bounce irradiance's mean over the same vertices and channels.
    pub indirect_reference_mean: Option<f64>,
    /// Its mean standard error.
    pub indirect_reference_standard_error: Option<f64>,
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

/// Mean and largest |a − b| (0, 0 for no values).
pub fn mean_and_max_difference(a: &[f64], b: &[f64]) -> (f64, f64) {
    let differences = a.iter().zip(b).map(|(x, y)| (x - y).abs());
    let (sum, max, count) = differences.fold((0.0, 0.0f64, 0usize), |(sum, max, count), d| (sum + d, max.max(d), count + 1));
    (if count > 0 { sum / count as f64 } else { 0.0 }, max)
}

/// The rows of one mesh: every form × hierarchy (brute force first, where asked) × pass.
pub fn error_rows(mesh: &str, surfels: &[Surfel], reference: &ReferenceAccessibility, comparison: &Comparison) -> Vec<ErrorRow> {
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
                let (mean_error, max_error) = mean_and_max_difference(&result.values, &reference.values);
                rows.push(ErrorRow {
                    mesh: mesh.into(),
                    surfels: surfels.len(),
                    receiver_gain: form.receiver_gain,
                    passes: result.passes,
                    hierarchy,
                    mean_error,
                    max_error,
                    reference_standard_error: reference.mean_standard_error(),
                    interactions: result.interactions,
                    cpu_ms: result.elapsed_ms,
                    indirect_mean_error: None,
                    indirect_reference_mean: None,
                    indirect_reference_standard_error: None,
                });
            }
        }
    }
    rows
}

/// The `ao_errors` table of `rows`.
pub fn ao_errors_table(rows: &[ErrorRow]) -> Table {
    let mut table = Table::new();
    table
        .text("mesh", "mesh name", rows.iter().map(|r| r.mesh.clone()).collect())
        .integer("surfels", "surfels (mesh vertices)", rows.iter().map(|r| r.surfels as i64).collect())
        .float("receiver_gain", "g of the shadow form: 1 the disc form factor, 4 the chapter's shader", rows.iter().map(|r| r.receiver_gain).collect())
        .integer("passes", "accessibility passes", rows.iter().map(|r| r.passes as i64).collect())
        .boolean("hierarchy", "emitters from the surfel tree (true) or every surfel (false)", rows.iter().map(|r| r.hierarchy).collect())
        .float("mean_error", "mean over vertices of |accessibility - ray-traced reference|", rows.iter().map(|r| r.mean_error).collect())
        .float("max_error", "largest |accessibility - ray-traced reference| over vertices", rows.iter().map(|r| r.max_error).collect())
        .float(
            "reference_standard_error",
            "mean standard error of the reference's per-vertex estimates (bounds its noise's effect on mean_error)",
            rows.iter().map(|r| r.reference_standard_error).collect(),
        )
        .integer("interactions", "emitter evaluations of all passes so far, whole scene (the cost in operations: machine-independent)", rows.iter().map(|r| r.interactions as i64).collect())
        .float("cpu_ms", "wall time of all passes so far on the CPU, whole scene, in ms (a ratio between rows carries to another machine, the figure does not)", rows.iter().map(|r| r.cpu_ms).collect())
        .optional_float(
            "indirect_mean_error",
            "indirect light, one bounce with emitters weighted by this row's accessibility: mean over vertices and channels of |surfels - ray-traced| (units of the scene's light); empty when the scene asks for no indirect light",
            rows.iter().map(|r| r.indirect_mean_error).collect(),
        )
        .optional_float("indirect_reference_mean", "mean of the ray-traced one-bounce irradiance over the same vertices and channels", rows.iter().map(|r| r.indirect_reference_mean).collect())
        .optional_float(
            "indirect_reference_standard_error",
            "mean standard error of the ray-traced one-bounce irradiance",
            rows.iter().map(|r| r.indirect_reference_standard_error).collect(),
        );
    table
}

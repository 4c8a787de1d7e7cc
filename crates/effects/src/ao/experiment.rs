//! The ambient-occlusion experiment of a scene that calls for `ambient_occlusion` or
//! `indirect` (docs/ao.md): every object's placed (and optionally subdivided) mesh becomes
//! surfels, one set for the whole scene so objects shadow each other; accessibility is
//! computed by brute force (up to a surfel count, n² per pass) and through the tree, for
//! 1, 2, 3 passes (and the scene's own count), and compared per object with the ray-traced
//! reference; where the scene asks for indirect light, the surfels' one-bounce gather is
//! compared with the ray-traced bounce. The result is the rows of `ao_errors` and pictures
//! of the scene with no AO, 1, 2, 3 passes and the reference, side by side, each labelled
//! with its technique and its accessibility error per covered pixel.
//!
//! Lighting of a visible point x with albedo ρ (units of the scene's `light`):
//! ρ · (Σ ambient · a(x) + Σ direct(x) + E_indirect(x)), a and E_indirect interpolated over
//! the triangle from its vertices (surfels), direct light with ray-traced shadows per pixel
//! (the same in every picture, so the pictures differ by accessibility and indirect light
//! alone). With `bent_normals`, direct light's cosine takes the interpolated bent normal.

use std::ops::Range;

use anyhow::Result;
use glam::DVec3;
use rayon::prelude::*;

use super::accessibility::{accessibility_by_pass, Accessibility, BruteForce};
use super::errors::{signed_differences, AccessibilityErrors, BentNormalErrors, ErrorRow, Technique};
use super::gtao::{gtao, GBuffer, Parameters};
use super::hierarchy::{Closeness, SurfelTree};
use super::histogram::{histogram_rows, HistogramRow};
use super::indirect::{direct_irradiance, reference_indirect, surfel_direct, surfel_indirect, EmitterWeight, ReferenceIndirect, Rgb};
use super::reference::{
    angles_degrees, reference_accessibility, reference_accessibility_within, reference_bent_normals, RaySettings, ReferenceAccessibility,
};
use super::shadow::ShadowForm;
use super::surfel::{mesh_defects, subdivided_times, surfels, Surfel};
use crate::experiment::EffectsStats;
use crate::geometry::Geometry;
use crate::hero::{ErrorMask, HeroPanel, HeroSet};
use crate::labels::{self, Panel};
use crate::pictures::{Picture, SignedMap};
use crate::scene::mesh::{self, Mesh};
use crate::scene::{LightSource, Role, Scene, SceneError, SceneProblem};
use crate::trace::{Camera, TracedFrame};
use nklut_tables::budget::{times, MemoryBudget};
use nklut_tables::stats::ErrorSummary;

/// One object's surfels: its name in tables and its range in the scene's surfels (the
/// object's vertices in order) and in the geometry's triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSurfels {
    pub name: String,
    pub surfels: Range<usize>,
    pub triangles: Range<usize>,
}

/// The scene's surfels and triangles.
pub struct SurfelScene {
    pub meshes: Vec<Mesh>,
    pub geometry: Geometry,
    pub surfels: Vec<Surfel>,
    pub objects: Vec<ObjectSurfels>,
    /// Diffuse albedo per surfel (a specular object's surfels: 0, it reflects no diffuse light).
    pub albedo: Vec<Rgb>,
    /// Diffuse albedo per object (the plain colour, without pattern).
    pub object_albedo: Vec<Rgb>,
    pub lights: Vec<LightSource>,
    /// Per surfel: a corner of a flipped or degenerate triangle of its mesh.
    pub defects: Vec<bool>,
}

/// The bytes the AO run holds per triangle of a placed (and subdivided) mesh, for the
/// memory check before subdividing: the mesh itself, its surfels (about one per two
/// triangles), the tracer's f64 triangle and its BVH, the surfel tree and the per-vertex
/// results. Measured: peak resident memory grows by 611 and 616 bytes per triangle from
/// the bunny to the bunny subdivided once and twice (69 451 → 277 804 → 1 111 216
/// triangles, release build, `--ao-max-brute 0`); counted as 768, a quarter more.
pub const BYTES_PER_SURFEL_TRIANGLE: usize = 768;

impl SurfelScene {
    /// Load, place and subdivide every object's mesh; a subdivision whose triangles would
    /// not fit `budget` is refused (naming the object) before it is made.
    pub fn new(scene: &Scene, budget: &MemoryBudget) -> Result<SurfelScene> {
        let named = |problem: SceneProblem| SceneError::new(&scene.file, problem);
        let mut meshes = Vec::new();
        let mut objects = Vec::new();
        let (mut all, mut albedo, mut object_albedo, mut defects) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut triangles = 0;
        for (i, object) in scene.objects.iter().enumerate() {
            let loaded =
                mesh::load(&object.mesh, |p| scene.mesh_path(p)).map_err(|error| named(SceneProblem::Mesh { object: i, error }))?;
            let subdivided_triangles = (loaded.triangles() as u128).saturating_mul(4u128.saturating_pow(object.subdivisions));
            let what = format!("{} triangles ({} subdivided {} times)", subdivided_triangles, object.mesh.label(), object.subdivisions);
            budget
                .check(&format!("objects[{i}].subdivide"), what, times(triangles as u128 + subdivided_triangles, BYTES_PER_SURFEL_TRIANGLE))
                .map_err(|e| named(SceneProblem::Memory(e)))?;
            let placed = subdivided_times(&loaded.placed(&object.placement), object.subdivisions);
            let own = surfels(&placed);
            let base = object.mesh.label();
            let taken = objects.iter().filter(|o: &&ObjectSurfels| o.name == base || o.name.starts_with(&format!("{base}-"))).count();
            let name = if taken == 0 { base } else { format!("{base}-{}", taken + 1) };
            objects.push(ObjectSurfels {
                name,
                surfels: all.len()..all.len() + own.len(),
                triangles: triangles..triangles + placed.triangles(),
            });
            let plain = match &object.role {
                Role::Diffuse(d) => d.albedo,
                Role::Specular(_) => [0.0; 3],
            };
            object_albedo.push(plain);
            albedo.extend(own.iter().map(|s| match &object.role {
                Role::Diffuse(d) => d.albedo_at(s.centre.to_array(), s.normal.to_array()),
                Role::Specular(_) => [0.0; 3],
            }));
            triangles += placed.triangles();
            all.extend(own);
            defects.extend(mesh_defects(&placed));
            meshes.push(placed);
        }
        let geometry = Geometry::new(&meshes).map_err(|e| named(SceneProblem::Geometry(e)))?;
        Ok(SurfelScene { meshes, geometry, surfels: all, objects, albedo, object_albedo, lights: scene.lights.clone(), defects })
    }

    /// Which object a global triangle index belongs to.
    fn object_of_triangle(&self, triangle: usize) -> usize {
        self.objects.iter().position(|o| o.triangles.contains(&triangle)).unwrap_or(0)
    }

    /// The global surfel indices of a triangle's corners and the barycentric weights of
    /// `point` in it (clamped to the triangle, renormalised).
    fn corners(&self, triangle: usize, point: DVec3) -> ([usize; 3], [f64; 3]) {
        let object = self.object_of_triangle(triangle);
        let local = triangle - self.objects[object].triangles.start;
        let mesh = &self.meshes[object];
        let vertices = [0, 1, 2].map(|k| mesh.indices[3 * local + k] as usize);
        let [a, b, c] = vertices.map(|v| DVec3::from_array(mesh.positions[v].map(f64::from)));
        let normal = (b - a).cross(c - a);
        let area = normal.length_squared();
        let weights = if area > 0.0 {
            let w = [(c - b).cross(point - b).dot(normal), (a - c).cross(point - c).dot(normal), (b - a).cross(point - a).dot(normal)]
                .map(|x| (x / area).max(0.0));
            let sum: f64 = w.iter().sum();
            if sum > 0.0 {
                w.map(|x| x / sum)
            } else {
                [1.0 / 3.0; 3]
            }
        } else {
            [1.0 / 3.0; 3]
        };
        (vertices.map(|v| self.objects[object].surfels.start + v), weights)
    }

    /// What each pixel of `camera`'s frame sees: the object, its triangle's surfels and the
    /// point's barycentric weights (`None`: no surface).
    pub fn coverage(&self, camera: &Camera) -> Vec<Option<PixelSample>> {
        (0..camera.width * camera.height)
            .into_par_iter()
            .map(|i| {
                let direction = camera.ray(i % camera.width, i / camera.width);
                let hit = self.geometry.nearest(camera.eye, direction, None, |_| true)?;
                let (corners, weights) = self.corners(hit.triangle as usize, hit.point);
                Some(PixelSample { object: self.object_of_triangle(hit.triangle as usize), corners, weights })
            })
            .collect()
    }
}

/// The surface a pixel sees: its object (index in [`SurfelScene::objects`]), the global
/// surfel indices of the triangle's corners and the barycentric weights of the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelSample {
    pub object: usize,
    pub corners: [usize; 3],
    pub weights: [f64; 3],
}

impl PixelSample {
    /// Per-vertex `values` interpolated at the pixel's point.
    pub fn interpolate(&self, values: &[f64]) -> f64 {
        (0..3).map(|k| self.weights[k] * values[self.corners[k]]).sum()
    }
}

/// The per-pixel errors (interpolated `values` − interpolated `reference`) of the pixels
/// where `object` is the nearest surface.
pub fn pixel_errors(coverage: &[Option<PixelSample>], object: usize, values: &[f64], reference: &[f64]) -> Vec<f64> {
    coverage.iter().flatten().filter(|p| p.object == object).map(|p| p.interpolate(values) - p.interpolate(reference)).collect()
}

/// How the experiment runs: reference rays, the largest surfel count run by brute force
/// (n² per pass), the passes compared (1..=`passes`), the shadow form and the tree's κ,
/// the picture size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AoSettings {
    pub rays: RaySettings,
    pub max_brute: usize,
    pub passes: u32,
    pub form: ShadowForm,
    pub closeness: Closeness,
    pub resolution: [u32; 2],
    /// The size of the hero frame (the pictures again at a size a person looks at); `None`:
    /// none.
    pub hero: Option<[u32; 2]>,
    /// What the run may hold (subdivided meshes are checked against it).
    pub budget: MemoryBudget,
}

impl Default for AoSettings {
    /// 256 rays per vertex (σ ≤ 1/32 per vertex, ~0.01 on a mean), brute force to 20 000
    /// surfels, 3 passes, the form factor (g = 1), κ = 16, 256×256 pictures.
    fn default() -> AoSettings {
        AoSettings {
            rays: RaySettings { rays: 256, ..RaySettings::default() },
            max_brute: 20_000,
            passes: 3,
            form: ShadowForm::FORM_FACTOR,
            closeness: Closeness::default(),
            resolution: [256, 256],
            hero: None,
            budget: MemoryBudget::of_machine(),
        }
    }
}

/// The rows of `ao_errors` and the pictures.
#[derive(Clone, Debug, Default)]
pub struct AoReport {
    pub rows: Vec<ErrorRow>,
    pub pictures: Vec<Picture>,
    /// Per shown pass count, the per-pixel signed accessibility error (surfels − reference,
    /// interpolated from the vertices): `ao_passes<k>_signed`.
    pub signed_maps: Vec<SignedMap>,
    /// The pictures' variants at the hero size, when asked for.
    pub hero: Option<HeroSet>,
    /// The signed error's histograms per object, technique and passes: `ao_histogram`.
    pub histograms: Vec<HistogramRow>,
}

/// Accessibility to light a picture with: per vertex (surfels, the reference), or per
/// pixel of the frame (GTAO; `None` where no surface is).
#[derive(Clone, Copy)]
enum Shown<'a> {
    PerVertex(&'a [f64]),
    PerPixel(&'a [Option<f64>]),
}

/// Values to light a picture with: accessibility, per-vertex indirect irradiance and bent
/// normals (`None`: the normal).
struct Lighting<'a> {
    accessibility: Shown<'a>,
    indirect: Option<&'a [Rgb]>,
    bent_normals: Option<&'a [DVec3]>,
}

/// The mean over `range` of `values`.
fn mean(values: impl Iterator<Item = f64>, count: usize) -> f64 {
    values.sum::<f64>() / count.max(1) as f64
}

/// Indirect light's error over a range of vertices and the three channels.
#[derive(Clone, Copy, Debug, PartialEq)]
struct IndirectError {
    /// Mean |twin − reference| with emitters weighted 1.
    mean: f64,
    /// Mean (twin − reference) with emitters weighted 1.
    signed: f64,
    /// Mean |twin − reference| with emitters weighted by the row's accessibility.
    accessibility_weighted: f64,
    /// Mean (twin − reference) with that weighting.
    accessibility_weighted_signed: f64,
    /// The reference's mean and mean standard error.
    level: f64,
    noise: f64,
}

/// Mean |twin − reference| and mean (twin − reference) over a range of vertices and the
/// three channels.
fn indirect_difference(twin: &[Rgb], reference: &ReferenceIndirect, range: Range<usize>) -> (f64, f64) {
    let count = 3 * range.len();
    let difference = |i: usize, c: usize| twin[i][c] - reference.values[i][c];
    let absolute = mean(range.clone().flat_map(|i| (0..3).map(move |c| difference(i, c).abs())), count);
    let signed = mean(range.flat_map(|i| (0..3).map(move |c| difference(i, c))), count);
    (absolute, signed)
}

fn indirect_error(one: &[Rgb], chapter: &[Rgb], reference: &ReferenceIndirect, range: Range<usize>) -> IndirectError {
    let count = 3 * range.len();
    let (mean_error, signed) = indirect_difference(one, reference, range.clone());
    let (accessibility_weighted, accessibility_weighted_signed) = indirect_difference(chapter, reference, range.clone());
    IndirectError {
        mean: mean_error,
        signed,
        accessibility_weighted,
        accessibility_weighted_signed,
        level: mean(range.clone().flat_map(|i| reference.values[i]), count),
        noise: mean(range.flat_map(|i| reference.standard_errors[i]), count),
    }
}

/// The log line of one surfel row: per-vertex error figures, area-weighted and per pixel,
/// defects, and the indirect light's error where measured.
fn surfel_row_line(
    name: &str,
    passes: u32,
    hierarchy: bool,
    accessibility: &AccessibilityErrors,
    measured: Option<IndirectError>,
) -> String {
    let v = &accessibility.per_vertex;
    format!(
        "  {} {} passes {}: |a − ref| per vertex mean {:.4} (signed {:+.4}), median {:.4}, p90 {:.4}, p99 {:.4}, max {:.4}; area-weighted {:.4}; per pixel {:.4}; {} defect vertices{}",
        name,
        passes,
        if hierarchy { "tree" } else { "brute force" },
        v.mean,
        v.signed_mean,
        v.median,
        v.p90,
        v.p99,
        v.max,
        accessibility.area_weighted.map_or(0.0, |s| s.mean),
        accessibility.per_pixel.map_or(0.0, |s| s.mean),
        accessibility.defect_vertices,
        measured
            .map(|m| format!(
                ", indirect mean |Δ| {:.4} (signed {:+.4}; weighted by accessibility {:.4}, {:+.4}) of {:.4}",
                m.mean, m.signed, m.accessibility_weighted, m.accessibility_weighted_signed, m.level
            ))
            .unwrap_or_default()
    )
}

/// Run the experiment for a scene with surfel effects; a scene without them computes
/// nothing (no surfels, no tree, no pass: `stats` stays as it was).
pub fn run(scene: &Scene, settings: &AoSettings, stats: &mut EffectsStats, log: &mut dyn FnMut(&str)) -> Result<AoReport> {
    let Some(effects) = &scene.effects else { return Ok(AoReport::default()) };
    if !effects.names(crate::scene::EffectFamily::Surfels) {
        return Ok(AoReport::default());
    }
    let stage = SurfelScene::new(scene, &settings.budget)?;
    let n = stage.surfels.len();
    stats.surfels += n;
    let tree = SurfelTree::new(&stage.surfels, settings.form, settings.closeness);
    stats.tree_nodes += tree.nodes.len();
    let brute = BruteForce { surfels: &stage.surfels, form: settings.form };
    let wanted = effects.ambient_occlusion.as_ref();
    let passes = settings.passes.max(wanted.map_or(0, |a| a.passes)).max(1);
    log(&format!(
        "ao: {n} surfels in {} objects, {} tree nodes, {} triangles",
        stage.objects.len(),
        tree.nodes.len(),
        stage.geometry.triangles()
    ));
    let start = std::time::Instant::now();
    let reference = reference_accessibility(&stage.geometry, &stage.surfels, settings.rays);
    log(&format!(
        "  reference: {} rays in {:.1} s, σ mean {:.4}",
        reference.rays,
        start.elapsed().as_secs_f64(),
        reference.mean_standard_error()
    ));
    let mut runs: Vec<(bool, Vec<Accessibility>)> = Vec::new();
    if n <= settings.max_brute {
        runs.push((false, accessibility_by_pass(&brute, passes)));
        stats.ao_passes += passes as u64;
    } else {
        log(&format!("  brute force skipped: {n} surfels > {} (n² per pass)", settings.max_brute));
    }
    runs.push((true, accessibility_by_pass(&tree, passes)));
    stats.ao_passes += passes as u64;

    let indirect = effects.indirect.map(|_| {
        let direct = surfel_direct(&stage.geometry, &stage.surfels, &stage.lights, settings.rays.offset);
        let albedo_of = |object: usize| stage.object_albedo[object];
        let reference = reference_indirect(&stage.geometry, &stage.surfels, &albedo_of, &stage.lights, settings.rays);
        (direct, reference)
    });

    let bent = wanted.is_some_and(|a| a.bent_normals);
    let reference_bent = bent.then(|| {
        let start = std::time::Instant::now();
        let normals = reference_bent_normals(&stage.geometry, &stage.surfels, settings.rays);
        log(&format!("  reference bent normals: {} rays in {:.1} s", n as u64 * settings.rays.rays as u64, start.elapsed().as_secs_f64()));
        normals
    });
    let plain_normals: Vec<DVec3> = stage.surfels.iter().map(|s| s.normal).collect();
    let camera = Camera::new(&scene.camera, 0, settings.resolution[0], settings.resolution[1]);
    let coverage = stage.coverage(&camera);
    let areas: Vec<f64> = stage.surfels.iter().map(|s| s.area).collect();
    let mut report = AoReport::default();
    // One bounce with emitters weighted 1 (the same for every row) and, per row, weighted by
    // its accessibility (the chapter's modulation), for comparison.
    let one_bounce = |weight: EmitterWeight, a: &[f64]| {
        indirect.as_ref().map(|(direct, _)| surfel_indirect(&stage.surfels, &stage.albedo, direct, &weight.weights(a), settings.form, 1))
    };
    let twin_one = one_bounce(EmitterWeight::One, &reference.values);
    stats.indirect_bounces += twin_one.is_some() as u64;
    for (hierarchy, history) in &runs {
        for result in history.iter().skip(1) {
            let twin = one_bounce(EmitterWeight::Accessibility, &result.values);
            stats.indirect_bounces += twin.is_some() as u64;
            for (index, object) in stage.objects.iter().enumerate() {
                let range = object.surfels.clone();
                let errors = signed_differences(&result.values[range.clone()], &reference.values[range.clone()]);
                let pixels = pixel_errors(&coverage, index, &result.values, &reference.values);
                let accessibility = AccessibilityErrors::new(&errors, &areas[range.clone()], &stage.defects[range.clone()], Some(&pixels));
                report.histograms.extend(histogram_rows(
                    &object.name,
                    technique(*hierarchy),
                    result.passes,
                    &errors,
                    &areas[range.clone()],
                    Some(&pixels),
                ));
                let bent_normals = reference_bent.as_ref().and_then(|truth| {
                    let surfel = ErrorSummary::of(&angles_degrees(&result.bent_normals[range.clone()], &truth[range.clone()]))?;
                    let normal = ErrorSummary::of(&angles_degrees(&plain_normals[range.clone()], &truth[range.clone()]))?;
                    Some(BentNormalErrors { surfel, normal })
                });
                let measured = twin
                    .as_ref()
                    .zip(twin_one.as_ref())
                    .zip(indirect.as_ref())
                    .map(|((chapter, one), (_, reference))| indirect_error(one, chapter, reference, range.clone()));
                report.rows.push(ErrorRow {
                    mesh: object.name.clone(),
                    technique: Technique::Surfels,
                    surfels: range.len(),
                    receiver_gain: settings.form.receiver_gain,
                    passes: result.passes,
                    hierarchy: *hierarchy,
                    accessibility: accessibility.clone(),
                    reference_standard_error: mean(range.clone().map(|i| reference.standard_errors[i]), range.len()),
                    bent_normals,
                    interactions: result.interactions,
                    cpu_ms: result.elapsed_ms,
                    indirect_mean_error: measured.map(|m| m.mean),
                    indirect_signed_error: measured.map(|m| m.signed),
                    indirect_accessibility_weighted_mean_error: measured.map(|m| m.accessibility_weighted),
                    indirect_accessibility_weighted_signed_error: measured.map(|m| m.accessibility_weighted_signed),
                    indirect_reference_mean: measured.map(|m| m.level),
                    indirect_reference_standard_error: measured.map(|m| m.noise),
                    within_radius: None,
                });
                log(&surfel_row_line(&object.name, result.passes, *hierarchy, &accessibility, measured));
            }
            let all: Vec<f64> =
                coverage.iter().flatten().map(|p| p.interpolate(&result.values) - p.interpolate(&reference.values)).collect();
            if let Some(e) = ErrorSummary::of(&all) {
                log(&format!(
                    "  all objects {} passes {}: |a − ref| over every covered pixel mean {:.4} (signed {:+.4}), p90 {:.4}, p99 {:.4} over {} pixels",
                    result.passes,
                    technique(*hierarchy),
                    e.mean,
                    e.signed_mean,
                    e.p90,
                    e.p99,
                    e.count
                ));
            }
        }
    }

    // Screen-space GTAO where the scene names it: one row set per configuration (radius);
    // the first named is the one pictured.
    let gtao_settings: Vec<crate::scene::surfels::Gtao> = wanted.map(|a| a.gtao.clone()).unwrap_or_default();
    let basis = Measured { stage: &stage, camera: &camera, coverage: &coverage, reference: &reference, indirect: indirect.as_ref() };
    let gtao_values = gtao_rows(&basis, settings, &gtao_settings, &mut report, log);

    let pictured = gtao_settings.first().copied().zip(gtao_values.as_deref());
    pictures(&basis, scene, settings, &runs, pictured, &mut report, stats);
    Ok(report)
}

/// What the surfel and GTAO rows were measured on, which the pictures show: the scene's
/// surfels, the camera and its pixels' surfels, the ray-traced reference, and per surfel the
/// direct light with the reference's indirect light where the scene names indirect light.
#[derive(Clone, Copy)]
struct Measured<'a> {
    stage: &'a SurfelScene,
    camera: &'a Camera,
    coverage: &'a [Option<PixelSample>],
    reference: &'a ReferenceAccessibility,
    indirect: Option<&'a (Vec<Rgb>, ReferenceIndirect)>,
}

/// The pictures: the scene's own emitters (the tree where it asks for it or brute force was
/// skipped), no AO, 1, 2, 3 passes, GTAO's first configuration (`gtao`, with its per-pixel
/// accessibility) and the reference, side by side and as the hero set.
fn pictures(
    m: &Measured,
    scene: &Scene,
    settings: &AoSettings,
    runs: &[(bool, Vec<Accessibility>)],
    gtao: Option<(crate::scene::surfels::Gtao, &[Option<f64>])>,
    report: &mut AoReport,
    stats: &mut EffectsStats,
) {
    let Measured { stage, camera, coverage, reference, indirect } = *m;
    let wanted = scene.effects.as_ref().and_then(|e| e.ambient_occlusion.as_ref());
    let bent = wanted.is_some_and(|a| a.bent_normals);
    let use_tree = wanted.is_some_and(|a| a.hierarchy) || stage.surfels.len() > settings.max_brute;
    let history = &runs.iter().find(|(h, _)| *h == use_tree).unwrap_or(&runs[runs.len() - 1]).1;
    let bounces = scene.effects.as_ref().and_then(|e| e.indirect).map_or(0, |i| i.bounces);
    let gathered = |a: &Accessibility| {
        indirect.map(|(direct, _)| {
            surfel_indirect(&stage.surfels, &stage.albedo, direct, &EmitterWeight::One.weights(&a.values), settings.form, bounces)
        })
    };
    let reference_lighting = Lighting {
        accessibility: Shown::PerVertex(&reference.values),
        indirect: indirect.map(|(_, r)| r.values.as_slice()),
        bent_normals: None,
    };
    // Each shown variant's lighting is gathered once and rendered at every size asked for.
    let shown: Vec<(&Accessibility, Option<Vec<Rgb>>)> = history.iter().take(4).map(|a| (a, gathered(a))).collect();
    let variants = |[width, height]: [u32; 2]| {
        let camera = Camera::new(&scene.camera, 0, width, height);
        let truth = render(stage, &camera, &reference_lighting);
        let frames: Vec<TracedFrame> = shown
            .iter()
            .map(|(a, light)| {
                let lighting = Lighting {
                    accessibility: Shown::PerVertex(&a.values),
                    indirect: light.as_deref(),
                    bent_normals: bent.then_some(a.bent_normals.as_slice()),
                };
                render(stage, &camera, &lighting)
            })
            .collect();
        (truth, frames)
    };
    for (a, _) in shown.iter().skip(1) {
        report.signed_maps.push(SignedMap {
            stem: format!("ao_passes{}_signed", a.passes),
            technique: "surfels",
            width: settings.resolution[0],
            height: settings.resolution[1],
            values: coverage.iter().map(|p| p.map(|p| p.interpolate(&a.values) - p.interpolate(&reference.values))).collect(),
        });
    }
    // GTAO's picture takes the reference's indirect light, so that it differs from the
    // reference by accessibility alone.
    let gtao_picture = |camera: &Camera, values: &[Option<f64>]| {
        let lighting = Lighting { accessibility: Shown::PerPixel(values), bent_normals: None, ..reference_lighting };
        render(stage, camera, &lighting)
    };
    let (truth, frames) = variants(settings.resolution);
    for (pass, frame) in frames.iter().enumerate() {
        let stem = if pass == 0 { "ao_none".to_string() } else { format!("ao_passes{pass}") };
        report.pictures.push(Picture { stem, frame: frame.clone(), reference: Some(truth.clone()) });
    }
    if indirect.is_some() {
        stats.indirect_bounces += bounces as u64 * frames.len() as u64;
    }
    let mut panels = surfel_panels(frames, &shown, use_tree, coverage, &reference.values);
    if let Some((g, values)) = gtao {
        let frame = gtao_picture(camera, values);
        report.pictures.push(Picture { stem: "ao_gtao".into(), frame: frame.clone(), reference: Some(truth.clone()) });
        let errors: Vec<f64> = coverage
            .iter()
            .zip(values)
            .filter_map(|(p, v)| p.as_ref().zip(*v).map(|(p, v)| v - p.interpolate(&reference.values)))
            .collect();
        let label = format!("GTAO {}", g.label());
        let label = match ErrorSummary::of(&errors) {
            Some(e) => format!("{label}\nmean |Δ| {:.3}/px", e.mean),
            None => label,
        };
        panels.push(Panel { label, frame });
    }
    panels.push(Panel { label: REFERENCE_LABEL.into(), frame: truth.clone() });
    report.pictures.push(Picture { stem: "ao_reference".into(), frame: truth, reference: None });
    report.pictures.push(Picture { stem: "ao_side_by_side".into(), frame: labels::side_by_side(&panels), reference: None });
    if let Some(size) = settings.hero {
        let (truth, frames) = variants(size);
        let gather = if use_tree { "tree" } else { "brute force" };
        let gtao_panel = gtao.map(|(g, _)| {
            let camera = Camera::new(&scene.camera, 0, size[0], size[1]);
            let frame = gtao_frame(stage, &camera, &stage.coverage(&camera), g);
            HeroPanel {
                stem: "gtao".into(),
                label: format!("GTAO {}", g.label()),
                method: "gtao".into(),
                configuration: None,
                passes: None,
                frame: gtao_picture(&camera, &frame.values),
            }
        });
        let panels = frames
            .into_iter()
            .enumerate()
            .map(|(pass, frame)| HeroPanel {
                stem: if pass == 0 { "none".into() } else { format!("passes{pass}_{}", gather.replace(' ', "_")) },
                label: if pass == 0 { "no AO".into() } else { format!("surfel AO, {pass} pass(es), {gather}") },
                method: if pass == 0 { "none".into() } else { gather.to_string() },
                configuration: None,
                passes: Some(pass as u32),
                frame,
            })
            .chain(gtao_panel)
            .collect();
        report.hero = Some(HeroSet {
            effect: crate::scene::EffectFamily::Surfels,
            reference_label: format!("reference: ray-traced accessibility, {} rays per vertex", settings.rays.rays),
            reference: truth,
            panels,
            mask: ErrorMask::Whole,
        });
    }
}

/// GTAO's rows, per configuration and object, per pixel on the same frame and against the
/// same interpolated reference as the surfels' per-pixel figures (and against occluders
/// within the search radius); the first configuration's signed map. Returns the first
/// configuration's per-pixel accessibility, the one pictured.
fn gtao_rows(
    m: &Measured,
    settings: &AoSettings,
    gtao_settings: &[crate::scene::surfels::Gtao],
    report: &mut AoReport,
    log: &mut dyn FnMut(&str),
) -> Option<Vec<Option<f64>>> {
    let Measured { stage, camera, coverage, reference, .. } = *m;
    let mut pictured = None;
    // The range-limited references, one per search radius (radius × multiplier).
    let mut within_references: Vec<(f64, super::reference::ReferenceAccessibility)> = Vec::new();
    for (configuration, &g) in gtao_settings.iter().enumerate() {
        let frame = gtao_frame(stage, camera, coverage, g);
        let search_radius = g.radius * g.heuristics.radius_multiplier;
        if !within_references.iter().any(|(r, _)| *r == search_radius) {
            // Rays one by one (no packets), at most 1024 per vertex.
            let rays = RaySettings { rays: settings.rays.rays.min(1024), ..settings.rays };
            within_references.push((search_radius, reference_accessibility_within(&stage.geometry, &stage.surfels, rays, search_radius)));
        }
        let within = &within_references.iter().find(|(r, _)| *r == search_radius).expect("computed above").1;
        let all_pixels = |truth: &[f64]| {
            let errors: Vec<f64> =
                coverage.iter().zip(&frame.values).filter_map(|(p, v)| p.as_ref().zip(*v).map(|(p, v)| v - p.interpolate(truth))).collect();
            ErrorSummary::of(&errors)
        };
        if let (Some(full), Some(limited)) = (all_pixels(&reference.values), all_pixels(&within.values)) {
            log(&format!(
                "  all objects gtao ({}): |a − ref| over every covered pixel mean {:.4} (signed {:+.4}), p90 {:.4}, p99 {:.4}; against occluders within {search_radius}: mean {:.4} (signed {:+.4}), p90 {:.4}, p99 {:.4}; {} pixels, {:.1} ms",
                g.label(),
                full.mean,
                full.signed_mean,
                full.p90,
                full.p99,
                limited.mean,
                limited.signed_mean,
                limited.p90,
                limited.p99,
                full.count,
                frame.cpu_ms
            ));
        }
        for (index, object) in stage.objects.iter().enumerate() {
            let range = object.surfels.clone();
            let pixels: Vec<f64> = coverage
                .iter()
                .zip(&frame.values)
                .filter_map(|(p, v)| p.as_ref().filter(|p| p.object == index).zip(*v).map(|(p, v)| v - p.interpolate(&reference.values)))
                .collect();
            let errors_within: Vec<f64> = coverage
                .iter()
                .zip(&frame.values)
                .filter_map(|(p, v)| p.as_ref().filter(|p| p.object == index).zip(*v).map(|(p, v)| v - p.interpolate(&within.values)))
                .collect();
            let within_radius = ErrorSummary::of(&errors_within);
            let accessibility = AccessibilityErrors {
                per_vertex: ErrorSummary::NONE,
                area_weighted: None,
                per_pixel: ErrorSummary::of(&pixels),
                defect_vertices: stage.defects[range.clone()].iter().filter(|&&d| d).count(),
                without_defects: None,
            };
            if let Some(p) = accessibility.per_pixel {
                log(&format!(
                    "  {} gtao ({}): |a − ref| per pixel mean {:.4} (signed {:+.4}), median {:.4}, p90 {:.4}, p99 {:.4}, max {:.4} over {} pixels; against occluders within the radius: {:.4} (signed {:+.4}, p90 {:.4}, p99 {:.4}); {:.1} ms",
                    object.name,
                    g.label(),
                    p.mean,
                    p.signed_mean,
                    p.median,
                    p.p90,
                    p.p99,
                    p.max,
                    p.count,
                    within_radius.map_or(0.0, |w| w.mean),
                    within_radius.map_or(0.0, |w| w.signed_mean),
                    within_radius.map_or(0.0, |w| w.p90),
                    within_radius.map_or(0.0, |w| w.p99),
                    frame.cpu_ms
                ));
            }
            report.rows.push(ErrorRow {
                mesh: object.name.clone(),
                technique: Technique::Gtao(g),
                surfels: range.len(),
                receiver_gain: settings.form.receiver_gain,
                passes: 0,
                hierarchy: false,
                accessibility,
                reference_standard_error: mean(range.clone().map(|i| reference.standard_errors[i]), range.len()),
                bent_normals: None,
                interactions: frame.reads,
                cpu_ms: frame.cpu_ms,
                indirect_mean_error: None,
                indirect_signed_error: None,
                indirect_accessibility_weighted_mean_error: None,
                indirect_accessibility_weighted_signed_error: None,
                indirect_reference_mean: None,
                indirect_reference_standard_error: None,
                within_radius,
            });
        }
        if configuration == 0 {
            report.signed_maps.push(SignedMap {
                stem: "ao_gtao_signed".into(),
                technique: "gtao",
                width: settings.resolution[0],
                height: settings.resolution[1],
                values: coverage
                    .iter()
                    .zip(&frame.values)
                    .map(|(p, v)| p.as_ref().zip(*v).map(|(p, v)| v - p.interpolate(&reference.values)))
                    .collect(),
            });
            pictured = Some(frame.values);
        }
    }
    pictured
}

/// GTAO over one frame: per pixel accessibility, the G-buffer reads it took, CPU time.
struct GtaoFrame {
    values: Vec<Option<f64>>,
    reads: u64,
    cpu_ms: f64,
}

/// GTAO over `camera`'s frame from what its pixels see (`coverage`): the G-buffer of points
/// and smooth normals interpolated from the vertices, as a rasteriser writes them.
fn gtao_frame(stage: &SurfelScene, camera: &Camera, coverage: &[Option<PixelSample>], g: crate::scene::surfels::Gtao) -> GtaoFrame {
    let gbuffer = GBuffer::from_coverage(camera, coverage, &stage.surfels);
    let start = std::time::Instant::now();
    let parameters = Parameters::of(g);
    let values = gtao(&gbuffer, parameters);
    let cpu_ms = start.elapsed().as_secs_f64() * 1e3;
    let covered = coverage.iter().flatten().count() as u64;
    GtaoFrame { values, reads: covered * parameters.reads_per_pixel(), cpu_ms }
}

/// The name of surfel AO's way of gathering emitters in tables and labels.
pub fn technique(hierarchy: bool) -> &'static str {
    if hierarchy {
        "tree"
    } else {
        "brute force"
    }
}

/// The side-by-side picture's label of the reference panel.
pub const REFERENCE_LABEL: &str = "ray-traced reference";

/// The mean over the pixels that see a surface of |interpolated `values` − interpolated
/// `reference`| (every object together: the figure of a whole picture); `None` where no
/// pixel sees one.
pub fn picture_mean_error(coverage: &[Option<PixelSample>], values: &[f64], reference: &[f64]) -> Option<f64> {
    let errors: Vec<f64> = coverage.iter().flatten().map(|p| p.interpolate(values) - p.interpolate(reference)).collect();
    ErrorSummary::of(&errors).map(|s| s.mean)
}

/// The label of a surfel picture: the technique ("no AO" for 0 passes) and, on a line of
/// its own, its accessibility error per covered pixel.
pub fn surfel_label(passes: u32, hierarchy: bool, error: Option<f64>) -> String {
    let technique = match passes {
        0 => "no AO".to_string(),
        1 => format!("surfel AO, 1 pass, {}", technique(hierarchy)),
        p => format!("surfel AO, {p} passes, {}", technique(hierarchy)),
    };
    match error {
        Some(e) => format!("{technique}\nmean |Δ| {e:.3}/px"),
        None => technique,
    }
}

/// The side-by-side picture's panels of the shown surfel variants (no AO, 1, 2, 3 passes),
/// each labelled with its technique and its error per covered pixel.
fn surfel_panels(
    frames: Vec<TracedFrame>,
    shown: &[(&Accessibility, Option<Vec<Rgb>>)],
    hierarchy: bool,
    coverage: &[Option<PixelSample>],
    reference: &[f64],
) -> Vec<Panel> {
    frames
        .into_iter()
        .zip(shown)
        .map(|(frame, (a, _))| Panel {
            label: surfel_label(a.passes, hierarchy, picture_mean_error(coverage, &a.values, reference)),
            frame,
        })
        .collect()
}

/// One frame of the scene lit with per-vertex `lighting`.
fn render(stage: &SurfelScene, camera: &Camera, lighting: &Lighting) -> TracedFrame {
    let ambient: Rgb = stage.lights.iter().fold([0.0; 3], |sum, light| match light {
        LightSource::Ambient { colour } => std::array::from_fn(|c| sum[c] + colour[c]),
        _ => sum,
    });
    let pixels: Vec<(Rgb, u64)> = (0..camera.width * camera.height)
        .into_par_iter()
        .map(|i| {
            let direction = camera.ray(i % camera.width, i / camera.width);
            let Some(hit) = stage.geometry.nearest(camera.eye, direction, None, |_| true) else { return ([0.0; 3], 1) };
            let (corners, w) = stage.corners(hit.triangle as usize, hit.point);
            let blend = |f: &dyn Fn(usize) -> f64| w[0] * f(corners[0]) + w[1] * f(corners[1]) + w[2] * f(corners[2]);
            let a = match lighting.accessibility {
                Shown::PerVertex(values) => blend(&|v| values[v]),
                Shown::PerPixel(values) => values.get(i as usize).copied().flatten().unwrap_or(1.0),
            };
            let albedo: Rgb = std::array::from_fn(|c| blend(&|v| stage.albedo[v][c]));
            // The side the camera sees: a back face is lit as its front would be from there.
            let normal = if hit.normal.dot(direction) > 0.0 { -hit.normal } else { hit.normal };
            let shading_normal = match lighting.bent_normals {
                Some(bent) => {
                    let b = corners.iter().zip(w).fold(DVec3::ZERO, |sum, (&v, weight)| sum + bent[v] * weight);
                    let b = b.try_normalize().unwrap_or(normal);
                    if b.dot(normal) < 0.0 {
                        normal
                    } else {
                        b
                    }
                }
                None => normal,
            };
            let direct = direct_irradiance(&stage.geometry, hit.point, shading_normal, &stage.lights, 1e-6);
            let indirect: Rgb = match lighting.indirect {
                Some(values) => std::array::from_fn(|c| blend(&|v| values[v][c])),
                None => [0.0; 3],
            };
            (std::array::from_fn(|c| albedo[c] * (ambient[c] * a + direct[c] + indirect[c])), 1 + stage.lights.len() as u64)
        })
        .collect();
    TracedFrame {
        width: camera.width,
        height: camera.height,
        rays: pixels.iter().map(|p| p.1).sum(),
        seen: vec![None; pixels.len()],
        radiance: pixels.into_iter().map(|p| p.0).collect(),
    }
}

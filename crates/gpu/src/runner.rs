//! The scene runner: computes only what the scene names.
//!
//! - Pages: only the scene's materials are ingested (`Selection::pages`).
//! - Pipelines (one per method and pass, compiled on first use):
//!   `timing` → one fullscreen pipeline per named method (with `subtract`: blended over
//!   the expensive `burner`, + the burner's own pipeline);
//!   `image_error` → one mesh pipeline per named method + the `exact` mesh pipeline as the
//!   reference (the same pipeline when `exact` is named).
//! - Textures: a LUT is baked only for a material some object renders with `lut`.
//! - Effects: a scene naming `reflection` or `refraction` renders one distance map per
//!   specular object and compiles one shading pipeline per (effect, method)
//!   (`super::effects`); its measurements replace the F-only passes. Surfel ambient
//!   occlusion and indirect light run only when named (`super::passes::ao`).

use nklut_tables::gpu_tables::{gpu_timing, image_errors};
use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Result};
use wgpu::util::DeviceExt;

use super::camera;
use super::context::{AdapterLine, Gpu};
use super::effects::EffectsRun;
use super::image_error::{self, ErrorSummary};
use super::lut;
use super::mesh;
use super::params::{self, MaterialUniform};
use super::render::{
    padded_row_bytes, readback_buffer, Draw, MaterialBinding, Renderer, Shade, Target, ViewUniform, DISPLAY_TARGET, FLOAT_TARGET,
};
use super::sampling::{self, PairKind, Plan, SampleStats};
use super::timing::{FresnelClock, Stopwatch, Timer};
use nklut_effects::experiment::EffectsStats;
use nklut_effects::scene::{read_materials, EffectFamily, Experiment, MeshSource, Scene, SceneError, SceneMaterial, SceneProblem, Shading};
use nklut_optics::db::Database;
use nklut_optics::fresnel::Method;
use nklut_optics::spectrum::Kind;
use nklut_pipeline::ingest;
use nklut_pipeline::output::{Table, TableFiles};

/// What a run created and touched, and what it skipped.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunStats {
    pub pipelines_compiled: usize,
    pub shader_modules_compiled: usize,
    /// Catalog pages ingested (only the scene's materials).
    pub pages_touched: usize,
    /// LUT textures baked (one per material rendered with `lut`).
    pub textures_baked: usize,
    /// Image-error frames rendered (each with the reference and every method).
    pub frames_rendered: u64,
    /// Timed passes, warm-up included.
    pub timed_passes: u64,
    /// The effects' counters: distance maps (cube maps) and their layers, reference and
    /// distance-map frames, surfels, tree nodes, passes, bounces — zero unless the scene
    /// names the effect.
    pub effects: EffectsStats,
    /// Specular-effect shading pipelines compiled (one per effect and method named).
    pub effect_pipelines: usize,
    /// Of those, the ones with the refraction branch (none unless the scene names refraction).
    pub refraction_pipelines: usize,
    pub skipped: Vec<String>,
    /// Measurements that failed after others had finished (their rows are kept and written).
    pub failures: Vec<String>,
}

impl fmt::Display for RunStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} pipelines compiled ({} shader modules), {} pages touched, {} textures baked, {} frames rendered, {} passes timed",
            self.pipelines_compiled,
            self.shader_modules_compiled,
            self.pages_touched,
            self.textures_baked,
            self.frames_rendered,
            self.timed_passes
        )?;
        let e = &self.effects;
        write!(
            f,
            ", {} cube maps × {} layers, {} effect pipelines ({} with refraction), {} reference frames",
            e.cube_maps, e.layers, self.effect_pipelines, self.refraction_pipelines, e.reference_frames
        )?;
        write!(
            f,
            ", {} surfels, {} tree nodes, {} AO passes, {} indirect bounces",
            e.surfels, e.tree_nodes, e.ao_passes, e.indirect_bounces
        )?;
        for skipped in &self.skipped {
            write!(f, "\n  skipped: {skipped}")?;
        }
        for failure in &self.failures {
            write!(f, "\n  failed: {failure}")?;
        }
        Ok(())
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct TimingRow {
    pub material: String,
    pub method: Shading,
    /// The formula timed for `exact`: the dielectric one (k = 0) on a dielectric material,
    /// the complex one on a conductor (the study's anchors); empty for the other methods.
    pub formula: &'static str,
    pub timer: Timer,
    pub resolution: [u32; 2],
    /// F evaluations per pixel in each timed pass (the amplification).
    pub evaluations: u32,
    /// The timer's resolution estimated from its readings (ns).
    pub timer_resolution_ns: f64,
    /// The seed of the pairs' order.
    pub seed: u64,
    /// Every timed sample (ms), in the order taken.
    pub samples: Vec<f64>,
    pub stats: SampleStats,
    pub relative_to_exact: Option<f64>,
    pub relative_to_fetch: Option<f64>,
    pub relative_to_exact_dielectric: Option<f64>,
}

/// The formula `exact` is timed by on a material of `kind` (the study's anchors).
pub fn exact_formula(kind: Kind) -> &'static str {
    match kind {
        Kind::Dielectric => "dielectric (k = 0)",
        Kind::Conductor => "complex",
    }
}

/// The shader a timed pair draws: `exact` on a dielectric by the dielectric formula.
pub fn timed_shade(method: Shading, kind: Kind) -> Shade {
    match (method, kind) {
        (Shading::Fresnel(Method::Exact), Kind::Dielectric) => Shade::ExactDielectric,
        _ => Shade::Method(method),
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ImageErrorRow {
    pub material: String,
    pub method: Shading,
    pub object: String,
    pub frames: u32,
    pub resolution: [u32; 2],
    /// `None` where no covered pixel had a reference above 0.
    pub mean_rel_error: Option<f64>,
    pub max_rel_error: f64,
    pub pixels: u64,
    pub skipped_zero_reference: u64,
}

pub struct RunReport {
    pub adapter: AdapterLine,
    pub experiments: Vec<Experiment>,
    pub stats: RunStats,
    pub timing: Vec<TimingRow>,
    pub image_errors: Vec<ImageErrorRow>,
    /// The specular effects' measurements (empty unless the scene names them).
    pub effects: EffectsRun,
}

/// A material of the scene, ready to bind.
struct BoundMaterial {
    kind: Kind,
    binding: MaterialBinding,
}

/// A mesh on the GPU.
struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// Run `scene` on `gpu`, its pages read with `config` (channel wavelengths, coverage).
/// `log` receives progress lines.
pub fn run(scene: &Scene, db: &Database, config: &ingest::Config, gpu: &Gpu, log: &mut dyn FnMut(&str)) -> Result<RunReport> {
    run_opening(scene, &|| Ok(db.clone()), config, gpu, log)
}

/// [`run`], opening the database with `open_db` only when the scene names materials: a
/// scene of diffuse objects alone (ambient occlusion, indirect light) reads none.
pub fn run_opening(
    scene: &Scene,
    open_db: &dyn Fn() -> Result<Database>,
    config: &ingest::Config,
    gpu: &Gpu,
    log: &mut dyn FnMut(&str),
) -> Result<RunReport> {
    let mut stats = RunStats::default();
    let materials = if scene.materials().is_empty() {
        Vec::new()
    } else {
        let (materials, pages) = read_materials(scene, &open_db()?, config)?;
        stats.pages_touched = pages;
        materials
    };
    run_with_materials(scene, &materials, gpu, stats, log)
}

/// Run `scene` with the channel indices already known (`material` ids of the scene map to
/// these entries; used by `run` and by tests).
pub fn run_with_materials(
    scene: &Scene,
    materials: &[SceneMaterial],
    gpu: &Gpu,
    mut stats: RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<RunReport> {
    let specular_effects = scene.names_effect(EffectFamily::SpecularPaths);
    let mut effects = EffectsRun::default();
    // One arm per family, no wildcard: a family added to the scene does not compile until
    // the GPU runs it here.
    for family in EffectFamily::ALL.into_iter().filter(|&family| scene.names_effect(family)) {
        match family {
            EffectFamily::SpecularPaths => effects = super::effects::run_scene(scene, materials, gpu, &mut stats, log)?,
            EffectFamily::Surfels => {
                super::passes::ao::run_scene(scene, gpu, &mut stats.effects, log)?;
            }
        }
    }
    if !specular_effects {
        stats.skipped.push("reflection, refraction: not in the scene's effects (no cube map, no effect pipeline)".into());
    } else if scene.effects.as_ref().is_none_or(|e| e.refraction.is_none()) {
        stats.skipped.push("refraction: not in the scene's effects (reflection-only pipelines)".into());
    }
    let (timing, image_errors) = if specular_effects {
        stats.skipped.push("F-only passes: the scene's effects take its measurements (effects_timing, effects_errors)".into());
        (Vec::new(), Vec::new())
    } else {
        run_fresnel_only(scene, materials, gpu, &mut stats, log)?
    };
    Ok(RunReport { adapter: gpu.line.clone(), experiments: scene.experiments.clone(), stats, timing, image_errors, effects })
}

/// The F-only passes of a scene without specular effects: timing of F(c) on a fullscreen
/// ramp and image error of F(|N·V|) on the bare objects.
fn run_fresnel_only(
    scene: &Scene,
    materials: &[SceneMaterial],
    gpu: &Gpu,
    stats: &mut RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<(Vec<TimingRow>, Vec<ImageErrorRow>)> {
    let mut renderer = Renderer::new(gpu);
    let mut bound = HashMap::new();
    let mut baked = Vec::new();
    for SceneMaterial { page, optics, .. } in materials {
        let prepared = params::prepare(&optics.channels);
        let uniform = MaterialUniform::from_prepared(&prepared);
        let wants_lut = scene.specular_objects().any(|(_, s)| s.material == *page && s.shadings.contains(&Shading::Fresnel(Method::Lut)));
        let lut_view = wants_lut.then(|| {
            let texture = lut::upload(gpu, &lut::texels(&prepared, scene.lut.size as usize), page);
            stats.textures_baked += 1;
            baked.push(page.clone());
            texture.create_view(&Default::default())
        });
        bound.insert(page.clone(), BoundMaterial { kind: optics.kind, binding: renderer.bind(gpu, &uniform, lut_view.as_ref())? });
    }
    if baked.is_empty() {
        stats.skipped.push("LUT bake: no object uses the lut method".into());
    }
    let unnamed: Vec<&str> = Shading::ALL.iter().filter(|m| !scene.shadings().contains(m)).map(|m| m.name()).collect();
    if !unnamed.is_empty() {
        stats.skipped.push(format!("methods not in the scene (no pipelines): {}", unnamed.join(", ")));
    }
    let mut timing = Vec::new();
    if scene.wants(Experiment::Timing) && scene.material_shadings().is_empty() {
        // An AO scene names no (material, method) pair: nothing for the F-only passes.
        stats.skipped.push("timing: the scene names no (material, method) pair (AO passes: `nklut gpu ao-timing`)".into());
    } else if scene.wants(Experiment::Timing) {
        timing = run_timing(scene, &bound, gpu, &mut renderer, stats, log)?;
    } else {
        stats.skipped.push("timing: not in the scene's measurements".into());
    }
    let mut image_errors = Vec::new();
    if scene.wants(Experiment::ImageError) {
        // A failure here keeps the timing measured before it.
        match run_image_error(scene, &bound, gpu, &mut renderer, stats, log) {
            Ok(rows) => image_errors = rows,
            Err(error) if !timing.is_empty() => stats.failures.push(format!("image_error: {error:#}")),
            Err(error) => return Err(error),
        }
    } else {
        stats.skipped.push("image_error: not in the scene's measurements".into());
    }
    stats.pipelines_compiled = renderer.created.pipelines;
    stats.shader_modules_compiled = renderer.created.shader_modules;
    Ok((timing, image_errors))
}

fn run_timing(
    scene: &Scene,
    bound: &HashMap<String, BoundMaterial>,
    gpu: &Gpu,
    renderer: &mut Renderer,
    stats: &mut RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<TimingRow>> {
    let settings = &scene.timing;
    let [width, height] = settings.resolution;
    let target = Target::new(gpu, width, height, DISPLAY_TARGET, false)?;
    let mut stopwatch = Stopwatch::new(gpu)?;
    let burner =
        if settings.subtract { Some(renderer.pipeline(gpu, Shade::Burner, Draw::Fullscreen(DISPLAY_TARGET))?.clone()) } else { None };
    log(&format!(
        "timing: {width}x{height}, {} warm-up + {} timed rounds over every (material, method) in a seeded order, a throwaway pass leading each submit, timer {}{}",
        settings.warmup,
        settings.repeats,
        stopwatch.timer().name(),
        if settings.subtract { ", subtracting the burner pass" } else { "" }
    ));
    let pairs = scene.material_shadings();
    let measured_pass = if settings.subtract { Draw::FullscreenOver(DISPLAY_TARGET) } else { Draw::Fullscreen(DISPLAY_TARGET) };
    let mut pipelines = Vec::new();
    for (page, method) in &pairs {
        pipelines.push(renderer.pipeline(gpu, timed_shade(*method, bound[page].kind), measured_pass)?.clone());
    }
    let draws: Vec<_> = pairs
        .iter()
        .zip(&pipelines)
        .map(|((page, _), pipeline)| ((pipeline, &bound[page].binding.bind_group), &bound[page].binding.view))
        .collect();
    let kinds: Vec<PairKind> = pairs.iter().map(|(_, method)| PairKind { baseline: !matches!(method, Shading::Fresnel(_)) }).collect();
    // The study's subtraction is timed as the study did, one evaluation per pixel: the
    // burner shares the pass and would be amplified with the method.
    let amplify = settings.amplify && !settings.subtract;
    if settings.amplify && settings.subtract {
        stats.skipped.push("amplification: not with subtract (the study's method, one evaluation per pixel)".into());
    }
    let plan = Plan { warmup: settings.warmup, repeats: settings.repeats, amplify, seed: settings.seed };
    let mut clock = FresnelClock {
        gpu,
        target: &target,
        stopwatch: &mut stopwatch,
        draws,
        burner: burner.as_ref(),
        resolution: settings.resolution,
        written: None,
    };
    let measurement = sampling::measure(&mut clock, &kinds, &plan)?;
    clock.reset();
    log(&format!(
        "  {} F evaluations per pixel (calibration {}); {} warm-up rounds; timer resolution {:.0} ns{}; sample target {:.3} ms; order seed {}{}",
        measurement.evaluations,
        measurement.calibration.iter().map(|(n, ms)| format!("{n}: {ms:.4} ms")).collect::<Vec<_>>().join(", "),
        measurement.warmup_rounds,
        measurement.resolution_ns,
        if measurement.floor_ms > 0.0 { format!(", wall floor {:.4} ms", measurement.floor_ms) } else { String::new() },
        measurement.target_ms,
        measurement.seed,
        if measurement.capped { " (amplification capped: the target was not reached)" } else { "" }
    ));
    let pixels = width as u64 * height as u64;
    let mut rows = Vec::new();
    for ((page, method), samples) in pairs.into_iter().zip(measurement.samples.iter()) {
        let stats = sampling::stats(samples, measurement.evaluations, pixels, &measurement);
        log(&format!(
            "  {page} {method}: median {:.4} ms, IQR {:.4} ms, n {}, {:.4} ns per evaluation per pixel{}",
            stats.median_ms,
            stats.spread_ms,
            stats.n,
            stats.ns_per_evaluation,
            if stats.near_resolution { " (within 10 × the timer's resolution or 2 × its floor)" } else { "" }
        ));
        let kind = bound[&page].kind;
        rows.push(TimingRow {
            formula: if method == Shading::Fresnel(Method::Exact) { exact_formula(kind) } else { "" },
            material: page,
            method,
            timer: stopwatch.timer(),
            resolution: settings.resolution,
            evaluations: measurement.evaluations,
            timer_resolution_ns: measurement.resolution_ns,
            seed: measurement.seed,
            samples: samples.clone(),
            stats,
            relative_to_exact: None,
            relative_to_fetch: None,
            relative_to_exact_dielectric: None,
        });
    }
    stats.timed_passes += stopwatch.passes;
    relate(&mut rows, &|page| bound[page].kind);
    if !rows.iter().any(|r| r.relative_to_exact_dielectric.is_some()) {
        stats.skipped.push("relative_to_exact_dielectric: the scene does not time exact on a dielectric material".into());
    }
    Ok(rows)
}

/// Each row's median relative to exact's and to the bare fetch's (`texture`) on the same
/// material, and to exact's on the first dielectric material timed (the study's
/// normalisation).
pub fn relate(rows: &mut [TimingRow], kind: &dyn Fn(&str) -> Kind) {
    let median = |rows: &[TimingRow], material: &str, method: Shading| {
        rows.iter().find(|r| r.material == material && r.method == method).map(|r| r.stats.median_ms).filter(|m| *m > 0.0)
    };
    let reference = rows
        .iter()
        .find(|r| r.method == Shading::Fresnel(Method::Exact) && kind(&r.material) == Kind::Dielectric)
        .map(|r| r.stats.median_ms)
        .filter(|m| *m > 0.0);
    let related: Vec<(Option<f64>, Option<f64>)> = rows
        .iter()
        .map(|r| (median(rows, &r.material, Shading::Fresnel(Method::Exact)), median(rows, &r.material, Shading::Texture)))
        .collect();
    for (row, (exact, fetch)) in rows.iter_mut().zip(related) {
        row.relative_to_exact = exact.map(|e| row.stats.median_ms / e);
        row.relative_to_fetch = fetch.map(|f| row.stats.median_ms / f);
        row.relative_to_exact_dielectric = reference.map(|e| row.stats.median_ms / e);
    }
}

fn upload_mesh(gpu: &Gpu, mesh: &mesh::Mesh) -> GpuMesh {
    let vertices = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mesh vertices"),
        contents: bytemuck::cast_slice(&mesh.interleaved()),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let indices = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("mesh indices"),
        contents: bytemuck::cast_slice(&mesh.indices),
        usage: wgpu::BufferUsages::INDEX,
    });
    GpuMesh { vertices, indices, index_count: mesh.indices.len() as u32 }
}

fn run_image_error(
    scene: &Scene,
    bound: &HashMap<String, BoundMaterial>,
    gpu: &Gpu,
    renderer: &mut Renderer,
    stats: &mut RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<ImageErrorRow>> {
    let [width, height] = scene.resolution;
    let camera_path = &scene.camera;
    log(&format!(
        "image error: {width}x{height}, {} frames {}° apart around {:?} at {} m",
        camera_path.frames, camera_path.degrees_per_frame, camera_path.axis, camera_path.distance
    ));
    let mut meshes: HashMap<MeshSource, GpuMesh> = HashMap::new();
    let mut rows = Vec::new();
    let (budget, mut triangles) = (nklut_pipeline::budget::MemoryBudget::of_machine(), 0u128);
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(specular) = object.specular() else { continue };
        if !meshes.contains_key(&object.mesh) {
            let mesh = mesh::load(&object.mesh, |p| scene.mesh_path(p))
                .map_err(|error| SceneError::new(&scene.file, SceneProblem::Mesh { object: i, error }))?;
            // The meshes held so far, this one included, before it is uploaded.
            triangles += mesh.triangles() as u128;
            nklut_effects::geometry::check_loaded(&budget, i, triangles, &object.mesh.label())
                .map_err(|e| SceneError::new(&scene.file, SceneProblem::Memory(e)))?;
            log(&format!("  mesh {}: {} triangles", object.mesh.label(), mesh.triangles()));
            meshes.insert(object.mesh.clone(), upload_mesh(gpu, &mesh));
        }
        let gpu_mesh = &meshes[&object.mesh];
        let material = &bound[&specular.material];
        let reference = renderer.pipeline(gpu, Shade::Method(Shading::Fresnel(Method::Exact)), Draw::Mesh)?.clone();
        let mut pipelines = Vec::new();
        for method in &specular.shadings {
            pipelines.push(renderer.pipeline(gpu, Shade::Method(*method), Draw::Mesh)?.clone());
        }
        // Sizes against the device's limits before any allocation: one readback of every
        // target (the reference and each method) per frame.
        let image_bytes = padded_row_bytes(width, 16) as u64 * height as u64;
        let buffer = readback_buffer(gpu, image_bytes * (pipelines.len() as u64 + 1))
            .map_err(|e| anyhow!("scene {}: {e:#}", scene.file.display()))?;
        let targets =
            (0..=pipelines.len()).map(|_| Target::new(gpu, width, height, FLOAT_TARGET, true)).collect::<Result<Vec<Target>>>()?;
        let mut summaries = vec![ErrorSummary::default(); pipelines.len()];
        for frame in 0..camera_path.frames {
            let view = ViewUniform::camera(&camera::frame(camera_path, frame, width, height), width, height);
            gpu.queue.write_buffer(&material.binding.view, 0, bytemuck::bytes_of(&view));
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            for (i, (target, pipeline)) in targets.iter().zip(std::iter::once(&reference).chain(&pipelines)).enumerate() {
                {
                    let mut pass = target.begin(&mut encoder, None);
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &material.binding.bind_group, &[]);
                    pass.set_vertex_buffer(0, gpu_mesh.vertices.slice(..));
                    pass.set_index_buffer(gpu_mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..gpu_mesh.index_count, 0, 0..1);
                }
                target.copy_out(&mut encoder, &buffer, image_bytes * i as u64);
            }
            gpu.queue.submit([encoder.finish()]);
            let bytes = gpu.read_buffer(&buffer)?;
            let image = |i: usize| targets[i].decode(&bytes[image_bytes as usize * i..image_bytes as usize * (i + 1)]);
            let reference_image = image(0);
            for (m, summary) in summaries.iter_mut().enumerate() {
                summary.add(&image_error::compare(&image(m + 1), &reference_image));
            }
            stats.frames_rendered += 1;
        }
        for (method, summary) in specular.shadings.iter().zip(&summaries) {
            log(&format!(
                "  {} {} {}: mean relative error {}, max {:.3e} over {} pixels",
                object.mesh.label(),
                specular.material,
                method,
                summary.mean_relative().map_or("none (no lit pixel)".into(), |e| format!("{e:.3e}")),
                summary.max_relative,
                summary.pixels
            ));
            rows.push(ImageErrorRow {
                material: specular.material.clone(),
                method: *method,
                object: object.mesh.label(),
                frames: summary.frames,
                resolution: scene.resolution,
                mean_rel_error: summary.mean_relative(),
                max_rel_error: summary.max_relative,
                pixels: summary.pixels,
                skipped_zero_reference: summary.skipped_zero_reference,
            });
        }
    }
    Ok(rows)
}

fn resolution_text([w, h]: [u32; 2]) -> String {
    format!("{w}x{h}")
}

/// `gpu_timing.*`: one row per timed (material, method).
pub fn timing_table(report: &RunReport) -> Table {
    timing_rows_table(&report.timing, &report.adapter)
}

/// `gpu_timing.*` of `rows` measured on `a` (no rows: the columns alone, which the browser
/// bench's results follow).
pub fn timing_rows_table(rows: &[TimingRow], a: &AdapterLine) -> Table {
    let text = |f: &dyn Fn(&TimingRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let float = |f: &dyn Fn(&TimingRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(gpu_timing::ADAPTER, text(&|_| a.name.clone()))
        .put(gpu_timing::BACKEND, text(&|_| a.backend.clone()))
        .put(gpu_timing::DRIVER, text(&|_| a.driver.clone()))
        .put(gpu_timing::TIMER, text(&|r| r.timer.name().into()))
        .put(gpu_timing::METHOD, text(&|r| r.method.name().into()))
        .put(gpu_timing::FORMULA, text(&|r| r.formula.into()))
        .put(gpu_timing::MATERIAL, text(&|r| r.material.clone()))
        .put(gpu_timing::RESOLUTION, text(&|r| resolution_text(r.resolution)))
        .put(gpu_timing::EVALUATIONS, rows.iter().map(|r| r.evaluations as i64).collect())
        .put(gpu_timing::TIMER_RESOLUTION_NS, float(&|r| r.timer_resolution_ns))
        .put(gpu_timing::SEED, text(&|r| r.seed.to_string()))
        .put(gpu_timing::REPEATS, rows.iter().map(|r| r.stats.n as i64).collect())
        .put(gpu_timing::MEAN_MS, float(&|r| r.stats.mean_ms))
        .put(gpu_timing::MEDIAN_MS, float(&|r| r.stats.median_ms))
        .put(gpu_timing::SPREAD_MS, float(&|r| r.stats.spread_ms))
        .put(gpu_timing::NS_PER_EVALUATION, float(&|r| r.stats.ns_per_evaluation))
        .put(gpu_timing::RELATIVE_TO_EXACT, rows.iter().map(|r| r.relative_to_exact).collect())
        .put(gpu_timing::RELATIVE_TO_FETCH, rows.iter().map(|r| r.relative_to_fetch).collect())
        .put(gpu_timing::RELATIVE_TO_EXACT_DIELECTRIC, rows.iter().map(|r| r.relative_to_exact_dielectric).collect())
        .put(gpu_timing::NEAR_RESOLUTION, text(&|r| if r.stats.near_resolution { "yes" } else { "no" }.into()))
        .put(gpu_timing::SAMPLES_MS, text(&|r| r.samples.iter().map(|x| format!("{x:.6}")).collect::<Vec<_>>().join(" ")));
    table
}

/// `image_errors.*`: one row per (object, material, method).
pub fn image_error_table(report: &RunReport) -> Table {
    image_error_rows_table(&report.image_errors)
}

/// `image_errors.*` of `rows` (no rows: the columns alone).
pub fn image_error_rows_table(rows: &[ImageErrorRow]) -> Table {
    let text = |f: &dyn Fn(&ImageErrorRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(image_errors::MATERIAL, text(&|r| r.material.clone()))
        .put(image_errors::METHOD, text(&|r| r.method.name().into()))
        .put(image_errors::OBJECT, text(&|r| r.object.clone()))
        .put(image_errors::FRAMES, rows.iter().map(|r| r.frames as i64).collect())
        .put(image_errors::RESOLUTION, text(&|r| resolution_text(r.resolution)))
        .put(image_errors::MEAN_REL_ERROR, rows.iter().map(|r| r.mean_rel_error).collect())
        .put(image_errors::MAX_REL_ERROR, rows.iter().map(|r| r.max_rel_error).collect())
        .put(image_errors::PIXELS, rows.iter().map(|r| r.pixels as i64).collect())
        .put(image_errors::SKIPPED_ZERO_REFERENCE, rows.iter().map(|r| r.skipped_zero_reference as i64).collect());
    table
}

/// Publish the tables of the measurements the run took, and its frames, under `out` as
/// one set (`gpu`).
pub fn write_tables(report: &RunReport, out: &Path) -> Result<Vec<PathBuf>> {
    let effects = &report.effects;
    let mut tables: Vec<(Table, &str)> = Vec::new();
    if !effects.timing.is_empty() {
        tables.push((super::effects::timing_table(&effects.timing, &report.adapter), nklut_tables::effects_tables::effects_timing::STEM));
    } else if report.experiments.contains(&Experiment::Timing) && !report.timing.is_empty() {
        tables.push((timing_table(report), gpu_timing::STEM));
    }
    let mut frames = Vec::new();
    if !effects.errors.is_empty() {
        tables.push((nklut_effects::experiment::error_table(&effects.errors), nklut_tables::effects_tables::effects_errors::STEM));
        frames = nklut_effects::pictures::files("effects_gpu_frames", &effects.pictures)?;
    } else if report.experiments.contains(&Experiment::ImageError) {
        tables.push((image_error_table(report), image_errors::STEM));
    }
    let streamed: Vec<_> = tables.iter().flat_map(|(table, stem)| table.streamed_files(stem, false)).collect();
    let files: Vec<&dyn nklut_pipeline::output::SetContent> = streamed
        .iter()
        .map(|f| f as &dyn nklut_pipeline::output::SetContent)
        .chain(frames.iter().map(|f| f as &dyn nklut_pipeline::output::SetContent))
        .collect();
    nklut_pipeline::output::publish_contents(out, "gpu", &files)
}

//! The scene runner: computes only what the scene names.
//!
//! - Pages: only the scene's materials are ingested (`Selection { pages }`).
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
use super::timing::{median_and_iqr, Stopwatch, Timer};
use nklut_effects::experiment::EffectsStats;
use nklut_effects::scene::{read_materials, Experiment, MeshSource, Scene, SceneError, SceneMaterial, SceneProblem, Shading};
use nklut_optics::db::Database;
use nklut_optics::fresnel::Method;
use nklut_optics::spectrum::Kind;
use nklut_pipeline::ingest;
use nklut_pipeline::output::Table;

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
        Ok(())
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct TimingRow {
    pub material: String,
    pub method: Shading,
    pub timer: Timer,
    pub resolution: [u32; 2],
    pub repeats: u32,
    pub median_ms: f64,
    pub spread_ms: f64,
    pub relative_to_exact_dielectric: Option<f64>,
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
    let specular_effects = scene.names_effect(nklut_effects::scene::EffectFamily::SpecularPaths);
    let effects = super::effects::run_scene(scene, materials, gpu, &mut stats, log)?;
    if !specular_effects {
        stats.skipped.push("reflection, refraction: not in the scene's effects (no cube map, no effect pipeline)".into());
    } else if scene.effects.as_ref().is_none_or(|e| e.refraction.is_none()) {
        stats.skipped.push("refraction: not in the scene's effects (reflection-only pipelines)".into());
    }
    super::passes::ao::run_scene(scene, gpu, &mut stats.effects, log)?;
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
    if scene.wants(Experiment::Timing) {
        timing = run_timing(scene, &bound, gpu, &mut renderer, stats, log)?;
    } else {
        stats.skipped.push("timing: not in the scene's measurements".into());
    }
    let mut image_errors = Vec::new();
    if scene.wants(Experiment::ImageError) {
        image_errors = run_image_error(scene, &bound, gpu, &mut renderer, stats, log)?;
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
        "timing: {width}x{height}, {} warm-up + {} timed rounds over every (material, method), interleaved, timer {}{}",
        settings.warmup,
        settings.repeats,
        stopwatch.timer().name(),
        if settings.subtract { ", subtracting the burner pass" } else { "" }
    ));
    let pairs = scene.material_shadings();
    let measured_pass = if settings.subtract { Draw::FullscreenOver(DISPLAY_TARGET) } else { Draw::Fullscreen(DISPLAY_TARGET) };
    let mut pipelines = Vec::new();
    for (page, method) in &pairs {
        gpu.queue.write_buffer(&bound[page].binding.view, 0, bytemuck::bytes_of(&ViewUniform::fullscreen(width, height)));
        pipelines.push(renderer.pipeline(gpu, Shade::Method(*method), measured_pass)?.clone());
    }
    let draws: Vec<_> = pairs.iter().zip(&pipelines).map(|((page, _), pipeline)| (pipeline, &bound[page].binding.bind_group)).collect();
    let samples = stopwatch.measure_interleaved(gpu, &target, &draws, burner.as_ref(), settings)?;
    let mut rows = Vec::new();
    for ((page, method), samples) in pairs.into_iter().zip(samples) {
        let (median_ms, spread_ms) = median_and_iqr(&samples);
        log(&format!("  {page} {method}: median {median_ms:.4} ms, IQR {spread_ms:.4} ms"));
        rows.push(TimingRow {
            material: page,
            method,
            timer: stopwatch.timer(),
            resolution: settings.resolution,
            repeats: settings.repeats,
            median_ms,
            spread_ms,
            relative_to_exact_dielectric: None,
        });
    }
    stats.timed_passes += stopwatch.passes;
    // The study's normalisation: exact on a dielectric material.
    let reference = rows
        .iter()
        .find(|r| r.method == Shading::Fresnel(Method::Exact) && bound[&r.material].kind == Kind::Dielectric)
        .map(|r| r.median_ms);
    match reference {
        Some(reference) => rows.iter_mut().for_each(|r| r.relative_to_exact_dielectric = Some(r.median_ms / reference)),
        None => stats.skipped.push("relative_to_exact_dielectric: the scene does not time exact on a dielectric material".into()),
    }
    Ok(rows)
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
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(specular) = object.specular() else { continue };
        if !meshes.contains_key(&object.mesh) {
            let mesh = mesh::load(&object.mesh, |p| scene.mesh_path(p))
                .map_err(|error| SceneError::new(&scene.file, SceneProblem::Mesh { object: i, error }))?;
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
    let mut table = Table::new();
    table
        .text("adapter", "adapter name as the driver reports it", text(&|_| a.name.clone()))
        .text("backend", "wgpu backend", text(&|_| a.backend.clone()))
        .text("driver", "driver name and version", text(&|_| a.driver.clone()))
        .text("timer", "timestamp (GPU timestamp queries around the pass) or wall (CPU time around submit-and-wait)", text(&|r| r.timer.name().into()))
        .text("method", "Fresnel method (SPEC §5) or baseline (constant, texture)", text(&|r| r.method.name().into()))
        .text("material", "page id", text(&|r| r.material.clone()))
        .text("resolution", "fullscreen pass size WxH in pixels", text(&|r| resolution_text(r.resolution)))
        .integer("repeats", "timed passes (after warm-up)", rows.iter().map(|r| r.repeats as i64).collect())
        .float("median_ms", "median pass time (ms)", rows.iter().map(|r| r.median_ms).collect())
        .float("spread_ms", "interquartile range of the pass times (ms)", rows.iter().map(|r| r.spread_ms).collect())
        .optional_float(
            "relative_to_exact_dielectric",
            "median_ms / median_ms of exact on the first dielectric material timed (the study's normalisation); empty when the scene times none",
            rows.iter().map(|r| r.relative_to_exact_dielectric).collect(),
        );
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
        .text("material", "page id", text(&|r| r.material.clone()))
        .text("method", "Fresnel method (SPEC §5) or baseline", text(&|r| r.method.name().into()))
        .text("object", "mesh: cube, sphere or the OBJ file stem", text(&|r| r.object.clone()))
        .integer("frames", "frames of the camera orbit", rows.iter().map(|r| r.frames as i64).collect())
        .text("resolution", "render target WxH in pixels", text(&|r| resolution_text(r.resolution)))
        .optional_float(
            "mean_rel_error",
            "mean over frames of the mean over covered pixels and channels of |a - r| / r (r = exact render; r <= 0 skipped); empty where no sample had r > 0",
            rows.iter().map(|r| r.mean_rel_error).collect(),
        )
        .float("max_rel_error", "largest |a - r| / r of any covered pixel and channel", rows.iter().map(|r| r.max_rel_error).collect())
        .integer("pixels", "covered pixels summed over frames", rows.iter().map(|r| r.pixels as i64).collect())
        .integer(
            "skipped_zero_reference",
            "covered pixel channels with r = 0, left out of the error",
            rows.iter().map(|r| r.skipped_zero_reference as i64).collect(),
        );
    table
}

/// Publish the tables of the measurements the run took, and its frames, under `out` as
/// one set (`gpu`).
pub fn write_tables(report: &RunReport, out: &Path) -> Result<Vec<PathBuf>> {
    let effects = &report.effects;
    let mut tables: Vec<(Table, &str)> = Vec::new();
    if !effects.timing.is_empty() {
        tables.push((super::effects::timing_table(&effects.timing, &report.adapter), "effects_timing"));
    } else if report.experiments.contains(&Experiment::Timing) {
        tables.push((timing_table(report), "gpu_timing"));
    }
    let mut frames = Vec::new();
    if !effects.errors.is_empty() {
        tables.push((nklut_effects::experiment::error_table(&effects.errors), "effects_errors"));
        frames = nklut_effects::pictures::files("effects_gpu_frames", &effects.pictures)?;
    } else if report.experiments.contains(&Experiment::ImageError) {
        tables.push((image_error_table(report), "image_errors"));
    }
    let streamed: Vec<_> = tables.iter().flat_map(|(table, stem)| table.streamed_files(stem, false)).collect();
    let files: Vec<&dyn nklut_pipeline::output::SetContent> = streamed
        .iter()
        .map(|f| f as &dyn nklut_pipeline::output::SetContent)
        .chain(frames.iter().map(|f| f as &dyn nklut_pipeline::output::SetContent))
        .collect();
    nklut_pipeline::output::publish_contents(out, "gpu", &files)
}

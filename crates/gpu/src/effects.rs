//! Multiple reflections and refractions on the GPU, driven by the scene: the runner's part
//! of the specular effects (GPU Gems 3 ch. 17, with F from the scene's Fresnel methods).
//!
//! Only what the scene names runs. Without a `reflection` or `refraction` effect nothing
//! here is built (no cube map, no pipeline). Otherwise: one layered distance map per
//! specular object (`passes::distance_maps`), rendered once — the scene is static; one
//! shading pipeline per (effect, method) named (`passes::specular`; a scene without
//! `refraction` compiles the reflection-only variant); then
//!
//! - `timing` → `effects_timing`: per (method, depths, search steps), the GPU time of the
//!   distance-map update and of the shading pass, each its own timed pass (timestamp
//!   queries where the adapter has them, else wall time; the `timer` column says which);
//! - `image_error` → `effects_errors` rows with `renderer` = gpu: the GPU frames against
//!   the f64 ray-traced reference, split into geometry, Fresnel and total error exactly as
//!   the CPU twin's rows (`effects::experiment::measure`); the reference is traced only
//!   for this measurement.

use anyhow::{anyhow, Result};
use nklut_tables::effects_tables::effects_timing;

use super::context::Gpu;
use super::passes::distance_maps::{GpuMaps, MapRenderer, SceneMeshes};
use super::passes::specular::{Effect, Shot, SpecularPass};
use super::render::{Target, FLOAT_TARGET};
use super::runner::RunStats;
use super::timing::{median_and_iqr, Stopwatch, Timer};
use nklut_effects::experiment::{configuration_columns, measure, Configuration, EffectErrorRow, MapFrames, Settings};
use nklut_effects::pictures::Picture;
use nklut_effects::scene::{Depths, Experiment, Scene, SceneMaterial, SearchSteps};
use nklut_effects::trace::{stage_from_table, Camera, TracedFrame};
use nklut_optics::fresnel::Method;
use nklut_pipeline::output::Table;

/// One row of `effects_timing`.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectTimingRow {
    pub method: Method,
    pub effect: Effect,
    pub depths: Depths,
    pub steps: SearchSteps,
    pub map_size: u32,
    pub layers: u32,
    pub cube_maps: usize,
    pub resolution: [u32; 2],
    pub timer: Timer,
    pub repeats: u32,
    /// Median time of one update of every distance map (ms).
    pub map_update_ms: f64,
    /// Median time of the shading pass (ms).
    pub shading_ms: f64,
    pub shading_spread_ms: f64,
}

/// What the effects part of a run measured.
#[derive(Default)]
pub struct EffectsRun {
    pub timing: Vec<EffectTimingRow>,
    pub errors: Vec<EffectErrorRow>,
    pub pictures: Vec<Picture>,
}

/// The scene's Fresnel methods, in the crate's order.
fn methods(scene: &Scene) -> Vec<Method> {
    Method::ALL.into_iter().filter(|m| scene.shadings().iter().any(|s| s.fresnel() == Some(*m))).collect()
}

/// One timed configuration of `effects_timing`: the shading pass's Fresnel method, depths
/// and search steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimedConfiguration {
    pub method: Method,
    pub depths: Depths,
    pub steps: SearchSteps,
}

/// Every configuration the scene's `timing` measures, in the order of its rows: per depths,
/// per search steps, per method (none without specular effects).
pub fn timed_configurations(scene: &Scene) -> Vec<TimedConfiguration> {
    let Some(effects) = scene.effects.as_ref().filter(|e| e.names(nklut_effects::scene::EffectFamily::SpecularPaths)) else {
        return Vec::new();
    };
    let mut configurations = Vec::new();
    for depths in effects.depths() {
        for &steps in &effects.distance_maps.steps {
            for method in methods(scene) {
                configurations.push(TimedConfiguration { method, depths, steps });
            }
        }
    }
    configurations
}

/// The GPU's frames, for `effects::experiment::measure`.
struct GpuFrames<'a> {
    gpu: &'a Gpu,
    scene: &'a Scene,
    meshes: &'a SceneMeshes,
    maps: &'a GpuMaps,
    pass: &'a mut SpecularPass,
}

impl MapFrames for GpuFrames<'_> {
    fn name(&self) -> &'static str {
        "gpu"
    }

    fn frame(&mut self, frame: u32, camera: &Camera, method: Method, depths: Depths, steps: SearchSteps) -> Result<TracedFrame> {
        let shot = Shot { camera: &self.scene.camera, frame, depths, steps };
        Ok(self.pass.render(self.gpu, self.meshes, self.maps, shot, method, [camera.width, camera.height])?.traced())
    }
}

/// Run the specular effects the scene names; counters go to `stats`.
pub fn run_scene(
    scene: &Scene,
    materials: &[SceneMaterial],
    gpu: &Gpu,
    stats: &mut RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<EffectsRun> {
    let mut run = EffectsRun::default();
    let Some(effects) = scene.effects.as_ref().filter(|e| e.names(nklut_effects::scene::EffectFamily::SpecularPaths)) else {
        return Ok(run);
    };
    let stage = stage_from_table(scene, materials)?;
    let settings = &effects.distance_maps;
    let meshes = SceneMeshes::upload(gpu, &stage)?;
    let renderer = MapRenderer::new(gpu, &stage)?;
    let maps =
        renderer.allocate(gpu, &stage, settings.size, settings.layers).map_err(|e| anyhow!("scene {}: {e:#}", scene.file.display()))?;
    renderer.render(gpu, &meshes, &maps)?;
    stats.effects.cube_maps = maps.views.len();
    stats.effects.layers = settings.layers;
    log(&format!(
        "effects: {} distance maps of 6×{}² texels × {} layers rendered on the GPU",
        maps.views.len(),
        settings.size,
        settings.layers
    ));
    let mut pass = SpecularPass::new(gpu, &stage, scene.lut.size as usize)?;
    let methods = methods(scene);
    for depths in effects.depths() {
        for &method in &methods {
            pass.pipeline(gpu, Effect::of(depths), method)?;
        }
    }
    if scene.wants(Experiment::Timing) {
        run.timing = time_effects(scene, gpu, &renderer, &meshes, &maps, &mut pass, stats, log)?;
    }
    if scene.wants(Experiment::ImageError) {
        let report = {
            let mut frames = GpuFrames { gpu, scene, meshes: &meshes, maps: &maps, pass: &mut pass };
            measure(scene, &stage, Settings::of(scene), &mut frames, log)?
        };
        stats.effects.reference_frames += report.stats.reference_frames;
        stats.effects.twin_frames += report.stats.twin_frames;
        stats.frames_rendered += report.stats.twin_frames as u64;
        run.errors = report.rows;
        run.pictures = report.pictures;
    }
    stats.effect_pipelines = pass.pipelines_compiled;
    stats.refraction_pipelines = pass.compiled().filter(|(effect, _)| *effect == Effect::Refraction).count();
    stats.textures_baked += pass.lut_curves.min(1);
    Ok(run)
}

/// Time the map update and the shading pass of every configuration, interleaved round by
/// round like the F-only timing.
#[allow(clippy::too_many_arguments)]
fn time_effects(
    scene: &Scene,
    gpu: &Gpu,
    renderer: &MapRenderer,
    meshes: &SceneMeshes,
    maps: &GpuMaps,
    pass: &mut SpecularPass,
    stats: &mut RunStats,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<EffectTimingRow>> {
    let Some(effects) = &scene.effects else { return Ok(Vec::new()) };
    let [width, height] = scene.timing.resolution;
    let target = Target::new(gpu, width, height, FLOAT_TARGET, true)?;
    let mut stopwatch = Stopwatch::new(gpu)?;
    let configurations = timed_configurations(scene);
    let settings = &scene.timing;
    let mut update = Vec::new();
    let mut shading = vec![Vec::new(); configurations.len()];
    for round in 0..settings.warmup + settings.repeats {
        let ms = stopwatch.time_pass(gpu, |encoder, timestamps| renderer.encode(meshes, maps, encoder, timestamps))?;
        if round >= settings.warmup {
            update.push(ms);
        }
        for (samples, &TimedConfiguration { method, depths, steps }) in shading.iter_mut().zip(&configurations) {
            let shot = Shot { camera: &scene.camera, frame: 0, depths, steps };
            let mut failed = None;
            let ms = stopwatch.time_pass(gpu, |encoder, timestamps| {
                failed = pass.encode(gpu, meshes, maps, shot, method, &target, encoder, timestamps).err();
            })?;
            if let Some(error) = failed {
                return Err(error);
            }
            if round >= settings.warmup {
                samples.push(ms);
            }
        }
    }
    stats.timed_passes += stopwatch.passes;
    let (map_update_ms, _) = median_and_iqr(&update);
    let mut rows = Vec::new();
    for (samples, TimedConfiguration { method, depths, steps }) in shading.iter().zip(configurations) {
        let (shading_ms, shading_spread_ms) = median_and_iqr(samples);
        log(&format!(
            "  {} depth {}/{} steps {}/{}: map update {map_update_ms:.3} ms, shading {shading_ms:.3} ms ({})",
            method.name(),
            depths.reflection,
            depths.refraction,
            steps.linear,
            steps.secant,
            stopwatch.timer().name()
        ));
        rows.push(EffectTimingRow {
            method,
            effect: Effect::of(depths),
            depths,
            steps,
            map_size: effects.distance_maps.size,
            layers: effects.distance_maps.layers,
            cube_maps: maps.views.len(),
            resolution: [width, height],
            timer: stopwatch.timer(),
            repeats: settings.repeats,
            map_update_ms,
            shading_ms,
            shading_spread_ms,
        });
    }
    Ok(rows)
}

/// `effects_timing.*`: one row per (method, depths, search steps).
pub fn timing_table(rows: &[EffectTimingRow], adapter: &super::AdapterLine) -> Table {
    let text = |f: &dyn Fn(&EffectTimingRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let integer = |f: &dyn Fn(&EffectTimingRow) -> i64| rows.iter().map(f).collect::<Vec<_>>();
    let float = |f: &dyn Fn(&EffectTimingRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(effects_timing::ADAPTER, text(&|_| adapter.name.clone()))
        .put(effects_timing::BACKEND, text(&|_| adapter.backend.clone()))
        .put(effects_timing::TIMER, text(&|r| r.timer.name().into()))
        .put(effects_timing::METHOD, text(&|r| r.method.name().into()))
        .put(effects_timing::EFFECT, text(&|r| r.effect.name().into()));
    configuration_columns(
        &mut table,
        rows.iter().map(|r| Configuration { depths: r.depths, steps: r.steps, map_size: r.map_size, layers: r.layers }),
    );
    table
        .put(effects_timing::CUBE_MAPS, integer(&|r| r.cube_maps as i64))
        .put(effects_timing::RESOLUTION, text(&|r| format!("{}x{}", r.resolution[0], r.resolution[1])))
        .put(effects_timing::REPEATS, integer(&|r| r.repeats as i64))
        .put(effects_timing::MAP_UPDATE_MS, float(&|r| r.map_update_ms))
        .put(effects_timing::SHADING_MS, float(&|r| r.shading_ms))
        .put(effects_timing::SHADING_SPREAD_MS, float(&|r| r.shading_spread_ms))
        .put(effects_timing::FRAME_MS, float(&|r| r.map_update_ms + r.shading_ms));
    table
}

//! The image-error experiment of a scene with effects: for every depth and search
//! configuration the scene names, every camera frame is rendered three ways and compared
//! per specular object and Fresnel method (docs/effects.md):
//!
//! - the reference: exact geometry (the BVH tracer), exact Fresnel;
//! - the distance-map twin with exact Fresnel: its error against the reference is the
//!   *geometry* error (what the maps and their search cost);
//! - the twin with the method: its error against the twin with exact Fresnel, on the same
//!   paths, is the *Fresnel* error; against the reference, the *total*.
//!
//! What renders the distance-map frames is a [`MapFrames`]: the f64 CPU twin here
//! ([`CpuTwin`]), or the GPU runner's passes (`gpu::effects`); the reference is always the
//! f64 tracer. The materials come from the database through `ingest` (only the scene's
//! pages); the result is the `effects_errors` table, one row per renderer and configuration.

pub use super::distance_map::Configuration;
use super::distance_map::{DistanceMap, DistanceMapTracer};
use super::hero::{HeroPanel, HeroSet};
use super::image_error::{compare_object, FrameError};
use super::pictures::Picture;
use anyhow::Result;
use nklut_tables::effects_tables::{configuration, effects_cpu_timing, effects_errors};
use std::time::Instant;

use super::trace::{reference, render, Camera, PathRules, Stage, TracedFrame};
use crate::scene::{Depths, Role, Scene, SearchSteps};
use nklut_optics::fresnel::{Encoding, LutSpec, Method};
use nklut_tables::output::Table;
use nklut_tables::stats::median;

/// How much of the scene's camera path to render and at what size; `lut` is the texture of
/// the `lut` method (the GPU runner's: `lut.size` texels of half floats).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub frames: u32,
    pub resolution: [u32; 2],
    pub lut: LutSpec,
    /// The size of the hero frame (camera frame 0 of the deepest configuration, rendered
    /// again at a size a person looks at); `None`: no hero frame.
    pub hero: Option<[u32; 2]>,
}

impl Settings {
    /// The scene's frames, size and LUT, no hero frame.
    pub fn of(scene: &Scene) -> Settings {
        Settings {
            frames: scene.camera.frames,
            resolution: scene.resolution,
            lut: LutSpec::new(scene.lut.size as usize, Encoding::F16),
            hero: None,
        }
    }
}

/// The Fresnel methods the scene's specular objects name, in [`Method::ALL`]'s order.
pub fn scene_methods(scene: &Scene) -> Vec<Method> {
    Method::ALL.into_iter().filter(|m| scene.shadings().iter().any(|s| s.fresnel() == Some(*m))).collect()
}

/// Errors summed over frames (means over every pixel, or every channel sample with a
/// relative error, of all frames).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSum {
    pub pixels: usize,
    relative: f64,
    relative_samples: usize,
    delta_e: f64,
    absolute: f64,
}

impl ErrorSum {
    pub fn add(&mut self, e: &FrameError) {
        self.pixels += e.pixels;
        if let Some(mean) = e.mean_relative {
            self.relative += mean * e.relative_samples as f64;
            self.relative_samples += e.relative_samples;
        }
        self.delta_e += e.mean_delta_e2000 * e.pixels as f64;
        self.absolute += e.mean_absolute * e.pixels as f64;
    }

    fn mean(&self, sum: f64) -> f64 {
        if self.pixels > 0 {
            sum / self.pixels as f64
        } else {
            0.0
        }
    }

    /// The mean relative error; `None` when no sample had one (every r ≤ 0).
    pub fn mean_relative(&self) -> Option<f64> {
        (self.relative_samples > 0).then(|| self.relative / self.relative_samples as f64)
    }
    pub fn mean_delta_e2000(&self) -> f64 {
        self.mean(self.delta_e)
    }
    pub fn mean_absolute(&self) -> f64 {
        self.mean(self.absolute)
    }
}

/// One row of `effects_errors`.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectErrorRow {
    /// What traced the distance maps: `cpu-twin` or `gpu`.
    pub renderer: &'static str,
    pub object: String,
    pub material: String,
    pub method: Method,
    pub depths: Depths,
    pub steps: SearchSteps,
    pub map_size: u32,
    pub layers: u32,
    pub frames: u32,
    pub resolution: [u32; 2],
    pub geometry: ErrorSum,
    pub fresnel: ErrorSum,
    pub total: ErrorSum,
}

/// The twin's frame through each specular object's own map.
pub fn twin_frame(
    stage: &Stage,
    camera: &Camera,
    maps: &[Option<DistanceMap>],
    method: Method,
    depths: Depths,
    steps: SearchSteps,
    lut: LutSpec,
) -> TracedFrame {
    let optics = stage.optics(method, lut);
    let tracers: Vec<Option<DistanceMapTracer>> = maps.iter().map(|m| m.as_ref().map(|map| DistanceMapTracer { map, steps })).collect();
    render(stage, camera, PathRules { optics: &optics, depths }, |object| {
        tracers[object].as_ref().expect("every specular object has a map")
    })
}

/// The distance maps of every specular object (`None` for diffuse ones).
pub fn distance_maps(stage: &Stage, size: u32, layers: u32) -> Vec<Option<DistanceMap>> {
    (0..stage.objects.len()).map(|o| stage.is_specular(o).then(|| DistanceMap::render(stage, o, size, layers))).collect()
}

/// What the experiment measured: the table's rows, and frames to look at (camera frame 0 of
/// every depth configuration at the last search configuration: the reference, the twin with
/// each method, and each twin's error against the reference).
#[derive(Clone, Debug, Default)]
pub struct EffectsReport {
    pub rows: Vec<EffectErrorRow>,
    pub pictures: Vec<Picture>,
    pub stats: EffectsStats,
    /// The wall time of each configuration's frames, beside the reference's.
    pub timing: Vec<FrameTimingRow>,
    /// Camera frame 0 at the hero size, when asked for ([`Settings::hero`]).
    pub hero: Option<HeroSet>,
}

/// One row of `effects_cpu_timing`: how long one frame of a configuration took the
/// renderer, beside the f64 reference tracer on the same frames (the anchor of the same
/// run: the ratio is what carries to another machine).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimingRow {
    pub renderer: &'static str,
    pub method: Method,
    pub configuration: Configuration,
    pub frames: u32,
    pub resolution: [u32; 2],
    /// Median over the frames of one frame through the distance maps.
    pub frame_ms: f64,
    /// Median over the same frames of the reference tracer's frame.
    pub reference_ms: f64,
}

fn milliseconds(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// What the experiment computed, so tests and logs can see that nothing ran that the scene
/// did not ask for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EffectsStats {
    /// Distance maps (cube maps) rendered: one per specular object.
    pub cube_maps: usize,
    /// Layers per cube map.
    pub layers: u32,
    /// Reference frames traced (one per camera frame and depth/search configuration).
    pub reference_frames: usize,
    /// Distance-map frames traced (one per camera frame, configuration and method).
    pub twin_frames: usize,
    /// Surfels built (one per vertex of every object; none unless the scene names
    /// `ambient_occlusion` or `indirect`).
    pub surfels: usize,
    /// Nodes of the surfel tree built.
    pub tree_nodes: usize,
    /// Accessibility passes computed (on the CPU) or dispatched (on the GPU).
    pub ao_passes: u64,
    /// Indirect-light gathers (bounces) computed.
    pub indirect_bounces: u64,
}

/// Renders frames through the distance maps (the maps are the renderer's own).
pub trait MapFrames {
    /// `cpu-twin` or `gpu`, for the table's `renderer` column.
    fn name(&self) -> &'static str;
    /// Frame `frame` of the scene's camera path (`camera` is its pinhole) with every bounce's
    /// F from `method`.
    fn frame(&mut self, frame: u32, camera: &Camera, method: Method, depths: Depths, steps: SearchSteps) -> Result<TracedFrame>;
}

/// The f64 CPU twin of the GPU algorithm over maps it ray-cast itself.
pub struct CpuTwin<'a> {
    pub stage: &'a Stage,
    pub maps: Vec<Option<DistanceMap>>,
    pub lut: LutSpec,
}

impl MapFrames for CpuTwin<'_> {
    fn name(&self) -> &'static str {
        "cpu-twin"
    }

    fn frame(&mut self, _frame: u32, camera: &Camera, method: Method, depths: Depths, steps: SearchSteps) -> Result<TracedFrame> {
        Ok(twin_frame(self.stage, camera, &self.maps, method, depths, steps, self.lut))
    }
}

/// Run the experiment with the CPU twin; `log` receives progress lines. A scene without
/// effects has no rows.
pub fn image_errors(scene: &Scene, stage: &Stage, settings: Settings, log: &mut dyn FnMut(&str)) -> EffectsReport {
    let Some(effects) = &scene.effects else { return EffectsReport::default() };
    let maps_settings = &effects.distance_maps;
    let maps = distance_maps(stage, maps_settings.size, maps_settings.layers);
    log(&format!(
        "effects: {} distance maps of 6×{}² texels × {} layers",
        maps.iter().flatten().count(),
        maps_settings.size,
        maps_settings.layers
    ));
    let mut twin = CpuTwin { stage, maps, lut: settings.lut };
    let cube_maps = twin.maps.iter().flatten().count();
    let mut report = measure(scene, stage, settings, &mut twin, log).expect("the CPU twin cannot fail");
    report.stats.cube_maps = cube_maps;
    report.stats.layers = maps_settings.layers;
    report
}

/// Run the experiment with `renderer`'s frames against the f64 reference.
pub fn measure(
    scene: &Scene,
    stage: &Stage,
    settings: Settings,
    renderer: &mut dyn MapFrames,
    log: &mut dyn FnMut(&str),
) -> Result<EffectsReport> {
    let mut report = EffectsReport::default();
    let Some(effects) = &scene.effects else { return Ok(report) };
    let maps_settings = &effects.distance_maps;
    let methods = scene_methods(scene);
    let [width, height] = settings.resolution;
    let last_steps = maps_settings.steps.last().copied();
    for depths in effects.depths() {
        for &steps in &maps_settings.steps {
            let shown = |frame: u32| frame == 0 && Some(steps) == last_steps;
            let stem =
                |name: &str| format!("depth{}-{}_steps{}-{}_{name}", depths.reflection, depths.refraction, steps.linear, steps.secant);
            let mut sums: Vec<(usize, Method, ErrorSum, ErrorSum, ErrorSum)> = Vec::new();
            let mut reference_ms = Vec::new();
            let mut method_ms: Vec<Vec<f64>> = vec![Vec::new(); methods.len()];
            for frame in 0..settings.frames {
                let camera = Camera::new(&scene.camera, frame, width, height);
                let start = Instant::now();
                let truth = reference(stage, &camera, depths);
                reference_ms.push(milliseconds(start));
                let start = Instant::now();
                let exact_twin = renderer.frame(frame, &camera, Method::Exact, depths, steps)?;
                let exact_ms = milliseconds(start);
                report.stats.reference_frames += 1;
                report.stats.twin_frames += 1;
                if shown(frame) {
                    report.pictures.push(Picture { stem: stem("reference"), frame: truth.clone(), reference: None });
                }
                for (m, &method) in methods.iter().enumerate() {
                    let with_method = if method == Method::Exact {
                        method_ms[m].push(exact_ms);
                        exact_twin.clone()
                    } else {
                        report.stats.twin_frames += 1;
                        let start = Instant::now();
                        let frame = renderer.frame(frame, &camera, method, depths, steps)?;
                        method_ms[m].push(milliseconds(start));
                        frame
                    };
                    if shown(frame) {
                        report.pictures.push(Picture {
                            stem: stem(method.name()),
                            frame: with_method.clone(),
                            reference: Some(truth.clone()),
                        });
                    }
                    for (object, specular) in scene.objects.iter().enumerate().filter_map(|(i, o)| match &o.role {
                        Role::Specular(s) => Some((i, s)),
                        Role::Diffuse(_) => None,
                    }) {
                        if !specular.shadings.iter().any(|s| s.fresnel() == Some(method)) {
                            continue;
                        }
                        let index = match sums.iter().position(|s| s.0 == object && s.1 == method) {
                            Some(i) => i,
                            None => {
                                sums.push((object, method, ErrorSum::default(), ErrorSum::default(), ErrorSum::default()));
                                sums.len() - 1
                            }
                        };
                        let entry = &mut sums[index];
                        entry.2.add(&compare_object(&exact_twin, &truth, object));
                        entry.3.add(&compare_object(&with_method, &exact_twin, object));
                        entry.4.add(&compare_object(&with_method, &truth, object));
                    }
                }
            }
            let configuration = Configuration { depths, steps, map_size: maps_settings.size, layers: maps_settings.layers };
            let reference_ms = median(&reference_ms).unwrap_or(0.0);
            for (&method, times) in methods.iter().zip(method_ms) {
                report.timing.push(FrameTimingRow {
                    renderer: renderer.name(),
                    method,
                    configuration,
                    frames: settings.frames,
                    resolution: settings.resolution,
                    frame_ms: median(&times).unwrap_or(0.0),
                    reference_ms,
                });
            }
            for (object, method, geometry, fresnel, total) in sums {
                let scene_object = &scene.objects[object];
                let material = scene_object.specular().map(|s| s.material.clone()).unwrap_or_default();
                log(&format!(
                    "  {} {} {material} {method} depth {}/{} steps {}/{}: geometry ΔE {:.3}, Fresnel ΔE {:.3}, total ΔE {:.3}",
                    renderer.name(),
                    scene_object.mesh.label(),
                    depths.reflection,
                    depths.refraction,
                    steps.linear,
                    steps.secant,
                    geometry.mean_delta_e2000(),
                    fresnel.mean_delta_e2000(),
                    total.mean_delta_e2000()
                ));
                report.rows.push(EffectErrorRow {
                    renderer: renderer.name(),
                    object: scene_object.mesh.label(),
                    material,
                    method,
                    depths,
                    steps,
                    map_size: maps_settings.size,
                    layers: maps_settings.layers,
                    frames: settings.frames,
                    resolution: settings.resolution,
                    geometry,
                    fresnel,
                    total,
                });
            }
        }
    }
    if let Some(size) = settings.hero {
        report.hero = Some(hero(scene, stage, size, &methods, renderer)?);
    }
    Ok(report)
}

/// The hero frame: camera frame 0 of the deepest depth configuration at the last search
/// configuration, at `size`: the reference and the distance maps with each method.
fn hero(scene: &Scene, stage: &Stage, size: [u32; 2], methods: &[Method], renderer: &mut dyn MapFrames) -> Result<HeroSet> {
    let Some(effects) = scene.effects.as_ref() else { anyhow::bail!("a hero frame needs a scene with effects") };
    let (Some(depths), Some(&steps)) =
        (effects.depths().into_iter().max_by_key(|d| (d.reflection + d.refraction, *d)), effects.distance_maps.steps.last())
    else {
        anyhow::bail!("a hero frame needs a depth and a search configuration")
    };
    let camera = Camera::new(&scene.camera, 0, size[0], size[1]);
    let reference = reference(stage, &camera, depths);
    let mut panels = Vec::new();
    for &method in methods {
        let frame = renderer.frame(0, &camera, method, depths, steps)?;
        panels.push(HeroPanel {
            stem: method.name().to_string(),
            label: format!(
                "{}, {} reflection(s), {} refraction(s), {}+{} search steps",
                method.name(),
                depths.reflection,
                depths.refraction,
                steps.linear,
                steps.secant
            ),
            method: method.name().to_string(),
            configuration: Some(Configuration {
                depths,
                steps,
                map_size: effects.distance_maps.size,
                layers: effects.distance_maps.layers,
            }),
            passes: None,
            frame,
        });
    }
    Ok(HeroSet {
        effect: crate::scene::EffectFamily::SpecularPaths,
        reference_label: format!(
            "reference: ray-traced, exact Fresnel, {} reflection(s), {} refraction(s)",
            depths.reflection, depths.refraction
        ),
        reference,
        panels,
        mask: super::hero::ErrorMask::SpecularObjects,
    })
}

/// `effects_cpu_timing.*`: one row per (method, depths, search steps).
pub fn timing_table(rows: &[FrameTimingRow]) -> Table {
    let mut table = Table::new();
    table
        .put(effects_cpu_timing::RENDERER, rows.iter().map(|r| r.renderer.to_string()).collect())
        .put(effects_cpu_timing::METHOD, rows.iter().map(|r| r.method.name().to_string()).collect());
    configuration_columns(&mut table, rows.iter().map(|r| r.configuration));
    table
        .put(effects_cpu_timing::FRAMES, rows.iter().map(|r| r.frames as i64).collect())
        .put(effects_cpu_timing::RESOLUTION, rows.iter().map(|r| format!("{}x{}", r.resolution[0], r.resolution[1])).collect())
        .put(effects_cpu_timing::FRAME_MS, rows.iter().map(|r| r.frame_ms).collect())
        .put(effects_cpu_timing::REFERENCE_MS, rows.iter().map(|r| r.reference_ms).collect())
        .put(
            effects_cpu_timing::RATIO_TO_REFERENCE,
            rows.iter().map(|r| if r.reference_ms > 0.0 { r.frame_ms / r.reference_ms } else { 0.0 }).collect(),
        );
    table
}

/// The columns that name each row's [`Configuration`], in the effects' tables' order.
pub fn configuration_columns(table: &mut Table, rows: impl Iterator<Item = Configuration>) {
    let rows: Vec<Configuration> = rows.collect();
    let integer = |f: &dyn Fn(&Configuration) -> u32| rows.iter().map(|r| f(r) as i64).collect::<Vec<_>>();
    table
        .put(configuration::REFLECTION_DEPTH, integer(&|r| r.depths.reflection))
        .put(configuration::REFRACTION_DEPTH, integer(&|r| r.depths.refraction))
        .put(configuration::LINEAR_STEPS, integer(&|r| r.steps.linear))
        .put(configuration::SECANT_STEPS, integer(&|r| r.steps.secant))
        .put(configuration::MAP_SIZE, integer(&|r| r.map_size))
        .put(configuration::LAYERS, integer(&|r| r.layers));
}

/// `effects_errors.*`: one row per (object, material, method, depths, search steps).
pub fn error_table(rows: &[EffectErrorRow]) -> Table {
    let text = |f: &dyn Fn(&EffectErrorRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let integer = |f: &dyn Fn(&EffectErrorRow) -> i64| rows.iter().map(f).collect::<Vec<_>>();
    let float = |f: &dyn Fn(&EffectErrorRow) -> f64| rows.iter().map(f).collect::<Vec<_>>();
    let optional = |f: &dyn Fn(&EffectErrorRow) -> Option<f64>| rows.iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .put(effects_errors::OBJECT, text(&|r| r.object.clone()))
        .put(effects_errors::MATERIAL, text(&|r| r.material.clone()))
        .put(effects_errors::METHOD, text(&|r| r.method.name().into()))
        .put(effects_errors::RENDERER, text(&|r| r.renderer.into()));
    configuration_columns(
        &mut table,
        rows.iter().map(|r| Configuration { depths: r.depths, steps: r.steps, map_size: r.map_size, layers: r.layers }),
    );
    table
        .put(effects_errors::FRAMES, integer(&|r| r.frames as i64))
        .put(effects_errors::RESOLUTION, text(&|r| format!("{}x{}", r.resolution[0], r.resolution[1])))
        .put(effects_errors::PIXELS, integer(&|r| r.total.pixels as i64))
        .put(effects_errors::GEOMETRY_MEAN_REL_ERROR, optional(&|r| r.geometry.mean_relative()))
        .put(effects_errors::GEOMETRY_MEAN_DELTA_E2000, float(&|r| r.geometry.mean_delta_e2000()))
        .put(effects_errors::FRESNEL_MEAN_REL_ERROR, optional(&|r| r.fresnel.mean_relative()))
        .put(effects_errors::FRESNEL_MEAN_DELTA_E2000, float(&|r| r.fresnel.mean_delta_e2000()))
        .put(effects_errors::TOTAL_MEAN_REL_ERROR, optional(&|r| r.total.mean_relative()))
        .put(effects_errors::TOTAL_MEAN_DELTA_E2000, float(&|r| r.total.mean_delta_e2000()))
        .put(effects_errors::TOTAL_MEAN_ABS_ERROR, float(&|r| r.total.mean_absolute()));
    table
}

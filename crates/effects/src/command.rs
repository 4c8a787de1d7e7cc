//! `nklut effects`: the effects a scene names, on the CPU, as one stage like the others.
//! The scene's frame count and size may be overridden (and then pass the scene's own
//! checks again); every size the run will hold — distance maps, frames, surfels of
//! subdivided meshes, reference rays — is estimated and checked against the memory budget
//! before any of it is allocated ([`memory_needs`]); the database is opened only when
//! reflections or refractions need materials; and the tables and pictures of the run are
//! published as one set (`effects`), so frames of an earlier or killed run never mix with
//! this run's tables.

use nklut_tables::effects_tables::{ao_errors, ao_histogram, effects_cpu_timing, effects_errors, effects_hero, spectral_errors};
use std::path::{Path, PathBuf};

use anyhow::Result;

use super::ao::experiment::AoSettings;
use super::distance_map::Texel;
use super::experiment::{self, EffectsStats};
use super::hero::{files as hero_files, hero_resolution, hero_table, HeroSet};
use super::trace::TracedFrame;
use crate::scene::{EffectFamily, Scene, SceneError};
use nklut_optics::db::Database;
use nklut_tables::budget::{times, MemoryBudget};
use nklut_tables::ingest::Config;
use nklut_tables::output::{ParquetEncoder, SetContent, SetFile};

/// The most reference rays per vertex (`--ao-rays`): 2²⁰, a standard error below 0.0005.
pub const MAX_AO_RAYS: u32 = 1 << 20;

/// The largest surfel count run by brute force (`--ao-max-brute`): 2¹⁷ surfels, 1.7·10¹⁰
/// pairs a pass (hours on the CPU); the tree takes every scene above it.
pub const MAX_AO_BRUTE: usize = 1 << 17;

/// What `nklut effects` is asked to do.
#[derive(Clone, Debug)]
pub struct EffectsRequest {
    pub scene: PathBuf,
    /// Camera frames to render (default: the scene's).
    pub frames: Option<u32>,
    /// Frame size (default: the scene's resolution).
    pub resolution: Option<[u32; 2]>,
    /// Reference rays per vertex for ambient occlusion and indirect light.
    pub ao_rays: u32,
    /// The largest surfel count run by brute force.
    pub ao_max_brute: usize,
    /// The long side of the hero frame in pixels (`None`: no hero frame).
    pub hero_size: Option<u32>,
    pub config: Config,
    pub budget: MemoryBudget,
}

/// What the run did: the files written and what it computed.
#[derive(Clone, Debug, Default)]
pub struct EffectsOutcome {
    pub written: Vec<PathBuf>,
    pub stats: EffectsStats,
    /// Pictures written (reflections and refractions, then ambient occlusion).
    pub frames: usize,
}

/// The scene with the request's overrides, checked again.
pub fn scene_of(request: &EffectsRequest) -> Result<Scene, SceneError> {
    let mut scene = Scene::load(&request.scene)?;
    if let Some(frames) = request.frames {
        scene.camera.frames = frames;
    }
    if let Some(resolution) = request.resolution {
        scene.resolution = resolution;
    }
    scene.recheck()?;
    Ok(scene)
}

/// One figure of the memory a run will hold: the field that decides it, in words, bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryNeed {
    pub field: String,
    pub what: String,
    pub bytes: u128,
}

/// The memory the effects of `scene` will hold that the scene's fields decide before any
/// mesh is read, family by family ([`family_needs`]). (Subdivided meshes are checked when
/// their triangles are known.)
pub fn memory_needs(scene: &Scene, ao_rays: u32, hero: Option<[u32; 2]>) -> Vec<MemoryNeed> {
    let families: Vec<EffectFamily> = EffectFamily::ALL.into_iter().filter(|&family| scene.names_effect(family)).collect();
    let mut needs: Vec<MemoryNeed> = families.iter().flat_map(|&family| family_needs(family, scene, ao_rays)).collect();
    needs.extend(geometry_need(scene, &families));
    if let Some([width, height]) = hero {
        // Per family: the reference and up to one panel per method (or 4 AO variants), each
        // frame with its error map, encoded pictures and crops besides.
        let panels = families
            .iter()
            .map(|family| match family {
                EffectFamily::SpecularPaths => 1 + scene.shadings().len() as u128,
                EffectFamily::Surfels => 5,
            })
            .sum::<u128>();
        let per_pixel = std::mem::size_of::<[f64; 3]>() + std::mem::size_of::<Option<usize>>() + std::mem::size_of::<f64>() + 8;
        needs.push(MemoryNeed {
            field: "--hero-size".into(),
            what: format!("{panels} hero panels at {width}x{height}"),
            bytes: times(panels * u128::from(width) * u128::from(height), per_pixel),
        });
    }
    needs
}

/// The geometry of the scene's built-in meshes (their triangles are known before any is
/// built; meshes from files are checked as they are read): per triangle, what the traced
/// stage holds ([`super::geometry::BYTES_PER_TRACED_TRIANGLE`]) and, for surfels, what a
/// subdivided surfel mesh holds
/// ([`super::ao::experiment::BYTES_PER_SURFEL_TRIANGLE`]), for each family the scene names.
fn geometry_need(scene: &Scene, families: &[EffectFamily]) -> Option<MemoryNeed> {
    let mut kinds: Vec<(&crate::scene::MeshSource, usize)> = Vec::new();
    let (mut traced, mut surfel) = (0u128, 0u128);
    for object in &scene.objects {
        let at = match kinds.iter().position(|(source, _)| **source == object.mesh) {
            Some(at) => at,
            None => {
                kinds.push((&object.mesh, crate::scene::mesh::built_in_size(&object.mesh).map_or(0, |(triangles, _)| triangles)));
                kinds.len() - 1
            }
        };
        let triangles = kinds[at].1 as u128;
        traced = traced.saturating_add(triangles);
        surfel = surfel.saturating_add(triangles.saturating_mul(4u128.saturating_pow(object.subdivisions)));
    }
    let bytes = families
        .iter()
        .map(|family| match family {
            EffectFamily::SpecularPaths => super::geometry::traced_bytes(traced),
            EffectFamily::Surfels => times(surfel, super::ao::experiment::BYTES_PER_SURFEL_TRIANGLE),
        })
        .fold(0u128, u128::saturating_add);
    (bytes > 0).then(|| MemoryNeed {
        field: "objects".into(),
        what: format!("the geometry of {} objects ({traced} triangles of built-in meshes, BVH included)", scene.objects.len()),
        bytes,
    })
}

/// The memory one family of effects holds: for specular paths the distance maps of every
/// specular object (built, then kept) and the frames of the image-error experiment; for
/// surfels the AO pictures and the reference rays of each worker thread.
fn family_needs(family: EffectFamily, scene: &Scene, ao_rays: u32) -> Vec<MemoryNeed> {
    let Some(effects) = &scene.effects else { return Vec::new() };
    let [width, height] = scene.resolution;
    let pixels = u128::from(width) * u128::from(height);
    let frame_bytes = times(pixels, std::mem::size_of::<[f64; 3]>() + std::mem::size_of::<Option<usize>>());
    let threads = rayon::current_num_threads() as u128;
    let resolution = format!("resolution {width}x{height}");
    match family {
        EffectFamily::SpecularPaths => {
            let maps = &effects.distance_maps;
            let specular = scene.specular_objects().count() as u128;
            let texels = 6 * u128::from(maps.size) * u128::from(maps.size) * u128::from(maps.layers);
            let methods = scene.shadings().len() as u128;
            let configurations = effects.depths().len() as u128;
            // Kept: per depth, the reference and each method's frame with a copy of the
            // reference; in flight: the reference, the exact twin and a method's twin.
            // The spectral comparison (`effects.spectral`), per depth: the spectral frame
            // and each index source's frame with a copy of the spectral one as its reference.
            let spectral = if effects.spectral.is_some() { configurations * 5 } else { 0 };
            let frames = configurations * (1 + 2 * methods) + 3 + spectral;
            vec![
                // Each map's texels are gathered per texel, then laid out per layer: twice at once.
                MemoryNeed {
                    field: "effects.distance_maps".into(),
                    what: format!("{specular} cube map(s) of 6 × {}² texels × {} layers", maps.size, maps.layers),
                    bytes: times(specular * texels, 2 * std::mem::size_of::<Option<Texel>>()),
                },
                MemoryNeed {
                    field: "resolution".into(),
                    what: format!("{frames} frames at {resolution}"),
                    bytes: frame_bytes.saturating_mul(frames),
                },
            ]
        }
        EffectFamily::Surfels => {
            // Per worker: each ray's bin and two coordinates, and its direction.
            let per_ray = 2 * std::mem::size_of::<(usize, [f64; 2])>() + std::mem::size_of::<[f64; 3]>();
            vec![
                // Five panels, the side-by-side picture of them, their error images' references.
                MemoryNeed {
                    field: "resolution".into(),
                    what: format!("the AO pictures at {resolution}"),
                    bytes: frame_bytes.saturating_mul(16),
                },
                MemoryNeed {
                    field: "--ao-rays".into(),
                    what: format!("{ao_rays} rays per vertex on {threads} threads"),
                    bytes: times(u128::from(ao_rays) * threads, per_ray),
                },
            ]
        }
    }
}

/// What one family of effects adds to the stage's set: tables (with their file stems) and
/// pictures.
#[derive(Default)]
struct FamilyOutput {
    tables: Vec<(nklut_tables::output::Table, &'static str)>,
    pictures: Vec<SetFile>,
    hero: Option<HeroSet>,
}

/// The most pixels on a hero frame's long side (`--hero-size`).
pub const MAX_HERO_SIZE: u32 = 4096;

impl EffectsRequest {
    /// The hero frame's size for `scene`, if one is asked for.
    pub fn hero_resolution(&self, scene: &Scene) -> Option<[u32; 2]> {
        self.hero_size.filter(|&s| s > 0).map(|s| hero_resolution(scene.resolution, s))
    }
}

/// Run one family of effects the scene names.
fn run_family(
    family: EffectFamily,
    scene: &Scene,
    request: &EffectsRequest,
    open_db: &dyn Fn() -> Result<Database>,
    stats: &mut EffectsStats,
    log: &mut dyn FnMut(&str),
) -> Result<FamilyOutput> {
    match family {
        EffectFamily::SpecularPaths => {
            let db = open_db()?;
            let (materials, _) = crate::scene::read_materials(scene, &db, &request.config)?;
            let mut stage = super::trace::stage_from_table(scene, &materials)?;
            stage.channels_nm = request.config.channels.nanometres();
            let settings = experiment::Settings { hero: request.hero_resolution(scene), ..experiment::Settings::of(scene) };
            let report = experiment::image_errors(scene, &stage, settings, &mut |line| log(line));
            *stats = report.stats;
            let mut tables = vec![
                (experiment::error_table(&report.rows), effects_errors::STEM),
                (experiment::timing_table(&report.timing), effects_cpu_timing::STEM),
            ];
            let mut pictures = super::pictures::files("effects_frames", &report.pictures)?;
            if let Some(spectral) = scene.effects.as_ref().and_then(|e| e.spectral) {
                let compared =
                    super::spectral_errors::spectral_errors(scene, &stage, scene.resolution, spectral.wavelengths, &mut |line| log(line))?;
                tables.push((super::spectral_errors::spectral_error_table(&compared.rows), spectral_errors::STEM));
                pictures.extend(super::pictures::files(super::spectral_errors::SPECTRAL_DIR, &compared.pictures)?);
                pictures.extend(
                    compared
                        .delta_e_maps
                        .into_iter()
                        .map(|f| SetFile::new(format!("{}/{}", super::spectral_errors::SPECTRAL_DIR, f.name), f.bytes)),
                );
            }
            Ok(FamilyOutput { tables, pictures, hero: report.hero })
        }
        EffectFamily::Surfels => {
            let mut settings = AoSettings {
                max_brute: request.ao_max_brute,
                resolution: scene.resolution,
                hero: request.hero_resolution(scene),
                budget: request.budget,
                ..Default::default()
            };
            settings.rays.rays = request.ao_rays;
            let report = super::ao::experiment::run(scene, &settings, stats, &mut |line| log(line))?;
            Ok(FamilyOutput {
                tables: vec![
                    (super::ao::errors::ao_errors_table(&report.rows), ao_errors::STEM),
                    (super::ao::histogram::ao_histogram_table(&report.histograms), ao_histogram::STEM),
                ],
                pictures: [
                    super::pictures::files("ao_frames", &report.pictures)?,
                    super::pictures::signed_files("ao_frames", &report.signed_maps)?,
                ]
                .concat(),
                hero: report.hero,
            })
        }
    }
}

/// Check every need against the budget: the first that does not fit is the error.
pub fn check_memory(scene: &Scene, ao_rays: u32, hero: Option<[u32; 2]>, budget: &MemoryBudget) -> Result<()> {
    for need in memory_needs(scene, ao_rays, hero) {
        budget.check(&need.field, &need.what, need.bytes)?;
    }
    Ok(())
}

/// Run the effects of the request's scene and publish their tables and pictures under
/// `out` as one set, each table's Parquet file encoded by `parquet` (the pipeline's,
/// `nklut_pipeline::output::parquet`: this crate builds no Parquet writer). `open_db` is
/// called only when reflections or refractions need the scene's materials.
pub fn command(
    request: &EffectsRequest,
    open_db: &dyn Fn() -> Result<Database>,
    parquet: ParquetEncoder,
    out: &Path,
    log: &mut dyn FnMut(&str),
) -> Result<EffectsOutcome> {
    let scene = scene_of(request)?;
    let Some(effects) = scene.effects.clone() else {
        anyhow::bail!("scene {}: no `effects` section, nothing to trace (use `nklut gpu run`)", scene.file.display());
    };
    if !(1..=MAX_AO_RAYS).contains(&request.ao_rays) {
        anyhow::bail!("--ao-rays {} must lie in 1..={MAX_AO_RAYS}", request.ao_rays);
    }
    if request.ao_max_brute > MAX_AO_BRUTE {
        anyhow::bail!(
            "--ao-max-brute {} must lie in 0..={MAX_AO_BRUTE} (surfels run by brute force, n² pairs a pass)",
            request.ao_max_brute
        );
    }
    if let Some(size) = request.hero_size.filter(|s| *s > MAX_HERO_SIZE) {
        anyhow::bail!("--hero-size {size} must lie in 0..={MAX_HERO_SIZE} (0: no hero frame)");
    }
    check_memory(&scene, request.ao_rays, request.hero_resolution(&scene), &request.budget)?;
    let mut outcome = EffectsOutcome::default();
    let mut tables = Vec::new();
    let mut pictures: Vec<SetFile> = Vec::new();
    let mut heroes = Vec::new();
    for family in EffectFamily::ALL.into_iter().filter(|&family| effects.names(family)) {
        let output = run_family(family, &scene, request, open_db, &mut outcome.stats, log)?;
        tables.extend(output.tables);
        pictures.extend(output.pictures);
        heroes.extend(output.hero);
    }
    if !heroes.is_empty() {
        let (files, rows) = hero_files(&heroes)?;
        tables.push((hero_table(&rows), effects_hero::STEM));
        pictures.extend(files);
    }
    outcome.frames = pictures.len();
    let streamed: Vec<_> = tables.iter().flat_map(|(table, stem)| table.streamed_files_with(stem, false, parquet)).collect();
    let files: Vec<&dyn SetContent> =
        streamed.iter().map(|f| f as &dyn SetContent).chain(pictures.iter().map(|f| f as &dyn SetContent)).collect();
    outcome.written = nklut_tables::output::publish_contents(out, "effects", &files)?;
    Ok(outcome)
}

/// The bytes of one traced frame of `width`×`height` (what [`memory_needs`] counts).
pub fn frame_bytes(frame: &TracedFrame) -> usize {
    frame.radiance.len() * std::mem::size_of::<[f64; 3]>() + frame.seen.len() * std::mem::size_of::<Option<usize>>()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> Scene {
        Scene::parse(text, Path::new("t.yaml")).unwrap()
    }

    /// The estimates count what the structures hold: one frame of the scene's size is
    /// the bytes a traced frame of that size has.
    #[test]
    fn the_estimates_follow_the_structures() {
        let frame = TracedFrame { width: 4, height: 2, radiance: vec![[0.0; 3]; 8], seen: vec![None; 8], rays: 0 };
        let one_frame = frame_bytes(&frame) as u128;
        let s = scene("resolution: [4, 2]\nmeasurements: [image_error]\neffects: {reflection: {max_depth: [1, 2]}, distance_maps: {size: 8, layers: 3}}\nobjects:\n  - {mesh: sphere, material: a/b/c, methods: [exact, schlick]}\n  - {mesh: room, diffuse: [0.5, 0.5, 0.5]}\n");
        let needs = memory_needs(&s, 1, None);
        assert_eq!(needs[0].bytes, 2 * 6 * 64 * 3 * std::mem::size_of::<Option<Texel>>() as u128);
        // Two depths × (reference + 2 × two methods) + 3 in flight = 13 frames.
        assert_eq!(needs[1].bytes, 13 * one_frame);
    }

    /// The geometry is counted before any mesh is built: a 64 × 32 UV sphere is 64·32·2 =
    /// 4 096 triangles, a room (a cube seen from inside) 6·2 = 12; each is
    /// BYTES_PER_TRACED_TRIANGLE when traced, and a surfel scene's subdivided mesh 4ˢ times
    /// its triangles at BYTES_PER_SURFEL_TRIANGLE.
    #[test]
    fn the_geometry_is_counted_before_it_is_built() {
        let s = scene("resolution: [4, 2]\nmeasurements: [image_error]\neffects: {reflection: {max_depth: 1}, distance_maps: {size: 8, layers: 2}}\nobjects:\n  - {mesh: sphere, material: a/b/c, methods: [exact]}\n  - {mesh: sphere, diffuse: [0.5, 0.5, 0.5]}\n  - {mesh: room, diffuse: [0.5, 0.5, 0.5]}\n");
        let geometry = memory_needs(&s, 1, None).into_iter().find(|n| n.field == "objects").unwrap();
        assert_eq!(geometry.bytes, (2 * 4096 + 12) * 512);
        assert_eq!(super::super::geometry::BYTES_PER_TRACED_TRIANGLE, 512);
        // 5 000 spheres: 20.5 M triangles, refused by name under a 4 GiB budget.
        let mut many = String::from("measurements: [image_error]\neffects: {reflection: {max_depth: 1}, distance_maps: {size: 8, layers: 2}}\nobjects:\n  - {mesh: sphere, material: a/b/c, methods: [exact]}\n");
        many.push_str(&"  - {mesh: sphere, diffuse: [0.5, 0.5, 0.5]}\n".repeat(5000));
        let error = check_memory(&scene(&many), 1, None, &MemoryBudget::given(4 << 30)).unwrap_err().to_string();
        assert!(error.starts_with("objects: the geometry of 5001 objects (20484096 triangles"), "{error}");
        let ao = scene("resolution: [16, 16]\nmeasurements: [image_error]\neffects: {ambient_occlusion: {passes: 1}}\nobjects:\n  - {mesh: room, subdivide: 2, diffuse: [0.5, 0.5, 0.5]}\n");
        let geometry = memory_needs(&ao, 1, None).into_iter().find(|n| n.field == "objects").unwrap();
        assert_eq!(geometry.bytes, 12 * 16 * super::super::ao::experiment::BYTES_PER_SURFEL_TRIANGLE as u128);
    }

    /// Sizes inside every field's range can still be too much together: the check names
    /// the field before anything is allocated.
    #[test]
    fn an_oversized_scene_is_refused_by_its_field() {
        let s = scene("measurements: [image_error]\neffects: {reflection: {max_depth: 1}, distance_maps: {size: 4096, layers: 8}}\nobjects:\n  - {mesh: sphere, material: a/b/c, method: exact}\n");
        let error = check_memory(&s, 1, None, &MemoryBudget::given(8 << 30)).unwrap_err().to_string();
        assert!(error.starts_with("effects.distance_maps: 1 cube map(s) of 6 × 4096² texels × 8 layers would take about"), "{error}");
        assert!(check_memory(&s, 1, None, &MemoryBudget::given(1 << 50)).is_ok());
        let ao = scene("resolution: [16, 16]\nmeasurements: [image_error]\neffects: {ambient_occlusion: {passes: 1}}\nobjects:\n  - {mesh: plane, diffuse: [0.5, 0.5, 0.5]}\n");
        let error = check_memory(&ao, MAX_AO_RAYS, None, &MemoryBudget::given(1 << 20)).unwrap_err().to_string();
        assert!(error.starts_with("--ao-rays"), "{error}");
    }
}

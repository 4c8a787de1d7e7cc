//! The browser bench (`nklut gpu web SCENE`): one self-contained HTML page per scene that
//! runs the native runner's F-only measurements in any WebGPU browser, phones included,
//! from `file://` or a static host, with no network and no build step.
//!
//! Everything the GPU sees is prepared here, by the code the native runner uses, and
//! embedded in the page as one JSON block ([`Bench`]): the WGSL of every pipeline composed
//! by [`crate::compose`] (the F-only pass per method through [`crate::render::compose`],
//! and, to be compiled and checked, every variant of every pass of
//! [`crate::passes::interfaces`]); the material uniforms ([`MaterialUniform`] bytes), the
//! LUT texels ([`crate::lut::texels`], as half floats), the meshes ([`mesh::Mesh::interleaved`])
//! and the camera's view uniforms per frame ([`ViewUniform::camera`]), all base64. The
//! page's script (`web/bench.js`) does only what the host must: device, buffers, pipelines,
//! passes, timing, readback, and the image error of SPEC §6 on the read-back targets (the
//! rule of [`crate::image_error::compare`], twinned in the script and held to it by
//! `tests/web_bench.rs`). Its result is a JSON file whose rows follow the columns of
//! `gpu_timing` and `image_errors` ([`crate::runner::timing_rows_table`],
//! [`crate::runner::image_error_rows_table`]); `nklut report --devices` reads it.
//!
//! For a scene that names reflection or refraction the page, as the native runner, leaves
//! the F-only passes out and times the map update and the shading pass per configuration
//! as `effects_timing` ([`effects`]); for a scene that names ambient occlusion it times the
//! surfel passes and every GTAO configuration as `ao_timing` ([`ao`]). Not in the page:
//! indirect light and the effects' image error against the f64 reference (traced on the
//! CPU by the native runner); the page says so, and compiles their modules and records
//! their messages.

pub mod ao;
pub mod effects;

use anyhow::{anyhow, Result};
use base64::Engine;
use serde::Serialize;

use super::camera;
use super::mesh;
use super::params::{self, MaterialUniform};
use super::render::{self, ViewUniform};
use nklut_effects::scene::{EffectFamily, Experiment, Scene, SceneError, SceneMaterial, SceneProblem, Shading};
use nklut_optics::fresnel::Method;

/// The version of [`Bench`] and of the result the page writes.
pub const FORMAT: &str = "nklut-web-bench/1";

/// What the page runs, embedded in it as JSON.
#[derive(Debug, Serialize)]
pub struct Bench {
    pub format: &'static str,
    /// The nklut version that wrote the page.
    pub version: &'static str,
    /// The scene's file stem (`default` for scenes/default.yaml).
    pub scene: String,
    pub formats: Formats,
    /// Column names of the result rows, in table order.
    pub columns: Columns,
    pub materials: Vec<MaterialPlan>,
    /// The 1×1 texture bound where a material has no LUT (half-float bits, base64).
    pub blank_lut: String,
    pub timing: Option<TimingPlan>,
    pub image_error: Option<ImagePlan>,
    pub meshes: Vec<MeshPlan>,
    /// The specular effects' map update and shading pass per configuration
    /// (`effects_timing`), when the scene names reflection or refraction and `timing`.
    pub effects: Option<effects::EffectsPlan>,
    /// The surfel passes and GTAO's configurations (`ao_timing`), when the scene names
    /// `ambient_occlusion`.
    pub ao: Option<ao::AoPlan>,
    /// Every composed module of every pass, compiled by the page and its messages recorded;
    /// the F-only pass's variants are also the page's pipelines.
    pub checks: Vec<ModulePlan>,
    /// What the page leaves out for this scene, each with why.
    pub skipped: Vec<String>,
}

/// WebGPU texture formats of the native runner's targets.
#[derive(Debug, Serialize)]
pub struct Formats {
    pub display: &'static str,
    pub float: &'static str,
    pub depth: &'static str,
    pub lut: &'static str,
}

#[derive(Debug, Serialize)]
pub struct Columns {
    pub gpu_timing: Vec<String>,
    pub image_errors: Vec<String>,
    pub effects_timing: Vec<String>,
    pub ao_timing: Vec<String>,
}

#[derive(Debug, Serialize)]
pub struct MaterialPlan {
    pub page: String,
    /// `dielectric` or `conductor` (the study normalises by exact on a dielectric).
    pub kind: &'static str,
    /// `MaterialParams` of `shaders/fresnel.wgsl`, base64 of its bytes.
    pub uniform: String,
    /// The `lut` method's texture when an object renders the material with `lut` or
    /// `texture`: half-float RGBA texels, base64, and its width.
    pub lut: Option<String>,
    pub lut_width: u32,
}

#[derive(Debug, Serialize)]
pub struct ModulePlan {
    pub name: String,
    /// The shading a variant of the F-only pass draws (`schlick`, `burner`): the page's
    /// pipelines take their module from it. None for the other passes' modules.
    pub shade: Option<String>,
    pub wgsl: String,
}

#[derive(Debug, Serialize)]
pub struct TimingPlan {
    pub resolution: [u32; 2],
    pub warmup: u32,
    pub repeats: u32,
    pub subtract: bool,
    /// Repeat F per pixel until a sample spans enough of the timer ([`crate::sampling`]).
    pub amplify: bool,
    /// The seed of the pairs' order, in decimal (it may pass 2^53).
    pub seed: String,
    /// The constants of [`crate::sampling`], which the page twins.
    pub sampling: SamplingRules,
    /// `View` of the fullscreen pass (base64).
    pub view: String,
    /// The timed (material, shading) pairs, the units of `gpu_timing`.
    pub pairs: Vec<PairPlan>,
}

#[derive(Debug, Serialize)]
pub struct SamplingRules {
    pub span_over_resolution: f64,
    pub span_over_floor: f64,
    pub min_sample_ms: f64,
    pub near_resolution: f64,
    pub near_floor: f64,
    pub max_evaluations: u32,
    pub max_calibration_rounds: usize,
    pub settled: f64,
    pub settle_window: usize,
    pub max_extra_warmup: u32,
}

impl SamplingRules {
    pub fn of_runner() -> Self {
        use crate::sampling as s;
        SamplingRules {
            span_over_resolution: s::SPAN_OVER_RESOLUTION,
            span_over_floor: s::SPAN_OVER_FLOOR,
            min_sample_ms: s::MIN_SAMPLE_MS,
            near_resolution: s::NEAR_RESOLUTION,
            near_floor: s::NEAR_FLOOR,
            max_evaluations: s::MAX_EVALUATIONS,
            max_calibration_rounds: s::MAX_CALIBRATION_ROUNDS,
            settled: s::SETTLED,
            settle_window: s::SETTLE_WINDOW,
            max_extra_warmup: s::MAX_EXTRA_WARMUP,
        }
    }
}

#[derive(Debug, Serialize)]
pub struct PairPlan {
    pub material: usize,
    pub method: &'static str,
    /// The F-only module it draws (`exact_dielectric` for exact on a dielectric material).
    pub shade: String,
    /// [`crate::runner::exact_formula`] for exact, else empty.
    pub formula: &'static str,
    /// A baseline (constant, bare fetch), not a Fresnel method.
    pub baseline: bool,
}

#[derive(Debug, Serialize)]
pub struct ImagePlan {
    pub resolution: [u32; 2],
    /// `View` of each frame of the camera orbit (base64).
    pub frames: Vec<String>,
    pub objects: Vec<ObjectPlan>,
}

#[derive(Debug, Serialize)]
pub struct ObjectPlan {
    pub mesh: usize,
    pub material: usize,
    pub methods: Vec<&'static str>,
}

#[derive(Debug, Serialize)]
pub struct MeshPlan {
    pub label: String,
    /// Position and normal per vertex, 6 f32 (base64).
    pub vertices: String,
    /// u32 triangle indices (base64).
    pub indices: String,
    pub index_count: u32,
}

fn base64(bytes: &[u8]) -> String {
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// The WebGPU name of a texture format the runner uses.
fn texture_format(format: wgpu::TextureFormat) -> &'static str {
    match format {
        wgpu::TextureFormat::Rgba8Unorm => "rgba8unorm",
        wgpu::TextureFormat::Rgba32Float => "rgba32float",
        wgpu::TextureFormat::Rgba16Float => "rgba16float",
        wgpu::TextureFormat::Depth32Float => "depth32float",
        _ => "unsupported",
    }
}

/// Half-float bits of RGBA texels, as `lut::upload_rows` writes them, base64.
fn half_texels(texels: &[[f32; 4]]) -> String {
    base64(bytemuck::cast_slice(&super::lut::half_bits(texels)))
}

/// The plan of `scene` with its materials' channel indices (`materials`, as the native
/// runner takes them); meshes are read here.
pub fn plan(scene: &Scene, materials: &[SceneMaterial]) -> Result<Bench> {
    let page_index =
        |page: &str| materials.iter().position(|m| m.page == page).ok_or_else(|| anyhow!("scene material {page} was not read"));
    let wants_lut = |page: &str| {
        scene
            .specular_objects()
            .any(|(_, s)| s.material == page && s.shadings.iter().any(|m| matches!(m, Shading::Fresnel(Method::Lut) | Shading::Texture)))
    };
    let material_plans = materials
        .iter()
        .map(|SceneMaterial { page, optics, .. }| {
            let prepared = params::prepare(&optics.channels);
            let lut = wants_lut(page).then(|| half_texels(&super::lut::texels(&prepared, scene.lut.size as usize)));
            MaterialPlan {
                page: page.clone(),
                kind: optics.kind.as_str(),
                uniform: base64(bytemuck::bytes_of(&MaterialUniform::from_prepared(&prepared))),
                lut,
                lut_width: scene.lut.size,
            }
        })
        .collect();

    // As the native runner: a scene with specular effects measures those, not the F-only
    // passes.
    let specular_effects = scene.names_effect(EffectFamily::SpecularPaths);
    let timing = (scene.wants(Experiment::Timing) && !specular_effects).then(|| -> Result<TimingPlan> {
        let [width, height] = scene.timing.resolution;
        let pairs = scene
            .material_shadings()
            .into_iter()
            .map(|(page, method)| {
                let material = page_index(&page)?;
                let kind = materials[material].optics.kind;
                Ok(PairPlan {
                    material,
                    method: method.name(),
                    shade: super::runner::timed_shade(method, kind).name(),
                    formula: if method == Shading::Fresnel(Method::Exact) { super::runner::exact_formula(kind) } else { "" },
                    baseline: !matches!(method, Shading::Fresnel(_)),
                })
            })
            .collect::<Result<_>>()?;
        Ok(TimingPlan {
            resolution: scene.timing.resolution,
            warmup: scene.timing.warmup,
            repeats: scene.timing.repeats,
            subtract: scene.timing.subtract,
            amplify: scene.timing.amplify,
            seed: scene.timing.seed.to_string(),
            sampling: SamplingRules::of_runner(),
            view: base64(bytemuck::bytes_of(&ViewUniform::fullscreen(width, height))),
            pairs,
        })
    });

    let mut meshes: Vec<(nklut_effects::scene::MeshSource, MeshPlan)> = Vec::new();
    let image_error = (scene.wants(Experiment::ImageError) && !specular_effects).then(|| image_plan(scene, &mut meshes, page_index));
    let timing = timing.transpose()?;
    let image_error = image_error.transpose()?;

    let mut checks = Vec::new();
    for (interface, variants) in super::passes::interfaces()? {
        let f_only = interface.name == <render::Renderer as super::passes::Pass>::INTERFACE.name;
        for variant in variants {
            let shade = f_only.then(|| variant.name.clone());
            checks.push(ModulePlan { name: effects::module_name(&interface, &variant.name), shade, wgsl: variant.wgsl });
        }
    }

    let effects = effects::plan(scene, materials)?;
    let ao = ao::plan(scene)?;
    let skipped = skipped_parts(scene, specular_effects, ao.as_ref().is_some_and(|a| a.gtao.is_some()));
    let format = texture_format;
    let names = |table: nklut_pipeline::output::Table| table.columns.into_iter().map(|c| c.name).collect();
    Ok(Bench {
        format: FORMAT,
        version: env!("CARGO_PKG_VERSION"),
        scene: scene.file.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
        formats: Formats {
            display: format(render::DISPLAY_TARGET),
            float: format(render::FLOAT_TARGET),
            depth: format(render::DEPTH),
            lut: format(super::lut::FORMAT),
        },
        columns: Columns {
            gpu_timing: names(super::runner::timing_rows_table(&[], &Default::default())),
            image_errors: names(super::runner::image_error_rows_table(&[])),
            effects_timing: names(super::effects::timing_table(&[], &Default::default())),
            ao_timing: names(super::ao_timing::ao_timing_table(&[], &Default::default())),
        },
        materials: material_plans,
        blank_lut: half_texels(&[[1.0; 4]]),
        timing,
        image_error,
        meshes: meshes.into_iter().map(|(_, plan)| plan).collect(),
        effects,
        ao,
        checks,
        skipped,
    })
}

/// The F-only image-error passes' plan: the camera's frames and every specular object with
/// its mesh, each mesh embedded once in `meshes` (held against the memory budget).
fn image_plan(
    scene: &Scene,
    meshes: &mut Vec<(nklut_effects::scene::MeshSource, MeshPlan)>,
    page_index: impl Fn(&str) -> Result<usize>,
) -> Result<ImagePlan> {
    let [width, height] = scene.resolution;
    let frames = (0..scene.camera.frames)
        .map(|i| base64(bytemuck::bytes_of(&ViewUniform::camera(&camera::frame(&scene.camera, i, width, height), width, height))))
        .collect();
    let mut objects = Vec::new();
    let (budget, mut triangles) = (nklut_pipeline::budget::MemoryBudget::of_machine(), 0u128);
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(specular) = object.specular() else { continue };
        let mesh_index = match meshes.iter().position(|(source, _)| *source == object.mesh) {
            Some(index) => index,
            None => {
                let mesh = mesh::load(&object.mesh, |p| scene.mesh_path(p))
                    .map_err(|error| SceneError::new(&scene.file, SceneProblem::Mesh { object: i, error }))?;
                // The meshes embedded so far, this one included, before its copies.
                triangles += mesh.triangles() as u128;
                nklut_effects::geometry::check_loaded(&budget, i, triangles, &object.mesh.label())
                    .map_err(|e| SceneError::new(&scene.file, SceneProblem::Memory(e)))?;
                meshes.push((
                    object.mesh.clone(),
                    MeshPlan {
                        label: object.mesh.label(),
                        vertices: base64(bytemuck::cast_slice(&mesh.interleaved())),
                        indices: base64(bytemuck::cast_slice(&mesh.indices)),
                        index_count: mesh.indices.len() as u32,
                    },
                ));
                meshes.len() - 1
            }
        };
        objects.push(ObjectPlan {
            mesh: mesh_index,
            material: page_index(&specular.material)?,
            methods: specular.shadings.iter().map(|m| m.name()).collect(),
        });
    }
    Ok(ImagePlan { resolution: scene.resolution, frames, objects })
}

/// What the page leaves to the native runner, in words: the surfel passes' errors, GTAO's
/// larger frames, and the F-only passes or the effects' image error where the scene's
/// specular effects take the measurements.
fn skipped_parts(scene: &Scene, specular_effects: bool, gtao: bool) -> Vec<String> {
    let mut skipped = Vec::new();
    if scene.names_effect(EffectFamily::Surfels) {
        skipped.push(
            "the scene's indirect light and the surfel AO's error against the ray-traced reference: the native runner's (`nklut gpu run`, `nklut effects`)"
                .to_string(),
        );
    }
    if gtao {
        skipped.push(
            "GTAO at 1024² and 1920×1080: the page times the scene's resolution only (`nklut gpu ao-timing` times the larger frames)"
                .to_string(),
        );
    }
    if specular_effects {
        skipped.push("F-only passes: the scene's reflection and refraction take its measurements, as in the native runner".to_string());
        if scene.wants(Experiment::ImageError) {
            skipped.push(
                "reflection, refraction image error (effects_errors): against the f64 ray-traced reference, which `nklut gpu run` traces on the CPU"
                    .to_string(),
            );
        }
        if !scene.wants(Experiment::Timing) {
            skipped.push("reflection, refraction timing: the scene does not ask for it (`measurements: [timing]`)".to_string());
        }
    }
    skipped
}

/// The rows of `table` (`name` in errors) as JSON objects without the cells `measured`: the
/// rows the page completes with what it measures.
fn rows_without(
    table: &nklut_pipeline::output::Table,
    name: &str,
    measured: &[&str],
) -> Result<Vec<serde_json::Map<String, serde_json::Value>>> {
    let json: serde_json::Value = serde_json::from_slice(&table.to_json()?)?;
    let serde_json::Value::Array(objects) = json else { return Err(anyhow!("{name} as JSON is not an array")) };
    objects
        .into_iter()
        .map(|row| match row {
            serde_json::Value::Object(mut cells) => {
                for cell in measured {
                    cells.remove(*cell);
                }
                Ok(cells)
            }
            other => Err(anyhow!("a {name} row is not an object: {other}")),
        })
        .collect()
}

const TEMPLATE: &str = include_str!("web/page.html");
const SCRIPT: &str = include_str!("web/bench.js");

/// The page of `bench`: the template with the title (HTML-escaped), the plan (JSON with
/// every `<` written `\u003c`, so no text of it can close or re-open a script element) and
/// the script, each filled in one pass so no filled text is read as a placeholder.
pub fn page(bench: &Bench) -> Result<String> {
    let json = serde_json::to_string(bench)?.replace('<', "\\u003c");
    let hash = format!("{:016x}", plan_hash(&json));
    let title = format!("nklut browser bench: {}", bench.scene).replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    let mut out = String::with_capacity(TEMPLATE.len() + json.len() + SCRIPT.len());
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("{{") {
        let end = start + rest[start..].find("}}").ok_or_else(|| anyhow!("unclosed placeholder in the page template"))?;
        out.push_str(&rest[..start]);
        out.push_str(match &rest[start + 2..end] {
            "TITLE" => &title,
            "PLAN" => &json,
            "HASH" => &hash,
            "SCRIPT" => SCRIPT,
            other => return Err(anyhow!("unknown placeholder {other} in the page template")),
        });
        rest = &rest[end + 2..];
    }
    out.push_str(rest);
    Ok(out)
}

/// FNV-1a 64 (Fowler, Noll & Vo) of the plan's JSON as embedded: the result's `plan_hash`.
pub fn plan_hash(json: &str) -> u64 {
    json.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// `View` of a fullscreen pass of `width` × `height`, base64 (the page's `ramp`).
pub fn fullscreen_view(width: u32, height: u32) -> String {
    base64(bytemuck::bytes_of(&ViewUniform::fullscreen(width, height)))
}

/// The file name of `scene`'s page under the output folder.
pub fn page_name(bench: &Bench) -> String {
    format!("web/{}.html", bench.scene)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Shade;
    use nklut_optics::spectrum::{Index, Kind};

    fn scene(text: &str) -> Scene {
        Scene::parse(text, std::path::Path::new("scenes/tiny.yaml")).unwrap()
    }

    #[test]
    fn the_plan_holds_the_runner_s_modules_and_bytes() {
        let scene = scene(
            "resolution: [32, 16]\ncamera: {axis: [0, 1, 0], distance: 3, frames: 2}\nobjects:\n  - {mesh: cube, material: t/m/g, methods: [schlick, lut]}\nmeasurements: [timing, image_error]\ntiming: {resolution: [64, 8], warmup: 1, repeats: 3}\nlut: {size: 16}\n",
        );
        let material = SceneMaterial::new("t/m/g", [Index::new(0.2, 3.0), Index::new(0.5, 2.5), Index::new(1.3, 1.9)], Kind::Conductor);
        let bench = plan(&scene, std::slice::from_ref(&material)).unwrap();
        assert_eq!(bench.scene, "tiny");
        // The F-only pass per shading, the burner and exact (the image-error reference)
        // among them, each the runner's module.
        let shaded: Vec<&ModulePlan> = bench.checks.iter().filter(|m| m.shade.is_some()).collect();
        let shade = |name: &str| shaded.iter().find(|m| m.shade.as_deref() == Some(name)).unwrap_or_else(|| panic!("no {name}"));
        for name in ["schlick", "lut", "exact", "burner"] {
            assert_eq!(shade(name).name, format!("fresnel pass: {name}"));
        }
        assert_eq!(shade("schlick").wgsl, render::compose(Shade::Method(Shading::Fresnel(Method::Schlick))).unwrap());
        assert_eq!(shade("burner").wgsl, render::compose(Shade::Burner).unwrap());
        assert_eq!(shade("exact_dielectric").wgsl, render::compose(Shade::ExactDielectric).unwrap());
        assert_eq!(shaded.len(), Shading::ALL.len() + 2);
        // Bytes as the native runner uploads them.
        let decode = |s: &str| base64::engine::general_purpose::STANDARD.decode(s).unwrap();
        let uniform = MaterialUniform::from_prepared(&params::prepare(&material.optics.channels));
        assert_eq!(decode(&bench.materials[0].uniform), bytemuck::bytes_of(&uniform));
        let lut = decode(bench.materials[0].lut.as_ref().unwrap());
        assert_eq!(lut.len(), 16 * 4 * 2);
        let image = bench.image_error.as_ref().unwrap();
        assert_eq!(image.frames.len(), 2);
        let frame1 = ViewUniform::camera(&camera::frame(&scene.camera, 1, 32, 16), 32, 16);
        assert_eq!(decode(&image.frames[1]), bytemuck::bytes_of(&frame1));
        let cube = mesh::load(&nklut_effects::scene::MeshSource::Cube, |p| p.to_path_buf()).unwrap();
        assert_eq!(decode(&bench.meshes[0].vertices), bytemuck::cast_slice::<f32, u8>(&cube.interleaved()));
        assert_eq!(bench.meshes[0].index_count as usize, cube.indices.len());
        // The timing pairs and the result columns of the native tables.
        let timing = bench.timing.as_ref().unwrap();
        assert_eq!(timing.pairs.iter().map(|p| p.method).collect::<Vec<_>>(), ["schlick", "lut"]);
        assert_eq!(bench.columns.gpu_timing.first().map(String::as_str), Some("adapter"));
        assert!(bench.columns.image_errors.contains(&"mean_rel_error".to_string()));
        // Every variant of every pass, to be compiled by the browser.
        let variants: usize = crate::passes::interfaces().unwrap().iter().map(|(_, s)| s.len()).sum();
        assert_eq!(bench.checks.len(), variants);
    }

    #[test]
    fn the_page_cannot_be_closed_by_the_plan_s_text() {
        let scene = scene("objects:\n  - {mesh: cube, material: \"t/x/a<!--<script>\", methods: [schlick]}\nmeasurements: [timing]\n");
        let material = SceneMaterial::new("t/x/a<!--<script>", [Index::new(1.5, 0.0); 3], Kind::Dielectric);
        let html = page(&plan(&scene, &[material]).unwrap()).unwrap();
        assert_eq!(html.matches("</script>").count(), html.matches("<script").count());
        assert!(html.contains("a\\u003c!--\\u003cscript>"));
        assert!(!html.contains("{{"), "every placeholder filled");
        // FNV-1a 64 of "" and "a" (the published test vectors).
        assert_eq!(plan_hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(plan_hash("a"), 0xaf63_dc4c_8601_ec8c);
    }
}

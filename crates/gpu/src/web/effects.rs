//! The browser bench's part of the specular effects (multiple reflections and refractions
//! through layered distance maps, Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3 ch. 17):
//! what the page needs to run the native runner's map update and shading pass
//! ([`crate::effects::run_scene`]) and time them per configuration as `effects_timing`.
//!
//! Every byte comes from the functions the native passes upload from: the packed scene
//! meshes ([`PackedMeshes`]), the map layout and buffer size ([`map_layout`],
//! [`map_buffer_bytes`]), the map-update uniforms and the six face uniforms of each layer
//! step ([`MapUniforms`], [`layer_steps`]), the shading pass's objects, materials and LUT
//! atlas ([`StageUniforms`]) and each configuration's frame ([`FrameUniform::new`]); the
//! passes' bindings come from their [`Interface`] declarations, the modules are the
//! compile check's (composed by [`crate::compose`]), and each row's configuration cells are
//! the native `effects_timing` table's own ([`crate::effects::timing_table`]). The page's
//! script uploads the bytes where the plan says and fills in only what it measures.

use anyhow::{anyhow, Result};
use serde::Serialize;

use super::base64;
use crate::effects::{timed_configurations, timing_table, EffectTimingRow, TimedConfiguration};
use crate::passes::distance_maps::{
    self, layer_steps, map_buffer_bytes, map_layout, MapRenderer, MapUniforms, PackedMeshes, FACE_LAYERS, GEOMETRY_CLEAR, MAP_FORMAT,
    MESH_ATTRIBUTES, SURFACE_CLEAR,
};
use crate::passes::specular::{Effect, FrameUniform, Shot, SpecularPass, StageUniforms};
use crate::passes::{Interface, Pass, Resource};
use crate::timing::Timer;
use nklut_effects::scene::{EffectFamily, Experiment, Scene, SceneMaterial};
use nklut_effects::trace::stage_from_table;

/// The columns of `effects_timing` the page measures and fills in; every other column's
/// cell comes with the configuration.
pub const MEASURED: [&str; 7] = ["adapter", "backend", "timer", "map_update_ms", "shading_ms", "shading_spread_ms", "frame_ms"];

/// The specular effects' timing, as the page runs it.
#[derive(Debug, Serialize)]
pub struct EffectsPlan {
    /// The shading target (`timing.resolution`).
    pub resolution: [u32; 2],
    pub warmup: u32,
    pub repeats: u32,
    pub meshes: SceneMeshPlan,
    pub maps: MapsPlan,
    pub shading: ShadingPlan,
    /// One per row of `effects_timing`, in the native runner's order.
    pub configurations: Vec<ConfigurationPlan>,
    /// The columns the page fills in ([`MEASURED`]).
    pub measured: Vec<&'static str>,
}

/// A pass's declaration ([`Interface`]): the page builds its bind group layouts from it.
#[derive(Debug, Serialize)]
pub struct PassPlan {
    /// The compile check's module the pass's pipeline takes.
    pub module: String,
    pub vertex: &'static str,
    pub fragment: &'static str,
    pub bindings: Vec<BindingPlan>,
}

#[derive(Debug, Serialize)]
pub struct BindingPlan {
    pub group: u32,
    pub binding: u32,
    pub name: &'static str,
    /// `uniform`, `read-only-storage`, `storage` (WebGPU's buffer binding types),
    /// `float-2d` (filterable), `unfilterable-float-2d-array` or `filtering` (a sampler).
    pub kind: &'static str,
}

/// Every object's placed mesh in one vertex and one index buffer ([`PackedMeshes`]).
#[derive(Debug, Serialize)]
pub struct SceneMeshPlan {
    /// f32 vertices (base64), `stride` bytes each, with `attributes`.
    pub vertices: String,
    pub stride: u64,
    pub attributes: Vec<AttributePlan>,
    /// u32 indices (base64).
    pub indices: String,
    /// Per object: its index range and first vertex; drawn as instance `object`.
    pub draws: Vec<DrawPlan>,
}

#[derive(Debug, Serialize)]
pub struct AttributePlan {
    pub location: u32,
    pub offset: u64,
    pub format: &'static str,
}

#[derive(Debug, Serialize)]
pub struct DrawPlan {
    pub object: usize,
    pub first_index: u32,
    pub index_count: u32,
    pub base_vertex: i32,
}

/// The map update: one render pass per (map, layer, face), each layer's faces then copied
/// into the map buffers at `offset` (and, below the diffuse layer, into `previous`).
#[derive(Debug, Serialize)]
pub struct MapsPlan {
    pub pass: PassPlan,
    /// Texels per face edge, layers per map, maps.
    pub size: u32,
    pub layers: u32,
    pub cube_maps: usize,
    /// Bytes of each map buffer (`geometry`, `surfaces`).
    pub buffer_bytes: u64,
    /// Array layers of the per-layer face textures (the six faces and a spare).
    pub face_layers: u32,
    pub format: &'static str,
    pub geometry_clear: [f64; 4],
    pub surface_clear: [f64; 4],
    /// `Lights` (uniform) and the `MapObject` array (storage), base64.
    pub lights: String,
    pub objects: String,
    pub steps: Vec<StepPlan>,
}

#[derive(Debug, Serialize)]
pub struct StepPlan {
    /// The six faces' `MapFace` uniforms (base64), in face order.
    pub faces: Vec<String>,
    /// The objects each face's pass draws.
    pub draw: Vec<usize>,
    /// Byte offset of the layer's six faces in each map buffer.
    pub offset: u64,
    /// Copy the layer into `previous` for the next layer's peel.
    pub keep: bool,
}

/// The shading pass's per-stage data.
#[derive(Debug, Serialize)]
pub struct ShadingPlan {
    pub vertex: &'static str,
    pub fragment: &'static str,
    pub bindings: Vec<BindingPlan>,
    /// The `SceneObject` array with each object's map (storage), base64.
    pub objects: String,
    /// The `MaterialParams` array (storage), base64.
    pub materials: String,
    /// The `lut` atlas (half-float RGBA texels, base64), `lut_width` × `lut_rows`; none when
    /// no configuration shades with `lut` (the page's blank texture is bound instead).
    pub lut: Option<String>,
    pub lut_width: u32,
    pub lut_rows: u32,
}

#[derive(Debug, Serialize)]
pub struct ConfigurationPlan {
    /// The compile check's module of (effect, method).
    pub module: String,
    pub method: &'static str,
    pub effect: &'static str,
    /// `EffectFrame` of frame 0 at [`EffectsPlan::resolution`] (uniform), base64.
    pub frame: String,
    /// The row's cells but the [`MEASURED`] ones, from the native table.
    pub row: serde_json::Map<String, serde_json::Value>,
}

pub(super) fn bindings(interface: &Interface) -> Vec<BindingPlan> {
    interface
        .bindings
        .iter()
        .map(|b| BindingPlan {
            group: b.group,
            binding: b.binding,
            name: b.name,
            kind: match b.resource {
                Resource::Uniform => "uniform",
                Resource::Read => "read-only-storage",
                Resource::ReadWrite => "storage",
                Resource::Texture2d => "float-2d",
                Resource::TextureArray => "unfilterable-float-2d-array",
                Resource::Sampler => "filtering",
            },
        })
        .collect()
}

fn vertex_format(format: wgpu::VertexFormat) -> &'static str {
    match format {
        wgpu::VertexFormat::Float32x3 => "float32x3",
        wgpu::VertexFormat::Float32x4 => "float32x4",
        _ => "unsupported",
    }
}

/// The check module's name of a pass's variant (as [`super::plan`] names its `checks`).
pub fn module_name(interface: &Interface, variant: &str) -> String {
    if variant == interface.name {
        variant.to_string()
    } else {
        format!("{}: {variant}", interface.name)
    }
}

/// The effects plan of `scene` (none when it names no reflection or refraction, or does not
/// ask for `timing`); meshes are read here.
pub fn plan(scene: &Scene, materials: &[SceneMaterial]) -> Result<Option<EffectsPlan>> {
    let Some(effects) = scene.effects.as_ref().filter(|e| e.names(EffectFamily::SpecularPaths)) else { return Ok(None) };
    if !scene.wants(Experiment::Timing) {
        return Ok(None);
    }
    let stage = stage_from_table(scene, materials)?;
    let settings = &effects.distance_maps;
    let (size, layers) = (settings.size, settings.layers);
    if size == 0 || !size.is_multiple_of(16) {
        return Err(anyhow!("distance_maps.size {size}: the GPU maps need a multiple of 16 texels per face edge"));
    }

    let packed = PackedMeshes::of(&stage);
    let draws = packed
        .ranges
        .iter()
        .zip(&packed.base_vertex)
        .enumerate()
        .filter(|(_, (range, _))| !range.is_empty())
        .map(|(object, (range, &base_vertex))| DrawPlan {
            object,
            first_index: range.start,
            index_count: range.end - range.start,
            base_vertex,
        })
        .collect();
    let layout = distance_maps::mesh_buffer_layout();
    let meshes = SceneMeshPlan {
        vertices: base64(bytemuck::cast_slice(&packed.vertices)),
        stride: layout.array_stride,
        attributes: MESH_ATTRIBUTES
            .iter()
            .map(|a| AttributePlan { location: a.shader_location, offset: a.offset, format: vertex_format(a.format) })
            .collect(),
        indices: base64(bytemuck::cast_slice(&packed.indices)),
        draws,
    };

    let (views, map_of) = map_layout(&stage, size, layers);
    let uniforms = MapUniforms::of(&stage);
    let map_interface = <MapRenderer as Pass>::INTERFACE;
    let maps = MapsPlan {
        pass: PassPlan {
            module: module_name(&map_interface, map_interface.name),
            vertex: map_interface.entry_points[0],
            fragment: map_interface.entry_points[1],
            bindings: bindings(&map_interface),
        },
        size,
        layers,
        cube_maps: views.len(),
        buffer_bytes: map_buffer_bytes(&views),
        face_layers: FACE_LAYERS,
        format: super::texture_format(MAP_FORMAT),
        geometry_clear: GEOMETRY_CLEAR,
        surface_clear: SURFACE_CLEAR,
        lights: base64(bytemuck::bytes_of(&uniforms.lights)),
        objects: base64(bytemuck::cast_slice(&uniforms.objects)),
        steps: layer_steps(&stage, &views, &uniforms)
            .into_iter()
            .map(|step| StepPlan {
                faces: step.faces.iter().map(|f| base64(bytemuck::bytes_of(f))).collect(),
                draw: step.draw,
                offset: step.offset,
                keep: !step.diffuse,
            })
            .collect(),
    };

    let configurations = timed_configurations(scene);
    let stage_uniforms = StageUniforms::of(&stage);
    let shading_interface = <SpecularPass as Pass>::INTERFACE;
    let wants_lut = configurations.iter().any(|c| c.method == nklut_optics::fresnel::Method::Lut) && !stage_uniforms.channels.is_empty();
    let lut_width = scene.lut.size;
    let shading = ShadingPlan {
        vertex: shading_interface.entry_points[0],
        fragment: shading_interface.entry_points[1],
        bindings: bindings(&shading_interface),
        objects: base64(bytemuck::cast_slice(&stage_uniforms.with_maps(&map_of, &views))),
        materials: base64(bytemuck::cast_slice(&stage_uniforms.materials)),
        lut: wants_lut.then(|| super::half_texels(&stage_uniforms.lut_atlas(lut_width as usize))),
        lut_width,
        lut_rows: 2 * stage_uniforms.channels.len() as u32,
    };

    let resolution = scene.timing.resolution;
    let rows = row_cells(scene, &configurations, size, layers, views.len())?;
    let configurations = configurations
        .iter()
        .zip(rows)
        .map(|(c, row)| {
            let effect = Effect::of(c.depths);
            let shot = Shot { camera: &scene.camera, frame: 0, depths: c.depths, steps: c.steps };
            ConfigurationPlan {
                module: module_name(&shading_interface, &crate::passes::specular_variant(effect, c.method)),
                method: c.method.name(),
                effect: effect.name(),
                frame: base64(bytemuck::bytes_of(&FrameUniform::new(stage_uniforms.lights, shot, resolution))),
                row,
            }
        })
        .collect();
    Ok(Some(EffectsPlan {
        resolution,
        warmup: scene.timing.warmup,
        repeats: scene.timing.repeats,
        meshes,
        maps,
        shading,
        configurations,
        measured: MEASURED.to_vec(),
    }))
}

/// Each configuration's row of the native `effects_timing` table with its measured cells
/// left out: the configuration columns as the native runner writes them.
fn row_cells(
    scene: &Scene,
    configurations: &[TimedConfiguration],
    size: u32,
    layers: u32,
    cube_maps: usize,
) -> Result<Vec<serde_json::Map<String, serde_json::Value>>> {
    let rows: Vec<EffectTimingRow> = configurations
        .iter()
        .map(|c| EffectTimingRow {
            method: c.method,
            effect: Effect::of(c.depths),
            depths: c.depths,
            steps: c.steps,
            map_size: size,
            layers,
            cube_maps,
            resolution: scene.timing.resolution,
            timer: Timer::Timestamp,
            repeats: scene.timing.repeats,
            map_update_ms: 0.0,
            shading_ms: 0.0,
            shading_spread_ms: 0.0,
        })
        .collect();
    super::rows_without(&timing_table(&rows, &Default::default()), "effects_timing", &MEASURED)
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::Engine;
    use nklut_optics::spectrum::{Index, Kind};

    const SCENE: &str = "resolution: [32, 32]
camera: {axis: [0, 1, 0.2], distance: 1.8, frames: 1}
effects:
  reflection: {max_depth: 2}
  distance_maps: {size: 16, layers: 3, linear_steps: [8, 15], secant_steps: [1]}
objects:
  - {mesh: sphere, scale: 0.5, position: [0.2, 0, 0], material: t/l/glass, methods: [exact, lut]}
  - {mesh: cube, scale: 0.25, position: [-0.6, -0.2, 0.3], material: t/m/gold, methods: [exact]}
  - {mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75]}
measurements: [timing]
timing: {resolution: [40, 24], warmup: 1, repeats: 2}
lut: {size: 32}
";

    fn decode(s: &str) -> Vec<u8> {
        base64::engine::general_purpose::STANDARD.decode(s).unwrap()
    }

    fn materials() -> Vec<SceneMaterial> {
        vec![
            SceneMaterial::new("t/l/glass", [Index::new(1.5, 0.0); 3], Kind::Dielectric),
            SceneMaterial::new("t/m/gold", [Index::new(0.2, 3.0), Index::new(0.5, 2.5), Index::new(1.3, 1.9)], Kind::Conductor),
        ]
    }

    /// The plan's bytes are the native passes' uploads, and its layer steps land where a
    /// hand count puts them.
    #[test]
    fn the_effects_plan_holds_the_native_passes_bytes() {
        let scene = Scene::parse(SCENE, std::path::Path::new("scenes/effects-tiny.yaml")).unwrap();
        let plan = plan(&scene, &materials()).unwrap().expect("reflection and timing: a plan");
        let stage = stage_from_table(&scene, &materials()).unwrap();
        // Meshes: the packed arrays, one draw per object.
        let packed = PackedMeshes::of(&stage);
        assert_eq!(decode(&plan.meshes.vertices), bytemuck::cast_slice::<f32, u8>(&packed.vertices));
        assert_eq!(decode(&plan.meshes.indices), bytemuck::cast_slice::<u32, u8>(&packed.indices));
        assert_eq!(plan.meshes.draws.len(), 3);
        assert_eq!((plan.meshes.stride, plan.meshes.attributes[1].offset), (24, 12));
        // Maps: two specular objects, 6 × 16² × 3 texels each, 16 bytes a texel.
        let maps = &plan.maps;
        assert_eq!((maps.cube_maps, maps.buffer_bytes), (2, 2 * 6 * 256 * 3 * 16));
        let uniforms = MapUniforms::of(&stage);
        assert_eq!(decode(&maps.objects), bytemuck::cast_slice::<_, u8>(&uniforms.objects));
        assert_eq!(decode(&maps.lights), bytemuck::bytes_of(&uniforms.lights));
        // Steps: per map, layers 0 and 1 peel the specular objects (0 and 1), layer 2 holds
        // the room (2); layer l of map m at (m·3 + l)·6·16²·16 bytes; only layer 1 peels.
        assert_eq!(maps.steps.len(), 6);
        for (s, step) in maps.steps.iter().enumerate() {
            let layer = s % 3;
            assert_eq!(step.offset, (s * 6 * 256 * 16) as u64);
            assert_eq!(step.draw, if layer == 2 { vec![2] } else { vec![0, 1] });
            assert_eq!(step.keep, layer < 2);
            let faces: Vec<distance_maps::FaceUniform> = step.faces.iter().map(|f| bytemuck::pod_read_unaligned(&decode(f))).collect();
            assert_eq!(faces.iter().map(|f| f.face).collect::<Vec<_>>(), [0, 1, 2, 3, 4, 5]);
            assert!(faces.iter().all(|f| f.peel == (layer == 1) as u32 && f.near == uniforms.near && f.far == uniforms.far));
        }
        // Shading: objects with their maps, materials, the lut atlas (two rows per specular
        // object, 32 half-float RGBA texels each).
        let shading = StageUniforms::of(&stage);
        let (views, map_of) = map_layout(&stage, 16, 3);
        assert_eq!(decode(&plan.shading.objects), bytemuck::cast_slice::<_, u8>(&shading.with_maps(&map_of, &views)));
        assert_eq!(decode(&plan.shading.materials), bytemuck::cast_slice::<_, u8>(&shading.materials));
        assert_eq!((plan.shading.lut_width, plan.shading.lut_rows), (32, 4));
        assert_eq!(decode(plan.shading.lut.as_ref().unwrap()).len(), 4 * 32 * 4 * 2);
        // Configurations: depth 2 × steps 8 and 15 × exact and lut; each frame the native one.
        let names: Vec<(&str, &str)> = plan.configurations.iter().map(|c| (c.method, c.module.as_str())).collect();
        assert_eq!(
            names,
            [
                ("exact", "specular effect: reflection, exact"),
                ("lut", "specular effect: reflection, lut"),
                ("exact", "specular effect: reflection, exact"),
                ("lut", "specular effect: reflection, lut")
            ]
        );
        let second = timed_configurations(&scene)[2];
        let shot = Shot { camera: &scene.camera, frame: 0, depths: second.depths, steps: second.steps };
        assert_eq!(decode(&plan.configurations[2].frame), bytemuck::bytes_of(&FrameUniform::new(shading.lights, shot, [40, 24])));
        // The row cells: the configuration's columns as the native table writes them, the
        // measured ones left to the page.
        let row = &plan.configurations[2].row;
        assert_eq!(
            (row["linear_steps"].as_u64(), row["reflection_depth"].as_u64(), row["refraction_depth"].as_u64()),
            (Some(15), Some(2), Some(0))
        );
        assert_eq!(
            (row["effect"].as_str(), row["resolution"].as_str(), row["repeats"].as_u64()),
            (Some("reflection"), Some("40x24"), Some(2))
        );
        let columns = timing_table(&[], &Default::default()).columns.len();
        assert_eq!(row.len() + MEASURED.len(), columns);
        assert!(MEASURED.iter().all(|m| !row.contains_key(*m)));
    }

    /// No plan where the scene names no reflection or refraction, or no timing.
    #[test]
    fn only_a_timed_effects_scene_has_a_plan() {
        let without_timing = SCENE.replace("measurements: [timing]", "measurements: [image_error]");
        let scene = Scene::parse(&without_timing, std::path::Path::new("s.yaml")).unwrap();
        assert!(plan(&scene, &materials()).unwrap().is_none());
        let bare = "objects:\n  - {mesh: cube, material: t/l/glass, methods: [exact]}\nmeasurements: [timing]\n";
        let scene = Scene::parse(bare, std::path::Path::new("s.yaml")).unwrap();
        assert!(plan(&scene, &materials()).unwrap().is_none());
    }
}

//! Layered distance maps rendered on the GPU (`shaders/distance_map_render.wgsl`): the
//! map-update pass of the specular effects (Umenhoffer, Patow and Szirmay-Kalos, GPU Gems 3
//! ch. 17). For each specular object, each layer and each of the six cube faces, one
//! render pass rasterises the objects that layer holds around the object's reference
//! point (the centre of its bounding box): layers below the last peel the specular
//! surfaces one by one (each keeps, per texel, the nearest fragment beyond the previous
//! layer's), the last holds the first diffuse surface with its lit colour. The CPU twin is
//! `effects::distance_map::DistanceMap::render`, which casts the same texel rays in f64.
//!
//! Input: the stage (placed meshes, which objects are specular, diffuse surfaces, light),
//! the map size and layer count. Output: [`GpuMaps`], every map in one pair of storage
//! buffers in the layout of `shaders/distance_map.wgsl` (layer-major, then face, row,
//! column): `geometry` (distance, normal; distance −1 where nothing is seen) and
//! `surfaces` (a diffuse surface's lit colour in rgb, the specular object's index in a,
//! −1 for diffuse), with one [`MapView`] per map.

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use wgpu::util::DeviceExt;

use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compose;
use crate::context::Gpu;
use crate::contracts::LightKind;
use crate::render::{check_buffer_size, depth_test, readback_buffer, texture_2d, DEPTH};
use nklut_effects::distance_map::{DistanceMap, Texel};
use nklut_effects::scene::mesh::widen;
use nklut_effects::scene::{Diffuse, LightSource, Pattern, SearchSteps, MAX_LIGHTS};
use nklut_effects::trace::{ObjectOptics, Stage, Surface};

/// Where one map sits in the map buffers (`MapView` of `shaders/distance_map.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MapView {
    pub centre: [f32; 4],
    pub size: u32,
    pub layers: u32,
    /// Index of the map's first texel.
    pub base: u32,
    pub pad: u32,
}

impl MapView {
    pub fn texels(&self) -> usize {
        (6 * self.size * self.size * self.layers) as usize
    }
}

/// The search's step counts (`SearchSteps` of `shaders/distance_map.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct StepsUniform {
    pub linear: u32,
    pub secant: u32,
    pub pad: [u32; 2],
}

impl StepsUniform {
    pub fn new(steps: SearchSteps) -> Self {
        StepsUniform { linear: steps.linear, secant: steps.secant, pad: [0; 2] }
    }
}

/// Every map's texels as the shaders read them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MapTexels {
    /// (distance, normal); distance −1 where nothing is seen.
    pub geometry: Vec<[f32; 4]>,
    /// rgb = a diffuse surface's lit colour; a = the specular object's index, −1 for diffuse.
    pub surfaces: Vec<[f32; 4]>,
    pub views: Vec<MapView>,
}

/// The shader's packing of one texel.
fn texel_words(texel: &Option<Texel>) -> ([f32; 4], [f32; 4]) {
    match texel {
        None => ([-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, -1.0]),
        Some(t) => {
            let geometry = [t.distance as f32, t.normal.x as f32, t.normal.y as f32, t.normal.z as f32];
            let surface = match t.surface {
                Surface::Specular(object) => [0.0, 0.0, 0.0, object as f32],
                Surface::Diffuse(c) => [c[0] as f32, c[1] as f32, c[2] as f32, -1.0],
            };
            (geometry, surface)
        }
    }
}

fn view_of(centre: DVec3, size: u32, layers: u32, base: usize) -> MapView {
    MapView { centre: [centre.x as f32, centre.y as f32, centre.z as f32, 0.0], size, layers, base: base as u32, pad: 0 }
}

impl MapTexels {
    /// CPU-rendered maps in the shaders' layout, one after another.
    pub fn pack(maps: &[DistanceMap]) -> MapTexels {
        let mut out = MapTexels::default();
        for map in maps {
            out.views.push(view_of(map.centre, map.size, map.layers.len() as u32, out.geometry.len()));
            for (geometry, surface) in map.layers.iter().flatten().map(texel_words) {
                out.geometry.push(geometry);
                out.surfaces.push(surface);
            }
        }
        out
    }

    /// Map `m` back as the CPU twin's type (for comparing the two renderings).
    pub fn unpack(&self, m: usize) -> DistanceMap {
        let view = self.views[m];
        let per_layer = 6 * (view.size * view.size) as usize;
        let texel = |i: usize| -> Option<Texel> {
            let [distance, nx, ny, nz] = self.geometry[i];
            let [r, g, b, object] = self.surfaces[i];
            (distance >= 0.0).then(|| Texel {
                distance: distance as f64,
                normal: DVec3::new(nx as f64, ny as f64, nz as f64),
                surface: if object >= 0.0 { Surface::Specular(object as usize) } else { Surface::Diffuse([r as f64, g as f64, b as f64]) },
            })
        };
        let layers =
            (0..view.layers as usize).map(|l| (0..per_layer).map(|i| texel(view.base as usize + l * per_layer + i)).collect()).collect();
        let c = view.centre;
        DistanceMap { centre: DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64), size: view.size, layers }
    }
}

/// `DiffuseSurface` of `shaders/diffuse.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DiffuseUniform {
    pub albedo: [f32; 4],
    pub second: [f32; 4],
    pub shape: [f32; 4],
    pub kind: [u32; 4],
}

fn widen3(v: [f64; 3]) -> [f32; 4] {
    [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]
}

impl DiffuseUniform {
    pub fn new(d: &Diffuse) -> Self {
        let (second, shape, kind) = match &d.pattern {
            Pattern::Plain => ([0.0; 3], [0.0; 3], 0),
            Pattern::Checker { size, albedo } => (*albedo, [*size, 0.0, 0.0], 1),
            Pattern::Gradient { axis, albedo } => (*albedo, *axis, 2),
        };
        DiffuseUniform { albedo: widen3(d.albedo), second: widen3(second), shape: widen3(shape), kind: [kind, 0, 0, 0] }
    }
}

/// `LightItem` of `shaders/diffuse.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightItem {
    pub kind: [u32; 4],
    pub vector: [f32; 4],
    pub colour: [f32; 4],
}

/// `Lights` of `shaders/diffuse.wgsl`: the scene's lights, the first `count[0]` items.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightsUniform {
    pub count: [u32; 4],
    pub items: [LightItem; MAX_LIGHTS],
}

impl LightsUniform {
    /// The lights of a stage (at most [`MAX_LIGHTS`]: the scene's check).
    pub fn new(lights: &[LightSource]) -> Self {
        let mut uniform = LightsUniform { count: [lights.len().min(MAX_LIGHTS) as u32, 0, 0, 0], ..Default::default() };
        for (item, light) in uniform.items.iter_mut().zip(lights) {
            let (vector, colour) = match light {
                LightSource::Directional { direction, colour } => (*direction, *colour),
                LightSource::Point { position, intensity } => (*position, *intensity),
                LightSource::Ambient { colour } => ([0.0; 3], *colour),
            };
            *item = LightItem { kind: [LightKind::of(light).code(), 0, 0, 0], vector: widen3(vector), colour: widen3(colour) };
        }
        uniform
    }
}

/// `MapFace` of `shaders/distance_map_render.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FaceUniform {
    pub centre: [f32; 4],
    pub face: u32,
    pub peel: u32,
    pub near: f32,
    pub far: f32,
}

/// `MapObject` of `shaders/distance_map_render.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MapObjectUniform {
    pub surface: DiffuseUniform,
    pub specular: [u32; 4],
}

/// What a layer's geometry target is cleared to: distance −1, nothing seen.
pub const GEOMETRY_CLEAR: [f64; 4] = [-1.0, 0.0, 0.0, 0.0];
/// What a layer's surface target is cleared to: object −1, no specular object.
pub const SURFACE_CLEAR: [f64; 4] = [0.0, 0.0, 0.0, -1.0];

/// The map-update pass's uniforms for a stage, as plain data: each object's
/// [`MapObjectUniform`], the lights, and the projection range (nearer than `near` or
/// farther than `far` is clipped), which spans the whole scene from any reference point
/// inside its box.
#[derive(Clone, Debug, PartialEq)]
pub struct MapUniforms {
    pub objects: Vec<MapObjectUniform>,
    pub lights: LightsUniform,
    pub near: f32,
    pub far: f32,
}

impl MapUniforms {
    pub fn of(stage: &Stage) -> MapUniforms {
        let objects = stage
            .objects
            .iter()
            .map(|o| match o {
                ObjectOptics::Specular(_) => MapObjectUniform { surface: DiffuseUniform::default(), specular: [1, 0, 0, 0] },
                ObjectOptics::Diffuse(d) => MapObjectUniform { surface: DiffuseUniform::new(d), specular: [0; 4] },
            })
            .collect();
        let (low, high) = stage.meshes.iter().flat_map(|m| &m.positions).fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(low, high), p| {
            let p = widen(*p);
            (low.min(p), high.max(p))
        });
        let far = 2.0 * (high - low).length().max(1e-6);
        MapUniforms { objects, lights: LightsUniform::new(&stage.lights), near: (far * 1e-6) as f32, far: far as f32 }
    }
}

/// Where every map of a stage sits: one [`MapView`] per specular object in object order,
/// and each object's map (`None` for diffuse ones).
pub fn map_layout(stage: &Stage, size: u32, layers: u32) -> (Vec<MapView>, Vec<Option<u32>>) {
    let mut views = Vec::new();
    let mut map_of = Vec::new();
    let mut texels = 0usize;
    for object in 0..stage.objects.len() {
        if stage.is_specular(object) {
            map_of.push(Some(views.len() as u32));
            let view = view_of(stage.geometry.object_centre(object), size, layers, texels);
            texels += view.texels();
            views.push(view);
        } else {
            map_of.push(None);
        }
    }
    (views, map_of)
}

/// The bytes of one map buffer (`geometry` or `surfaces`) holding every map of `views`
/// (16 at least: a binding is never empty).
pub fn map_buffer_bytes(views: &[MapView]) -> u64 {
    (views.iter().map(MapView::texels).sum::<usize>().max(1) * 16) as u64
}

/// One layer of one map in the map update: its six faces' uniforms (one render pass each,
/// in face order), the objects its passes draw, and where its faces land in the map
/// buffers. Layers below the diffuse one are also kept as the next layer's `previous`.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerStep {
    pub map: usize,
    pub layer: u32,
    /// The last layer: the diffuse surfaces (else the specular ones, peeled).
    pub diffuse: bool,
    pub faces: [FaceUniform; 6],
    /// The objects drawn into every face (each as instance `object`).
    pub draw: Vec<usize>,
    /// Byte offset of the layer's six faces in each map buffer.
    pub offset: u64,
}

/// Every layer step of the map update of `views`, in encoding order (map, then layer).
pub fn layer_steps(stage: &Stage, views: &[MapView], uniforms: &MapUniforms) -> Vec<LayerStep> {
    let mut steps = Vec::new();
    for (map, view) in views.iter().enumerate() {
        for layer in 0..view.layers {
            let diffuse = layer + 1 == view.layers;
            let peel = (layer > 0 && !diffuse) as u32;
            let faces = std::array::from_fn(|face| FaceUniform {
                centre: view.centre,
                face: face as u32,
                peel,
                near: uniforms.near,
                far: uniforms.far,
            });
            let draw = (0..stage.objects.len()).filter(|&o| stage.is_specular(o) != diffuse).collect();
            let offset = (view.base as u64 + (layer * 6 * view.size * view.size) as u64) * 16;
            steps.push(LayerStep { map, layer, diffuse, faces, draw, offset });
        }
    }
    steps
}

/// Every object's placed mesh packed in one vertex and one index array: object o's indices
/// are `ranges[o]`, its vertices start at `base_vertex[o]` (what [`SceneMeshes`] uploads).
/// Every triangle is wound counter-clockwise seen from the mesh's outside
/// ([`nklut_effects::scene::mesh::Mesh::outward_indices`]), so a fragment's `front_facing`
/// says from which side of the triangle's plane the camera sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct PackedMeshes {
    /// Position and normal per vertex, 6 f32 ([`MESH_ATTRIBUTES`]).
    pub vertices: Vec<f32>,
    pub indices: Vec<u32>,
    pub ranges: Vec<std::ops::Range<u32>>,
    pub base_vertex: Vec<i32>,
}

impl PackedMeshes {
    pub fn of(stage: &Stage) -> PackedMeshes {
        let mut packed = PackedMeshes { vertices: Vec::new(), indices: Vec::new(), ranges: Vec::new(), base_vertex: Vec::new() };
        for mesh in &stage.meshes {
            packed.base_vertex.push((packed.vertices.len() / 6) as i32);
            let start = packed.indices.len() as u32;
            packed.indices.extend(mesh.outward_indices());
            packed.ranges.push(start..packed.indices.len() as u32);
            packed.vertices.extend(mesh.interleaved());
        }
        packed
    }
}

/// Every object's placed mesh in one vertex and one index buffer; object o's indices are
/// `ranges[o]`, its vertices start at `base_vertex[o]`. Drawn with instance o, so the
/// shaders know the object.
pub struct SceneMeshes {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub ranges: Vec<std::ops::Range<u32>>,
    pub base_vertex: Vec<i32>,
}

impl SceneMeshes {
    pub fn upload(gpu: &Gpu, stage: &Stage) -> Result<SceneMeshes> {
        let PackedMeshes { vertices, indices, ranges, base_vertex } = PackedMeshes::of(stage);
        check_buffer_size(gpu, (vertices.len() * 4) as u64, "scene vertices", "use coarser meshes")?;
        let buffer = |label: &str, contents: &[u8], usage| {
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        Ok(SceneMeshes {
            vertices: buffer("scene vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX),
            indices: buffer("scene indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
            ranges,
            base_vertex,
        })
    }

    /// Draw the objects for which `include` holds, each as instance `object`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, include: impl Fn(usize) -> bool) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for (object, range) in self.ranges.iter().enumerate() {
            if include(object) && !range.is_empty() {
                pass.draw_indexed(range.clone(), self.base_vertex[object], object as u32..object as u32 + 1);
            }
        }
    }
}

/// The vertex layout of [`SceneMeshes`]: position, normal.
pub const MESH_ATTRIBUTES: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

pub fn mesh_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout { array_stride: 24, step_mode: wgpu::VertexStepMode::Vertex, attributes: &MESH_ATTRIBUTES }
}

/// The render pipeline of a pass that draws [`SceneMeshes`] (positions and normals, depth
/// tested, no culling) with the WGSL `source`, entry points `[vertex, fragment]`, into
/// `targets`. A shader that does not validate is an error naming `label`.
pub fn mesh_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    source: String,
    [vertex, fragment]: [&str; 2],
    targets: &[Option<wgpu::ColorTargetState>],
) -> Result<wgpu::RenderPipeline> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module =
        device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(label), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some(vertex),
            compilation_options: Default::default(),
            buffers: &[Some(mesh_buffer_layout())],
        },
        // Counter-clockwise is the front ([`PackedMeshes`] winds every triangle so, seen
        // from outside): `front_facing` is the side of the plane the camera sees.
        primitive: wgpu::PrimitiveState { cull_mode: None, front_face: wgpu::FrontFace::Ccw, ..Default::default() },
        depth_stencil: Some(depth_test()),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some(fragment),
            compilation_options: Default::default(),
            targets,
        }),
        multiview_mask: None,
        cache: None,
    });
    if let Some(error) = pollster::block_on(scope.pop()) {
        bail!("{label}: the shader does not validate: {error}");
    }
    Ok(pipeline)
}

/// Every map of a scene on the GPU.
pub struct GpuMaps {
    pub geometry: wgpu::Buffer,
    pub surfaces: wgpu::Buffer,
    pub views: Vec<MapView>,
    /// The map of each object (`None` for diffuse ones).
    pub map_of: Vec<Option<u32>>,
    /// Where the maps are rendered (`None` for maps uploaded from the CPU).
    targets: Option<LayerTargets>,
}

/// The render targets of one layer (six faces, reused layer after layer and map after
/// map), the previous layer kept for peeling, and one bind group per (map, layer, face).
struct LayerTargets {
    geometry: wgpu::Texture,
    surfaces: wgpu::Texture,
    previous: wgpu::Texture,
    depth: wgpu::TextureView,
    geometry_faces: Vec<wgpu::TextureView>,
    surface_faces: Vec<wgpu::TextureView>,
    /// What each layer of each map draws and where it lands ([`layer_steps`]).
    steps: Vec<LayerStep>,
    /// One per face of each step, in step order.
    bind_groups: Vec<wgpu::BindGroup>,
}

pub const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Array layers of the per-layer face textures: the six faces and one spare. wgpu's GL
/// backend makes every square 2D texture of 6·k layers a cube map (its heuristic for cube
/// compatibility), which it cannot copy to a buffer and which would not bind as the
/// `texture_2d_array` the peel reads; a seventh layer keeps it a 2D array on every backend.
pub const FACE_LAYERS: u32 = 7;

/// The map-update pass: its pipeline and the per-face uniforms, built once per scene.
pub struct MapRenderer {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    objects: wgpu::Buffer,
    lights: wgpu::Buffer,
    uniforms: MapUniforms,
}

impl Pass for MapRenderer {
    const INTERFACE: Interface = Interface {
        name: "distance-map faces",
        shader: "distance_map_render",
        entry_points: &["vs_map", "fs_map"],
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[
            Binding::new(0, 0, "map_face", Resource::Uniform),
            Binding::new(0, 1, "lights", Resource::Uniform),
            Binding::new(0, 2, "map_objects", Resource::Read),
            Binding::new(0, 3, "previous", Resource::TextureArray),
        ],
    };
}

/// A map must have a size the texture-to-buffer copy can take (rows of size·16 bytes, a
/// multiple of 256) and fit the device's texture limits.
pub fn check_map_size(gpu: &Gpu, size: u32, layers: u32) -> Result<()> {
    let limits = gpu.device.limits();
    if size == 0 || !size.is_multiple_of(16) {
        bail!("distance_maps.size {size}: the GPU maps need a multiple of 16 texels per face edge");
    }
    if size > limits.max_texture_dimension_2d || 6 * layers > limits.max_texture_array_layers {
        bail!("distance_maps {size}x{size}, {layers} layers: over this device's texture limits");
    }
    Ok(())
}

impl MapRenderer {
    pub fn new(gpu: &Gpu, stage: &Stage) -> Result<MapRenderer> {
        let device = &gpu.device;
        let interface = Self::INTERFACE;
        let source = compose(&format!("#import {}", interface.shader))?;
        let (pipeline_layout, mut layouts) = interface.pipeline_layout(device);
        let target = Some(wgpu::ColorTargetState { format: MAP_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL });
        let [vertex, fragment] = [interface.entry_points[0], interface.entry_points[1]];
        let pipeline = mesh_pipeline(device, interface.name, &pipeline_layout, source, [vertex, fragment], &[target.clone(), target])?;
        let uniforms = MapUniforms::of(stage);
        let buffer = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        Ok(MapRenderer {
            pipeline,
            layout: layouts.remove(0),
            objects: buffer("map objects", bytemuck::cast_slice(&uniforms.objects), wgpu::BufferUsages::STORAGE),
            lights: buffer("lights", bytemuck::bytes_of(&uniforms.lights), wgpu::BufferUsages::UNIFORM),
            uniforms,
        })
    }

    /// Allocate the maps of every specular object of `stage`: `size` texels per face edge,
    /// `layers` layers. Sizes are checked before anything is allocated.
    pub fn allocate(&self, gpu: &Gpu, stage: &Stage, size: u32, layers: u32) -> Result<GpuMaps> {
        check_map_size(gpu, size, layers)?;
        let (views, map_of) = map_layout(stage, size, layers);
        let bytes = map_buffer_bytes(&views);
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            bail!("{} distance maps of {size}x{size}x6x{layers} texels need {bytes} bytes, over this device's max_storage_buffer_binding_size ({limit})", views.len());
        }
        check_buffer_size(gpu, bytes, "distance maps", "lower effects.distance_maps.size or layers")?;
        let buffer = |label| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let targets = self.targets(gpu, stage, &views)?;
        Ok(GpuMaps { geometry: buffer("map geometry"), surfaces: buffer("map surfaces"), views, map_of, targets })
    }

    /// The render targets of one layer's six faces and each face's bind group, for `maps`
    /// (none without maps).
    fn targets(&self, gpu: &Gpu, stage: &Stage, views: &[MapView]) -> Result<Option<LayerTargets>> {
        let device = &gpu.device;
        let Some(first) = views.first() else { return Ok(None) };
        let size = first.size;
        let texture = |label, array_layers, format, usage| {
            texture_2d(gpu, label, wgpu::Extent3d { width: size, height: size, depth_or_array_layers: array_layers }, format, usage)
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let geometry = texture("map layer geometry", FACE_LAYERS, MAP_FORMAT, attachment);
        let surfaces = texture("map layer surfaces", FACE_LAYERS, MAP_FORMAT, attachment);
        let previous =
            texture("previous map layer", FACE_LAYERS, MAP_FORMAT, wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST);
        let previous_view = previous
            .create_view(&wgpu::TextureViewDescriptor { dimension: Some(wgpu::TextureViewDimension::D2Array), ..Default::default() });
        let depth = texture("map depth", 1, DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT).create_view(&Default::default());
        let face_view = |texture: &wgpu::Texture, face: u32| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: face,
                array_layer_count: Some(1),
                ..Default::default()
            })
        };
        let steps = layer_steps(stage, views, &self.uniforms);
        let mut bind_groups = Vec::new();
        for uniform in steps.iter().flat_map(|step| &step.faces) {
            let face_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("map face"),
                contents: bytemuck::bytes_of(uniform),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            bind_groups.push(Self::INTERFACE.bind_group(
                device,
                &self.layout,
                0,
                &[
                    (0, face_buffer.as_entire_binding()),
                    (1, self.lights.as_entire_binding()),
                    (2, self.objects.as_entire_binding()),
                    (3, wgpu::BindingResource::TextureView(&previous_view)),
                ],
            )?);
        }
        Ok(Some(LayerTargets {
            steps,
            geometry_faces: (0..6).map(|f| face_view(&geometry, f)).collect(),
            surface_faces: (0..6).map(|f| face_view(&surfaces, f)).collect(),
            geometry,
            surfaces,
            previous,
            depth,
            bind_groups,
        }))
    }

    /// Encode the update of every map in `maps` (all layers, all faces) into `encoder`: 6 ×
    /// layers render passes per map, each layer's faces copied into the map buffers (and,
    /// below the diffuse layer, kept for the next layer's peel). `timestamps`, where given,
    /// are written at the start of the first pass and the end of the last. Maps uploaded
    /// from the CPU have no targets: nothing is encoded.
    pub fn encode(&self, meshes: &SceneMeshes, maps: &GpuMaps, encoder: &mut wgpu::CommandEncoder, timestamps: Option<&wgpu::QuerySet>) {
        let Some(targets) = &maps.targets else { return };
        let total_passes = targets.bind_groups.len();
        let colour = |[r, g, b, a]: [f64; 4]| wgpu::Color { r, g, b, a };
        for (s, step) in targets.steps.iter().enumerate() {
            let size = maps.views[step.map].size;
            for face in 0..6usize {
                let pass_number = s * 6 + face;
                let writes =
                    timestamps.filter(|_| pass_number == 0 || pass_number + 1 == total_passes).map(|set| wgpu::RenderPassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: (pass_number == 0).then_some(0),
                        end_of_pass_write_index: (pass_number + 1 == total_passes).then_some(1),
                    });
                let clear = |view, colour| wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(colour), store: wgpu::StoreOp::Store },
                };
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("distance-map face"),
                    color_attachments: &[
                        Some(clear(&targets.geometry_faces[face], colour(GEOMETRY_CLEAR))),
                        Some(clear(&targets.surface_faces[face], colour(SURFACE_CLEAR))),
                    ],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &targets.depth,
                        depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: writes,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &targets.bind_groups[pass_number], &[]);
                meshes.draw(&mut pass, |object| step.draw.contains(&object));
            }
            let whole = wgpu::Extent3d { width: size, height: size, depth_or_array_layers: 6 };
            let at = |texture| wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            };
            if !step.diffuse {
                encoder.copy_texture_to_texture(at(&targets.geometry), at(&targets.previous), whole);
            }
            for (texture, buffer) in [(&targets.geometry, &maps.geometry), (&targets.surfaces, &maps.surfaces)] {
                encoder.copy_texture_to_buffer(
                    at(texture),
                    wgpu::TexelCopyBufferInfo {
                        buffer,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: step.offset,
                            bytes_per_row: Some(size * 16),
                            rows_per_image: Some(size),
                        },
                    },
                    whole,
                );
            }
        }
    }

    /// Update every map and wait for it.
    pub fn render(&self, gpu: &Gpu, meshes: &SceneMeshes, maps: &GpuMaps) -> Result<()> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(meshes, maps, &mut encoder, None);
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        gpu.take_errors()
    }
}

impl GpuMaps {
    /// Read every map back (for tests and for comparing with the CPU twin).
    pub fn read(&self, gpu: &Gpu) -> Result<MapTexels> {
        let bytes = self.geometry.size();
        let readback = readback_buffer(gpu, 2 * bytes)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.geometry, 0, &readback, 0, bytes);
        encoder.copy_buffer_to_buffer(&self.surfaces, 0, &readback, bytes, bytes);
        gpu.queue.submit([encoder.finish()]);
        let words: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&gpu.read_buffer(&readback)?);
        let (geometry, surfaces) = words.split_at(words.len() / 2);
        Ok(MapTexels { geometry: geometry.to_vec(), surfaces: surfaces.to_vec(), views: self.views.clone() })
    }

    /// Upload maps the CPU rendered (the twin's maps, to test the shading pass alone).
    pub fn upload(gpu: &Gpu, stage: &Stage, maps: &[Option<DistanceMap>]) -> Result<GpuMaps> {
        let rendered: Vec<DistanceMap> = maps.iter().flatten().cloned().collect();
        let texels = MapTexels::pack(&rendered);
        let mut next = 0;
        let map_of = (0..stage.objects.len())
            .map(|o| {
                maps.get(o).and_then(|m| m.as_ref()).map(|_| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let buffer = |label: &str, contents: &[[f32; 4]]| {
            let contents: &[u8] = if contents.is_empty() { &[0; 16] } else { bytemuck::cast_slice(contents) };
            gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        check_buffer_size(gpu, (texels.geometry.len() * 16) as u64, "distance maps", "lower effects.distance_maps.size or layers")?;
        Ok(GpuMaps {
            geometry: buffer("map geometry", &texels.geometry),
            surfaces: buffer("map surfaces", &texels.surfaces),
            views: texels.views,
            map_of,
            targets: None,
        })
    }
}

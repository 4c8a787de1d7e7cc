//! The distance-map search on the GPU (`shaders/distance_search.wgsl` over the library
//! `shaders/distance_map.wgsl`): a compute pass that
//! runs the linear + secant search of GPU Gems 3 ch. 17 for a batch of rays against one
//! object's layered distance map, so the WGSL can be held to its CPU twin
//! (`effects::distance_map`) ray by ray. The map goes up as the effect pass lays it out
//! ([`MapTexels::pack`]).

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::compose::compute_pipelines;
use super::context::Gpu;
use super::passes::distance_maps::{MapTexels, MapView, StepsUniform};
use super::passes::interface::{Binding, Interface, Pass, Resource};
use super::render::{check_buffer_size, readback_buffer};
use nklut_effects::distance_map::DistanceMap;
use nklut_effects::scene::SearchSteps;

/// The uniform block `SearchBatch` of `shaders/distance_search.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct SearchBatch {
    map: MapView,
    steps: StepsUniform,
    count: u32,
    pad: [u32; 3],
}

/// A ray relative to the map's centre (w unused).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SearchRay {
    pub origin: [f32; 4],
    pub direction: [f32; 4],
}

/// Where the search ended: point (relative to the centre) and t in `point[3]` (t < 0: no
/// hit); `at` = [layer, texel index, 0, 0].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct SearchHit {
    pub point: [f32; 4],
    pub at: [u32; 4],
}

/// The search alone, one ray per invocation: the pass the search tests hold to the CPU twin.
pub struct DistanceSearchPass;

impl Pass for DistanceSearchPass {
    const INTERFACE: Interface = Interface {
        name: "distance-map search",
        shader: "distance_search",
        entry_points: &["cs_search"],
        stages: wgpu::ShaderStages::COMPUTE,
        bindings: &[
            Binding::new(0, 0, "batch", Resource::Uniform),
            Binding::new(0, 1, "rays", Resource::Read),
            Binding::new(0, 2, "hits", Resource::ReadWrite),
            Binding::new(1, 0, "map_texels", Resource::Read),
        ],
    };
}

/// Run the search for every ray on the GPU and read the hits back.
pub fn search(gpu: &Gpu, map: &DistanceMap, rays: &[SearchRay], steps: SearchSteps) -> Result<Vec<SearchHit>> {
    if rays.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let texels = MapTexels::pack(std::slice::from_ref(map));
    let storage_limit = device.limits().max_storage_buffer_binding_size;
    for (what, bytes) in [("distance map", std::mem::size_of_val(texels.geometry.as_slice())), ("rays", std::mem::size_of_val(rays))] {
        if bytes as u64 > storage_limit {
            bail!("the {what} needs a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({storage_limit})");
        }
    }
    let hits_bytes = (rays.len() * std::mem::size_of::<SearchHit>()) as u64;
    check_buffer_size(gpu, hits_bytes, "search hits", "search fewer rays at once")?;
    let params = SearchBatch { map: texels.views[0], steps: StepsUniform::new(steps), count: rays.len() as u32, pad: [0; 3] };
    let interface = DistanceSearchPass::INTERFACE;
    let (pipeline_layout, layouts) = interface.pipeline_layout(device);
    let [pipeline] = compute_pipelines(device, interface.shader, Some(&pipeline_layout), ["cs_search"], "the distance-map search")?;
    let buffer = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
    };
    let params_buffer = buffer("search params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
    let texel_buffer = buffer("distance map", bytemuck::cast_slice(&texels.geometry), wgpu::BufferUsages::STORAGE);
    let ray_buffer = buffer("search rays", bytemuck::cast_slice(rays), wgpu::BufferUsages::STORAGE);
    let hit_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("search hits"),
        size: hits_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = readback_buffer(gpu, hits_bytes)?;
    let bind_group = interface.bind_group(
        device,
        &layouts[0],
        0,
        &[(0, params_buffer.as_entire_binding()), (1, ray_buffer.as_entire_binding()), (2, hit_buffer.as_entire_binding())],
    )?;
    let map_group = interface.bind_group(device, &layouts[1], 1, &[(0, texel_buffer.as_entire_binding())])?;
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.set_bind_group(1, &map_group, &[]);
        pass.dispatch_workgroups((rays.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&hit_buffer, 0, &readback, 0, hits_bytes);
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu.read_buffer(&readback)?;
    Ok(bytemuck::cast_slice(&bytes).to_vec())
}

/// This module's structs shared with `shaders/distance_search.wgsl` (`crate::layout`).
pub fn shared_structs() -> Vec<crate::layout::SharedStruct> {
    vec![crate::layout::shared_struct!(SearchBatch as "SearchBatch" { map, steps, count, pad })]
}

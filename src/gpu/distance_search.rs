//! The distance-map search on the GPU (`shaders/distance_map.wgsl`): a compute pass that
//! runs the linear + secant search of GPU Gems 3 ch. 17 for a batch of rays against one
//! object's layered distance map, so the WGSL can be held to its CPU twin
//! (`effects::distance_map`) ray by ray. The map's texels go up as f32 (distance, normal);
//! a texel with nothing in it has distance −1.

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::compose::compute_pipelines;
use super::context::Gpu;
use super::render::{check_buffer_size, readback_buffer};
use crate::effects::distance_map::{start_tolerance, DistanceMap};
use crate::scene::SearchSteps;

/// The uniform block `SearchParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct SearchParams {
    size: u32,
    layers: u32,
    linear: u32,
    secant: u32,
    count: u32,
    tolerance: f32,
    pad: [u32; 2],
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

/// The map's texels in the shader's layout: layer-major, (distance, normal) in f32.
pub fn pack(map: &DistanceMap) -> Vec<[f32; 4]> {
    map.layers
        .iter()
        .flatten()
        .map(|texel| match texel {
            Some(t) => [t.distance as f32, t.normal.x as f32, t.normal.y as f32, t.normal.z as f32],
            None => [-1.0, 0.0, 0.0, 0.0],
        })
        .collect()
}

/// Run the search for every ray on the GPU and read the hits back.
pub fn search(gpu: &Gpu, map: &DistanceMap, rays: &[SearchRay], steps: SearchSteps) -> Result<Vec<SearchHit>> {
    if rays.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let texels = pack(map);
    let storage_limit = device.limits().max_storage_buffer_binding_size;
    for (what, bytes) in [("distance map", std::mem::size_of_val(texels.as_slice())), ("rays", std::mem::size_of_val(rays))] {
        if bytes as u64 > storage_limit {
            bail!("the {what} needs a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({storage_limit})");
        }
    }
    let hits_bytes = (rays.len() * std::mem::size_of::<SearchHit>()) as u64;
    check_buffer_size(gpu, hits_bytes, "search hits")?;
    let params = SearchParams {
        size: map.size,
        layers: map.layers.len() as u32,
        linear: steps.linear,
        secant: steps.secant,
        count: rays.len() as u32,
        tolerance: start_tolerance(map.size) as f32,
        pad: [0; 2],
    };
    let [pipeline] = compute_pipelines(device, "distance_map", None, ["cs_search"], "the distance-map search")?;
    let buffer = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
    let params_buffer = buffer("search params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
    let texel_buffer = buffer("distance map", bytemuck::cast_slice(&texels), wgpu::BufferUsages::STORAGE);
    let ray_buffer = buffer("search rays", bytemuck::cast_slice(rays), wgpu::BufferUsages::STORAGE);
    let hit_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("search hits"),
        size: hits_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = readback_buffer(gpu, hits_bytes)?;
    let layout = pipeline.get_bind_group_layout(0);
    let entries: Vec<wgpu::BindGroupEntry> = [&params_buffer, &texel_buffer, &ray_buffer, &hit_buffer]
        .iter()
        .enumerate()
        .map(|(binding, buffer)| wgpu::BindGroupEntry { binding: binding as u32, resource: buffer.as_entire_binding() })
        .collect();
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("distance-map search"), layout: &layout, entries: &entries });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups((rays.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&hit_buffer, 0, &readback, 0, hits_bytes);
    gpu.queue.submit([encoder.finish()]);
    let bytes = gpu.read_buffer(&readback)?;
    Ok(bytemuck::cast_slice(&bytes).to_vec())
}

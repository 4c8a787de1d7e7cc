//! The screen-space GTAO pass (`shaders/gtao.wgsl`): per pixel of a G-buffer of view-space
//! points and normals, the accessibility of Jimenez et al. 2016 (the derivation and the
//! f64/f32 CPU twin are `effects::ao::gtao`).
//!
//! Inputs: the G-buffer (per pixel a point, w = 1 where a surface is, and a unit normal),
//! the focal length in pixels, and GTAO's parameters (radius, slices, steps). Output: per
//! pixel the accessibility, `None` where no surface is ([`GtaoPass::run`]). One dispatch
//! of 8×8 workgroups; sizes are checked against the device's limits before any
//! allocation; wgpu errors come back as `Result`s. The kernel runs Algorithm 1 without the
//! heuristics of `effects::ao::gtao::Heuristics` (the bare preset); other parameters are
//! refused with an error.

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compute_pipelines;
use crate::context::Gpu;
use crate::render::{check_buffer_size, readback_buffer};
use nklut_effects::ao::gtao::{GBuffer, Parameters};

/// The workgroup's edge in pixels (`@workgroup_size(8, 8)`).
const TILE: u32 = 8;

/// The shader's uniform `GtaoParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct GtaoParams {
    width: u32,
    height: u32,
    slices: u32,
    steps: u32,
    focal: f32,
    radius: f32,
    pad: [f32; 2],
}

/// A G-buffer pixel as the shader reads it (`GSample`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct GSample {
    position: [f32; 4],
    normal: [f32; 4],
}

/// The pass with its G-buffer uploaded and its pipeline compiled.
pub struct GtaoPass {
    width: u32,
    height: u32,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    output: wgpu::Buffer,
}

impl Pass for GtaoPass {
    const INTERFACE: Interface = Interface {
        name: "gtao",
        shader: "gtao",
        entry_points: &["cs_gtao"],
        stages: wgpu::ShaderStages::COMPUTE,
        bindings: &[
            Binding::new(0, 0, "params", Resource::Uniform),
            Binding::new(0, 1, "gbuffer", Resource::Read),
            Binding::new(0, 2, "accessibility", Resource::ReadWrite),
        ],
    };
}

impl GtaoPass {
    /// Upload `gbuffer` and compile the kernel for `parameters`.
    pub fn new(gpu: &Gpu, gbuffer: &GBuffer<f32>, parameters: Parameters<f32>) -> Result<GtaoPass> {
        if parameters.heuristics != nklut_effects::ao::gtao::Heuristics::BARE.narrowed() {
            bail!(
                "the WGSL GTAO pass runs Algorithm 1 without heuristics (preset bare); these parameters carry heuristics: {parameters:?}"
            );
        }
        let (width, height) = (gbuffer.width, gbuffer.height);
        let pixels = width as usize * height as usize;
        if pixels == 0 || gbuffer.samples.len() != pixels {
            bail!("the G-buffer holds {} samples for {width}×{height} pixels", gbuffer.samples.len());
        }
        let limits = gpu.device.limits();
        let groups = [width.div_ceil(TILE), height.div_ceil(TILE)];
        if groups.iter().any(|&g| g > limits.max_compute_workgroups_per_dimension) {
            bail!(
                "{width}×{height} pixels need {}×{} workgroups of {TILE}×{TILE}, over this device's max_compute_workgroups_per_dimension ({})",
                groups[0],
                groups[1],
                limits.max_compute_workgroups_per_dimension
            );
        }
        let sizes = [("G-buffer", pixels * std::mem::size_of::<GSample>()), ("GTAO accessibility", pixels * 4)];
        for (what, bytes) in sizes {
            if bytes as u64 > limits.max_storage_buffer_binding_size {
                bail!(
                    "the {what} needs a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({})",
                    limits.max_storage_buffer_binding_size
                );
            }
            check_buffer_size(gpu, bytes as u64, what, "lower the resolution")?;
        }
        let samples: Vec<GSample> = gbuffer
            .samples
            .iter()
            .map(|s| match s {
                Some(s) => GSample {
                    position: [s.position[0], s.position[1], s.position[2], 1.0],
                    normal: [s.normal[0], s.normal[1], s.normal[2], 0.0],
                },
                None => GSample::default(),
            })
            .collect();
        let params = GtaoParams {
            width,
            height,
            slices: parameters.slices,
            steps: parameters.steps,
            focal: gbuffer.focal,
            radius: parameters.radius,
            pad: [0.0; 2],
        };
        let device = &gpu.device;
        let interface = Self::INTERFACE;
        let (pipeline_layout, layouts) = interface.pipeline_layout(device);
        let [pipeline] = compute_pipelines(device, interface.shader, Some(&pipeline_layout), ["cs_gtao"], "the GTAO kernel")?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let uniform = init("gtao params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
        let input = init("gtao g-buffer", bytemuck::cast_slice(&samples), wgpu::BufferUsages::STORAGE);
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("gtao accessibility"),
            size: (pixels * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let resources = [(0, uniform.as_entire_binding()), (1, input.as_entire_binding()), (2, output.as_entire_binding())];
        let bind_group = interface.bind_group(device, &layouts[0], 0, &resources)?;
        if let Some(error) = pollster::block_on(scope.pop()) {
            bail!("allocating the GTAO pass's buffers: {error}");
        }
        gpu.take_errors()?;
        Ok(GtaoPass { width, height, pipeline, bind_group, output })
    }

    /// Record the pass into `encoder`, with `timestamps` written at its start and end.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, timestamps: Option<wgpu::ComputePassTimestampWrites>) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("gtao"), timestamp_writes: timestamps });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.dispatch_workgroups(self.width.div_ceil(TILE), self.height.div_ceil(TILE), 1);
    }

    /// Run the pass and read back the accessibility per pixel (`None` where no surface is).
    pub fn run(&self, gpu: &Gpu) -> Result<Vec<Option<f32>>> {
        let bytes = self.output.size();
        let readback = readback_buffer(gpu, bytes)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(&mut encoder, None);
        encoder.copy_buffer_to_buffer(&self.output, 0, &readback, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
        let data = gpu.read_buffer(&readback)?;
        gpu.take_errors()?;
        Ok(bytemuck::cast_slice::<u8, f32>(&data).iter().map(|&a| (a >= 0.0).then_some(a)).collect())
    }
}

/// This module's structs shared with `shaders/gtao.wgsl` (`crate::layout`).
pub fn shared_structs() -> Vec<crate::layout::SharedStruct> {
    use crate::layout::shared_struct;
    vec![
        shared_struct!(GtaoParams as "GtaoParams" { width, height, slices, steps, focal, radius, pad }),
        shared_struct!(GSample as "GSample" { position, normal }),
    ]
}

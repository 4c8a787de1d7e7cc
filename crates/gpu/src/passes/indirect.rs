//! The surfel indirect-light pass (`cs_indirect` of `shaders/surfel_ao.wgsl`): diffuse
//! light bounced between surfels, brute force over emitters (Bunnell, GPU Gems 2 ch. 14,
//! indirect lighting; the f64 CPU twin is `effects::ao::indirect::surfel_indirect`,
//! docs/ao.md).
//!
//! Inputs: the surfels, the shadow form's gain g, per surfel its albedo and direct
//! irradiance (linear RGB, from the CPU's shadow rays), per emitter a weight (its
//! accessibility, or 1), the bounce count. Output: per surfel the indirect irradiance summed
//! over the bounces ([`IndirectOutput`]) and the dispatches. A bounce gathers
//! E(i) = Σ_j B_j · F_ij · w_j with B_j = ρ_j · E_prev(j) (E_prev: direct light for the first
//! bounce); the radiosity of the next bounce is formed on the CPU in f32 between
//! dispatches. Sizes are checked against the device's limits before allocation; wgpu
//! errors come back as `Result`s.

use anyhow::{bail, Result};
use wgpu::util::DeviceExt;

use super::ao::{GpuDisc, Params};
use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compute_pipelines;
use crate::context::Gpu;
use crate::render::{check_buffer_size, readback_buffer};
use nklut_effects::ao::indirect::Rgb;
use nklut_effects::ao::shadow::ShadowForm;
use nklut_effects::ao::surfel::Surfel;

const WORKGROUP: u32 = 64;

/// Indirect irradiance per surfel summed over the bounces, and the dispatches recorded.
#[derive(Clone, Debug, PartialEq)]
pub struct IndirectOutput {
    pub irradiance: Vec<[f32; 3]>,
    pub dispatches: u64,
}

/// The pass with its buffers and pipeline.
pub struct IndirectPass {
    count: u32,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    weights: wgpu::Buffer,
    radiosity: wgpu::Buffer,
    gathered: wgpu::Buffer,
}

impl Pass for IndirectPass {
    const INTERFACE: Interface = Interface {
        name: "surfel indirect",
        shader: "surfel_ao",
        entry_points: &["cs_indirect"],
        stages: wgpu::ShaderStages::COMPUTE,
        bindings: &[
            Binding::new(0, 0, "params", Resource::Uniform),
            Binding::new(0, 1, "discs", Resource::Read),
            Binding::new(0, 3, "state", Resource::ReadWrite),
            Binding::new(0, 5, "radiosity", Resource::Read),
            Binding::new(0, 6, "gathered", Resource::ReadWrite),
        ],
    };
}

impl IndirectPass {
    /// Upload `surfels` and compile the gather.
    pub fn new(gpu: &Gpu, surfels: &[Surfel], form: ShadowForm) -> Result<IndirectPass> {
        if surfels.is_empty() {
            bail!("the indirect pass needs at least one surfel");
        }
        let n = surfels.len();
        let limits = gpu.device.limits();
        if n.div_ceil(WORKGROUP as usize) > limits.max_compute_workgroups_per_dimension as usize {
            bail!(
                "{n} surfels need more workgroups than this device's max_compute_workgroups_per_dimension ({})",
                limits.max_compute_workgroups_per_dimension
            );
        }
        for (what, bytes) in [("surfels", n * std::mem::size_of::<GpuDisc>()), ("radiosity", n * 16), ("weights", n * 4)] {
            if bytes as u64 > limits.max_storage_buffer_binding_size {
                bail!(
                    "the {what} need a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({})",
                    limits.max_storage_buffer_binding_size
                );
            }
            check_buffer_size(gpu, bytes as u64, what, "use fewer surfels (coarser meshes, less subdivide)")?;
        }
        let device = &gpu.device;
        let interface = Self::INTERFACE;
        let (pipeline_layout, layouts) = interface.pipeline_layout(device);
        let [pipeline] =
            compute_pipelines(device, interface.shader, Some(&pipeline_layout), ["cs_indirect"], "the surfel indirect-light kernel")?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let writable = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        // The emitters' weights at offset 0 of their buffer.
        let params = Params { count: n as u32, gain: form.receiver_gain as f32, ..Params::default() };
        let uniform = init("surfel indirect params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
        let discs: Vec<GpuDisc> = surfels.iter().map(GpuDisc::new).collect();
        let disc_buffer = init("surfels", bytemuck::cast_slice(&discs), wgpu::BufferUsages::STORAGE);
        let weights = init("emitter weights", bytemuck::cast_slice(&vec![1.0f32; n]), writable);
        let radiosity = init("radiosity", bytemuck::cast_slice(&vec![[0.0f32; 4]; n]), writable);
        let gathered = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("gathered irradiance"),
            size: (n * 16) as u64,
            usage: writable,
            mapped_at_creation: false,
        });
        let buffers = [(0, &uniform), (1, &disc_buffer), (3, &weights), (5, &radiosity), (6, &gathered)];
        let resources: Vec<(u32, wgpu::BindingResource)> = buffers.iter().map(|(binding, b)| (*binding, b.as_entire_binding())).collect();
        let bind_group = interface.bind_group(device, &layouts[0], 0, &resources)?;
        if let Some(error) = pollster::block_on(scope.pop()) {
            bail!("allocating the indirect pass's buffers: {error}");
        }
        gpu.take_errors()?;
        Ok(IndirectPass { count: n as u32, pipeline, bind_group, weights, radiosity, gathered })
    }

    /// One bounce: what every surfel gathers from the others' `radiosity`.
    fn gather(&self, gpu: &Gpu, radiosity: &[[f32; 4]]) -> Result<Vec<[f32; 4]>> {
        gpu.queue.write_buffer(&self.radiosity, 0, bytemuck::cast_slice(radiosity));
        let bytes = self.count as u64 * 16;
        let readback = readback_buffer(gpu, bytes)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(self.count.div_ceil(WORKGROUP), 1, 1);
        }
        encoder.copy_buffer_to_buffer(&self.gathered, 0, &readback, 0, bytes);
        gpu.queue.submit([encoder.finish()]);
        Ok(bytemuck::cast_slice(&gpu.read_buffer(&readback)?).to_vec())
    }

    /// Indirect irradiance after `bounces` bounces (summed), emitters weighted by
    /// `weights`; `albedo` and `direct` per surfel.
    pub fn run(&self, gpu: &Gpu, albedo: &[Rgb], direct: &[Rgb], weights: &[f64], bounces: u32) -> Result<IndirectOutput> {
        let n = self.count as usize;
        if albedo.len() != n || direct.len() != n || weights.len() != n {
            bail!(
                "the indirect pass has {n} surfels; got {} albedos, {} direct irradiances, {} weights",
                albedo.len(),
                direct.len(),
                weights.len()
            );
        }
        let narrow: Vec<f32> = weights.iter().map(|&w| w as f32).collect();
        gpu.queue.write_buffer(&self.weights, 0, bytemuck::cast_slice(&narrow));
        let mut lighting: Vec<[f32; 4]> = direct.iter().map(|e| [e[0] as f32, e[1] as f32, e[2] as f32, 0.0]).collect();
        let mut total = vec![[0.0f32; 3]; n];
        for _ in 0..bounces {
            let radiosity: Vec<[f32; 4]> = lighting
                .iter()
                .zip(albedo)
                .map(|(e, rho)| [e[0] * rho[0] as f32, e[1] * rho[1] as f32, e[2] * rho[2] as f32, 0.0])
                .collect();
            lighting = self.gather(gpu, &radiosity)?;
            for (t, e) in total.iter_mut().zip(&lighting) {
                for c in 0..3 {
                    t[c] += e[c];
                }
            }
        }
        Ok(IndirectOutput { irradiance: total, dispatches: bounces as u64 })
    }
}

//! The screen-space GTAO pass (`shaders/gtao.wgsl`): per pixel of a G-buffer of view-space
//! points and normals, the accessibility of Jimenez et al. 2016 with the heuristics
//! engines add (XeGTAO; the derivation and the f64/f32 CPU twin are `effects::ao::gtao`,
//! whose every heuristic the kernel runs: radius multiplier, falloff, sample distribution
//! power and start offset, thin-occluder compensation, final power, the |n_φ| lerp, the
//! screen-radius clamp, depth reads clamped to the image's edge, per-pixel Hilbert-R2 noise
//! with N-frame accumulation, and XeGTAO's edge-aware denoiser, `effects::ao::denoise`).
//!
//! Inputs: the G-buffer (per pixel a point, w = 1 where a surface is, and a unit normal),
//! the focal length in pixels, and GTAO's parameters ([`Parameters`]), in the uniform
//! `GtaoParams` (one copy per frame, each with its frame index, bound at its own offset).
//! Output: per pixel the accessibility, `None` where no surface is ([`GtaoPass::run`]),
//! the mean of the accumulated frames. One dispatch of 8×8 workgroups per frame, every frame
//! adding to the running sum in the output buffer and the last dividing by the frame count
//! (the CPU body's order); then one dispatch per denoiser pass, reading one of two image
//! buffers and writing the other. Sizes are checked against the device's limits before any
//! allocation; wgpu errors come back as `Result`s.

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compute_pipelines;
use crate::context::Gpu;
use crate::render::{check_buffer_size, readback_buffer};
use nklut_effects::ao::denoise::centre_weight;
use nklut_effects::ao::gtao::{GBuffer, Parameters};
use nklut_effects::scene::surfels::{MAX_DENOISE_PASSES, MAX_GTAO_FRAMES};

/// The workgroup's edge in pixels (`@workgroup_size(8, 8)`).
const TILE: u32 = 8;

/// The shader's uniform `GtaoParams`: the frame's size, the parameters and heuristics of
/// [`Parameters`] as the f32 twin holds them, and which frame of how many this dispatch is.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct GtaoParams {
    width: u32,
    height: u32,
    slices: u32,
    steps: u32,
    frame: u32,
    frames: u32,
    noise: u32,
    clamp_to_edge: u32,
    focal: f32,
    radius: f32,
    radius_multiplier: f32,
    falloff_range: f32,
    distribution_power: f32,
    start_pixels: f32,
    thin_occluder: f32,
    thickness_blend: f32,
    final_power: f32,
    normal_lerp: f32,
    min_radius_pixels: f32,
    max_radius_pixels: f32,
    denoise_centre: f32,
    denoise_last: u32,
    pad0: u32,
    pad1: u32,
}

impl GtaoParams {
    /// Frame `frame`'s uniform for a `width` × `height` G-buffer of focal length `focal`.
    /// An unclamped screen radius (∞) is the largest f32: `min` with it leaves every finite
    /// radius as it is, as `min` with ∞ does on the CPU, without an ∞ in the shader.
    fn new(width: u32, height: u32, focal: f32, p: Parameters<f32>, frame: u32) -> GtaoParams {
        let h = p.heuristics;
        GtaoParams {
            width,
            height,
            slices: p.slices,
            steps: p.steps,
            frame,
            frames: accumulated_frames(p),
            noise: u32::from(h.noise),
            clamp_to_edge: u32::from(h.clamp_to_edge),
            focal,
            radius: p.radius,
            radius_multiplier: h.radius_multiplier,
            falloff_range: h.falloff_range,
            distribution_power: h.distribution_power,
            start_pixels: h.start_pixels,
            thin_occluder: h.thin_occluder,
            thickness_blend: h.thickness_blend,
            final_power: h.final_power,
            normal_lerp: h.normal_lerp,
            min_radius_pixels: h.min_radius_pixels,
            max_radius_pixels: h.max_radius_pixels.min(f32::MAX),
            denoise_centre: 0.0,
            denoise_last: 0,
            pad0: 0,
            pad1: 0,
        }
    }

    /// Denoiser pass `pass`'s uniform: the frame's, with the centre pixel's weight
    /// (`effects::ao::denoise::centre_weight` in f32) and the last-pass flag.
    fn denoising(self, p: Parameters<f32>, pass: u32) -> GtaoParams {
        let last = pass + 1 == p.heuristics.denoise_passes;
        GtaoParams { denoise_centre: centre_weight(p.heuristics.denoise_beta, last), denoise_last: u32::from(last), ..self }
    }
}

/// The frames `effects::ao::gtao::pixel_visibility` accumulates: `frames` (at least 1)
/// with noise, one without (every frame the same).
pub fn accumulated_frames(p: Parameters<f32>) -> u32 {
    if p.heuristics.noise {
        p.heuristics.frames.max(1)
    } else {
        1
    }
}

/// Why the pass refuses `p`: a number that is not finite (or ∞ where only the screen-radius
/// maximum may be), or more frames than a scene may accumulate.
fn check_parameters(p: &Parameters<f32>, focal: f32) -> Result<()> {
    let h = &p.heuristics;
    let finite = [
        ("focal length", focal),
        ("radius", p.radius),
        ("radius_multiplier", h.radius_multiplier),
        ("falloff_range", h.falloff_range),
        ("distribution_power", h.distribution_power),
        ("start_pixels", h.start_pixels),
        ("thin_occluder", h.thin_occluder),
        ("thickness_blend", h.thickness_blend),
        ("final_power", h.final_power),
        ("normal_lerp", h.normal_lerp),
        ("min_radius_pixels", h.min_radius_pixels),
        ("denoise_beta", h.denoise_beta),
    ];
    for (name, value) in finite {
        if !value.is_finite() {
            bail!("GTAO's {name} is {value}: the GPU pass takes finite numbers");
        }
    }
    if h.denoise_passes > 0 && h.denoise_beta <= 0.0 {
        bail!("GTAO's denoise_beta is {}: the denoiser's centre weight must be positive", h.denoise_beta);
    }
    if h.denoise_passes > MAX_DENOISE_PASSES {
        bail!("GTAO's denoiser runs {} passes; at most {MAX_DENOISE_PASSES}", h.denoise_passes);
    }
    if h.max_radius_pixels.is_nan() {
        bail!("GTAO's max_radius_pixels is NaN");
    }
    let frames = accumulated_frames(*p);
    if frames > MAX_GTAO_FRAMES {
        bail!("GTAO accumulates {frames} frames; at most {MAX_GTAO_FRAMES}");
    }
    Ok(())
}

/// A G-buffer pixel as the shader reads it (`GSample`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct GSample {
    position: [f32; 4],
    normal: [f32; 4],
}

/// The G-buffer as the shader reads it (`GSample` per pixel: w = 1 where a surface is).
pub fn gbuffer_bytes(gbuffer: &GBuffer<f32>) -> Vec<u8> {
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
    bytemuck::cast_slice(&samples).to_vec()
}

/// The bytes between two frames' uniforms: `GtaoParams`' size rounded up to the device's
/// uniform offset alignment.
pub fn uniform_stride(alignment: u32) -> u64 {
    (std::mem::size_of::<GtaoParams>() as u64).next_multiple_of(alignment.max(1) as u64)
}

/// The size of one frame's uniform (`GtaoParams`).
pub const UNIFORM_SIZE: u64 = std::mem::size_of::<GtaoParams>() as u64;

/// Every accumulated frame's uniform, frame k at byte k × `stride`, then each denoiser
/// pass's: pass j at byte (frames + j) × `stride` ([`uniform_slots`] in all).
pub fn uniform_bytes(gbuffer: &GBuffer<f32>, parameters: Parameters<f32>, stride: u64) -> Vec<u8> {
    let frames = accumulated_frames(parameters);
    let size = UNIFORM_SIZE as usize;
    let mut uniforms = vec![0u8; (stride * uniform_slots(parameters) as u64) as usize];
    let frame_params = |frame| GtaoParams::new(gbuffer.width, gbuffer.height, gbuffer.focal, parameters, frame);
    let denoise = (0..parameters.heuristics.denoise_passes).map(|pass| frame_params(frames - 1).denoising(parameters, pass));
    for (slot, params) in (0..frames).map(frame_params).chain(denoise).enumerate() {
        let at = stride as usize * slot;
        uniforms[at..at + size].copy_from_slice(bytemuck::bytes_of(&params));
    }
    uniforms
}

/// The uniforms one configuration needs: one per accumulated frame and one per denoiser
/// pass.
pub fn uniform_slots(parameters: Parameters<f32>) -> u32 {
    accumulated_frames(parameters) + parameters.heuristics.denoise_passes
}

/// The frame a timing of one frame dispatches: the second of an accumulating configuration
/// (it reads the running sum and adds to it, as every frame after the first), else the one.
pub fn timed_frame(frames: u32) -> u32 {
    frames.clamp(1, 2) - 1
}

/// The pass with its G-buffer uploaded and its pipelines compiled.
pub struct GtaoPass {
    width: u32,
    height: u32,
    frames: u32,
    /// The frame kernel and the denoiser's two (accessibility → denoised, and back).
    pipelines: [wgpu::ComputePipeline; 3],
    /// One per accumulated frame, then one per denoiser pass: the uniform at its offset.
    bind_groups: Vec<wgpu::BindGroup>,
    output: wgpu::Buffer,
    denoised: wgpu::Buffer,
}

impl Pass for GtaoPass {
    const INTERFACE: Interface = Interface {
        name: "gtao",
        shader: "gtao",
        entry_points: &["cs_gtao", "cs_denoise_forward", "cs_denoise_back"],
        stages: wgpu::ShaderStages::COMPUTE,
        bindings: &[
            Binding::new(0, 0, "params", Resource::Uniform),
            Binding::new(0, 1, "gbuffer", Resource::Read),
            Binding::new(0, 2, "accessibility", Resource::ReadWrite),
            Binding::new(0, 3, "denoised", Resource::ReadWrite),
        ],
    };
}

impl GtaoPass {
    /// Upload `gbuffer` and compile the kernel for `parameters`.
    pub fn new(gpu: &Gpu, gbuffer: &GBuffer<f32>, parameters: Parameters<f32>) -> Result<GtaoPass> {
        check_parameters(&parameters, gbuffer.focal)?;
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
        let sizes = [
            ("G-buffer", pixels * std::mem::size_of::<GSample>()),
            ("GTAO accessibility", pixels * 4),
            ("GTAO denoiser's buffer", pixels * 4),
        ];
        for (what, bytes) in sizes {
            if bytes as u64 > limits.max_storage_buffer_binding_size {
                bail!(
                    "the {what} needs a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({})",
                    limits.max_storage_buffer_binding_size
                );
            }
            check_buffer_size(gpu, bytes as u64, what, "lower the resolution")?;
        }
        let samples = gbuffer_bytes(gbuffer);
        let stride = uniform_stride(limits.min_uniform_buffer_offset_alignment);
        let uniforms = uniform_bytes(gbuffer, parameters, stride);
        let size = std::mem::size_of::<GtaoParams>() as u64;
        let frames = accumulated_frames(parameters);
        let slots = uniform_slots(parameters);
        let device = &gpu.device;
        let interface = Self::INTERFACE;
        let (pipeline_layout, layouts) = interface.pipeline_layout(device);
        let pipelines = compute_pipelines(
            device,
            interface.shader,
            Some(&pipeline_layout),
            ["cs_gtao", "cs_denoise_forward", "cs_denoise_back"],
            "the GTAO kernels",
        )?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let uniform = init("gtao params", &uniforms, wgpu::BufferUsages::UNIFORM);
        let input = init("gtao g-buffer", &samples, wgpu::BufferUsages::STORAGE);
        let image = |label: &str| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: (pixels * 4) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let (output, denoised) = (image("gtao accessibility"), image("gtao denoised"));
        let bind_groups = (0..slots as u64)
            .map(|slot| {
                let params = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &uniform,
                    offset: slot * stride,
                    size: std::num::NonZeroU64::new(size),
                });
                let resources =
                    [(0, params), (1, input.as_entire_binding()), (2, output.as_entire_binding()), (3, denoised.as_entire_binding())];
                interface.bind_group(device, &layouts[0], 0, &resources)
            })
            .collect::<Result<Vec<_>>>()?;
        if let Some(error) = pollster::block_on(scope.pop()) {
            bail!("allocating the GTAO pass's buffers: {error}");
        }
        gpu.take_errors()?;
        Ok(GtaoPass { width, height, frames, pipelines, bind_groups, output, denoised })
    }

    /// The frames accumulated ([`accumulated_frames`]): one dispatch each.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// The denoiser's passes: one dispatch each, after the frames.
    pub fn denoise_passes(&self) -> u32 {
        self.bind_groups.len() as u32 - self.frames
    }

    /// Record every frame (the accumulated result) and the denoiser's passes over it into
    /// `encoder`, in one compute pass with `timestamps` written at its start and end.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, timestamps: Option<wgpu::ComputePassTimestampWrites>) {
        self.encode_frames(encoder, 0..self.frames(), timestamps);
    }

    /// Record the dispatches of `frames` (clamped to the accumulated ones) and then the
    /// denoiser's passes into `encoder`, in one compute pass: a frame after the first adds
    /// to what the output holds, so the result is the accumulated one only for
    /// `0..frames()`; one frame alone with the denoiser is what a frame costs (an engine
    /// denoises every frame before its temporal accumulation).
    pub fn encode_frames(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frames: std::ops::Range<u32>,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("gtao"), timestamp_writes: timestamps });
        let groups = (self.width.div_ceil(TILE), self.height.div_ceil(TILE));
        pass.set_pipeline(&self.pipelines[0]);
        for frame in frames.start.min(self.frames())..frames.end.min(self.frames()) {
            pass.set_bind_group(0, &self.bind_groups[frame as usize], &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        }
        for denoise in 0..self.denoise_passes() {
            pass.set_pipeline(&self.pipelines[1 + denoise as usize % 2]);
            pass.set_bind_group(0, &self.bind_groups[(self.frames + denoise) as usize], &[]);
            pass.dispatch_workgroups(groups.0, groups.1, 1);
        }
    }

    /// Run every frame and the denoiser, and read back the accumulated, denoised
    /// accessibility per pixel (`None` where no surface is).
    pub fn run(&self, gpu: &Gpu) -> Result<Vec<Option<f32>>> {
        // An odd number of denoiser passes leaves the result in the denoiser's buffer.
        let result = if self.denoise_passes() % 2 == 1 { &self.denoised } else { &self.output };
        let bytes = result.size();
        let readback = readback_buffer(gpu, bytes)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(&mut encoder, None);
        encoder.copy_buffer_to_buffer(result, 0, &readback, 0, bytes);
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
        shared_struct!(GtaoParams as "GtaoParams" {
            width, height, slices, steps, frame, frames, noise, clamp_to_edge, focal, radius, radius_multiplier, falloff_range,
            distribution_power, start_pixels, thin_occluder, thickness_blend, final_power, normal_lerp, min_radius_pixels,
            max_radius_pixels, denoise_centre, denoise_last, pad0, pad1,
        }),
        shared_struct!(GSample as "GSample" { position, normal }),
    ]
}

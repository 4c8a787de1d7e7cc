//! The specular-effects shading pass (`shaders/specular.wgsl`): every object of the scene
//! rasterised from the camera; diffuse fragments show their lit colour, specular fragments
//! run the bounce loop of Umenhoffer, Patow and Szirmay-Kalos (GPU Gems 3 ch. 17) through
//! the distance maps of [`super::distance_maps`], with F from one Fresnel method. The CPU
//! twin is `effects::trace::render` with `effects::distance_map::DistanceMapTracer`.
//!
//! Pipelines are keyed by (effect, method) and compiled on first use: the effect
//! [`Effect::Reflection`] compiles the refraction branch out, so a scene that names no
//! refraction never builds a refraction pipeline. The `lut` method reads an atlas of two
//! rows per specular object — the curve from outside (η) and from inside (conj(1/η), whose
//! exact curve is 1 past the critical angle) — baked like the runner's LUTs: exact F at
//! texel centres, half floats, linear filter, clamp-to-edge.
//!
//! Input: the stage, [`GpuMaps`], the camera frame, depths and search steps. Output: an
//! RGBA32Float target — rgb the linear radiance, a = 1 + the specular object a pixel shows
//! (0: a diffuse surface or nothing) — read back as an [`EffectImage`].

use std::collections::HashMap;
use std::fmt;

use anyhow::{anyhow, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::distance_maps::{mesh_pipeline, DiffuseUniform, GpuMaps, LightsUniform, MapView, SceneMeshes, StepsUniform};
use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compose;
use crate::context::Gpu;
use crate::contracts::ObjectRole;
use crate::params::{prepare, MaterialUniform};
use crate::render::{readback_buffer, Target, FLOAT_TARGET};
use crate::{camera, lut};
use nklut_effects::optics::{inside_index, GEOMETRIC_CHANNEL};
use nklut_effects::scene::{CameraPath, Depths, SearchSteps};
use nklut_effects::trace::{ObjectOptics, Stage};
use nklut_optics::fresnel::Method;
use nklut_optics::spectrum::Kind;

/// Which bounces a pipeline can take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// Mirror reflections only (the refraction branch compiled out).
    Reflection,
    /// Reflections and refractions.
    Refraction,
}

impl Effect {
    /// The effect a depth configuration needs.
    pub fn of(depths: Depths) -> Effect {
        if depths.refraction > 0 {
            Effect::Refraction
        } else {
            Effect::Reflection
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Effect::Reflection => "reflection",
            Effect::Refraction => "refraction",
        }
    }
}

impl fmt::Display for Effect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The call of the Fresnel library for curve `curve` (2m: material m from outside, 2m + 1
/// from inside).
fn reflectance_call(method: Method) -> String {
    match method {
        Method::Lut => "nklut_fresnel_lut(lut_atlas, lut_sampler, c, curve)".into(),
        other => format!("{}(c, materials[curve])", crate::params::wgsl_function(nklut_effects::scene::Shading::Fresnel(other))),
    }
}

/// The shading module of (effect, method): `shaders/specular.wgsl` and its imports plus the
/// two generated lines that pick them.
pub fn compose_effect(effect: Effect, method: Method) -> Result<String, crate::compose::ComposeError> {
    compose(&format!(
        "const REFRACTION: bool = {};\nfn reflectance(c: f32, curve: u32) -> vec3<f32> {{ return {}; }}\n#import specular\n",
        effect == Effect::Refraction,
        reflectance_call(method)
    ))
}

/// `EffectFrame` of `shaders/specular.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub lights: LightsUniform,
    pub steps: StepsUniform,
    pub depths: [u32; 4],
}

impl FrameUniform {
    /// The frame of `shot` on a target of `width` × `height` pixels, lit by `lights`.
    pub fn new(lights: LightsUniform, shot: Shot, [width, height]: [u32; 2]) -> FrameUniform {
        let near = 1e-3 * shot.camera.distance.max(1e-3);
        let far = 100.0 * shot.camera.distance.max(1.0);
        let view = camera::frame_within(shot.camera, shot.frame, width, height, near, far);
        FrameUniform {
            view_proj: view.view_proj.map(|column| column.map(|x| x as f32)),
            eye: [view.eye[0] as f32, view.eye[1] as f32, view.eye[2] as f32, 1.0],
            lights,
            steps: StepsUniform::new(shot.steps),
            depths: [shot.depths.reflection, shot.depths.refraction, 0, 0],
        }
    }
}

/// `SceneObject` of `shaders/specular.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ObjectUniform {
    pub surface: DiffuseUniform,
    pub role: [u32; 4],
    pub geometric_n: [f32; 4],
    pub map: MapView,
}

/// The shading pass's per-stage data, as plain data: each object's uniform (its map left
/// empty: [`StageUniforms::with_maps`] fills it), the materials (per specular object, its
/// parameters from outside then from inside; one empty material where there is none, as a
/// binding is never empty) and each specular object's channel indices (the LUT atlas's
/// source).
#[derive(Clone, Debug, PartialEq)]
pub struct StageUniforms {
    pub objects: Vec<ObjectUniform>,
    pub materials: Vec<MaterialUniform>,
    pub channels: Vec<nklut_optics::spectrum::ChannelIndex>,
    pub lights: LightsUniform,
}

impl StageUniforms {
    pub fn of(stage: &Stage) -> StageUniforms {
        let mut objects = Vec::new();
        let mut materials = Vec::new();
        let mut channels = Vec::new();
        for optics in &stage.objects {
            objects.push(match optics {
                ObjectOptics::Diffuse(d) => ObjectUniform { surface: DiffuseUniform::new(d), ..Default::default() },
                ObjectOptics::Specular(m) => {
                    let role = match m.kind {
                        Kind::Conductor => ObjectRole::Conductor,
                        Kind::Dielectric => ObjectRole::Dielectric,
                    }
                    .code();
                    let material = channels.len() as u32;
                    materials.push(MaterialUniform::from_channels(&m.channels));
                    materials.push(MaterialUniform::from_channels(&m.channels.map(inside_index)));
                    channels.push(m.channels);
                    ObjectUniform {
                        role: [role, material, 0, 0],
                        geometric_n: [m.channels[GEOMETRIC_CHANNEL].n as f32, 0.0, 0.0, 0.0],
                        ..Default::default()
                    }
                }
            });
        }
        if materials.is_empty() {
            materials.push(MaterialUniform::default());
        }
        StageUniforms { objects, materials, channels, lights: LightsUniform::new(&stage.lights) }
    }

    /// Each object's uniform with its map of `views` (`map_of[o]`; none for diffuse objects).
    pub fn with_maps(&self, map_of: &[Option<u32>], views: &[MapView]) -> Vec<ObjectUniform> {
        self.objects
            .iter()
            .zip(map_of)
            .map(|(object, map)| ObjectUniform { map: map.map(|m| views[m as usize]).unwrap_or_default(), ..*object })
            .collect()
    }

    /// The `lut` atlas's texels, `lut_size` per row: per specular object, its curve from
    /// outside then from inside (`2 × channels` rows; none without specular objects).
    pub fn lut_atlas(&self, lut_size: usize) -> Vec<[f32; 4]> {
        let mut texels = Vec::new();
        for channels in &self.channels {
            texels.extend(lut::texels(&prepare(channels), lut_size));
            texels.extend(lut::texels(&prepare(&channels.map(inside_index)), lut_size));
        }
        texels
    }
}

/// One rendered frame of the effect, read back.
#[derive(Clone, Debug, PartialEq)]
pub struct EffectImage {
    pub width: u32,
    pub height: u32,
    /// Linear RGB per pixel, row-major, top row first.
    pub radiance: Vec<[f32; 3]>,
    /// The specular object each pixel shows (`None`: a diffuse surface or nothing).
    pub seen: Vec<Option<usize>>,
}

/// One frame's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shot<'a> {
    pub camera: &'a CameraPath,
    pub frame: u32,
    pub depths: Depths,
    pub steps: SearchSteps,
}

/// The shading pass of one stage: its buffers, and its pipelines by (effect, method).
pub struct SpecularPass {
    /// Group 0 (the frame, objects, materials, LUT) and group 1 (the maps).
    layouts: Vec<wgpu::BindGroupLayout>,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: HashMap<(Effect, Method), wgpu::RenderPipeline>,
    /// Each object's uniform but its map (set per frame from the maps bound), the
    /// materials, lights and LUT sources.
    uniforms: StageUniforms,
    materials: wgpu::Buffer,
    lut_atlas: Option<wgpu::TextureView>,
    blank: wgpu::TextureView,
    sampler: wgpu::Sampler,
    /// Pipelines compiled so far.
    pub pipelines_compiled: usize,
    /// LUT curves baked (two per specular object, only when a `lut` pipeline was asked for).
    pub lut_curves: usize,
    lut_size: usize,
}

impl Pass for SpecularPass {
    const INTERFACE: Interface = Interface {
        name: "specular effect",
        shader: "specular",
        entry_points: &["vs_effect", "fs_effect"],
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[
            Binding::new(0, 0, "frame", Resource::Uniform),
            Binding::new(0, 1, "objects", Resource::Read),
            Binding::new(0, 2, "materials", Resource::Read),
            Binding::new(0, 3, "lut_atlas", Resource::Texture2d),
            Binding::new(0, 4, "lut_sampler", Resource::Sampler),
            Binding::new(1, 0, "map_texels", Resource::Read),
            Binding::new(1, 1, "map_surfaces", Resource::Read),
        ],
    };
}

impl SpecularPass {
    /// The pass for `stage`; `lut_size` texels per curve for the `lut` method.
    pub fn new(gpu: &Gpu, stage: &Stage, lut_size: usize) -> Result<SpecularPass> {
        let device = &gpu.device;
        let (pipeline_layout, layouts) = Self::INTERFACE.pipeline_layout(device);
        let uniforms = StageUniforms::of(stage);
        let materials = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("effect materials"),
            contents: bytemuck::cast_slice(&uniforms.materials),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Ok(SpecularPass {
            layouts,
            pipeline_layout,
            pipelines: HashMap::new(),
            uniforms,
            materials,
            lut_atlas: None,
            blank: lut::upload(gpu, &[[1.0; 4]], "blank").create_view(&Default::default()),
            sampler: lut::sampler(gpu),
            pipelines_compiled: 0,
            lut_curves: 0,
            lut_size,
        })
    }

    /// The pipeline of (effect, method), compiled on first use; a shader that does not
    /// validate is an error naming both.
    pub fn pipeline(&mut self, gpu: &Gpu, effect: Effect, method: Method) -> Result<&wgpu::RenderPipeline> {
        if method == Method::Lut && self.lut_atlas.is_none() {
            self.bake_luts(gpu);
        }
        if !self.pipelines.contains_key(&(effect, method)) {
            let source = compose_effect(effect, method)?;
            let interface = Self::INTERFACE;
            let label = format!("the {effect} pipeline of {}", method.name());
            let target = Some(wgpu::ColorTargetState { format: FLOAT_TARGET, blend: None, write_mask: wgpu::ColorWrites::ALL });
            let entries = [interface.entry_points[0], interface.entry_points[1]];
            let pipeline = mesh_pipeline(&gpu.device, &label, &self.pipeline_layout, source, entries, &[target])?;
            self.pipelines.insert((effect, method), pipeline);
            self.pipelines_compiled += 1;
        }
        self.pipelines.get(&(effect, method)).ok_or_else(|| anyhow!("pipeline {effect} {} missing", method.name()))
    }

    /// Bake the `lut` atlas: per specular object, its curve from outside then from inside.
    fn bake_luts(&mut self, gpu: &Gpu) {
        let texels = self.uniforms.lut_atlas(self.lut_size);
        let rows = 2 * self.uniforms.channels.len() as u32;
        if rows > 0 {
            self.lut_atlas = Some(lut::upload_rows(gpu, &texels, rows, "effect lut atlas").create_view(&Default::default()));
            self.lut_curves = rows as usize;
        }
    }

    /// The (effect, method) pairs compiled so far.
    pub fn compiled(&self) -> impl Iterator<Item = (Effect, Method)> + '_ {
        self.pipelines.keys().copied()
    }

    /// Encode one frame of (effect, method) into `target`, with optional timestamps at the
    /// start and end of the pass. The pipeline must have been compiled ([`Self::pipeline`]).
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        gpu: &Gpu,
        meshes: &SceneMeshes,
        maps: &GpuMaps,
        shot: Shot,
        method: Method,
        target: &Target,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: Option<&wgpu::QuerySet>,
    ) -> Result<()> {
        let effect = Effect::of(shot.depths);
        let pipeline =
            self.pipelines.get(&(effect, method)).ok_or_else(|| anyhow!("the {effect} pipeline of {} was not compiled", method.name()))?;
        let device = &gpu.device;
        let uniform = FrameUniform::new(self.uniforms.lights, shot, [target.width, target.height]);
        let frame = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("effect frame"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let objects = self.uniforms.with_maps(&maps.map_of, &maps.views);
        let objects = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("effect objects"),
            contents: bytemuck::cast_slice(&objects),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let interface = Self::INTERFACE;
        let lut = self.lut_atlas.as_ref().unwrap_or(&self.blank);
        let frame_group = interface.bind_group(
            device,
            &self.layouts[0],
            0,
            &[
                (0, frame.as_entire_binding()),
                (1, objects.as_entire_binding()),
                (2, self.materials.as_entire_binding()),
                (3, wgpu::BindingResource::TextureView(lut)),
                (4, wgpu::BindingResource::Sampler(&self.sampler)),
            ],
        )?;
        let maps_group = interface.bind_group(
            device,
            &self.layouts[1],
            1,
            &[(0, maps.geometry.as_entire_binding()), (1, maps.surfaces.as_entire_binding())],
        )?;
        let writes = timestamps.map(|set| wgpu::RenderPassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        });
        let mut pass = target.begin(encoder, writes);
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &frame_group, &[]);
        pass.set_bind_group(1, &maps_group, &[]);
        meshes.draw(&mut pass, |_| true);
        Ok(())
    }

    /// Render one frame of `width`×`height` pixels and read it back.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        meshes: &SceneMeshes,
        maps: &GpuMaps,
        shot: Shot,
        method: Method,
        [width, height]: [u32; 2],
    ) -> Result<EffectImage> {
        self.pipeline(gpu, Effect::of(shot.depths), method)?;
        let target = Target::new(gpu, width, height, FLOAT_TARGET, true)?;
        let buffer = readback_buffer(gpu, target.readback_bytes())?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        self.encode(gpu, meshes, maps, shot, method, &target, &mut encoder, None)?;
        target.copy_out(&mut encoder, &buffer, 0);
        gpu.queue.submit([encoder.finish()]);
        let pixels = target.decode(&gpu.read_buffer(&buffer)?);
        Ok(EffectImage {
            width,
            height,
            radiance: pixels.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect(),
            seen: pixels.chunks_exact(4).map(|p| (p[3] >= 1.0).then(|| p[3] as usize - 1)).collect(),
        })
    }
}

impl EffectImage {
    /// The frame in the CPU tracers' type (f64 radiance), to measure it with
    /// `effects::image_error`.
    pub fn traced(&self) -> nklut_effects::trace::TracedFrame {
        nklut_effects::trace::TracedFrame {
            width: self.width,
            height: self.height,
            radiance: self.radiance.iter().map(|p| p.map(f64::from)).collect(),
            seen: self.seen.clone(),
            rays: 0,
        }
    }
}

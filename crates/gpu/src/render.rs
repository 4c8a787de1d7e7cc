//! Pipelines composed from the shader library, per-material bindings, render targets and
//! readback. Pipelines and shader modules are created on first use and counted.

use std::collections::HashMap;

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::context::Gpu;
use super::params::MaterialUniform;
use super::passes::interface::{Binding, Interface, Pass, Resource};
use nklut_effects::scene::Shading;
use nklut_optics::fresnel::Method;

/// The Fresnel shader library (`shaders/fresnel.wgsl`), which every pass imports.
pub const LIBRARY: &str = super::compose::SHADERS[0].1;

/// Format of the ramp and image-error targets (read back as f32).
pub const FLOAT_TARGET: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Format of the timing target: what a display would get.
pub const DISPLAY_TARGET: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The depth test of every mesh pass: the nearest fragment wins ([`DEPTH`], cleared to 1).
pub fn depth_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH,
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// What `shade(c)` returns in a composed pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shade {
    Method(Shading),
    /// The expensive shader of the `--subtract` timing.
    Burner,
    /// `exact` by the dielectric formula (k = 0, `fresnel_exact_dielectric`): how the
    /// timing anchors exact on a dielectric material, as the study did.
    ExactDielectric,
}

impl Shade {
    /// The call of the library's pure function on the pipeline's bindings: the material's
    /// parameters, or its LUT texture and sampler.
    fn call(self) -> String {
        match self {
            Shade::Method(Shading::Fresnel(Method::Lut)) => "fresnel_lut(c, lut_texture, lut_sampler)".into(),
            Shade::Method(Shading::Texture) => "fresnel_texture(c, lut_texture, lut_sampler)".into(),
            Shade::Method(method) => format!("{}(c, material)", super::params::wgsl_function(method)),
            Shade::Burner => "fresnel_burner(c)".into(),
            Shade::ExactDielectric => "fresnel_exact_dielectric(c, material)".into(),
        }
    }

    pub fn name(self) -> String {
        match self {
            Shade::Method(method) => method.name().into(),
            Shade::Burner => "burner".into(),
            Shade::ExactDielectric => "exact_dielectric".into(),
        }
    }
}

/// The F-only pass (`shaders/fresnel_pass.wgsl` with the library it imports) plus the one
/// generated line that picks the method.
pub fn compose(shade: Shade) -> Result<String, super::compose::ComposeError> {
    super::compose::compose(&format!("#import fresnel_pass\nfn shade(c: f32) -> vec3<f32> {{ return {}; }}\n", shade.call()))
}

/// Which entry points and target a pipeline draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Draw {
    /// `vs_fullscreen` + `fs_ramp`: c = (x + ½)/width over the whole target, F evaluated
    /// `viewport.z` times per pixel ([`ViewUniform::fullscreen_amplified`]).
    Fullscreen(wgpu::TextureFormat),
    /// The same, blended additively over what is there: the measured draw of the
    /// `--subtract` timing. Without blending, a tiler that sees an opaque draw cover a whole
    /// tile drops the draws before it (lavapipe does, as do mobile GPUs' hidden-surface
    /// removal), and the expensive pass underneath would never run.
    FullscreenOver(wgpu::TextureFormat),
    /// `vs_mesh` + `fs_mesh` into `FLOAT_TARGET` with a `DEPTH` buffer.
    Mesh,
}

/// The uniform block `View` of the library.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct ViewUniform {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub viewport: [f32; 4],
}

impl ViewUniform {
    pub fn fullscreen(width: u32, height: u32) -> Self {
        ViewUniform { viewport: [width as f32, height as f32, 0.0, 0.0], ..Default::default() }
    }

    /// The fullscreen pass evaluating F `evaluations` times per pixel (`viewport.z`, read
    /// by `fs_ramp`; 0 and 1 both mean once).
    pub fn fullscreen_amplified(width: u32, height: u32, evaluations: u32) -> Self {
        ViewUniform { viewport: [width as f32, height as f32, evaluations as f32, 0.0], ..Default::default() }
    }

    pub fn camera(frame: &super::camera::Frame, width: u32, height: u32) -> Self {
        ViewUniform {
            view_proj: frame.view_proj.map(|column| column.map(|x| x as f32)),
            eye: [frame.eye[0] as f32, frame.eye[1] as f32, frame.eye[2] as f32, 1.0],
            viewport: [width as f32, height as f32, 0.0, 0.0],
        }
    }
}

/// One material's uniforms and texture, bound at group 0.
pub struct MaterialBinding {
    pub view: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

/// Counters of what was created.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Created {
    pub shader_modules: usize,
    pub pipelines: usize,
}

pub struct Renderer {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    sampler: wgpu::Sampler,
    /// 1×1 texture bound where a material has no LUT.
    blank: wgpu::TextureView,
    modules: HashMap<Shade, wgpu::ShaderModule>,
    pipelines: HashMap<(Shade, Draw), wgpu::RenderPipeline>,
    pub created: Created,
}

impl Pass for Renderer {
    const INTERFACE: Interface = Interface {
        name: "fresnel pass",
        shader: "fresnel_pass",
        entry_points: &["vs_fullscreen", "fs_ramp", "vs_mesh", "fs_mesh"],
        stages: wgpu::ShaderStages::VERTEX_FRAGMENT,
        bindings: &[
            Binding::new(0, 0, "material", Resource::Uniform),
            Binding::new(0, 1, "view", Resource::Uniform),
            Binding::new(0, 2, "lut_texture", Resource::Texture2d),
            Binding::new(0, 3, "lut_sampler", Resource::Sampler),
        ],
    };
}

impl Renderer {
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let (pipeline_layout, mut layouts) = Self::INTERFACE.pipeline_layout(device);
        let layout = layouts.remove(0);
        let sampler = super::lut::sampler(gpu);
        let blank = super::lut::upload(gpu, &[[1.0, 1.0, 1.0, 1.0]], "blank").create_view(&Default::default());
        Renderer {
            layout,
            pipeline_layout,
            sampler,
            blank,
            modules: HashMap::new(),
            pipelines: HashMap::new(),
            created: Created::default(),
        }
    }

    /// The pipeline for `shade` in `pass`, compiled on first use. Shader errors (a library
    /// that does not validate) are returned, not panicked.
    pub fn pipeline(&mut self, gpu: &Gpu, shade: Shade, pass: Draw) -> Result<&wgpu::RenderPipeline> {
        if !self.pipelines.contains_key(&(shade, pass)) {
            let source = compose(shade)?;
            let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            if let std::collections::hash_map::Entry::Vacant(entry) = self.modules.entry(shade) {
                entry.insert(gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&format!("fresnel pass + {}", shade.name())),
                    source: wgpu::ShaderSource::Wgsl(source.into()),
                }));
                self.created.shader_modules += 1;
            }
            let pipeline = self.create_pipeline(gpu, shade, pass);
            if let Some(error) = pollster::block_on(scope.pop()) {
                self.modules.remove(&shade);
                bail!("compiling the {} pipeline: {error}", shade.name());
            }
            self.pipelines.insert((shade, pass), pipeline);
            self.created.pipelines += 1;
        }
        Ok(&self.pipelines[&(shade, pass)])
    }

    fn create_pipeline(&self, gpu: &Gpu, shade: Shade, pass: Draw) -> wgpu::RenderPipeline {
        let module = &self.modules[&shade];
        let mesh_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let mesh_buffers =
            [Some(wgpu::VertexBufferLayout { array_stride: 24, step_mode: wgpu::VertexStepMode::Vertex, attributes: &mesh_attributes })];
        let additive = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let mut blend = None;
        let (vertex_entry, fragment_entry, format, buffers, depth_stencil): (_, _, _, &[_], _) = match pass {
            Draw::Fullscreen(format) => ("vs_fullscreen", "fs_ramp", format, &[], None),
            Draw::FullscreenOver(format) => {
                blend = Some(wgpu::BlendState { color: additive, alpha: additive });
                ("vs_fullscreen", "fs_ramp", format, &[], None)
            }
            Draw::Mesh => ("vs_mesh", "fs_mesh", FLOAT_TARGET, &mesh_buffers, Some(depth_test())),
        };
        gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&format!("{} {:?}", shade.name(), pass)),
            layout: Some(&self.pipeline_layout),
            vertex: wgpu::VertexState { module, entry_point: Some(vertex_entry), compilation_options: Default::default(), buffers },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some(fragment_entry),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState { format, blend, write_mask: wgpu::ColorWrites::ALL })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// Bind a material: its uniform block and its LUT (or the blank texture).
    pub fn bind(&self, gpu: &Gpu, material: &MaterialUniform, lut: Option<&wgpu::TextureView>) -> Result<MaterialBinding> {
        let device = &gpu.device;
        let material_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("material"),
            contents: bytemuck::bytes_of(material),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let view = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("view"),
            contents: bytemuck::bytes_of(&ViewUniform::default()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = Self::INTERFACE.bind_group(
            device,
            &self.layout,
            0,
            &[
                (0, material_buffer.as_entire_binding()),
                (1, view.as_entire_binding()),
                (2, wgpu::BindingResource::TextureView(lut.unwrap_or(&self.blank))),
                (3, wgpu::BindingResource::Sampler(&self.sampler)),
            ],
        )?;
        Ok(MaterialBinding { view, bind_group })
    }
}

/// A colour target (and, for meshes, a depth buffer) with a readback buffer.
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub colour: wgpu::Texture,
    pub colour_view: wgpu::TextureView,
    pub depth_view: Option<wgpu::TextureView>,
}

/// Bytes per row of a readback copy: width·16 rounded up to 256 (wgpu's copy alignment).
pub fn padded_row_bytes(width: u32, bytes_per_pixel: u32) -> u32 {
    let unpadded = width * bytes_per_pixel;
    unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT
}

/// A `width`×`height` 2D texture must fit the device's `max_texture_dimension_2d`; checked
/// before anything is allocated, so an oversized scene is an error and not a device panic.
pub fn check_texture_size(gpu: &Gpu, width: u32, height: u32) -> Result<()> {
    let limit = gpu.device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > limit || height > limit {
        bail!("a {width}x{height} render target exceeds this device's max_texture_dimension_2d ({limit}); lower the resolution");
    }
    Ok(())
}

/// A buffer of `size` bytes must fit the device's `max_buffer_size`.
/// `size` bytes for `what` fit one buffer of this device; else an error naming the limit
/// and `remedy`, what the scene can change to need less.
pub fn check_buffer_size(gpu: &Gpu, size: u64, what: &str, remedy: &str) -> Result<()> {
    let limit = gpu.device.limits().max_buffer_size;
    if size > limit {
        bail!("the {what} needs a {size}-byte buffer, over this device's max_buffer_size ({limit}); {remedy}");
    }
    Ok(())
}

impl Target {
    pub fn new(gpu: &Gpu, width: u32, height: u32, format: wgpu::TextureFormat, depth: bool) -> Result<Self> {
        check_texture_size(gpu, width, height)?;
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = |format, usage, label| texture_2d(gpu, label, size, format, usage);
        let colour = texture(format, wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC, "colour");
        let colour_view = colour.create_view(&Default::default());
        let depth_view = depth.then(|| texture(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT, "depth").create_view(&Default::default()));
        Ok(Target { width, height, colour, colour_view, depth_view })
    }

    /// Size of one RGBA32Float readback of this target.
    pub fn readback_bytes(&self) -> u64 {
        padded_row_bytes(self.width, 16) as u64 * self.height as u64
    }

    /// Begin a pass that clears colour to (0, 0, 0, 0) and depth to 1.
    pub fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    ) -> wgpu::RenderPass<'e> {
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("nklut pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.colour_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: self.depth_view.as_ref().map(|view| wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }

    /// Copy the colour target (RGBA32Float) into `buffer` at `offset`.
    pub fn copy_out(&self, encoder: &mut wgpu::CommandEncoder, buffer: &wgpu::Buffer, offset: u64) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.colour,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset,
                    bytes_per_row: Some(padded_row_bytes(self.width, 16)),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d { width: self.width, height: self.height, depth_or_array_layers: 1 },
        );
    }

    /// RGBA f32 pixels, row-major, from the bytes `copy_out` wrote.
    pub fn decode(&self, bytes: &[u8]) -> Vec<f32> {
        let row = padded_row_bytes(self.width, 16) as usize;
        let used = self.width as usize * 16;
        let mut pixels = Vec::with_capacity(self.width as usize * self.height as usize * 4);
        for y in 0..self.height as usize {
            pixels.extend(bytemuck::pod_collect_to_vec::<u8, f32>(&bytes[y * row..y * row + used]));
        }
        pixels
    }
}

/// A 2D texture (an array of `size.depth_or_array_layers` layers), one mip level.
pub fn texture_2d(gpu: &Gpu, label: &str, size: wgpu::Extent3d, format: wgpu::TextureFormat, usage: wgpu::TextureUsages) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A buffer the CPU can read back, `size` bytes.
pub fn readback_buffer(gpu: &Gpu, size: u64) -> Result<wgpu::Buffer> {
    check_buffer_size(gpu, size, "readback", "lower the resolution or name fewer methods per object")?;
    Ok(gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    }))
}

/// Render the cosθ ramp of `method` (c = (x + ½)/width in every row) for `material` into
/// an RGBA32Float target and read it back: the shader's F as the tests compare it.
pub fn ramp(gpu: &Gpu, renderer: &mut Renderer, method: Shading, binding: &MaterialBinding, width: u32, height: u32) -> Result<Vec<f32>> {
    ramp_of(gpu, renderer, Shade::Method(method), binding, [width, height], 1)
}

/// [`ramp`] of any `shade` with F evaluated `evaluations` times per pixel (the timing's
/// amplified pass: each pixel the mean of F at c, c + φ, c + 2φ … mod 1).
pub fn ramp_of(
    gpu: &Gpu,
    renderer: &mut Renderer,
    shade: Shade,
    binding: &MaterialBinding,
    [width, height]: [u32; 2],
    evaluations: u32,
) -> Result<Vec<f32>> {
    let target = Target::new(gpu, width, height, FLOAT_TARGET, false)?;
    gpu.queue.write_buffer(&binding.view, 0, bytemuck::bytes_of(&ViewUniform::fullscreen_amplified(width, height, evaluations)));
    let pipeline = renderer.pipeline(gpu, shade, Draw::Fullscreen(FLOAT_TARGET))?.clone();
    let buffer = readback_buffer(gpu, target.readback_bytes())?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = target.begin(&mut encoder, None);
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &binding.bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    target.copy_out(&mut encoder, &buffer, 0);
    gpu.queue.submit([encoder.finish()]);
    Ok(target.decode(&gpu.read_buffer(&buffer)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The body of library function `name`, from its `fn` to the closing brace at column 0.
    fn body<'a>(library: &'a str, name: &str) -> &'a str {
        let start = library.find(&format!("fn {name}(")).unwrap_or_else(|| panic!("no fn {name}"));
        let end = start + library[start..].find("\n}\n").expect("a closing brace");
        &library[start..end]
    }

    #[test]
    fn library_has_one_pure_function_per_method_and_pipelines_add_one_line() {
        // shaders/fresnel.wgsl with the methods' functions it imports.
        let library = format!("{LIBRARY}{}", crate::params::wgsl_library());
        for method in Shading::ALL {
            let name = crate::params::wgsl_function(method);
            assert_eq!(library.matches(&format!("fn {name}(")).count(), 1, "{name}");
            // Pure: its parameters come in as arguments, never from the bindings.
            let text = body(&library, name);
            for global in ["material", "view", "lut_texture", "lut_sampler"] {
                assert!(
                    !text.split(|ch: char| !ch.is_alphanumeric() && ch != '_').any(|word| word == global),
                    "{name} reads the global {global}"
                );
            }
            let composed = compose(Shade::Method(method)).unwrap();
            // The library whole, its `#import` lines replaced by the modules.
            let mut parts = LIBRARY.split("#import contracts\n").flat_map(|part| part.split("#import fresnel_methods\n"));
            assert!(parts.all(|part| composed.contains(part)));
            assert!(composed.contains(&crate::params::wgsl_library()));
            let line = composed.trim_end().lines().last().unwrap_or_default().to_string();
            assert!(line.starts_with("fn shade(c: f32) -> vec3<f32> { return fresnel_") && line.ends_with("; }"), "{line}");
        }
        assert!(!LIBRARY.contains("\nfn shade("), "the library leaves shade() to the composition");
    }

    #[test]
    fn readback_rows_are_256_byte_aligned() {
        assert_eq!(padded_row_bytes(1024, 16), 16384);
        assert_eq!(padded_row_bytes(100, 16), 1792);
        assert_eq!(padded_row_bytes(1, 16), 256);
    }
}

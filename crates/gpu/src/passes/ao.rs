//! The surfel ambient-occlusion pass (`shaders/surfel_ao.wgsl`): accessibility and bent
//! normals of every surfel after N passes, by brute force over all emitters or through the
//! surfel tree (Bunnell, GPU Gems 2 ch. 14; the f64 CPU twin is `effects::ao::accessibility`
//! and `effects::ao::hierarchy`, docs/ao.md).
//!
//! Inputs: the surfels, optionally their tree (nodes, leaf order), the shadow form's gain g
//! and the tree's κ, the pass count. Outputs: per surfel the accessibility of the last pass
//! and its unit bent normal ([`AoOutput`]), and the count of dispatches. Everything is
//! recorded in one compute pass: per accessibility pass, the tree's node weights (the
//! leaves' area-weighted mean accessibility of the previous pass), then the gather; two
//! accessibility buffers take turns as previous and next. Sizes are checked against the
//! device's limits before any allocation; wgpu errors come back as `Result`s.

use anyhow::{bail, Result};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::interface::{Binding, Interface, Pass, Resource};
use crate::compose::compute_pipelines;
use crate::context::Gpu;
use crate::render::{check_buffer_size, readback_buffer};
use nklut_effects::ao::hierarchy::{Closeness, SurfelTree};
use nklut_effects::ao::shadow::ShadowForm;
use nklut_effects::ao::surfel::Surfel;

/// Invocations per workgroup of every entry point.
const WORKGROUP: u32 = 64;
/// The traversal stack of `cs_tree`: a tree deeper than this cannot be walked.
pub use crate::contracts::SURFEL_STACK as STACK_DEPTH;
const NO_CHILD: u32 = u32::MAX;

/// The shader's uniform `Params` (shared by the accessibility and indirect passes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct Params {
    pub(crate) count: u32,
    pub(crate) nodes: u32,
    pub(crate) gain: f32,
    pub(crate) closeness: f32,
    pub(crate) previous: u32,
    pub(crate) next: u32,
    pub(crate) weights: u32,
    pub(crate) pad: u32,
}

/// A disc as the shader reads it: centre and area, unit normal.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuDisc {
    pub centre_area: [f32; 4],
    pub normal: [f32; 4],
}

impl GpuDisc {
    pub fn new(s: &Surfel) -> GpuDisc {
        let (c, n) = (s.centre.as_vec3(), s.normal.as_vec3());
        GpuDisc { centre_area: [c.x, c.y, c.z, s.area as f32], normal: [n.x, n.y, n.z, 0.0] }
    }
}

/// Per index k: node k's [left, right, first, end) and (order[k], rank[k], 0, 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuLinks {
    node: [u32; 4],
    leaf: [u32; 4],
}

/// Which emitters a receiver gathers from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gather {
    BruteForce,
    Hierarchy,
}

/// Per surfel after the last pass: accessibility and unit bent normal.
#[derive(Clone, Debug, PartialEq)]
pub struct AoOutput {
    pub accessibility: Vec<f32>,
    pub bent_normals: Vec<[f32; 3]>,
    /// Compute dispatches recorded (node weights and gathers).
    pub dispatches: u64,
}

/// The pass with its buffers and pipelines, ready to dispatch any number of passes.
pub struct SurfelAoPass {
    count: u32,
    nodes: u32,
    gather: Gather,
    brute_force: wgpu::ComputePipeline,
    node_weights: wgpu::ComputePipeline,
    tree: wgpu::ComputePipeline,
    /// Bind groups whose parameters read the previous pass from the first accessibility
    /// buffer and write the second, and the other way round.
    bind_groups: [wgpu::BindGroup; 2],
    /// Two accessibility buffers of `count` values, then the nodes' weights.
    state: wgpu::Buffer,
    bent: wgpu::Buffer,
}

fn depth(nodes: &[nklut_effects::ao::hierarchy::Node]) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 1usize)];
    while let Some((k, d)) = stack.pop() {
        deepest = deepest.max(d);
        if let Some([l, r]) = nodes.get(k).and_then(|n| n.children) {
            stack.push((l as usize, d + 1));
            stack.push((r as usize, d + 1));
        }
    }
    if nodes.is_empty() {
        0
    } else {
        deepest
    }
}

/// The storage buffer sizes and workgroup count of `count` receivers against the device.
fn check_limits(gpu: &Gpu, count: usize, nodes: usize) -> Result<()> {
    let limits = gpu.device.limits();
    let groups = count.div_ceil(WORKGROUP as usize).max(nodes.div_ceil(WORKGROUP as usize));
    if groups > limits.max_compute_workgroups_per_dimension as usize {
        bail!(
            "{count} surfels need {groups} workgroups of {WORKGROUP}, over this device's max_compute_workgroups_per_dimension ({})",
            limits.max_compute_workgroups_per_dimension
        );
    }
    let sizes = [
        ("surfel and node discs", (count + nodes) * std::mem::size_of::<GpuDisc>()),
        ("surfel tree links", count.max(nodes) * std::mem::size_of::<GpuLinks>()),
        ("accessibility and node weights", (2 * count + nodes.max(1)) * 4),
        ("bent normals", count * 16),
    ];
    for (what, bytes) in sizes {
        if bytes as u64 > limits.max_storage_buffer_binding_size {
            bail!(
                "the {what} need a {bytes}-byte storage buffer, over this device's max_storage_buffer_binding_size ({})",
                limits.max_storage_buffer_binding_size
            );
        }
        check_buffer_size(gpu, bytes as u64, what, "use fewer surfels (coarser meshes, less subdivide)")?;
    }
    if limits.max_storage_buffers_per_shader_stage < 4 {
        bail!("the surfel pass binds 4 storage buffers; this device allows {}", limits.max_storage_buffers_per_shader_stage);
    }
    Ok(())
}

impl Pass for SurfelAoPass {
    const INTERFACE: Interface = Interface {
        name: "surfel ao",
        shader: "surfel_ao",
        entry_points: &["cs_brute_force", "cs_node_weights", "cs_tree", "cs_shadow_terms"],
        stages: wgpu::ShaderStages::COMPUTE,
        bindings: &[
            Binding::new(0, 0, "params", Resource::Uniform),
            Binding::new(0, 1, "discs", Resource::Read),
            Binding::new(0, 2, "links", Resource::Read),
            Binding::new(0, 3, "state", Resource::ReadWrite),
            Binding::new(0, 4, "bent", Resource::ReadWrite),
        ],
    };
}

/// What the surfel pass uploads, from `surfels` and (for the hierarchy) their `tree`: the
/// discs (surfels, then the tree's nodes), the links, and the two parameter blocks (the
/// first reads the previous pass from the first accessibility buffer and writes the
/// second, the other the other way round). The native pass and the browser bench upload
/// these same bytes.
pub struct SurfelUpload {
    pub discs: Vec<GpuDisc>,
    pub(crate) links: Vec<GpuLinks>,
    pub(crate) params: [Params; 2],
}

impl SurfelUpload {
    pub fn of(surfels: &[Surfel], tree: Option<&SurfelTree>, form: ShadowForm, closeness: Closeness) -> SurfelUpload {
        let n = surfels.len();
        let node_count = tree.map_or(0, |t| t.nodes.len());
        let mut discs: Vec<GpuDisc> = surfels.iter().map(GpuDisc::new).collect();
        let mut links = vec![GpuLinks::default(); n.max(node_count)];
        if let Some(tree) = tree {
            discs.extend(tree.nodes.iter().map(|node| GpuDisc::new(&node.disc)));
            for (k, node) in tree.nodes.iter().enumerate() {
                let [l, r] = node.children.unwrap_or([NO_CHILD, NO_CHILD]);
                links[k].node = [l, r, node.first, node.end];
            }
            for (position, &s) in tree.order.iter().enumerate() {
                links[position].leaf[0] = s;
                links[s as usize].leaf[1] = position as u32;
            }
        }
        let n32 = n as u32;
        let params = |previous: u32, next: u32| Params {
            count: n32,
            nodes: node_count as u32,
            gain: form.receiver_gain as f32,
            closeness: closeness.0 as f32,
            previous,
            next,
            weights: 2 * n32,
            pad: 0,
        };
        SurfelUpload { discs, links, params: [params(0, n32), params(n32, 0)] }
    }

    /// The bytes of the discs, the links and the two parameter blocks.
    pub fn bytes(&self) -> [Vec<u8>; 4] {
        [
            bytemuck::cast_slice(&self.discs).to_vec(),
            bytemuck::cast_slice(&self.links).to_vec(),
            bytemuck::bytes_of(&self.params[0]).to_vec(),
            bytemuck::bytes_of(&self.params[1]).to_vec(),
        ]
    }

    /// Bytes of the accessibility state (two buffers of one value per surfel, then the
    /// nodes' weights) and of the bent normals.
    pub fn state_bytes(&self) -> [u64; 2] {
        let n = self.params[0].count as u64;
        [(2 * n + (self.params[0].nodes as u64).max(1)) * 4, n * 16]
    }
}

impl SurfelAoPass {
    /// Upload `surfels` (and `tree`, for [`Gather::Hierarchy`]) and compile the kernel.
    pub fn new(
        gpu: &Gpu,
        surfels: &[Surfel],
        tree: Option<&SurfelTree>,
        gather: Gather,
        form: ShadowForm,
        closeness: Closeness,
    ) -> Result<SurfelAoPass> {
        if surfels.is_empty() {
            bail!("the surfel pass needs at least one surfel");
        }
        let tree = match (gather, tree) {
            (Gather::Hierarchy, None) => bail!("the hierarchy needs the surfel tree"),
            (Gather::Hierarchy, Some(tree)) => Some(tree),
            (Gather::BruteForce, _) => None,
        };
        let node_count = tree.map_or(0, |t| t.nodes.len());
        if let Some(tree) = tree {
            let deepest = depth(&tree.nodes);
            if deepest + 1 > STACK_DEPTH {
                bail!("the surfel tree is {deepest} levels deep; the traversal's stack holds {STACK_DEPTH}");
            }
            if tree.order.len() != surfels.len() {
                bail!("the surfel tree holds {} leaves for {} surfels", tree.order.len(), surfels.len());
            }
        }
        check_limits(gpu, surfels.len(), node_count)?;
        let device = &gpu.device;
        let n = surfels.len();
        let n32 = n as u32;
        let SurfelUpload { discs, links, params } = SurfelUpload::of(surfels, tree, form, closeness);
        let interface = Self::INTERFACE;
        let (pipeline_layout, layouts) = interface.pipeline_layout(device);
        let [brute_force, node_weights, tree_pipeline] = compute_pipelines(
            device,
            interface.shader,
            Some(&pipeline_layout),
            ["cs_brute_force", "cs_node_weights", "cs_tree"],
            "the surfel ambient-occlusion kernel",
        )?;

        let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let init = |label: &str, contents: &[u8], usage: wgpu::BufferUsages| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let writable = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let uniforms = params.map(|p| init("surfel ao params", bytemuck::bytes_of(&p), wgpu::BufferUsages::UNIFORM));
        let disc_buffer = init("surfel and node discs", bytemuck::cast_slice(&discs), wgpu::BufferUsages::STORAGE);
        let link_buffer = init("surfel tree links", bytemuck::cast_slice(&links), wgpu::BufferUsages::STORAGE);
        let state = init("accessibility and node weights", bytemuck::cast_slice(&vec![1.0f32; 2 * n + node_count.max(1)]), writable);
        let bent = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bent normals"),
            size: (n * 16) as u64,
            usage: writable,
            mapped_at_creation: false,
        });
        let bind_group = |uniform: &wgpu::Buffer| {
            let buffers = [uniform, &disc_buffer, &link_buffer, &state, &bent];
            let resources: Vec<(u32, wgpu::BindingResource)> =
                buffers.iter().enumerate().map(|(binding, b)| (binding as u32, b.as_entire_binding())).collect();
            interface.bind_group(device, &layouts[0], 0, &resources)
        };
        let bind_groups = [bind_group(&uniforms[0])?, bind_group(&uniforms[1])?];
        if let Some(error) = pollster::block_on(scope.pop()) {
            bail!("allocating the surfel pass's buffers: {error}");
        }
        gpu.take_errors()?;
        Ok(SurfelAoPass {
            count: n32,
            nodes: node_count as u32,
            gather,
            brute_force,
            node_weights,
            tree: tree_pipeline,
            bind_groups,
            state,
            bent,
        })
    }

    /// The byte offset in `state` of the accessibility after `passes` passes.
    fn result_offset(&self, passes: u32) -> u64 {
        (passes % 2) as u64 * self.count as u64 * 4
    }

    /// Record `passes` passes (from full accessibility) into `encoder`, in one compute pass
    /// with `timestamps` written at its start and end; the dispatches recorded.
    pub fn encode(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        passes: u32,
        timestamps: Option<wgpu::ComputePassTimestampWrites>,
    ) -> u64 {
        let ones = vec![1.0f32; self.count as usize];
        encoder.clear_buffer(&self.bent, 0, None);
        gpu.queue.write_buffer(&self.state, 0, bytemuck::cast_slice(&ones));
        let groups = self.count.div_ceil(WORKGROUP);
        let mut dispatches = 0;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("surfel ao"), timestamp_writes: timestamps });
        for k in 0..passes {
            pass.set_bind_group(0, &self.bind_groups[(k % 2) as usize], &[]);
            match self.gather {
                Gather::BruteForce => {
                    pass.set_pipeline(&self.brute_force);
                    pass.dispatch_workgroups(groups, 1, 1);
                    dispatches += 1;
                }
                Gather::Hierarchy => {
                    pass.set_pipeline(&self.node_weights);
                    pass.dispatch_workgroups(self.nodes.div_ceil(WORKGROUP), 1, 1);
                    pass.set_pipeline(&self.tree);
                    pass.dispatch_workgroups(groups, 1, 1);
                    dispatches += 2;
                }
            }
        }
        dispatches
    }

    /// Run `passes` passes and read back the accessibility and bent normals (0 passes: all
    /// accessible, the bent normals zero — the CPU twin's pass 0 is the normals).
    pub fn run(&self, gpu: &Gpu, passes: u32) -> Result<AoOutput> {
        let bytes = self.count as u64 * 16;
        let readback = readback_buffer(gpu, bytes + self.count as u64 * 4)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let dispatches = self.encode(gpu, &mut encoder, passes, None);
        encoder.copy_buffer_to_buffer(&self.bent, 0, &readback, 0, bytes);
        encoder.copy_buffer_to_buffer(&self.state, self.result_offset(passes), &readback, bytes, self.count as u64 * 4);
        gpu.queue.submit([encoder.finish()]);
        let data = gpu.read_buffer(&readback)?;
        let (bent, accessibility) = data.split_at(bytes as usize);
        let bent: &[[f32; 4]] = bytemuck::cast_slice(bent);
        Ok(AoOutput {
            accessibility: bytemuck::cast_slice(accessibility).to_vec(),
            bent_normals: bent.iter().map(|b| [b[1], b[2], b[3]]).collect(),
            dispatches,
        })
    }
}

/// The shadow term alone on the GPU for (emitter, receiver) pairs: (S, v) per pair, to
/// hold `shadow_term` to its CPU twin.
pub fn shadow_terms(gpu: &Gpu, pairs: &[(Surfel, Surfel)], form: ShadowForm) -> Result<Vec<[f32; 4]>> {
    let surfels: Vec<Surfel> = pairs.iter().flat_map(|(e, r)| [*e, *r]).collect();
    let pass = SurfelAoPass::new(gpu, &surfels, None, Gather::BruteForce, form, Closeness::default())?;
    let layout = pass.brute_force.get_bind_group_layout(0);
    let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow terms"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let shader = SurfelAoPass::INTERFACE.shader;
    let [pipeline] = compute_pipelines(&gpu.device, shader, Some(&pipeline_layout), ["cs_shadow_terms"], "the shadow-term kernel")?;
    let bytes = pairs.len() as u64 * 16;
    let readback = readback_buffer(gpu, bytes.max(16))?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut compute = encoder.begin_compute_pass(&Default::default());
        compute.set_pipeline(&pipeline);
        compute.set_bind_group(0, &pass.bind_groups[0], &[]);
        compute.dispatch_workgroups((pairs.len() as u32).div_ceil(WORKGROUP), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&pass.bent, 0, &readback, 0, bytes);
    gpu.queue.submit([encoder.finish()]);
    let data = gpu.read_buffer(&readback)?;
    Ok(bytemuck::cast_slice::<u8, [f32; 4]>(&data)[..pairs.len()].to_vec())
}

/// What a scene's surfel effects gave on the GPU: accessibility and bent normals after the
/// scene's passes, the indirect light where it asks for it, and the largest difference of
/// the accessibility from the f64 CPU twin (the same emitters and passes); GTAO's frame
/// where the scene names it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSurfels {
    pub accessibility: AoOutput,
    pub indirect: Option<super::indirect::IndirectOutput>,
    pub twin_difference: f64,
    pub gtao: Option<SceneGtao>,
}

/// GTAO on the GPU over the scene's first frame (its `resolution`), the scene's first GTAO
/// configuration: per pixel accessibility and the largest difference from the f32 CPU twin
/// over the covered pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneGtao {
    pub accessibility: Vec<Option<f32>>,
    pub twin_difference: f64,
}

/// Run the surfel effects a scene names on the GPU (ambient occlusion with its passes,
/// hierarchy on or off; indirect light with its bounces, emitters weighted as
/// `EmitterWeight::default()`: 1), counting surfels, tree nodes, passes and bounces into `stats`. A scene
/// that names neither computes nothing and returns `None`.
pub fn run_scene(
    scene: &nklut_effects::scene::Scene,
    gpu: &Gpu,
    stats: &mut nklut_effects::experiment::EffectsStats,
    log: &mut dyn FnMut(&str),
) -> Result<Option<SceneSurfels>> {
    use nklut_effects::ao::accessibility::{accessibility, BruteForce};
    use nklut_effects::ao::experiment::{AoSettings, SurfelScene};
    use nklut_effects::ao::indirect::surfel_direct;
    let Some(effects) = &scene.effects else { return Ok(None) };
    if !effects.names(nklut_effects::scene::EffectFamily::Surfels) {
        return Ok(None);
    }
    let settings = AoSettings::default();
    let stage = SurfelScene::new(scene, &settings.budget)?;
    let n = stage.surfels.len();
    stats.surfels += n;
    let passes = effects.ambient_occlusion.as_ref().map_or(0, |a| a.passes);
    let hierarchy = effects.ambient_occlusion.as_ref().is_some_and(|a| a.hierarchy);
    let tree = hierarchy.then(|| SurfelTree::new(&stage.surfels, settings.form, settings.closeness));
    stats.tree_nodes += tree.as_ref().map_or(0, |t| t.nodes.len());
    let gather = if hierarchy { Gather::Hierarchy } else { Gather::BruteForce };
    let pass = SurfelAoPass::new(gpu, &stage.surfels, tree.as_ref(), gather, settings.form, settings.closeness)?;
    let output = pass.run(gpu, passes)?;
    stats.ao_passes += passes as u64;
    let brute = BruteForce { surfels: &stage.surfels, form: settings.form };
    let twin = match &tree {
        Some(tree) => accessibility(tree, passes),
        None => accessibility(&brute, passes),
    };
    let twin_difference = output.accessibility.iter().zip(&twin.values).map(|(g, c)| (*g as f64 - c).abs()).fold(0.0, f64::max);
    log(&format!(
        "surfels on the GPU: {n} surfels, {passes} passes {}, {} dispatches; max |GPU − CPU twin| {twin_difference:.2e}",
        if hierarchy { "through the tree" } else { "by brute force" },
        output.dispatches
    ));
    let indirect = match effects.indirect {
        Some(indirect) => {
            let direct = surfel_direct(&stage.geometry, &stage.surfels, &stage.lights, settings.rays.offset);
            let accessibility: Vec<f64> = output.accessibility.iter().map(|&a| a as f64).collect();
            let weights = nklut_effects::ao::indirect::EmitterWeight::default().weights(&accessibility);
            let light = super::indirect::IndirectPass::new(gpu, &stage.surfels, settings.form)?.run(
                gpu,
                &stage.albedo,
                &direct,
                &weights,
                indirect.bounces,
            )?;
            stats.indirect_bounces += indirect.bounces as u64;
            log(&format!("indirect light on the GPU: {} bounces", indirect.bounces));
            Some(light)
        }
        None => None,
    };
    // The scene's first configuration (the one pictured), every heuristic and frame of it.
    let gtao = match effects.ambient_occlusion.as_ref().and_then(|a| a.gtao.first().copied()) {
        Some(g) => {
            use nklut_effects::ao::gtao::{gtao, GBuffer, Parameters};
            let [width, height] = scene.resolution;
            let camera = nklut_effects::trace::Camera::new(&scene.camera, 0, width, height);
            let gbuffer = GBuffer::from_coverage(&camera, &stage.coverage(&camera), &stage.surfels).narrowed();
            let parameters = Parameters::of(g).narrowed();
            let accessibility = super::gtao::GtaoPass::new(gpu, &gbuffer, parameters)?.run(gpu)?;
            let twin = gtao(&gbuffer, parameters);
            let twin_difference =
                accessibility.iter().zip(&twin).filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs() as f64)).fold(0.0, f64::max);
            log(&format!("gtao on the GPU: {width}×{height}, {}; max |GPU − CPU twin| {twin_difference:.2e}", g.label()));
            Some(SceneGtao { accessibility, twin_difference })
        }
        None => None,
    };
    Ok(Some(SceneSurfels { accessibility: output, indirect, twin_difference, gtao }))
}

/// This module's structs shared with `shaders/surfel_ao.wgsl` (`crate::layout`).
pub fn shared_structs() -> Vec<crate::layout::SharedStruct> {
    use crate::layout::shared_struct;
    vec![
        shared_struct!(Params as "Params" { count, nodes, gain, closeness, previous, next, weights, pad }),
        shared_struct!(GpuLinks as "Links" { node, leaf }),
    ]
}

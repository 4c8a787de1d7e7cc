//! What a GPU pass declares: its shader, its entry points and every resource it binds
//! (group, binding, the WGSL variable's name, what kind of resource, who reads it). The
//! declaration is the one source of the pass's bind group layouts ([`Interface::layout`])
//! and of the checks on what a caller binds ([`Interface::bind_group`]); the tests reflect
//! each pass's composed WGSL with naga ([`Interface::check`]), so a binding added, renamed
//! or retyped on one side only fails a test instead of a device validation at run time.

use anyhow::{bail, Result};

/// What a binding holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resource {
    /// A uniform buffer.
    Uniform,
    /// A storage buffer the pass reads (`var<storage, read>`).
    Read,
    /// A storage buffer the pass writes (`var<storage, read_write>`).
    ReadWrite,
    /// A 2D float texture sampled with filtering (`texture_2d<f32>`).
    Texture2d,
    /// A 2D float texture array read texel by texel (`texture_2d_array<f32>`, unfilterable:
    /// the distance maps' 32-bit float layers).
    TextureArray,
    /// A filtering sampler.
    Sampler,
}

/// One declared binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    pub group: u32,
    pub binding: u32,
    /// The WGSL variable.
    pub name: &'static str,
    pub resource: Resource,
}

impl Binding {
    pub const fn new(group: u32, binding: u32, name: &'static str, resource: Resource) -> Binding {
        Binding { group, binding, name, resource }
    }
}

/// A pass's declaration.
#[derive(Clone, Copy, Debug)]
pub struct Interface {
    /// The pass, in labels and errors.
    pub name: &'static str,
    /// The shader module of `shaders/` it composes (`#import <shader>`).
    pub shader: &'static str,
    /// The entry points it runs.
    pub entry_points: &'static [&'static str],
    /// Compute, or vertex and fragment.
    pub stages: wgpu::ShaderStages,
    pub bindings: &'static [Binding],
}

/// A GPU pass: a unit with a declared interface.
pub trait Pass {
    const INTERFACE: Interface;
}

impl Interface {
    /// The groups the pass binds, ascending.
    pub fn groups(&self) -> Vec<u32> {
        let mut groups: Vec<u32> = self.bindings.iter().map(|b| b.group).collect();
        groups.sort_unstable();
        groups.dedup();
        groups
    }

    /// The layout entries of `group`.
    pub fn layout_entries(&self, group: u32) -> Vec<wgpu::BindGroupLayoutEntry> {
        self.bindings
            .iter()
            .filter(|b| b.group == group)
            .map(|b| wgpu::BindGroupLayoutEntry { binding: b.binding, visibility: self.stages, ty: binding_type(b.resource), count: None })
            .collect()
    }

    /// The bind group layout of `group`.
    pub fn layout(&self, device: &wgpu::Device, group: u32) -> wgpu::BindGroupLayout {
        device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(self.name), entries: &self.layout_entries(group) })
    }

    /// The pipeline layout of every group, with the group layouts it holds (in group order).
    pub fn pipeline_layout(&self, device: &wgpu::Device) -> (wgpu::PipelineLayout, Vec<wgpu::BindGroupLayout>) {
        let layouts: Vec<wgpu::BindGroupLayout> = self.groups().into_iter().map(|g| self.layout(device, g)).collect();
        let refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let pipeline = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(self.name),
            bind_group_layouts: &refs,
            immediate_size: 0,
        });
        (pipeline, layouts)
    }

    /// A bind group of `group` from `resources` by binding number: each declared binding of
    /// the group given once, nothing else (an error naming the pass and binding otherwise).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        group: u32,
        resources: &[(u32, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup> {
        let mut declared: Vec<u32> = self.bindings.iter().filter(|b| b.group == group).map(|b| b.binding).collect();
        declared.sort_unstable();
        let mut given: Vec<u32> = resources.iter().map(|(b, _)| *b).collect();
        given.sort_unstable();
        if given != declared {
            bail!("{}: group {group} declares bindings {declared:?}, given {given:?}", self.name);
        }
        let entries: Vec<wgpu::BindGroupEntry> =
            resources.iter().map(|(binding, resource)| wgpu::BindGroupEntry { binding: *binding, resource: resource.clone() }).collect();
        Ok(device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(self.name), layout, entries: &entries }))
    }

    /// Hold the declaration to a WGSL module: every declared binding is a global of the
    /// module at that group and binding, with that name and kind, and every global the
    /// pass's entry points use is declared. Returns each disagreement.
    pub fn check(&self, source: &str) -> Result<(), Vec<String>> {
        let module = naga::front::wgsl::parse_str(source).map_err(|e| vec![format!("{}: {}", self.name, e.emit_to_string(source))])?;
        let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .map_err(|e| vec![format!("{}: {}", self.name, e.emit_to_string(source))])?;
        let mut problems = Vec::new();
        let globals: Vec<(naga::Handle<naga::GlobalVariable>, &naga::GlobalVariable)> = module.global_variables.iter().collect();
        for b in self.bindings {
            let found = globals.iter().find(|(_, g)| g.binding.as_ref().is_some_and(|r| r.group == b.group && r.binding == b.binding));
            let Some((_, global)) = found else {
                problems.push(format!("{}: @group({}) @binding({}) {} is not in the shader", self.name, b.group, b.binding, b.name));
                continue;
            };
            if global.name.as_deref() != Some(b.name) {
                problems
                    .push(format!("{}: @group({}) @binding({}) is {:?}, declared {}", self.name, b.group, b.binding, global.name, b.name));
            }
            let kind = resource_of(&module, global);
            if kind != Some(b.resource) {
                problems.push(format!("{}: {} is {kind:?} in the shader, declared {:?}", self.name, b.name, b.resource));
            }
        }
        for entry in self.entry_points {
            let Some(index) = module.entry_points.iter().position(|e| e.name == *entry) else {
                problems.push(format!("{}: no entry point {entry}", self.name));
                continue;
            };
            let uses = info.get_entry_point(index);
            for (handle, global) in &globals {
                let Some(r) = &global.binding else { continue };
                if !uses[*handle].is_empty() && !self.bindings.iter().any(|b| b.group == r.group && b.binding == r.binding) {
                    problems.push(format!(
                        "{}: {entry} uses @group({}) @binding({}) {:?}, which the pass does not declare",
                        self.name, r.group, r.binding, global.name
                    ));
                }
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(problems)
        }
    }
}

/// The wgpu binding type of a resource.
fn binding_type(resource: Resource) -> wgpu::BindingType {
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    match resource {
        Resource::Uniform => buffer(wgpu::BufferBindingType::Uniform),
        Resource::Read => buffer(wgpu::BufferBindingType::Storage { read_only: true }),
        Resource::ReadWrite => buffer(wgpu::BufferBindingType::Storage { read_only: false }),
        Resource::Texture2d => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        Resource::TextureArray => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        Resource::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
    }
}

/// What a module's global is, as a [`Resource`] (`None`: a kind no pass declares).
fn resource_of(module: &naga::Module, global: &naga::GlobalVariable) -> Option<Resource> {
    match global.space {
        naga::AddressSpace::Uniform => Some(Resource::Uniform),
        naga::AddressSpace::Storage { access } if access.contains(naga::StorageAccess::STORE) => Some(Resource::ReadWrite),
        naga::AddressSpace::Storage { .. } => Some(Resource::Read),
        naga::AddressSpace::Handle => match &module.types[global.ty].inner {
            naga::TypeInner::Image { dim: naga::ImageDimension::D2, arrayed: false, class: naga::ImageClass::Sampled { .. } } => {
                Some(Resource::Texture2d)
            }
            naga::TypeInner::Image { dim: naga::ImageDimension::D2, arrayed: true, class: naga::ImageClass::Sampled { .. } } => {
                Some(Resource::TextureArray)
            }
            naga::TypeInner::Sampler { comparison: false } => Some(Resource::Sampler),
            _ => None,
        },
        _ => None,
    }
}

//! Shader modules composed from the WGSL files of `shaders/`. WGSL has no imports, so a
//! line `#import name` (alone on its line) is replaced by the text of `shaders/name.wgsl`
//! (or of a module generated from Rust: `contracts`, [`crate::contracts`], and
//! `fresnel_methods`, [`crate::params::wgsl_library`]), itself
//! composed first; a file imported twice in one module appears once, at its first
//! import. A name that is not a shader file, or a file that imports itself through others,
//! is an error naming the chain. The GPU runner keys each composed module by what it
//! shades (the pass and the Fresnel method), so a module is compiled once per key;
//! compute kernels are compiled here too ([`compute_pipelines`]).

use anyhow::{bail, Result};

/// The shader files of `shaders/`, by import name.
pub const SHADERS: [(&str, &str); 11] = [
    ("fresnel", include_str!("../../../shaders/fresnel.wgsl")),
    ("fresnel_pass", include_str!("../../../shaders/fresnel_pass.wgsl")),
    ("distance_map", include_str!("../../../shaders/distance_map.wgsl")),
    ("distance_search", include_str!("../../../shaders/distance_search.wgsl")),
    ("distance_map_render", include_str!("../../../shaders/distance_map_render.wgsl")),
    ("diffuse", include_str!("../../../shaders/diffuse.wgsl")),
    ("scene_mesh", include_str!("../../../shaders/scene_mesh.wgsl")),
    ("specular", include_str!("../../../shaders/specular.wgsl")),
    ("lut_sample", include_str!("../../../shaders/lut_sample.wgsl")),
    ("surfel_ao", include_str!("../../../shaders/surfel_ao.wgsl")),
    ("gtao", include_str!("../../../shaders/gtao.wgsl")),
];

/// Why a module could not be composed.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum ComposeError {
    #[error("shader import {name:?} (via {chain}): no such file in shaders/")]
    Unknown { name: String, chain: String },
    #[error("shader imports form a cycle: {chain}")]
    Cycle { chain: String },
}

/// `source` with every `#import` resolved against [`SHADERS`] and the generated modules
/// `contracts` ([`crate::contracts::wgsl`]) and `fresnel_methods`
/// ([`crate::params::wgsl_library`]).
pub fn compose(source: &str) -> Result<String, ComposeError> {
    let contracts = crate::contracts::wgsl();
    let methods = crate::params::wgsl_library();
    let mut files: Vec<(&str, &str)> = SHADERS.to_vec();
    files.push(("contracts", &contracts));
    files.push(("fresnel_methods", &methods));
    compose_from(&files, source)
}

/// `source` with every `#import` resolved against `files`.
pub fn compose_from(files: &[(&str, &str)], source: &str) -> Result<String, ComposeError> {
    let mut out = String::new();
    let mut included = Vec::new();
    expand(files, source, &mut vec!["(root)".to_string()], &mut included, &mut out)?;
    Ok(out)
}

/// The compute pipelines of `entries` in the module `#import shader`, compiled under one
/// validation scope: a composition or shader error is an error naming `what`, not a
/// panic. `layout` `None` lets wgpu derive the bind-group layout from the shader.
pub fn compute_pipelines<const N: usize>(
    device: &wgpu::Device,
    shader: &str,
    layout: Option<&wgpu::PipelineLayout>,
    entries: [&str; N],
    what: &str,
) -> Result<[wgpu::ComputePipeline; N]> {
    let source = compose(&format!("#import {shader}"))?;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module =
        device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(shader), source: wgpu::ShaderSource::Wgsl(source.into()) });
    let pipelines = entries.map(|entry| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout,
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    });
    if let Some(error) = pollster::block_on(scope.pop()) {
        bail!("compiling {what}: {error}");
    }
    Ok(pipelines)
}

/// The name a line imports, if it is an import.
fn imported(line: &str) -> Option<&str> {
    line.trim().strip_prefix("#import").map(str::trim).filter(|name| !name.is_empty())
}

fn expand(
    files: &[(&str, &str)],
    source: &str,
    chain: &mut Vec<String>,
    included: &mut Vec<String>,
    out: &mut String,
) -> Result<(), ComposeError> {
    for line in source.lines() {
        let Some(name) = imported(line) else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        if chain.iter().any(|c| c == name) {
            return Err(ComposeError::Cycle { chain: format!("{} -> {name}", chain.join(" -> ")) });
        }
        if included.iter().any(|i| i == name) {
            continue;
        }
        let Some(&(_, text)) = files.iter().find(|(file, _)| *file == name) else {
            return Err(ComposeError::Unknown { name: name.to_string(), chain: chain.join(" -> ") });
        };
        chain.push(name.to_string());
        expand(files, text, chain, included, out)?;
        chain.pop();
        included.push(name.to_string());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imports_resolve_depth_first_and_each_file_once() {
        let files = [("a", "#import c\nfn a() {}"), ("b", "#import c\n#import a\nfn b() {}"), ("c", "fn c() {}")];
        let composed = compose_from(&files, "#import b\n  #import a\nfn main() {}").unwrap();
        assert_eq!(composed, "fn c() {}\nfn a() {}\nfn b() {}\nfn main() {}\n");
    }

    #[test]
    fn unknown_names_and_cycles_are_errors_naming_the_chain() {
        let files = [("a", "#import b"), ("b", "#import a"), ("c", "#import nowhere")];
        assert_eq!(compose_from(&files, "#import a").unwrap_err(), ComposeError::Cycle { chain: "(root) -> a -> b -> a".into() });
        let unknown = compose_from(&files, "#import c").unwrap_err();
        assert_eq!(unknown, ComposeError::Unknown { name: "nowhere".into(), chain: "(root) -> c".into() });
        assert!(unknown.to_string().contains("nowhere"));
    }

    /// Every `.wgsl` file of `shaders/` is in [`SHADERS`] under its file name (a file left
    /// out would fail only when a pass imports it, at run time), with its text, and each
    /// composes (`passes`' tests validate every module a pass compiles with naga).
    #[test]
    fn every_shader_file_is_listed_and_composes() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shaders");
        let mut files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.unwrap().file_name().into_string().ok())
            .filter_map(|name| name.strip_suffix(".wgsl").map(str::to_string))
            .collect();
        files.sort();
        let mut listed: Vec<String> = SHADERS.iter().map(|(name, _)| name.to_string()).collect();
        listed.sort();
        assert_eq!(files, listed, "the files of shaders/ against compose::SHADERS");
        for (name, text) in SHADERS {
            let on_disk = std::fs::read_to_string(dir.join(format!("{name}.wgsl"))).unwrap();
            assert_eq!(text, on_disk, "SHADERS[{name:?}] is not shaders/{name}.wgsl");
        }
        for (name, _) in SHADERS {
            let composed = compose(&format!("#import {name}")).unwrap();
            assert!(!composed.lines().any(|l| imported(l).is_some()), "{name} left an import");
        }
    }

    #[test]
    fn the_pass_brings_the_library() {
        let pass = compose("#import fresnel_pass").unwrap();
        let library = SHADERS[0].1;
        let parts = library.split("#import contracts\n").flat_map(|part| part.split("#import fresnel_methods\n"));
        assert!(parts.into_iter().all(|part| pass.contains(part)), "the pass brings the whole library");
        assert!(pass.contains(&crate::params::wgsl_library()), "and every method's function");
        assert_eq!(pass.matches("fn fresnel_exact(").count(), 1);
    }
}

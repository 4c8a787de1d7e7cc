//! GPU passes as units with declared inputs and outputs ([`Pass`]: the shader, entry points
//! and bindings of [`interface`], checked against the WGSL): each owns its pipelines and
//! buffers, checks its sizes against the device's limits before allocating, and returns
//! wgpu's errors as `Result`s.
//!
//! - [`distance_maps`]: the layered distance maps of the specular objects, rasterised
//!   around each object's reference point with depth peeling (`shaders/distance_map_render.wgsl`).
//! - [`specular`]: the shading pass of multiple reflections and refractions through those
//!   maps, one pipeline per (effect, method) (`shaders/specular.wgsl`).
//! - [`ao`]: surfel accessibility and bent normals, N passes, brute force or through the
//!   surfel tree (`shaders/surfel_ao.wgsl`), held to the f64 CPU twin of `effects::ao`.
//! - [`gtao`]: screen-space ground-truth AO per pixel of a G-buffer (`shaders/gtao.wgsl`),
//!   held to the CPU twin of `effects::ao::gtao`.
//! - [`indirect`]: one or two bounces of diffuse indirect light between surfels (the same
//!   shader's `cs_indirect`), held to `effects::ao::indirect`.

pub mod ao;
pub mod distance_maps;
pub mod gtao;
pub mod indirect;
pub mod interface;
pub mod specular;

pub use interface::{Binding, Interface, Pass, Resource};

/// A composed module of a pass: the variant it is (`reflection, exact`; `schlick`; the
/// pass's name where it has one module) and its WGSL.
pub struct Variant {
    pub name: String,
    pub wgsl: String,
}

/// The name of the specular pass's variant of (effect, method): `reflection, exact`.
pub fn specular_variant(effect: specular::Effect, method: nklut_optics::fresnel::Method) -> String {
    format!("{}, {}", effect.name(), method.name())
}

/// Every pass's interface with the composed WGSL of each of its variants (one per
/// (effect, method) of the specular pass, one per shading of the Fresnel pass): what
/// [`Interface::check`] holds the declarations to, and what the browser bench compiles.
pub fn interfaces() -> Result<Vec<(Interface, Vec<Variant>)>, crate::compose::ComposeError> {
    use nklut_effects::scene::Shading;
    use nklut_optics::fresnel::Method;
    let single = |interface: Interface| -> Result<(Interface, Vec<Variant>), crate::compose::ComposeError> {
        let wgsl = crate::compose::compose(&format!("#import {}", interface.shader))?;
        Ok((interface, vec![Variant { name: interface.name.to_string(), wgsl }]))
    };
    let mut specular = Vec::new();
    for effect in [specular::Effect::Reflection, specular::Effect::Refraction] {
        for method in Method::ALL {
            let name = specular_variant(effect, method);
            specular.push(Variant { name, wgsl: specular::compose_effect(effect, method)? });
        }
    }
    let burner = crate::render::Shade::Burner;
    let dielectric = crate::render::Shade::ExactDielectric;
    let mut fresnel = vec![
        Variant { name: burner.name(), wgsl: crate::render::compose(burner)? },
        Variant { name: dielectric.name(), wgsl: crate::render::compose(dielectric)? },
    ];
    for shading in Shading::ALL {
        let shade = crate::render::Shade::Method(shading);
        fresnel.push(Variant { name: shade.name(), wgsl: crate::render::compose(shade)? });
    }
    Ok(vec![
        single(<ao::SurfelAoPass as Pass>::INTERFACE)?,
        single(<indirect::IndirectPass as Pass>::INTERFACE)?,
        single(<gtao::GtaoPass as Pass>::INTERFACE)?,
        single(<distance_maps::MapRenderer as Pass>::INTERFACE)?,
        single(<crate::distance_search::DistanceSearchPass as Pass>::INTERFACE)?,
        (<specular::SpecularPass as Pass>::INTERFACE, specular),
        (<crate::render::Renderer as Pass>::INTERFACE, fresnel),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each pass's declared bindings are its shader's, by group, binding, name and kind, and
    /// its entry points use nothing it does not declare, in every variant.
    #[test]
    fn every_pass_declares_what_its_shader_binds() {
        let all = interfaces().unwrap();
        assert_eq!(all.len(), 7);
        for (interface, sources) in &all {
            assert!(!sources.is_empty());
            for source in sources {
                interface.check(&source.wgsl).unwrap_or_else(|problems| panic!("{}: {problems:#?}", source.name));
            }
        }
    }

    /// The check fails on each kind of disagreement: a binding the shader lacks, a wrong
    /// name, a wrong kind, and a binding an entry point uses that is not declared.
    #[test]
    fn the_check_sees_each_disagreement() {
        let (interface, sources) = interfaces().unwrap().remove(0);
        let source = &sources[0].wgsl;
        let with = |bindings: &'static [Binding]| Interface { bindings, ..interface };
        let problems = |bindings| with(bindings).check(source).unwrap_err().join("\n");
        let mut declared: Vec<Binding> = interface.bindings.to_vec();
        // `bent` (binding 4) left out: cs_brute_force writes it.
        declared.retain(|b| b.binding != 4);
        assert!(problems(declared.clone().leak()).contains("uses @group(0) @binding(4)"), "{}", problems(declared.clone().leak()));
        // `state` declared read-only.
        let mut wrong_kind = interface.bindings.to_vec();
        wrong_kind[3].resource = Resource::Read;
        assert!(problems(wrong_kind.leak()).contains("state is Some(ReadWrite) in the shader, declared Read"));
        // A misnamed binding and one the shader does not have.
        let mut renamed = interface.bindings.to_vec();
        renamed[1].name = "surfels";
        renamed.push(Binding::new(0, 9, "extra", Resource::Uniform));
        let text = problems(renamed.leak());
        assert!(text.contains("declared surfels") && text.contains("@binding(9) extra is not in the shader"), "{text}");
    }
}

//! Per-material shader uniforms (SPEC §5): the GPU packing of the fresnel module's
//! per-channel parameters. Everything numerical lives in [`nklut_optics::fresnel`]
//! ([`Prepared`], [`ShaderParams`], each method's unit under `fresnel/methods/`); this file
//! lays the three channels out as the uniform block `MaterialParams` and writes that
//! struct's WGSL from the same list ([`wgsl_library`]), so the two cannot differ.

use bytemuck::{Pod, Zeroable};

use nklut_effects::scene::Shading;
use nklut_optics::fresnel::{Method, Prepared, ShaderChannel, ShaderParams, METHOD_UNIFORM_MEMBERS};
use nklut_optics::spectrum::ChannelIndex;

/// The fresnel module's parameters of a material, red, green, blue.
pub fn prepare(channels: &ChannelIndex) -> [Prepared; 3] {
    channels.map(Prepared::new)
}

/// The uniform block `MaterialParams` (written by [`wgsl_library`]): one vec4 per
/// parameter, rgb = red, green, blue, w unused (0): n, k, F0, then every method's
/// members ([`Method::uniform`]) in the order of [`Method::ALL`], then the `constant`
/// baseline's colour. Its layout is held to the shader's by `crate::layout`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MaterialUniform {
    pub n: [f32; 4],
    pub k: [f32; 4],
    pub f0: [f32; 4],
    /// Every method's members (e.g. `schlick_compensated`'s weight: 2n, or 0 where it
    /// falls back to plain `schlick_nk`).
    pub methods: [[f32; 4]; METHOD_UNIFORM_MEMBERS],
    /// The `constant` baseline: F0.
    pub constant_colour: [f32; 4],
}

impl Default for MaterialUniform {
    fn default() -> Self {
        Self::zeroed()
    }
}

impl MaterialUniform {
    pub fn new(params: &[ShaderParams; 3]) -> Self {
        let v = |f: &dyn Fn(&ShaderParams) -> f32| [f(&params[0]), f(&params[1]), f(&params[2]), 0.0];
        let members = params.map(|p| p.members());
        let mut methods = [[0.0; 4]; METHOD_UNIFORM_MEMBERS];
        for (i, member) in methods.iter_mut().enumerate() {
            *member = [members[0][i], members[1][i], members[2][i], 0.0];
        }
        MaterialUniform {
            n: v(&|p| p.channel().n),
            k: v(&|p| p.channel().k),
            f0: v(&|p| p.channel().f0),
            methods,
            constant_colour: v(&|p| p.channel().f0),
        }
    }

    pub fn from_prepared(prepared: &[Prepared; 3]) -> Self {
        Self::new(&[0, 1, 2].map(|c| prepared[c].shader_params()))
    }

    pub fn from_channels(channels: &ChannelIndex) -> Self {
        Self::from_prepared(&prepare(channels))
    }

    /// The shader parameters of `channel` (0 red, 1 green, 2 blue), as the GPU reads them.
    pub fn channel(&self, channel: usize) -> ShaderParams {
        let i = channel;
        let members: Vec<f32> = self.methods.iter().map(|member| member[i]).collect();
        let base = ShaderChannel { n: self.n[i], k: self.k[i], f0: self.f0[i] };
        ShaderParams::from_members(base, &members).expect("one value per uniform member")
    }

    /// The f32 CPU reference of `method` for `channel`: the method's f32 twin (which its
    /// WGSL function mirrors operation by operation; `tests/gpu.rs` holds them to 1e-5).
    /// `None` for the methods that read a texture (`lut`, `texture`): their reference is
    /// the CPU LUT model.
    pub fn evaluate_f32(&self, method: Shading, channel: usize, c: f32) -> Option<f32> {
        match method {
            Shading::Constant => Some(self.constant_colour[channel]),
            _ => self.channel(channel).analytic(method.fresnel()?, c),
        }
    }
}

/// The names of `MaterialParams`' members in order (the Rust struct's fields, with the
/// methods' members spelled out).
pub fn uniform_members() -> Vec<&'static str> {
    let mut names = vec!["n", "k", "f0"];
    names.extend(Method::ALL.iter().flat_map(|m| m.uniform().iter().copied()));
    names.push("constant_colour");
    names
}

/// The generated shader module `fresnel_methods` (served by `crate::compose`): the struct
/// `MaterialParams` of [`MaterialUniform`] and every method's WGSL function, from the
/// methods' units. `shaders/fresnel.wgsl` imports it and holds the helpers they share.
pub fn wgsl_library() -> String {
    let mut out = String::from(
        "// Generated from the Fresnel methods' units (crates/optics/src/fresnel/methods/) by\n\
         // crates/gpu/src/params.rs: the per-channel parameters (rgb = red, green, blue) and one\n\
         // function per method.\n\nstruct MaterialParams {\n",
    );
    for name in uniform_members() {
        out.push_str(&format!("    {name}: vec4<f32>,\n"));
    }
    out.push_str("}\n");
    for method in Method::ALL {
        out.push_str(method.wgsl());
    }
    out
}

/// The function of the Fresnel library that shades `shading`.
pub fn wgsl_function(shading: Shading) -> &'static str {
    match shading {
        Shading::Fresnel(method) => method.wgsl_function(),
        Shading::Constant => "fresnel_constant",
        Shading::Texture => "fresnel_texture",
    }
}

/// Methods that read the material's texture.
pub fn needs_texture(method: Shading) -> bool {
    match method {
        Shading::Fresnel(method) => method.reads_texture(),
        Shading::Texture => true,
        Shading::Constant => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::fresnel;
    use nklut_optics::spectrum::Index;

    const GOLD: ChannelIndex = [Index::new(0.16, 3.8), Index::new(0.5, 2.3), Index::new(1.2, 1.8)];

    #[test]
    fn uniform_round_trips_shader_params() {
        let prepared = prepare(&GOLD);
        let uniform = MaterialUniform::from_prepared(&prepared);
        for (i, p) in prepared.iter().enumerate() {
            assert_eq!(uniform.channel(i), p.shader_params());
            assert_eq!(uniform.constant_colour[i], p.f0 as f32);
            assert_eq!(uniform.n[i], p.index.n as f32);
        }
        assert_eq!(uniform.n[3], 0.0);
    }

    #[test]
    fn every_shader_method_has_a_reference_but_the_texture_ones() {
        let uniform = MaterialUniform::from_channels(&GOLD);
        for method in Shading::ALL {
            let value = uniform.evaluate_f32(method, 1, 0.5);
            assert_eq!(value.is_none(), needs_texture(method), "{method}");
            if let (Some(value), Some(m)) = (value, method.fresnel()) {
                assert_eq!(value, fresnel::Prepared::new(GOLD[1]).shader_params().analytic(m, 0.5).unwrap());
            }
        }
    }

    /// The composed Fresnel library, parsed and validated by naga (wgpu's own front end).
    fn library() -> naga::Module {
        let source = crate::compose::compose("#import fresnel").unwrap();
        naga::front::wgsl::parse_str(&source).unwrap()
    }

    /// Every shading's function is a function of the library.
    #[test]
    fn every_shading_names_a_function_of_the_library() {
        let module = library();
        let functions: Vec<&str> = module.functions.iter().filter_map(|(_, f)| f.name.as_deref()).collect();
        for shading in Shading::ALL {
            assert!(functions.contains(&wgsl_function(shading)), "{shading}: no {} in fresnel.wgsl", wgsl_function(shading));
        }
        assert_eq!(Shading::ALL.iter().filter(|s| s.fresnel().is_some()).count(), Method::ALL.len());
    }
}

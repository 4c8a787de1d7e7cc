//! Per-material shader uniforms (SPEC §5): the GPU packing of the fresnel module's
//! per-channel parameters. Everything numerical — F0, the compensated λ and its fallback
//! (weight 0), Lazányi's a, the nvidia fit, and the f32 methods the WGSL mirrors — lives in
//! [`nklut_optics::fresnel`] ([`Prepared`], [`ShaderParams`], `fresnel::*_f32`); this file only
//! lays the three channels out as the uniform block of `shaders/fresnel.wgsl`.

use bytemuck::{Pod, Zeroable};

use nklut_effects::scene::Shading;
use nklut_optics::fresnel::{Method, Prepared, ShaderParams};
use nklut_optics::spectrum::ChannelIndex;

/// The fresnel module's parameters of a material, red, green, blue.
pub fn prepare(channels: &ChannelIndex) -> [Prepared; 3] {
    channels.map(Prepared::new)
}

/// The uniform block `MaterialParams` of `shaders/fresnel.wgsl`: one vec4 per
/// [`ShaderParams`] field, rgb = red, green, blue, w unused (0). Its layout is held to the
/// shader's by `crate::layout`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct MaterialUniform {
    pub n: [f32; 4],
    pub k: [f32; 4],
    pub f0: [f32; 4],
    /// 2n, or 0 where `schlick_compensated` falls back (then it is plain `schlick_nk`).
    pub compensation_weight: [f32; 4],
    pub compensation_lambda: [f32; 4],
    pub lazanyi_a: [f32; 4],
    pub nvidia_bias: [f32; 4],
    pub nvidia_scale: [f32; 4],
    pub nvidia_power: [f32; 4],
    /// `f82_tint`'s authored F0 and tint (linear).
    pub f82_f0: [f32; 4],
    pub f82_tint: [f32; 4],
    /// The `constant` baseline: F0.
    pub constant_colour: [f32; 4],
}

impl MaterialUniform {
    pub fn new(params: &[ShaderParams; 3]) -> Self {
        let v = |f: fn(&ShaderParams) -> f32| [f(&params[0]), f(&params[1]), f(&params[2]), 0.0];
        MaterialUniform {
            n: v(|p| p.n),
            k: v(|p| p.k),
            f0: v(|p| p.f0),
            compensation_weight: v(|p| p.compensation_weight),
            compensation_lambda: v(|p| p.compensation_lambda),
            lazanyi_a: v(|p| p.lazanyi_a),
            nvidia_bias: v(|p| p.nvidia_bias),
            nvidia_scale: v(|p| p.nvidia_scale),
            nvidia_power: v(|p| p.nvidia_power),
            f82_f0: v(|p| p.f82_f0),
            f82_tint: v(|p| p.f82_tint),
            constant_colour: v(|p| p.f0),
        }
    }

    pub fn from_prepared(prepared: &[Prepared; 3]) -> Self {
        Self::new(&prepared.map(|p| p.shader_params()))
    }

    pub fn from_channels(channels: &ChannelIndex) -> Self {
        Self::from_prepared(&prepare(channels))
    }

    /// The shader parameters of `channel` (0 red, 1 green, 2 blue), as the GPU reads them.
    pub fn channel(&self, channel: usize) -> ShaderParams {
        let i = channel;
        ShaderParams {
            n: self.n[i],
            k: self.k[i],
            f0: self.f0[i],
            compensation_weight: self.compensation_weight[i],
            compensation_lambda: self.compensation_lambda[i],
            lazanyi_a: self.lazanyi_a[i],
            nvidia_bias: self.nvidia_bias[i],
            nvidia_scale: self.nvidia_scale[i],
            nvidia_power: self.nvidia_power[i],
            f82_f0: self.f82_f0[i],
            f82_tint: self.f82_tint[i],
        }
    }

    /// The f32 CPU reference of `method` for `channel`: the fresnel module's `*_f32`
    /// function (which `shaders/fresnel.wgsl` mirrors operation by operation; `tests/gpu.rs`
    /// holds them to 1e-5). `None` for the methods that read a texture (`lut`, `texture`):
    /// their reference is the CPU LUT model.
    pub fn evaluate_f32(&self, method: Shading, channel: usize, c: f32) -> Option<f32> {
        match method {
            Shading::Constant => Some(self.constant_colour[channel]),
            _ => self.channel(channel).analytic(method.fresnel()?, c),
        }
    }
}

/// The function of `shaders/fresnel.wgsl` that shades `shading`: one entry per shading, no
/// wildcard, so a method added to `fresnel::Method` does not compile until its WGSL
/// function is named here (and `tests` check the name is a function of the library).
pub fn wgsl_function(shading: Shading) -> &'static str {
    match shading {
        Shading::Fresnel(method) => match method {
            Method::Exact => "fresnel_exact",
            Method::Schlick => "fresnel_schlick",
            Method::SchlickNk => "fresnel_schlick_nk",
            Method::SchlickCompensated => "fresnel_schlick_compensated",
            Method::Lazanyi => "fresnel_lazanyi",
            Method::Nvidia => "fresnel_nvidia",
            Method::Lut => "fresnel_lut",
            Method::F82Tint => "fresnel_f82_tint",
        },
        Shading::Constant => "fresnel_constant",
        Shading::Texture => "fresnel_texture",
    }
}

/// Methods that read the material's texture.
pub fn needs_texture(method: Shading) -> bool {
    matches!(method, Shading::Fresnel(Method::Lut) | Shading::Texture)
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

//! `nvidia` (SPEC §5.6; Fernando & Kilgard 2003, The Cg Tutorial ch. 7): the empirical
//! F = max(0, min(1, bias + scale (1 − c)^power)), bias, scale and power fitted per channel
//! by least squares against `exact` ([`crate::fresnel::fit_nvidia`], the fit and its
//! derivation in `fresnel/nvidia.rs`).

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::{fit_nvidia, nvidia, NvidiaFit};

/// The unit of `nvidia`: the fit per channel.
pub struct Nvidia;

impl FresnelMethod for Nvidia {
    type Params<T: Real> = NvidiaFit<T>;
    const NAME: &'static str = "nvidia";
    const WGSL_FUNCTION: &'static str = "fresnel_nvidia";
    const WGSL: &'static str = "
// nvidia (SPEC §5.6): max(0, min(1, bias + scale (1 − c)^power)), fitted per material.
fn fresnel_nvidia(c: f32, p: MaterialParams) -> vec3<f32> {
    let m = vec3<f32>(1.0 - clamp(c, 0.0, 1.0));
    let f = p.nvidia_bias.rgb + p.nvidia_scale.rgb * shader_pow(m, p.nvidia_power.rgb);
    return clamp(f, vec3<f32>(0.0), vec3<f32>(1.0));
}
";
    const UNIFORM: &'static [&'static str] = &["nvidia_bias", "nvidia_scale", "nvidia_power"];

    fn fit(channel: &Channel) -> NvidiaFit {
        fit_nvidia(&channel.exact)
    }

    fn members<T: Real>(fit: &NvidiaFit<T>, out: &mut [T]) {
        out[..3].copy_from_slice(&[fit.bias, fit.scale, fit.power]);
    }

    /// The shader's parameters: the fit's residual is not carried (0).
    fn from_members<T: Real>(members: &[T]) -> NvidiaFit<T> {
        NvidiaFit { bias: members[0], scale: members[1], power: members[2], rms_residual: T::ZERO }
    }

    #[inline]
    fn reflectance(_: &Channel, fit: &NvidiaFit, cos_theta: f64) -> Option<f64> {
        Some(nvidia(fit.bias, fit.scale, fit.power, cos_theta))
    }

    #[inline]
    fn reflectance_f32(_: &ShaderChannel, fit: &NvidiaFit<f32>, cos_theta: f32) -> Option<f32> {
        Some(nvidia(fit.bias, fit.scale, fit.power, cos_theta))
    }

    /// (1 − c)^power changes on the scale c ~ 1/power; the clamps at 0 and 1 are kinks.
    fn kinks(_: &Channel, fit: &NvidiaFit) -> Vec<f64> {
        let mut cosines = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0].map(|j| j / fit.power).to_vec();
        for level in [0.0, 1.0] {
            let m = ((level - fit.bias) / fit.scale).powf(1.0 / fit.power);
            cosines.push(1.0 - m);
        }
        cosines
    }
}

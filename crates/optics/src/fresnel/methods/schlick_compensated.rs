//! `schlick_compensated` (SPEC §5.4): `schlick_nk` less w (1 − c)^λ, w = 2n and λ fitted per
//! channel so that F is exact at θ = 84.26° (c = 0.1); where no real λ exists, w = 0 and
//! the method is plain `schlick_nk` (a [`CompensationFallback`]). Closed form and fit:
//! [`crate::fresnel::schlick_compensated`], [`crate::fresnel::compensation`].

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
#[allow(unused_imports)] // the module doc's link
use crate::fresnel::CompensationFallback;
use crate::fresnel::{compensation, schlick_compensated, Compensation};

/// The unit of `schlick_compensated`: the weight and λ per channel.
pub struct SchlickCompensated;

impl FresnelMethod for SchlickCompensated {
    type Params<T: Real> = Compensation<T>;
    const NAME: &'static str = "schlick_compensated";
    const WGSL_FUNCTION: &'static str = "fresnel_schlick_compensated";
    const WGSL: &'static str = "
// schlick_compensated (SPEC §5.4): schlick_nk − w (1 − c)^λ, w = 2n and λ per channel
// exact at θ = 84.26°; where no real λ exists w = 0 (plain schlick_nk).
fn fresnel_schlick_compensated(c: f32, p: MaterialParams) -> vec3<f32> {
    let m = vec3<f32>(1.0 - clamp(c, 0.0, 1.0));
    return fresnel_schlick_nk(c, p) - p.compensation_weight.rgb * shader_pow(m, p.compensation_lambda.rgb);
}
";
    const UNIFORM: &'static [&'static str] = &["compensation_weight", "compensation_lambda"];

    fn fit(channel: &Channel) -> Compensation {
        compensation(channel.index, &channel.exact)
    }

    fn members<T: Real>(params: &Compensation<T>, out: &mut [T]) {
        out[0] = params.weight;
        out[1] = params.lambda;
    }

    /// The shader's parameters: a fallback is weight 0, its reason is not carried.
    fn from_members<T: Real>(members: &[T]) -> Compensation<T> {
        Compensation { weight: members[0], lambda: members[1], fallback: None }
    }

    #[inline]
    fn reflectance(channel: &Channel, params: &Compensation, cos_theta: f64) -> Option<f64> {
        let n = channel.index.n;
        Some(schlick_compensated(n, channel.index.k, params.weight, params.lambda, cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, params: &Compensation<f32>, cos_theta: f32) -> Option<f32> {
        Some(schlick_compensated(channel.n, channel.k, params.weight, params.lambda, cos_theta))
    }

    /// (1 − c)^λ changes on the scale c ~ 1/λ.
    fn kinks(_: &Channel, params: &Compensation) -> Vec<f64> {
        match params.fallback {
            None => [0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0].map(|j| j / params.lambda).to_vec(),
            Some(_) => Vec::new(),
        }
    }
}

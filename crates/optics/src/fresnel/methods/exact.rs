//! `exact` (SPEC §5.1): the unpolarised Fresnel reflectance (Rs + Rp)/2 of η = n + ik, the
//! reference every other method is measured against. Born & Wolf §14.2 in the stable
//! forms of `fresnel/exact.rs` (derivation there); the f64 body uses the channel's
//! precomputed terms, the f32 twin ([`exact_f32`]) forms them per evaluation as the WGSL
//! `exact_channel` of `shaders/fresnel.wgsl` does.

use crate::fresnel::exact_f32;
use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;

/// The unit of `exact`: no parameters beyond n and k.
pub struct Exact;

impl FresnelMethod for Exact {
    type Params<T: Real> = ();
    const NAME: &'static str = "exact";
    const WGSL_FUNCTION: &'static str = "fresnel_exact";
    const WGSL: &'static str = "
// exact (SPEC §5.1): exact_channel per channel.
fn fresnel_exact(c: f32, p: MaterialParams) -> vec3<f32> {
    let n = p.n;
    let k = p.k;
    return vec3<f32>(exact_channel(n.r, k.r, c), exact_channel(n.g, k.g, c), exact_channel(n.b, k.b, c));
}
";
    const UNIFORM: &'static [&'static str] = &[];

    fn fit(_: &Channel) {}

    fn members<T: Real>(_: &(), _: &mut [T]) {}

    fn from_members<T: Real>(_: &[T]) {}

    #[inline]
    fn reflectance(channel: &Channel, _: &(), cos_theta: f64) -> Option<f64> {
        Some(channel.exact.reflectance(cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, _: &(), cos_theta: f32) -> Option<f32> {
        Some(exact_f32(channel.n, channel.k, cos_theta))
    }
}

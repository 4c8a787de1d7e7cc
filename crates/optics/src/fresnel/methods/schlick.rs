//! `schlick` (SPEC §5.2; Schlick 1994, "An Inexpensive BRDF Model for Physically-based
//! Rendering", eq. 24): F = F0 + (1 − F0)(1 − c)⁵ with F0 from (n, k). The closed form is
//! [`crate::fresnel::schlick`], one body for f64 and f32.

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::schlick;

/// The unit of `schlick`: F0 is shared by every method.
pub struct Schlick;

impl FresnelMethod for Schlick {
    type Params<T: Real> = ();
    const NAME: &'static str = "schlick";
    const WGSL_FUNCTION: &'static str = "fresnel_schlick";
    const WGSL: &'static str = "
// schlick (SPEC §5.2; Schlick 1994): F0 + (1 − F0)(1 − c)⁵, F0 precomputed.
fn fresnel_schlick(c: f32, p: MaterialParams) -> vec3<f32> {
    let m5 = pow5(vec3<f32>(1.0 - clamp(c, 0.0, 1.0)));
    let f0 = p.f0.rgb;
    return f0 + (vec3<f32>(1.0) - f0) * m5;
}
";
    const UNIFORM: &'static [&'static str] = &[];

    fn fit(_: &Channel) {}

    fn members<T: Real>(_: &(), _: &mut [T]) {}

    fn from_members<T: Real>(_: &[T]) {}

    #[inline]
    fn reflectance(channel: &Channel, _: &(), cos_theta: f64) -> Option<f64> {
        Some(schlick(channel.f0, cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, _: &(), cos_theta: f32) -> Option<f32> {
        Some(schlick(channel.f0, cos_theta))
    }
}

//! `schlick_nk` (SPEC §5.3; Lazányi & Szirmay-Kalos 2005, "Fresnel Term Approximations for
//! Metals", eq. 3): F = ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²), Schlick's form from n
//! and k at the point of use. The closed form is [`crate::fresnel::schlick_nk`].

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::schlick_nk;

/// The unit of `schlick_nk`: n and k only.
pub struct SchlickNk;

impl FresnelMethod for SchlickNk {
    type Params<T: Real> = ();
    const NAME: &'static str = "schlick_nk";
    const WGSL_FUNCTION: &'static str = "fresnel_schlick_nk";
    const WGSL: &'static str = "
// schlick_nk (SPEC §5.3; Lazányi & Szirmay-Kalos 2005):
// ((n − 1)² + 4n(1 − c)⁵ + k²)/((n + 1)² + k²), from n and k.
fn fresnel_schlick_nk(c: f32, p: MaterialParams) -> vec3<f32> {
    let m5 = pow5(vec3<f32>(1.0 - clamp(c, 0.0, 1.0)));
    let n = p.n.rgb;
    let k = p.k.rgb;
    let one = vec3<f32>(1.0);
    return ((n - one) * (n - one) + 4.0 * n * m5 + k * k) / ((n + one) * (n + one) + k * k);
}
";
    const UNIFORM: &'static [&'static str] = &[];

    fn fit(_: &Channel) {}

    fn members<T: Real>(_: &(), _: &mut [T]) {}

    fn from_members<T: Real>(_: &[T]) {}

    #[inline]
    fn reflectance(channel: &Channel, _: &(), cos_theta: f64) -> Option<f64> {
        Some(schlick_nk(channel.index.n, channel.index.k, cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, _: &(), cos_theta: f32) -> Option<f32> {
        Some(schlick_nk(channel.n, channel.k, cos_theta))
    }
}

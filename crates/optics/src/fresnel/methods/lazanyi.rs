//! `lazanyi` (SPEC §5.5; Lazányi & Szirmay-Kalos 2005, the error compensation term
//! a·c·(1 − c)^α with α = 6; Hoffman 2019's F82 form): F = F0 + (1 − F0)(1 − c)⁵ − a c (1 − c)⁶,
//! a per channel so that F is exact at c = 1/7 ([`crate::fresnel::lazanyi_a`]).

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::{lazanyi, lazanyi_a};

/// The unit of `lazanyi`: a per channel.
pub struct Lazanyi;

impl FresnelMethod for Lazanyi {
    type Params<T: Real> = T;
    const NAME: &'static str = "lazanyi";
    const WGSL_FUNCTION: &'static str = "fresnel_lazanyi";
    const WGSL: &'static str = "
// lazanyi (SPEC §5.5; Lazányi & Szirmay-Kalos 2005, the F82 form):
// F0 + (1 − F0)(1 − c)⁵ − a c (1 − c)⁶, a exact at c = 1/7.
fn fresnel_lazanyi(c: f32, p: MaterialParams) -> vec3<f32> {
    let unit_c = clamp(c, 0.0, 1.0);
    let m = vec3<f32>(1.0 - unit_c);
    let m5 = pow5(m);
    let f0 = p.f0.rgb;
    return f0 + (vec3<f32>(1.0) - f0) * m5 - p.lazanyi_a.rgb * unit_c * (m5 * m);
}
";
    const UNIFORM: &'static [&'static str] = &["lazanyi_a"];

    fn fit(channel: &Channel) -> f64 {
        lazanyi_a(channel.index, &channel.exact)
    }

    fn members<T: Real>(a: &T, out: &mut [T]) {
        out[0] = *a;
    }

    fn from_members<T: Real>(members: &[T]) -> T {
        members[0]
    }

    #[inline]
    fn reflectance(channel: &Channel, a: &f64, cos_theta: f64) -> Option<f64> {
        Some(lazanyi(channel.f0, *a, cos_theta))
    }

    #[inline]
    fn reflectance_f32(channel: &ShaderChannel, a: &f32, cos_theta: f32) -> Option<f32> {
        Some(lazanyi(channel.f0, *a, cos_theta))
    }
}

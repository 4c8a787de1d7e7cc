//! `f82_tint` (SPEC §5.8; the F82-tint metal of OpenPBR 1.1, the Adobe Standard Material and
//! Blender 4's Principled BSDF, after Hoffman 2023): F = F_S(c) − b c (1 − c)⁶ from the
//! authored colours F0 and tint, b formed per evaluation as a shader does. The closed form
//! and the colours: [`crate::fresnel::f82_tint`], [`crate::fresnel::f82_colours`].

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;
use crate::fresnel::{f82_colours, f82_tint, F82Colours};

/// The unit of `f82_tint`: the authored F0 and tint per channel.
pub struct F82Tint;

impl FresnelMethod for F82Tint {
    type Params<T: Real> = F82Colours<T>;
    const NAME: &'static str = "f82_tint";
    const WGSL_FUNCTION: &'static str = "fresnel_f82_tint";
    const WGSL: &'static str = "
// f82_tint (SPEC §5.8; OpenPBR's, Adobe's and Blender's metal Fresnel): from the
// authored colours F0 and tint, F_S(c) − b c (1 − c)⁶ with F_S(c) = F0 + (1 − F0)(1 − c)⁵,
// b = F_S(μ̄)(1 − tint)/(μ̄ (1 − μ̄)⁶), μ̄ = 1/7 (LAZANYI_COS), b formed here as an engine's shader does.
fn fresnel_f82_tint(c: f32, p: MaterialParams) -> vec3<f32> {
    let unit_c = clamp(c, 0.0, 1.0);
    let m = vec3<f32>(1.0 - unit_c);
    let m5 = pow5(m);
    let f0 = p.f82_f0.rgb;
    let one = vec3<f32>(1.0);
    let mu = LAZANYI_COS;
    let mu_m = vec3<f32>(1.0 - mu);
    let mu_m5 = pow5(mu_m);
    let at_mu = f0 + (one - f0) * mu_m5;
    let b = at_mu * (one - p.f82_tint.rgb) / (mu * (mu_m5 * mu_m));
    return f0 + (one - f0) * m5 - b * unit_c * (m5 * m);
}
";
    const UNIFORM: &'static [&'static str] = &["f82_f0", "f82_tint"];

    fn fit(channel: &Channel) -> F82Colours {
        f82_colours(channel.index, &channel.exact)
    }

    fn members<T: Real>(colours: &F82Colours<T>, out: &mut [T]) {
        out[0] = colours.f0;
        out[1] = colours.tint;
    }

    fn from_members<T: Real>(members: &[T]) -> F82Colours<T> {
        F82Colours { f0: members[0], tint: members[1] }
    }

    #[inline]
    fn reflectance(_: &Channel, colours: &F82Colours, cos_theta: f64) -> Option<f64> {
        Some(f82_tint(colours.f0, colours.tint, cos_theta))
    }

    #[inline]
    fn reflectance_f32(_: &ShaderChannel, colours: &F82Colours<f32>, cos_theta: f32) -> Option<f32> {
        Some(f82_tint(colours.f0, colours.tint, cos_theta))
    }
}

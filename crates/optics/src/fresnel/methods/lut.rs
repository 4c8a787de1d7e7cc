//! `lut` (SPEC §5.7): F read from an N×1 texture of `exact` with a GPU's linear filter
//! (the texture and its sampling in `fresnel/lut.rs`). It has no analytic body: a
//! [`crate::fresnel::Model`] of `lut` carries its texture and samples it.

use crate::fresnel::method::{Channel, FresnelMethod, ShaderChannel};
use crate::fresnel::real::Real;

/// The unit of `lut`: its texture is baked per material, not a uniform.
pub struct Lut;

impl FresnelMethod for Lut {
    type Params<T: Real> = ();
    const NAME: &'static str = "lut";
    const WGSL_FUNCTION: &'static str = "fresnel_lut";
    const WGSL: &'static str = "
// lut (SPEC §5.7): N×1 texture of one index's curve, texel i = F at c = (i + ½)/N,
// hardware linear filter, clamp-to-edge, u = c, v = ½. A ray from inside samples the
// texture baked from exact F of the inside index (total reflection past the critical angle).
fn fresnel_lut(c: f32, curve: texture_2d<f32>, curve_sampler: sampler) -> vec3<f32> {
    return textureSampleLevel(curve, curve_sampler, vec2<f32>(c, 0.5), 0.0).rgb;
}
";
    const READS_TEXTURE: bool = true;
    const UNIFORM: &'static [&'static str] = &[];

    fn fit(_: &Channel) {}

    fn members<T: Real>(_: &(), _: &mut [T]) {}

    fn from_members<T: Real>(_: &[T]) {}

    #[inline]
    fn reflectance(_: &Channel, _: &(), _: f64) -> Option<f64> {
        None
    }

    #[inline]
    fn reflectance_f32(_: &ShaderChannel, _: &(), _: f32) -> Option<f32> {
        None
    }
}

//! A Fresnel method as one unit (SPEC §5): the type that owns the method's per-channel
//! parameters, how they are fitted from the channel's index, its body in f64 (the CPU
//! reference) and f32 (the shader twin), its WGSL function with the uniform members it
//! reads, and where its error integrand has kinks. Every method implements
//! [`FresnelMethod`] in a file of its own under `fresnel/methods/`, and the list in
//! `fresnel/methods/mod.rs` (one line per method) makes the [`Method`] enum, its tables'
//! names, the lazily fitted parameters of [`Prepared`](super::Prepared), the shader's parameters
//! ([`ShaderParams`](super::ShaderParams)) and the GPU's uniform layout from it. docs/extending.md walks
//! through adding one.
//!
//! [`Method`]: super::Method

use std::fmt::Debug;

use super::real::Real;
use super::{ExactTerms, Index};

/// One channel's index with what every method shares: the sanitised (n, k), F0 and the
/// angle-independent terms of `exact` (the fits are made against them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Channel {
    /// The sanitised index (see [`super::sanitise`]).
    pub index: Index,
    /// Normal-incidence reflectance F0 = ((n − 1)² + k²)/((n + 1)² + k²) (SPEC §5.2).
    pub f0: f64,
    /// Angle-independent terms of `exact`.
    pub exact: ExactTerms,
}

/// The same as a shader receives it: n, k and F0 rounded once to f32.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShaderChannel {
    /// n.
    pub n: f32,
    /// k.
    pub k: f32,
    /// F0 = ((n − 1)² + k²)/((n + 1)² + k²).
    pub f0: f32,
}

impl ShaderChannel {
    /// `channel` rounded to f32.
    pub fn of(channel: &Channel) -> Self {
        Self { n: channel.index.n as f32, k: channel.index.k as f32, f0: channel.f0 as f32 }
    }
}

/// The most uniform members one method may add to the shader's `MaterialParams`.
pub const MAX_UNIFORM_MEMBERS: usize = 4;

/// A Fresnel method: everything about it in one place.
///
/// The CPU evaluates [`FresnelMethod::reflectance`] with parameters fitted once per
/// channel ([`FresnelMethod::fit`], called the first time the method is asked for), the
/// f32 twin [`FresnelMethod::reflectance_f32`] with the same parameters rounded to f32
/// member by member, and the GPU the WGSL function [`FresnelMethod::WGSL_FUNCTION`] of
/// [`FresnelMethod::WGSL`], which reads the members [`FresnelMethod::UNIFORM`] of
/// `MaterialParams` (`vec4<f32>`, rgb = red, green, blue) besides the shared `n`, `k` and
/// `f0`. The twin and the WGSL perform the same operations in the same order, which
/// `nklut-gpu`'s tests hold to 1e-5 on a real adapter.
pub trait FresnelMethod: 'static {
    /// The method's per-channel parameters in either precision (`()` where it has none).
    type Params<T: Real>: Copy + Debug + PartialEq + Send + Sync;
    /// The name on the command line and in every table.
    const NAME: &'static str;
    /// The name of its WGSL function, `fn <name>(c: f32, p: MaterialParams) -> vec3<f32>`
    /// (a texture method takes the texture and its sampler instead of `p`).
    const WGSL_FUNCTION: &'static str;
    /// The WGSL source of that function. It may call the library's helpers of
    /// `shaders/fresnel.wgsl` (`pow5`, `shader_pow`, `exact_channel`) and read the
    /// constants of the generated module `contracts`.
    const WGSL: &'static str;
    /// Whether F comes from a texture (then [`FresnelMethod::reflectance`] is `None` and
    /// the GPU binds the material's texture): `lut`.
    const READS_TEXTURE: bool = false;
    /// The members this method adds to `MaterialParams`, one per parameter, in the order of
    /// [`FresnelMethod::members`] (at most [`MAX_UNIFORM_MEMBERS`]).
    const UNIFORM: &'static [&'static str];

    /// The parameters of `channel`, fitted or derived from its index and exact terms.
    fn fit(channel: &Channel) -> Self::Params<f64>;

    /// The parameters as the values of [`FresnelMethod::UNIFORM`], written into the
    /// front of `out` (as long as `UNIFORM`).
    fn members<T: Real>(params: &Self::Params<T>, out: &mut [T]);

    /// The parameters from the values of [`FresnelMethod::UNIFORM`] (as long as it).
    fn from_members<T: Real>(members: &[T]) -> Self::Params<T>;

    /// F at cosθ in f64; `None` for a method that reads a texture (`lut`). Mark it
    /// `#[inline]`: it is called from other crates' loops, which cannot inline a
    /// non-generic function of this crate otherwise (without it `schlick` cost 2.2× in
    /// `cargo bench --bench fresnel`).
    fn reflectance(channel: &Channel, params: &Self::Params<f64>, cos_theta: f64) -> Option<f64>;

    /// F at cosθ in the shader's f32 arithmetic; `None` for a texture method. `#[inline]`
    /// as [`FresnelMethod::reflectance`].
    fn reflectance_f32(channel: &ShaderChannel, params: &Self::Params<f32>, cos_theta: f32) -> Option<f32>;

    /// Cosines where F(θ) has a kink or changes on a scale much finer than [0, π/2]
    /// (the error integrator splits its interval there); none by default.
    fn kinks(_channel: &Channel, _params: &Self::Params<f64>) -> Vec<f64> {
        Vec::new()
    }

    /// The f64 parameters rounded once to f32, member by member (as the uniform carries
    /// them).
    fn rounded(params: &Self::Params<f64>) -> Self::Params<f32> {
        let mut wide = [0.0f64; MAX_UNIFORM_MEMBERS];
        Self::members(params, &mut wide);
        Self::from_members(&wide.map(|v| v as f32)[..Self::UNIFORM.len()])
    }
}

/// Checks, at build time, what a method's constants promise: a name, a WGSL function,
/// at most [`MAX_UNIFORM_MEMBERS`] members. `methods!` calls it for every method.
pub(crate) const fn check<M: FresnelMethod>() {
    assert!(!M::NAME.is_empty(), "a Fresnel method needs a name");
    assert!(!M::WGSL_FUNCTION.is_empty(), "a Fresnel method needs a WGSL function");
    assert!(M::UNIFORM.len() <= MAX_UNIFORM_MEMBERS, "a Fresnel method adds at most MAX_UNIFORM_MEMBERS uniform members");
}

//! Fresnel reflectance methods (SPEC §5). Every method maps (n, k, cosθ) to F for one
//! colour channel, outside medium air (a medium of index n₁ ≠ 1 uses n₂/n₁).
//!
//! Each method is one unit ([`FresnelMethod`], a file under `fresnel/methods/` and a line in
//! the list of `fresnel/methods/mod.rs`): its parameters and their fit, its body in f64 for
//! the CPU (the study's figures) and in f32 with the operation order of its WGSL twin, so
//! GPU-precision error can be measured separately (docs/precision.md), and its WGSL
//! function with the uniform members it reads. The closed forms are written once over
//! [`Real`]; `exact` has its own f32 body ([`exact_f32`]) because the f64 one precomputes
//! angle-independent terms and guards overflow with `hypot`, which the shader does not.
//! Parameters that do not depend on the angle are fitted once per material and channel,
//! when a method is first asked for ([`Prepared`]); a [`Model`] adds the texture of the
//! `lut` method and evaluates any [`Method`].
//!
//! Public entry points for other stages:
//! - [`exact`], [`exact_f32`] and the closed forms in [`approx`], generic over [`Real`];
//! - [`Prepared::new`] and [`Prepared::params`] (e.g. the compensated λ with its
//!   [`CompensationFallback`], the nvidia fit), [`FitMemo`] (the nvidia fits kept between
//!   commands), [`ShaderParams`] (the f32 uniforms a shader needs);
//! - for textures: [`Encoding`] (`quantise`, `encode`, `decode`),
//!   [`sample_lut`], [`Lut::bake`].

pub mod approx;
mod exact;
pub mod lut;
pub mod memo;
pub mod method;
pub mod methods;
pub mod nvidia;
pub mod real;
pub mod reference;

pub use approx::{
    compensation, f82_colours, f82_tint, lazanyi, lazanyi_a, schlick, schlick_compensated, schlick_f0, schlick_nk, Compensation,
    CompensationFallback, F82Colours, COMPENSATION_COS, LAZANYI_COS,
};
pub use exact::{exact, exact_f32, ExactTerms, LANES};
pub use lut::{filter, filter_weights, sample_lut, texel_values, Encoding, Filter, Lut, LutSpec, LUT_SIZES};
pub use memo::FitMemo;
pub use method::{Channel, FresnelMethod, ShaderChannel};
pub use methods::{Method, Stored, METHOD_UNIFORM_MEMBERS};
pub use nvidia::{fit_nvidia, nvidia, NvidiaFit};
pub use real::Real;

use methods::{AllParams, LazyParams, Resolved};

use crate::spectrum::Index;

impl Method {
    /// The method of [`Method::name`] `name`.
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The arithmetic a method is evaluated in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Precision {
    /// f64 on the CPU.
    F64,
    /// f32 with the shader's operation order.
    F32,
}

impl Precision {
    /// Both precisions, f64 first.
    pub const ALL: [Precision; 2] = [Precision::F64, Precision::F32];

    /// The name in tables: `f64` or `f32`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        }
    }
}

/// One value per [`Precision`]: a method's figure in f64 and in its f32 shader twin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PerPrecision<T> {
    /// The f64 figure.
    pub f64: T,
    /// The f32 figure.
    pub f32: T,
}

impl<T: Copy> PerPrecision<T> {
    /// The same value in both precisions.
    pub fn splat(value: T) -> Self {
        Self { f64: value, f32: value }
    }

    /// `value` of each precision.
    pub fn from_fn(mut value: impl FnMut(Precision) -> T) -> Self {
        Self { f64: value(Precision::F64), f32: value(Precision::F32) }
    }
}

impl<T> std::ops::Index<Precision> for PerPrecision<T> {
    type Output = T;

    fn index(&self, precision: Precision) -> &T {
        match precision {
            Precision::F64 => &self.f64,
            Precision::F32 => &self.f32,
        }
    }
}

impl<T> std::ops::IndexMut<Precision> for PerPrecision<T> {
    fn index_mut(&mut self, precision: Precision) -> &mut T {
        match precision {
            Precision::F64 => &mut self.f64,
            Precision::F32 => &mut self.f32,
        }
    }
}

/// Bad input never panics and never yields NaN: NaN n reads as 1 and NaN k as 0 (no
/// interface), negative values as 0, and n, k are capped at 1e150 (beyond which every
/// method is F = 1 to double precision anyway).
pub fn sanitise(index: Index) -> Index {
    const CAP: f64 = 1e150;
    let n = if index.n.is_nan() { 1.0 } else { index.n.clamp(0.0, CAP) };
    let k = if index.k.is_nan() { 0.0 } else { index.k.clamp(0.0, CAP) };
    Index::new(n, k)
}

/// cosθ clamped to [0, 1]; NaN reads as 0 (grazing). In f32 a shader's
/// `clamp(c, 0.0, 1.0)`.
#[inline]
pub fn unit_cos<T: Real>(cos_theta: T) -> T {
    if cos_theta >= T::ZERO {
        cos_theta.min(T::ONE)
    } else {
        T::ZERO
    }
}

/// One channel ready for every method (SPEC §5): the sanitised index, F0 and the exact
/// terms computed at once (read through [`Channel`]: `prepared.index`, `prepared.f0`,
/// `prepared.exact`), each method's parameters fitted the first time it is asked for and
/// kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Prepared {
    channel: Channel,
    /// n, k and F0 rounded to f32.
    shader: ShaderChannel,
    fits: LazyParams,
}

impl std::ops::Deref for Prepared {
    type Target = Channel;

    fn deref(&self) -> &Channel {
        &self.channel
    }
}

impl Prepared {
    /// The channel of `index` (sanitised first); no method is fitted yet.
    pub fn new(index: Index) -> Self {
        let index = sanitise(index);
        let channel = Channel { index, f0: schlick_f0(index.n, index.k), exact: ExactTerms::new(index) };
        Self { channel, shader: ShaderChannel::of(&channel), fits: LazyParams::default() }
    }

    /// This one with the parameters of `M` given (a fit made before, e.g. by a
    /// [`FitMemo`]) instead of fitted on first use; ignored where `M` was fitted already.
    pub fn with_params<M: Stored>(self, params: M::Params<f64>) -> Self {
        let _ = M::cell(&self.fits).set(params);
        self
    }

    /// What every method shares.
    pub fn channel(&self) -> &Channel {
        &self.channel
    }

    /// The parameters of the method `M`, fitted now if they were not yet.
    pub fn params<M: Stored>(&self) -> &M::Params<f64> {
        self.fits.get::<M>(&self.channel)
    }

    /// F of an analytic method at cosθ; `None` for [`Method::Lut`] (use a [`Model`]).
    #[inline]
    pub fn analytic(&self, method: Method, cos_theta: f64) -> Option<f64> {
        self.fits.reflectance(method, &self.channel, cos_theta)
    }

    /// The same in the shader's f32 arithmetic, with the parameters rounded once to f32.
    pub fn analytic_f32(&self, method: Method, cos_theta: f32) -> Option<f32> {
        self.resolved(method).reflectance_f32(&self.shader, cos_theta)
    }

    /// `method`'s parameters in both precisions, fitted now if they were not yet.
    fn resolved(&self, method: Method) -> Resolved {
        Resolved::of(method, &self.fits, &self.channel)
    }

    /// Cosines where `method`'s F(θ) has kinks or fine structure (see
    /// [`FresnelMethod::kinks`]).
    pub fn kinks(&self, method: Method) -> Vec<f64> {
        self.fits.kinks(method, &self.channel)
    }

    /// The f32 uniforms of a shader for this channel (every method fitted).
    pub fn shader_params(&self) -> ShaderParams {
        ShaderParams { channel: self.shader, methods: self.fits.all_rounded(&self.channel) }
    }
}

/// The per-channel f32 parameters a shader receives, every method's (computed in f64 on
/// the CPU, then rounded once). A compensated fallback is weight 0 (no correction term).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaderParams {
    channel: ShaderChannel,
    methods: AllParams,
}

impl ShaderParams {
    /// n, k and F0.
    pub fn channel(&self) -> ShaderChannel {
        self.channel
    }

    /// Every method's uniform members in the order of [`Method::ALL`] and of each method's
    /// [`Method::uniform`] ([`METHOD_UNIFORM_MEMBERS`] values).
    pub fn members(&self) -> Vec<f32> {
        self.methods.members()
    }

    /// The parameters a shader reads: n, k, F0 and the members of [`ShaderParams::members`]
    /// (`None` unless there are [`METHOD_UNIFORM_MEMBERS`] of them).
    pub fn from_members(channel: ShaderChannel, members: &[f32]) -> Option<Self> {
        (members.len() == METHOD_UNIFORM_MEMBERS).then(|| Self { channel, methods: AllParams::from_members(members) })
    }

    /// F of an analytic method at cosθ in shader arithmetic; `None` for [`Method::Lut`].
    #[inline]
    pub fn analytic(&self, method: Method, cos_theta: f32) -> Option<f32> {
        self.methods.reflectance_f32(method, &self.channel, cos_theta)
    }
}

/// One method ready to evaluate for one channel: the prepared parameters plus, for
/// `lut`, the texture baked from `exact` with the given [`LutSpec`]. Built only by its
/// constructors, so a `lut` model always has its texture and no other has one.
#[derive(Clone, Debug)]
pub struct Model {
    method: Method,
    prepared: Prepared,
    /// The method's parameters in both precisions (fitted when the model is made).
    resolved: Resolved,
    /// Some exactly when `method` is [`Method::Lut`].
    lut: Option<Lut>,
}

impl Model {
    /// `lut` is used only when `method` is [`Method::Lut`].
    pub fn new(index: Index, method: Method, lut: LutSpec) -> Self {
        Self::from_prepared(Prepared::new(index), method, lut)
    }

    /// [`Model::new`] from parameters prepared before (`lut` baked only for [`Method::Lut`]).
    pub fn from_prepared(prepared: Prepared, method: Method, lut: LutSpec) -> Self {
        let lut = (method == Method::Lut).then(|| Lut::bake(lut, |c| prepared.exact.reflectance(c)));
        Self { method, resolved: prepared.resolved(method), prepared, lut }
    }

    /// `lut` with a texture baked elsewhere (e.g. one curve quantised per encoding).
    pub fn with_lut(prepared: Prepared, lut: Lut) -> Self {
        Self { method: Method::Lut, resolved: prepared.resolved(Method::Lut), prepared, lut: Some(lut) }
    }

    /// The method evaluated.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The channel's parameters.
    pub fn prepared(&self) -> &Prepared {
        &self.prepared
    }

    /// The texture of a `lut` model (`None` for every analytic method).
    pub fn lut(&self) -> Option<&Lut> {
        self.lut.as_ref()
    }

    /// F in f64.
    #[inline]
    pub fn reflectance(&self, cos_theta: f64) -> f64 {
        match &self.lut {
            Some(lut) => lut.sample(cos_theta),
            // An analytic method (a `lut` model always has its texture).
            None => self.resolved.reflectance(&self.prepared.channel, cos_theta).unwrap_or(0.0),
        }
    }

    /// F in shader f32 arithmetic.
    #[inline]
    pub fn reflectance_f32(&self, cos_theta: f32) -> f32 {
        match &self.lut {
            Some(lut) => lut.sample_f32(cos_theta),
            None => self.resolved.reflectance_f32(&self.prepared.shader, cos_theta).unwrap_or(0.0),
        }
    }
}

#[cfg(test)]
mod tests;

//! Fresnel reflectance methods (SPEC §5). Every method maps (n, k, cosθ) to F for one
//! colour channel, outside medium air (a medium of index n₁ ≠ 1 uses n₂/n₁).
//!
//! Each method is evaluated twice: in f64 for the CPU (the study's figures) and in f32 with
//! the operation order a WGSL shader uses, so GPU-precision error can be measured
//! separately (docs/precision.md). The closed forms are written once over [`Real`];
//! `exact` has its own f32 body ([`exact_f32`]) because the f64 one precomputes
//! angle-independent terms and guards overflow with `hypot`, which the shader does not. Parameters that do not depend on the angle are
//! computed once per material and channel ([`Prepared`]); a [`Model`] adds the texture
//! of the `lut` method and evaluates any [`Method`].
//!
//! Public entry points for other stages:
//! - [`exact`], [`exact_f32`] and the closed forms in [`approx`], generic over [`Real`];
//! - [`Prepared::new`] (F0, compensated λ with its [`CompensationFallback`], Lazányi a,
//!   the nvidia fit), [`FitMemo`] (the nvidia fits kept between commands),
//!   [`ShaderParams`] (the f32 uniforms a shader needs);
//! - for textures: [`Encoding`] (`quantise`, `encode`, `decode`),
//!   [`sample_lut`], [`Lut::bake`].

pub mod approx;
mod exact;
pub mod lut;
pub mod memo;
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
pub use nvidia::{fit_nvidia, nvidia, NvidiaFit};
pub use real::Real;

use crate::spectrum::Index;

/// The Fresnel methods of SPEC §5, in the order of the spec.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// The exact Fresnel reflectance of unpolarised light (SPEC §5.1).
    Exact,
    /// Schlick's F0 + (1 − F0)(1 − c)⁵ with F0 from (n, k) (SPEC §5.2).
    Schlick,
    /// Schlick's form written with n and k instead of F0 (SPEC §5.3).
    SchlickNk,
    /// `schlick_nk` less 2n (1 − c)^λ, λ fitted per channel (SPEC §5.4).
    SchlickCompensated,
    /// Lazányi and Szirmay-Kalos' F82 form, exact at c = 1/7 (SPEC §5.5).
    Lazanyi,
    /// bias + scale (1 − c)^power, fitted per channel (SPEC §5.6).
    Nvidia,
    /// A lookup texture of `exact`, sampled with linear filtering (SPEC §5.7).
    Lut,
    /// The F82-tint metal Fresnel of OpenPBR, Adobe and Blender (SPEC §5.8).
    F82Tint,
}

impl Method {
    /// Every method, in the order of the spec and of every table. [`Method::index`] holds
    /// the list complete: a method left out of it fails the build.
    pub const ALL: [Method; 8] = [
        Method::Exact,
        Method::Schlick,
        Method::SchlickNk,
        Method::SchlickCompensated,
        Method::Lazanyi,
        Method::Nvidia,
        Method::Lut,
        Method::F82Tint,
    ];

    /// The method's position in [`Method::ALL`]. One arm per method, no wildcard, each a
    /// constant evaluated when the crate is built: a method added to the enum does not
    /// compile until it has an arm here, and its arm does not compile until the method is
    /// in `ALL` (write the new arm as the others: `const { Method::position(Method::New) }`).
    pub const fn index(self) -> usize {
        match self {
            Method::Exact => const { Method::position(Method::Exact) },
            Method::Schlick => const { Method::position(Method::Schlick) },
            Method::SchlickNk => const { Method::position(Method::SchlickNk) },
            Method::SchlickCompensated => const { Method::position(Method::SchlickCompensated) },
            Method::Lazanyi => const { Method::position(Method::Lazanyi) },
            Method::Nvidia => const { Method::position(Method::Nvidia) },
            Method::Lut => const { Method::position(Method::Lut) },
            Method::F82Tint => const { Method::position(Method::F82Tint) },
        }
    }

    /// Where `method` is in [`Method::ALL`]; evaluated at build time by [`Method::index`],
    /// where a method missing from the list is a compile error.
    const fn position(method: Method) -> usize {
        let mut i = 0;
        while i < Method::ALL.len() {
            if Method::ALL[i] as u8 == method as u8 {
                return i;
            }
            i += 1;
        }
        panic!("a Method is missing from Method::ALL")
    }

    /// The name used on the command line and in every table.
    pub fn name(self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::Schlick => "schlick",
            Method::SchlickNk => "schlick_nk",
            Method::SchlickCompensated => "schlick_compensated",
            Method::Lazanyi => "lazanyi",
            Method::Nvidia => "nvidia",
            Method::Lut => "lut",
            Method::F82Tint => "f82_tint",
        }
    }

    /// The method of [`Method::name`] `name`.
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

// Each method is in `Method::ALL` once: its entry is at its own index.
const _: () = {
    let mut i = 0;
    while i < Method::ALL.len() {
        assert!(Method::ALL[i].index() == i, "Method::ALL lists a method twice");
        i += 1;
    }
};

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

/// Everything the analytic methods need for one channel, computed once: SPEC §5.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prepared {
    /// The sanitised index (see [`sanitise`]).
    pub index: Index,
    /// Normal-incidence reflectance F0 = ((n − 1)² + k²)/((n + 1)² + k²) (SPEC §5.2).
    pub f0: f64,
    /// Angle-independent terms of `exact`.
    pub exact: ExactTerms,
    /// λ of `schlick_compensated` and whether it fell back (SPEC §5.4).
    pub compensation: Compensation,
    /// a of `lazanyi` (SPEC §5.5).
    pub lazanyi_a: f64,
    /// bias, scale, power of `nvidia` (SPEC §5.6).
    pub nvidia: NvidiaFit,
    /// The authored colours of `f82_tint` (SPEC §5.8).
    pub f82: F82Colours,
}

impl Prepared {
    /// The parameters of `index` (sanitised first), the `nvidia` fit made here.
    pub fn new(index: Index) -> Self {
        Self::with_nvidia_fit(index, fit_nvidia)
    }

    /// [`Prepared::new`] with the `nvidia` fit from `fit` (given the exact terms of the
    /// sanitised index): [`fit_nvidia`], or a fit it made before ([`FitMemo`]).
    pub fn with_nvidia_fit(index: Index, fit: impl FnOnce(&ExactTerms) -> NvidiaFit) -> Self {
        let index = sanitise(index);
        let exact = ExactTerms::new(index);
        Self {
            index,
            f0: schlick_f0(index.n, index.k),
            exact,
            compensation: compensation(index, &exact),
            lazanyi_a: lazanyi_a(index, &exact),
            nvidia: fit(&exact),
            f82: f82_colours(index, &exact),
        }
    }

    /// F of an analytic method at cosθ; `None` for [`Method::Lut`] (use a [`Model`]).
    #[inline]
    pub fn analytic(&self, method: Method, cos_theta: f64) -> Option<f64> {
        let Index { n, k } = self.index;
        Some(match method {
            Method::Exact => self.exact.reflectance(cos_theta),
            Method::Schlick => schlick(self.f0, cos_theta),
            Method::SchlickNk => schlick_nk(n, k, cos_theta),
            Method::SchlickCompensated => schlick_compensated(n, k, self.compensation.weight, self.compensation.lambda, cos_theta),
            Method::Lazanyi => lazanyi(self.f0, self.lazanyi_a, cos_theta),
            Method::Nvidia => nvidia(self.nvidia.bias, self.nvidia.scale, self.nvidia.power, cos_theta),
            Method::Lut => return None,
            Method::F82Tint => f82_tint(self.f82.f0, self.f82.tint, cos_theta),
        })
    }

    /// The f32 uniforms of a shader for this channel.
    pub fn shader_params(&self) -> ShaderParams {
        ShaderParams {
            n: self.index.n as f32,
            k: self.index.k as f32,
            f0: self.f0 as f32,
            compensation_weight: self.compensation.weight as f32,
            compensation_lambda: self.compensation.lambda as f32,
            lazanyi_a: self.lazanyi_a as f32,
            nvidia_bias: self.nvidia.bias as f32,
            nvidia_scale: self.nvidia.scale as f32,
            nvidia_power: self.nvidia.power as f32,
            f82_f0: self.f82.f0 as f32,
            f82_tint: self.f82.tint as f32,
        }
    }
}

/// The per-channel f32 parameters a shader receives (computed in f64 on the CPU, then
/// rounded once). A compensated fallback is encoded as weight 0 (no correction term).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShaderParams {
    /// n.
    pub n: f32,
    /// k.
    pub k: f32,
    /// F0 = ((n − 1)² + k²)/((n + 1)² + k²).
    pub f0: f32,
    /// 2n in front of (1 − c)^λ of `schlick_compensated`; 0 on its fallback.
    pub compensation_weight: f32,
    /// λ of `schlick_compensated`.
    pub compensation_lambda: f32,
    /// a of `lazanyi`.
    pub lazanyi_a: f32,
    /// bias of `nvidia`.
    pub nvidia_bias: f32,
    /// scale of `nvidia`.
    pub nvidia_scale: f32,
    /// power of `nvidia`.
    pub nvidia_power: f32,
    /// The authored F0 and tint of `f82_tint` (linear).
    pub f82_f0: f32,
    /// The tint of `f82_tint` (linear).
    pub f82_tint: f32,
}

impl ShaderParams {
    /// F of an analytic method at cosθ in shader arithmetic; `None` for [`Method::Lut`].
    #[inline]
    pub fn analytic(&self, method: Method, cos_theta: f32) -> Option<f32> {
        Some(match method {
            Method::Exact => exact_f32(self.n, self.k, cos_theta),
            Method::Schlick => schlick(self.f0, cos_theta),
            Method::SchlickNk => schlick_nk(self.n, self.k, cos_theta),
            Method::SchlickCompensated => {
                schlick_compensated(self.n, self.k, self.compensation_weight, self.compensation_lambda, cos_theta)
            }
            Method::Lazanyi => lazanyi(self.f0, self.lazanyi_a, cos_theta),
            Method::Nvidia => nvidia(self.nvidia_bias, self.nvidia_scale, self.nvidia_power, cos_theta),
            Method::Lut => return None,
            Method::F82Tint => f82_tint(self.f82_f0, self.f82_tint, cos_theta),
        })
    }
}

/// One method ready to evaluate for one channel: the prepared parameters plus, for
/// `lut`, the texture baked from `exact` with the given [`LutSpec`]. Built only by its
/// constructors, so a `lut` model always has its texture and no other has one.
#[derive(Clone, Debug)]
pub struct Model {
    method: Method,
    prepared: Prepared,
    shader: ShaderParams,
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
        Self { method, shader: prepared.shader_params(), prepared, lut }
    }

    /// `lut` with a texture baked elsewhere (e.g. one curve quantised per encoding).
    pub fn with_lut(prepared: Prepared, lut: Lut) -> Self {
        Self { method: Method::Lut, shader: prepared.shader_params(), prepared, lut: Some(lut) }
    }

    /// The method evaluated.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The channel's parameters in f64.
    pub fn prepared(&self) -> &Prepared {
        &self.prepared
    }

    /// The same rounded to f32, as a shader receives them.
    pub fn shader(&self) -> &ShaderParams {
        &self.shader
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
            None => self.prepared.analytic(self.method, cos_theta).unwrap_or(0.0),
        }
    }

    /// F in shader f32 arithmetic.
    #[inline]
    pub fn reflectance_f32(&self, cos_theta: f32) -> f32 {
        match &self.lut {
            Some(lut) => lut.sample_f32(cos_theta),
            None => self.shader.analytic(self.method, cos_theta).unwrap_or(0.0),
        }
    }
}

#[cfg(test)]
mod tests;

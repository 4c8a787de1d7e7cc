//! The list of Fresnel methods (SPEC §5): one line per method, naming the file under
//! `fresnel/methods/` and the type in it that implements [`FresnelMethod`]. Everything
//! that enumerates the methods is made from this list by `methods!`: the [`Method`] enum
//! and [`Method::ALL`] (complete by construction, in the order of the list, which is the
//! order of every table), the names, the WGSL functions and uniform members, the lazily
//! fitted parameters of [`super::Prepared`] and the f32 parameters of
//! [`super::ShaderParams`]. A method is added by its file and its line here
//! (docs/extending.md).

use std::sync::OnceLock;

use super::method::{check, Channel, FresnelMethod, ShaderChannel, MAX_UNIFORM_MEMBERS};

/// Makes the enum and the per-method storage from the list of `module::Type` lines.
macro_rules! methods {
    ($($module:ident :: $unit:ident),+ $(,)?) => {
        $(pub mod $module;)+

        /// The Fresnel methods of SPEC §5, in the order of the list in `fresnel/methods/mod.rs`
        /// (the order of every table). Each variant is the unit of the same name: see
        /// its type for the formula and its source.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Method {
            $(
                #[doc = concat!("[`", stringify!($module), "::", stringify!($unit), "`].")]
                $unit,
            )+
        }

        impl Method {
            /// Every method, in the order of the list.
            pub const ALL: [Method; [$(Method::$unit),+].len()] = [$(Method::$unit),+];

            /// The method's position in [`Method::ALL`].
            pub const fn index(self) -> usize {
                self as usize
            }

            /// The name used on the command line and in every table.
            pub const fn name(self) -> &'static str {
                match self {
                    $(Method::$unit => <$module::$unit as FresnelMethod>::NAME,)+
                }
            }

            /// The name of the method's WGSL function.
            pub const fn wgsl_function(self) -> &'static str {
                match self {
                    $(Method::$unit => <$module::$unit as FresnelMethod>::WGSL_FUNCTION,)+
                }
            }

            /// The WGSL source of that function.
            pub const fn wgsl(self) -> &'static str {
                match self {
                    $(Method::$unit => <$module::$unit as FresnelMethod>::WGSL,)+
                }
            }

            /// Whether F comes from a texture (`lut`): no closed form to evaluate.
            pub const fn reads_texture(self) -> bool {
                match self {
                    $(Method::$unit => <$module::$unit as FresnelMethod>::READS_TEXTURE,)+
                }
            }

            /// The members the method adds to the shader's `MaterialParams`.
            pub const fn uniform(self) -> &'static [&'static str] {
                match self {
                    $(Method::$unit => <$module::$unit as FresnelMethod>::UNIFORM,)+
                }
            }
        }

        // Every method's constants keep their promises, and its name is its own.
        const _: () = {
            $(check::<$module::$unit>();)+
            let mut i = 0;
            while i < Method::ALL.len() {
                let mut j = 0;
                while j < i {
                    assert!(!const_eq(Method::ALL[i].name(), Method::ALL[j].name()), "two Fresnel methods share a name");
                    j += 1;
                }
                i += 1;
            }
        };

        /// Every method's parameters of one channel, each fitted when first asked for.
        #[doc(hidden)]
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct LazyParams {
            $($module: OnceLock<<$module::$unit as FresnelMethod>::Params<f64>>,)+
        }

        /// Every method's parameters of one channel in f32, as the uniform carries them.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub(crate) struct AllParams {
            $($module: <$module::$unit as FresnelMethod>::Params<f32>,)+
        }

        /// A method of the list, whose parameters a [`super::Prepared`] keeps.
        pub trait Stored: FresnelMethod {
            /// Where they are kept.
            #[doc(hidden)]
            fn cell(params: &LazyParams) -> &OnceLock<Self::Params<f64>>;
        }

        $(
            impl Stored for $module::$unit {
                fn cell(params: &LazyParams) -> &OnceLock<Self::Params<f64>> {
                    &params.$module
                }
            }
        )+

        impl LazyParams {
            /// The parameters of `M` for `channel`, fitted now if they were not yet.
            pub(crate) fn get<M: Stored>(&self, channel: &Channel) -> &M::Params<f64> {
                M::cell(self).get_or_init(|| M::fit(channel))
            }

            /// F of `method` in f64, its parameters fitted on first use.
            pub(crate) fn reflectance(&self, method: Method, channel: &Channel, cos_theta: f64) -> Option<f64> {
                match method {
                    $(Method::$unit => <$module::$unit>::reflectance(channel, self.get::<$module::$unit>(channel), cos_theta),)+
                }
            }

            /// The kinks of `method`'s error integrand.
            pub(crate) fn kinks(&self, method: Method, channel: &Channel) -> Vec<f64> {
                match method {
                    $(Method::$unit => <$module::$unit>::kinks(channel, self.get::<$module::$unit>(channel)),)+
                }
            }

            /// Every method's parameters rounded to f32 (every fit made).
            pub(crate) fn all_rounded(&self, channel: &Channel) -> AllParams {
                AllParams {
                    $($module: <$module::$unit>::rounded(self.get::<$module::$unit>(channel)),)+
                }
            }
        }

        /// One method's parameters in both precisions, resolved once for a
        /// [`super::Model`], so that its evaluations dispatch on the method alone.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub(crate) enum Resolved {
            $($unit(<$module::$unit as FresnelMethod>::Params<f64>, <$module::$unit as FresnelMethod>::Params<f32>),)+
        }

        impl Resolved {
            /// `method`'s parameters from `fits` (fitted now if they were not yet) and their
            /// rounding to f32.
            pub(crate) fn of(method: Method, fits: &LazyParams, channel: &Channel) -> Self {
                match method {
                    $(Method::$unit => {
                        let params = *fits.get::<$module::$unit>(channel);
                        Resolved::$unit(params, <$module::$unit>::rounded(&params))
                    })+
                }
            }

            /// F in f64.
            #[inline]
            pub(crate) fn reflectance(&self, channel: &Channel, cos_theta: f64) -> Option<f64> {
                match self {
                    $(Resolved::$unit(params, _) => <$module::$unit>::reflectance(channel, params, cos_theta),)+
                }
            }

            /// F in f32.
            #[inline]
            pub(crate) fn reflectance_f32(&self, shader: &ShaderChannel, cos_theta: f32) -> Option<f32> {
                match self {
                    $(Resolved::$unit(_, params) => <$module::$unit>::reflectance_f32(shader, params, cos_theta),)+
                }
            }
        }

        impl AllParams {
            /// F of `method` in f32.
            pub(crate) fn reflectance_f32(&self, method: Method, shader: &ShaderChannel, cos_theta: f32) -> Option<f32> {
                match method {
                    $(Method::$unit => <$module::$unit>::reflectance_f32(shader, &self.$module, cos_theta),)+
                }
            }

            /// The uniform members of every method, in the order of the list.
            pub(crate) fn members(&self) -> Vec<f32> {
                let mut out = Vec::new();
                $(
                    let mut values = [0.0f32; MAX_UNIFORM_MEMBERS];
                    <$module::$unit>::members(&self.$module, &mut values);
                    out.extend_from_slice(&values[..<$module::$unit as FresnelMethod>::UNIFORM.len()]);
                )+
                out
            }

            /// The parameters from the uniform members of every method ([`AllParams::members`]).
            pub(crate) fn from_members(members: &[f32]) -> Self {
                let mut at = 0;
                $(
                    let count = <$module::$unit as FresnelMethod>::UNIFORM.len();
                    let $module = <$module::$unit>::from_members(&members[at..at + count]);
                    at += count;
                )+
                debug_assert_eq!(at, members.len());
                AllParams { $($module,)+ }
            }
        }
    };
}

/// `a == b` in a constant.
const fn const_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

methods! {
    exact::Exact,
    schlick::Schlick,
    schlick_nk::SchlickNk,
    schlick_compensated::SchlickCompensated,
    lazanyi::Lazanyi,
    nvidia::Nvidia,
    lut::Lut,
    f82_tint::F82Tint,
    schlick_fitted::SchlickFitted,
}

/// The number of uniform members every method adds together.
pub const METHOD_UNIFORM_MEMBERS: usize = {
    let mut count = 0;
    let mut i = 0;
    while i < Method::ALL.len() {
        count += Method::ALL[i].uniform().len();
        i += 1;
    }
    count
};

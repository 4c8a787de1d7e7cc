//! Colour science for the reference colours (SPEC §4): the embedded CIE tables, XYZ →
//! linear sRGB and the sRGB encoding (IEC 61966-2-1), CIELAB and CIEDE2000 (Sharma et
//! al. 2005), the spectral reference colour of a page, the index-approximation error of
//! the three-wavelength channels, and effective channel indices fitted over angle.
//!
//! For the bake: [`sample_spectrum`] once per page, then [`spectral_curve`] at the texel
//! centres [`crate::encoding::texel_cosines`] (or [`reflectance_rgb`] at one cosθ).

pub mod acescg;
pub mod angle_average;
pub mod cie;
pub mod fit;
pub mod lab;
pub mod memo;
pub mod page;
pub mod spectral;
pub mod srgb;

pub use angle_average::{angle_quadrature, AngleQuadrature};
pub use fit::{fit_effective_index, fit_effective_index_from, mean_relative_error, EffectiveIndex};
pub use lab::{delta_e2000, xyz_to_lab, Lab};
pub use memo::{CurveMemo, EffectiveMemo, Fingerprint};
pub use page::{page_colors, relative_error, spectral_reference, PageColors, SpectralReference};
pub use spectral::{
    reflectance_rgb, reflectance_spectrum_rgb, sample_spectrum, spectral_curve, spectral_weights, PreparedSpectrum, SpectralWeights,
};

//! Per-page colour figures: the spectral reference (SPEC §4), the index-approximation
//! error of the three-wavelength shortcut, and the effective channel indices.

use super::angle_average::AngleQuadrature;
use super::fit::{mean_relative_error, EffectiveIndex};
use super::lab::delta_e2000;
use super::memo::{CurveMemo, EffectiveMemo, Fingerprint};
use super::spectral::{sample_spectrum, spectral_weights, PreparedSpectrum};
use crate::fresnel;
use crate::spectrum::{Index, Material};

/// The spectral reference of one material, sampled where the figures need it.
#[derive(Clone, Debug)]
pub struct SpectralReference {
    /// n, k on the 1 nm grid 360–830 nm (held outside the data).
    pub spectrum: Vec<Index>,
    /// Share of Σ S ȳ outside the data's wavelength range (a fraction).
    pub extrapolated_share: f64,
    /// Linear sRGB at normal incidence.
    pub f0: [f64; 3],
    /// Linear sRGB at the quadrature nodes.
    pub at_nodes: Vec<[f64; 3]>,
    /// Linear sRGB at the LUT texel centres (empty when no texels were asked for).
    pub at_texels: Vec<[f64; 3]>,
}

/// Sample the spectrum of `material` and its reference colour at normal incidence, at
/// the quadrature nodes and at `texel_cosines`: computed, or taken from `memo` where it
/// holds them (the curves remembered between the commands of one output folder).
pub fn spectral_reference(
    material: &Material,
    quadrature: &AngleQuadrature,
    texel_cosines: &[f64],
    memo: Option<&CurveMemo>,
) -> SpectralReference {
    let nothing_remembered;
    let memo = match memo {
        Some(memo) => memo,
        None => {
            nothing_remembered = CurveMemo::default();
            &nothing_remembered
        }
    };
    let (spectrum, extrapolated_share) = sample_spectrum(&material.data);
    let prepared = PreparedSpectrum::new(&spectrum);
    let sampled = Fingerprint::of_spectrum(&spectrum);
    SpectralReference {
        f0: prepared.rgb(1.0),
        at_nodes: memo.curve(sampled, &prepared, &quadrature.cosines),
        at_texels: memo.curve(sampled, &prepared, texel_cosines),
        extrapolated_share,
        spectrum,
    }
}

/// Everything `colors.csv` reports for one material.
#[derive(Clone, Debug)]
pub struct PageColors {
    /// Spectral reference at normal incidence, linear sRGB.
    pub f0_spectral: [f64; 3],
    /// Exact Fresnel at normal incidence of the three-wavelength channel indices.
    pub f0_three_channel: [f64; 3],
    /// |three-channel − spectral| / |spectral| at normal incidence, per channel.
    pub index_error_f0: [f64; 3],
    /// The same, averaged over θ uniform in [0°, 90°].
    pub index_error_angle: [f64; 3],
    /// CIEDE2000 between the two normal-incidence colours (CIELAB, D65 white).
    pub delta_e2000_f0: f64,
    /// Fitted per-channel (n, k) and their mean relative error over θ.
    pub effective: [EffectiveIndex; 3],
    /// Whether the reference stays inside [0, 1] at normal incidence and at every
    /// quadrature node — the channels an exact Fresnel curve (≤ 1) can match.
    pub reference_in_unit_range: [bool; 3],
    /// Share of Σ S ȳ outside the data's wavelength range (a fraction).
    pub extrapolated_share: f64,
    /// Spectral F0 outside [0, 1] (kept as is).
    pub out_of_gamut_f0: [bool; 3],
    /// Spectral reference outside [0, 1] anywhere: F0, the quadrature nodes or the texels.
    pub out_of_gamut_angle: [bool; 3],
}

/// The relative error |value − reference| / |reference|; 0 where both are 0, and where
/// only the reference is 0 the absolute error (never NaN or ∞).
pub fn relative_error(value: f64, reference: f64) -> f64 {
    let difference = (value - reference).abs();
    if reference != 0.0 {
        difference / reference.abs()
    } else {
        difference
    }
}

fn outside_unit(value: f64) -> bool {
    !(0.0..=1.0).contains(&value)
}

/// The per-page figures from a material and its spectral reference (the effective fits
/// from `fits` where it holds them).
pub fn page_colors(material: &Material, reference: &SpectralReference, quadrature: &AngleQuadrature, fits: &EffectiveMemo) -> PageColors {
    let channels = material.channels;
    let channel_curve = |c: usize| -> Vec<f64> { reference.at_nodes.iter().map(|rgb| rgb[c]).collect() };
    let f0_three_channel = channels.map(|index| fresnel::exact(index.n, index.k, 1.0));
    let weights = spectral_weights();
    let mut colors = PageColors {
        f0_spectral: reference.f0,
        f0_three_channel,
        index_error_f0: [0, 1, 2].map(|c| relative_error(f0_three_channel[c], reference.f0[c])),
        index_error_angle: [0, 1, 2].map(|c| mean_relative_error(channels[c], &channel_curve(c), quadrature)),
        delta_e2000_f0: delta_e2000(weights.lab(f0_three_channel), weights.lab(reference.f0)),
        effective: [0, 1, 2].map(|c| fits.effective(&channel_curve(c), channels[c], quadrature)),
        reference_in_unit_range: [false; 3],
        extrapolated_share: reference.extrapolated_share,
        out_of_gamut_f0: reference.f0.map(outside_unit),
        out_of_gamut_angle: [false; 3],
    };
    for c in 0..3 {
        let nodes_outside = reference.at_nodes.iter().any(|rgb| outside_unit(rgb[c]));
        let texels_outside = reference.at_texels.iter().any(|rgb| outside_unit(rgb[c]));
        colors.reference_in_unit_range[c] = !nodes_outside && !outside_unit(reference.f0[c]);
        colors.out_of_gamut_angle[c] = nodes_outside || texels_outside || colors.out_of_gamut_f0[c];
    }
    colors
}

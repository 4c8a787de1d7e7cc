//! The per-material curves every figure of a material page draws: F(θ) per channel of
//! the spectral reference (CIE 1931 2°, D65, linear sRGB), of exact Fresnel with the
//! three-channel and the fitted indices, and of each approximation with the
//! three-channel index (the same `fresnel::Model` the validator measures); and the
//! CIEDE2000 of each against the reference at every angle.

use super::charts::{method_color, FITTED_COLOR, REFERENCE_COLOR};
use nklut_optics::color::{self, PreparedSpectrum};
use nklut_optics::fresnel::{self, Encoding, ExactTerms, FitMemo, LutSpec, Method, Model};
use nklut_optics::spectrum::{ChannelIndex, Index};

/// Angles of every curve: 0°, 1°, …, 90°.
pub const THETA_POINTS: usize = 91;

/// θ grid of the curves: `points` angles from 0° to 90°.
pub fn theta_grid(points: usize) -> Vec<f64> {
    (0..points).map(|i| 90.0 * i as f64 / (points - 1) as f64).collect()
}

/// The LUT drawn: the default bake (256 texels, 8-bit sRGB-encoded).
pub const PLOTTED_LUT: LutSpec = LutSpec::new(256, Encoding::Unorm8Srgb);

/// One curve: a name, how it is drawn, and linear-sRGB F at each angle of the grid.
#[derive(Clone, Debug)]
pub struct PlotCurve {
    pub name: String,
    pub color: plotters::style::RGBColor,
    pub dashed: bool,
    /// F (red, green, blue) at each θ of the grid.
    pub rgb: Vec<[f64; 3]>,
}

impl PlotCurve {
    /// F of one channel over the grid.
    pub fn channel(&self, c: usize) -> Vec<f64> {
        self.rgb.iter().map(|v| v[c]).collect()
    }
}

/// Name of the reference curve (always first).
pub const REFERENCE: &str = "spectral reference";
/// Name of exact Fresnel with the fitted indices.
pub const FITTED: &str = "exact, fitted index";

/// Exact and each approximation for `index` (per channel) on the θ grid `theta_deg`.
/// `schlick_nk` equals `schlick` with F0 from (n, k) and is not drawn twice.
/// The `nvidia` fits come from `fits` where it holds them.
pub fn method_curves(index: &ChannelIndex, theta_deg: &[f64], fits: &FitMemo) -> Vec<PlotCurve> {
    let cosines: Vec<f64> = theta_deg.iter().map(|t| t.to_radians().cos()).collect();
    // Each channel's fits (compensation, Lazányi, Nvidia) once, shared by every method.
    let prepared = index.map(|index| fits.prepared(index));
    Method::ALL
        .into_iter()
        .filter(|&m| drawn(m))
        .map(|method| {
            let models = [0, 1, 2].map(|c| Model::from_prepared(prepared[c].clone(), method, PLOTTED_LUT));
            let rgb = cosines.iter().map(|&cos| [0, 1, 2].map(|c| models[c].reflectance(cos))).collect();
            let name = if method == Method::Lut { format!("lut {}", PLOTTED_LUT.name()) } else { method.name().to_string() };
            PlotCurve { name, color: method_color(method), dashed: method != Method::Exact, rgb }
        })
        .collect()
}

/// Whether a method has its own curve: all but `schlick_nk`, which is `schlick` with F0
/// from (n, k), the same curve.
pub fn drawn(method: Method) -> bool {
    method != Method::SchlickNk
}

/// The curves of a material: the spectral reference (from the page's spectrum on the
/// 1 nm grid), exact Fresnel with the fitted indices when fitted, then exact and every
/// approximation with the three-channel indices.
pub fn material_curves(
    spectrum: &[Index],
    three_channel: &ChannelIndex,
    fitted: Option<&ChannelIndex>,
    theta_deg: &[f64],
    fits: &FitMemo,
) -> Vec<PlotCurve> {
    let cosines: Vec<f64> = theta_deg.iter().map(|t| t.to_radians().cos()).collect();
    let mut curves = vec![PlotCurve {
        name: REFERENCE.into(),
        color: REFERENCE_COLOR,
        dashed: false,
        rgb: PreparedSpectrum::new(spectrum).curve(&cosines),
    }];
    if let Some(fitted) = fitted {
        let terms = fitted.map(|i| ExactTerms::new(fresnel::sanitise(i)));
        let rgb = cosines.iter().map(|&cos| [0, 1, 2].map(|c| terms[c].reflectance(cos))).collect();
        curves.push(PlotCurve { name: FITTED.into(), color: FITTED_COLOR, dashed: true, rgb });
    }
    curves.extend(method_curves(three_channel, theta_deg, fits));
    curves
}

/// CIEDE2000 of each of `curves` against `reference` at each angle (CIELAB, D65 white);
/// the reference's Lab is computed once.
pub fn delta_e_over_angle(reference: &PlotCurve, curves: &[PlotCurve]) -> Vec<Vec<f64>> {
    let weights = color::spectral_weights();
    let reference: Vec<color::Lab> = reference.rgb.iter().map(|r| weights.lab(*r)).collect();
    curves.iter().map(|curve| reference.iter().zip(&curve.rgb).map(|(r, c)| color::delta_e2000(*r, weights.lab(*c))).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::spectrum::SPECTRAL_SAMPLES;

    #[test]
    fn a_constant_spectrum_is_white_light_times_exact_fresnel() {
        // D65 through the CIE observer maps to linear sRGB white (1, 1, 1), so the
        // reference colour of a flat spectrum is exact Fresnel of its index in every channel.
        let index = Index::new(1.5, 0.0);
        let theta = theta_grid(10);
        let curves = material_curves(&vec![index; SPECTRAL_SAMPLES], &[index; 3], None, &theta, &FitMemo::default());
        assert_eq!(curves[0].name, REFERENCE);
        assert_eq!(curves[1].name, "exact");
        for (r, e) in curves[0].rgb.iter().zip(&curves[1].rgb) {
            for c in 0..3 {
                assert!((r[c] - e[c]).abs() < 1e-3 * e[c].max(1e-3), "{r:?} vs {e:?}");
            }
        }
        // F0 of n = 1.5 is ((n - 1)/(n + 1))^2 = 0.04.
        assert!((curves[1].rgb[0][0] - 0.04).abs() < 1e-12);
        let de = &delta_e_over_angle(&curves[0], &curves[1..2])[0];
        assert!(de.iter().all(|d| *d < 0.2), "{de:?}");
    }

    /// Every curve of a material page has its own colour: each drawn method of
    /// `Method::ALL`, the spectral reference and the fitted exact curve (a method added
    /// with a colour already taken, e.g. the reference's grey, fails here).
    #[test]
    fn every_drawn_curve_has_its_own_colour() {
        let index = Index::new(0.5, 2.3);
        let curves = material_curves(&vec![index; SPECTRAL_SAMPLES], &[index; 3], Some(&[index; 3]), &theta_grid(4), &FitMemo::default());
        let drawn_methods = Method::ALL.into_iter().filter(|&m| drawn(m)).count();
        assert_eq!(curves.len(), 2 + drawn_methods, "the reference, the fitted curve and every drawn method");
        for (i, a) in curves.iter().enumerate() {
            for b in &curves[..i] {
                assert_ne!(a.color, b.color, "{} and {} share a colour", a.name, b.name);
            }
        }
        // The colours of the curves this crate drew before the palette became one entry
        // per method keep their colour (the reports read the same).
        let okabe_ito = |m: Method| method_color(m);
        assert_eq!(okabe_ito(Method::Schlick), plotters::style::RGBColor(230, 159, 0));
        assert_eq!(okabe_ito(Method::F82Tint), plotters::style::RGBColor(0, 114, 178));
    }
}

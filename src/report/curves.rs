//! The per-material Fresnel curves of the report, computed from the channel indices with
//! the same `fresnel::Model` the validator measures.

use super::charts::{Series, PALETTE};
use crate::fresnel::{Encoding, LutSpec, Method, Model};
use crate::color;
use crate::spectrum::{ChannelIndex, Material};

/// θ grid of the plots: `points` angles from 0° to 90°.
pub fn theta_grid(points: usize) -> Vec<f64> {
    (0..points).map(|i| 90.0 * i as f64 / (points - 1) as f64).collect()
}

/// The LUT drawn in the plots: the default bake (256 texels, 8-bit sRGB-encoded).
pub const PLOTTED_LUT: LutSpec = LutSpec::new(256, Encoding::Unorm8Srgb);

/// Curves per channel of every method for the given indices; the first is `exact`.
/// `schlick_nk` equals `schlick` (SPEC §5.3) and is not drawn twice.
pub fn method_curves(index: &ChannelIndex, points: usize) -> Vec<Series> {
    let cosines: Vec<f64> = theta_grid(points).iter().map(|t| t.to_radians().cos()).collect();
    Method::ALL
        .iter()
        .filter(|m| **m != Method::SchlickNk)
        .enumerate()
        .map(|(i, &method)| {
            let values = [0, 1, 2].map(|c| {
                let model = Model::new(index[c], method, PLOTTED_LUT);
                cosines.iter().map(|&cos| model.reflectance(cos)).collect()
            });
            let name = if method == Method::Lut { format!("lut {}", PLOTTED_LUT.name()) } else { method.name().to_string() };
            Series { name, color: PALETTE[i % PALETTE.len()], dashed: i > 0, values }
        })
        .collect()
}

/// The curves of a material's plot: the spectral reference (SPEC §4), exact Fresnel with
/// the effective indices when fitted, then every method with the three-channel indices.
pub fn material_curves(material: &Material, effective: Option<&ChannelIndex>, points: usize) -> Vec<Series> {
    let cosines: Vec<f64> = theta_grid(points).iter().map(|t| t.to_radians().cos()).collect();
    let spectrum = color::sample_spectrum(&material.data).0;
    let reference = color::spectral_curve(&spectrum, &cosines);
    let mut series = vec![Series {
        name: "spectral reference".into(),
        color: PALETTE[7],
        dashed: false,
        values: [0, 1, 2].map(|c| reference.iter().map(|rgb| rgb[c]).collect()),
    }];
    if let Some(effective) = effective {
        let mut fitted = method_curves(effective, points).remove(0);
        fitted.name = "exact, effective index".into();
        fitted.color = PALETTE[6];
        fitted.dashed = true;
        series.push(fitted);
    }
    series.extend(method_curves(&material.channels, points));
    series
}

//! The per-material Fresnel curves of the report, computed from the channel indices.

use super::charts::{Series, PALETTE};
use crate::fresnel;
use crate::spectrum::ChannelIndex;

/// θ grid of the plots: 0°, 1°, …, 90°.
pub fn theta_grid(points: usize) -> Vec<f64> {
    (0..points).map(|i| 90.0 * i as f64 / (points - 1) as f64).collect()
}

/// Exact curves per channel for the given indices; the first series is always `exact`.
pub fn method_curves(index: &ChannelIndex, points: usize) -> Vec<Series> {
    let cosines: Vec<f64> = theta_grid(points).iter().map(|t| t.to_radians().cos()).collect();
    let channel = |f: &dyn Fn(f64, f64, f64) -> f64| -> [Vec<f64>; 3] {
        [0, 1, 2].map(|c| cosines.iter().map(|&cos| f(index[c].n, index[c].k, cos)).collect())
    };
    vec![Series { name: "exact".into(), color: PALETTE[0], dashed: false, values: channel(&fresnel::exact) }]
}

//! The angle average of SPEC §4/§6: a mean over θ uniform in [0°, 90°], computed with
//! composite Gauss–Legendre quadrature in θ.
//!
//! [0, π/2] is cut into `PANELS` equal panels with `NODES` Gauss–Legendre nodes each. A
//! smooth integrand converges like a degree-(2·NODES − 1) rule per panel; the relative
//! error |F − F_ref|/F_ref has kinks where the sign of F − F_ref changes, which only
//! the panel width resolves, so several narrow panels beat one wide rule. Measured on
//! the `3d` metals' index errors against a 4096-node rule, worst relative deviation:
//! 16 × 8 nodes 1.2·10⁻⁴, 24 × 8 7.1·10⁻⁵, 32 × 8 2.3·10⁻⁵, 16 × 16 2.9·10⁻⁵. The default
//! is 24 × 8 = 192 nodes: four significant digits (tested against 2048 nodes).

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

use crate::memo::Fingerprint;

/// Panels and nodes per panel of the default rule.
pub const PANELS: usize = 24;
/// Gauss–Legendre nodes per panel of the default rule.
pub const NODES: usize = 8;

/// Nodes (as cosθ) and weights (summing to 1) of a mean over θ ∈ [0, π/2].
#[derive(Clone, Debug)]
pub struct AngleQuadrature {
    /// The nodes, as cosθ.
    pub cosines: Vec<f64>,
    /// Their weights, summing to 1.
    pub weights: Vec<f64>,
    /// The nodes' and weights' fingerprint, made when first asked for.
    fingerprint: OnceLock<Fingerprint>,
}

impl AngleQuadrature {
    /// The rule of these nodes and weights.
    pub fn of_nodes(cosines: Vec<f64>, weights: Vec<f64>) -> Self {
        Self { cosines, weights, fingerprint: OnceLock::new() }
    }

    /// The bits of the nodes and weights, as a memo's key of what is computed over the
    /// rule (made once per rule).
    pub fn fingerprint(&self) -> Fingerprint {
        *self.fingerprint.get_or_init(|| Fingerprint::of(self.cosines.iter().chain(&self.weights).copied()))
    }

    /// Composite Gauss–Legendre with `panels` × `nodes` points.
    pub fn new(panels: usize, nodes: usize) -> Self {
        let (points, point_weights) = gauss_legendre(nodes);
        let width = FRAC_PI_2 / panels as f64;
        let mut cosines = Vec::with_capacity(panels * nodes);
        let mut weights = Vec::with_capacity(panels * nodes);
        for panel in 0..panels {
            let middle = (panel as f64 + 0.5) * width;
            for (x, w) in points.iter().zip(&point_weights) {
                cosines.push((middle + 0.5 * width * x).cos());
                // ∫ over the panel = (width/2) Σ w f; the mean divides by π/2.
                weights.push(0.5 * width * w / FRAC_PI_2);
            }
        }
        Self::of_nodes(cosines, weights)
    }

    /// Σ weight·value: the mean over θ of a function sampled at `cosines`.
    pub fn mean(&self, values: impl IntoIterator<Item = f64>) -> f64 {
        self.weights.iter().zip(values).map(|(w, v)| w * v).sum()
    }
}

/// The default rule (`PANELS` × `NODES`), built once.
pub fn angle_quadrature() -> &'static AngleQuadrature {
    static RULE: OnceLock<AngleQuadrature> = OnceLock::new();
    RULE.get_or_init(|| AngleQuadrature::new(PANELS, NODES))
}

/// Gauss–Legendre nodes and weights on [−1, 1]: roots of P_n by Newton's method from
/// the Chebyshev-like guess cos(π(i − ¼)/(n + ½)), w = 2/((1 − x²) P_n'(x)²)
/// (Abramowitz & Stegun 25.4.29).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for i in 1..=n {
        let mut x = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            let (p, dp) = legendre(n, x);
            derivative = dp;
            let step = p / dp;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(n, x);
        if dp.is_finite() {
            derivative = dp;
        }
        nodes.push(x);
        weights.push(2.0 / ((1.0 - x * x) * derivative * derivative));
    }
    (nodes, weights)
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut previous, mut current) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let next = ((2 * k - 1) as f64 * x * current - (k - 1) as f64 * previous) / k as f64;
        previous = current;
        current = next;
    }
    (current, n as f64 * (x * current - previous) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let (x, w) = gauss_legendre(8);
        assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
        // ∫ x^14 over [−1, 1] = 2/15 (degree 14 ≤ 2·8 − 1).
        let integral: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(14)).sum();
        assert!((integral - 2.0 / 15.0).abs() < 1e-14, "{integral}");
    }

    #[test]
    fn mean_over_theta_of_known_functions() {
        let rule = angle_quadrature();
        assert!((rule.weights.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        // Mean of cosθ over [0, π/2] = 2/π; of cos²θ = 1/2.
        assert!((rule.mean(rule.cosines.iter().copied()) - 2.0 / std::f64::consts::PI).abs() < 1e-14);
        assert!((rule.mean(rule.cosines.iter().map(|c| c * c)) - 0.5).abs() < 1e-14);
    }
}

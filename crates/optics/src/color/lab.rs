//! CIELAB (CIE 15:2004 §8.2.1) and the CIEDE2000 colour difference (CIE 142-2001, in the
//! form of Sharma, Wu & Dalal, Color Res. Appl. 30(1), 21–30, 2005).

use std::f64::consts::PI;

/// CIE L*a*b* coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lab {
    /// Lightness L*, 0 (black) to 100 (white).
    pub l: f64,
    /// a*: green (−) to red (+).
    pub a: f64,
    /// b*: blue (−) to yellow (+).
    pub b: f64,
}

/// CIELAB of `xyz` relative to the white `white_xyz` (same scale, e.g. Y_white = 1):
/// L* = 116 f(Y/Yn) − 16, a* = 500 (f(X/Xn) − f(Y/Yn)), b* = 200 (f(Y/Yn) − f(Z/Zn)),
/// f(t) = t^⅓ for t > (6/29)³, else t/(3·(6/29)²) + 4/29. Negative t (out-of-gamut
/// inputs) takes the linear branch and stays finite.
pub fn xyz_to_lab(xyz: [f64; 3], white_xyz: [f64; 3]) -> Lab {
    let f = |t: f64| {
        const DELTA: f64 = 6.0 / 29.0;
        if t > DELTA * DELTA * DELTA {
            t.cbrt()
        } else {
            t / (3.0 * DELTA * DELTA) + 4.0 / 29.0
        }
    };
    let [fx, fy, fz] = [0, 1, 2].map(|i| f(xyz[i] / white_xyz[i]));
    Lab { l: 116.0 * fy - 16.0, a: 500.0 * (fx - fy), b: 200.0 * (fy - fz) }
}

/// CIEDE2000 ΔE₀₀ between two colours with k_L = k_C = k_H = 1 (Sharma et al. 2005,
/// eqs. 1–22): a* rescaled by 1 + G with G = ½(1 − √(C̄⁷/(C̄⁷ + 25⁷))), hue angles with
/// the zero-chroma and ±180° conventions of the paper, weights S_L, S_C, S_H and the
/// rotation term R_T = −sin(2Δθ)·R_C.
///
/// ```
/// use nklut_optics::color::{delta_e2000, Lab};
/// // Pair 1 of Sharma, Wu and Dalal's test data: ΔE₀₀ = 2.0425.
/// let de = delta_e2000(Lab { l: 50.0, a: 2.6772, b: -79.7751 }, Lab { l: 50.0, a: 0.0, b: -82.7485 });
/// assert!((de - 2.0425).abs() < 1e-4);
/// ```
pub fn delta_e2000(first: Lab, second: Lab) -> f64 {
    let c_star_mean = (first.a.hypot(first.b) + second.a.hypot(second.b)) / 2.0;
    let g = 0.5 * (1.0 - seventh_power_ratio(c_star_mean).sqrt());
    let prime = |lab: Lab| {
        let a = (1.0 + g) * lab.a;
        let chroma = a.hypot(lab.b);
        (chroma, hue_degrees(a, lab.b))
    };
    let (c1, h1) = prime(first);
    let (c2, h2) = prime(second);

    let delta_l = second.l - first.l;
    let delta_c = c2 - c1;
    let delta_h_angle = if c1 * c2 == 0.0 {
        0.0
    } else if (h2 - h1).abs() <= 180.0 {
        h2 - h1
    } else if h2 - h1 > 180.0 {
        h2 - h1 - 360.0
    } else {
        h2 - h1 + 360.0
    };
    let delta_h = 2.0 * (c1 * c2).sqrt() * (delta_h_angle / 2.0).to_radians().sin();

    let l_mean = (first.l + second.l) / 2.0;
    let c_mean = (c1 + c2) / 2.0;
    let h_mean = if c1 * c2 == 0.0 {
        h1 + h2
    } else if (h1 - h2).abs() <= 180.0 {
        (h1 + h2) / 2.0
    } else if h1 + h2 < 360.0 {
        (h1 + h2 + 360.0) / 2.0
    } else {
        (h1 + h2 - 360.0) / 2.0
    };
    let t = 1.0 - 0.17 * (h_mean - 30.0).to_radians().cos()
        + 0.24 * (2.0 * h_mean).to_radians().cos()
        + 0.32 * (3.0 * h_mean + 6.0).to_radians().cos()
        - 0.20 * (4.0 * h_mean - 63.0).to_radians().cos();
    let delta_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let rotation = -(2.0 * delta_theta).to_radians().sin() * 2.0 * seventh_power_ratio(c_mean).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * c_mean;
    let s_h = 1.0 + 0.015 * c_mean * t;

    let (l_term, c_term, h_term) = (delta_l / s_l, delta_c / s_c, delta_h / s_h);
    (l_term * l_term + c_term * c_term + h_term * h_term + rotation * c_term * h_term).max(0.0).sqrt()
}

/// C⁷/(C⁷ + 25⁷), the chroma weight shared by G and R_C.
fn seventh_power_ratio(chroma: f64) -> f64 {
    let c7 = chroma.powi(7);
    if c7 == 0.0 {
        0.0
    } else {
        c7 / (c7 + 25f64.powi(7))
    }
}

/// Hue angle in degrees in [0, 360); 0 where a = b = 0 (Sharma et al. eq. 4).
fn hue_degrees(a: f64, b: f64) -> f64 {
    if a == 0.0 && b == 0.0 {
        return 0.0;
    }
    let h = b.atan2(a) * 180.0 / PI;
    if h < 0.0 {
        h + 360.0
    } else {
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 1 of Sharma, Wu & Dalal (2005): L1 a1 b1, L2 a2 b2, ΔE00 (4 decimals).
    const SHARMA_PAIRS: [[f64; 7]; 34] = [
        [50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425],
        [50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615],
        [50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412],
        [50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000],
        [50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000],
        [50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000],
        [50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669],
        [50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669],
        [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792],
        [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792],
        [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195],
        [50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195],
        [50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045],
        [50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045],
        [50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461],
        [50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065],
        [50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492],
        [50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977],
        [50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030],
        [50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535],
        [50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000],
        [50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000],
        [50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000],
        [50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000],
        [60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644],
        [63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630],
        [61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731],
        [35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645],
        [22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373],
        [36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146],
        [90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441],
        [90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381],
        [6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377],
        [2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082],
    ];

    #[test]
    fn ciede2000_matches_sharma_table_in_both_orders() {
        for (i, p) in SHARMA_PAIRS.iter().enumerate() {
            let first = Lab { l: p[0], a: p[1], b: p[2] };
            let second = Lab { l: p[3], a: p[4], b: p[5] };
            let forward = delta_e2000(first, second);
            let backward = delta_e2000(second, first);
            assert!((forward - p[6]).abs() < 5e-5, "pair {}: {forward} vs {}", i + 1, p[6]);
            assert!((backward - forward).abs() < 1e-12, "pair {} not symmetric", i + 1);
        }
        let same = Lab { l: 40.0, a: 30.0, b: -20.0 };
        assert_eq!(delta_e2000(same, same), 0.0);
    }

    #[test]
    fn lab_of_white_and_of_middle_grey() {
        let white = crate::color::srgb::D65_WHITE_XYZ;
        let lab = xyz_to_lab(white, white);
        assert!((lab.l - 100.0).abs() < 1e-12 && lab.a.abs() < 1e-12 && lab.b.abs() < 1e-12);
        // Y = 0.18 → L* = 116·0.18^⅓ − 16 = 49.4961076...
        let grey = xyz_to_lab(white.map(|v| 0.18 * v), white);
        assert!((grey.l - 49.496_107_6).abs() < 1e-6, "{}", grey.l);
        // Below the knee: Y = 0.001 → L* = 903.296·0.001 = 0.9033 (κ = (29/3)³).
        let dark = xyz_to_lab(white.map(|v| 0.001 * v), white);
        assert!((dark.l - 0.903_296).abs() < 1e-5, "{}", dark.l);
    }
}

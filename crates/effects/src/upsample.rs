//! RGB → spectrum for the spectral reference's diffuse surroundings and lights: Smits,
//! "An RGB-to-Spectrum Conversion for Reflectances" (Journal of Graphics Tools 4(4), 1999).
//!
//! Smits builds a reflectance from seven basis spectra on ten equal bins over 380–720 nm
//! (white, cyan, magenta, yellow, red, green, blue; his table 1, held at the end bins
//! outside that range): the smallest channel times white, the next difference times the
//! secondary (cyan, magenta or yellow) the two larger channels share, the last difference
//! times the primary of the largest. Two changes, both stated:
//!
//! - white is taken as 1 in every bin (Smits's table has 0.9992–1.0000), so a grey albedo
//!   is a flat spectrum and round-trips exactly;
//! - Smits's spectrum reproduces the RGB only approximately through our weights (CIE 1931,
//!   D65, the grid of the spectral reference; his basis was fitted for another observer
//!   sampling); the residual is removed by adding δ_r·red + δ_g·green + δ_b·blue of his own
//!   basis, δ = G⁻¹(rgb − Σ_λ w(λ)S(λ)) with G the 3×3 matrix of the primaries' colours on
//!   the grid. The round trip is then exact to rounding; [`Upsampler::smits_residual`]
//!   gives the error before the correction (stated in docs/effects.md).
//!
//! Lights are D65-shaped: the weights already carry D65, so a light of RGB colour c is the
//! relative spectrum lift(c), 1 (D65 itself) for white, scaled by its RGB.

use nklut_optics::color::srgb::{invert, Matrix3};

/// Smits's basis, ten bins of 34 nm from 380 nm (table 1 of the paper), white replaced by 1.
const WHITE: [f64; 10] = [1.0; 10];
const CYAN: [f64; 10] = [0.9710, 0.9426, 1.0007, 1.0007, 1.0007, 1.0007, 0.1564, 0.0, 0.0, 0.0];
const MAGENTA: [f64; 10] = [1.0, 1.0, 0.9685, 0.2229, 0.0, 0.0458, 0.8369, 1.0, 1.0, 0.9959];
const YELLOW: [f64; 10] = [0.0001, 0.0, 0.1088, 0.6651, 1.0, 1.0, 0.9996, 0.9586, 0.9685, 0.9840];
const RED: [f64; 10] = [0.1012, 0.0515, 0.0, 0.0, 0.0, 0.0, 0.8325, 1.0149, 1.0149, 1.0149];
const GREEN: [f64; 10] = [0.0, 0.0, 0.0273, 0.7937, 1.0, 0.9418, 0.1719, 0.0, 0.0, 0.0025];
const BLUE: [f64; 10] = [1.0, 1.0, 0.8916, 0.3323, 0.0, 0.0, 0.0003, 0.0369, 0.0483, 0.0496];

/// The bin of Smits's table a wavelength falls in (held at the ends).
fn bin(nm: f64) -> usize {
    (((nm - 380.0) / 34.0).floor().max(0.0) as usize).min(9)
}

/// The seven basis spectra in the order of a [`Lifted`]'s weights.
const BASIS: [&[f64; 10]; 7] = [&WHITE, &CYAN, &MAGENTA, &YELLOW, &RED, &GREEN, &BLUE];
/// The positions of red, green and blue in [`BASIS`] (the correction's primaries).
const PRIMARIES: [usize; 3] = [4, 5, 6];

/// A colour lifted to a spectrum, held as its weights on Smits's seven basis spectra
/// (white, cyan, magenta, yellow, red, green, blue; the correction included): its value at
/// one wavelength of the grid costs seven products, so a ray carrying a few wavelengths
/// reads only those.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lifted([f64; 7]);

/// Smits's weights of `rgb` on the basis: the smallest channel on white, the next
/// difference on the secondary the two larger channels share, the last on the primary of
/// the largest.
fn smits_weights(rgb: [f64; 3]) -> [f64; 7] {
    let [r, g, b] = rgb;
    let (white, cyan, magenta, yellow, red, green, blue) = (0, 1, 2, 3, 4, 5, 6);
    let terms: [(usize, f64); 3] = if r <= g && r <= b {
        if g <= b {
            [(white, r), (cyan, g - r), (blue, b - g)]
        } else {
            [(white, r), (cyan, b - r), (green, g - b)]
        }
    } else if g <= r && g <= b {
        if r <= b {
            [(white, g), (magenta, r - g), (blue, b - r)]
        } else {
            [(white, g), (magenta, b - g), (red, r - b)]
        }
    } else if r <= g {
        [(white, b), (yellow, r - b), (green, g - r)]
    } else {
        [(white, b), (yellow, g - b), (red, r - g)]
    };
    let mut weights = [0.0; 7];
    for (basis, weight) in terms {
        weights[basis] = weight;
    }
    weights
}

/// The lift of RGB to spectra on one set of wavelengths with their linear-sRGB weights.
#[derive(Clone, Debug)]
pub struct Upsampler {
    /// The basis spectra at each wavelength, in [`BASIS`] order.
    basis: Vec<[f64; 7]>,
    weights: Vec<[f64; 3]>,
    /// The colour of each basis spectrum on the grid (colour is linear in the spectrum).
    basis_colours: [[f64; 3]; 7],
    /// G⁻¹, G[i][c] = Σ_λ w_i(λ) primary_c(λ).
    correction: Matrix3,
}

impl Upsampler {
    /// For wavelengths `nm` whose colour weights are `weights` (Σ_λ w(λ)S(λ) is the linear
    /// sRGB of a spectrum S).
    pub fn new(nm: &[f64], weights: &[[f64; 3]]) -> Upsampler {
        let basis: Vec<[f64; 7]> = nm.iter().map(|&l| BASIS.map(|table| table[bin(l)])).collect();
        let basis_colours: [[f64; 3]; 7] = std::array::from_fn(|j| {
            basis.iter().zip(weights).fold([0.0; 3], |rgb, (s, w)| [rgb[0] + s[j] * w[0], rgb[1] + s[j] * w[1], rgb[2] + s[j] * w[2]])
        });
        let g: Matrix3 = std::array::from_fn(|i| std::array::from_fn(|c| basis_colours[PRIMARIES[c]][i]));
        // On a grid too coarse to tell the primaries apart the correction is left out
        // (the round trip is then Smits's own).
        let correction = invert(&g).unwrap_or([[0.0; 3]; 3]);
        Upsampler { basis, weights: weights.to_vec(), basis_colours, correction }
    }

    /// The lifted spectrum's value at wavelength `lane` of the grid.
    pub fn value(&self, lifted: &Lifted, lane: usize) -> f64 {
        self.basis[lane].iter().zip(&lifted.0).map(|(b, w)| b * w).sum()
    }

    fn values(&self, lifted: &Lifted) -> Vec<f64> {
        (0..self.basis.len()).map(|lane| self.value(lifted, lane)).collect()
    }

    /// Smits's spectrum of `rgb` alone, before the correction.
    pub fn smits(&self, rgb: [f64; 3]) -> Vec<f64> {
        self.values(&Lifted(smits_weights(rgb)))
    }

    /// The colour of a spectrum on these wavelengths.
    pub fn colour(&self, spectrum: &[f64]) -> [f64; 3] {
        spectrum.iter().zip(&self.weights).fold([0.0; 3], |rgb, (s, w)| [rgb[0] + s * w[0], rgb[1] + s * w[1], rgb[2] + s * w[2]])
    }

    /// rgb − colour(smits(rgb)): what Smits's spectrum alone misses.
    pub fn smits_residual(&self, rgb: [f64; 3]) -> [f64; 3] {
        let back = self.colour(&self.smits(rgb));
        std::array::from_fn(|c| rgb[c] - back[c])
    }

    /// `rgb` lifted: Smits's weights, corrected in his primaries so that the spectrum's
    /// colour is `rgb` to rounding (the residual from the basis colours, colour being
    /// linear). A grey is flat (white is 1) and left as it is.
    pub fn lift(&self, rgb: [f64; 3]) -> Lifted {
        let mut weights = smits_weights(rgb);
        if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
            return Lifted(weights);
        }
        let back = weights.iter().zip(&self.basis_colours).fold([0.0; 3], |s, (w, c)| [s[0] + w * c[0], s[1] + w * c[1], s[2] + w * c[2]]);
        let residual: [f64; 3] = std::array::from_fn(|c| rgb[c] - back[c]);
        for (c, primary) in PRIMARIES.iter().enumerate() {
            weights[*primary] += (0..3).map(|i| self.correction[c][i] * residual[i]).sum::<f64>();
        }
        Lifted(weights)
    }

    /// The spectrum of `rgb` on the grid ([`Upsampler::lift`] at every wavelength).
    pub fn spectrum(&self, rgb: [f64; 3]) -> Vec<f64> {
        self.values(&self.lift(rgb))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::color::spectral_weights;
    use nklut_optics::spectrum::spectral_wavelength_nm;

    fn full_grid() -> Upsampler {
        let weights = spectral_weights();
        let nm: Vec<f64> = (0..weights.active).map(spectral_wavelength_nm).collect();
        Upsampler::new(&nm, &weights.rgb[..weights.active])
    }

    #[test]
    fn smits_follows_his_decomposition_and_the_correction_closes_the_round_trip() {
        let lift = full_grid();
        // 400 nm is bin 0, 560 nm bin 5, 700 nm bin 9; below 380 and above 720 held.
        assert_eq!((bin(400.0), bin(560.0), bin(700.0), bin(360.0), bin(780.0)), (0, 5, 9, 0, 9));
        // (0.2, 0.5, 0.8): r smallest, g ≤ b: 0.2 white + 0.3 cyan + 0.3 blue.
        let s = lift.smits([0.2, 0.5, 0.8]);
        assert!((s[560 - 360] - (0.2 + 0.3 * 1.0007 + 0.3 * 0.0)).abs() < 1e-15);
        assert!((s[400 - 360] - (0.2 + 0.3 * 0.9710 + 0.3 * 1.0)).abs() < 1e-15);
        // A grey is flat and exact.
        assert!(lift.spectrum([0.37; 3]).iter().all(|v| *v == 0.37));
        let mut worst: f64 = 0.0;
        for rgb in
            [[0.85, 0.85, 0.8], [0.15, 0.2, 0.45], [0.9, 0.5, 0.2], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.6, 0.6, 0.6]]
        {
            let back = lift.colour(&lift.spectrum(rgb));
            assert!((0..3).all(|c| (back[c] - rgb[c]).abs() < 1e-14), "{rgb:?} → {back:?}");
            worst = worst.max(lift.smits_residual(rgb).iter().fold(0.0f64, |m, v| m.max(v.abs())));
        }
        // Smits alone misses by some hundredths on saturated primaries through CIE 1931/D65.
        eprintln!("Smits 1999 round trip before the correction: largest |Δ| {worst:.4}");
        assert!(worst > 1e-3 && worst < 0.2, "{worst}");
    }
}

//! The nine dispersion formulas of refractiveindex.info (SPEC §1; the database's
//! `doc/Dispersion formulas.pdf`). λ in µm; missing trailing coefficients are zero.

/// A dispersion formula: its number (1-9), coefficients C1.. (`coefficients[0]` is C1)
/// and the wavelength range (µm) where it is valid.
#[derive(Clone, Debug, PartialEq)]
pub struct Formula {
    /// The formula's number, 1–9.
    pub number: u8,
    /// C1, C2, …: `coefficients[0]` is C1.
    pub coefficients: Vec<f64>,
    /// The wavelengths (µm) where the formula is valid.
    pub range_um: (f64, f64),
}

/// How many coefficients each formula defines (C1..Cmax).
pub fn max_coefficients(number: u8) -> usize {
    match number {
        1..=4 => 17,
        5 | 6 => 11,
        7 | 9 => 6,
        8 => 4,
        _ => 0,
    }
}

impl Formula {
    /// C(i) with the database's 1-based numbering; absent trailing coefficients are 0.
    fn c(&self, i: usize) -> f64 {
        self.coefficients.get(i - 1).copied().unwrap_or(0.0)
    }

    /// Whether `um` (µm) lies in the formula's range.
    pub fn contains(&self, um: f64) -> bool {
        um >= self.range_um.0 && um <= self.range_um.1
    }

    /// n(λ) for λ in µm, ignoring the range (the caller checks it). NaN when the formula
    /// gives n² < 0 there; the caller reports that as `negative-n`.
    pub fn refractive_index(&self, um: f64) -> f64 {
        let l2 = um * um;
        match self.number {
            // 1. Sellmeier: n² − 1 = C1 + Σ C(i) λ²/(λ² − C(i+1)²)
            1 => (1.0 + self.c(1) + (2..=16).step_by(2).map(|i| self.c(i) * l2 / (l2 - self.c(i + 1).powi(2))).sum::<f64>()).sqrt(),
            // 2. Sellmeier-2: n² − 1 = C1 + Σ C(i) λ²/(λ² − C(i+1))
            2 => (1.0 + self.c(1) + (2..=16).step_by(2).map(|i| self.c(i) * l2 / (l2 - self.c(i + 1))).sum::<f64>()).sqrt(),
            // 3. Polynomial: n² = C1 + Σ C(i) λ^C(i+1)
            3 => (self.c(1) + self.power_series(um, 2, 16)).sqrt(),
            // 4. RefractiveIndex.INFO: n² = C1 + C2 λ^C3/(λ² − C4^C5) + C6 λ^C7/(λ² − C8^C9) + Σ_{i≥10} C(i) λ^C(i+1)
            4 => (self.c(1)
                + self.c(2) * um.powf(self.c(3)) / (l2 - self.c(4).powf(self.c(5)))
                + self.c(6) * um.powf(self.c(7)) / (l2 - self.c(8).powf(self.c(9)))
                + self.power_series(um, 10, 16))
            .sqrt(),
            // 5. Cauchy: n = C1 + Σ C(i) λ^C(i+1)
            5 => self.c(1) + self.power_series(um, 2, 10),
            // 6. Gases: n − 1 = C1 + Σ C(i)/(C(i+1) − λ⁻²)
            6 => 1.0 + self.c(1) + (2..=10).step_by(2).map(|i| self.c(i) / (self.c(i + 1) - 1.0 / l2)).sum::<f64>(),
            // 7. Herzberger: n = C1 + C2/(λ² − 0.028) + C3/(λ² − 0.028)² + C4 λ² + C5 λ⁴ + C6 λ⁶
            7 => {
                let d = l2 - 0.028;
                self.c(1) + self.c(2) / d + self.c(3) / (d * d) + self.c(4) * l2 + self.c(5) * l2 * l2 + self.c(6) * l2 * l2 * l2
            }
            // 8. Retro: (n² − 1)/(n² + 2) = C1 + C2 λ²/(λ² − C3) + C4 λ²  ⇒  n² = (1 + 2x)/(1 − x)
            8 => {
                let x = self.c(1) + self.c(2) * l2 / (l2 - self.c(3)) + self.c(4) * l2;
                ((1.0 + 2.0 * x) / (1.0 - x)).sqrt()
            }
            // 9. Exotic: n² = C1 + C2/(λ² − C3) + C4 (λ − C5)/((λ − C5)² + C6)
            9 => {
                let d = um - self.c(5);
                (self.c(1) + self.c(2) / (l2 - self.c(3)) + self.c(4) * d / (d * d + self.c(6))).sqrt()
            }
            _ => f64::NAN,
        }
    }

    /// Σ C(i) λ^C(i+1) for i = first, first+2, …, last. Terms with C(i) = 0 are skipped so
    /// that an absent pair contributes exactly zero (0 · λ^0 and 0 · ∞ alike).
    fn power_series(&self, um: f64, first: usize, last: usize) -> f64 {
        (first..=last).step_by(2).filter(|&i| self.c(i) != 0.0).map(|i| self.c(i) * um.powf(self.c(i + 1))).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn formula(number: u8, coefficients: &[f64]) -> Formula {
        Formula { number, coefficients: coefficients.to_vec(), range_um: (0.2, 2.0) }
    }

    #[test]
    fn each_formula_against_hand_computed_values() {
        // At λ = 0.5 µm, λ² = 0.25.
        // 1: n² = 1 + 0.1 + 1.0·0.25/(0.25 − 0.01) = 1.1 + 1.0416666…
        let n = formula(1, &[0.1, 1.0, 0.1]).refractive_index(0.5);
        assert!((n - (1.1f64 + 0.25 / 0.24).sqrt()).abs() < 1e-15);
        // 2: n² = 1 + 0 + 1.0·0.25/(0.25 − 0.01)
        let n = formula(2, &[0.0, 1.0, 0.01]).refractive_index(0.5);
        assert!((n - (1.0f64 + 0.25 / 0.24).sqrt()).abs() < 1e-15);
        // 3: n² = 2.25 + 0.01·λ^−2 = 2.25 + 0.04
        let n = formula(3, &[2.25, 0.01, -2.0]).refractive_index(0.5);
        assert!((n - 2.29f64.sqrt()).abs() < 1e-15);
        // 4: n² = 1 + 0.5·λ²/(λ² − 0.1²) + 0 + 0.02·λ^-2
        let c = [1.0, 0.5, 2.0, 0.1, 2.0, 0.0, 0.0, 0.0, 0.0, 0.02, -2.0];
        let n = formula(4, &c).refractive_index(0.5);
        assert!((n - (1.0 + 0.5 * 0.25 / 0.24 + 0.08f64).sqrt()).abs() < 1e-15);
        // 5: n = 1.5 + 0.004·λ^−2 = 1.516
        let n = formula(5, &[1.5, 0.004, -2.0]).refractive_index(0.5);
        assert!((n - 1.516).abs() < 1e-15);
        // 6: n = 1 + 1e-4 + 0.01/(100 − 4)
        let n = formula(6, &[1e-4, 0.01, 100.0]).refractive_index(0.5);
        assert!((n - (1.0 + 1e-4 + 0.01 / 96.0)).abs() < 1e-15);
        // 7: n = 1.5 + 0.01/(0.25 − 0.028) + 0.001/0.222² + 0.1·0.25
        let n = formula(7, &[1.5, 0.01, 0.001, 0.1]).refractive_index(0.5);
        assert!((n - (1.5 + 0.01 / 0.222 + 0.001 / (0.222 * 0.222) + 0.025)).abs() < 1e-14);
        // 8: x = 0.3 → n² = 1.6/0.7
        let n = formula(8, &[0.3]).refractive_index(0.5);
        assert!((n - (1.6f64 / 0.7).sqrt()).abs() < 1e-15);
        // 9: n² = 2 + 0.1/(0.25 − 0.05) + 0.2·(0.5 − 0.4)/(0.01 + 0.01) = 2 + 0.5 + 1
        let n = formula(9, &[2.0, 0.1, 0.05, 0.2, 0.4, 0.01]).refractive_index(0.5);
        assert!((n - 3.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn negative_square_gives_nan() {
        assert!(formula(3, &[-1.0]).refractive_index(0.5).is_nan());
    }
}

//! The CIE tables embedded in the crate: the CIE 1931 2° colour-matching functions
//! (360–830 nm, 1 nm) and illuminant D65 (300–780 nm, 5 nm), parsed once.
//!
//! Source: CIE 15:2004 tables (copied from `../shared/cie/` into `data/cie/`).

use std::sync::OnceLock;

use crate::spectrum::{spectral_wavelength_nm, SPECTRAL_SAMPLES, SPECTRAL_START_NM};

const CMF_CSV: &str = include_str!("../../data/cie/cie1931_2deg_xyz_cmf_1nm.csv");
const D65_CSV: &str = include_str!("../../data/cie/cie_d65_spd.csv");

/// The CIE tables on the spectral grid of SPEC §4 (λ_i = 360 + i nm, i < 471).
#[derive(Clone, Debug)]
pub struct CieTables {
    /// \[x̄, ȳ, z̄\](λ_i), CIE 1931 2° standard observer.
    pub cmf: Vec<[f64; 3]>,
    /// S(λ_i), illuminant D65 (relative power, 100 at 560 nm), linear between the 5 nm
    /// rows of the table and **zero beyond 780 nm**, where the table stops: the integrals
    /// of SPEC §4 then run over the table's range. (The CIE's own D65 continues at ~60–70
    /// up to 830 nm, but there ȳ < 1.6·10⁻⁵ of its peak; the white point moves by < 10⁻⁵.)
    pub d65: Vec<f64>,
}

/// The embedded tables, parsed on first use.
pub fn tables() -> &'static CieTables {
    static TABLES: OnceLock<CieTables> = OnceLock::new();
    TABLES.get_or_init(|| {
        let cmf_rows = parse_csv(CMF_CSV, 4);
        let d65_rows = parse_csv(D65_CSV, 2);
        CieTables { cmf: cmf_on_grid(&cmf_rows), d65: d65_on_grid(&d65_rows) }
    })
}

/// Rows of a numeric CSV with a header line. The embedded tables are part of the
/// program, so a malformed one is a build defect (caught by the tests), not a data error.
fn parse_csv(text: &str, columns: usize) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let row: Vec<f64> =
                line.split(',').map(|cell| cell.trim().parse::<f64>().expect("embedded CIE table: a cell is not a number")).collect();
            assert_eq!(row.len(), columns, "embedded CIE table: wrong column count in {line:?}");
            row
        })
        .collect()
}

fn cmf_on_grid(rows: &[Vec<f64>]) -> Vec<[f64; 3]> {
    (0..SPECTRAL_SAMPLES)
        .map(|i| {
            let nm = spectral_wavelength_nm(i);
            let row = rows.iter().find(|row| row[0] == nm).expect("embedded CMF table covers 360–830 nm in 1 nm steps");
            [row[1], row[2], row[3]]
        })
        .collect()
}

fn d65_on_grid(rows: &[Vec<f64>]) -> Vec<f64> {
    (0..SPECTRAL_SAMPLES).map(|i| linear_or_zero(rows, SPECTRAL_START_NM + i as f64)).collect()
}

/// Linear interpolation in a (λ, value) table; zero outside the table's range.
fn linear_or_zero(rows: &[Vec<f64>], nm: f64) -> f64 {
    let after = rows.partition_point(|row| row[0] < nm);
    if after < rows.len() && rows[after][0] == nm {
        return rows[after][1];
    }
    if after == 0 || after >= rows.len() {
        return 0.0;
    }
    let (a, b) = (&rows[after - 1], &rows[after]);
    let t = (nm - a[0]) / (b[0] - a[0]);
    a[1] + t * (b[1] - a[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_hold_known_values() {
        let t = tables();
        assert_eq!(t.cmf.len(), SPECTRAL_SAMPLES);
        // ȳ(555 nm) = 1.0 exactly in the CIE 1931 table; D65(560) = 100 by definition.
        assert_eq!(t.cmf[195][1], 1.0);
        assert_eq!(t.d65[200], 100.0);
        // D65 at 362 nm lies 2/5 of the way from 360 nm (46.6383) to 365 nm (49.3637).
        assert!((t.d65[2] - (46.6383 + 0.4 * (49.3637 - 46.6383))).abs() < 1e-12, "{}", t.d65[2]);
        assert!(t.d65[420] > 60.0 && t.d65[421] == 0.0); // 780 nm is the last row
    }
}

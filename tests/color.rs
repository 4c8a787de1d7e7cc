//! Colour tests against the real database (`refractiveindex/database`, or $NKLUT_DB):
//! an independent recomputation of one page's F0 colour, finiteness over every kept
//! page, the effective-index target on the `3d` metals and the angle quadrature.

mod common;

use std::path::Path;

use common::database;
use nklut::color::{self, AngleQuadrature};
use nklut::ingest::{ingest, Ingest, Selection};

fn shelf(name: &str) -> Ingest {
    ingest(&database(), &Selection::shelf(name), &nklut::ingest::Config::default()).unwrap()
}

/// Numeric rows of a CSV file with a header.
fn read_csv(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect()
}

/// Linear interpolation in sorted (x, y) rows; `None` outside.
fn interpolate(rows: &[(f64, f64)], x: f64) -> Option<f64> {
    if x < rows[0].0 || x > rows[rows.len() - 1].0 {
        return None;
    }
    let pair = rows.windows(2).find(|w| w[0].0 <= x && x <= w[1].0)?;
    let t = (x - pair[0].0) / (pair[1].0 - pair[0].0);
    Some(pair[0].1 + t * (pair[1].1 - pair[0].1))
}

/// Solve A x = y for 3×3 A by Cramer's rule.
fn solve(a: [[f64; 3]; 3], y: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let mut x = [0.0; 3];
    for (col, value) in x.iter_mut().enumerate() {
        let mut m = a;
        for row in 0..3 {
            m[row][col] = y[row];
        }
        *value = det(m) / d;
    }
    x
}

/// F0 colour of `3d/metals/gold` from scratch: the data file's own rows, the shared CIE
/// CSVs, D65 interpolated to 1 nm (0 beyond 780 nm), F0 = ((n−1)² + k²)/((n+1)² + k²),
/// sRGB from the primaries: with P the primaries' XYZ columns, RGB_j = (P⁻¹ XYZ)_j /
/// (P⁻¹ XYZ_white)_j.
#[test]
fn gold_f0_agrees_with_an_independent_summation() {
    let db = database();
    let gold = shelf("3d");
    let page = gold.find("3d/metals/gold").expect("3d/metals/gold is kept");
    assert_eq!(page.page.data, "main/Au/nk/Rakic-BB.yml");

    // The page's rows "λ(µm) n k" below `data: |`.
    let text = std::fs::read_to_string(db.root.join("data/main/Au/nk/Rakic-BB.yml")).unwrap();
    let rows: Vec<[f64; 3]> = text
        .lines()
        .filter_map(|l| {
            let v: Vec<f64> = l.split_whitespace().filter_map(|t| t.parse().ok()).collect();
            (v.len() == 3).then(|| [v[0] * 1000.0, v[1], v[2]])
        })
        .collect();
    assert!(rows.len() > 100);
    let n_rows: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[1])).collect();
    let k_rows: Vec<(f64, f64)> = rows.iter().map(|r| (r[0], r[2])).collect();
    let held = |table: &[(f64, f64)], nm: f64| interpolate(table, nm.clamp(table[0].0, table[table.len() - 1].0)).unwrap();

    // The CIE tables as published (../shared/cie), not the copy the crate embeds.
    let cie = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/cie");
    let cmf = read_csv(&cie.join("cie1931_2deg_xyz_cmf_1nm.csv"));
    let d65: Vec<(f64, f64)> = read_csv(&cie.join("cie_d65_spd.csv")).iter().map(|r| (r[0], r[1])).collect();
    let (mut xyz, mut white) = ([0.0; 3], [0.0; 3]);
    for row in &cmf {
        let nm = row[0];
        let s = interpolate(&d65, nm).unwrap_or(0.0);
        let (n, k) = (held(&n_rows, nm), held(&k_rows, nm));
        let f0 = ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        for j in 0..3 {
            xyz[j] += f0 * s * row[j + 1];
            white[j] += s * row[j + 1];
        }
    }
    let primaries = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)];
    let mut p = [[0.0; 3]; 3];
    for (col, (x, y)) in primaries.iter().enumerate() {
        p[0][col] = x / y;
        p[1][col] = 1.0;
        p[2][col] = (1.0 - x - y) / y;
    }
    let (raw, raw_white) = (solve(p, xyz), solve(p, white));
    let expected: Vec<f64> = (0..3).map(|j| raw[j] / raw_white[j]).collect();

    let (spectrum, share) = color::sample_spectrum(&page.material.data);
    let rgb = color::reflectance_rgb(&spectrum, 1.0);
    for j in 0..3 {
        assert!((rgb[j] - expected[j]).abs() < 1e-6, "channel {j}: {rgb:?} vs {expected:?}");
    }
    assert!(expected[0] > 1.0, "gold's red F0 is above 1: {expected:?}");
    assert_eq!(share, 0.0); // Rakić BB covers 248–1240 nm
}

/// Every kept page of the database has finite colours (a property over the whole data).
#[test]
fn colours_are_finite_for_every_kept_page() {
    let all = ingest(&database(), &Selection::All, &nklut::ingest::Config::default()).unwrap();
    assert!(all.kept.len() > 1000);
    let rule = AngleQuadrature::new(2, 2);
    for page in &all.kept {
        let reference = color::spectral_reference(&page.material, &rule, &[0.5, 0.001], None);
        let values = reference.at_nodes.iter().chain(&reference.at_texels).chain(std::iter::once(&reference.f0));
        for rgb in values {
            assert!(rgb.iter().all(|v| v.is_finite() && v.abs() < 10.0), "{}: {rgb:?}", page.id());
        }
        assert!((0.0..=1.0).contains(&reference.extrapolated_share), "{}", page.id());
        assert!(reference.spectrum.iter().all(|i| i.n > 0.0 && i.k >= 0.0 && i.n.is_finite() && i.k.is_finite()), "{}", page.id());
        let lab = color::spectral_weights().lab(reference.f0);
        assert!(lab.l.is_finite() && lab.a.is_finite() && lab.b.is_finite(), "{}", page.id());
    }
}

/// The accuracy target: on the `3d` metals every channel whose reference stays in [0, 1]
/// is matched by its effective index to < 0.5 % mean relative error over angle, never
/// worse than the three-wavelength index; gold's red (reference > 1) is the exception.
#[test]
fn effective_indices_meet_the_target_on_3d_metals() {
    let metals: Vec<_> = shelf("3d").kept.into_iter().filter(|p| p.page.book == "metals").collect();
    assert!(metals.len() >= 8);
    let colors = nklut::colors::compute(&metals, 0, &mut Default::default(), &Default::default(), &Default::default());
    let mut unmatched = vec![];
    for (page, colors) in metals.iter().zip(&colors) {
        for c in 0..3 {
            let fit = colors.effective[c];
            assert!(fit.index.n > 0.0 && fit.index.k >= 0.0);
            assert!(fit.error <= colors.index_error_angle[c] + 1e-12, "{} channel {c}: {colors:?}", page.id());
            if colors.reference_in_unit_range[c] {
                assert!(fit.error < 0.005, "{} channel {c}: {fit:?}", page.id());
            } else {
                unmatched.push((page.id(), c));
            }
        }
    }
    assert_eq!(unmatched, vec![("3d/metals/gold".to_string(), 0)]);
}

/// The default 24 × 8-node rule agrees with a 2048-node one to 4 significant digits on the mean relative error over θ.
#[test]
fn angle_quadrature_has_converged() {
    let metals: Vec<_> = shelf("3d").kept.into_iter().filter(|p| p.page.book == "metals").collect();
    let fine = AngleQuadrature::new(256, 8);
    let default = color::angle_quadrature();
    for page in &metals {
        let (spectrum, _) = color::sample_spectrum(&page.material.data);
        for (c, index) in page.material.channels.iter().enumerate() {
            let error = |rule: &AngleQuadrature| {
                let reference: Vec<f64> = color::spectral_curve(&spectrum, &rule.cosines).iter().map(|rgb| rgb[c]).collect();
                color::mean_relative_error(*index, &reference, rule)
            };
            let (coarse, exact) = (error(default), error(&fine));
            assert!((coarse / exact - 1.0).abs() < 1e-4, "{} channel {c}: {coarse} vs {exact}", page.id());
        }
    }
}

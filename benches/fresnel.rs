use criterion::{criterion_group, criterion_main, Criterion};
fn bench(c: &mut Criterion) {
    c.bench_function("exact", |b| b.iter(|| nklut::fresnel::exact(0.2, 3.0, 0.5)));
}
criterion_group!(benches, bench);
criterion_main!(benches);

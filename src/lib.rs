//! nklut: refractiveindex.info → per-channel complex indices, spectral reference colours,
//! Fresnel methods with their measured error, and lookup textures for engines.
//!
//! The work lives in the workspace's crates, whose boundaries are the layers (Cargo
//! enforces the direction of every import): `nklut-optics` (the database reader, spectra,
//! the Fresnel methods, colour science: no polars, no wgpu, no BVH) ← `nklut-pipeline`
//! (ingest, colours, validate, bake, params, report, recommend; tables and sets) ← `nklut-effects`
//! (scene files, the CPU tracers, surfel AO) ← `nklut-gpu` (the wgpu runner, feature
//! `gpu`) ← this package, the `nklut` binary. This library re-exports their modules under
//! one name, for the binary, the integration tests and the benchmarks.

pub use nklut_effects as effects;
pub use nklut_effects::scene;
#[cfg(feature = "gpu")]
pub use nklut_gpu as gpu;
pub use nklut_optics::{appearance, atomic, color, db, encoding, fresnel, memo, minimise, spectrum};
pub use nklut_pipeline::{bake, budget, colors, escape, ingest, output, params, progress, recommend, report, validate};

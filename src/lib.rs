//! nklut: refractiveindex.info → per-channel complex indices, spectral reference colours,
//! Fresnel methods with their measured error, and lookup textures for engines.
//!
//! The work lives in the workspace's crates, whose boundaries are the layers (Cargo
//! enforces the direction of every import): `nklut-optics` (the database reader, spectra,
//! the Fresnel methods, colour science: no polars, no wgpu, no BVH) ← `nklut-tables`
//! (ingest's reading of pages, tables as CSV and JSON and their publishing as sets, stats,
//! the memory budget, progress, texel images, the engine models: no polars) ←
//! `nklut-pipeline` (colours, validate, bake, params, report, recommend; Parquet through
//! polars) and, beside it, `nklut-effects` (scene files, the CPU tracers, surfel AO) ←
//! `nklut-gpu` (the wgpu runner, feature `gpu`) ← this package, the `nklut` binary. This library re-exports their modules under
//! one name, for the binary, the integration tests and the benchmarks.

pub use nklut_effects as effects;
pub use nklut_effects::scene;
#[cfg(feature = "gpu")]
pub use nklut_gpu as gpu;
pub use nklut_optics::{appearance, color, db, encoding, fresnel, memo, minimise, spectrum};

pub use nklut_pipeline::{
    bake, budget, colors, columns, effects_tables, escape, ingest, memo_file, output, params, progress, recommend, report, validate,
};

use std::path::{Path, PathBuf};

/// The database folder of the command line: `--db DIR`, else `$NKLUT_DB`, else
/// [`db::DEFAULT_DB`] (the library reads no environment variable; the binary, the tests and
/// the benchmarks decide here).
pub fn database_dir(db: Option<&Path>) -> PathBuf {
    match db {
        Some(dir) => dir.to_path_buf(),
        None => std::env::var_os("NKLUT_DB").map(PathBuf::from).unwrap_or_else(|| PathBuf::from(db::DEFAULT_DB)),
    }
}

/// [`db::Database::open`] of [`database_dir`], its error with what to do on this command line.
pub fn open_database(db: Option<&Path>) -> anyhow::Result<db::Database> {
    use anyhow::Context;
    db::Database::open(database_dir(db)).context("run `make db`, pass --db DIR or set NKLUT_DB")
}

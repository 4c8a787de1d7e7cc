//! nklut: refractiveindex.info → per-channel complex indices, spectral reference colours,
//! Fresnel methods with their measured error, and lookup textures for engines.
//!
//! Modules follow the data, and every import points one way — a module uses only modules
//! before it in this order (tests/module_order.rs checks it):
//!
//! `db` (catalog, pages, formulas) → `spectrum` (n, k at λ; channels; coverage) → `ingest`
//! (the selected pages into tables) → `fresnel` (the methods, f64 and f32 over
//! [`fresnel::Real`]) → `color` (CIE 1931, D65, sRGB; spectral reference; effective
//! indices) → `validate` (method errors) / `bake` (textures, manifest) / `params` (engine
//! parameters, MaterialX and glTF) → `report` → `scene` (scene files, pure data) →
//! `effects` (the CPU tracers: reference and distance-map twin, surfel AO) → `gpu`
//! (feature `gpu`: wgpu timing and rendering).
//!
//! Leaves any module may use: `budget` (the memory a run may take, checked before large
//! allocations), `encoding` (sRGB transfer function, texel encodings and
//! centres), `output` (tables, atomic publishing of a set of files), `progress` (bars on a
//! terminal, quiet in CI), `minimise` (Brent's 1D minimiser), `memo` (results remembered
//! between the commands of one output folder). The command line lives in the
//! binary (`src/main.rs`, `src/cli.rs`); stages take plain values.
//!
//! "SPEC §n" in comments is section n of `docs/SPEC.md`, the specification in this
//! repository.

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip: the
// comparison's whole point, not a style to refactor.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bake;
pub mod budget;
pub mod color;
pub mod db;
pub mod effects;
pub mod encoding;
pub mod fresnel;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod ingest;
pub mod memo;
pub mod minimise;
pub mod output;
pub mod params;
pub mod progress;
pub mod report;
pub mod scene;
pub mod spectrum;
pub mod validate;

//! nklut: refractiveindex.info → per-channel complex indices, spectral reference colours,
//! Fresnel methods with their measured error, and lookup textures for engines.
//!
//! Modules follow the data through the pipeline:
//! `db` (catalog, pages, formulas) → `spectrum` (n, k at λ; channels; visible filter) →
//! `ingest` (the whole database into tables) → `color` (CIE, sRGB) → `fresnel`
//! (methods) → `validate` (errors) → `bake` (textures, manifest) → `params` (engine
//! parameters, MaterialX and glTF exports) → `report`; `minimise` is Brent's 1D minimiser;
//! `output` writes files atomically at the edge; `scene` and
//! (feature `gpu`) `gpu` time and render every method with wgpu; `effects` traces the
//! multiple reflections and refractions a scene calls for on the CPU (reference and twin).

pub mod bake;
pub mod color;
pub mod db;
pub mod effects;
pub mod fresnel;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod ingest;
pub mod minimise;
pub mod output;
pub mod params;
pub mod progress;
pub mod report;
pub mod scene;
pub mod spectrum;
pub mod validate;

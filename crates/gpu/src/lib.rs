//! The wgpu runner (`gpu` feature): every Fresnel method as a pure WGSL function
//! (`shaders/fresnel.wgsl`), timed per material on any adapter, and rendered on a cube and
//! a sculpture to measure image error (docs/precision.md); and the first pass of the
//! effects: multiple reflections and refractions through layered distance maps
//! (`effects`, `passes::{distance_maps, specular}`, the search `shaders/distance_map.wgsl`
//! tested alone by `distance_search`), each held to its CPU twin in `nklut_effects`; and the surfel ambient-occlusion pass
//! (`passes::ao`, `shaders/surfel_ao.wgsl`). Pure CPU parts (`params`, `mesh`, `camera`,
//! `image_error`, `timing` statistics) take plain data; device I/O is in `context`,
//! `render`, `lut::upload`, `distance_search` and `runner`. Sizes are checked against the
//! device's limits before allocation.

pub mod ao_timing;
pub mod compose;
pub mod context;
pub mod contracts;
pub mod distance_search;
pub mod effects;
pub mod image_error;
pub mod layout;
pub mod lut;
pub mod params;
pub mod passes;
pub mod render;
pub mod runner;
pub mod sampling;
pub mod timing;
pub mod web;

// Meshes and the camera path are pure scene data (`scene`), shared with the CPU tracers.
pub use nklut_effects::scene::{camera, mesh};

pub use context::{adapters, open, AdapterLine, Gpu};
pub use runner::{run, run_opening, run_with_materials, RunReport, RunStats};

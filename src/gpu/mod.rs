//! The wgpu runner (issue 7, `gpu` feature): every Fresnel method of SPEC §5 as WGSL
//! (`shaders/fresnel.wgsl`), timed per material on any adapter, and rendered on a cube and
//! a sculpture to measure image error (SPEC §6). Pure CPU parts (`params`, `mesh`,
//! `camera`, `image_error`, `timing` statistics) take plain data; device I/O is in
//! `context`, `render`, `lut::upload` and `runner`.

pub mod context;
pub mod distance_search;
pub mod image_error;
pub mod lut;
pub mod params;
pub mod render;
pub mod runner;
pub mod timing;

// Meshes and the camera path are pure scene data (`scene`), shared with the CPU tracers.
pub use crate::scene::{camera, mesh};

pub use context::{adapters, open, AdapterLine, Gpu};
pub use runner::{run, run_with_materials, RunReport, RunStats};

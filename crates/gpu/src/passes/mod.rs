//! GPU passes as units with declared inputs and outputs: each owns its pipelines and
//! buffers, checks its sizes against the device's limits before allocating, and returns
//! wgpu's errors as `Result`s.
//!
//! - [`distance_maps`]: the layered distance maps of the specular objects, rasterised
//!   around each object's reference point with depth peeling (`shaders/distance_map_render.wgsl`).
//! - [`specular`]: the shading pass of multiple reflections and refractions through those
//!   maps, one pipeline per (effect, method) (`shaders/specular.wgsl`).
//! - [`ao`]: surfel accessibility and bent normals, N passes, brute force or through the
//!   surfel tree (`shaders/surfel_ao.wgsl`), held to the f64 CPU twin of `effects::ao`.
//! - [`indirect`]: one or two bounces of diffuse indirect light between surfels (the same
//!   shader's `cs_indirect`), held to `effects::ao::indirect`.

pub mod ao;
pub mod distance_maps;
pub mod indirect;
pub mod specular;

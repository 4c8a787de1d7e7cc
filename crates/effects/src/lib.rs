//! Effects a scene calls for, on the CPU: multiple specular reflections and refractions
//! with Fresnel weights from any method of `fresnel` (docs/effects.md).
//!
//! - [`geometry`]: the scene's placed triangles with smooth normals and their BVH (obvhs).
//! - [`optics`]: one bounce — F per channel, mirror and Snell directions, total internal
//!   reflection.
//! - [`trace`]: the bounce loop over any [`trace::Tracer`], the camera, frames rendered in
//!   parallel, and the exact f64 reference (BVH tracer, exact Fresnel).
//! - [`upsample`]: RGB albedos and lights lifted to spectra (Smits 1999, corrected to
//!   round-trip exactly).
//! - [`spectral`]: the spectral mode of the reference: per wavelength on a grid of the 1 nm
//!   samples of `colors`, dispersion, F(λ) at every bounce, Beer–Lambert inside.
//! - [`distance_map`]: the layered distance maps of GPU Gems 3 ch. 17 and their linear +
//!   secant search, as a tracer: the CPU twin the GPU shaders are held to, and the way to
//!   split an image's error into geometry (the map) and Fresnel (the method).
//! - [`image_error`]: a frame against its reference.
//! - [`packet`]: packets of rays from one origin traced together for occlusion (the
//!   ambient-occlusion reference's hemisphere rays).
//! - [`labels`]: text burned into pictures (8 × 8 bitmap font): labelled panels side by
//!   side, the signed maps' legends.
//! - [`pictures`]: frames as linear EXR and sRGB PNG, and false-colour error images.
//! - [`colour_bar`]: the scale rule of a false-colour picture (the 1-2-5 step above the
//!   99th percentile) and its legend with the values burned in.
//! - [`ao`]: surfel ambient occlusion, bent normals and their ray-traced reference.
//! - [`experiment`]: the scene's image-error experiment (geometry, Fresnel and total error
//!   per object, method, depth and search steps) and its `effects_errors` table.
//! - [`spectral_errors`]: the three-channel reference against the spectral one per object,
//!   index source and depth (`spectral_errors`), and the price of each.
//! - [`command`]: the `effects` stage: the scene with its overrides, the memory check of
//!   every size it asks for, the experiments it names, and their outputs as one set.
//!
//! - [`scene`]: scene files — objects, materials, the camera path, the effects a scene
//!   names — as pure, checked data (the GPU runner reads them too).
//!
//! Pure computation on plain data; scene files come in through [`scene`].

// `!(a <= b)` is written where a NaN must take the branch that `a > b` would skip.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod ao;
pub mod colour_bar;
pub mod command;
pub mod distance_map;
pub mod experiment;
pub mod geometry;
pub mod hero;
pub mod image_error;
pub mod labels;
pub mod optics;
pub mod packet;
pub mod pictures;
pub mod scene;
pub mod spectral;
pub mod spectral_errors;
pub mod trace;
pub mod upsample;

#[cfg(test)]
mod tests;

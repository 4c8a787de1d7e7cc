//! Surfel ambient occlusion: per-vertex accessibility, bent normals and diffuse
//! indirect light from disc-to-disc transfer, after Bunnell, "Dynamic Ambient Occlusion and
//! Indirect Lighting" (GPU Gems 2, ch. 14), with a ray-traced reference to measure it against.
//!
//! - [`surfel`]: one oriented disc per mesh vertex (centre, normal, a third of the adjacent
//!   triangles' area), robust to degenerate faces, duplicate and isolated vertices; and
//!   midpoint subdivision to make test and sweep meshes finer.
//! - [`shadow`]: the shadow an emitter disc casts on a receiving point (the form-factor
//!   approximation with horizon and back-face clamps), a pure f64 function.
//! - [`accessibility`]: accessibility by brute force over every emitter, in passes (pass k
//!   weights each emitter by its accessibility of pass k − 1), and bent normals.
//! - [`errors`]: the `ao_errors` rows (error per mesh, g, passes, hierarchy) and table.
//! - [`histogram`]: the `ao_histogram` table (the signed error's distribution per object,
//!   technique and passes; per vertex, per area and per pixel).
//! - [`experiment`]: a scene's surfel effects: surfels of every placed object, accessibility
//!   against the reference per object (brute force and tree, 1–3 passes), indirect light's
//!   error, and pictures with no AO, 1, 2, 3 passes and the reference.
//! - [`denoise`]: XeGTAO's edge-aware 3 × 3 spatial denoiser over a GTAO image.
//! - [`gtao`]: screen-space ground-truth AO (Jimenez et al. 2016) over a G-buffer of
//!   view-space points and normals: the technique engines ship, the surfels' comparison.
//! - [`hierarchy`]: surfels merged into a binary tree (parents: mean centre and normal,
//!   summed area), traversed from the root, descending only where an emitter is close
//!   relative to its size.
//! - [`indirect`]: direct light with shadow rays, one or two bounces of diffuse indirect
//!   light gathered from lit surfels' fronts (colour bleeding), and its one-bounce reference.
//! - [`reference`]: per-vertex accessibility by cosine-weighted hemisphere rays against the
//!   real triangles (the BVH of `super::geometry`), fixed seed, with its standard error.
//! - [`shapes`]: closed self-occluding meshes for tests and benchmarks (torus, bumpy sphere).
//!
//! The f64 code here is the CPU twin a GPU kernel is held to. Pure computation on plain data.

pub mod accessibility;
pub mod denoise;
pub mod errors;
pub mod experiment;
pub mod gtao;
pub mod hierarchy;
pub mod histogram;
pub mod indirect;
pub mod reference;
pub mod shadow;
pub mod shapes;
pub mod surfel;

#[cfg(test)]
mod tests;

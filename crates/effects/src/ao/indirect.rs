//! Diffuse indirect light (colour bleeding) from surfels, and its ray-traced reference.
//!
//! Direct light: a directional light of colour E_L (linear RGB, on a surface facing it)
//! towards the unit direction l gives E_d(x) = E_L · max(0, n·l) · V(x, l), a point light of
//! intensity I at distance d gives I · max(0, n·l) / d² · V, the visibility V by one shadow
//! ray through the scene's BVH (to the light, for a point light) — computed the same way at
//! surfels (for the twin) and at ray hits (for the reference), so the comparison measures
//! the transfer alone. Ambient sources bring no direct light here: accessibility scales them.
//!
//! Surfels (Bunnell, GPU Gems 2 ch. 14, indirect lighting): a lit surfel's front emits
//! radiosity B_j = ρ_j · E_d(j) (ρ the diffuse albedo per channel; B = π × radiance), and
//! a receiver gathers E₁(i) = Σ_j B_j · F_ij · w_j with F_ij the disc form factor to the
//! emitter's front ([`super::shadow::bounce`]) and w_j the emitter's weight
//! ([`EmitterWeight`]): 1 by default, or the emitter's accessibility (the chapter's
//! modulation: a front that is itself hidden shows less of itself). A second bounce repeats
//! the gather with B_j = ρ_j · E₁(j); the result is the sum of the bounces.
//!
//! Why 1: B_j already carries the emitter's shadowing (E_d has its shadow ray), and its
//! accessibility measures how much of *its* hemisphere is covered — by the very surfaces that
//! face it, which are the receivers it lights. A floor under a sphere has accessibility well
//! below 1 because the sphere is above it, and that is where the sphere's underside gets its
//! bounce; weighting by accessibility darkens exactly the emitters that matter. Measured on
//! `scenes/ao-colour-bleeding.yaml` (docs/ao.md): the sphere's one-bounce error falls from a
//! signed −0.065 (weight = accessibility) to near 0 with weight 1.
//!
//! Reference (one bounce): E₁(x) = ∫ L(y(ω)) cos θ dω with L = ρ(y) E_d(y) / π at the first
//! surface y the ray meets; with cosine-distributed directions the estimator is the mean of
//! ρ(y) E_d(y) over the rays (rays that leave the scene bring 0), standard error from the
//! sample variance per channel.

use glam::DVec3;
use rayon::prelude::*;

use super::reference::{cosine_direction, RaySettings, SplitMix64};
use super::shadow::{bounce, ShadowForm};
use super::surfel::Surfel;
use crate::geometry::Geometry;
use crate::scene::LightSource;

/// Linear RGB.
pub type Rgb = [f64; 3];

fn scaled(c: Rgb, s: f64) -> Rgb {
    c.map(|x| x * s)
}

fn times(a: Rgb, b: Rgb) -> Rgb {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

fn plus(a: Rgb, b: Rgb) -> Rgb {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// Direct irradiance at `point` with unit `normal` from `lights`, shadowed by `geometry`
/// (the shadow ray starts `offset` × the scene's size off the surface along the normal).
pub fn direct_irradiance(geometry: &Geometry, point: DVec3, normal: DVec3, lights: &[LightSource], offset: f64) -> Rgb {
    let origin = point + normal * (offset * geometry.size());
    lights.iter().fold([0.0; 3], |sum, light| {
        let arriving = match light {
            LightSource::Directional { direction, colour } => {
                let towards = -DVec3::from_array(*direction).normalize_or_zero();
                let cosine = normal.dot(towards);
                if !(cosine > 0.0) || geometry.occluded(origin, towards) {
                    return sum;
                }
                scaled(*colour, cosine)
            }
            LightSource::Point { position, intensity } => {
                let to_light = DVec3::from_array(*position) - point;
                let distance = to_light.length();
                let towards = to_light / distance;
                let cosine = normal.dot(towards);
                let blocked = || {
                    let from_origin = DVec3::from_array(*position) - origin;
                    let reach = from_origin.length();
                    geometry.nearest(origin, from_origin / reach, None, |_| true).is_some_and(|hit| hit.t < reach)
                };
                if !(cosine > 0.0 && distance > 0.0) || blocked() {
                    return sum;
                }
                scaled(*intensity, cosine / (distance * distance))
            }
            LightSource::Ambient { .. } => return sum,
        };
        plus(sum, arriving)
    })
}

/// Direct irradiance at every surfel.
pub fn surfel_direct(geometry: &Geometry, surfels: &[Surfel], lights: &[LightSource], offset: f64) -> Vec<Rgb> {
    surfels.par_iter().map(|s| direct_irradiance(geometry, s.centre, s.normal, lights, offset)).collect()
}

/// How a gather weights an emitter's radiosity.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EmitterWeight {
    /// 1: the radiosity as lit (its shadow ray already darkens it); the measured default.
    #[default]
    One,
    /// The emitter's accessibility (the chapter's modulation).
    Accessibility,
}

impl EmitterWeight {
    /// The per-emitter weights given the emitters' `accessibility`.
    pub fn weights(self, accessibility: &[f64]) -> Vec<f64> {
        match self {
            EmitterWeight::One => vec![1.0; accessibility.len()],
            EmitterWeight::Accessibility => accessibility.to_vec(),
        }
    }
}

/// Indirect irradiance at every surfel after `bounces` bounces (summed), by brute force
/// over emitters; `albedo` and `direct` per surfel, `weights` per emitter (accessibility,
/// or all 1).
pub fn surfel_indirect(surfels: &[Surfel], albedo: &[Rgb], direct: &[Rgb], weights: &[f64], form: ShadowForm, bounces: u32) -> Vec<Rgb> {
    let mut total = vec![[0.0; 3]; surfels.len()];
    let mut lighting: Vec<Rgb> = direct.to_vec();
    for _ in 0..bounces {
        let radiosity: Vec<Rgb> = lighting.iter().zip(albedo).map(|(e, rho)| times(*e, *rho)).collect();
        lighting = (0..surfels.len()).into_par_iter().map(|i| gather(surfels, i, &radiosity, weights, form)).collect();
        total = total.iter().zip(&lighting).map(|(t, e)| plus(*t, *e)).collect();
    }
    total
}

fn gather(surfels: &[Surfel], receiver: usize, radiosity: &[Rgb], weights: &[f64], form: ShadowForm) -> Rgb {
    let me = &surfels[receiver];
    let mut sum = [0.0; 3];
    for (j, emitter) in surfels.iter().enumerate() {
        if j != receiver {
            sum = plus(sum, scaled(radiosity[j], bounce(form, emitter, me.centre, me.normal) * weights[j]));
        }
    }
    sum
}

/// Per-surfel reference indirect irradiance (one bounce) and its standard error per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceIndirect {
    pub values: Vec<Rgb>,
    pub standard_errors: Vec<Rgb>,
    pub rays: u64,
}

/// One bounce of indirect irradiance at every surfel by cosine-distributed rays;
/// `albedo_of(object)` is the diffuse albedo of the object a ray meets.
pub fn reference_indirect(
    geometry: &Geometry,
    surfels: &[Surfel],
    albedo_of: &(dyn Fn(usize) -> Rgb + Sync),
    lights: &[LightSource],
    settings: RaySettings,
) -> ReferenceIndirect {
    let estimates: Vec<(Rgb, Rgb)> = nklut_tables::progress::par_map(surfels.len(), "bounce rays", |i| {
        one_bounce(geometry, &surfels[i], i as u64, albedo_of, lights, settings)
    });
    let (values, standard_errors) = estimates.into_iter().unzip();
    // Each ray costs a shadow ray per light at its hit besides itself.
    ReferenceIndirect { values, standard_errors, rays: surfels.len() as u64 * settings.rays as u64 * (1 + lights.len() as u64) }
}

fn one_bounce(
    geometry: &Geometry,
    surfel: &Surfel,
    stream: u64,
    albedo_of: &(dyn Fn(usize) -> Rgb + Sync),
    lights: &[LightSource],
    settings: RaySettings,
) -> (Rgb, Rgb) {
    let mut random = SplitMix64::new(settings.seed ^ 0xb0b, stream);
    let origin = surfel.centre + surfel.normal * (settings.offset * geometry.size());
    let rays = settings.rays.max(1);
    let (mut sum, mut squares) = ([0.0; 3], [0.0; 3]);
    for _ in 0..rays {
        let direction = cosine_direction(surfel.normal, random.next_f64(), random.next_f64());
        let Some(hit) = geometry.nearest(origin, direction, None, |_| true) else { continue };
        // The side of the surface the ray sees: a back face reflects nothing.
        if hit.normal.dot(direction) >= 0.0 {
            continue;
        }
        let sample = times(albedo_of(hit.object), direct_irradiance(geometry, hit.point, hit.normal, lights, settings.offset));
        sum = plus(sum, sample);
        squares = plus(squares, times(sample, sample));
    }
    let n = rays as f64;
    let mean = scaled(sum, 1.0 / n);
    let error = std::array::from_fn(|c| ((squares[c] / n - mean[c] * mean[c]).max(0.0) / n).sqrt());
    (mean, error)
}

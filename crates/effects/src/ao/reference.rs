//! The ray-traced reference of surfel accessibility: per surfel (mesh vertex), the fraction
//! of cosine-weighted hemisphere rays about its normal that leave the scene without meeting
//! a triangle — the Monte Carlo estimate of (1/π)∫ V(ω) cos θ dω. Rays run against the real
//! triangles in f64 through the BVH of `super::super::geometry` (the reflection effect's
//! reference), in parallel with rayon (a progress bar on a terminal); each surfel draws from its own SplitMix64 stream
//! (Steele, Lea and Flood, "Fast Splittable Pseudorandom Number Generators", OOPSLA 2014)
//! seeded by the fixed seed and its index, so results do not depend on the thread count.
//!
//! Directions: Malley's method (a uniform point on the unit disc lifted to the hemisphere
//! is cosine-distributed) in the orthonormal basis of Duff et al. ("Building an Orthonormal
//! Basis, Revisited", JCGT 6(1), 2017). Each estimate is a binomial proportion p̂ of N rays,
//! its standard error √(p̂(1 − p̂)/N) reported with it.

use glam::DVec3;

use super::surfel::Surfel;
use crate::geometry::Geometry;

/// How many rays, from which seed, how far along its normal a ray starts off the surface
/// (a fraction of the scene's size, `Geometry::size`: 10⁻⁶ of it, ten times the self-hit
/// distance, at every scale; so a ray leaving a vertex does not meet the faces there), and whether the
/// rays go in packets (one BVH walk per direction bin) or one by one — the same counts
/// either way; one by one is the benchmark's anchor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RaySettings {
    pub rays: u32,
    pub seed: u64,
    pub offset: f64,
    pub packets: bool,
}

impl Default for RaySettings {
    fn default() -> RaySettings {
        RaySettings { rays: 4096, seed: 0x005e_eda0, offset: 1e-6, packets: true }
    }
}

/// Per-surfel reference accessibility and its standard error.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceAccessibility {
    pub values: Vec<f64>,
    pub standard_errors: Vec<f64>,
    pub rays: u64,
}

impl ReferenceAccessibility {
    /// The largest per-surfel standard error.
    pub fn max_standard_error(&self) -> f64 {
        self.standard_errors.iter().copied().fold(0.0, f64::max)
    }

    /// The mean of the per-surfel standard errors: how far the reference's noise can move
    /// a mean absolute error judged against it (E|x + e| − |x| ≤ E|e| ≤ σ).
    pub fn mean_standard_error(&self) -> f64 {
        self.standard_errors.iter().sum::<f64>() / self.standard_errors.len().max(1) as f64
    }
}

/// SplitMix64: a 64-bit counter through a mixing function.
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64, stream: u64) -> SplitMix64 {
        let mut first = SplitMix64(seed ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        first.next_u64();
        first
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Two unit vectors completing `n` (unit) to a right-handed orthonormal basis.
pub fn basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// A cosine-distributed direction about `n` from two uniform numbers (Malley's method).
pub fn cosine_direction(n: DVec3, u1: f64, u2: f64) -> DVec3 {
    Hemisphere::about(n).direction(u1, u2)
}

/// The hemisphere about a unit normal, in the basis [`basis`] completes it to, formed once
/// for all the rays of a vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hemisphere {
    tangent: DVec3,
    bitangent: DVec3,
    normal: DVec3,
}

impl Hemisphere {
    pub fn about(normal: DVec3) -> Hemisphere {
        let (tangent, bitangent) = basis(normal);
        Hemisphere { tangent, bitangent, normal }
    }

    /// The cosine-distributed direction of (u1, u2): the point (√u1 cos 2πu2, √u1 sin 2πu2)
    /// of the unit disc lifted to the hemisphere (Malley's method).
    #[inline(always)]
    pub fn direction(&self, u1: f64, u2: f64) -> DVec3 {
        let radius = u1.sqrt();
        let (sin, cos) = sin_cos_of_turns(u2);
        self.tangent * (radius * cos) + self.bitangent * (radius * sin) + self.normal * (1.0 - u1).max(0.0).sqrt()
    }
}

/// (sin 2πu, cos 2πu) for u in [0, 1) (any finite u is taken modulo 1 by its quadrant):
/// 4u splits exactly into a quadrant q and a remainder f in [−½, ½], the angle a = f·π/2
/// lies in [−π/4, π/4], and the Taylor series of sin a and cos a to the a¹⁷ and a¹⁸ terms
/// (truncation below 10⁻¹⁹ there) give both, rotated by q quarter turns: no call and no
/// branch but the quadrant's selects. Agrees with libm's sin(2πu) and cos(2πu) to 10⁻¹⁵
/// (the rounding of 2πu itself); exact at the quarter turns.
#[inline(always)]
pub fn sin_cos_of_turns(u: f64) -> (f64, f64) {
    let quarters = u * 4.0;
    let q = (quarters + 0.5).floor();
    let a = (quarters - q) * std::f64::consts::FRAC_PI_2;
    let a2 = a * a;
    // sin a = a (1 − a²/3! + a⁴/5! − …), cos a = 1 − a²/2! + a⁴/4! − …, by Horner.
    let sin_series = 1.0
        + a2 * (-1.0 / 6.0
            + a2 * (1.0 / 120.0
                + a2 * (-1.0 / 5040.0
                    + a2 * (1.0 / 362_880.0
                        + a2 * (-1.0 / 39_916_800.0
                            + a2 * (1.0 / 6_227_020_800.0 + a2 * (-1.0 / 1_307_674_368_000.0 + a2 * (1.0 / 355_687_428_096_000.0))))))));
    let cos_series = 1.0
        + a2 * (-0.5
            + a2 * (1.0 / 24.0
                + a2 * (-1.0 / 720.0
                    + a2 * (1.0 / 40_320.0
                        + a2 * (-1.0 / 3_628_800.0
                            + a2 * (1.0 / 479_001_600.0
                                + a2 * (-1.0 / 87_178_291_200.0
                                    + a2 * (1.0 / 20_922_789_888_000.0 + a2 * (-1.0 / 6_402_373_705_728_000.0)))))))));
    let (sin_a, cos_a) = (a * sin_series, cos_series);
    let quadrant = (q as i64).rem_euclid(4);
    let (sin, cos) = if quadrant & 1 == 0 { (sin_a, cos_a) } else { (cos_a, -sin_a) };
    if quadrant & 2 == 0 {
        (sin, cos)
    } else {
        (-sin, -cos)
    }
}

/// The reference accessibility of every surfel against `geometry`.
pub fn reference_accessibility(geometry: &Geometry, surfels: &[Surfel], settings: RaySettings) -> ReferenceAccessibility {
    reference_accessibility_within(geometry, surfels, settings, f64::INFINITY)
}

/// The reference accessibility counting only occluders closer than `reach` (a range-limited
/// reference: what an AO radius could see at best; ∞ gives [`reference_accessibility`]).
pub fn reference_accessibility_within(
    geometry: &Geometry,
    surfels: &[Surfel],
    settings: RaySettings,
    reach: f64,
) -> ReferenceAccessibility {
    let estimates: Vec<(f64, f64)> =
        nklut_tables::progress::par_map(surfels.len(), "ao rays", |i| open_fraction(geometry, &surfels[i], i as u64, settings, reach));
    let (values, standard_errors) = estimates.into_iter().unzip();
    ReferenceAccessibility { values, standard_errors, rays: surfels.len() as u64 * settings.rays as u64 }
}

/// The ray-traced bent normal of every surfel: the normalised mean of the directions of its
/// cosine-distributed rays that meet nothing (the mean unoccluded direction), `None` where
/// every ray is blocked. Rays one by one from the surfel's own stream of a seed apart from
/// the accessibility's.
pub fn reference_bent_normals(geometry: &Geometry, surfels: &[Surfel], settings: RaySettings) -> Vec<Option<DVec3>> {
    nklut_tables::progress::par_map(surfels.len(), "bent normal rays", |i| {
        let surfel = &surfels[i];
        let mut random = SplitMix64::new(settings.seed ^ 0xbe27, i as u64);
        let origin = surfel.centre + surfel.normal * (settings.offset * geometry.size());
        let hemisphere = Hemisphere::about(surfel.normal);
        let sum = (0..settings.rays.max(1)).fold(DVec3::ZERO, |sum, _| {
            let direction = hemisphere.direction(random.next_f64(), random.next_f64());
            if geometry.occluded(origin, direction) {
                sum
            } else {
                sum + direction
            }
        });
        sum.try_normalize()
    })
}

/// Angles in degrees between unit vectors `a` and the reference's (`None`: left out).
pub fn angles_degrees(a: &[DVec3], reference: &[Option<DVec3>]) -> Vec<f64> {
    a.iter().zip(reference).filter_map(|(v, r)| r.map(|r| v.dot(r).clamp(-1.0, 1.0).acos().to_degrees())).collect()
}

/// Rays per direction bin (on average): the packets [`Geometry::open_rays`] traces together.
const RAYS_PER_PACKET: u32 = 48;

/// The fraction of rays from `surfel` that meet nothing, and its standard error. The rays
/// are drawn in turn from the surfel's stream; in packets they are grouped by where their
/// (u1, u2) fall on a grid of the unit square — neighbouring cells of the square are
/// neighbouring patches of the hemisphere under Malley's map — and each group is traced as
/// one packet, which counts what its rays count one by one.
fn open_fraction(geometry: &Geometry, surfel: &Surfel, stream: u64, settings: RaySettings, reach: f64) -> (f64, f64) {
    let mut random = SplitMix64::new(settings.seed, stream);
    let origin = surfel.centre + surfel.normal * (settings.offset * geometry.size());
    let rays = settings.rays.max(1);
    let open = if settings.packets && reach == f64::INFINITY {
        open_in_packets(geometry, origin, surfel.normal, rays, &mut random)
    } else {
        open_one_by_one(geometry, origin, surfel.normal, rays, reach, &mut random)
    };
    let p = open as f64 / rays as f64;
    (p, (p * (1.0 - p) / rays as f64).sqrt())
}

/// How many of `rays` cosine-weighted rays about `normal` meet nothing, traced one by one.
fn open_one_by_one(geometry: &Geometry, origin: DVec3, normal: DVec3, rays: u32, reach: f64, random: &mut SplitMix64) -> usize {
    (0..rays)
        .filter(|_| {
            let direction = cosine_direction(normal, random.next_f64(), random.next_f64());
            !geometry.occluded_within(origin, direction, reach)
        })
        .count()
}

/// The same rays as [`open_one_by_one`], grouped by direction bin (a counting sort by
/// cell) and traced as packets.
fn open_in_packets(geometry: &Geometry, origin: DVec3, normal: DVec3, rays: u32, random: &mut SplitMix64) -> usize {
    let grid = DirectionGrid::for_rays(rays);
    let drawn: Vec<(usize, [f64; 2])> = (0..rays)
        .map(|_| {
            let (u1, u2) = (random.next_f64(), random.next_f64());
            (grid.cell(u1, u2), [u1, u2])
        })
        .collect();
    let mut starts = vec![0usize; grid.cells() + 1];
    for (cell, _) in &drawn {
        starts[cell + 1] += 1;
    }
    for cell in 0..grid.cells() {
        starts[cell + 1] += starts[cell];
    }
    let mut next = starts.clone();
    let mut sorted = vec![[0.0; 2]; drawn.len()];
    for (cell, numbers) in drawn {
        sorted[next[cell]] = numbers;
        next[cell] += 1;
    }
    let hemisphere = Hemisphere::about(normal);
    let directions: Vec<DVec3> = sorted.iter().map(|&[u1, u2]| hemisphere.direction(u1, u2)).collect();
    starts.windows(2).map(|bin| geometry.open_rays(origin, &directions[bin[0]..bin[1]])).sum()
}

/// A grid over the unit square of (u1, u2) — u1 is sin²θ, u2 the azimuth over 2π — with
/// about [`RAYS_PER_PACKET`] rays per cell and twice as many azimuth columns as rows, so a
/// cell spans comparable angles both ways.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DirectionGrid {
    rows: usize,
    columns: usize,
}

impl DirectionGrid {
    fn for_rays(rays: u32) -> DirectionGrid {
        let cells = (rays / RAYS_PER_PACKET).max(1) as f64;
        let rows = (cells / 2.0).sqrt().round().max(1.0) as usize;
        DirectionGrid { rows, columns: ((cells / rows as f64).round() as usize).max(1) }
    }

    fn cells(&self) -> usize {
        self.rows * self.columns
    }

    fn cell(&self, u1: f64, u2: f64) -> usize {
        let row = ((u1 * self.rows as f64) as usize).min(self.rows - 1);
        let column = ((u2 * self.columns as f64) as usize).min(self.columns - 1);
        row * self.columns + column
    }
}

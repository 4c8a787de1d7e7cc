//! The scene's triangles for the CPU ray tracers: every object's mesh placed in the scene,
//! smooth normals interpolated across each triangle as a rasteriser interpolates them, and a
//! BVH over them.
//!
//! The BVH is obvhs's compressed wide BVH (8-wide, PLOC build; Ylitie, Karras and Laine,
//! "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017). Its
//! node tests run in f32; the triangle test is ours and runs in f64 — the watertight test of
//! Woop, Benthin and Wald ("Watertight Ray/Triangle Intersection", JCGT 2(1), 2013), so a
//! ray through a shared edge or vertex (the centre of a UV sphere's face, say) hits at least
//! one of the triangles there, as a rasteriser would — and the distance it hands
//! back to the traversal is rounded up to the next f32, so a node is never culled against a
//! distance shorter than the true nearest hit. obvhs's node test starts every ray at
//! t = 1e-4 (scene units), so a leaf box the ray has already left by then would not be
//! entered and a crossing nearer than that inside it would be lost (on the bunny normalised
//! to the unit sphere: one ambient-occlusion ray in 8.9 M, an occluder at t = 1.3e-6 in a
//! box left at 1.6e-6). So the traversal's ray starts [`TRAVERSAL_BACKOFF`] behind the true
//! origin and every distance handed to it is shifted by as much; the triangle test keeps
//! the true origin, so the hits and their distances are unchanged.
//!
//! Rays that share an origin and nearly a direction (the ambient-occlusion reference's) can
//! instead be traced as packets over a second, binary BVH (`super::packet`), with the same
//! triangle test and so the same answers.

use std::sync::OnceLock;

use glam::{DVec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::cwbvh::builder::build_cwbvh;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};
use obvhs::BvhBuildParams;

use super::packet::{Corners, Packet, PacketTree, RayMask, PACKET_RAYS};
use crate::scene::mesh::{widen, wound_against_normals, Mesh};
pub use crate::scene::mesh::{GeometryError, MAX_CORNER};
use nklut_tables::budget::{MemoryBudget, TooLarge};

/// Hits closer to the ray's origin than this fraction of the scene's size R (its largest
/// corner coordinate, [`Geometry::size`]) are the surface the ray leaves, not a new one:
/// 10⁻⁷R — a tenth of a micrometre in a scene a metre across, a tenth of a nanometre in one
/// a millimetre across. A placed mesh's f32 corners are rounded to 2⁻²⁴R ≈ 6·10⁻⁸R, so no
/// surface a scene can hold is nearer to another than about that; a hit point computed in
/// f64 strays by some 2⁻⁵²R ≈ 2·10⁻¹⁶R, far below it. Relative, so a scene scaled by any
/// factor in `scene::SCALE_RANGE` (10⁻⁴–10⁴) finds the same hits.
pub const SELF_HIT_RELATIVE: f64 = 1e-7;

/// obvhs 0.4's node test clamps every ray's start to t = 10⁻⁴ in the traversal ray's units
/// (`cwbvh::node::EPSILON`): an absolute length, whatever the scene's size.
const OBVHS_T_MIN: f64 = 1e-4;

/// How far behind the true origin the traversal's ray starts: twice [`OBVHS_T_MIN`], so no
/// box around a crossing near the origin is skipped. Absolute because obvhs's start is; the
/// f32 rounding of the moved start (≈ 2⁻²⁴(R + this)) is covered by [`BOX_PADDING`], which
/// is taken relative to R + this.
const TRAVERSAL_BACKOFF: f64 = 2.0 * OBVHS_T_MIN;

/// How far each triangle's box is widened for the BVH's f32 node test, relative to the
/// extent the traversal's rays span, R + [`TRAVERSAL_BACKOFF`] (R the scene's size, its
/// largest corner coordinate). The node test rounds: the traversal's ray is the f64 ray
/// rounded to f32 (origin and direction, 2⁻²⁴ relative each) and each slab distance takes
/// three roundings, so the ray the boxes see strays from the true one by about
/// 4·2⁻²⁴·(|o| + t) ≈ 2.4·10⁻⁷(|o| + t), at most 1.3·10⁻⁶·(R + backoff) for a ray from
/// inside the scene's box (|o| ≤ √3R, moved back by the backoff) to a hit in it
/// (t ≤ 2√3R plus the backoff). Unwidened, a ray through an edge where two flat boxes
/// meet — a room's corner, seen along a diagonal plane — could enter neither and leave a
/// closed room, the watertight triangle test never run. 4·10⁻⁶ is three times the stray.
const BOX_PADDING: f64 = 4e-6;

/// Direction components smaller than this are zero for the BVH traversal (not for the
/// triangle test). A fraction of a unit direction, so free of the scene's scale: the
/// traversal's ray turns by under 10⁻⁶ rad, straying by at most 10⁻⁶·t ≤ 3.5·10⁻⁶R from
/// the true ray inside the scene's box, which the boxes' padding and the quantisation of
/// obvhs's nodes (outwards) leave inside every box the true ray enters.
const TINY_DIRECTION: f64 = 1e-6;

/// One triangle in f64 with its vertex normals and the object it belongs to.
#[derive(Clone, Copy, Debug)]
struct Triangle {
    corners: [DVec3; 3],
    normals: [DVec3; 3],
    object: u32,
}

/// Where a ray meets a triangle: distance t along the ray and the barycentric weights
/// (u, v) of its second and third corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f64,
    pub u: f64,
    pub v: f64,
}

impl Triangle {
    /// The watertight test, both faces; `None` when the ray misses or runs in the plane.
    /// Coordinates are moved to the ray's origin and sheared so the ray runs along +z; the
    /// signed edge functions then decide inside-ness exactly on shared edges.
    #[inline(always)]
    fn crossing(&self, origin: DVec3, direction: DVec3) -> Option<Crossing> {
        crossing_from(self.corners.map(|corner| corner - origin), &Shear::of(direction))
    }

    /// The interpolated vertex normal at (u, v), normalised.
    fn normal(&self, u: f64, v: f64) -> DVec3 {
        let [na, nb, nc] = self.normals;
        let n = na * (1.0 - u - v) + nb * u + nc * v;
        let [a, b, c] = self.corners;
        let geometric = (b - a).cross(c - a);
        n.try_normalize().or_else(|| geometric.try_normalize()).unwrap_or(DVec3::Z)
    }

    /// The triangle's box for obvhs's f32 node test, widened by `pad` on every side.
    fn padded_box(&self, pad: f64) -> Aabb {
        let (low, high) = self.corners.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
        let narrow = |p: DVec3| Vec3A::new(p.x as f32, p.y as f32, p.z as f32);
        Aabb::new(narrow(low - DVec3::splat(pad)), narrow(high + DVec3::splat(pad)))
    }

    /// The triangle's own unit normal (its plane's), turned to the side its vertex normals
    /// point to (the mesh's outside, whatever the winding: [`wound_against_normals`]); the
    /// interpolated normal where the plane is degenerate.
    fn geometric(&self, u: f64, v: f64) -> DVec3 {
        let [a, b, c] = self.corners;
        match (b - a).cross(c - a).try_normalize() {
            Some(plane) if wound_against_normals(self.corners, self.normals) => -plane,
            Some(plane) => plane,
            None => self.normal(u, v),
        }
    }
}

/// The watertight test of a ray (its shear) against a triangle whose corners are given
/// relative to the ray's origin (`corner − origin`: per ray in [`Triangle::crossing`], once
/// for all the rays of a packet in [`Geometry::open_rays`]).
#[inline(always)]
pub fn crossing_from(relative: [DVec3; 3], shear: &Shear) -> Option<Crossing> {
    match shear.axis {
        Axis::X => crossing_along::<1, 2, 0>(relative, shear.factors),
        Axis::Y => crossing_along::<2, 0, 1>(relative, shear.factors),
        Axis::Z => crossing_along::<0, 1, 2>(relative, shear.factors),
    }
}

/// The watertight test with the ray's dominant axis `KZ` fixed at compile time, so the
/// permutation is a register shuffle rather than indexing. A triangle is rejected as soon
/// as two edge functions disagree in sign; the depths are sheared only for a crossing.
#[inline(always)]
fn crossing_along<const KX: usize, const KY: usize, const KZ: usize>(relative: [DVec3; 3], [sx, sy, sz]: [f64; 3]) -> Option<Crossing> {
    let [p0, p1, p2] = relative.map(|p| (p[KX] + sx * p[KZ], p[KY] + sy * p[KZ]));
    let e0 = p1.0 * p2.1 - p1.1 * p2.0;
    let e1 = p2.0 * p0.1 - p2.1 * p0.0;
    if (e0 < 0.0 && e1 > 0.0) || (e0 > 0.0 && e1 < 0.0) {
        return None;
    }
    let e2 = p0.0 * p1.1 - p0.1 * p1.0;
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let determinant = e0 + e1 + e2;
    if determinant == 0.0 || !determinant.is_finite() {
        return None;
    }
    let [z0, z1, z2] = relative.map(|p| p[KZ] * sz);
    let inverse = 1.0 / determinant;
    let t = (e0 * z0 + e1 * z1 + e2 * z2) * inverse;
    Some(Crossing { t, u: e1 * inverse, v: e2 * inverse })
}

/// The rays of a packet by heading: the axis each runs most along (its shear's axis) and
/// whether it runs towards +∞ or −∞ on it; six sets of rays.
pub struct Headings([RayMask; 6]);

impl Headings {
    pub fn of(shears: &[Shear]) -> Headings {
        let mut headings = [0; 6];
        for (ray, shear) in shears.iter().enumerate() {
            headings[shear.heading()] |= 1 << ray;
        }
        Headings(headings)
    }

    /// The rays a triangle (corners less the rays' origin) lies behind: those heading
    /// towards +∞ on an axis where no corner is above 0, or towards −∞ where none is below.
    /// For them the watertight test's depths z = p[kz]/d[kz] are all ≤ 0, so its t — a
    /// weighted sum of the depths, each product keeping the sign the weights' common sign
    /// gives it — is ≤ 0 in floating point too: no such ray is blocked, and the test need
    /// not run.
    #[inline(always)]
    pub fn behind(&self, relative: &[DVec3; 3]) -> RayMask {
        let mut rays = 0;
        for axis in 0..3 {
            let coordinates = relative.map(|p| p[axis]);
            if coordinates.iter().all(|&c| c <= 0.0) {
                rays |= self.0[2 * axis];
            }
            if coordinates.iter().all(|&c| c >= 0.0) {
                rays |= self.0[2 * axis + 1];
            }
        }
        rays
    }
}

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Axis {
    X,
    Y,
    Z,
}

/// A ray's shear for the watertight test (Woop et al.): the axis it runs most along, which
/// becomes z (the other two following it cyclically), and the factors (−dx/dz, −dy/dz,
/// 1/dz) in that frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shear {
    axis: Axis,
    factors: [f64; 3],
}

impl Shear {
    #[inline(always)]
    pub fn of(direction: DVec3) -> Shear {
        let (axis, [kx, ky, kz]) = match direction.abs().max_position() {
            0 => (Axis::X, [1, 2, 0]),
            1 => (Axis::Y, [2, 0, 1]),
            _ => (Axis::Z, [0, 1, 2]),
        };
        let (dx, dy, dz) = (direction[kx], direction[ky], direction[kz]);
        Shear { axis, factors: [-dx / dz, -dy / dz, 1.0 / dz] }
    }

    /// 2·axis, plus 1 when the ray runs towards −∞ on it (1/dz < 0): its set in [`Headings`].
    fn heading(&self) -> usize {
        2 * self.axis as usize + usize::from(self.factors[2] < 0.0)
    }
}

/// The nearest surface along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub point: DVec3,
    /// The interpolated (smooth) unit normal, on the side the mesh's normals point to.
    pub normal: DVec3,
    /// The triangle's plane normal on the same side: what decides whether a ray arrives
    /// from outside or inside (an interpolated normal can face a grazing ray that the
    /// triangle itself faces away from).
    pub geometric: DVec3,
    /// Index of the object in the scene's object list.
    pub object: usize,
    /// Index of the triangle in the geometry (to leave it without hitting it again).
    pub triangle: u32,
}

/// All of a scene's triangles and their BVH; the binary BVH for ray packets is built the
/// first time a packet asks for it.
pub struct Geometry {
    triangles: Vec<Triangle>,
    bvh: CwBvh,
    packet_tree: OnceLock<PacketTree>,
    /// The scene's size R: its largest corner coordinate.
    size: f64,
    /// [`SELF_HIT_RELATIVE`] × R.
    self_hit: f64,
}

pub use crate::scene::mesh::{traced_bytes, BYTES_PER_TRACED_TRIANGLE};

/// Check that the meshes of a scene loaded so far, up to `objects[object]` (`triangles` in
/// all, `label` the last one's mesh), fit `budget` at [`traced_bytes`]: the one geometry
/// check of every path that loads a scene's meshes, before what it builds of them (the
/// traced stage; the GPU runner's and the browser bench's raster meshes, which hold less:
/// no f64 triangles and no BVH).
pub fn check_loaded(budget: &MemoryBudget, object: usize, triangles: u128, label: &str) -> Result<(), TooLarge> {
    budget.check(
        &format!("objects[{object}]"),
        format!("the geometry of objects 0–{object} ({triangles} triangles, {label} the last)"),
        traced_bytes(triangles),
    )
}

/// Triangles per leaf of the packets' binary BVH.
const PACKET_LEAF_TRIANGLES: u32 = 2;

impl Geometry {
    /// The placed meshes, one per object, in the scene's object order.
    pub fn new(meshes: &[Mesh]) -> Result<Geometry, GeometryError> {
        let mut triangles = Vec::new();
        for (object, mesh) in meshes.iter().enumerate() {
            for corner in mesh.indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|i| widen(mesh.positions[corner[i] as usize]));
                if let Some(far) = [a, b, c].into_iter().find(|p| !(p.abs().max_element() <= MAX_CORNER)) {
                    return Err(GeometryError::OutOfBounds { object, triangle: triangles.len(), corner: far.to_array() });
                }
                let normals = [0, 1, 2].map(|i| widen(mesh.normals[corner[i] as usize]));
                triangles.push(Triangle { corners: [a, b, c], normals, object: object as u32 });
            }
        }
        if triangles.is_empty() {
            return Err(GeometryError::Empty);
        }
        // The smallest positive f64 where every corner is at the origin (no triangle has area).
        let size = triangles.iter().flat_map(|t| t.corners).fold(f64::MIN_POSITIVE, |r, p| r.max(p.abs().max_element()));
        let boxes: Vec<Aabb> = triangles.iter().map(|t| t.padded_box(BOX_PADDING * (size + TRAVERSAL_BACKOFF))).collect();
        let bvh = build_cwbvh(&boxes, BvhBuildParams::medium_build(), &mut Default::default());
        Ok(Geometry { triangles, bvh, packet_tree: OnceLock::new(), size, self_hit: SELF_HIT_RELATIVE * size })
    }

    /// The centre of the bounding box of `object`'s triangles (the origin if it has none).
    pub fn object_centre(&self, object: usize) -> DVec3 {
        let corners = self.triangles.iter().filter(|t| t.object as usize == object).flat_map(|t| t.corners);
        let (low, high) = corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(low, high), p| (low.min(p), high.max(p)));
        if low.is_finite() {
            (low + high) * 0.5
        } else {
            DVec3::ZERO
        }
    }

    pub fn triangles(&self) -> usize {
        self.triangles.len()
    }

    /// The scene's size R: its largest corner coordinate, what f32 positions are rounded
    /// relative to and the scene-relative lengths ([`SELF_HIT_RELATIVE`]) are fractions of.
    pub fn size(&self) -> f64 {
        self.size
    }

    /// Hits nearer than this to a ray's origin are the surface it leaves:
    /// [`SELF_HIT_RELATIVE`] × [`Geometry::size`].
    pub fn self_hit_distance(&self) -> f64 {
        self.self_hit
    }

    /// The traversal's f32 ray. Direction components below [`TINY_DIRECTION`] in size are
    /// flushed to +0: obvhs 0.4 loses every hit of a ray whose direction has a tiny
    /// negative component (−1e-8, say; see the test `tiny_direction_components_keep_their_hits`).
    /// That turns the traversal ray by under 1e-6 rad; node boxes are quantised outwards.
    /// The ray starts [`TRAVERSAL_BACKOFF`] behind `origin`.
    fn bvh_ray(origin: DVec3, direction: DVec3) -> Ray {
        let narrow = |p: DVec3| Vec3A::new(p.x as f32, p.y as f32, p.z as f32);
        let flush = |x: f64| if x.abs() < TINY_DIRECTION { 0.0 } else { x };
        let start = origin - direction * TRAVERSAL_BACKOFF;
        Ray::new(narrow(start), narrow(DVec3::new(flush(direction.x), flush(direction.y), flush(direction.z))), 0.0, f32::INFINITY)
    }

    /// The nearest hit along origin + t·direction (direction of unit length) with
    /// t > [`Geometry::self_hit_distance`], skipping triangle `leaving` (the surface the ray starts on)
    /// and objects for which `include` is false.
    pub fn nearest(&self, origin: DVec3, direction: DVec3, leaving: Option<u32>, include: impl Fn(usize) -> bool) -> Option<Hit> {
        if !(origin.is_finite() && direction.is_finite()) {
            return None; // a degenerate ray meets nothing
        }
        let mut best: Option<(f64, Crossing, u32)> = None;
        let mut found = RayHit::none();
        self.bvh.ray_traverse(Self::bvh_ray(origin, direction), &mut found, |_, id| {
            let index = self.bvh.primitive_indices[id];
            let triangle = &self.triangles[index as usize];
            if Some(index) == leaving || !include(triangle.object as usize) {
                return f32::INFINITY;
            }
            match triangle.crossing(origin, direction) {
                Some(c) if c.t > self.self_hit && best.is_none_or(|(t, _, _)| c.t < t) => {
                    best = Some((c.t, c, index));
                    ((c.t + TRAVERSAL_BACKOFF) as f32).next_up()
                }
                _ => f32::INFINITY,
            }
        });
        best.map(|(t, crossing, index)| self.hit(t, crossing, index, origin, direction))
    }

    /// Whether the ray meets any triangle at t > [`Geometry::self_hit_distance`] (an occlusion query
    /// for ambient occlusion and shadow rays): the traversal stops at the first such crossing
    /// instead of searching for the nearest.
    pub fn occluded(&self, origin: DVec3, direction: DVec3) -> bool {
        self.occluded_within(origin, direction, f64::INFINITY)
    }

    /// [`Geometry::occluded`] counting only crossings closer than `reach` (a range-limited
    /// occlusion query: what an AO radius sees).
    pub fn occluded_within(&self, origin: DVec3, direction: DVec3, reach: f64) -> bool {
        if !(origin.is_finite() && direction.is_finite()) {
            return false;
        }
        let escaped = self.bvh.ray_traverse_miss(Self::bvh_ray(origin, direction), |_, id| {
            let index = self.bvh.primitive_indices[id];
            let crossed = self.triangles[index as usize].crossing(origin, direction).is_some_and(|c| c.t > self.self_hit && c.t < reach);
            if crossed {
                0.0
            } else {
                f32::INFINITY
            }
        });
        !escaped
    }

    /// How many of the rays from `origin` along `directions` (unit vectors, best close to one
    /// another: the rays of one vertex in one direction bin) meet no triangle at
    /// t > [`Geometry::self_hit_distance`] — the count [`Geometry::occluded`] gives ray by ray, found
    /// by tracing them as packets of up to [`PACKET_RAYS`] (`super::packet`).
    pub fn open_rays(&self, origin: DVec3, directions: &[DVec3]) -> usize {
        if !origin.is_finite() {
            return directions.len();
        }
        let tree = self.packet_tree();
        directions
            .chunks(PACKET_RAYS)
            .map(|chunk| {
                if !chunk.iter().all(|d| d.is_finite()) {
                    return chunk.iter().filter(|d| !self.occluded(origin, **d)).count();
                }
                let packet = Packet::new(origin, chunk);
                let shears: Vec<Shear> = chunk.iter().map(|d| Shear::of(*d)).collect();
                let headings = Headings::of(&shears);
                tree.open_rays(
                    &packet,
                    #[inline(always)]
                    |relative, rays| {
                        let mut candidates = rays & !headings.behind(relative);
                        let mut blocked = 0;
                        while candidates != 0 {
                            let ray = candidates.trailing_zeros() as usize;
                            candidates &= candidates - 1;
                            if crossing_from(*relative, &shears[ray]).is_some_and(|c| c.t > self.self_hit) {
                                blocked |= 1 << ray;
                            }
                        }
                        blocked
                    },
                )
            })
            .sum()
    }

    /// [`Geometry::nearest`] over every object for rays that share an origin (the
    /// wavelengths one refraction bends each by its own n), traced together as packets of up
    /// to [`PACKET_RAYS`] over the packet tree, each ray's walk ending at its nearest
    /// crossing so far. The triangle test is the same, so is each ray's nearest distance (at
    /// an exact tie, two triangles through one edge, either may be named).
    pub fn nearest_rays(&self, origin: DVec3, directions: &[DVec3], leaving: Option<u32>) -> Vec<Option<Hit>> {
        if directions.len() < 2 || !origin.is_finite() || !directions.iter().all(|d| d.is_finite()) {
            return directions.iter().map(|d| self.nearest(origin, *d, leaving, |_| true)).collect();
        }
        let tree = self.packet_tree();
        let mut hits = Vec::with_capacity(directions.len());
        for chunk in directions.chunks(PACKET_RAYS) {
            let mut packet = Packet::new(origin, chunk);
            let shears: Vec<Shear> = chunk.iter().map(|d| Shear::of(*d)).collect();
            let headings = Headings::of(&shears);
            // Each ray's nearest crossing as the walk found it, beside the distance it keeps.
            let mut crossings: [Option<Crossing>; PACKET_RAYS] = [None; PACKET_RAYS];
            let nearest = tree.nearest(&mut packet, |index, relative, rays, nearest| {
                if Some(index) == leaving {
                    return;
                }
                let mut candidates = rays & !headings.behind(relative);
                while candidates != 0 {
                    let ray = candidates.trailing_zeros() as usize;
                    candidates &= candidates - 1;
                    if let Some(c) = crossing_from(*relative, &shears[ray]) {
                        if c.t > self.self_hit && nearest[ray].is_none_or(|(t, _)| c.t < t) {
                            nearest[ray] = Some((c.t, index));
                            crossings[ray] = Some(c);
                        }
                    }
                }
            });
            hits.extend(chunk.iter().zip(nearest).zip(crossings).map(|((&direction, found), crossing)| {
                let ((t, index), crossing) = (found?, crossing?);
                Some(self.hit(t, crossing, index, origin, direction))
            }));
        }
        hits
    }

    /// The packet tree, built on first use.
    fn packet_tree(&self) -> &PacketTree {
        self.packet_tree.get_or_init(|| {
            let narrow = |p: DVec3| [p.x as f32, p.y as f32, p.z as f32];
            let corners: Vec<Corners> = self.triangles.iter().map(|t| t.corners.map(narrow)).collect();
            PacketTree::new(&corners, PACKET_LEAF_TRIANGLES)
        })
    }

    fn hit(&self, t: f64, crossing: Crossing, index: u32, origin: DVec3, direction: DVec3) -> Hit {
        let triangle = &self.triangles[index as usize];
        Hit {
            t,
            point: origin + direction * t,
            normal: triangle.normal(crossing.u, crossing.v),
            geometric: triangle.geometric(crossing.u, crossing.v),
            object: triangle.object as usize,
            triangle: index,
        }
    }

    /// Every hit along the ray (t > [`Geometry::self_hit_distance`]) on objects for which `include`
    /// is true, nearest first; hits within [`Geometry::self_hit_distance`] of each other (a ray through
    /// an edge shared by two triangles) count once.
    pub fn all_hits(&self, origin: DVec3, direction: DVec3, include: impl Fn(usize) -> bool) -> Vec<Hit> {
        if !(origin.is_finite() && direction.is_finite()) {
            return Vec::new();
        }
        let mut crossings: Vec<(f64, Crossing, u32)> = Vec::new();
        self.bvh.ray_traverse_anyhit(Self::bvh_ray(origin, direction), |_, id| {
            let index = self.bvh.primitive_indices[id];
            let triangle = &self.triangles[index as usize];
            if include(triangle.object as usize) {
                if let Some(c) = triangle.crossing(origin, direction) {
                    if c.t > self.self_hit && !crossings.iter().any(|(_, _, i)| *i == index) {
                        crossings.push((c.t, c, index));
                    }
                }
            }
        });
        crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
        crossings.dedup_by(|later, earlier| later.0 - earlier.0 < self.self_hit);
        crossings.into_iter().map(|(t, c, index)| self.hit(t, c, index, origin, direction)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::{plane, room, sphere};
    use crate::scene::Placement;

    /// A ray leaving a floor 10⁻⁵ of the scene's size from the crease where it meets a wall,
    /// at 45°, hits the wall at t = √2·10⁻⁵ of that size, at every scale of the range of
    /// scene sizes: the self-hit distance is 10⁻⁷ of the size (an absolute 10⁻⁷ would skip
    /// the hit at scale 10⁻⁴, where t = 1.4·10⁻⁹).
    #[test]
    fn a_hit_near_a_crease_is_found_at_every_scale() {
        for k in [1e-4, 1.0, 1e4] {
            let at = |p: [f64; 3]| p.map(|x| (x * k) as f32);
            // The floor y = 0 (x ∈ [0, 1]) facing +y, the wall x = 0 (y ∈ [0, 1]) facing +x.
            let mesh = Mesh {
                positions: [
                    [0., 0., -1.],
                    [1., 0., -1.],
                    [1., 0., 1.],
                    [0., 0., 1.],
                    [0., 0., -1.],
                    [0., 1., -1.],
                    [0., 1., 1.],
                    [0., 0., 1.],
                ]
                .map(at)
                .to_vec(),
                normals: [[0.0, 1.0, 0.0]; 4].into_iter().chain([[1.0, 0.0, 0.0]; 4]).collect(),
                indices: vec![0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7],
            };
            let geometry = Geometry::new(&[mesh]).unwrap();
            assert_eq!(geometry.size(), k as f32 as f64);
            let d = 1e-5 * k;
            let direction = DVec3::new(-1.0, 1.0, 0.0).normalize();
            let hit = geometry.nearest(DVec3::new(d, 0.0, 0.0), direction, None, |_| true).unwrap_or_else(|| panic!("scale {k}: no hit"));
            assert!((hit.t / (2f64.sqrt() * d) - 1.0).abs() < 1e-9, "scale {k}: {hit:?}");
            assert_eq!(hit.normal, DVec3::X, "scale {k}: the wall");
        }
    }

    #[test]
    fn nearest_hit_on_a_sphere_is_analytic_up_to_tessellation() {
        // A ray from (0, 0, 5) towards the origin meets the unit sphere at z = 1 (the UV
        // sphere's pole ring lies inside it by at most 1 − cos(π/rings)).
        let geometry = Geometry::new(&[sphere(64, 32)]).unwrap();
        let hit = geometry.nearest(DVec3::new(0.0, 0.0, 5.0), DVec3::NEG_Z, None, |_| true).unwrap();
        assert!((hit.t - 4.0).abs() < 1.0 - (std::f64::consts::PI / 32.0).cos() + 1e-9, "{}", hit.t);
        assert!(hit.normal.dot(DVec3::Z) > 0.999);
        // Leaving that triangle outwards finds nothing; inwards finds the far side at z ≈ −1.
        assert!(geometry.nearest(hit.point, DVec3::Z, Some(hit.triangle), |_| true).is_none());
        let far = geometry.nearest(hit.point, DVec3::NEG_Z, Some(hit.triangle), |_| true).unwrap();
        assert!((far.point.z + 1.0).abs() < 0.01 && far.normal.z < -0.99);
        // A degenerate ray meets nothing (and does not reach the traversal's assertions).
        assert!(geometry.nearest(DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 1.0), None, |_| true).is_none());
        assert!(geometry.all_hits(DVec3::splat(f64::INFINITY), DVec3::Z, |_| true).is_empty());
    }

    #[test]
    fn a_ray_through_a_shared_vertex_is_not_lost() {
        // Through the sphere's centre along z the far side is met exactly at a vertex (ring
        // 16 of 32, segment 16 of 64), shared by six triangles.
        let geometry = Geometry::new(&[sphere(64, 32)]).unwrap();
        for direction in [DVec3::Z, DVec3::NEG_Z, DVec3::X, DVec3::NEG_Y] {
            let hits = geometry.all_hits(DVec3::ZERO, direction, |_| true);
            assert_eq!(hits.len(), 1, "{direction:?}: {hits:?}");
            assert!((hits[0].t - 1.0).abs() < 1e-7);
        }
        // And the triangle test's barycentrics recover a point inside a triangle.
        let triangle = Triangle { corners: [DVec3::ZERO, DVec3::X, DVec3::Y], normals: [DVec3::Z; 3], object: 0 };
        let crossing = triangle.crossing(DVec3::new(0.25, 0.5, 2.0), DVec3::NEG_Z).unwrap();
        assert_eq!(crossing, Crossing { t: 2.0, u: 0.25, v: 0.5 });
        assert!(triangle.crossing(DVec3::new(0.75, 0.5, 2.0), DVec3::NEG_Z).is_none());
        assert_eq!(triangle.crossing(DVec3::new(0.25, 0.5, -1.0), DVec3::Z).map(|c| c.t), Some(1.0));
    }

    #[test]
    fn the_watertight_test_is_the_same_along_every_dominant_axis() {
        // One right triangle with its legs along the two axes other than `axis`, met head-on
        // along −axis from 2 units away at leg coordinates (0.25, 0.5): t = 2 and the
        // barycentric weights of the two leg ends are those coordinates, whichever axis the
        // ray runs along (each dominant axis has its own copy of the test).
        for axis in 0..3 {
            let unit = |k: usize| DVec3::from_array(std::array::from_fn(|i| if i == k { 1.0 } else { 0.0 }));
            let (a, b) = (unit((axis + 1) % 3), unit((axis + 2) % 3));
            let triangle = Triangle { corners: [DVec3::ZERO, a, b], normals: [unit(axis); 3], object: 0 };
            let inside = a * 0.25 + b * 0.5 + unit(axis) * 2.0;
            assert_eq!(triangle.crossing(inside, -unit(axis)), Some(Crossing { t: 2.0, u: 0.25, v: 0.5 }), "axis {axis}");
            assert_eq!(triangle.crossing(inside - unit(axis) * 4.0, unit(axis)).map(|c| c.t), Some(2.0), "axis {axis}");
            // Past the hypotenuse (0.75 + 0.5 > 1), and past each leg.
            for outside in [a * 0.75 + b * 0.5, a * -0.25 + b * 0.5, a * 0.25 + b * -0.5] {
                assert!(triangle.crossing(outside + unit(axis) * 2.0, -unit(axis)).is_none(), "axis {axis}: {outside:?}");
            }
        }
    }

    /// A tiny triangle 5e-6 in front of the ray's origin (its box is left long before
    /// obvhs's start at t = 1e-4), among a sphere's triangles far away: every query finds it.
    #[test]
    fn a_crossing_just_in_front_of_the_origin_is_found() {
        let far = sphere(16, 8).placed(&Placement { position: [0.0, 0.0, 5.0], scale: [1.0; 3] });
        let d = 1e-5_f32;
        let tiny = Mesh {
            positions: vec![[-d, -d, 5e-6], [d, -d, 5e-6], [0.0, d, 5e-6]],
            normals: vec![[0.0, 0.0, -1.0]; 3],
            indices: vec![0, 1, 2],
        };
        let geometry = Geometry::new(&[far, tiny]).unwrap();
        let (origin, direction) = (DVec3::ZERO, DVec3::new(0.01, 0.02, 1.0).normalize());
        let hit = geometry.nearest(origin, direction, None, |_| true).expect("the tiny triangle");
        assert_eq!(hit.object, 1);
        assert!((hit.t - 5e-6 / direction.z).abs() < 1e-12, "{}", hit.t);
        assert!(geometry.occluded(origin, direction));
        let hits = geometry.all_hits(origin, direction, |_| true);
        assert_eq!(hits.iter().map(|h| h.object).collect::<Vec<_>>(), vec![1, 0, 0], "the tiny triangle, then the sphere's two faces");
    }

    #[test]
    fn tiny_direction_components_keep_their_hits() {
        let geometry = Geometry::new(&[sphere(64, 32)]).unwrap();
        for tiny in [-1e-8, -1e-9, -5.5e-25, 1e-8, -1e-6, -1e-5] {
            let direction = DVec3::new(tiny, tiny, 1.0).normalize();
            let hits = geometry.all_hits(DVec3::new(0.0, 0.0, -2.0), direction, |_| true);
            assert_eq!(hits.len(), 2, "direction {direction:?}");
        }
    }

    #[test]
    fn all_hits_peel_a_room_around_a_plane_and_filter_objects() {
        let room = room().placed(&Placement { position: [0.0; 3], scale: [3.0, 2.0, 3.0] });
        let floor = plane().placed(&Placement { position: [0.0, -1.0, 0.0], scale: [1.0; 3] });
        let geometry = Geometry::new(&[room, floor]).unwrap();
        // Straight down from (0.5, 1, 0.25): the plane at y = −1 (t = 2), the floor at y = −2 (t = 3).
        let hits = geometry.all_hits(DVec3::new(0.5, 1.0, 0.25), DVec3::NEG_Y, |_| true);
        let found: Vec<(f64, usize)> = hits.iter().map(|h| (h.t, h.object)).collect();
        assert_eq!(found.len(), 2);
        assert!((found[0].0 - 2.0).abs() < 1e-12 && found[0].1 == 1);
        assert!((found[1].0 - 3.0).abs() < 1e-12 && found[1].1 == 0);
        // The room's floor faces into the room (+y).
        assert!((hits[1].normal - DVec3::Y).length() < 1e-12);
        let room_only = geometry.nearest(DVec3::new(0.5, 1.0, 0.25), DVec3::NEG_Y, None, |o| o == 0).unwrap();
        assert!((room_only.t - 3.0).abs() < 1e-12);
        // Through the edge of the two floor triangles (the diagonal x = z) the floor counts once.
        let diagonal = geometry.all_hits(DVec3::new(1.5, 1.0, 1.5), DVec3::NEG_Y, |o| o == 0);
        assert_eq!(diagonal.len(), 1);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20000))]

        /// A ray the triangle lies behind is never blocked by it: the watertight test gives it
        /// no crossing at t > 0, for triangles through, around and near the origin (zero,
        /// tiny and signed-zero coordinates) and directions of every heading.
        #[test]
        fn rays_a_triangle_lies_behind_do_not_cross_it(
            corners in proptest::array::uniform9(proptest::prop_oneof![4 => -2.0f64..2.0, 1 => proptest::strategy::Just(0.0), 1 => proptest::strategy::Just(-0.0), 1 => -1e-9f64..1e-9]),
            direction in proptest::array::uniform3(-1.0f64..1.0),
        ) {
            let direction = DVec3::from(direction);
            proptest::prop_assume!(direction.length() > 1e-3);
            let direction = direction.normalize();
            let relative = [0, 3, 6].map(|i| DVec3::new(corners[i], corners[i + 1], corners[i + 2]));
            let shear = Shear::of(direction);
            let headings = Headings::of(std::slice::from_ref(&shear));
            if headings.behind(&relative) & 1 == 1 {
                let crossing = crossing_from(relative, &shear);
                proptest::prop_assert!(crossing.is_none_or(|c| c.t <= 0.0), "{:?} {:?} {:?}", relative, direction, crossing);
            }
        }
    }

    #[test]
    fn rays_aimed_at_a_closed_room_s_edges_and_corners_never_escape() {
        // The room's walls meet at edges where two flat boxes touch; a ray aimed exactly at
        // an edge or corner must still meet a wall there (before the boxes were widened, a
        // ray in the room's diagonal plane x = −y left through the edge (3, −3, z)).
        let geometry = Geometry::new(&[room().placed(&Placement { position: [0.0; 3], scale: [3.0; 3] })]).unwrap();
        let mut targets = Vec::new();
        for a in [-3.0, 3.0] {
            for b in [-3.0, 3.0] {
                for t in [-2.9, -1.7, -0.4, 0.0, 0.3, 1.1, 2.5] {
                    targets.extend([DVec3::new(a, b, t), DVec3::new(a, t, b), DVec3::new(t, a, b)]);
                }
                targets.extend([DVec3::new(a, b, -3.0), DVec3::new(a, b, 3.0)]);
            }
        }
        let mut rays = 0;
        for x in [-2.5, -1.0, 0.0, 0.2953293607927585, 1.7] {
            for y in [-2.0, -0.2953293607927585, 0.0, 0.9] {
                for z in [-1.5, 0.0, 0.2731158383122385, 2.2] {
                    let origin = DVec3::new(x, y, z);
                    for &target in &targets {
                        let direction = (target - origin).normalize();
                        let hit = geometry.nearest(origin, direction, None, |_| true);
                        let hit = hit.unwrap_or_else(|| panic!("escaped: from {origin} towards {target}"));
                        assert!(hit.point.distance(target) < 1e-9, "from {origin} towards {target}: {}", hit.point);
                        rays += 1;
                    }
                }
            }
        }
        assert_eq!(rays, 80 * 92);
    }

    #[test]
    fn rays_of_one_origin_traced_together_meet_what_each_meets_alone() {
        // A glass sphere and a prism in a room: fans of 96 nearly parallel rays (one
        // refraction's wavelengths) and of 150 spread ones, from inside and outside the
        // objects and from a point on a triangle left behind: each ray's nearest hit in the
        // packet walk is the one `nearest` finds for it alone.
        use crate::scene::mesh::prism;
        let geometry = Geometry::new(&[
            sphere(24, 12).placed(&Placement { position: [-0.8, 0.0, 0.0], scale: [0.5; 3] }),
            prism().placed(&Placement { position: [0.7, 0.1, 0.2], scale: [0.6; 3] }),
            room().placed(&Placement { position: [0.0; 3], scale: [3.0; 3] }),
        ])
        .unwrap();
        let start = geometry.nearest(DVec3::new(-0.8, 0.0, -2.0), DVec3::Z, None, |_| true).unwrap();
        let mut cases = vec![(start.point, Some(start.triangle))];
        cases.extend([DVec3::new(-0.8, 0.05, 0.1), DVec3::new(0.7, 0.1, 0.2), DVec3::new(0.1, -0.4, -2.5)].map(|o| (o, None)));
        let mut compared = 0;
        for (case, &(origin, leaving)) in cases.iter().enumerate() {
            for fan in 0..6 {
                let axis =
                    DVec3::new((fan as f64 * 1.3 + case as f64).sin(), 0.3 * (fan as f64).cos(), (fan as f64 * 0.7).cos()).normalize();
                let (count, spread) = if fan % 2 == 0 { (96, 0.01) } else { (150, 1.5) };
                let directions: Vec<DVec3> = (0..count)
                    .map(|i| {
                        let a = i as f64 / count as f64;
                        (axis + DVec3::new((a * 17.0).sin(), (a * 29.0).cos(), a - 0.5) * spread).normalize()
                    })
                    .collect();
                let together = geometry.nearest_rays(origin, &directions, leaving);
                for (direction, hit) in directions.iter().zip(&together) {
                    let alone = geometry.nearest(origin, *direction, leaving, |_| true);
                    match (hit, alone) {
                        (Some(h), Some(a)) => {
                            assert_eq!(h.t, a.t, "from {origin} along {direction}");
                            assert_eq!(h.point, a.point);
                            assert!(h.triangle == a.triangle || h.object == a.object, "a tie across objects");
                        }
                        (None, None) => {}
                        (h, a) => panic!("from {origin} along {direction}: together {:?}, alone {:?}", h.map(|h| h.t), a.map(|a| a.t)),
                    }
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 4 * 3 * (96 + 150));
    }
}

//! Packets of rays that share an origin — the hemisphere rays of one vertex in one
//! direction bin — traced together for occlusion: one walk of a binary BVH in which each
//! node's box is tested against every live ray of the packet at once (the slab test over
//! arrays of directions, in vector lanes), descending while any ray enters it; at a leaf
//! the caller's test decides which of the rays that entered its box each triangle blocks
//! (`Geometry::open_rays`: the watertight test, skipped for rays the triangle lies behind),
//! and a blocked ray leaves the packet. Ambient-occlusion rays mostly escape, and rays of
//! one origin and nearly one direction enter nearly the same boxes, so the packet walks
//! each shared node once instead of once per ray (Wald, Slusallek, Benthin and Wagner,
//! "Interactive Rendering with Coherent Ray Tracing", Eurographics 2001, traced packets of
//! four).
//!
//! The same tree also finds nearest hits for a packet (`Geometry::nearest_rays`: the
//! wavelengths one refraction bends apart in the spectral reference): each ray carries a
//! limit, its nearest crossing so far, past which a box no longer counts, and of a node's
//! two children the one nearer along the packet's heading is walked first.
//!
//! The slab test (Kay and Kajiya, SIGGRAPH 1986) in f64 on boxes widened from the
//! builder's f32 boxes is conservative — reciprocal directions are held finite, so no
//! product is NaN, and the exit is rounded outwards — so every triangle a ray may cross is
//! tested, and a ray's answer is the one the triangle test gives it alone. The tree is
//! obvhs's binary BVH, stored as sibling pairs of one cache line each.

use glam::{DVec3, Vec3A};
use multiversion::target::match_target;
use obvhs::bvh2::builder::build_bvh2_from_tris;
use obvhs::triangle::Triangle as BvhTriangle;
use obvhs::BvhBuildParams;

use crate::scene::mesh::widen;

/// The most rays a packet holds (one bit each in its masks).
pub const PACKET_RAYS: usize = 64;

/// A set of a packet's rays, one bit per ray.
pub type RayMask = u64;

/// A triangle's corners in f32, as the meshes give them (widened to f64 exactly).
pub type Corners = [[f32; 3]; 3];

/// A node's box (f32, as the builder made it; widened exactly for the test) and either its
/// two children (the pair `first` of the tree's sibling pairs) or, for a leaf, its
/// triangles `first .. first + count` of the tree's corner list. 32 bytes, half the size
/// of f64 boxes.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct PacketNode {
    low: [f32; 3],
    high: [f32; 3],
    first: u32,
    count: u32,
}

/// Two siblings, tested together when their parent is reached: one cache line.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct SiblingPair([PacketNode; 2]);

/// A binary BVH over triangles for packets: the root, the other nodes in sibling pairs, and
/// the corners stored in leaf order next to one another (the traversal's memory traffic,
/// not its arithmetic, is what a ray costs).
pub struct PacketTree {
    /// None for a tree without triangles.
    root: Option<PacketNode>,
    pairs: Vec<SiblingPair>,
    corners: Vec<Corners>,
    /// Each of `corners`' triangles' index in the list the tree was built from.
    indices: Vec<u32>,
}

/// The rays of a packet: their origin and their reciprocal directions in
/// structure-of-arrays form.
pub struct Packet {
    origin: DVec3,
    rays: usize,
    reciprocal: [[f64; PACKET_RAYS]; 3],
    /// How far along each ray a box still counts: the nearest crossing found so far in a
    /// nearest-hit walk, infinity for occlusion.
    limits: [f64; PACKET_RAYS],
    /// The first ray's direction: the order a nearest-hit walk takes two children in.
    heading: DVec3,
}

/// 1/x, its size held to at most 10³⁰⁰ (a zero or denormal component), so the slab test's
/// products stay finite and never NaN: with box coordinates far below 10³ in size, a slab
/// the origin lies in still spans ±10³⁰⁰·… around t = 0 and one it lies outside stays out
/// of reach, as with the true reciprocal.
fn reciprocal_of(x: f64) -> f64 {
    let r = 1.0 / x;
    if r.abs() <= 1e300 {
        r
    } else {
        1e300f64.copysign(x)
    }
}

impl Packet {
    /// The packet of rays from `origin` along `directions` (at most [`PACKET_RAYS`]).
    pub fn new(origin: DVec3, directions: &[DVec3]) -> Packet {
        assert!(directions.len() <= PACKET_RAYS, "a packet holds at most {PACKET_RAYS} rays");
        let mut reciprocal = [[0.0; PACKET_RAYS]; 3];
        for (i, d) in directions.iter().enumerate() {
            for axis in 0..3 {
                reciprocal[axis][i] = reciprocal_of(d[axis]);
            }
        }
        Packet {
            origin,
            rays: directions.len(),
            reciprocal,
            limits: [f64::INFINITY; PACKET_RAYS],
            heading: directions.first().copied().unwrap_or(DVec3::Z),
        }
    }

    /// Every ray of the packet.
    fn all(&self) -> RayMask {
        if self.rays == PACKET_RAYS {
            RayMask::MAX
        } else {
            (1 << self.rays) - 1
        }
    }

    /// The rays of `live` that enter the box [`low`, `high`] at some t ≥ 0: blocks of eight
    /// rays, each lane's interval narrowed axis by axis, written so the lanes vectorise
    /// (there are no NaNs to order: see [`reciprocal_of`]).
    #[cfg(test)]
    fn entering(&self, low: [f32; 3], high: [f32; 3], live: RayMask) -> RayMask {
        self.entering_by::<false>(low, high, live, nonnegative_lanes)
    }

    /// [`Packet::entering`] with the lanes of a block gathered by `lanes` (one of the
    /// equivalent [`nonnegative_lanes`] forms); `LIMITED`: a ray leaves no farther than its
    /// limit (the nearest-hit walk).
    #[inline(always)]
    fn entering_by<const LIMITED: bool>(&self, low: [f32; 3], high: [f32; 3], live: RayMask, lanes: impl Fn(&[f64; 8]) -> u8) -> RayMask {
        let (near, far) = (widen(low) - self.origin, widen(high) - self.origin);
        // A box around the origin holds every ray at t = 0 (so for the boxes down to the
        // origin's own leaf, which every packet of a vertex walks, no ray is tested).
        if near.cmple(DVec3::ZERO).all() && far.cmpge(DVec3::ZERO).all() {
            return live;
        }
        let mut entered: RayMask = 0;
        for block in 0..self.rays.div_ceil(8) {
            let base = block * 8;
            if (live >> base) & 0xff == 0 {
                continue;
            }
            let mut enter = [0.0f64; 8];
            // Occlusion walks take no limits (a constant here: loading them costs the AO
            // reference ~10 %).
            let mut exit: [f64; 8] = if LIMITED { std::array::from_fn(|lane| self.limits[base + lane]) } else { [f64::INFINITY; 8] };
            for axis in 0..3 {
                let reciprocal = &self.reciprocal[axis][base..base + 8];
                for lane in 0..8 {
                    let (a, b) = (near[axis] * reciprocal[lane], far[axis] * reciprocal[lane]);
                    let (low_t, high_t) = if a < b { (a, b) } else { (b, a) };
                    enter[lane] = if low_t > enter[lane] { low_t } else { enter[lane] };
                    exit[lane] = if high_t < exit[lane] { high_t } else { exit[lane] };
                }
            }
            // A lane is entered when exit − enter ≥ 0 (the exit rounded outwards, relatively
            // and by 10⁻¹² scene units; neither side is NaN).
            let margins: [f64; 8] = std::array::from_fn(|lane| exit[lane] + (exit[lane].abs() * 1e-12 + 1e-12) - enter[lane]);
            entered |= RayMask::from(lanes(&margins)) << base;
        }
        entered & live
    }
}

impl PacketTree {
    /// The tree over `triangles`, at most `leaf_size` triangles per leaf.
    pub fn new(triangles: &[Corners], leaf_size: u32) -> PacketTree {
        let point = |p: [f32; 3]| Vec3A::new(p[0], p[1], p[2]);
        let boxes: Vec<BvhTriangle> =
            triangles.iter().map(|[a, b, c]| BvhTriangle { v0: point(*a), v1: point(*b), v2: point(*c) }).collect();
        let params = BvhBuildParams { max_prims_per_leaf: leaf_size, ..BvhBuildParams::medium_build() };
        let bvh = build_bvh2_from_tris(&boxes, params, &mut Default::default());
        let node = |i: usize| {
            let n = &bvh.nodes[i];
            PacketNode { low: n.aabb.min.into(), high: n.aabb.max.into(), first: n.first_index, count: n.prim_count }
        };
        // Depth first, each pair of siblings in one cache line: a walk down the first
        // children reads pairs that lie close in memory.
        let mut pairs = Vec::new();
        if triangles.is_empty() {
            return PacketTree { root: None, pairs, corners: Vec::new(), indices: Vec::new() };
        }
        let mut root = node(0);
        let mut pending: Vec<(usize, usize)> = Vec::new();
        let open_pair = |parent: &mut PacketNode, pairs: &mut Vec<SiblingPair>, pending: &mut Vec<(usize, usize)>| {
            if parent.count == 0 {
                let (old, new) = (parent.first as usize, pairs.len());
                pairs.push(SiblingPair([node(old), node(old + 1)]));
                parent.first = new as u32;
                pending.extend([(new, 1), (new, 0)]);
            }
        };
        open_pair(&mut root, &mut pairs, &mut pending);
        while let Some((pair, side)) = pending.pop() {
            let mut parent = pairs[pair].0[side];
            open_pair(&mut parent, &mut pairs, &mut pending);
            pairs[pair].0[side] = parent;
        }
        let corners = bvh.primitive_indices.iter().map(|&i| triangles[i as usize]).collect();
        PacketTree { root: Some(root), pairs, corners, indices: bvh.primitive_indices }
    }

    /// How many rays of `packet` cross no triangle (`blocked` as in [`open`]).
    pub fn open_rays(&self, packet: &Packet, blocked: impl Fn(&[DVec3; 3], RayMask) -> RayMask) -> usize {
        open(self, packet, blocked).count_ones() as usize
    }

    /// Each ray's nearest crossing (distance, index of the triangle in the list the tree was
    /// built from): `cross(index, relative, rays, nearest)` updates `nearest` for those of
    /// `rays` that cross the triangle nearer than their nearest so far (`relative`: its
    /// corners less the origin). A ray's limit shrinks to its nearest crossing, so boxes
    /// wholly beyond it are no longer entered.
    pub fn nearest(&self, packet: &mut Packet, cross: impl FnMut(u32, &[DVec3; 3], RayMask, &mut Nearest)) -> Nearest {
        nearest(self, packet, cross)
    }
}

/// Each ray's nearest crossing so far: (distance, triangle index).
pub type Nearest = [Option<(f64, u32)>; PACKET_RAYS];

/// The nearest-hit walk of [`PacketTree::nearest`]: as [`open`], but a ray stays in the
/// walk until the boxes left are beyond its nearest crossing, and a popped node is tested
/// again against the limits as they are by then.
#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn nearest<F: FnMut(u32, &[DVec3; 3], RayMask, &mut Nearest)>(tree: &PacketTree, packet: &mut Packet, mut cross: F) -> Nearest {
    let mut best: Nearest = [None; PACKET_RAYS];
    let Some(root) = &tree.root else { return best };
    let mut stack: Vec<(&PacketNode, RayMask)> = Vec::with_capacity(64);
    let lanes = match_target! {
        "x86_64+avx512f" => |margins: &[f64; 8]| nonnegative_lanes_avx512(margins),
        "x86_64+avx2" => |margins: &[f64; 8]| nonnegative_lanes_avx2(margins),
        _ => nonnegative_lanes,
    };
    stack.push((root, packet.all()));
    while let Some((node, rays)) = stack.pop() {
        let rays = packet.entering_by::<true>(node.low, node.high, rays, lanes);
        if rays == 0 {
            continue;
        }
        if node.count == 0 {
            let [first, second] = &tree.pairs[node.first as usize].0;
            // The nearer child along the heading is walked first (stacked last), so the
            // limits shrink before the farther one is tested.
            let along = |n: &PacketNode| (widen(n.low) + widen(n.high) - 2.0 * packet.origin).dot(packet.heading);
            let (near, far) = if along(first) <= along(second) { (first, second) } else { (second, first) };
            for child in [far, near] {
                if child.count == 0 {
                    prefetch(&tree.pairs[child.first as usize]);
                }
                stack.push((child, rays));
            }
            continue;
        }
        let leaf = node.first as usize..(node.first + node.count) as usize;
        for (corners, &index) in tree.corners[leaf.clone()].iter().zip(&tree.indices[leaf]) {
            let relative = corners.map(|p| widen(p) - packet.origin);
            cross(index, &relative, rays, &mut best);
        }
        for (limit, found) in packet.limits.iter_mut().zip(&best).take(packet.rays) {
            if let Some((t, _)) = found {
                *limit = t.min(*limit);
            }
        }
    }
    best
}

/// The rays of `packet` that no triangle whose box they enter blocks, as a mask:
/// `blocked(relative, rays)` gives those of `rays` a triangle blocks, `relative` holding
/// its corners less the packet's origin, formed once for all its rays. A node's two
/// children are tested together when it is reached (they share a cache line) and only a
/// child some ray enters is stacked, with the rays that enter it (and the line of its own
/// children asked for); the first child is walked first. The walk ends once every ray has
/// met a triangle.
#[multiversion::multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn open<F: Fn(&[DVec3; 3], RayMask) -> RayMask>(tree: &PacketTree, packet: &Packet, blocked: F) -> RayMask {
    let mut open = packet.all();
    let Some(root) = &tree.root else { return open };
    let mut stack: Vec<(&PacketNode, RayMask)> = Vec::with_capacity(64);
    let lanes = match_target! {
        "x86_64+avx512f" => |margins: &[f64; 8]| nonnegative_lanes_avx512(margins),
        "x86_64+avx2" => |margins: &[f64; 8]| nonnegative_lanes_avx2(margins),
        _ => nonnegative_lanes,
    };
    let entering_root = packet.entering_by::<false>(root.low, root.high, open, lanes);
    if entering_root != 0 {
        stack.push((root, entering_root));
    }
    while let Some((node, rays)) = stack.pop() {
        let rays = rays & open;
        if rays == 0 {
            continue;
        }
        if node.count == 0 {
            let [first, second] = &tree.pairs[node.first as usize].0;
            for child in [second, first] {
                let into = packet.entering_by::<false>(child.low, child.high, rays, lanes);
                if into != 0 {
                    if child.count == 0 {
                        prefetch(&tree.pairs[child.first as usize]);
                    }
                    stack.push((child, into));
                }
            }
            continue;
        }
        for corners in &tree.corners[node.first as usize..(node.first + node.count) as usize] {
            let relative = corners.map(|p| widen(p) - packet.origin);
            let live = rays & open;
            if live != 0 {
                open &= !blocked(&relative, live);
            }
        }
        if open == 0 {
            break;
        }
    }
    open
}

/// The lanes of `margins` that are ≥ 0, one bit each (bit i for lane i).
#[inline(always)]
fn nonnegative_lanes(margins: &[f64; 8]) -> u8 {
    (0..8).fold(0, |lanes, lane| lanes | u8::from(margins[lane] >= 0.0) << lane)
}

/// [`nonnegative_lanes`] as one AVX-512 comparison into a mask register (LLVM does not
/// find it in the portable form and reduces the lanes through shuffles instead).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn nonnegative_lanes_avx512(margins: &[f64; 8]) -> u8 {
    use std::arch::x86_64::{_mm512_cmp_pd_mask, _mm512_loadu_pd, _mm512_setzero_pd, _CMP_GE_OQ};
    // SAFETY: `margins` is eight readable f64s; the load has no alignment requirement.
    let margins = unsafe { _mm512_loadu_pd(margins.as_ptr()) };
    _mm512_cmp_pd_mask::<_CMP_GE_OQ>(margins, _mm512_setzero_pd())
}

/// [`nonnegative_lanes`] as two AVX comparisons and their sign masks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn nonnegative_lanes_avx2(margins: &[f64; 8]) -> u8 {
    use std::arch::x86_64::{_mm256_cmp_pd, _mm256_loadu_pd, _mm256_movemask_pd, _mm256_setzero_pd, _CMP_GE_OQ};
    let half = |at: usize| {
        // SAFETY: `margins[at..at + 4]` is four readable f64s; the load has no alignment requirement.
        let half = unsafe { _mm256_loadu_pd(margins[at..at + 4].as_ptr()) };
        _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(half, _mm256_setzero_pd())) as u8
    };
    half(0) | half(4) << 4
}

/// Asks for the cache line of `pair` ahead of its use (a hint; no effect elsewhere).
#[inline(always)]
fn prefetch(pair: &SiblingPair) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing architecturally and `pair` is a valid reference.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>((pair as *const SiblingPair).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = pair;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vector_lane_masks_are_the_portable_one() {
        let values = [0.0, -0.0, 1e-300, -1e-300, 2.5, -7.0, f64::INFINITY, f64::NEG_INFINITY, f64::MIN_POSITIVE, -f64::MAX];
        for start in 0..values.len() {
            let margins: [f64; 8] = std::array::from_fn(|lane| values[(start + lane * 3) % values.len()]);
            let portable = nonnegative_lanes(&margins);
            let expected = (0..8).filter(|&lane| margins[lane] >= 0.0).fold(0u8, |m, lane| m | 1 << lane);
            assert_eq!(portable, expected, "{margins:?}");
            #[cfg(target_arch = "x86_64")]
            {
                if is_x86_feature_detected!("avx512f") {
                    // SAFETY: the CPU has AVX-512F.
                    assert_eq!(unsafe { nonnegative_lanes_avx512(&margins) }, expected, "{margins:?}");
                }
                if is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU has AVX2.
                    assert_eq!(unsafe { nonnegative_lanes_avx2(&margins) }, expected, "{margins:?}");
                }
            }
        }
    }

    #[test]
    fn a_tree_without_triangles_blocks_nothing() {
        let tree = PacketTree::new(&[], 2);
        let packet = Packet::new(DVec3::ZERO, &[DVec3::Z, DVec3::X]);
        assert_eq!(tree.open_rays(&packet, |_, rays| rays), 2);
    }

    #[test]
    fn the_slab_test_takes_rays_into_boxes_ahead_and_around_them() {
        let directions = [DVec3::Z, DVec3::NEG_Z, DVec3::X, DVec3::new(1.0, 0.0, 1.0).normalize(), DVec3::new(0.0, 1e-300, 1.0)];
        let packet = Packet::new(DVec3::ZERO, &directions);
        // A box ahead on +z: the rays along +z (and the one with a denormal y component)
        // enter; the one at 45° passes beside it (x = z there, the box holds x ≤ 0.5 for z ≥ 1).
        assert_eq!(packet.entering([-0.5, -0.5, 1.0], [0.5, 0.5, 2.0], 0b11111), 0b10001);
        // A box around the origin holds every ray; the live mask limits the answer.
        assert_eq!(packet.entering([-1.0; 3], [1.0; 3], 0b11111), 0b11111);
        assert_eq!(packet.entering([-1.0; 3], [1.0; 3], 0b00110), 0b00110);
        // A box whose face lies in the ray's plane x = 0 (a zero component: 0 · ∞ would be
        // NaN) still counts as entered by the ray along that face.
        assert_eq!(packet.entering([0.0, -1.0, 1.0], [1.0, 1.0, 2.0], 0b00001), 0b00001);
        // A box behind the origin is never entered by the forward ray.
        assert_eq!(packet.entering([-0.5, -0.5, -2.0], [0.5, 0.5, -1.0], 0b00001), 0);
        assert_eq!(packet.all(), 0b11111);
        assert_eq!(Packet::new(DVec3::ZERO, &[DVec3::Z; PACKET_RAYS]).all(), u64::MAX);
    }
}

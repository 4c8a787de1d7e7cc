//! The surfel hierarchy (Bunnell, GPU Gems 2 ch. 14): surfels merged pairwise into a binary
//! tree — a parent's centre and normal are the area-weighted means of its children's (the
//! plain means where the areas are equal; the centroid of the surface it stands for), its
//! area their sum. A receiver walks the tree from the root and takes a node as one emitter
//! when it is far relative to its size, r² ≥ κ·A (κ = [`Closeness`]), and descends into its
//! children otherwise; a node holding the receiver itself is always descended, and a leaf
//! is the surfel. Distant shadow is blurrier; the cost drops from n² toward n log n.
//!
//! The tree splits the surfels at the median of their centres along the longest axis of
//! their bounding box, so siblings are neighbours and each node covers a contiguous range
//! of the leaf order — except a flat group whose normals largely cancel (the two faces of
//! a thin wall), which is halved by normal so no node merges discs facing opposite ways. In pass k a node's weight is the area-weighted mean accessibility of
//! its leaves from pass k − 1.

use glam::DVec3;

use super::accessibility::{Emitters, Occlusion};
use super::shadow::ShadowForm;
use super::surfel::Surfel;

/// κ: a node of area A is one emitter for a receiver at distance r when r² ≥ κ·A.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Closeness(pub f64);

impl Default for Closeness {
    /// κ = 16: a node is merged only from farther than about 2.3 of its disc radii
    /// (r ≥ 4·√A = 4√π·radius); measured in BENCHMARKS.md against brute force.
    fn default() -> Closeness {
        Closeness(16.0)
    }
}

/// One node: its merged disc, its children (none for a leaf) and its leaves' range in
/// [`SurfelTree::order`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    pub disc: Surfel,
    pub children: Option<[u32; 2]>,
    pub first: u32,
    pub end: u32,
}

/// The tree over a mesh's surfels; node 0 is the root.
pub struct SurfelTree<'a> {
    surfels: &'a [Surfel],
    pub nodes: Vec<Node>,
    /// Surfel indices in leaf order.
    pub order: Vec<u32>,
    /// Each surfel's position in `order`.
    rank: Vec<u32>,
    pub form: ShadowForm,
    pub closeness: Closeness,
}

impl<'a> SurfelTree<'a> {
    pub fn new(surfels: &'a [Surfel], form: ShadowForm, closeness: Closeness) -> SurfelTree<'a> {
        let mut order: Vec<u32> = (0..surfels.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * surfels.len());
        if !surfels.is_empty() {
            build(surfels, &mut order, 0, &mut nodes);
        }
        let mut rank = vec![0u32; surfels.len()];
        for (position, &s) in order.iter().enumerate() {
            rank[s as usize] = position as u32;
        }
        SurfelTree { surfels, nodes, order, rank, form, closeness }
    }

    fn holds(&self, node: &Node, surfel: usize) -> bool {
        (node.first..node.end).contains(&self.rank[surfel])
    }
}

/// Build the subtree over `order` (whose first leaf sits at `offset`), returning its index.
fn build(surfels: &[Surfel], order: &mut [u32], offset: u32, nodes: &mut Vec<Node>) -> u32 {
    let index = nodes.len() as u32;
    nodes.push(Node { disc: surfels[order[0] as usize], children: None, first: offset, end: offset + order.len() as u32 });
    if order.len() == 1 {
        return index;
    }
    let half = order.len() / 2;
    match split(surfels, order) {
        Split::Position(axis) => {
            order.select_nth_unstable_by(half, |a, b| surfels[*a as usize].centre[axis].total_cmp(&surfels[*b as usize].centre[axis]))
        }
        Split::Normal(axis) => {
            order.select_nth_unstable_by(half, |a, b| surfels[*a as usize].normal[axis].total_cmp(&surfels[*b as usize].normal[axis]))
        }
    };
    let (left, right) = order.split_at_mut(half);
    let l = build(surfels, left, offset, nodes);
    let r = build(surfels, right, offset + half as u32, nodes);
    nodes[index as usize].disc = merged(&nodes[l as usize].disc, &nodes[r as usize].disc);
    nodes[index as usize].children = Some([l, r]);
    index
}

/// How a node's surfels are halved: at the median of their centres along an axis, or of
/// their normals' component along an axis.
enum Split {
    Position(usize),
    Normal(usize),
}

/// A flat group (its box's shortest side under [`FLAT`] × its longest) whose normals
/// largely cancel (|area-weighted mean normal| < ½) — the two faces of a thin slab, say —
/// is halved by normal, so that no node merges discs facing opposite ways (their merged
/// normal would mean nothing); every other group along the longest side of its box.
fn split(surfels: &[Surfel], order: &[u32]) -> Split {
    let (mut low, mut high, mut normal_low, mut normal_high) = (DVec3::INFINITY, DVec3::NEG_INFINITY, DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (mut weighted, mut area) = (DVec3::ZERO, 0.0);
    for &s in order {
        let surfel = &surfels[s as usize];
        (low, high) = (low.min(surfel.centre), high.max(surfel.centre));
        (normal_low, normal_high) = (normal_low.min(surfel.normal), normal_high.max(surfel.normal));
        weighted += surfel.normal * surfel.area;
        area += surfel.area;
    }
    let extent = high - low;
    let flat = extent.min_element() < FLAT * extent.max_element();
    let opposed = area > 0.0 && weighted.length() < 0.5 * area;
    if flat && opposed {
        Split::Normal((normal_high - normal_low).max_position())
    } else {
        Split::Position(extent.max_position())
    }
}

/// A box is flat when its shortest side is under this fraction of its longest.
const FLAT: f64 = 0.1;

/// The parent of two discs: area-weighted mean centre and normal, summed area.
fn merged(a: &Surfel, b: &Surfel) -> Surfel {
    let area = a.area + b.area;
    let (wa, wb) = if area > 0.0 { (a.area / area, b.area / area) } else { (0.5, 0.5) };
    let normal = (a.normal * wa + b.normal * wb).try_normalize().unwrap_or(a.normal);
    Surfel { centre: a.centre * wa + b.centre * wb, normal, area }
}

impl Emitters for SurfelTree<'_> {
    fn surfels(&self) -> &[Surfel] {
        self.surfels
    }

    /// Leaves carry their surfel's accessibility; a parent the area-weighted mean of its
    /// children's (children come after their parent, so a reverse sweep sees them first).
    fn weights(&self, accessibility: &[f64]) -> Vec<f64> {
        let mut weights = vec![0.0; self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate().rev() {
            weights[i] = match node.children {
                None => accessibility[self.order[node.first as usize] as usize],
                Some([l, r]) => {
                    let [a, b] = [l, r].map(|c| &self.nodes[c as usize]);
                    let area = a.disc.area + b.disc.area;
                    if area > 0.0 {
                        (weights[l as usize] * a.disc.area + weights[r as usize] * b.disc.area) / area
                    } else {
                        0.5 * (weights[l as usize] + weights[r as usize])
                    }
                }
            };
        }
        weights
    }

    fn gather(&self, receiver: usize, weights: &[f64]) -> Occlusion {
        let me = &self.surfels[receiver];
        let mut occlusion = Occlusion::default();
        if self.nodes.is_empty() {
            return occlusion;
        }
        let mut stack = vec![0u32];
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            match node.children {
                None if self.order[node.first as usize] as usize == receiver => {}
                None => occlusion.add(self.form, &node.disc, weights[index as usize], me),
                Some(children) => {
                    let far = (node.disc.centre - me.centre).length_squared() >= self.closeness.0 * node.disc.area;
                    if far && !self.holds(node, receiver) {
                        occlusion.add(self.form, &node.disc, weights[index as usize], me);
                    } else {
                        stack.extend(children);
                    }
                }
            }
        }
        occlusion
    }
}

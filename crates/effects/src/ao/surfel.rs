//! Surfels: one oriented disc per mesh vertex (Bunnell, GPU Gems 2 ch. 14, "surface
//! elements"). Centre = the vertex; normal = the mesh's vertex normal, or, where the mesh
//! has none (or a zero or non-finite one), the area-weighted sum of the adjacent faces'
//! normals; area = Σ over the triangles sharing the vertex of ⅓ of the triangle's area, so
//! the surfels' areas add up to the mesh's area.
//!
//! Degenerate input stays finite: a zero-area (or non-finite) triangle adds no area and no
//! normal; a vertex no triangle uses, or one only degenerate triangles use, gets area 0 (it
//! casts no shadow) and the normal +z; duplicate vertices are separate surfels (the shadow
//! term gives coincident discs nothing to cast on each other).
//!
//! Defects ([`mesh_defects`]): a triangle is *flipped* when at least two of its edges are
//! run in the same direction by the triangle across them (a consistently wound surface runs
//! every shared edge once each way, so a lone triangle wound the wrong way disagrees on all
//! three of its edges and each neighbour on one), or when it is folded over: its face normal
//! more than 120° (cosine below −½) from the area-weighted sum of the faces' normals at two
//! or more of its corners (wound consistently but turned over by the geometry — the
//! sculpture has 70 such triangles); *degenerate* when its area is not finite or below 1e-9 of its longest edge
//! squared (collinear or coincident corners). The vertices of such triangles are flagged:
//! their normals and areas come from faces that are not a surface, so their error is the
//! mesh's, not the method's, and is reported apart.

use std::collections::HashMap;

use glam::DVec3;

use crate::scene::mesh::{smooth_normals, widen, Mesh};

/// An oriented disc: centre, unit normal, area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surfel {
    pub centre: DVec3,
    pub normal: DVec3,
    pub area: f64,
}

/// The normal of a vertex with nothing to define one.
pub const FALLBACK_NORMAL: DVec3 = DVec3::Z;

/// One surfel per vertex of `mesh`, in vertex order.
pub fn surfels(mesh: &Mesh) -> Vec<Surfel> {
    let centres: Vec<DVec3> = mesh.positions.iter().map(|&p| widen(p)).map(|p| if p.is_finite() { p } else { DVec3::ZERO }).collect();
    let mut areas = vec![0.0f64; centres.len()];
    let mut face_normals = vec![DVec3::ZERO; centres.len()];
    for triangle in mesh.indices.chunks_exact(3) {
        let corners = [0, 1, 2].map(|i| triangle[i] as usize);
        if corners.iter().any(|&c| c >= centres.len()) {
            continue; // a face naming a vertex that does not exist adds nothing
        }
        let [a, b, c] = corners.map(|c| centres[c]);
        let doubled = (b - a).cross(c - a); // length = twice the area
        let area = 0.5 * doubled.length();
        if !(area.is_finite() && area > 0.0) {
            continue;
        }
        for corner in corners {
            areas[corner] += area / 3.0;
            face_normals[corner] += doubled;
        }
    }
    let given = |vertex: usize| mesh.normals.get(vertex).map(|&n| widen(n)).and_then(|n| n.try_normalize());
    (0..centres.len())
        .map(|vertex| {
            let normal = given(vertex).or_else(|| face_normals[vertex].try_normalize()).unwrap_or(FALLBACK_NORMAL);
            Surfel { centre: centres[vertex], normal, area: areas[vertex] }
        })
        .collect()
}

/// Per vertex of `mesh`: whether it is a corner of a flipped or degenerate triangle
/// (module doc); a face naming a vertex that does not exist is skipped.
pub fn mesh_defects(mesh: &Mesh) -> Vec<bool> {
    let vertices = mesh.positions.len();
    let faces: Vec<[usize; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .filter(|t| t.iter().all(|&v| v < vertices))
        .collect();
    let mut directed: HashMap<(usize, usize), u32> = HashMap::with_capacity(3 * faces.len());
    for face in &faces {
        for k in 0..3 {
            *directed.entry((face[k], face[(k + 1) % 3])).or_default() += 1;
        }
    }
    // The faces' area-weighted normal at each vertex (not the mesh's own normals: a fold is
    // a face turned against its neighbours, whatever the normals say).
    let mut normals = vec![DVec3::ZERO; vertices];
    for face in &faces {
        let [a, b, c] = face.map(|v| widen(mesh.positions[v]));
        let doubled = (b - a).cross(c - a);
        if doubled.is_finite() {
            for &v in face {
                normals[v] += doubled;
            }
        }
    }
    let normals: Vec<DVec3> = normals.iter().map(|n| n.normalize_or_zero()).collect();
    let mut flagged = vec![false; vertices];
    for face in &faces {
        let [a, b, c] = face.map(|v| widen(mesh.positions[v]));
        let longest = [(b - a), (c - b), (a - c)].iter().map(|e| e.length_squared()).fold(0.0, f64::max);
        let doubled = (b - a).cross(c - a);
        let degenerate = !(doubled.length().is_finite() && longest.is_finite()) || doubled.length() <= 1e-9 * longest;
        let facing = doubled.normalize_or_zero();
        let folded = !degenerate && face.iter().filter(|&&v| facing.dot(normals[v]) < -0.5).count() >= 2;
        // An edge (u, v) run the same way by another face: its count is above one.
        let disagreeing = (0..3).filter(|&k| directed.get(&(face[k], face[(k + 1) % 3])).copied().unwrap_or(0) > 1).count();
        if degenerate || folded || disagreeing >= 2 {
            for &v in face {
                flagged[v] = true;
            }
        }
    }
    flagged
}

/// One level of midpoint subdivision: every triangle into four, a new vertex at the middle
/// of each edge (shared by the triangles on both sides), its normal the normalised mean of
/// the edge's ends. The surface does not move; it only gains vertices (and surfels).
pub fn subdivided(mesh: &Mesh) -> Mesh {
    let mut out =
        Mesh { positions: mesh.positions.clone(), normals: mesh.normals.clone(), indices: Vec::with_capacity(mesh.indices.len() * 4) };
    let has_normals = mesh.normals.len() == mesh.positions.len();
    let mut middles: HashMap<(u32, u32), u32> = HashMap::new();
    let mut middle = |out: &mut Mesh, a: u32, b: u32| -> u32 {
        *middles.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let [pa, pb] = [a, b].map(|v| out.positions[v as usize]);
            out.positions.push(std::array::from_fn(|axis| 0.5 * (pa[axis] + pb[axis])));
            if has_normals {
                let [na, nb] = [a, b].map(|v| widen(out.normals[v as usize]));
                let n = (na + nb).try_normalize().unwrap_or(na);
                out.normals.push([n.x as f32, n.y as f32, n.z as f32]);
            }
            out.positions.len() as u32 - 1
        })
    };
    for triangle in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]];
        let [ab, bc, ca] = [middle(&mut out, a, b), middle(&mut out, b, c), middle(&mut out, c, a)];
        out.indices.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    if !has_normals {
        out.normals.clear();
    }
    out
}

/// `mesh` subdivided `levels` times.
pub fn subdivided_times(mesh: &Mesh, levels: u32) -> Mesh {
    (0..levels).fold(mesh.clone(), |m, _| subdivided(&m))
}

/// The mesh decimated by vertex clustering (Rossignac and Borrel, "Multi-resolution 3D
/// approximations for rendering complex scenes", 1993): space is cut into cubes of edge
/// `cell`; the vertices in one cube merge into one at their mean position; a triangle whose
/// corners fall into fewer than three cubes disappears. Smooth normals are recomputed from
/// the faces. Coarse and deterministic: what a size sweep needs (the same shape with fewer
/// vertices), not a quality simplifier.
pub fn decimated(mesh: &Mesh, cell: f32) -> Mesh {
    let key = |p: [f32; 3]| p.map(|x| (x / cell).floor() as i64);
    let mut cluster_of: HashMap<[i64; 3], u32> = HashMap::new();
    let mut sums: Vec<([f64; 3], u32)> = Vec::new();
    let mut remap = Vec::with_capacity(mesh.positions.len());
    for &p in &mesh.positions {
        let next = sums.len() as u32;
        let cluster = *cluster_of.entry(key(p)).or_insert(next);
        if cluster == next {
            sums.push(([0.0; 3], 0));
        }
        let (sum, count) = &mut sums[cluster as usize];
        for axis in 0..3 {
            sum[axis] += p[axis] as f64;
        }
        *count += 1;
        remap.push(cluster);
    }
    let positions: Vec<[f32; 3]> = sums.iter().map(|(sum, count)| sum.map(|x| (x / *count as f64) as f32)).collect();
    let mut indices = Vec::with_capacity(mesh.indices.len());
    for triangle in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| remap.get(triangle[k] as usize).copied().unwrap_or(u32::MAX));
        if a != b && b != c && a != c && a != u32::MAX && b != u32::MAX && c != u32::MAX {
            indices.extend([a, b, c]);
        }
    }
    let normals = smooth_normals(&positions, &indices);
    Mesh { positions, normals, indices }
}

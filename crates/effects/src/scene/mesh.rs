//! Triangle meshes of scenes: the built-in cube and sphere and OBJ files (tobj), normalised to
//! fit the unit sphere, and the built-in `room` (an inward-facing box) and `plane` of scenes
//! with effects; then placed in the scene (scale, then move). Pure CPU data, shared by the
//! GPU runner and the CPU ray tracers.

use std::path::{Path, PathBuf};

use glam::DVec3;
use nklut_optics::db::file::FileProblem;
use nklut_tables::budget::TooLarge;

use crate::scene::{MeshSource, Placement};

/// The bytes a traced scene holds per triangle, everything that scales with its geometry:
/// the loaded and the placed mesh (vertices, normals and indices, twice), the f64
/// triangles (corners and normals, 152 bytes), their padded boxes, the compressed-wide
/// BVH and its build's sort keys and temporaries, and the packets' binary BVH. Measured:
/// peak resident memory grows by 319, 417 and 436 bytes per triangle from one sphere to 51,
/// 251 and 1 001 (4 096 triangles each; `nklut effects`, reflections, 8×8 pixels; BENCHMARKS.md,
/// "Memory budget: scene geometry"); counted as 512, above every measured figure (the
/// estimate is 1.17–1.61 times what the geometry took).
pub const BYTES_PER_TRACED_TRIANGLE: usize = 512;

/// The bytes a traced scene of `triangles` triangles holds in its geometry
/// ([`BYTES_PER_TRACED_TRIANGLE`] each), for the memory budget's check before it is built.
pub fn traced_bytes(triangles: u128) -> u128 {
    triangles.saturating_mul(BYTES_PER_TRACED_TRIANGLE as u128)
}

/// Indexed triangles with one normal per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

/// A mesh file that could not be used.
#[derive(Debug, thiserror::Error)]
#[error("mesh {}: {problem}", file.display())]
pub struct MeshError {
    pub file: PathBuf,
    pub problem: MeshProblem,
}

/// What was wrong with a mesh file.
#[derive(Debug, thiserror::Error)]
pub enum MeshProblem {
    /// Missing, not a regular file, or larger than [`MAX_OBJ_BYTES`].
    #[error("{0}")]
    Unreadable(FileProblem),
    /// Its parsed triangles would not fit the memory budget.
    #[error("{0}")]
    Memory(TooLarge),
    /// tobj could not parse it.
    #[error("{0}")]
    Obj(tobj::LoadError),
    #[error("no triangles")]
    NoTriangles,
    #[error("a face refers to a vertex that does not exist")]
    MissingVertex,
    #[error("a vertex position is not finite")]
    NonFinitePosition,
    #[error("a vertex normal is not finite")]
    NonFiniteNormal,
}

impl Mesh {
    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// The mesh placed in the scene: positions scaled then moved, normals through the inverse
    /// transpose of the scale and renormalised.
    pub fn placed(&self, placement: &Placement) -> Mesh {
        let widen = |p: &[f32; 3]| p.map(f64::from);
        let positions = self.positions.iter().map(|p| placement.point(widen(p)).map(|x| x as f32)).collect();
        let normals = self.normals.iter().map(|n| normalised(placement.normal(widen(n)))).collect();
        Mesh { positions, normals, indices: self.indices.clone() }
    }

    /// Interleaved vertex data `position, normal` (6 f32 per vertex) for the GPU.
    pub fn interleaved(&self) -> Vec<f32> {
        self.positions.iter().zip(&self.normals).flat_map(|(p, n)| [p[0], p[1], p[2], n[0], n[1], n[2]]).collect()
    }

    /// The indices with every triangle wound counter-clockwise seen from its outside (the
    /// side [`wound_against_normals`] names): what a rasteriser's front face is, so the
    /// GPU's `front_facing` at a pixel is the CPU tracers' side of the triangle's plane.
    pub fn outward_indices(&self) -> Vec<u32> {
        let mut indices = self.indices.clone();
        for triangle in indices.chunks_exact_mut(3) {
            let at = |i: usize| triangle[i] as usize;
            let corners = [0, 1, 2].map(|i| widen(self.positions[at(i)]));
            let normals = [0, 1, 2].map(|i| widen(self.normals[at(i)]));
            if wound_against_normals(corners, normals) {
                triangle.swap(1, 2);
            }
        }
        indices
    }
}

/// Whether a triangle's winding runs against its vertex normals: (b − a) × (c − a) · (n_a +
/// n_b + n_c) < 0, in f64 from the mesh's f32 data. The one rule of which side of a
/// triangle's plane is the mesh's outside, whatever the file's winding: the CPU tracers
/// turn the plane's normal by it (`geometry`), the GPU's meshes are wound by it
/// ([`Mesh::outward_indices`]).
pub fn wound_against_normals([a, b, c]: [DVec3; 3], [na, nb, nc]: [DVec3; 3]) -> bool {
    (b - a).cross(c - a).dot(na + nb + nc) < 0.0
}

/// A mesh's point or normal (f32, as meshes store them) in f64, exactly.
pub fn widen(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// The triangles and vertices of a built-in mesh (`None` for a file, known only once read),
/// counted on the mesh itself (the largest, the sphere, is 4 096 triangles).
pub fn built_in_size(source: &MeshSource) -> Option<(usize, usize)> {
    let mesh = match source {
        MeshSource::File(_) => return None,
        built_in => load(built_in, Path::to_path_buf).ok()?,
    };
    Some((mesh.triangles(), mesh.positions.len()))
}

/// Load a scene mesh; `path` resolves file paths.
pub fn load(source: &MeshSource, path: impl Fn(&Path) -> PathBuf) -> Result<Mesh, MeshError> {
    match source {
        MeshSource::Cube => Ok(cube()),
        MeshSource::Sphere => Ok(sphere(64, 32)),
        MeshSource::Room => Ok(room()),
        MeshSource::Plane => Ok(plane()),
        MeshSource::Prism => Ok(prism()),
        MeshSource::File(file) => load_obj(&path(file)),
    }
}

/// The cube with flat faces, corners on the unit sphere (half-size 1/√3).
pub fn cube() -> Mesh {
    let h = 1.0 / 3f32.sqrt();
    let mut mesh = Mesh::default();
    // (normal, two in-plane axes u, v with u × v = normal)
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
    ];
    for (normal, u, v) in faces {
        let base = mesh.positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            mesh.positions.push(std::array::from_fn(|i| h * (normal[i] + su * u[i] + sv * v[i])));
            mesh.normals.push(normal);
        }
        mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    mesh
}

/// The room: the box [−1, 1]³ with flat faces pointing inwards (counter-clockwise seen from
/// inside), so a camera and objects inside it see its walls.
pub fn room() -> Mesh {
    let mut mesh = cube();
    for p in &mut mesh.positions {
        *p = p.map(f32::signum); // the cube's corners are (±1/√3, ±1/√3, ±1/√3)
    }
    for n in &mut mesh.normals {
        *n = n.map(|x| -x);
    }
    for triangle in mesh.indices.chunks_exact_mut(3) {
        triangle.swap(1, 2);
    }
    mesh
}

/// The plane: the square [−1, 1]² in y = 0, facing +y (two triangles).
pub fn plane() -> Mesh {
    Mesh {
        positions: vec![[-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0]],
        normals: vec![[0.0, 1.0, 0.0]; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// The prism: an equilateral triangular prism with flat faces, corners on the unit sphere.
/// Its cross-section in the xz plane has corners at angles 0°, 120° and 240° on a circle of
/// radius 1/√2 (the apex edge at +x, so a ray along +z meets the face whose outward normal
/// is (½, 0, −√3/2) at 30° and leaves through the one of (½, 0, √3/2): an apex angle of
/// 60°), extruded over y ∈ [−1/√2, 1/√2].
pub fn prism() -> Mesh {
    let r = std::f32::consts::FRAC_1_SQRT_2;
    let corner = |degrees: f32, y: f32| [r * degrees.to_radians().cos(), y, r * degrees.to_radians().sin()];
    let mut mesh = Mesh::default();
    let mut quad = |corners: [[f32; 3]; 4], normal: [f32; 3]| {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(corners);
        mesh.normals.extend([normal; 4]);
        mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    };
    // The three sides, each between two corners of the section, normal at their mid-angle.
    // The last side ends at the first corner itself (0°, not 360°, whose f32 sine is 1.2e-7:
    // the seam would not close).
    for (a, b, mid) in [(0.0f32, 120.0f32, 60.0f32), (120.0, 240.0, 180.0), (240.0, 0.0, 300.0)] {
        let mid = mid.to_radians();
        quad([corner(a, -r), corner(a, r), corner(b, r), corner(b, -r)], [mid.cos(), 0.0, mid.sin()]);
    }
    // The two ends, counter-clockwise seen from outside like every face.
    for (y, normal, turn) in [(r, 1.0f32, [0.0f32, 240.0, 120.0]), (-r, -1.0, [0.0, 120.0, 240.0])] {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(turn.map(|degrees| corner(degrees, y)));
        mesh.normals.extend([[0.0, normal, 0.0]; 3]);
        mesh.indices.extend([base, base + 1, base + 2]);
    }
    mesh
}

/// A UV sphere of radius 1 with exact normals: `segments` around, `rings` pole to pole.
/// The seam's second column of vertices lies exactly on the first (its angle is 0, not 2π,
/// whose f32 sine is 1.7e-7) and each pole's ring on the pole itself (sin π in f32 is not
/// 0), so the surface is closed.
pub fn sphere(segments: u32, rings: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for ring in 0..=rings {
        let polar = std::f32::consts::PI * ring as f32 / rings as f32;
        let (sin_polar, cos_polar) = if ring == rings { (0.0, -1.0) } else { polar.sin_cos() };
        for segment in 0..=segments {
            let azimuth = std::f32::consts::TAU * (segment % segments) as f32 / segments as f32;
            let p = [sin_polar * azimuth.cos(), cos_polar, sin_polar * azimuth.sin()];
            mesh.positions.push(p);
            mesh.normals.push(p);
        }
    }
    let row = segments + 1;
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * row + segment;
            let b = a + row;
            mesh.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    mesh
}

/// The most bytes read from an OBJ file (the sculpture's is about 9 MB).
pub const MAX_OBJ_BYTES: u64 = 1 << 30;

/// Read an OBJ file (all models merged, triangulated; a regular file of at most
/// [`MAX_OBJ_BYTES`], whose parsed mesh fits the memory budget), normalise it to the unit
/// sphere and, where the file has no normals, compute smooth area-weighted vertex normals.
pub fn load_obj(file: &Path) -> Result<Mesh, MeshError> {
    let error = |problem: MeshProblem| MeshError { file: file.into(), problem };
    let opened = nklut_optics::db::file::open_regular(file).map_err(|e| error(MeshProblem::Unreadable(e)))?;
    // The parsed mesh takes a few times the text's bytes (tobj's lists, then ours).
    let stated = opened.metadata().map(|m| m.len()).unwrap_or(0);
    nklut_tables::budget::MemoryBudget::of_machine()
        .check("mesh", format!("the {stated}-byte OBJ file parsed"), 4 * u128::from(stated))
        .map_err(|e| error(MeshProblem::Memory(e)))?;
    let mut bytes = Vec::new();
    let length = nklut_optics::db::file::read_opened(opened, MAX_OBJ_BYTES, &mut bytes).map_err(|e| error(MeshProblem::Unreadable(e)))?;
    bytes.truncate(length);
    // The triangles its faces make, counted on the text before tobj parses it (its face
    // list alone takes about 100 bytes a face): the scene geometry's estimate per triangle.
    let triangles = obj_triangles(&bytes);
    nklut_tables::budget::MemoryBudget::of_machine()
        .check("mesh", format!("its {triangles} triangles (the scene geometry's estimate, BVH included)"), traced_bytes(triangles))
        .map_err(|e| error(MeshProblem::Memory(e)))?;
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    // Materials are not read (a scene names its own).
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| error(MeshProblem::Obj(e)))?;
    let mut mesh = Mesh::default();
    let mut has_normals = true;
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]));
        if m.normals.len() == m.positions.len() {
            mesh.normals.extend(m.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]));
        } else {
            has_normals = false;
        }
        mesh.indices.extend(m.indices.iter().map(|i| base + i));
    }
    if mesh.indices.is_empty() {
        return Err(error(MeshProblem::NoTriangles));
    }
    if mesh.indices.iter().any(|&i| i as usize >= mesh.positions.len()) {
        return Err(error(MeshProblem::MissingVertex));
    }
    if mesh.positions.iter().flatten().any(|x| !x.is_finite()) {
        return Err(error(MeshProblem::NonFinitePosition));
    }
    if mesh.normals.iter().flatten().any(|x| !x.is_finite()) {
        return Err(error(MeshProblem::NonFiniteNormal));
    }
    // Normalised first: the normals of faces the size of f32's range would overflow.
    normalise_to_unit_sphere(&mut mesh.positions);
    if !has_normals {
        mesh.normals = smooth_normals(&mesh.positions, &mesh.indices);
    }
    Ok(mesh)
}

/// The triangles the faces of an OBJ text make as tobj reads them triangulated: each
/// line whose first word is `f` or `l` (words split at Unicode white space, as tobj splits
/// them) with k corners makes k − 2 triangles, a point or a line (1 or 2 corners) one
/// degenerate triangle. Text past the first byte that is not UTF-8 is not counted (tobj stops there).
pub fn obj_triangles(bytes: &[u8]) -> u128 {
    let valid = match std::str::from_utf8(bytes) {
        Ok(_) => bytes,
        Err(e) => &bytes[..e.valid_up_to()],
    };
    valid.split(|&b| b == b'\n').map(face_triangles).sum()
}

/// The triangles of one OBJ line (see [`obj_triangles`]); ASCII lines, nearly all, without
/// decoding them.
fn face_triangles(line: &[u8]) -> u128 {
    let corners = if line.is_ascii() {
        // The ASCII characters Unicode calls white space (vertical tab included).
        let space = |b: &u8| matches!(b, b' ' | b'\t' | b'\n' | b'\x0B' | b'\x0C' | b'\r');
        let mut words = line.split(space).filter(|word| !word.is_empty());
        if !matches!(words.next(), Some(b"f" | b"l")) {
            return 0;
        }
        words.count()
    } else {
        let mut words = std::str::from_utf8(line).unwrap_or_default().split_whitespace();
        if !matches!(words.next(), Some("f" | "l")) {
            return 0;
        }
        words.count()
    } as u128;
    match corners {
        0 => 0,
        1 | 2 => 1,
        k => k - 2,
    }
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalised(v: [f64; 3]) -> [f32; 3] {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 {
        [(v[0] / length) as f32, (v[1] / length) as f32, (v[2] / length) as f32]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Smooth vertex normals: the sum of the adjacent faces' (b − a) × (c − a), whose length is
/// twice the face area, so larger faces weigh more; then normalised.
pub fn smooth_normals(positions: &[[f32; 3]], indices: &[u32]) -> Vec<[f32; 3]> {
    let mut sums = vec![[0.0f64; 3]; positions.len()];
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|i| positions[triangle[i] as usize]);
        let face = cross(sub(b, a), sub(c, a));
        for &vertex in triangle {
            for axis in 0..3 {
                sums[vertex as usize][axis] += face[axis] as f64;
            }
        }
    }
    sums.into_iter().map(normalised).collect()
}

/// Centre on the bounding-box centre and scale so the farthest vertex lies on the unit
/// sphere, in f64 (finite f32 positions anywhere in f32's range give finite results).
pub fn normalise_to_unit_sphere(positions: &mut [[f32; 3]]) {
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for p in positions.iter() {
        for axis in 0..3 {
            low[axis] = low[axis].min(f64::from(p[axis]));
            high[axis] = high[axis].max(f64::from(p[axis]));
        }
    }
    let centre: [f64; 3] = std::array::from_fn(|axis| 0.5 * (low[axis] + high[axis]));
    let offset = |p: &[f32; 3]| -> [f64; 3] { std::array::from_fn(|axis| f64::from(p[axis]) - centre[axis]) };
    let radius = positions.iter().map(|p| offset(p).iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0f64, f64::max);
    let scale = if radius > 0.0 { 1.0 / radius } else { 1.0 };
    for p in positions.iter_mut() {
        let d = offset(p);
        *p = std::array::from_fn(|axis| (d[axis] * scale) as f32);
    }
}

/// The largest coordinate a triangle's corner may have: the BVH is built in f32 (boxes,
/// Morton codes of their centres), where a corner near f32's range turns into infinities,
/// and the builder then indexes out of bounds. Placed scenes stay within ±2e4
/// (`scene::MAX_COORDINATE` and `SCALE_RANGE`).
pub const MAX_CORNER: f64 = 1e6;

/// A scene that cannot be traced.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    #[error("the scene has no triangles to trace")]
    Empty,
    #[error("object {object}'s triangle {triangle} has a corner at {corner:?}, beyond the ±{MAX_CORNER:e} the tracer takes")]
    OutOfBounds { object: usize, triangle: usize, corner: [f64; 3] },
}

/// Checks of a mesh's surface, for the tests of this layer and the layers above.
#[cfg(test)]
pub(crate) mod checks {
    use super::{cross, sub, Mesh};

    /// Every triangle's winding (b − a) × (c − a) points along its vertices' normal (a
    /// triangle of no area, at a sphere's pole, has no winding).
    pub fn wound_along_normals(mesh: &Mesh) -> bool {
        mesh.indices.chunks_exact(3).all(|triangle| {
            let [a, b, c] = [0, 1, 2].map(|i| mesh.positions[triangle[i] as usize]);
            let face = cross(sub(b, a), sub(c, a));
            face == [0.0; 3] || face.iter().zip(mesh.normals[triangle[0] as usize]).map(|(f, n)| f * n).sum::<f32>() > 0.0
        })
    }

    /// Whether every edge of the mesh, by its corners' exact positions, is shared by exactly
    /// two triangles: the surface is closed, with no crack a ray could pass through.
    /// Triangles with two corners in one place (a sphere's pole) have no area and are left
    /// out, with their edges.
    pub fn closed(mesh: &Mesh) -> bool {
        let mut edges: std::collections::HashMap<[[u32; 3]; 2], usize> = std::collections::HashMap::new();
        for triangle in mesh.indices.chunks_exact(3) {
            // −0 and 0 are one place.
            let corners = [0, 1, 2].map(|i| mesh.positions[triangle[i] as usize].map(|x| (x + 0.0).to_bits()));
            if corners[0] == corners[1] || corners[1] == corners[2] || corners[2] == corners[0] {
                continue;
            }
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let mut edge = [corners[a], corners[b]];
                edge.sort();
                *edges.entry(edge).or_default() += 1;
            }
        }
        edges.values().all(|&count| count == 2)
    }
}

#[cfg(test)]
mod tests {
    use super::checks::{closed, wound_along_normals};
    use super::*;

    fn radius(mesh: &Mesh) -> f32 {
        mesh.positions.iter().map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()).fold(0.0, f32::max)
    }

    /// Rewound for the GPU, every triangle runs counter-clockwise seen from where its normals
    /// point: an octahedron whose file winds half its faces the other way comes out wound
    /// along its normals, with each triangle's corners kept; the built-in meshes, wound so
    /// already, come out unchanged.
    #[test]
    fn outward_indices_wind_every_triangle_along_its_normals() {
        let corners = [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        let mut octahedron = Mesh { positions: corners.to_vec(), normals: corners.to_vec(), indices: Vec::new() };
        for x in [0, 1] {
            for y in [2, 3] {
                for z in [4, 5] {
                    octahedron.indices.extend([x, y, z]);
                }
            }
        }
        // Faces (x, y, z) in octants whose signs multiply to −1 run clockwise from outside.
        assert!(!wound_along_normals(&octahedron));
        let rewound = Mesh { indices: octahedron.outward_indices(), ..octahedron.clone() };
        assert!(wound_along_normals(&rewound));
        let flipped = rewound.indices.chunks_exact(3).zip(octahedron.indices.chunks_exact(3)).filter(|(a, b)| a != b).count();
        assert_eq!(flipped, 4);
        for (a, b) in rewound.indices.chunks_exact(3).zip(octahedron.indices.chunks_exact(3)) {
            let (mut a, mut b) = (a.to_vec(), b.to_vec());
            a.sort();
            b.sort();
            assert_eq!(a, b);
        }
        for mesh in [cube(), room(), sphere(64, 32), prism(), plane()] {
            assert_eq!(mesh.outward_indices(), mesh.indices);
        }
    }

    #[test]
    fn cube_faces_point_outwards_and_fit_the_unit_sphere() {
        let mesh = cube();
        assert_eq!(mesh.triangles(), 12);
        assert!((radius(&mesh) - 1.0).abs() < 1e-6);
        assert!(wound_along_normals(&mesh), "counter-clockwise seen from outside");
    }

    #[test]
    fn the_built_in_solids_are_closed() {
        assert!(closed(&cube()));
        let prism = prism();
        assert_eq!(prism.triangles(), 8);
        assert!(wound_along_normals(&prism));
        assert!(closed(&prism), "the seam at 0° must meet itself");
        for (segments, rings) in [(16, 8), (64, 32), (7, 3)] {
            let sphere = sphere(segments, rings);
            assert!(wound_along_normals(&sphere) && closed(&sphere), "sphere {segments}×{rings}");
        }
        assert!(!closed(&plane()));
    }

    #[test]
    fn room_faces_inwards_and_plane_faces_up() {
        let room = room();
        assert_eq!(room.triangles(), 12);
        assert!(wound_along_normals(&room));
        for (p, n) in room.positions.iter().zip(&room.normals) {
            assert!(p.iter().all(|x| x.abs() == 1.0), "{p:?}");
            // The normal points back towards the centre: n·p < 0.
            assert!(p.iter().zip(n).map(|(p, n)| p * n).sum::<f32>() < 0.0);
        }
        let plane = plane();
        assert!(wound_along_normals(&plane) && plane.normals.iter().all(|n| *n == [0.0, 1.0, 0.0]));
    }

    #[test]
    fn placement_scales_then_moves_and_keeps_normals_perpendicular() {
        let placement = Placement { position: [1.0, 2.0, 3.0], scale: [2.0, 1.0, 4.0] };
        let mesh = sphere(16, 8).placed(&placement);
        // A point (x, y, z) of the unit sphere lands on ((X−1)/2)² + (Y−2)² + ((Z−3)/4)² = 1,
        // whose gradient (¼(X−1), 2(Y−2), ⅛(Z−3)) is along the placed normal.
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let [x, y, z] = [(p[0] - 1.0) / 2.0, p[1] - 2.0, (p[2] - 3.0) / 4.0];
            assert!((x * x + y * y + z * z - 1.0).abs() < 1e-5);
            let gradient = [x / 2.0, y, z / 4.0];
            let g = gradient.iter().map(|g| g * g).sum::<f32>().sqrt();
            let along: f32 = gradient.iter().zip(n).map(|(g, n)| g * n).sum::<f32>() / g;
            assert!((along - 1.0).abs() < 1e-5, "{n:?} vs {gradient:?}");
        }
        assert!(wound_along_normals(&plane().placed(&placement)));
    }

    #[test]
    fn smooth_normals_of_a_tetrahedron_corner_weigh_by_area() {
        // Two faces meeting at vertex 0: a big one in z = 0 and a small one in x = 0.
        let positions = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 1.0]];
        let indices = [0, 1, 2, 0, 2, 3];
        let normals = smooth_normals(&positions, &indices);
        let n = normals[0];
        // face normals (0,0,16) and (4,0,0): sum (4,0,16) normalised
        let expected = normalised([4.0, 0.0, 16.0]);
        assert!(n.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-6), "{n:?}");
    }

    #[test]
    fn obj_without_normals_is_normalised_with_smooth_normals() {
        let dir = std::env::temp_dir().join(format!("nklut-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("quad.obj");
        std::fs::write(&file, "v 10 10 0\nv 14 10 0\nv 14 13 0\nv 10 13 0\nf 1 2 3 4\n").unwrap();
        let mesh = load_obj(&file).unwrap();
        assert_eq!(mesh.triangles(), 2);
        assert!((radius(&mesh) - 1.0).abs() < 1e-6);
        assert!(mesh.normals.iter().all(|n| (n[2] - 1.0).abs() < 1e-6));
        std::fs::write(&file, "v 0 0 0\n").unwrap();
        assert!(matches!(load_obj(&file).unwrap_err().problem, MeshProblem::NoTriangles));
        std::fs::write(&file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n").unwrap();
        assert!(matches!(load_obj(&file).map(|m| m.triangles()), Err(MeshError { problem: MeshProblem::Obj(_), .. }) | Ok(1)));
        let missing = load_obj(&dir.join("missing.obj")).unwrap_err();
        assert!(matches!(missing.problem, MeshProblem::Unreadable(FileProblem::Io(_))), "{missing}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The count before parsing is the count tobj's triangulation gives: a triangle 1, a
    /// quad 2, a pentagon 3 (a fan), a point and a line one degenerate triangle each; a
    /// face word after a tab, an ideographic space (U+3000, white space to tobj too) or at
    /// a CRLF line; comments, `fo` words and other records none.
    #[test]
    fn faces_are_counted_as_tobj_triangulates_them() {
        let vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 2 1\n";
        let cases = [
            ("f 1 2 3\n", 1),
            ("f 1 2 3 4\n", 2),
            ("f 1 2 3 4 5\n", 3),
            ("f 1 2 3\r\nf\t1 3 4\r\n", 2),
            ("f\u{3000}1 2 3 4\n", 2),
            ("f 1 2 3\nl 1 2\nf 1 2 3\n", 3),
            ("# f 1 2 3\nfo 1 2 3\nvn 0 0 1\nf 1//1 2//1 3//1 4//1 5//1\n", 3),
        ];
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("faces.obj");
        for (faces, triangles) in cases {
            let text = format!("{vertices}{faces}");
            assert_eq!(obj_triangles(text.as_bytes()), triangles, "{faces:?}");
            // tobj's own count agrees wherever it reads the file.
            std::fs::write(&file, &text).unwrap();
            if let Ok(mesh) = load_obj(&file) {
                assert_eq!(mesh.triangles() as u128, triangles, "{faces:?}");
            }
        }
        // Past a byte that is not UTF-8 nothing is counted: tobj stops reading there.
        let mut broken = b"f 1 2 3\nf 1 2 3\n".to_vec();
        broken.extend_from_slice(b"\xff\nf 1 2 3\n");
        assert_eq!(obj_triangles(&broken), 2);
    }
}

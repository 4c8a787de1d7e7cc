//! Closed, self-occluding test and benchmark meshes for ambient occlusion, built on the UV
//! sphere's grid (`crate::scene::mesh::sphere`): a torus with exact normals and a sphere with
//! radial bumps.

use crate::scene::mesh::{smooth_normals, sphere, Mesh};

/// A torus about the y axis: ring radius `major`, tube radius `minor`, exact outward
/// normals; `segments` around the ring and `sides` around the tube (the sphere's grid with
/// its seam vertices doubled, re-placed: grid column → angle around the ring, row → angle
/// around the tube; the doubled vertices at angle 0, not 2π, so both seams close, and each
/// triangle turned to wind counter-clockwise seen from outside).
pub fn torus(major: f32, minor: f32, segments: u32, sides: u32) -> Mesh {
    let mut mesh = sphere(segments, sides);
    let columns = segments + 1;
    for triangle in mesh.indices.chunks_exact_mut(3) {
        triangle.swap(1, 2);
    }
    for (k, (p, n)) in mesh.positions.iter_mut().zip(mesh.normals.iter_mut()).enumerate() {
        let (row, column) = (k as u32 / columns, k as u32 % columns);
        let u = std::f32::consts::TAU * (column % segments) as f32 / segments as f32;
        let v = std::f32::consts::TAU * (row % sides) as f32 / sides as f32;
        *n = [v.cos() * u.cos(), v.sin(), v.cos() * u.sin()];
        *p = [(major + minor * v.cos()) * u.cos(), minor * v.sin(), (major + minor * v.cos()) * u.sin()];
    }
    mesh
}

/// A sphere with radial bumps, r = 1 + amplitude · sin(lobes·θ) · sin(lobes·φ): closed,
/// with valleys whose walls hide each other; smooth normals from the faces.
pub fn bumpy_sphere(segments: u32, amplitude: f32, lobes: f32) -> Mesh {
    let mut mesh = sphere(segments, segments / 2);
    for p in &mut mesh.positions {
        let theta = p[1].clamp(-1.0, 1.0).acos();
        let phi = p[2].atan2(p[0]);
        let r = 1.0 + amplitude * (lobes * theta).sin() * (lobes * phi).sin();
        *p = p.map(|x| x * r);
    }
    mesh.normals = smooth_normals(&mesh.positions, &mesh.indices);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::checks::{closed, wound_along_normals};

    #[test]
    fn the_torus_is_closed_and_wound_counter_clockwise_from_outside() {
        for (segments, sides) in [(24, 12), (8, 6), (5, 3)] {
            let torus = torus(1.0, 0.6, segments, sides);
            assert!(wound_along_normals(&torus), "{segments}×{sides}");
            assert!(closed(&torus), "{segments}×{sides}: both seams meet themselves");
        }
    }
}

//! The camera path of SPEC §6: a circle around an axis through the origin, looking at the
//! origin, up = the axis. Column-major 4×4 matrices, clip depth 0..1 (WebGPU convention).

use crate::scene::CameraPath;

pub type Vec3 = [f64; 3];
/// Column-major: `m[column][row]`.
pub type Mat4 = [[f64; 4]; 4];

fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn normalise(a: Vec3) -> Vec3 {
    let length = dot(a, a).sqrt();
    [a[0] / length, a[1] / length, a[2] / length]
}

/// One frame of the path: the eye position and the view-projection matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub eye: Vec3,
    pub view_proj: Mat4,
}

/// Eye of frame `i`: distance·(cos φ u + sin φ v), φ = i·degrees_per_frame, where u, v are
/// an orthonormal basis of the plane perpendicular to the axis (u from the coordinate axis
/// least aligned with it).
pub fn eye(path: &CameraPath, frame: u32) -> Vec3 {
    let axis = normalise(path.axis);
    let least = (0..3).min_by(|&i, &j| axis[i].abs().total_cmp(&axis[j].abs())).unwrap_or(0);
    let mut helper = [0.0; 3];
    helper[least] = 1.0;
    let u = normalise(cross(axis, helper));
    let v = cross(axis, u);
    let phi = (frame as f64 * path.degrees_per_frame).to_radians();
    std::array::from_fn(|i| path.distance * (phi.cos() * u[i] + phi.sin() * v[i]))
}

/// Right-handed look-at from `eye` to the origin with `up`.
pub fn look_at_origin(eye: Vec3, up: Vec3) -> Mat4 {
    let forward = normalise([-eye[0], -eye[1], -eye[2]]);
    let side = normalise(cross(forward, up));
    let up = cross(side, forward);
    [
        [side[0], up[0], -forward[0], 0.0],
        [side[1], up[1], -forward[1], 0.0],
        [side[2], up[2], -forward[2], 0.0],
        [-dot(side, eye), -dot(up, eye), dot(forward, eye), 1.0],
    ]
}

/// Right-handed perspective, depth 0 at `near` and 1 at `far`.
pub fn perspective(fov_y_degrees: f64, aspect: f64, near: f64, far: f64) -> Mat4 {
    let f = 1.0 / (fov_y_degrees.to_radians() / 2.0).tan();
    let range = far / (near - far);
    [[f / aspect, 0.0, 0.0, 0.0], [0.0, f, 0.0, 0.0], [0.0, 0.0, range, -1.0], [0.0, 0.0, near * range, 0.0]]
}

pub fn multiply(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|column| std::array::from_fn(|row| (0..4).map(|i| a[i][row] * b[column][i]).sum()))
}

/// Frame `i` of the path for a target of `width`×`height`. Objects fit the unit sphere, so
/// near/far bracket distance ∓ 1 generously.
pub fn frame(path: &CameraPath, i: u32, width: u32, height: u32) -> Frame {
    frame_within(path, i, width, height, (path.distance - 1.0) * 0.5, path.distance + 2.0)
}

/// Frame `i` with depth kept between `near` and `far` from the eye (a scene the camera
/// stands inside, such as a room, needs more than [`frame`]'s range).
pub fn frame_within(path: &CameraPath, i: u32, width: u32, height: u32, near: f64, far: f64) -> Frame {
    let eye = eye(path, i);
    let view = look_at_origin(eye, normalise(path.axis));
    let projection = perspective(path.fov_y_degrees, width as f64 / height as f64, near, far);
    Frame { eye, view_proj: multiply(&projection, &view) }
}

/// A point through a matrix, with the perspective divide.
pub fn project(m: &Mat4, p: Vec3) -> Vec3 {
    let v: [f64; 4] = std::array::from_fn(|row| m[0][row] * p[0] + m[1][row] * p[1] + m[2][row] * p[2] + m[3][row]);
    [v[0] / v[3], v[1] / v[3], v[2] / v[3]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_stays_at_distance_perpendicular_to_the_axis() {
        let path = CameraPath::default();
        let axis = normalise(path.axis);
        for i in [0, 45, 90, 179] {
            let e = eye(&path, i);
            assert!((dot(e, e).sqrt() - 2.0).abs() < 1e-12);
            assert!(dot(e, axis).abs() < 1e-12);
        }
        let (a, b) = (eye(&path, 0), eye(&path, 1));
        let angle = (dot(a, b) / 4.0).acos().to_degrees();
        assert!((angle - 1.0).abs() < 1e-9);
    }

    #[test]
    fn origin_projects_to_the_centre_and_the_unit_sphere_fits() {
        let path = CameraPath::default();
        let f = frame(&path, 10, 128, 128);
        let centre = project(&f.view_proj, [0.0; 3]);
        assert!(centre[0].abs() < 1e-12 && centre[1].abs() < 1e-12 && centre[2] > 0.0 && centre[2] < 1.0);
        // The point of the unit sphere along the axis (up) lands inside the frame.
        let top = project(&f.view_proj, normalise(path.axis));
        assert!(top[1] > 0.0 && top[1] < 1.0, "{top:?}");
    }
}

//! Screen-space ground-truth ambient occlusion (GTAO): Jimenez, Wu, Pesce and Jarabo,
//! "Practical Real-Time Strategies for Accurate Indirect Occlusion" (SIGGRAPH 2016 course
//! notes; Activision ATVI-TR-16-01), §3–4 and Algorithm 1 — the screen-space technique
//! engines ship (Unreal, Unity HDRP), measured beside surfel AO against the same
//! ray-traced reference, on the same frames.
//!
//! Derivation. Accessibility is the cosine-weighted open fraction of the hemisphere about
//! the unit normal n, A = (1/π) ∫ V(ω) (n·ω)⁺ dω. Parametrise the sphere by planes through
//! the view vector v (slices, at angle φ ∈ [0, π) in the image) and the angle θ from v
//! within a slice (θ ∈ (−π, π], positive toward the slice's image direction):
//! dω = |sin θ| dθ dφ. In a slice, n projects to n_φ = n − (n·a) a (a the slice plane's unit
//! normal), of length |n_φ| and at angle γ from v; then n·ω = |n_φ| cos(θ − γ). Where the
//! visible surface is a heightfield seen from the point (all between a horizon and the
//! tangent plane occluded), the open directions of the slice are θ ∈ [h₋, h₊], h₋ ≤ 0 ≤ h₊,
//! clamped to the hemisphere about n (γ − π/2 ≤ h₋, h₊ ≤ γ + π/2). Splitting the inner
//! integral at θ = 0, where |sin θ| changes sign, gives the paper's eq. 10:
//!
//!   â(φ) = |n_φ| · ¼ [(−cos(2h₋ − γ) + cos γ + 2h₋ sin γ) + (−cos(2h₊ − γ) + cos γ + 2h₊ sin γ)]
//!
//! and A = (1/π) ∫₀^π â(φ) dφ, here the mean over `slices` equally spaced φ (midpoints, the
//! same at every pixel: deterministic, no noise to filter). Check: an open plane facing the
//! viewer (γ = 0, h± = ±π/2) gives â = ¼ (2 + 2) = 1. φ must turn evenly about v: slices
//! taken evenly in image angle (as Algorithm 1 and XeGTAO do) are uneven about v away from
//! the image centre, and an open plane seen there at 60° off-axis comes out 0.99, not 1;
//! here φ is the angle about v and each slice's image direction is where P + ε·(its
//! direction) projects.
//!
//! Horizons (Algorithm 1): from the pixel's view-space point P, `steps` samples on each
//! side along the slice's image direction, evenly spaced out to the projected radius
//! (radius · f / −P_z pixels, f the focal length in pixels). Each reads the G-buffer's
//! sample at the pixel it falls in and takes the point where the ray through the sample's
//! own position meets that texel's plane ([`texel_plane_point`]); where 0 < |Q − P| <
//! radius it raises that side's horizon cosine (Q − P)·v / |Q − P|, which starts at the
//! tangent plane. A perspective camera maps the image line through P's pixel onto the
//! plane through the eye, P and the slice direction, so the samples lie in the slice. The normal's angle takes the saturated cosine (γ ∈ [−π/2, π/2]) as engines do,
//! so a normal interpolated past the silhouette does not flip the integral.
//!
//! What a depth buffer cannot show is not there: occluders off screen, behind the visible
//! surface or farther than the radius (the reference sees them all); and the visible
//! surface is taken as solid behind it (a thin object occludes like a wall).
//!
//! One body over [`Real`]: f64 for the figures, and f32 in the operation order of
//! `shaders/gtao.wgsl`, its twin.

use glam::DVec3;
use rayon::prelude::*;

use super::experiment::PixelSample;
use super::surfel::Surfel;
use crate::scene::surfels::Gtao;
use crate::trace::Camera;
use nklut_optics::fresnel::Real;

/// A covered pixel: its view-space point and unit normal (x right, y up, the camera at the
/// origin looking down −z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSample<T> {
    pub position: [T; 3],
    pub normal: [T; 3],
}

/// What GTAO reads: per pixel (row-major, top row first) the view-space sample or `None`
/// (no surface), and the focal length in pixels: the view-space point (x, y, z) lies at
/// pixel coordinates (w/2 + f·x/−z, h/2 − f·y/−z).
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer<T> {
    pub width: u32,
    pub height: u32,
    pub focal: T,
    pub samples: Vec<Option<ViewSample<T>>>,
}

impl<T: Real> GBuffer<T> {
    /// The sample at pixel coordinates (`x`, `y`) already floored; `None` off the image or
    /// where no surface is.
    fn at(&self, x: T, y: T) -> Option<&ViewSample<T>> {
        if x < T::ZERO || y < T::ZERO || !(x < T::count(self.width as usize)) || !(y < T::count(self.height as usize)) {
            return None;
        }
        self.samples.get(y.index() * self.width as usize + x.index())?.as_ref()
    }
}

impl GBuffer<f64> {
    /// The G-buffer of `camera`'s frame from what each pixel sees (`coverage`, from
    /// `SurfelScene::coverage`): the point and the smooth normal interpolated from the
    /// triangle's vertices (surfel centres and normals), as a rasteriser writes them.
    pub fn from_coverage(camera: &Camera, coverage: &[Option<PixelSample>], surfels: &[Surfel]) -> GBuffer<f64> {
        let samples = coverage
            .iter()
            .map(|pixel| {
                let pixel = pixel.as_ref()?;
                let (mut point, mut normal) = (DVec3::ZERO, DVec3::ZERO);
                for (&corner, &weight) in pixel.corners.iter().zip(&pixel.weights) {
                    point += weight * surfels[corner].centre;
                    normal += weight * surfels[corner].normal;
                }
                let normal = camera.view_direction(normal.try_normalize().unwrap_or(surfels[pixel.corners[0]].normal));
                Some(ViewSample { position: camera.view_point(point).to_array(), normal: normal.to_array() })
            })
            .collect();
        GBuffer { width: camera.width, height: camera.height, focal: camera.focal_pixels(), samples }
    }

    /// The same buffer in f32 (what the GPU pass is given).
    pub fn narrowed(&self) -> GBuffer<f32> {
        let narrow = |v: [f64; 3]| v.map(|x| x as f32);
        GBuffer {
            width: self.width,
            height: self.height,
            focal: self.focal as f32,
            samples: self
                .samples
                .iter()
                .map(|s| s.map(|s| ViewSample { position: narrow(s.position), normal: narrow(s.normal) }))
                .collect(),
        }
    }
}

fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn along<T: Real>(a: [T; 3], s: T, b: [T; 3]) -> [T; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// Eq. 10: a slice's open fraction, weighted by the projected normal's `length`, between
/// the horizons `h_minus` ≤ 0 ≤ `h_plus` (angles from v) with the normal at angle `gamma`.
/// The twin of `slice_visibility` in `shaders/gtao.wgsl`.
pub fn slice_visibility<T: Real>(h_minus: T, h_plus: T, gamma: T, length: T) -> T {
    let (cos_g, sin_g) = (gamma.cos(), gamma.sin());
    let two = T::of(2.0);
    let side_minus = -(two * h_minus - gamma).cos() + cos_g + two * h_minus * sin_g;
    let side_plus = -(two * h_plus - gamma).cos() + cos_g + two * h_plus * sin_g;
    length * T::of(0.25) * (side_minus + side_plus)
}

/// GTAO's parameters in a precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parameters<T> {
    pub radius: T,
    pub slices: u32,
    pub steps: u32,
}

impl Parameters<f64> {
    pub fn of(gtao: Gtao) -> Parameters<f64> {
        Parameters { radius: gtao.radius, slices: gtao.slices, steps: gtao.steps }
    }

    pub fn narrowed(self) -> Parameters<f32> {
        Parameters { radius: self.radius as f32, slices: self.slices, steps: self.steps }
    }
}

/// Where the ray through pixel coordinates (`x`, `y`) meets the plane of the texel sample
/// `q` (its point and normal): the surface at the sample's own position rather than at
/// its texel's centre, so that a sample lies in its slice; `q`'s point where the ray
/// grazes that plane (|cos| ≤ 0.1) or meets it behind the eye. On a plane this is exact;
/// nearest-texel points alone lift the horizon of an open plane seen at 60° from its normal
/// by up to 0.03 in accessibility (the sample off the slice by up to half a pixel). The twin
/// of `texel_plane_point` in `shaders/gtao.wgsl`.
pub fn texel_plane_point<T: Real>(g: &GBuffer<T>, q: &ViewSample<T>, x: T, y: T) -> [T; 3] {
    let half = T::of(0.5);
    let ray = [(x - half * T::count(g.width as usize)) / g.focal, -(y - half * T::count(g.height as usize)) / g.focal, -T::ONE];
    let facing = dot(ray, q.normal);
    if !(facing.abs() > T::of(0.1) * dot(ray, ray).sqrt()) {
        return q.position;
    }
    let t = dot(q.position, q.normal) / facing;
    if t > T::ZERO {
        ray.map(|r| r * t)
    } else {
        q.position
    }
}

/// The accessibility GTAO gives pixel (`x`, `y`) of `g` (`None`: no surface there). The
/// twin of `pixel_visibility` in `shaders/gtao.wgsl`.
pub fn pixel_visibility<T: Real>(g: &GBuffer<T>, x: u32, y: u32, p: Parameters<T>) -> Option<T> {
    let (px, py) = (T::count(x as usize), T::count(y as usize));
    let here = *g.at(px, py)?;
    let position = here.position;
    let distance = dot(position, position).sqrt();
    let depth = -position[2];
    if !(distance > T::ZERO) || !(depth > T::ZERO) || p.slices == 0 {
        return Some(T::ONE);
    }
    let v = position.map(|c| -c / distance);
    let n = here.normal;
    let half = T::of(0.5);
    let half_pi = T::of(std::f64::consts::FRAC_PI_2);
    let pi = T::of(std::f64::consts::PI);
    let radius_pixels = p.radius * g.focal / depth;
    let radius2 = p.radius * p.radius;
    // The slices turn about v evenly: e₁ the image's x axis made perpendicular to v (never
    // parallel: P lies in front of the eye), e₂ = v × e₁.
    let x_axis = [T::ONE, T::ZERO, T::ZERO];
    let e1 = along(x_axis, -v[0], v);
    let e1_length = dot(e1, e1).sqrt();
    let e1 = e1.map(|e| e / e1_length);
    let e2 = cross(v, e1);
    let mut total = T::ZERO;
    for slice in 0..p.slices {
        let phi = pi * (T::count(slice as usize) + half) / T::count(p.slices as usize);
        let ortho = along(e1.map(|e| e * phi.cos()), phi.sin(), e2);
        // The slice's direction in the image: where P + ε·ortho projects, per ε.
        let screen_x = ortho[0] * depth + position[0] * ortho[2];
        let screen_y = -(ortho[1] * depth + position[1] * ortho[2]);
        let screen_length = (screen_x * screen_x + screen_y * screen_y).sqrt();
        if !(screen_length > T::ZERO) {
            continue;
        }
        let (c, s) = (screen_x / screen_length, screen_y / screen_length);
        let axis = cross(v, ortho);
        let projected = along(n, -dot(n, axis), axis);
        let length = dot(projected, projected).sqrt();
        if !(length > T::ZERO) {
            continue;
        }
        let cos_gamma = (dot(projected, v) / length).clamp(T::ZERO, T::ONE);
        let sign = if dot(projected, ortho) < T::ZERO { -T::ONE } else { T::ONE };
        let gamma = sign * cos_gamma.acos();
        // Horizon cosines, from the tangent plane: θ = γ + π/2 (plus side), γ − π/2 (minus).
        let mut cos_plus = (gamma + half_pi).cos();
        let mut cos_minus = (gamma - half_pi).cos();
        for step in 1..=p.steps {
            let t = radius_pixels * T::count(step as usize) / T::count(p.steps as usize);
            for side in [T::ONE, -T::ONE] {
                let (sample_x, sample_y) = (px + half + side * t * c, py + half + side * t * s);
                let (sx, sy) = (sample_x.floor(), sample_y.floor());
                if sx == px && sy == py {
                    continue;
                }
                let Some(q) = g.at(sx, sy) else { continue };
                let delta = along(texel_plane_point(g, q, sample_x, sample_y), -T::ONE, position);
                let d2 = dot(delta, delta);
                if d2 > T::ZERO && d2 < radius2 {
                    let cos_h = dot(delta, v) / d2.sqrt();
                    if side > T::ZERO {
                        cos_plus = cos_plus.max(cos_h);
                    } else {
                        cos_minus = cos_minus.max(cos_h);
                    }
                }
            }
        }
        let h_plus = gamma + (cos_plus.clamp(-T::ONE, T::ONE).acos() - gamma).min(half_pi);
        let h_minus = gamma + (-cos_minus.clamp(-T::ONE, T::ONE).acos() - gamma).max(-half_pi);
        total = total + slice_visibility(h_minus, h_plus, gamma, length);
    }
    Some((total / T::count(p.slices as usize)).clamp(T::ZERO, T::ONE))
}

/// Every pixel's GTAO accessibility (row-major; `None` where no surface is).
pub fn gtao<T: Real + Send + Sync>(g: &GBuffer<T>, p: Parameters<T>) -> Vec<Option<T>> {
    (0..g.width as usize * g.height as usize)
        .into_par_iter()
        .map(|i| pixel_visibility(g, (i % g.width as usize) as u32, (i / g.width as usize) as u32, p))
        .collect()
}

#[cfg(test)]
mod tests {
    //! GTAO against closed forms, on G-buffers ray-cast here from analytic surfaces (no
    //! mesh, no tracer of the crate): a plane, a hemispherical bowl, a floor meeting a wall.

    use super::*;

    /// A pinhole camera at `eye` looking at `target` (world y up), `size`² pixels (odd, so
    /// that the target lies at the centre of the middle pixel) with a 60° field of view.
    struct Pinhole {
        eye: DVec3,
        right: DVec3,
        up: DVec3,
        forward: DVec3,
        size: u32,
        focal: f64,
    }

    impl Pinhole {
        fn new(eye: DVec3, target: DVec3, size: u32) -> Pinhole {
            let forward = (target - eye).normalize();
            let right = forward.cross(DVec3::Y).normalize();
            let up = right.cross(forward);
            Pinhole { eye, right, up, forward, size, focal: size as f64 / (2.0 * 30f64.to_radians().tan()) }
        }

        /// The G-buffer of the surface `hit(origin, direction) → (point, normal)`.
        fn gbuffer(&self, hit: impl Fn(DVec3, DVec3) -> Option<(DVec3, DVec3)>) -> GBuffer<f64> {
            let half = self.size as f64 / 2.0;
            let view = |d: DVec3| [d.dot(self.right), d.dot(self.up), -d.dot(self.forward)];
            let samples = (0..self.size * self.size)
                .map(|i| {
                    let (x, y) = ((i % self.size) as f64 + 0.5, (i / self.size) as f64 + 0.5);
                    let direction =
                        (self.forward + self.right * ((x - half) / self.focal) - self.up * ((y - half) / self.focal)).normalize();
                    let (point, normal) = hit(self.eye, direction)?;
                    Some(ViewSample { position: view(point - self.eye), normal: view(normal) })
                })
                .collect();
            GBuffer { width: self.size, height: self.size, focal: self.focal, samples }
        }

        fn centre(&self) -> (u32, u32) {
            (self.size / 2, self.size / 2)
        }
    }

    /// The nearest of the plane y = 0 (normal +y) where `keep` holds.
    fn floor(o: DVec3, d: DVec3, keep: impl Fn(DVec3) -> bool) -> Option<(f64, DVec3, DVec3)> {
        let t = -o.y / d.y;
        let p = o + t * d;
        (t > 0.0 && keep(p)).then_some((t, p, DVec3::Y))
    }

    #[test]
    fn an_open_plane_is_fully_accessible_from_any_view() {
        // Every sample lies in the tangent plane, so each horizon is the tangent plane and
        // â(φ) = |n_φ|(cos γ + γ sin γ), whose mean over φ is 1 exactly; 64 slices (midpoint
        // rule on a smooth periodic integrand) leave little. A sample off the slice plane
        // by the pixel it falls in can raise a horizon above the tangent line of the slice
        // by a hair: measured 6e-7.
        for eye in [DVec3::new(0.0, 3.0, 0.01), DVec3::new(-2.0, 1.0, 0.5), DVec3::new(1.0, 0.3, -1.5)] {
            let camera = Pinhole::new(eye, DVec3::ZERO, 41);
            let g = camera.gbuffer(|o, d| floor(o, d, |_| true).map(|(_, p, n)| (p, n)));
            let (x, y) = camera.centre();
            let open = pixel_visibility(&g, x, y, Parameters { radius: 1.0, slices: 64, steps: 16 }).unwrap();
            assert!((open - 1.0).abs() < 1e-5, "{eye}: {open}");
            // With 2 slices the midpoint rule is coarse where the view is oblique.
            let coarse = pixel_visibility(&g, x, y, Parameters { radius: 1.0, slices: 2, steps: 16 }).unwrap();
            assert!((coarse - 1.0).abs() < 0.2, "{eye}: {coarse}");
        }
    }

    /// Inside a sphere, dF = cos θ₁ cos θ₂ dA / (π s²) with s = 2R cos θ₁ = 2R cos θ₂, so
    /// the view factor from any point of it to any region is area / 4πR². The opening of a
    /// hemispherical bowl lets through exactly the rays that would meet the missing upper
    /// hemisphere (area 2πR²): every point of the bowl sees open sky 1/2.
    #[test]
    fn every_point_of_a_hemispherical_bowl_sees_half_the_sky() {
        let (centre, r) = (DVec3::ZERO, 1.0);
        let bowl = |o: DVec3, d: DVec3| {
            let oc = o - centre;
            let b = oc.dot(d);
            let disc = b * b - (oc.length_squared() - r * r);
            if disc < 0.0 {
                return None;
            }
            // The far intersection: the inside of the sphere seen through the opening.
            let p = o + (-b + disc.sqrt()) * d;
            (p.y <= centre.y).then(|| (p, (centre - p) / r))
        };
        let camera = Pinhole::new(DVec3::new(0.0, 4.0, 0.001), DVec3::new(0.0, -1.0, 0.0), 101);
        let g = camera.gbuffer(bowl);
        let (x, y) = camera.centre();
        let error = |steps: u32| {
            let p = Parameters { radius: 2.5, slices: 16, steps };
            (pixel_visibility(&g, x, y, p).unwrap() - 0.5).abs()
        };
        // From the bottom (5 below the eye) the rim is 45° up and A = cos² e at horizon
        // elevation e (|dA/de| ≤ 1). A bowl point at polar angle α shows at ρ = sin α /
        // (4 + cos α) focal lengths from the centre, dρ/dα = 1/16 at the rim: a step of the
        // search, 0.5/steps focal lengths (radius 2.5 at depth 5), is up to 8/steps rad of
        // α there, and the last sample inside the rim falls short of it by at most that:
        // e by at most 4/steps, A by at most 4/steps.
        for steps in [16, 64, 256] {
            let e = error(steps);
            assert!(e <= 4.0 / steps as f64, "{steps} steps: {e}");
        }
        assert!(error(256) < error(16));
        // Every bowl point more than 0.5 below the rim (its search still reaches the far
        // rim, at most 2 away).
        let p = Parameters { radius: 2.5, slices: 16, steps: 256 };
        let (mut checked, mut largest) = (0, 0.0f64);
        for (i, sample) in g.samples.iter().enumerate() {
            let Some(s) = sample else { continue };
            let view = DVec3::from_array(s.position);
            let world = camera.eye + camera.right * view.x + camera.up * view.y - camera.forward * view.z;
            if -world.y < 0.5 {
                continue;
            }
            let a = pixel_visibility(&g, (i as u32) % g.width, (i as u32) / g.width, p).unwrap();
            largest = largest.max((a - 0.5).abs());
            checked += 1;
        }
        // Measured: 885 pixels, largest 0.028 (at the bottom 0.082, 0.029, 0.0098 with 16,
        // 64, 256 steps); a point up the side sees its near rim closer and more foreshortened.
        assert!(largest < 0.04, "{largest}");
        assert!(checked > 800, "{checked}");
    }

    /// A floor point at distance d from a wall, occluders counted within the radius R (the
    /// wall taller and longer than R): in the slice at angle φ from the wall's normal
    /// (vertical slices, n = up) the wall's part within R ends at height √(R² − D²),
    /// D = d/cos φ, so the open part of that slice is ½ + D²/2R² (eq. 10 with γ = 0,
    /// h₋ = −π/2, cos h₊ = D/R); outside |φ| < φ₀ = acos(d/R) the wall is out of reach.
    /// Integrating over φ: A = 1 − φ₀/π + d √(R² − d²) / (π R²). Accessibility is a
    /// property of the point, so an oblique camera's slices give the same A.
    #[test]
    fn a_floor_point_beside_a_wall_matches_the_closed_form() {
        let (radius, height) = (1.0f64, 10.0);
        for d in [0.15, 0.5, 0.8] {
            let scene = |o: DVec3, dir: DVec3| {
                let floor_hit = floor(o, dir, |p| p.x < d);
                let t = (d - o.x) / dir.x;
                let p = o + t * dir;
                let wall_hit = (t > 0.0 && p.y >= 0.0 && p.y <= height && p.z.abs() <= height).then_some((t, p, -DVec3::X));
                [floor_hit, wall_hit].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, p, n)| (p, n))
            };
            let phi0 = (d / radius).acos();
            let expected =
                1.0 - phi0 / std::f64::consts::PI + d * (radius * radius - d * d).sqrt() / (std::f64::consts::PI * radius * radius);
            for eye in [DVec3::new(-2.0, 2.5, 0.3), DVec3::new(-1.0, 3.0, -1.2)] {
                let camera = Pinhole::new(eye, DVec3::ZERO, 201);
                let g = camera.gbuffer(scene);
                let (x, y) = camera.centre();
                let got = pixel_visibility(&g, x, y, Parameters { radius, slices: 32, steps: 128 }).unwrap();
                // The sampled wall point nearest the sphere of radius R lies within one step
                // of it, so the horizon can only fall short (A too high); the slices'
                // midpoint rule adds a little either way. Measured +0.0008 … +0.0099.
                assert!((got - expected).abs() < 0.015, "d {d}, eye {eye}: {got} against {expected}");
                assert!(got > expected - 1e-3, "d {d}, eye {eye}: {got} below {expected}");
            }
        }
    }

    #[test]
    fn the_f32_twin_follows_the_f64_body() {
        let camera = Pinhole::new(DVec3::new(-2.0, 2.5, 0.3), DVec3::ZERO, 41);
        let g = camera.gbuffer(|o, d| {
            let wall = {
                let t = (0.4 - o.x) / d.x;
                let p = o + t * d;
                (t > 0.0 && p.y >= 0.0 && p.y <= 2.0).then_some((t, p, -DVec3::X))
            };
            [floor(o, d, |p| p.x < 0.4), wall].into_iter().flatten().min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, p, n)| (p, n))
        });
        let p = Parameters { radius: 1.0, slices: 4, steps: 8 };
        let wide = gtao(&g, p);
        let narrow = gtao(&g.narrowed(), p.narrowed());
        let mut largest = 0.0f64;
        for (a, b) in wide.iter().zip(&narrow) {
            assert_eq!(a.is_some(), b.is_some());
            if let (Some(a), Some(b)) = (a, b) {
                largest = largest.max((a - *b as f64).abs());
            }
        }
        // f32 rounding moves a sample to the neighbouring pixel only on a pixel boundary;
        // none does here. Measured 1.3e-6.
        assert!(largest < 1e-4, "{largest}");
    }
}
